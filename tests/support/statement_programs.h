// Random NQC programs mixing the whole language for the RCX (firmware 1.0),
// for differential testing against nqc (tests/backend/statement_programs_test.cpp):
// globals and block locals, if/else chains, while, do-while, for, until,
// repeat (constant and variable counts), switch with fall-through and
// default, break and continue in every kind of loop, inline functions with
// the four parameter kinds and `return`, nested and called from several
// places, subroutines called from main and from another task, tasks started
// and stopped, every compound assignment, ++ and --, unary operators,
// abs() and sign(), comparisons and && || as conditions and as values,
// 16-bit edge values, timers, sensors, motors, sounds, the display, IR
// messages and the datalog.
//
// What makes two correct compilers' code agree on these programs whatever
// their instruction counts:
// - main runs in three phases of 5 s, each ended by a wait until then;
//   the scenarios change the inputs only 500 ms before a phase ends, while
//   main waits, so every sensor reading is of a value that holds;
// - sounds are few enough never to fill the firmware's queue;
// - main starts the task `other` for a turn (`flag = k; start other;`) and
//   waits until it sets `flag = k + 1`: the two never run statements at once;
// - every loop is bounded by its own counter or a small count, and long
//   waits only happen outside loops;
// - timers are read only right after a wait that ends half a tick away;
// - what nqc gets wrong (docs/compiler.md) stays out: no operator has two
//   constant operands (nqc folds them in 32 bits), no comparison is
//   against -32768 or 32767, no `&&`/`||` has a constant side, and the
//   loop guards come first in conditions.
// Values become visible in the datalog and as the final globals, which
// `rcxc compare` looks at. The same seed gives the same program.
#pragma once

#include <algorithm>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace rcxc::test {

class StatementGenerator {
 public:
  explicit StatementGenerator(unsigned seed) : rng_(seed) { small_ = pick(0, 1) == 0; }

  // The globals the statements use, in the order the program declares them.
  static std::vector<std::string> globals() {
    return {"a", "b", "c", "d", "e", "flag", "m1", "m2", "m3", "s1", "s2", "o1", "o2", "f0c", "f1c", "f2c"};
  }

  std::string program() {
    std::ostringstream out;
    // Sometimes globals no statement uses, up to 28 in all: they keep
    // their slots (nqc's numbering), leaving the compilers few for the rest.
    out << "int a, b, c, d, e, flag, m1, m2, m3, s1, s2, o1, o2, f0c, f1c, f2c";
    for (int p = pick(0, 2) == 0 ? pick(1, 12) : 0; p > 0; --p) out << ", p" << p;
    out << ";\n";
    functions_ = pick(0, 3);
    for (int f = 0; f < functions_; ++f) function(out, f);
    subs_ = pick(0, 2);
    for (int s = 0; s < subs_; ++s) {
      out << "sub sub" << s << "() {\n";
      // nqc refuses a sub calling a sub (rcxc inlines it): none here.
      Context ctx{.where = Where::Sub, .counter = "s", .callable = functions_};
      block(out, ctx, 2, pick(2, 5));
      out << "}\n";
    }
    beeper_ = pick(0, 2) == 0;
    if (beeper_) {
      // Started and stopped by main around a wait of its own: two beeps.
      out << "task beeper() {\n  while (true) {\n    PlaySound(" << pick(0, 5) << ");\n    Wait(40);\n  }\n}\n";
      sounds_ += 2;
    }
    // main first (into a string): it decides how many turns `other` gets.
    std::ostringstream body;
    main_body(body);
    if (handshakes_ > 0) {
      // Started anew for each turn, it takes the branch of the turn.
      out << "task other() {\n";
      for (int k = 0; k < handshakes_; ++k) {
        out << (k == 0 ? "  if" : "  else if") << " (flag == " << 2 * k + 1 << ") {\n";
        Context ctx{.where = Where::Other, .counter = "o", .callable = functions_, .subs_callable = true};
        block(out, ctx, 2, pick(1, 3));
        out << "  flag = " << 2 * k + 2 << ";\n  }\n";
      }
      out << "}\n";
    }
    out << body.str();
    return out.str();
  }

