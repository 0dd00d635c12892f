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
