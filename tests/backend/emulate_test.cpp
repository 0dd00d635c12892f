// The compiler's output run on the emulator (runtime/vm.h): operators
// against a C reference over edge values, subroutine nesting, many subs,
// slot exhaustion, branch forms at the near/far boundary, the corpus.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>

#include <fmt/format.h>

#include "backend/compile.h"
#include "runtime/vm.h"
#include "tests/support/compiled.h"

using namespace rcxc;

namespace {

struct Compiled {
  std::optional<backend::Output> out;
  Diagnostics diags;
  ir::Log log;
  std::string messages;
};

Compiled compile(const std::string& text, ir::OptLevel level = ir::OptLevel::Os, bool stdlib = false) {
  Compiled c;
  SourceManager sm;
  frontend::Options options;
  options.no_stdlib = !stdlib;
  c.out = backend::compile_source("test.nqc", text, options, level, sm, c.diags, c.log);
  for (const auto& d : c.diags.all()) c.messages += render_text(d, sm);
  return c;
}

// Runs the image until every task ended (or `limit_ms`), returns the machine.
rcx::Machine run(const rcx::Image& image, std::int64_t limit_ms = 60'000) {
  rcx::Machine m;
  auto err = m.load(0, image);
  EXPECT_FALSE(err.has_value()) << *err;
  m.start_program();
  m.run(limit_ms * rcx::kMicrosPerMs);
  return m;
}

int global(const rcx::Machine& m, const rcx::Image& image, const std::string& name) {
  return test::global_value(m, image, name);
}

std::int16_t w(long v) { return static_cast<std::int16_t>(static_cast<std::uint16_t>(v & 0xffff)); }

// The C reference on 16-bit values, with the documented choices where C
// leaves it open: x / 0 and x % 0 leave x (the firmware's division), >>
// shifts in zeros (as nqc's code does), shift counts < 0 shift nothing and
// counts > 15 shift everything out.
std::map<std::string, std::function<int(int, int)>> binary_reference() {
  return {
      {"+", [](int a, int b) { return w(a + b); }},
      {"-", [](int a, int b) { return w(a - b); }},
      {"*", [](int a, int b) { return w(static_cast<long>(a) * b); }},
      {"/", [](int a, int b) { return b == 0 ? a : w(a / b); }},
      {"%", [](int a, int b) { return b == 0 ? a : (b == -1 ? 0 : w(a % b)); }},
      {"&", [](int a, int b) { return w(a & b); }},
      {"|", [](int a, int b) { return w(a | b); }},
      {"^", [](int a, int b) { return w(a ^ b); }},
      {"<<", [](int a, int b) { return b < 0 ? a : b > 15 ? 0 : w(static_cast<long>(a) * (1L << b)); }},
      {">>", [](int a, int b) { return b < 0 ? a : b > 15 ? 0 : w(static_cast<std::uint16_t>(a) >> b); }},
      {"<", [](int a, int b) { return a < b ? 1 : 0; }},
      {"<=", [](int a, int b) { return a <= b ? 1 : 0; }},
      {">", [](int a, int b) { return a > b ? 1 : 0; }},
      {">=", [](int a, int b) { return a >= b ? 1 : 0; }},
      {"==", [](int a, int b) { return a == b ? 1 : 0; }},
      {"!=", [](int a, int b) { return a != b ? 1 : 0; }},
      {"&&", [](int a, int b) { return (a != 0 && b != 0) ? 1 : 0; }},
      {"||", [](int a, int b) { return (a != 0 || b != 0) ? 1 : 0; }},
  };
}

std::vector<int> edge_values() {
  std::vector<int> v{-32768, -1, 0, 1, 32767, 2, -2, 7, -300, 12345};
  std::mt19937 rng(42);
  std::uniform_int_distribution<int> any(-32768, 32767);
  for (int i = 0; i < 4; ++i) v.push_back(any(rng));
  return v;
}

std::vector<int> shift_counts() { return {0, 1, 2, 3, 7, 8, 14, 15, 16, -1}; }

// Runs a case for every (a, b) pair, `per_program` cases to a program (the
// 32 slots limit them): `decls(k)` names case k's result variables,
// `stmts(k, a, b)` computes them, `check(m, image, k, a, b)` checks them.
// The operands are globals, so nothing is folded at compile time.
void for_pairs(const std::vector<int>& lhs, const std::vector<int>& rhs, std::size_t per_program,
               const std::function<std::string(std::size_t)>& decls,
               const std::function<std::string(std::size_t, int, int)>& stmts,
               const std::function<void(const rcx::Machine&, const rcx::Image&, std::size_t, int, int)>& check) {
  std::vector<std::pair<int, int>> pairs;
  for (int a : lhs)
    for (int b : rhs) pairs.emplace_back(a, b);
  for (std::size_t base = 0; base < pairs.size(); base += per_program) {
    std::size_t n = std::min(per_program, pairs.size() - base);
    std::string declared = "int a, b, x, y";
    std::string body;
    for (std::size_t k = 0; k < n; ++k) {
      declared += decls(k);
      body += stmts(k, pairs[base + k].first, pairs[base + k].second);
    }
    std::string src = declared + ";\ntask main() {\n" + body + "}\n";
    auto c = compile(src);
    ASSERT_TRUE(c.out) << c.messages << src;
    auto m = run(c.out->image);
    ASSERT_EQ(m.stop().kind, rcx::StopKind::Ended) << src;
    for (std::size_t k = 0; k < n; ++k) check(m, c.out->image, k, pairs[base + k].first, pairs[base + k].second);
  }
}

// Checks `a OP b` for every pair.
void check_binary(const std::string& op, const std::vector<int>& lhs, const std::vector<int>& rhs, bool constant_rhs) {
  auto ref = binary_reference().at(op);
  for_pairs(
      lhs, rhs, 20, [](std::size_t k) { return fmt::format(", r{}", k); },
      [&](std::size_t k, int a, int b) {
        return constant_rhs ? fmt::format("  a = {}; r{} = a {} ({});\n", a, k, op, b)
                            : fmt::format("  a = {}; b = {}; r{} = a {} b;\n", a, b, k, op);
      },
      [&](const rcx::Machine& m, const rcx::Image& image, std::size_t k, int a, int b) {
        EXPECT_EQ(global(m, image, fmt::format("r{}", k)), ref(a, b))
            << a << " " << op << " " << b << (constant_rhs ? " (constant right side)" : "");
      });
}

// The result replaces an operand: x = (x OP b) + 1, y = a OP y and
// x = b ? x OP b : -x, where the compiler works in the target variable
// itself and must not overwrite it before its last read.
void check_into_operand(const std::string& op, const std::vector<int>& lhs, const std::vector<int>& rhs) {
  auto ref = binary_reference().at(op);
  for_pairs(
      lhs, rhs, 6, [](std::size_t k) { return fmt::format(", p{0}, q{0}, s{0}", k); },
      [&](std::size_t k, int a, int b) {
        return fmt::format("  a = {1}; b = {2}; x = a; x = (x {0} b) + 1; p{3} = x;\n", op, a, b, k) +
               fmt::format("  y = b; y = a {0} y; q{1} = y;\n", op, k) +
               fmt::format("  x = a; x = (b ? x {0} b : -x); s{1} = x;\n", op, k);
      },
      [&](const rcx::Machine& m, const rcx::Image& image, std::size_t k, int a, int b) {
        EXPECT_EQ(global(m, image, fmt::format("p{}", k)), w(ref(a, b) + 1)) << "x = (x " << op << " b) + 1, " << a << ", " << b;
        EXPECT_EQ(global(m, image, fmt::format("q{}", k)), ref(a, b)) << "y = a " << op << " y, " << a << ", " << b;
        EXPECT_EQ(global(m, image, fmt::format("s{}", k)), b != 0 ? ref(a, b) : w(-a))
            << "x = b ? x " << op << " b : -x, " << a << ", " << b;
      });
}

}  // namespace

