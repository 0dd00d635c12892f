// Rerolling is kept only when the final code is smaller and its temporary
// finds a slot (backend/compile.cpp).
#include <gtest/gtest.h>

#include <algorithm>

#include "backend/compile.h"

using namespace rcxc;

namespace {

// `globals` variables all in use, then a power ramp of 7 written-out steps.
std::string ramp_after_globals(int globals) {
  std::string text;
  for (int i = 0; i < globals; ++i) text += "int g" + std::to_string(i) + ";\n";
  text += "task main() {\n";
  for (int i = 0; i < globals; ++i) text += "  g" + std::to_string(i) + " = " + std::to_string(i) + ";\n";
  for (int p = 1; p <= 7; ++p) text += "  SetPower(OUT_A, " + std::to_string(p) + "); Wait(10);\n";
  return text + "}\n";
}

struct Compiled {
  std::optional<backend::Output> out;
  bool errors = false;
  bool rerolled = false;
};

Compiled compile(const std::string& text, ir::OptLevel level = ir::OptLevel::Os) {
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  Compiled c;
  c.out = backend::compile_source("ramp.nqc", text, {}, level, sm, diags, log);
  c.errors = diags.has_errors();
  c.rerolled = std::any_of(log.begin(), log.end(), [](const std::string& l) { return l.find("rerolled") != l.npos; });
  return c;
}

}  // namespace

// 31 globals leave one slot for the counter; 32 leave none, and the
// straight code compiles as before.
TEST(RerollCompile, TheLoopOnlyWhereASlotIsFree) {
  for (int globals : {31, 32}) {
    Compiled c = compile(ramp_after_globals(globals));
    ASSERT_TRUE(c.out.has_value()) << globals;
    EXPECT_FALSE(c.errors) << globals;
    EXPECT_EQ(c.rerolled, globals == 31);
    EXPECT_EQ(c.out->slots_used, 32);
  }
}

// Seven copies of {SetPower(OUT_A, n); Wait(10)} are 56 bytes; the loop is
// 17 + 8. The rest of main (pwr, dir, on) is the same in both.
TEST(RerollCompile, TheLoopIsTheSmallerCode) {
  Compiled c = compile(ramp_after_globals(0));
  Compiled straight = compile(ramp_after_globals(0), ir::OptLevel::O1);
  ASSERT_TRUE(c.out.has_value() && straight.out.has_value());
  EXPECT_TRUE(c.rerolled);
  EXPECT_EQ(straight.out->code_bytes - c.out->code_bytes, 56 - 25);
}

// 7000 written-out additions, each with a wait after it (neighbouring
// additions would gather into one), are 63000 bytes, over the 32767 a
// task may have: the loop makes the program fit, and the straight code's
// error is not reported.
TEST(RerollCompile, ALoopRescuesATaskTooLongWrittenOut) {
  std::string text = "int x;\ntask main() {\n";
  for (int i = 0; i < 7000; ++i) text += "  x += " + std::to_string(i) + "; Wait(1);\n";
  Compiled c = compile(text + "}\n");
  ASSERT_TRUE(c.out.has_value());
  EXPECT_FALSE(c.errors);
  EXPECT_TRUE(c.rerolled);
  EXPECT_LT(c.out->code_bytes, 100);
  Compiled straight = compile(text + "}\n", ir::OptLevel::O1);
  EXPECT_FALSE(straight.out.has_value());
  EXPECT_TRUE(straight.errors);
}