 private:
  enum class Where { Main, Other, Sub, Function };

  struct Context {
    Where where = Where::Main;
    std::string counter{};             // prefix of the loop counters: m1, m2, ... (functions: their one)
    int loops = 0;                   // loops around the statement
    std::vector<std::string> vars{};   // assignable names besides a..e: parameters, locals
    std::vector<std::string> reads{};  // names only read (`const int &` parameters)
    std::vector<std::string> constants{};  // `const int` parameters: constants
    int callable = 0;                // functions f0 .. f(callable-1) may be called
    bool subs_callable = false;
    bool in_switch = false;
    std::string exit_label{};  // a label after an enclosing loop, for goto
  };

  // Statements in a nested block.
  int statements() { return pick(1, small_ ? 2 : 4); }

  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  template <class T, std::size_t N>
  const T& one_of(const T (&items)[N]) {
    return items[pick(0, static_cast<int>(N) - 1)];
  }

  std::string var(const Context& ctx) {
    static const char* globals[] = {"a", "b", "c", "d", "e"};
    if (!ctx.vars.empty() && pick(0, 2) == 0) return ctx.vars[pick(0, static_cast<int>(ctx.vars.size()) - 1)];
    return one_of(globals);
  }

  // Under `^` no `const int &` parameter either: its argument may have a
  // side effect, and it is evaluated where the parameter is read.
  std::string readable(const Context& ctx) {
    if (!ctx.reads.empty() && no_effects_ == 0 && pick(0, 3) == 0) return ctx.reads[pick(0, static_cast<int>(ctx.reads.size()) - 1)];
    return var(ctx);
  }

  std::string small() { return std::to_string(pick(-20, 20)); }

  std::string edge() {
    static const int edges[] = {-32768, -32767, 32767, 32766, -1, 0, 1, 255, 256, 16384, -16384, 1000};
    return std::to_string(one_of(edges));
  }

  std::string sensor() {
    static const char* sensors[] = {"SENSOR_1", "SENSOR_2", "SENSOR_3"};
    return one_of(sensors);
  }

  // An expression with never two constant operands to one operator. Some
  // leaves are `++v`, `v--`, ...: side effects in the order nqc's code has
  // them (docs/language.md), except under `^`, whose sides nqc's code
  // computes twice (docs/compiler.md).
  std::string expr(const Context& ctx, int depth) {
    if (depth == 0 || pick(0, 4) == 0) {
      int k = pick(0, 11);
      if (k == 0) return sensor();
      if (k == 2 && pick(0, 2) == 0) return "Message()";
      if (k == 1 && no_effects_ == 0) {
        static const char* forms[] = {"++", "--"};
        std::string v = var(ctx), op = one_of(forms);
        return "(" + (pick(0, 1) ? v + op : op + v) + ")";
      }
      return readable(ctx);
    }
    auto operand = [&] { return expr(ctx, depth - 1); };
    auto other = [&] { return pick(0, 1) == 0 ? small() : operand(); };
    switch (pick(0, 14)) {
      case 0: case 1: {
        static const char* ops[] = {"+", "-", "*", "&", "|"};
        return "(" + operand() + " " + one_of(ops) + " " + other() + ")";
      }
      case 2: {
        ++no_effects_;
        std::string x = "(" + operand() + " ^ " + other() + ")";
        --no_effects_;
        return x;
      }
      case 3: {
        // A constant divisor is never 0; a variable one may be (the dividend
        // is then left, on the brick and with both compilers).
        static const char* ops[] = {"/", "%"};
        std::string divisor = pick(0, 1) == 0 ? operand() : std::to_string(one_of(kDivisors));
        return "(" + operand() + " " + one_of(ops) + " " + divisor + ")";
      }
      case 4: return "(" + operand() + (pick(0, 1) ? " << " : " >> ") + std::to_string(pick(0, 15)) + ")";
      case 5: case 6: return "(" + comparison(ctx, depth - 1) + ")";
      case 7: return "(" + comparison(ctx, depth - 1) + (pick(0, 1) ? " && " : " || ") + comparison(ctx, depth - 1) + ")";
      case 8: {
        static const char* ops[] = {"-", "!", "~"};
        return std::string(one_of(ops)) + "(" + operand() + ")";
      }
      case 9: return std::string(pick(0, 1) ? "abs(" : "sign(") + operand() + ")";
      case 10: return "(" + comparison(ctx, depth - 1) + " ? " + operand() + " : " + other() + ")";
      default: return "(" + operand() + (pick(0, 1) ? " + " : " - ") + other() + ")";
    }
  }