class BinaryOperator : public ::testing::TestWithParam<std::string> {};

TEST_P(BinaryOperator, MatchesTheReferenceWhenTheResultReplacesAnOperand) {
  const std::string& op = GetParam();
  bool shift = op == "<<" || op == ">>";
  std::vector<int> values{-32768, -1, 0, 1, 32767, 7, -300};
  check_into_operand(op, values, shift ? std::vector<int>{0, 1, 7, 15, 16, -1} : values);
}

TEST_P(BinaryOperator, MatchesTheReferenceOnEdgeValues) {
  const std::string& op = GetParam();
  bool shift = op == "<<" || op == ">>";
  check_binary(op, edge_values(), shift ? shift_counts() : edge_values(), false);
}

TEST_P(BinaryOperator, MatchesTheReferenceWithAConstantRightSide) {
  const std::string& op = GetParam();
  bool shift = op == "<<" || op == ">>";
  check_binary(op, edge_values(), shift ? shift_counts() : std::vector<int>{-32768, -1, 0, 1, 3, 32767}, true);
}

std::string operator_name(const ::testing::TestParamInfo<std::string>& info) {
  static const std::map<std::string, std::string> names{
      {"+", "Add"}, {"-", "Sub"}, {"*", "Mul"}, {"/", "Div"}, {"%", "Mod"}, {"&", "And"},
      {"|", "Or"}, {"^", "Xor"}, {"<<", "Shl"}, {">>", "Shr"}, {"<", "Lt"}, {"<=", "Le"},
      {">", "Gt"}, {">=", "Ge"}, {"==", "Eq"}, {"!=", "Ne"}, {"&&", "LogAnd"}, {"||", "LogOr"}};
  return names.at(info.param);
}

