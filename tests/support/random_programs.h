// Generators of random NQC programs from a seed, shared by the random
// program tests (tests/backend/random_programs_test.cpp) and the size
// benchmark (bench/size_bench.cpp). The same seed gives the same program.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace rcxc::test {

// CI runs the fixed seeds 1..N. RCXC_SEED_OFFSET=K runs K+1..K+N instead,
// for wider runs by hand (docs/testing.md); a failure names its seed.
inline unsigned seed_offset() {
  const char* k = std::getenv("RCXC_SEED_OFFSET");
  return k ? static_cast<unsigned>(std::strtoul(k, nullptr, 10)) : 0u;
}

class Generator {
 public:
  explicit Generator(unsigned seed) : rng_(seed) {}

  std::string program() {
    std::ostringstream out;
    out << "int x, y;\n";
    int subs = pick(0, 3);
    for (int s = 0; s < subs; ++s) {
      out << "sub s" << s << "() {\n";
      block(out, 2, s);  // a sub may call the subs before it (inlined)
      out << "}\n";
    }
    subs_ = subs;
    out << "task main() {\n  x = 0; y = 0;\n";
    block(out, 3, subs);
    marker(out);
    out << "}\n";
    return out.str();
  }

 protected:
  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

  std::string mask() {
    static const char* masks[] = {"OUT_A", "OUT_B", "OUT_C", "OUT_A+OUT_C", "OUT_A+OUT_B+OUT_C", "OUT_B+OUT_C"};
    return masks[pick(0, 5)];
  }

  std::mt19937& rng() { return rng_; }

  void marker(std::ostringstream& out) {
    out << "  SelectDisplay(" << (markers_++ % 2 + 1) << "); Wait(" << pick(1, 3) << ");\n";
  }

  void motor(std::ostringstream& out) {
    static const char* calls[] = {"OnFwd", "OnRev", "Off", "Float", "On", "Fwd", "Rev", "Toggle"};
    int k = pick(0, 9);
    if (k < 8) out << "  " << calls[k] << "(" << mask() << ");\n";
    else if (k == 8) out << "  SetPower(" << mask() << ", " << pick(0, 7) << ");\n";
    else out << "  SetPower(" << mask() << ", x & 7);\n";
  }

  void block(std::ostringstream& out, int depth, int callable) {
    int n = pick(1, 6);
    for (int i = 0; i < n; ++i) {
      int k = pick(0, 12);
      if (k <= 4) motor(out);
      else if (k == 12) ramp(out);
      else if (k == 5) marker(out);
      else if (k == 6) out << "  x += " << pick(-3, 5) << ";\n";
      else if (k == 7) out << "  y = x * " << pick(1, 3) << ";\n";
      else if (k == 8 && depth > 0) {
        out << "  if (x > " << pick(-2, 4) << ") {\n";
        block(out, depth - 1, callable);
        out << "  } else {\n";
        block(out, depth - 1, callable);
        out << "  }\n";
      } else if (k == 9 && depth > 0) {
        // Sometimes directly nested (merged into one loop, ir/nested_repeat.cpp).
        out << "  repeat (" << pick(1, 3) << ") ";
        if (pick(0, 2) == 0) out << "repeat (" << pick(1, 3) << ") ";
        out << "{\n";
        block(out, depth - 1, callable);
        out << "  }\n";
      } else if (k >= 10 && callable > 0) {
        // Sometimes after a short wait: what every call of a subroutine has
        // beside it moves into it (backend/absorb.h).
        if (pick(0, 1) == 1) out << "  Wait(" << pick(1, 2) * 2 << ");\n";
        out << "  s" << pick(0, callable - 1) << "();\n";
      } else {
        motor(out);
      }
    }
  }

  // A power ramp written out step by step (rerolled into a loop when
  // long enough, ir/reroll.cpp).
  void ramp(std::ostringstream& out) {
    std::string m = mask();
    int first = pick(0, 3), n = pick(3, 5), wait = pick(1, 3);
    for (int p = first; p < first + n; ++p) out << "  SetPower(" << m << ", " << p << "); Wait(" << wait << ");\n";
  }

  std::mt19937 rng_;
  int subs_ = 0;
  int markers_ = 0;
};

// Two tasks commanding the same outputs, never at the same time: each
// acts only in its own time windows (main at 400 ms x k, the other at
// 400 ms x k + 200 ms, scheduled by Timer(0), which reads tenths), so whatever a command costs,
// the order of everything they do is fixed. A step is at most a few dozen
// instructions, which take 4 ms each while the other task busy-waits.
class TwoTaskGenerator : public Generator {
 public:
  using Generator::Generator;