  std::string comparison(const Context& ctx, int depth) {
    static const char* ops[] = {"<", "<=", "==", "!=", ">", ">="};
    std::string l = expr(ctx, depth);
    std::string r = pick(0, 1) == 0 ? small() : expr(ctx, depth);
    return l + " " + one_of(ops) + " " + r;
  }

  std::string condition(const Context& ctx) {
    switch (pick(0, 5)) {
      case 0: return "!(" + comparison(ctx, 1) + ")";
      case 1: return "(" + comparison(ctx, 1) + ") " + (pick(0, 1) ? "&&" : "||") + " (" + comparison(ctx, 1) + ")";
      case 2: return expr(ctx, 2);  // a value as a condition
      default: return comparison(ctx, 1);
    }
  }

  std::string mask() {
    static const char* masks[] = {"OUT_A", "OUT_B", "OUT_C", "OUT_A+OUT_C", "OUT_A+OUT_B+OUT_C"};
    return one_of(masks);
  }

  // Whether the statement runs once per pass of a task's top level: in
  // main or other, outside loops (subs and functions run in loops too).
  static bool direct(const Context& ctx) {
    return ctx.loops == 0 && (ctx.where == Where::Main || ctx.where == Where::Other);
  }

  void indent(std::ostringstream& out, const Context& ctx) { out << std::string(2 + 2 * ctx.loops, ' '); }