INSTANTIATE_TEST_SUITE_P(Operators, BinaryOperator,
                         ::testing::Values("+", "-", "*", "/", "%", "&", "|", "^", "<<", ">>", "<", "<=", ">", ">=",
                                           "==", "!=", "&&", "||"),
                         operator_name);

TEST(Emulate, UnaryOperatorsAndConditional) {
  auto values = edge_values();
  // 5 results per value: 5 values per program fit the 32 slots.
  for (std::size_t from = 0; from < values.size(); from += 5) {
    std::string d = "int a", b;
    std::size_t to = std::min(values.size(), from + 5);
    for (std::size_t k = from; k < to; ++k) {
      d += fmt::format(", n{0}, c{0}, l{0}, q{0}, s{0}", k);
      b += fmt::format("  a = {1}; n{0} = -a; c{0} = ~a; l{0} = !a; q{0} = a > 0 ? a : -a; s{0} = a; s{0} = -s{0};\n",
                       k, values[k]);
    }
    std::string src = d + ";\ntask main() {\n" + b + "}\n";
    auto c = compile(src);
    ASSERT_TRUE(c.out) << c.messages;
    auto m = run(c.out->image);
    for (std::size_t k = from; k < to; ++k) {
      int a = values[k];
      EXPECT_EQ(global(m, c.out->image, fmt::format("n{}", k)), w(-a)) << a;
      EXPECT_EQ(global(m, c.out->image, fmt::format("c{}", k)), w(~a)) << a;
      EXPECT_EQ(global(m, c.out->image, fmt::format("l{}", k)), a == 0 ? 1 : 0) << a;
      EXPECT_EQ(global(m, c.out->image, fmt::format("q{}", k)), a > 0 ? a : w(-a)) << a;
      EXPECT_EQ(global(m, c.out->image, fmt::format("s{}", k)), w(-a)) << a;
    }
  }
}

TEST(Emulate, AnAbsorbingOperandMakesTheOperationConstantWhenTheOtherOnlyReads) {
  // Folded: each result is one `set` of a constant, at every level.
  // Not folded: an assignment or increment inside must still happen, and
  // the random source must still be drawn (each read moves it on), so `y`
  // gets the second number the brick draws, as without the `0 *`.
  const char* src = R"(
    int d, s, x, y, n, a, b, c, e, f;
    task main() {
      d = -32768; s = 3; n = 0;
      a = (2/60) * (d - 30) + 6; b = 0 << s; c = 0 >> (s + d); e = 0 % d;
      f = 0 * (n++);
      x = 0 * Random(1000); y = Random(1000);
    })";
  const char* drawn = "int x, y;\ntask main() { x = Random(1000); y = Random(1000); }\n";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::Os}) {
    auto c = compile(src, level, true);
    auto plain = compile(drawn, level, true);
    ASSERT_TRUE(c.out && plain.out) << c.messages;
    auto m = run(c.out->image), p = run(plain.out->image);
    EXPECT_EQ(global(m, c.out->image, "a"), 6);
    EXPECT_EQ(global(m, c.out->image, "b"), 0);
    EXPECT_EQ(global(m, c.out->image, "c"), 0);
    EXPECT_EQ(global(m, c.out->image, "e"), 0);
    EXPECT_EQ(global(m, c.out->image, "f"), 0);
    EXPECT_EQ(global(m, c.out->image, "n"), 1);
    EXPECT_EQ(global(m, c.out->image, "x"), 0);
    EXPECT_EQ(global(m, c.out->image, "y"), global(p, plain.out->image, "y"));
    const auto& code = c.out->image.find(rcx::FragmentType::Task, 0)->code;
    // No multiplication, division or subtraction was left to compute a..e.
    EXPECT_EQ(std::count(code.begin(), code.end(), rcx::info(rcx::Op::DivideVariable).code), 0);
    EXPECT_EQ(std::count(code.begin(), code.end(), rcx::info(rcx::Op::SubtractFromVariable).code), 0);
  }
}

