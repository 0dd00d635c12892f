// Random programs compiled without optimisation and with each level must
// do the same: the same output states at every marker (a display change
// followed by a wait, which no optimisation moves a motor command across),
// the same final outputs and variables. Fixed seeds: a failure names the
// seed and prints the program.
#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include <fmt/format.h>

#include "backend/compile.h"
#include "runtime/vm.h"

using namespace rcxc;

namespace {

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
      int k = pick(0, 11);
      if (k <= 4) motor(out);
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
        out << "  repeat (" << pick(1, 3) << ") {\n";
        block(out, depth - 1, callable);
        out << "  }\n";
      } else if (k >= 10 && callable > 0) {
        out << "  s" << pick(0, callable - 1) << "();\n";
      } else {
        motor(out);
      }
    }
  }

  std::mt19937 rng_;
  int subs_ = 0;
  int markers_ = 0;
};

// Two tasks commanding the same outputs, never at the same time: each
// acts only in its own time windows (main at 200 ms x k, the other at
// 200 ms x k + 100 ms, scheduled by Timer(0)), so whatever a command costs,
// the order of everything they do is fixed.
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
      out << "  until (Timer(0) >= " << 20 * k + 10 << ");\n";
      step(out);
      if (shared_sub && pick(0, 2) == 0) out << "  both();\n";
    }
    out << "}\n";
    out << "task main() {\n  x = 0; y = 0; ClearTimer(0); start other;\n";
    for (int k = 0; k < steps; ++k) {
      if (k > 0) out << "  until (Timer(0) >= " << 20 * k << ");\n";
      step(out);
      if (shared_sub && pick(0, 2) == 0) out << "  both();\n";
    }
    out << "  until (Timer(0) >= " << 20 * steps + 5 << ");\n";
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

struct Observed {
  std::vector<std::string> at_markers;  // output states when each marker showed
  std::string final;
};

std::string describe(const std::array<rcx::Output, rcx::kOutputs>& outs) {
  std::string s;
  for (const auto& o : outs)
    s += fmt::format("[{} {} {}]", static_cast<int>(o.mode), static_cast<int>(o.dir), o.power);
  return s;
}

std::optional<Observed> observe(const std::string& text, ir::OptLevel level, std::string& error) {
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  frontend::Options options;
  auto out = backend::compile_source("random.nqc", text, options, level, sm, diags, log);
  if (!out) {
    for (const auto& d : diags.all()) error += render_text(d, sm);
    return std::nullopt;
  }
  rcx::Machine m;
  if (auto err = m.load(0, out->image)) {
    error = *err;
    return std::nullopt;
  }
  m.start_program();
  m.run(120'000 * rcx::kMicrosPerMs);
  Observed seen;
  std::array<rcx::Output, rcx::kOutputs> outs{};
  for (const auto& e : m.state().events) {
    if (e.kind == rcx::EventKind::Output) outs[static_cast<std::size_t>(e.index)] = e.output;
    if (e.kind == rcx::EventKind::Display) seen.at_markers.push_back(describe(outs));
  }
  seen.final = describe(m.state().outputs);
  for (int v : {0, 1}) seen.final += fmt::format(" var{}={}", v, m.state().vars[static_cast<std::size_t>(v)]);
  return seen;
}

}  // namespace

TEST(RandomPrograms, EveryOptimisationLevelBehavesAsUnoptimised) {
  for (unsigned seed = 1; seed <= 300; ++seed) {
    std::string text = Generator(seed).program();
    std::string error;
    auto reference = observe(text, ir::OptLevel::O0, error);
    ASSERT_TRUE(reference) << "seed " << seed << ": " << error << "\n" << text;
    for (auto level : {ir::OptLevel::O1, ir::OptLevel::Os}) {
      auto got = observe(text, level, error);
      ASSERT_TRUE(got) << "seed " << seed << ": " << error << "\n" << text;
      ASSERT_EQ(got->at_markers, reference->at_markers) << "seed " << seed << "\n" << text;
      ASSERT_EQ(got->final, reference->final) << "seed " << seed << "\n" << text;
    }
  }
}

TEST(RandomPrograms, TwoTasksInTurnsBehaveAsUnoptimised) {
  for (unsigned seed = 1; seed <= 300; ++seed) {
    std::string text = TwoTaskGenerator(seed).program();
    std::string error;
    auto reference = observe(text, ir::OptLevel::O0, error);
    ASSERT_TRUE(reference) << "seed " << seed << ": " << error << "\n" << text;
    for (auto level : {ir::OptLevel::O1, ir::OptLevel::Os}) {
      auto got = observe(text, level, error);
      ASSERT_TRUE(got) << "seed " << seed << ": " << error << "\n" << text;
      ASSERT_EQ(got->at_markers, reference->at_markers) << "seed " << seed << "\n" << text;
      ASSERT_EQ(got->final, reference->final) << "seed " << seed << "\n" << text;
    }
  }
}