  std::string program() {
    std::ostringstream out;
    int steps = pick(2, 6);
    bool shared_sub = pick(0, 1) == 1;
    out << "int x, y;\n";
    if (shared_sub) {
      out << "sub both() {\n";
      step(out);
      out << "}\n";
    }
    out << "task other() {\n";
    for (int k = 0; k < steps; ++k) {
      out << "  until (Timer(0) >= " << 4 * k + 2 << ");\n";
      step(out);
      if (shared_sub && pick(0, 2) == 0) out << "  both();\n";
    }
    out << "}\n";
    // Commands before the start are what `other` begins knowing.
    out << "task main() {\n  x = 0; y = 0;\n";
    if (pick(0, 1) == 1) step(out);
    out << "  ClearTimer(0); start other;\n";
    for (int k = 0; k < steps; ++k) {
      if (k > 0) out << "  until (Timer(0) >= " << 4 * k << ");\n";
      step(out);
      if (shared_sub && pick(0, 2) == 0) out << "  both();\n";
    }
    out << "  until (Timer(0) >= " << 4 * steps + 3 << ");\n";
    marker(out);
    out << "}\n";
    return out.str();
  }

 private:
  void step(std::ostringstream& out) {
    int n = pick(1, 4);
    for (int i = 0; i < n; ++i) {
      int k = pick(0, 6);
      if (k <= 3) motor(out);
      else if (k == 4) out << "  x += " << pick(-2, 3) << ";\n";
      else if (k == 5) {
        out << "  if (x > " << pick(-1, 2) << ") {\n";
        motor(out);
        out << "  } else {\n";
        motor(out);
        out << "  }\n";
      } else {
        out << "  SelectDisplay(" << pick(1, 6) << ");\n";
      }
    }
  }
};

// Subroutines kept as subroutines (their bodies are long enough not to be
// inlined), called from two tasks (one after the other) with few kinds of instruction around the
// calls, so that what the calls share often moves into the subroutine
// (backend/absorb.h): waits of a few lengths, sounds, additions, motor
// commands, and tests that branch around an instruction or to a call.
class CallNeighbourGenerator : public Generator {
 public:
  using Generator::Generator;

  std::string program() {
    std::ostringstream out;
    out << "int x, y;\n";
    subs_ = pick(1, 3);
    for (int s = 0; s < subs_; ++s) {
      out << "sub s" << s << "() {\n";
      int n = pick(3, 5);
      for (int i = 0; i < n; ++i) out << neighbour();
      if (pick(0, 3) == 0) out << "  if (x > " << pick(0, 4) << ") return;\n  PlaySound(" << pick(0, 5) << ");\n";
      if (pick(0, 3) == 0) out << "  do { y += 1; } while (y % 3 != 0);\n";
      out << "}\n";
    }
    out << "task other() {\n";
    calls(out, pick(1, 4));
    out << "}\n";
    out << "task main() {\n  x = 0; y = 0;\n";
    // `other` gets the subroutines (and x and y) to itself for 3 s, longer
    // than its calls take: no race whose outcome the timing decides.
    if (pick(0, 1) == 1) out << "  start other; Wait(300);\n";
    calls(out, pick(2, 6));
    out << "  Wait(100);\n";
    marker(out);
    out << "}\n";
    return out.str();
  }

 private:
  std::string neighbour() {
    switch (pick(0, 5)) {
      case 0:
      case 1: return "  Wait(" + std::to_string(pick(1, 3) * 2) + ");\n";
      case 2: return "  PlaySound(" + std::to_string(pick(0, 1)) + ");\n";
      case 3: return "  x += " + std::to_string(pick(1, 2)) + ";\n";
      case 4: {
        std::ostringstream m;
        motor(m);
        return m.str();
      }
      default: return "  if (x > " + std::to_string(pick(0, 6)) + ") PlaySound(2);\n";
    }
  }

  // Most calls have the program's usual instruction before and after them
  // (a wait sometimes longer than usual), the others something else or
  // nothing.
  std::string beside(const std::string& usual) {
    int r = pick(0, 9);
    if (r < 6) return usual;
    if (r < 7 && usual.starts_with("  Wait(")) return "  Wait(" + std::to_string(pick(4, 8)) + ");\n";
    if (r < 9) return neighbour();
    return "";
  }

  void calls(std::ostringstream& out, int n) {
    for (int i = 0; i < n; ++i) {
      out << beside(before_);
      out << "  s" << pick(0, subs_ - 1) << "();\n";
      out << beside(after_);
    }
  }

  std::string before_ = neighbour(), after_ = neighbour();
};

// A task `walk` going one way and back in an endless loop: two halves
// alike but for one direction command on outputs S (ir/flip.cpp keeps one
// half and flips S), with other steps around it, sometimes ones that turn
// S too (then nothing may flip). main stops `walk` in the middle of the
// long wait that ends every half, and another task sometimes toggles
// outputs in the middle of such a wait, so no level's few instructions
// more or less can change the order of what happens.
class BackAndForthGenerator : public Generator {
 public:
  using Generator::Generator;

