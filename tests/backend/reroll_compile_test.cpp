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

Compiled compile(const std::string& text) {
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  Compiled c;
  c.out = backend::compile_source("ramp.nqc", text, {}, ir::OptLevel::Os, sm, diags, log);
  c.errors = diags.has_errors();
  c.rerolled = std::any_of(log.begin(), log.end(), [](const std::string& l) { return l.find("rerolled") != l.npos; });
  return c;
}

}  // namespace

TEST(RerollCompile, AFreeSlotTakesTheLoop) {
  Compiled c = compile(ramp_after_globals(31));
  ASSERT_TRUE(c.out.has_value());
  EXPECT_FALSE(c.errors);
  EXPECT_TRUE(c.rerolled);
  EXPECT_EQ(c.out->slots_used, 32);
}

TEST(RerollCompile, NoFreeSlotKeepsTheStraightCode) {
  Compiled c = compile(ramp_after_globals(32));
  ASSERT_TRUE(c.out.has_value());
  EXPECT_FALSE(c.errors);
  EXPECT_FALSE(c.rerolled);
  EXPECT_EQ(c.out->slots_used, 32);
}

// Seven copies of {SetPower(OUT_A, n); Wait(10)} are 56 bytes; the loop is
// 17 + 8. The rest of main (pwr, dir, on) is the same in both.
TEST(RerollCompile, TheLoopIsTheSmallerCode) {
  Compiled c = compile(ramp_after_globals(0));
  ASSERT_TRUE(c.out.has_value());
  EXPECT_TRUE(c.rerolled);
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  auto straight = backend::compile_source("ramp.nqc", ramp_after_globals(0), {}, ir::OptLevel::O1, sm, diags, log);
  ASSERT_TRUE(straight.has_value());
  EXPECT_EQ(straight->code_bytes - c.out->code_bytes, 56 - 25);
}

// 7000 written-out additions are 35000 bytes, over the 32767 a task may
// have: the loop makes the program fit, and the straight code's error is
// not reported.
TEST(RerollCompile, ALoopRescuesATaskTooLongWrittenOut) {
  std::string text = "int x;\ntask main() {\n";
  for (int i = 0; i < 7000; ++i) text += "  x += " + std::to_string(i) + ";\n";
  Compiled c = compile(text + "}\n");
  ASSERT_TRUE(c.out.has_value());
  EXPECT_FALSE(c.errors);
  EXPECT_TRUE(c.rerolled);
  EXPECT_LT(c.out->code_bytes, 100);
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  EXPECT_FALSE(backend::compile_source("long.nqc", text + "}\n", {}, ir::OptLevel::O1, sm, diags, log).has_value());
  EXPECT_TRUE(diags.has_errors());
}