TEST(Emulate, AShiftBySixteenOrMoreIsZeroWithoutComputingItsLeftSide) {
  // Every bit is shifted out, so `d << 16` is `0` when d only reads: one
  // `set` of 0 (as for `r = 0`), not d copied in and then overwritten. A left
  // side that changes something still runs (n is incremented).
  const char* src = R"(
    int d, n, r, q, k;
    task main() { d = 12345; n = 4; r = d << 16; q = (d - n) >> 17; k = (n++) << 16; })";
  const char* zeros = R"(
    int d, n, r, q, k;
    task main() { d = 12345; n = 4; r = 0; q = 0; k = n; n = n + 1; k = 0; })";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = compile(src, level, true);
    auto z = compile(zeros, level, true);
    ASSERT_TRUE(c.out && z.out) << c.messages;
    auto m = run(c.out->image);
    EXPECT_EQ(global(m, c.out->image, "r"), 0);
    EXPECT_EQ(global(m, c.out->image, "q"), 0);
    EXPECT_EQ(global(m, c.out->image, "k"), 0);
    EXPECT_EQ(global(m, c.out->image, "n"), 5);
    EXPECT_LE(c.out->image.find(rcx::FragmentType::Task, 0)->code.size(),
              z.out->image.find(rcx::FragmentType::Task, 0)->code.size());
  }
}

TEST(Emulate, AnUnusedRandomDrawStillMovesTheSourceOn) {
  // `t` is never read, but its draw decides which number `y` gets: the
  // second the brick draws, at every level, as with `x` kept.
  const char* src = "int y;\ntask main() { int t; t = Random(1000) + 1; y = Random(1000); }\n";
  const char* drawn = "int x, y;\ntask main() { x = Random(1000); y = Random(1000); }\n";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::Os}) {
    auto c = compile(src, level, true);
    auto plain = compile(drawn, level, true);
    ASSERT_TRUE(c.out && plain.out) << c.messages;
    auto m = run(c.out->image), p = run(plain.out->image);
    EXPECT_EQ(global(m, c.out->image, "y"), global(p, plain.out->image, "y"));
  }
}

TEST(Emulate, CompoundAssignmentsAndIncrements) {
  auto c = compile(R"(
int x, y, z, p, q;
task main() {
  x = 7; x += 5; x -= 2; x *= 3; x /= 4; x %= 5;      // ((7+5-2)*3/4) % 5 = 7 % 5 = 2
  y = -9; y ||= y;                                  // abs
  z = -9; z +-= z;                                  // sign
  p = 5; q = p++ + 10;                              // q = 15, p = 6
  p <<= 2; p ^= 3; p >>= 1;                         // 24 ^ 3 = 27, >> 1 = 13
}
)");
  ASSERT_TRUE(c.out) << c.messages;
  auto m = run(c.out->image);
  EXPECT_EQ(global(m, c.out->image, "x"), 2);
  EXPECT_EQ(global(m, c.out->image, "y"), 9);
  EXPECT_EQ(global(m, c.out->image, "z"), -1);
  EXPECT_EQ(global(m, c.out->image, "q"), 15);
  EXPECT_EQ(global(m, c.out->image, "p"), 13);
}