  std::string program() {
    std::ostringstream out;
    std::string s = mask();
    int dir = pick(0, 1);  // OnFwd/OnRev or Fwd/Rev
    int first = pick(0, 1);
    std::vector<std::string> before = steps(pick(0, 2)), after = steps(pick(0, 2));
    int long_wait = pick(10, 20) * 2;
    int ticks = long_wait + waited_;
    auto half = [&](bool forward) {
      std::ostringstream h;
      for (const auto& step : before) h << step;
      h << "    " << (dir == 0 ? (forward ? "OnFwd" : "OnRev") : (forward ? "Fwd" : "Rev")) << "(" << s << ");\n";
      for (const auto& step : after) h << step;
      h << "    Wait(" << long_wait << ");\n";
      return h.str();
    };
    out << "int x;\n";
    out << "task walk() {\n  while (true) {\n" << half(first == 1) << half(first == 0) << "  }\n}\n";
    bool other = pick(0, 2) == 0;
    // In the middle of a long wait: k whole periods less half the wait.
    auto mid_wait = [&](int periods) { return 2 * ticks * periods - long_wait / 2; };
    if (other) out << "task other() {\n  Wait(" << mid_wait(1) << ");\n  Toggle(" << mask() << ");\n}\n";
    out << "task main() {\n  x = 0;\n";
    for (int i = pick(0, 2); i > 0; --i) motor(out);
    out << "  start walk;\n";
    if (other) out << "  start other;\n";
    out << "  Wait(" << mid_wait(pick(2, 3)) << ");\n  stop walk;\n";
    marker(out);
    out << "}\n";
    return out.str();
  }

 private:
  // Steps between the turns: waits, sounds, additions, and motor commands,
  // half of them only switching outputs or setting their power.
  std::vector<std::string> steps(int n) {
    std::vector<std::string> v;
    for (int i = 0; i < n; ++i) {
      std::ostringstream m;
      switch (pick(0, 5)) {
        case 0: {
          int w = pick(1, 3);
          waited_ += w;
          m << "    Wait(" << w << ");\n";
          break;
        }
        case 1: m << "    PlaySound(" << pick(0, 5) << ");\n"; break;
        case 2: m << "    x += " << pick(1, 3) << ";\n"; break;
        case 3: {
          static const char* calls[] = {"On", "Off", "Float"};
          m << "    " << calls[pick(0, 2)] << "(" << mask() << ");\n";
          break;
        }
        case 4: m << "    SetPower(" << mask() << ", " << pick(1, 7) << ");\n"; break;
        default: motor(m); m.str("  " + m.str());
      }
      v.push_back(m.str());
    }
    return v;
  }

  int waited_ = 0;  // ticks of the steps' waits in one half (before and after)
};

// Tasks main ends by starting (ir/tailstart.cpp runs them in main): main
// does some steps and ends, on each side of an if, by starting a task;
// task a may end by starting c. Sometimes a task `keeper` starts beside
// one of them (before or after it, in the same run of starts), which c or
// b may stop; it only plays a sound and waits, so whichever runs first,
// the order of what happens is fixed.
class TailStartGenerator : public Generator {
 public:
  using Generator::Generator;

  std::string program() {
    std::ostringstream out;
    bool keeper = pick(0, 1) == 1;
    out << "int x, y;\n";
    // Declared in the order main may run them in its place: a task runs
    // there only when it is numbered before the others beside it.
    task(out, "a", pick(0, 1) == 1 ? "  start c;\n" : "");
    task(out, "b", keeper && pick(0, 1) == 1 ? "  stop keeper;\n" : "");
    task(out, "c", keeper ? "  stop keeper;\n" : "");
    if (keeper) out << "task keeper() {\n  PlaySound(" << pick(0, 5) << ");\n  Wait(" << pick(5, 40) * 10 << ");\n}\n";
    out << "task main() {\n  x = 0; y = 0;\n";
    block(out, 2, 0);
    out << "  if (x > " << pick(-2, 4) << ") {\n";
    block(out, 1, 0);
    out << ends_with("a", keeper) << "  } else {\n";
    if (pick(0, 1) == 1) block(out, 1, 0);
    out << ends_with("b", keeper) << "  }\n}\n";
    return out.str();
  }

 private:
  void task(std::ostringstream& out, const char* name, const std::string& end) {
    out << "task " << name << "() {\n";
    block(out, 2, 0);
    marker(out);
    out << end << "}\n";
  }

  // `start task;`, and sometimes keeper's start before or after it.
  std::string ends_with(const std::string& task, bool keeper) {
    std::string start = "  start " + task + ";\n";
    if (!keeper || pick(0, 2) == 0) return start;
    return pick(0, 1) == 1 ? "  start keeper;\n" + start : start + "  start keeper;\n";
  }
};

// Coin tosses (`if (Random(1) == 0)` and its other spellings) in nested
// repeat loops up to five deep, whose sides record what they saw; sometimes
// the drawn value goes to a global and is read again (no toss may replace
// it then).
class CoinGenerator : public Generator {
 public:
  using Generator::Generator;

