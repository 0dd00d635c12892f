// Large and deep inputs must be handled without a crash or stack overflow
// (their speed is measured in bench/frontend_bench.cpp, not here).
#include <gtest/gtest.h>

#include "tests/frontend/frontend_test_util.h"
#include "tests/frontend/generated_programs.h"

using namespace rcxc;
using rcxc::test::run_frontend;

TEST(Stress, ThousandNestedBlocksAndStatements) {
  auto r = run_frontend(test::deeply_nested_program(1000));
  EXPECT_TRUE(r.program.has_value()) << r.text().substr(0, 2000);
  EXPECT_EQ(r.diags.all().size(), 0u) << r.text().substr(0, 2000);
}

TEST(Stress, ThousandNestedParenthesesFoldToTheRightValue) {
  std::string e;
  for (int i = 0; i < 1000; ++i) e += "(1 + ";
  e += "0";
  for (int i = 0; i < 1000; ++i) e += ")";
  auto r = run_frontend("int g = " + e + ";\ntask main() { }\n", true);
  ASSERT_TRUE(r.program.has_value()) << r.text().substr(0, 2000);
  EXPECT_EQ(r.program->globals[0].init->constant, std::optional<std::int16_t>(1000));
}

TEST(Stress, ThousandNestedMacroCalls) {
  std::string e;
  for (int i = 0; i < 1000; ++i) e += "INC(";
  e += "0";
  for (int i = 0; i < 1000; ++i) e += ")";
  auto r = run_frontend("#define INC(x) ((x) + 1)\nint g = " + e + ";\ntask main() { }\n", true);
  ASSERT_TRUE(r.program.has_value()) << r.text().substr(0, 2000);
  EXPECT_EQ(r.program->globals[0].init->constant, std::optional<std::int16_t>(1000));
}

// Statements and an expression each well within the nesting limit, that
// together pass it: the parser stops neither (its stack grows by one
// symbol per `do`, the sum is 1600 tall), so the tree's walk must run.
std::string do_loops_around_sum(int loops, int terms) {
  std::string s = "int x; task main() { ";
  for (int i = 0; i < loops; ++i) s += "do ";
  s += "x = x";
  for (int i = 1; i < terms; ++i) s += "+x";
  s += ";";
  for (int i = 0; i < loops; ++i) s += " while (x);";
  return s + " }\n";
}

TEST(Stress, StatementsAndExpressionNestedPastTheLimitTogether) {
  auto r = run_frontend(do_loops_around_sum(1700, 1600), true);
  EXPECT_FALSE(r.program.has_value());
  EXPECT_NE(r.text().find("error: nested more than 3200 levels deep"), std::string::npos) << r.text().substr(0, 2000);
}

TEST(Stress, StatementsAndExpressionNestedJustWithinTheLimit) {
  auto r = run_frontend(do_loops_around_sum(1500, 1600), true);
  EXPECT_TRUE(r.program.has_value()) << r.text().substr(0, 2000);
}

TEST(Stress, FiftyThousandLineProgram) {
  std::string src = test::long_program(50000);
  ASSERT_GE(std::count(src.begin(), src.end(), '\n'), 50000);
  auto r = run_frontend(src);
  ASSERT_TRUE(r.program.has_value()) << r.text().substr(0, 2000);
  EXPECT_EQ(r.diags.all().size(), 0u);
}

TEST(Stress, ManyErrorsAreAllReported) {
  std::string src = "task main()\n{\n";
  for (int i = 0; i < 2000; ++i) src += "  break;\n";
  src += "}\n";
  auto r = run_frontend(src, true);
  EXPECT_FALSE(r.program.has_value());
  EXPECT_EQ(r.diags.error_count(), 2000u);
}
