// A comparison used as a value (`b = (x >= y);`) costs a test and a set on
// one outcome and a test, a set and a jump on the other. Which outcome
// pays the jump is a choice of the code's layout; on neither outcome may
// rcxc's code run more instructions than nqc's (docs/compiler.md, "Speed
// on the brick"). The counts of nqc's code are read off `nqc -Trcx -L` of
// the same programs, by hand: the task's `pwr ABC, 7; dir ABC, fwd` (2)
// and the statement's instructions on each outcome.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

struct Case {
  std::string statement;
  int x, y;           // the inputs, set before the program starts
  int value;          // what b ends as
  int nqc;            // instructions nqc's code runs
  int at_most;        // what rcxc's may run (fewer where a jump is saved)
};

int variable_index(const rcx::Image& image, const std::string& name) {
  for (const auto& s : image.symbols)
    if (s.type == rcx::SymbolType::Variable && s.name == name) return s.index;
  ADD_FAILURE() << "no variable " << name;
  return 0;
}

// x and y are never written by the program: the brick's values are set
// before it starts, so no level can fold the comparison.
void check(const Case& c, ir::OptLevel level) {
  std::string text = "int x, y, b;\ntask main() {\n  " + c.statement + "\n}\n";
  auto compiled = test::compile_program(text, level);
  ASSERT_TRUE(compiled.out);
  const auto& image = compiled.out->image;
  rcx::Machine m;
  ASSERT_FALSE(m.load(0, image).has_value());
  for (auto [name, value] : {std::pair{"x", c.x}, std::pair{"y", c.y}, std::pair{"b", 7}}) {
    auto v = static_cast<std::uint16_t>(value);
    std::vector<std::uint8_t> set = {0x14, static_cast<std::uint8_t>(variable_index(image, name)), 2,
                                     static_cast<std::uint8_t>(v & 0xff), static_cast<std::uint8_t>(v >> 8)};
    m.execute_direct(set);
  }
  std::int64_t before = m.instructions_executed();
  m.start_program();
  m.run(1000 * rcx::kMicrosPerMs);
  std::string what = c.statement + " with x=" + std::to_string(c.x) + ", y=" + std::to_string(c.y);
  EXPECT_EQ(test::global_value(m, image, "b"), c.value) << what;
  EXPECT_LE(m.instructions_executed() - before, c.at_most) << what << " (nqc's code: " << c.nqc << ")";
}

const std::vector<Case> kCases = {
    // set 0; chk; jmp / set 1: three on either outcome in nqc's code.
    // rcxc's test branches to `set 1`: two when true.
    {"b = (x >= y);", 5, 3, 1, 5, 4},
    {"b = (x >= y);", 2, 3, 0, 5, 5},
    {"b = (x <= y);", 2, 3, 1, 5, 4},
    {"b = (x <= y);", 5, 3, 0, 5, 5},
    {"b = !(x < y);", 3, 3, 1, 5, 4},
    {"b = !(x < y);", 2, 3, 0, 5, 5},
    // set 0; chk (branches over set 1 when false); set 1.
    {"b = (x < y);", 2, 3, 1, 5, 5},
    {"b = (x < y);", 5, 3, 0, 4, 4},
    {"b = (x == y);", 3, 3, 1, 5, 5},
    {"b = (x == y);", 2, 3, 0, 4, 4},
    {"b = (x == y) + 1;", 3, 3, 2, 6, 6},
    {"b = (x == y) + 1;", 2, 3, 1, 5, 5},
    // b (7 before) read by its own test: chk (to set 1); set 0; jmp / set 1.
    {"b = (b >= y);", 0, -3, 1, 4, 4},
    {"b = (b >= y);", 0, 30, 0, 5, 5},
    {"b = (b == y);", 0, 7, 1, 4, 4},
    {"b = (b == y);", 0, 6, 0, 5, 5},
    // chk (to set 0 when b >= y); jmp; set 1 / set 0; jmp: three either way.
    {"b = (b < y);", 0, 30, 1, 5, 5},
    {"b = (b < y);", 0, -3, 0, 5, 5},
    // chk b < 3; chk y < 4 (both to set 1); set 0; jmp / set 1.
    {"b = (b < 3 || y < 4);", 0, 9, 0, 6, 6},
    {"b = (b < 3 || y < 4);", 0, 2, 1, 5, 5},
    // The sign bit, x >> 15: nqc's `set; chk (to div when x >= 0); and; div;
    // or; jmp / div`. rcxc's `set; chk (to set 0); set 1; jmp / set 0`.
    {"b = (x >> 15);", 5, 0, 0, 5, 5},
    {"b = (x >> 15);", -5, 0, 1, 8, 6},
};

TEST(ComparisonValue, NoOutcomeRunsMoreThanNqcsCode) {
  for (auto level : {ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os})
    for (const auto& c : kCases) check(c, level);
}

// -O0 may lay the code out simply, but computes the same values.
TEST(ComparisonValue, MinusO0ComputesTheSameValues) {
  for (auto c : kCases) {
    c.at_most = 1000;
    check(c, ir::OptLevel::O0);
  }
}

}  // namespace
}  // namespace rcxc