  std::string program() {
    std::ostringstream out;
    out << "int x, y, n, t;\ntask main() {\n  x = 0; y = 0; n = 0;\n";
    block(out, 5, 1);
    marker(out);
    out << "}\n";
    return out.str();
  }

 private:
  // `runs`: how many times the enclosing loops run what block writes.
  void block(std::ostringstream& out, int depth, int runs) {
    int k = pick(1, 3);
    for (int i = 0; i < k; ++i) {
      int r = pick(0, 6);
      if (r <= 1 && depth > 0) {
        int count = pick(1, 3);
        out << "  repeat (" << count << ") {\n  n += 1;\n";
        block(out, depth - 1, runs * count);
        out << "  }\n";
      } else if (r <= 4) {
        static const char* tests[] = {"Random(1) == 0", "Random(1) != 0", "Random(1) > 0", "Random(1) < 1",
                                      "1 == Random(1)", "Random(1) >= 1", "Random(1) <= 0", "0 < Random(1)"};
        out << "  if (" << tests[pick(0, 7)] << ") { x = x * 2 + 1; ";
        side(out, runs);
        out << "} else { x = x * 2; ";
        side(out, runs);
        out << "}\n";
      } else if (r == 5) {
        out << "  t = Random(1); if (t == 0) y += 5; y += t;\n";
      } else {
        out << "  y += " << pick(1, 4) << ";\n";
      }
    }
  }

  // A sound only while the program can play no more than the firmware's
  // queue holds (one playing, eight waiting): a full queue drops sounds,
  // and which ones depends on the code's speed, which -Os trades.
  void side(std::ostringstream& out, int runs) {
    if (pick(0, 2) == 0) {
      int sound = pick(0, 5);
      if (sounds_ + runs <= kQueuedSounds) {
        out << "PlaySound(" << sound << "); ";
        sounds_ += runs;
      }
    }
    if (pick(0, 2) == 0) out << "y += " << pick(1, 9) << "; ";
  }

  static constexpr int kQueuedSounds = 9;
  int sounds_ = 0;
};

// if/else statements whose two sides begin alike (a motor command, a
// sound, arithmetic on x or y), tested on x, y, a timer, an output's state
// or a random number: -O2 and -Os run a common beginning once before the
// test (ir/hoist.cpp) where that cannot change the test, which a common
// `x += 1` before a test of x, or a draw before a test that draws, would.
class CommonHeadGenerator : public Generator {
 public:
  using Generator::Generator;

  std::string program() {
    std::ostringstream out;
    out << "int x, y;\ntask main() {\n  x = " << pick(-2, 3) << "; y = 0; ClearTimer(0);\n";
    block(out, 3);
    marker(out);
    out << "}\n";
    return out.str();
  }

 private:
  std::string statement() {
    std::ostringstream out;
    int k = pick(0, 7);
    static const char* calls[] = {"OnFwd", "OnRev", "Off", "Float", "Toggle"};
    if (k <= 2) out << calls[pick(0, 4)] << "(" << mask() << "); ";
    else if (k == 3) out << "SetPower(" << mask() << ", " << pick(0, 7) << "); ";
    else if (k == 4) out << "PlaySound(" << pick(0, 5) << "); ";
    else if (k == 5) out << "x += " << pick(1, 3) << "; ";
    else if (k == 6) out << "y = " << (pick(0, 1) ? "Random(3)" : "x * 2") << "; ";
    else out << "Wait(" << pick(1, 3) << "); ";
    return out.str();
  }

  std::string test() {
    switch (pick(0, 5)) {
      case 0: return "x > " + std::to_string(pick(-1, 4));
      case 1: return "y == " + std::to_string(pick(0, 2));
      case 2: return "Timer(0) >= " + std::to_string(pick(0, 2));
      case 3: return "OutputStatus(" + std::to_string(pick(0, 2)) + ") > 10";
      case 4: return "Random(2) == 1";
      default: return "x != y";
    }
  }

  void block(std::ostringstream& out, int depth) {
    int n = pick(1, 4);
    for (int i = 0; i < n; ++i) {
      if (pick(0, 3) == 0 || depth == 0) {
        out << "  " << statement() << "\n";
        continue;
      }
      std::string head;
      for (int h = pick(1, 3); h > 0; --h) head += statement();
      out << "  if (" << test() << ") {\n  " << head << statement() << "\n";
      if (pick(0, 2) == 0) block(out, depth - 1);
      out << "  } else {\n  " << head << statement() << "\n";
      if (pick(0, 2) == 0) block(out, depth - 1);
      out << "  }\n";
    }
  }
};

// Subroutines and inline functions whose locals are read before they are
// written, so each call sees what the previous call left (one variable for
// all calls, as in nqc), called from main, in loops and branches, and from
// one another: -O1 and -Os inline the subroutines, and every level must
// still compute what -O0's one copy computes.
class KeptLocalGenerator : public Generator {
 public:
  using Generator::Generator;