TEST(Emulate, ControlFlowStatements) {
  auto c = compile(R"(
int i, sum, evens, sw, rep, nested, dw;
task main() {
  sum = 0; evens = 0;
  for (i = 0; i < 10; i++) { if (i == 7) continue; sum += i; if (i % 2 == 0) evens++; }
  i = 0; while (true) { i++; if (i >= 5) break; }
  sw = 0;
  switch (i) { case 1: sw = 1; break; case 5: sw = 5; case 6: sw += 10; break; default: sw = -1; }
  rep = 0; repeat (3) { repeat (4) rep++; }
  nested = 0; repeat (2) repeat (2) repeat (2) repeat (2) repeat (2) nested++;
  dw = 0; do { dw += 3; } while (dw < 10);
  until (dw == 0) dw -= 3;
}
)");
  ASSERT_TRUE(c.out) << c.messages;
  auto m = run(c.out->image);
  EXPECT_EQ(global(m, c.out->image, "sum"), 45 - 7);
  EXPECT_EQ(global(m, c.out->image, "evens"), 5);
  EXPECT_EQ(global(m, c.out->image, "i"), 5);
  EXPECT_EQ(global(m, c.out->image, "sw"), 15);
  EXPECT_EQ(global(m, c.out->image, "rep"), 12);
  EXPECT_EQ(global(m, c.out->image, "nested"), 32);  // 5 deep: one level counts in a variable
  EXPECT_EQ(global(m, c.out->image, "dw"), 0);
}

TEST(Emulate, RepeatLeftByBreakDoesNotDisturbOuterCounters) {
  auto c = compile(R"(
int outer, inner;
task main() {
  outer = 0; inner = 0;
  repeat (3) { outer++; repeat (10) { inner++; if (inner % 4 == 0) break; } }
}
)");
  ASSERT_TRUE(c.out) << c.messages;
  auto m = run(c.out->image);
  EXPECT_EQ(global(m, c.out->image, "outer"), 3);
  EXPECT_EQ(global(m, c.out->image, "inner"), 12);
}

TEST(Emulate, InlineFunctionParameterKinds) {
  auto c = compile(R"(
int g, r, v, k;
void by_value(int x) { x = x + 1; r = x; }
void by_ref(int &x) { x = x * 2; }
void by_const(const int x) { k = x * 3; }
void by_expr(const int &e) { g = 0; v = e; g = 5; v += e; }
task main() {
  g = 10; by_value(g); by_ref(g); by_const(7); by_expr(g + 1);
}
)");
  ASSERT_TRUE(c.out) << c.messages;
  auto m = run(c.out->image);
  EXPECT_EQ(global(m, c.out->image, "r"), 11);
  EXPECT_EQ(global(m, c.out->image, "k"), 21);
  // by_expr re-evaluates g + 1 at each use: 0 + 1, then 5 + 1.
  EXPECT_EQ(global(m, c.out->image, "v"), 7);
  EXPECT_EQ(global(m, c.out->image, "g"), 5);
}

TEST(Emulate, NestedSubsThreeDeepFromSeveralTasks) {
  auto c = compile(R"(
int a, b, c, done1, done2;
sub inner() { c = c + 1; }
sub middle() { b = b + 1; inner(); }
sub outer() { a = a + 1; middle(); }
task main() { a = 0; b = 0; c = 0; done1 = 0; done2 = 0; start second; outer(); outer(); done1 = 1; }
task second() { outer(); done2 = 1; }
)");
  ASSERT_TRUE(c.out) << c.messages;
  auto m = run(c.out->image);
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Ended);
  EXPECT_EQ(global(m, c.out->image, "a"), 3);
  EXPECT_EQ(global(m, c.out->image, "b"), 3);
  EXPECT_EQ(global(m, c.out->image, "c"), 3);
  EXPECT_EQ(global(m, c.out->image, "done1"), 1);
  EXPECT_EQ(global(m, c.out->image, "done2"), 1);
}

TEST(Emulate, InlinedCopiesOfASubShareSlotsWhenTheirValuesNeverMeet) {
  // s0 needs a temporary (x & 7) and is inlined 18 times into s1 (a sub
  // cannot call a sub); each copy's temporary is dead outside its three
  // instructions, so all share one slot although main calls s1 twice.
  std::string src = "int x, p;\nsub s0() { p = p + (x & 7); }\nsub s1() {";
  for (int i = 0; i < 18; ++i) src += " s0(); x = x + 1;";
  src += " }\ntask main() { x = 0; p = 0; s1(); s1(); }\n";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::Os}) {
    auto c = compile(src, level, true);
    ASSERT_TRUE(c.out) << c.messages;
    EXPECT_LE(c.out->slots_used, 3);
    auto m = run(c.out->image);
    int expected = 0;
    for (int i = 0; i < 36; ++i) expected += i & 7;
    EXPECT_EQ(global(m, c.out->image, "p"), expected);
  }
}