  void statement(std::ostringstream& out, Context& ctx, int depth) {
    int k = pick(0, 30);
    indent(out, ctx);
    switch (k) {
      case 0: case 1: case 2: out << var(ctx) << " = " << expr(ctx, 3) << ";\n"; return;
      case 3: case 4: {
        // `||=` sets the absolute value, `+-=` the sign.
        static const char* ops[] = {"+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "||=", "+-="};
        std::string op = one_of(ops);
        if (op == "^=") ++no_effects_;
        std::string rhs = (op == "/=" || op == "%=") && pick(0, 1) ? std::to_string(one_of(kDivisors)) : expr(ctx, 2);
        if (op == "^=") --no_effects_;
        out << var(ctx) << " " << op << " " << rhs << ";\n";
        return;
      }
      case 5: out << var(ctx) << (pick(0, 1) ? " <<= " : " >>= ") << pick(0, 15) << ";\n"; return;
      case 6: {
        static const char* forms[] = {"++", "--"};
        std::string v = var(ctx), op = one_of(forms);
        out << (pick(0, 1) ? v + op : op + v) << ";\n";
        return;
      }
      case 7: out << var(ctx) << " = " << edge() << ";\n"; return;
      case 8: case 9:
        if (depth > 0) return if_chain(out, ctx, depth);
        break;
      case 10: case 11:
        if (depth > 0) return loop(out, ctx, depth);
        break;
      case 12:
        if (depth > 0) return switch_statement(out, ctx, depth);
        break;
      case 13: case 14:
        if (ctx.callable > 0) return call(out, ctx);
        break;
      case 15:
        if (ctx.subs_callable && subs_ > 0) {
          out << "sub" << pick(0, subs_ - 1) << "();\n";
          return;
        }
        break;
      case 16: case 17: return motor(out, ctx);
      case 18:
        // The queue holds a sound playing and 8 waiting: no more than that
        // may be asked for, or which are dropped depends on speed.
        if (!direct(ctx) || sounds_ >= 6) break;
        ++sounds_;
        if (pick(0, 1)) out << "PlaySound(" << pick(0, 5) << ");\n";
        else out << "PlayTone(" << pick(2, 40) * 50 << ", " << pick(1, 20) << ");\n";
        return;
      case 19: out << "AddToDatalog(" << readable(ctx) << ");\n"; return;
      case 20:
        switch (pick(0, 3)) {
          case 0: out << "SelectDisplay(" << pick(0, 6) << ");\n"; break;
          case 1: out << "SelectDisplay(" << var(ctx) << " & 3);\n"; break;
          default: out << "SendMessage(" << var(ctx) << " & 255);\n";
        }
        return;
      case 21:
        if (direct(ctx)) {
          switch (pick(0, 2)) {
            case 0: out << "OnFor(" << mask() << ", " << pick(1, 4) << ");\n"; break;
            case 1: out << "ClearMessage();\n"; break;
            default: out << "Wait(" << pick(1, 4) << ");\n";
          }
          return;
        }
        break;
      case 22:
        if (direct(ctx)) {
          // Read half a tick (50 ms) away from the timer's next step.
          int t = pick(0, 2);
          out << "ClearTimer(" << t << "); Wait(" << pick(0, 2) * 10 + 5 << "); " << var(ctx) << " = Timer(" << t
              << ");\n";
          return;
        }
        break;
      case 23: case 24:
        // In a switch, break leaves the switch and continue the loop.
        if (ctx.loops > 0 || ctx.in_switch) {
          out << "if (" << condition(ctx) << ") " << (ctx.loops > 0 && pick(0, 1) ? "continue" : "break") << ";\n";
          return;
        }
        break;
      case 25:
        if (ctx.where == Where::Function || ctx.where == Where::Sub) {
          out << "if (" << condition(ctx) << ") return;\n";
          return;
        }
        break;
      case 26:
        if (locals_.size() < kMostLocals) {
          // A block local, visible to the statements after it in its block.
          std::string name = "l" + std::to_string(local_names_++);
          locals_.push_back(name);
          out << "int " << name << " = " << expr(ctx, 2) << ";\n";
          ctx.vars.push_back(name);
          return;
        }
        break;
      case 28:
        if (!ctx.constants.empty()) {
          // A constant parameter, beside a variable (nqc folds two constants in 32 bits).
          static const char* ops[] = {"+", "-", "*", "&", "|", "^"};
          std::string v = var(ctx);
          std::string left = readable(ctx);
          std::string op = one_of(ops);
          // Not `^` over a `const int &` parameter (readable() above): its
          // argument may have a side effect, which nqc's code runs twice.
          // Taken after the draws, so every other program stays as it was.
          if (op == "^" && std::find(ctx.reads.begin(), ctx.reads.end(), left) != ctx.reads.end()) op = "|";
          out << v << " = " << left << " " << op << " "
              << ctx.constants[static_cast<std::size_t>(pick(0, static_cast<int>(ctx.constants.size()) - 1))] << ";\n";
          return;
        }
        break;
      case 29:
        if (!ctx.exit_label.empty()) {
          out << "if (" << condition(ctx) << ") goto " << ctx.exit_label << ";\n";
          return;
        }
        if (depth > 0 && (ctx.where == Where::Main || ctx.where == Where::Other)) {
          // Forward over a block.
          std::string label = "skip" + std::to_string(labels_++);
          out << "if (" << condition(ctx) << ") goto " << label << ";\n";
          indent(out, ctx);
          braced(out, ctx, depth - 1);
          out << "\n";
          indent(out, ctx);
          out << label << ": ;\n";
          return;
        }
        break;
      case 27: out << var(ctx) << " = " << sensor() << (pick(0, 1) ? " + " : " * ") << readable(ctx) << ";\n"; return;
      default: break;
    }
    out << var(ctx) << " += " << expr(ctx, 2) << ";\n";
  }

  // One statement that is one statement (statement() sometimes writes a
  // loop's counter set-up before it), for a body without braces.
  void single_statement(std::ostringstream& out, Context& ctx, int depth) {
    indent(out, ctx);
    switch (depth > 0 ? pick(0, 4) : pick(0, 2)) {
      case 0: out << var(ctx) << " = " << expr(ctx, 3) << ";\n"; return;
      case 1: return motor(out, ctx);
      case 2: out << var(ctx) << " -= " << expr(ctx, 2) << ";\n"; return;
      case 3: return if_chain(out, ctx, depth);
      default: return switch_statement(out, ctx, depth);
    }
  }

  void block(std::ostringstream& out, Context ctx, int depth, int n) {
    std::size_t locals_before = locals_.size();
    for (int i = 0; i < n; ++i) statement(out, ctx, depth);
    show_locals(out, ctx, locals_before);
  }

  // Locals declared since `from` go out of scope: their values go to the datalog.
  void show_locals(std::ostringstream& out, const Context& ctx, std::size_t from) {
    for (std::size_t l = from; l < locals_.size(); ++l) {
      indent(out, ctx);
      out << "AddToDatalog(" << locals_[l] << ");\n";
    }
    locals_.resize(from);
  }

  void braced(std::ostringstream& out, const Context& ctx, int depth) {
    if (pick(0, 4) == 0) {
      // One statement without braces (a local declared there would be the
      // whole body: C refuses that, so none).
      std::size_t locals = locals_.size();
      locals_.resize(kMostLocals, "");
      out << "\n";
      Context inner = ctx;
      single_statement(out, inner, depth);
      locals_.resize(locals);
      indent(out, ctx);
      return;
    }
    out << "{\n";
    block(out, ctx, depth, statements());
    indent(out, ctx);
    out << "}";
  }

  void if_chain(std::ostringstream& out, Context& ctx, int depth) {
    Context inner = ctx;
    out << "if (" << condition(ctx) << ") ";
    braced(out, inner, depth - 1);
    int elses = pick(0, 3);
    for (int i = 0; i < elses; ++i) {
      bool last = i == elses - 1 && pick(0, 1) == 0;
      out << (last ? " else " : " else if (" + condition(ctx) + ") ");
      braced(out, inner, depth - 1);
      if (last) break;
    }
    out << "\n";
  }

  std::string counter(const Context& ctx) {
    if (ctx.where == Where::Function) return ctx.counter;
    return ctx.counter + std::to_string(ctx.loops + 1);
  }

  // A loop counting its passes in g: set to 0 before it, one more at the
  // top of each pass (where `continue` cannot skip it). `tail` is written
  // after the body, so a condition in it is drawn after the body's.
  template <class Tail>
  void counted_loop(std::ostringstream& out, const Context& ctx, const Context& inner, int depth,
                    const std::string& g, const std::string& head, Tail tail) {
    out << g << " = 0;\n";
    indent(out, ctx);
    out << head << "\n";
    indent(out, inner);
    out << g << "++;\n";
    block(out, inner, depth - 1, statements());
    indent(out, ctx);
    out << tail() << "\n";
  }

  void loop(std::ostringstream& out, Context& ctx, int depth) {
    Context inner = ctx;
    ++inner.loops;
    inner.in_switch = false;
    // In a task, sometimes a label after the loop that its body may jump to.
    if ((ctx.where == Where::Main || ctx.where == Where::Other) && pick(0, 3) == 0)
      inner.exit_label = "out" + std::to_string(labels_++);
    // Functions have one counter: one loop deep. Subs and other: two.
    int most = ctx.where == Where::Function ? 1 : ctx.where == Where::Main ? 3 : 2;
    int kind = pick(0, 7);
    if (ctx.loops >= most) kind = 4;  // repeat needs no counter
    std::string g = counter(ctx), limit = std::to_string(pick(1, 4));
    switch (kind) {
      case 0:
        counted_loop(out, ctx, inner, depth, g, "while (" + g + " < " + limit + " && (" + condition(ctx) + ")) {",
                     [] { return std::string("}"); });
        break;
      case 1:
        counted_loop(out, ctx, inner, depth, g, "do {",
                     [&] { return "} while (" + g + " < " + limit + " && (" + condition(ctx) + "));"; });
        break;
      case 2:
        out << "for (" << g << " = 0; " << g << " < " << limit << " && (" << condition(ctx) << "); " << g
            << "++) ";
        braced(out, inner, depth - 1);
        out << "\n";
        break;
      case 6:
        counted_loop(out, ctx, inner, depth, g, "do {",
                     [&] { return "} until (" + g + " >= " + limit + " || (" + condition(ctx) + "));"; });
        break;
      case 3:
        counted_loop(out, ctx, inner, depth, g, "until (" + g + " >= " + limit + " || (" + condition(ctx) + ")) {",
                     [] { return std::string("}"); });
        break;
      default:
        // A constant count, or a variable one kept small (a negative count
        // runs the body no time).
        if (pick(0, 1)) out << "repeat (" << pick(0, 4) << ") ";
        else out << "repeat (" << var(ctx) << (pick(0, 1) ? " & 3" : " % 4") << ") ";
        braced(out, inner, depth - 1);
        out << "\n";
    }
    if (!inner.exit_label.empty() && inner.exit_label != ctx.exit_label) {
      indent(out, ctx);
      out << inner.exit_label << ": ;\n";
    }
  }

  void switch_statement(std::ostringstream& out, Context& ctx, int depth) {
    Context inner = ctx;
    inner.in_switch = true;
    out << "switch (" << (pick(0, 1) ? var(ctx) + " & 3" : var(ctx)) << ") {\n";
    std::vector<int> labels = {0, 1, 2, 3, -1, 5};
    std::shuffle(labels.begin(), labels.end(), rng_);
    int cases = pick(1, 4);
    bool has_default = pick(0, 1) == 1;
    int default_at = has_default ? pick(0, cases) : -1;
    for (int c = 0; c <= cases; ++c) {
      if (c == default_at) {
        indent(out, ctx);
        out << "default:\n";
      }
      if (c == cases) break;
      indent(out, ctx);
      out << "case " << labels[static_cast<std::size_t>(c)] << ":";
      if (pick(0, 3) == 0) out << " case " << labels[static_cast<std::size_t>(c) + 1] << ":", ++c;
      out << "\n";
      int n = pick(0, 3);
      block(out, inner, depth - 1, n);
      // Without the break it falls through into the next case; a label
      // needs a statement after it.
      if (n == 0 || pick(0, 2) > 0) {
        indent(out, inner);
        out << "break;\n";
      }
    }
    if (default_at == cases) block(out, inner, depth - 1, pick(1, 2));
    indent(out, ctx);
    out << "}\n";
  }

  void call(std::ostringstream& out, const Context& ctx) {
    int f = pick(0, ctx.callable - 1);
    out << "f" << f << "(";
    const auto& params = params_[static_cast<std::size_t>(f)];
    for (std::size_t p = 0; p < params.size(); ++p) {
      if (p > 0) out << ", ";
      switch (params[p]) {
        case Param::Value: out << expr(ctx, 2); break;
        case Param::Reference: out << var(ctx); break;
        // nqc takes only a constant for `const int` (rcxc any expression).
        case Param::Constant: out << small(); break;
        case Param::ConstantReference: out << expr(ctx, 2); break;
      }
    }
    out << ");\n";
  }

  void motor(std::ostringstream& out, const Context& ctx) {
    static const char* calls[] = {"On", "Off", "Float", "Fwd", "Rev", "Toggle", "OnFwd", "OnRev"};
    static const char* modes[] = {"SetOutput(%s, OUT_ON)", "SetOutput(%s, OUT_OFF)", "SetOutput(%s, OUT_FLOAT)",
                                  "SetDirection(%s, OUT_FWD)", "SetDirection(%s, OUT_REV)",
                                  "SetDirection(%s, OUT_TOGGLE)"};
    switch (pick(0, 5)) {
      case 0: out << "SetPower(" << mask() << ", " << pick(0, 7) << ");\n"; return;
      case 1: out << "SetPower(" << mask() << ", " << var(ctx) << " & 7);\n"; return;
      case 2: {
        std::string m = one_of(modes);
        out << m.replace(m.find("%s"), 2, mask()) << ";\n";
        return;
      }
      default: out << one_of(calls) << "(" << mask() << ");\n";
    }
  }

  enum class Param { Value, Reference, Constant, ConstantReference };

  void function(std::ostringstream& out, int f) {
    static const char* names[] = {"x", "r", "k", "q"};
    std::vector<Param> params;
    Context ctx{.where = Where::Function, .counter = "f" + std::to_string(f) + "c", .callable = f};
    out << "void f" << f << "(";
    int n = pick(1, 4);
    for (int p = 0; p < n; ++p) {
      auto kind = static_cast<Param>(pick(0, 3));
      params.push_back(kind);
      std::string name = names[static_cast<int>(kind)] + std::to_string(p);
      static const char* types[] = {"int ", "int &", "const int ", "const int &"};
      out << (p > 0 ? ", " : "") << types[static_cast<int>(kind)] << name;
      (kind == Param::Value || kind == Param::Reference ? ctx.vars
       : kind == Param::Constant                        ? ctx.constants
                                                        : ctx.reads)
          .push_back(name);
    }
    params_.push_back(params);
    out << ") {\n";
    block(out, ctx, 2, pick(2, 5));
    out << "}\n";
  }

  void main_body(std::ostringstream& out) {
    static const char* second[] = {"SetSensor(SENSOR_2, SENSOR_TOUCH);",
                                   "SetSensor(SENSOR_2, SENSOR_ROTATION); ClearSensor(SENSOR_2);",
                                   "SetSensor(SENSOR_2, SENSOR_LIGHT);"};
    out << "task main() {\n  SetSensor(SENSOR_1, SENSOR_TOUCH);\n  " << one_of(second) << "\n"
        << "  SetSensor(SENSOR_3, SENSOR_LIGHT);\n  CreateDatalog(" << kDatalogSize << ");\n  ClearTimer(3);\n";
    for (const char* v : {"a", "b", "c", "d", "e"}) out << "  " << v << " = " << (pick(0, 2) ? small() : edge()) << ";\n";
    bool other = pick(0, 2) > 0;
    for (int phase = 0; phase < 3; ++phase) {
      Context ctx{.where = Where::Main, .counter = "m", .callable = functions_, .subs_callable = true};
      int n = pick(2, small_ ? 3 : 5);
      for (int i = 0; i < n; ++i) {
        statement(out, ctx, small_ ? 2 : 3);
        if (other && pick(0, 4) == 0) handshake(out);
      }
      show_locals(out, ctx, 0);
      if (phase == 0 && beeper_) out << "  start beeper;\n  Wait(60);\n  stop beeper;\n";
      if (phase == 2 && other && handshakes_ == 0) handshake(out);
      // Waiting out the phase: a busy `until` would cost the emulator a
      // hundred thousand instructions a second, so it waits to the tick
      // before the phase's end and polls only over that last tick. A wait
      // alone ends as far into a tick as main came into it, so two codes a
      // few instructions apart across a tick left 99 ms apart.
      int end_tick = kPhaseTicks * (phase + 1);
      out << "  Wait(" << (end_tick - 1) * 10 << " - 10 * Timer(3));\n  until (Timer(3) >= " << end_tick << ");\n";
    }
    for (const char* v : {"a", "b", "c", "d", "e"}) out << "  AddToDatalog(" << v << ");\n";
    out << "}\n";
  }

  // Main hands `other` its next turn and waits for it to end.
  void handshake(std::ostringstream& out) {
    out << "  flag = " << 2 * handshakes_ + 1 << "; start other; until (flag == " << 2 * handshakes_ + 2 << ");\n";
    ++handshakes_;
  }

 public:
  // A phase of main lasts this many ticks of Timer(3) (100 ms each); the
  // inputs change kInputLeadMs before a phase ends.
  static constexpr int kPhaseTicks = 50;
  static constexpr int kInputLeadMs = 500;
  // Entries of the datalog main creates.
  static constexpr int kDatalogSize = 50;

 private:

  static constexpr std::size_t kMostLocals = 4;
  static constexpr int kDivisors[] = {-3, -2, -1, 1, 2, 3, 7, 16, 100};

  std::mt19937 rng_;
  int functions_ = 0;
  int subs_ = 0;
  // Half the programs are smaller: nqc's code for them has fewer tests
  // more than 127 bytes long, which it gets wrong (docs/compiler.md).
  bool small_ = false;
  bool beeper_ = false;
  int sounds_ = 0;
  int no_effects_ = 0;
  int labels_ = 0;  // inside `^`: no side effects
  int handshakes_ = 0;
  std::vector<std::string> locals_;  // block locals in scope
  int local_names_ = 0;  // locals declared so far (each gets a new name)
  std::vector<std::vector<Param>> params_;
};

}  // namespace rcxc::test