  std::string program() {
    std::ostringstream out;
    out << "int x, y;\n";
    int functions = pick(0, 2);
    for (int f = 0; f < functions; ++f) {
      out << "void f" << f << "(int a) {\n  int m" << f << ";\n";
      out << "  y = y * 3 + m" << f << ";\n  m" << f << " = a + " << pick(1, 9) << ";\n}\n";
    }
    int subs = pick(1, 3);
    for (int s = 0; s < subs; ++s) {
      out << "sub s" << s << "() {\n  int k" << s << ";\n";
      if (pick(0, 2) == 0) out << "  int j" << s << " = x;\n  y += j" << s << ";\n";  // written first
      kept_step(out, "k" + std::to_string(s));
      if (s > 0 && pick(0, 1) == 0) out << "  s" << pick(0, s - 1) << "();\n";
      if (functions > 0 && pick(0, 1) == 0) out << "  f" << pick(0, functions - 1) << "(x);\n";
      out << "}\n";
    }
    out << "task main() {\n  x = 0; y = 0;\n";
    int n = pick(2, 7);
    for (int i = 0; i < n; ++i) {
      int k = pick(0, 5);
      std::string call = k < 4 || functions == 0 ? "s" + std::to_string(pick(0, subs - 1)) + "();"
                                                 : "f" + std::to_string(pick(0, functions - 1)) + "(x);";
      if (k == 1) out << "  repeat (" << pick(2, 3) << ") { " << call << " x += 1; }\n";
      else if (k == 2) out << "  if (x > " << pick(0, 6) << ") " << call << " else x += 2;\n";
      else out << "  " << call << " x += " << pick(1, 4) << ";\n";
    }
    marker(out);
    out << "}\n";
    return out.str();
  }

 private:
  // Reads the kept local, then writes it: sometimes only on one side of an
  // if, so some calls leave it as it was.
  void kept_step(std::ostringstream& out, const std::string& k) {
    out << "  y = y + " << k << " * " << pick(1, 3) << ";\n";
    if (pick(0, 2) == 0) out << "  if (x > " << pick(0, 8) << ") " << k << " = x + y;\n";
    else out << "  " << k << " = " << k << " + x + " << pick(1, 5) << ";\n";
  }
};

// Arithmetic, comparisons and control flow over three globals, with the
// 16-bit edge values: every level must compute the same.
// Who else reads the program: nqc (which miscompiles some constants and
// long branches, see docs/compiler.md) or a C++ compiler, for which the text
// is also valid C++ once a prelude makes `int` a 16-bit type computing as
// the RCX does (tests/backend/random_programs_test.cpp).
enum class Audience : std::uint8_t { Rcxc, Nqc, Cpp };

class ExpressionGenerator {
 public:
  explicit ExpressionGenerator(unsigned seed, bool vary_constant_pairs = false)
      : ExpressionGenerator(seed, vary_constant_pairs ? Audience::Nqc : Audience::Rcxc) {}
  ExpressionGenerator(unsigned seed, Audience audience)
      : rng_(seed), vary_constant_pairs_(audience != Audience::Rcxc), near_edges_(audience == Audience::Nqc),
        cpp_(audience == Audience::Cpp) {}

  std::string program() {
    std::ostringstream out;
    out << "int a, b, c, g0, g1, g2, g3;\n";
    if (cpp_) {
      // Hooks the C++ prelude gives meaning to: W wraps a conditional's
      // value in the 16-bit type, SW gives switch an integer.
      out << "#define W(x) (x)\n#define SW(x) (x)\n";
    }
    // Inline functions with the four parameter kinds: a value copy, a
    // reference, a constant, and an expression evaluated at each use. For
    // C++, whose references do not re-evaluate, f1 is a macro.
    out << "void f0(int x, int &r) { x += " << pick(-3, 3) << "; r = (r " << binary_op() << " x); if (x > "
        << pick(-2, 5) << ") return; r--; }\n";
    std::string op1 = binary_op(), op2 = binary_op();
    if (cpp_)
      out << "#define f1(k, e) { a = (a " << op1 << " (k)); b = ((e) " << op2 << " b); c = (e); }\n";
    else
      out << "void f1(const int k, const int &e) { a = (a " << op1 << " k); b = (e " << op2 << " b); c = e; }\n";
    out << "task main() {\n  a = " << constant() << "; b = " << constant() << "; c = " << constant() << ";\n";
    // For nqc, smaller programs: only those under 128 bytes are compared.
    block(out, near_edges_ ? 1 : 2);
    out << "}\n";
    return out.str();
  }