TEST(Emulate, RecursionIsADiagnosticNamingTheCycle) {
  auto c = compile("sub a() { b(); }\nsub b() { a(); }\ntask main() { a(); }\n");
  EXPECT_FALSE(c.out);
  EXPECT_NE(c.messages.find("a -> b -> a"), std::string::npos) << c.messages;
}

TEST(Emulate, MoreThanEightSubsStillWork) {
  std::string src = "int n;\n";
  for (int i = 0; i < 11; ++i) src += fmt::format("sub s{0}() {{ n = n + {0}; }}\n", i);
  src += "task main() { n = 0;";
  for (int i = 0; i < 11; ++i) src += fmt::format(" s{0}(); s{0}();", i);
  src += " }\n";
  auto c = compile(src, ir::OptLevel::O1);
  ASSERT_TRUE(c.out) << c.messages;
  int subs = 0;
  for (const auto& f : c.out->image.fragments) subs += f.type == rcx::FragmentType::Subroutine ? 1 : 0;
  EXPECT_LE(subs, 8);
  auto m = run(c.out->image);
  EXPECT_EQ(global(m, c.out->image, "n"), 2 * 55);
}

TEST(Emulate, SlotExhaustionListsTheHolders) {
  std::string src = "int ";
  for (int i = 0; i < 33; ++i) src += fmt::format("{}v{}", i ? ", " : "", i);
  src += ";\ntask main() {";
  for (int i = 0; i < 33; ++i) src += fmt::format(" v{} = {};", i, i);
  src += " }\n";
  auto c = compile(src);
  EXPECT_FALSE(c.out);
  EXPECT_NE(c.messages.find("no variable slot left for 'v32'"), std::string::npos) << c.messages;
  EXPECT_NE(c.messages.find("slots 0 to 31 are held by 'v0', 'v1', 'v2', "), std::string::npos) << c.messages;
  EXPECT_EQ(c.messages.find("slot 0 is held by"), std::string::npos) << c.messages;
}

TEST(Emulate, LocalsInDisjointScopesShareSlots) {
  std::string src = "int out;\ntask main() { out = 0;";
  // 40 locals in separate blocks: more than 32, but never live together.
  for (int i = 0; i < 40; ++i) src += fmt::format(" {{ int l{0}; l{0} = out; out = l{0} + 1; }}", i);
  src += " }\n";
  auto c = compile(src, ir::OptLevel::O0);
  ASSERT_TRUE(c.out) << c.messages;
  auto m = run(c.out->image);
  EXPECT_EQ(global(m, c.out->image, "out"), 40);
}

TEST(Emulate, PragmaReserveKeepsSlotsFree) {
  auto c = compile("#pragma reserve 0 3\nint x;\ntask main() { x = 5; }\n");
  ASSERT_TRUE(c.out) << c.messages;
  for (const auto& s : c.out->image.symbols)
    if (s.type == rcx::SymbolType::Variable && s.name == "x") {
      EXPECT_GE(s.index, 4);
    }
}

TEST(Emulate, BranchesAcrossTheNearFarBoundary) {
  // if bodies of n one-byte instructions (ClearMessage) plus an increment:
  // the branch around them is near up to 127 bytes away, far beyond.
  for (int n : {110, 115, 116, 117, 118, 119, 120, 121, 122, 130}) {
    std::string body;
    for (int i = 0; i < n; ++i) body += "asm { 0x90 }; ";
    auto c = compile(fmt::format(R"(
int x, hits, loops;
task main() {{
  hits = 0; loops = 0;
  x = 1; if (x == 0) {{ {0} hits = 100; }}
  x = 0; if (x == 0) {{ {0} hits++; }}
  do {{ {0} loops++; }} while (loops < 3);
}}
)",
                                 body),
                     ir::OptLevel::O0);
    ASSERT_TRUE(c.out) << c.messages;
    auto m = run(c.out->image);
    EXPECT_EQ(global(m, c.out->image, "hits"), 1) << n;
    EXPECT_EQ(global(m, c.out->image, "loops"), 3) << n;
  }
}