 private:
  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  std::string var() { return std::string(1, "abc"[pick(0, 2)]); }
  std::string constant() {
    static const int edges[] = {-32768, -32767, -1, 0, 1, 2, 3, 7, 100, 32767};
    // nqc misjudges comparisons against the 16-bit extremes (it drops
    // `while (-32768 <= a && ...)` as if never true): for nqc, near-edges.
    static const int near_edges[] = {-32000, -30001, -1, 0, 1, 2, 3, 7, 100, 32000};
    const int* set = near_edges_ ? near_edges : edges;
    return pick(0, 2) == 0 ? std::to_string(pick(-300, 300)) : std::to_string(set[pick(0, 9)]);
  }
  std::string expr(int depth) {
    bool constant_only = false;
    return expr(depth, constant_only);
  }
  // `constant_only`: the expression has no variable in it. With
  // `vary_constant_pairs_`, no operator gets two such operands: nqc folds
  // those in 32 bits, where the RCX computes in 16 (see docs/compiler.md).
  std::string expr(int depth, bool& constant_only) {
    if (depth == 0 || pick(0, 3) == 0) {
      constant_only = pick(0, 1) == 0;
      return constant_only ? constant() : var();
    }
    static const char* binary[] = {"+", "-", "*", "/", "%", "&", "|", "^", "<", "<=", "==", "!=", ">", ">=", "&&", "||"};
    int k = pick(0, 21);
    bool c1 = false, c2 = false, c3 = false;
    auto operand = [&](bool& c) { return expr(depth - 1, c); };
    if (k < 16) {
      std::string l = operand(c1), r = operand(c2);
      if (vary_constant_pairs_ && c1 && c2) r = var(), c2 = false;
      constant_only = c1 && c2;
      return "(" + l + " " + binary[k] + " " + r + ")";
    }
    if (k == 16 || k == 17) {
      std::string l = operand(c1);
      // For nqc, a variable: nqc folds a constant `>>` arithmetically but
      // shifts logically at run time (rcxc folds as it runs), and a left
      // side can fold without being all constants (`1 ? ~0 : b`).
      if (vary_constant_pairs_) l = var(), c1 = false;
      constant_only = c1;
      return "(" + l + (k == 16 ? " << " : " >> ") + std::to_string(pick(0, 15)) + ")";
    }
    if (k == 18) {
      std::string c = operand(c1), t = operand(c2), e = operand(c3);
      constant_only = c1 && c2 && c3;
      return std::string(cpp_ ? "W" : "") + "(" + c + " ? " + t + " : " + e + ")";
    }
    static const char* unary[] = {"-", "~", "!"};
    std::string x = operand(c1);
    constant_only = c1;
    return std::string(unary[k - 19]) + "(" + x + ")";
  }
  void block(std::ostringstream& out, int depth) {
    int n = pick(1, 5);
    for (int i = 0; i < n; ++i) {
      int k = pick(0, 13);
      if (k <= 3) {
        out << "  " << var() << " = " << expr(3) << ";\n";
      } else if (k == 4) {
        static const char* ops[] = {"+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>="};
        int o = pick(0, 9);
        // nqc shifts only by constants 0..15.
        std::string count = near_edges_ ? std::to_string(pick(0, 15)) : std::to_string(pick(-2, 17));
        out << "  " << var() << " " << ops[o] << " " << (o >= 8 ? count : expr(2)) << ";\n";
      } else if (k == 5) {
        out << "  " << var() << (pick(0, 1) ? "++" : "--") << ";\n";
      } else if (k == 6 && depth > 0) {
        out << "  if (" << expr(2) << ") {\n";
        block(out, depth - 1);
        out << "  } else {\n";
        block(out, depth - 1);
        out << "  }\n";
      } else if (k == 7 && depth > 0) {
        // Bounded by a guard of its own whatever the condition does.
        std::string g = "g" + std::to_string(depth);
        // For nqc the guard comes first: nqc drops a loop whose condition
        // starts with an always-true test and `&&` (docs/compiler.md).
        std::string cond = "(" + expr(2) + ")", guard = g + " < " + std::to_string(pick(1, 4));
        out << "  " << g << " = 0;\n  while (" << (near_edges_ ? guard + " && " + cond : cond + " && " + guard)
            << ") {\n  " << g << "++;\n";
        ++in_loop_;
        block(out, depth - 1);
        --in_loop_;
        out << "  }\n";
      } else if (k == 8 && depth > 0) {
        out << "  switch (" << (cpp_ ? "SW(" : "(") << var() << " & 3)) {\n  case 0:\n";
        block(out, depth - 1);
        out << "  break;\n  case " << pick(1, 2) << ":\n";
        block(out, depth - 1);
        out << "  default:\n";
        block(out, depth - 1);
        out << "  }\n";
      } else if (k == 9 && depth > 0) {
        loop(out, depth);
      } else if (k == 10) {
        out << "  f0(" << expr(2) << ", " << var() << ");\n";
      } else if (k == 11) {
        out << "  f1(" << pick(-5, 5) << ", (" << var() << " " << binary_op() << " " << expr(1) << "));\n";
      } else if (k == 13) {
        steps(out);
      } else if (k == 12 && in_loop_ > 0) {
        out << "  if (" << expr(2) << ") " << (pick(0, 1) ? "break" : "continue") << ";\n";
      } else {
        out << "  " << var() << " = " << expr(2) << ";\n";
      }
    }
  }

  // Steps written out one by one (a += 40; a += 37; a += 34; ...): long
  // enough runs become loops (ir/reroll.cpp).
  void steps(std::ostringstream& out) {
    std::string v = var();
    int first = pick(-300, 300), step = pick(-40, 40), n = pick(3, 9);
    for (int i = 0; i < n; ++i) out << "  " << v << " += " << first + i * step << ";\n";
  }

  std::string binary_op() {
    static const char* ops[] = {"+", "-", "*", "/", "%", "&", "|", "^"};
    return ops[pick(0, 7)];
  }

  // for, do-while and repeat loops, each bounded by a guard or count.
  void loop(std::ostringstream& out, int depth) {
    std::string g = "g" + std::to_string(depth);
    std::string cond = "(" + expr(2) + ")", limit = std::to_string(pick(1, 4));
    ++in_loop_;
    switch (pick(0, 2)) {
      case 0:
        out << "  for (" << g << " = 0; " << g << " < " << limit << " && " << cond << "; " << g << "++) {\n";
        block(out, depth - 1);
        out << "  }\n";
        break;
      case 1:
        out << "  " << g << " = 0;\n  do {\n  " << g << "++;\n";
        block(out, depth - 1);
        out << "  } while (" << g << " < " << limit << " && " << cond << ");\n";
        break;
      default:
        out << "  repeat (" << limit << ") {\n";
        block(out, depth - 1);
        out << "  }\n";
    }
    --in_loop_;
  }

  std::mt19937 rng_;
  bool vary_constant_pairs_ = false;
  bool near_edges_ = false;  // for nqc: near-edge constants, smaller programs, guards first
  bool cpp_ = false;
  int in_loop_ = 0;
};

// Robot control loops, the shape most NQC programs have and none of the
// other generators makes: main configures sensors and runs forever,
// reacting in each pass to the touch sensors, a light level, a timer, a
// message or a count of presses with motor commands, sounds and short
// waits; sometimes a second task watches the light sensor the same way.
// What each does depends on the inputs, not on how fast a pass runs (no
// count of passes, nothing but settings repeated while an input level
// holds; the two tasks share no output, variable or timer), so both
// compilers' code must behave alike under `rcxc compare`'s scenarios.
// bench/speed_bench.cpp measures what a pass costs and how soon an input
// change shows on these programs, never used to tune the passes.
class ReactiveGenerator : public Generator {
 public:
  using Generator::Generator;

  std::string program() {
    std::ostringstream out;
    out << "int state, count, level, speed, seen;\n";
    if (pick(0, 2) == 0) {
      out << "void turn(int t) {\n  OnRev(OUT_A+OUT_C); Wait(t); OnFwd(OUT_A+OUT_C);\n}\n";
      helper_ = true;
    }
    bool watcher = pick(0, 2) == 0;
    if (watcher) {
      out << "task watch() {\n";
      loop_head(out);
      out << "  if (SENSOR_3 > " << pick(40, 60) << ") {\n";
      watch_action(out);
      out << "  } else {\n";
      watch_action(out);
      out << "  }\n";
      loop_tail(out);
      out << "}\n";
    }
    out << "task main() {\n  SetSensor(SENSOR_1, SENSOR_TOUCH); SetSensor(SENSOR_2, SENSOR_TOUCH);\n"
        << "  SetSensor(SENSOR_3, SENSOR_LIGHT);\n  state = 0; count = 0;\n";
    if (pick(0, 1) == 1) out << "  OnFwd(OUT_A+OUT_C);\n";
    if (watcher) out << "  start watch;\n";
    loop_head(out);
    int n = pick(1, 4);
    for (int i = 0; i < n; ++i) reaction(out, 2);
    loop_tail(out);
    out << "}\n";
    return out.str();
  }

 private:
  void loop_head(std::ostringstream& out) {
    loop_ = pick(0, 3);
    static const char* heads[] = {"  while (true) {\n", "  for (;;) {\n", "  do {\n", "  until (false) {\n"};
    out << heads[loop_];
  }
  void loop_tail(std::ostringstream& out) { out << (loop_ == 2 ? "  } while (true);\n" : "  }\n"); }

  // The watcher's outputs: B and its own variable.
  void watch_action(std::ostringstream& out) {
    static const char* calls[] = {"OnFwd(OUT_B)", "OnRev(OUT_B)", "Off(OUT_B)", "Float(OUT_B)", "seen = 1",
                                  "seen = 0"};
    out << "  " << calls[pick(0, 5)] << ";\n";
    if (pick(0, 2) == 0) out << "  Wait(" << pick(1, 20) << ");\n";
  }