TEST(Emulate, CorpusCompilesAndRuns) {
  std::filesystem::path corpus(RCXC_CORPUS_DIR);
  if (!std::filesystem::exists(corpus)) GTEST_SKIP() << "no corpus at " << corpus;
  int compiled = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(corpus)) {
    if (entry.path().extension() != ".nqc") continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    auto name = entry.path().filename().string();
    auto c = compile(text.str(), ir::OptLevel::Os, true);
    // Two tutorial programs are wrong on purpose: an undefined output and
    // an array, which the RCX does not have.
    if (name == "01_errors.nqc" || name == "03_variables.nqc") {
      EXPECT_FALSE(c.out) << name;
      continue;
    }
    ASSERT_TRUE(c.out) << name << "\n" << c.messages;
    ++compiled;
    rcx::Machine m;
    ASSERT_FALSE(m.load(0, c.out->image).has_value()) << name;
    m.start_program();
    m.run(5000 * rcx::kMicrosPerMs);
    EXPECT_FALSE(m.stop().fault.has_value()) << name << ": " << m.stop().fault->message;
  }
  EXPECT_GE(compiled, 40);
}

TEST(Emulate, HugeTaskGetsADiagnosticNotACrash) {
  // nqc crashes on a 20 000-line task; rcxc reports that it does not fit.
  std::string src = "int x, y, z;\ntask main() {\n";
  for (int i = 0; i < 20000; ++i) {
    switch (i % 4) {
      case 0: src += fmt::format("  x = x + {} * y;\n", i % 100); break;
      case 1: src += fmt::format("  if (x > {}) y = x % 7; else z = y ^ x;\n", i % 50); break;
      case 2: src += fmt::format("  OnFwd(OUT_A); Wait({});\n", i % 300); break;
      default: src += "  z = (x << 2) + (y >> 1);\n";
    }
  }
  src += "}\n";
  auto c = compile(src, ir::OptLevel::Os, true);
  EXPECT_FALSE(c.out);
  EXPECT_NE(c.messages.find("task main is"), std::string::npos) << c.messages.substr(0, 500);
  EXPECT_NE(c.messages.find("at most 32767 bytes"), std::string::npos);
}

TEST(Emulate, GotoLabelsAndAsm) {
  auto c = compile(R"(
#pragma reserve 0 0
int n, a, b;
task main() {
  n = 0;
again:
  n++;
  if (n < 4) goto again;
  repeat (3) { a = a + 1; if (a == 2) goto out; }
out:
  asm { set b, 40; add b, n; }      // mnemonic form: b = 40 + n
  asm { 0x14, 0, $a, 0x24, 0, 2, 10, 0 }  // raw: set var[0], a; add var[0], 10
}
)");
  ASSERT_TRUE(c.out) << c.messages;
  auto m = run(c.out->image);
  EXPECT_EQ(global(m, c.out->image, "n"), 4);
  EXPECT_EQ(global(m, c.out->image, "b"), 44);
  EXPECT_EQ(global(m, c.out->image, "a"), 2);
  EXPECT_EQ(m.state().vars[0], 12);  // slot 0 is reserved: only the raw bytes use it
}

TEST(Emulate, StartAndStopTasksWithTheLibrary) {
  auto c = compile(R"(
int ticks, seen;
task counter() { while (true) { ticks++; Wait(1); } }
task main() {
  ticks = 0;
  start counter;
  Wait(50);
  stop counter;
  seen = ticks;
  Wait(50);
  OnFwd(OUT_A);
}
)",
                   ir::OptLevel::Os, true);
  ASSERT_TRUE(c.out) << c.messages;
  auto m = run(c.out->image, 2000);
  int seen = global(m, c.out->image, "seen");
  EXPECT_GT(seen, 10);
  EXPECT_EQ(global(m, c.out->image, "ticks"), seen);  // stopped: no more ticks
  EXPECT_EQ(m.state().outputs[0].mode, rcx::OutputMode::On);
  EXPECT_EQ(m.state().outputs[0].dir, rcx::Direction::Forward);
  EXPECT_EQ(m.state().outputs[0].power, 7);
}