  // A condition that holds for a while (an input level, the state): what
  // it does runs again on every pass while it holds, so it may only set
  // what stays set (no toggles, sounds or turns, which would come as often
  // as the loop goes round and make the two codes' speeds visible).
  std::string level_test() {
    switch (pick(0, 6)) {
      case 0: return "SENSOR_1 == 1";
      case 1: return "SENSOR_2 == 0";
      case 2: return "SENSOR_1 == 1 && SENSOR_2 == 1";
      case 3: return "SENSOR_1 == 1 || SENSOR_2 == 1";
      case 4: return "SENSOR_3 < " + std::to_string(pick(35, 55));
      case 5: return "SENSOR_3 > " + std::to_string(pick(45, 65));
      default: return "state == " + std::to_string(pick(0, 2));
    }
  }

  // main's outputs: A and C, its variables.
  void level_action(std::ostringstream& out) {
    static const char* outputs[] = {"OUT_A", "OUT_C", "OUT_A+OUT_C"};
    static const char* calls[] = {"OnFwd", "OnRev", "Off", "Float", "Fwd", "Rev"};
    switch (pick(0, 6)) {
      case 0: case 1: case 2: out << "  " << calls[pick(0, 5)] << "(" << outputs[pick(0, 2)] << ");\n"; break;
      case 3: out << "  SetPower(" << outputs[pick(0, 2)] << ", " << pick(1, 7) << ");\n"; break;
      case 4: out << "  state = " << pick(0, 2) << ";\n"; break;
      case 5: out << "  Wait(" << pick(1, 10) << ");\n"; break;
      default: out << "  count = 0;\n";
    }
  }

  void level_actions(std::ostringstream& out) {
    int n = pick(1, 3);
    for (int i = 0; i < n; ++i) level_action(out);
  }

  // Once per event (a message, a period of the timer, a press): anything.
  void event_actions(std::ostringstream& out) {
    int n = pick(1, 3);
    for (int i = 0; i < n; ++i) {
      switch (pick(0, 5)) {
        case 0: out << "  PlaySound(" << pick(0, 5) << ");\n"; break;
        case 1: out << "  Toggle(OUT_" << "AC"[pick(0, 1)] << ");\n"; break;
        case 2:
          if (helper_) out << "  turn(" << pick(5, 40) << ");\n";
          else out << "  OnRev(OUT_A); Wait(" << pick(5, 40) << "); OnFwd(OUT_A);\n";
          break;
        case 3: out << "  count++;\n"; break;
        default: level_action(out);
      }
    }
  }

  void reaction(std::ostringstream& out, int depth) {
    switch (pick(0, 9)) {
      case 0: case 1:
        out << "  if (" << level_test() << ") {\n";
        level_actions(out);
        out << "  }\n";
        break;
      case 2: case 3:
        out << "  if (" << level_test() << ") {\n";
        if (depth > 0 && pick(0, 2) == 0) reaction(out, depth - 1);
        else level_actions(out);
        out << "  } else {\n";
        level_actions(out);
        out << "  }\n";
        break;
      case 4:
        out << "  level = SENSOR_3;\n  speed = (level - " << pick(30, 50) << ") / " << pick(2, 8) << ";\n"
            << "  if (speed < 0) speed = 0; else if (speed > 7) speed = 7;\n  SetPower(OUT_A, speed);\n";
        break;
      case 5:
        out << "  switch (state) {\n";
        for (int c = 0; c < 3; ++c) {
          out << "  case " << c << ":\n";
          level_actions(out);
          if (pick(0, 3) > 0) out << "  break;\n";
        }
        out << "  }\n";
        break;
      case 6:
        // Waiting in place for an input, or acting while it lasts.
        if (pick(0, 1) == 1) {
          out << "  until (" << level_test() << ");\n";
        } else {
          out << "  while (" << level_test() << ") {\n";
          level_actions(out);
          out << "  }\n";
        }
        break;
      case 7:
        out << "  if (Message() == " << pick(1, 7) << ") {\n  ClearMessage();\n";
        event_actions(out);
        out << "  }\n";
        break;
      case 8:
        out << "  if (Timer(0) > " << pick(5, 40) << ") {\n  ClearTimer(0);\n";
        event_actions(out);
        out << "  }\n";
        break;
      default:
        // Counting presses: one count per press, however long it lasts.
        out << "  if (SENSOR_" << pick(1, 2) << " == 1) {\n";
        event_actions(out);
        out << "  until (SENSOR_1 == 0 && SENSOR_2 == 0);\n  }\n";
        if (pick(0, 1) == 1) {
          out << "  if (count > " << pick(1, 4) << ") {\n  count = 0;\n";
          event_actions(out);
          out << "  }\n";
        }
    }
  }

  bool helper_ = false;
  int loop_ = 0;
};

}  // namespace rcxc::test
