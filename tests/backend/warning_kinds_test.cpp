// Each warning carries its kind from where it is said (preprocessor, checks,
// lowering, the IR passes) to the user: the name after the message, the
// JSON code, -Wno-NAME and -Werror=NAME. Programs written for each kind.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "backend/compile.h"
#include "frontend/warnings.h"

namespace rcxc {
namespace {

struct Sample {
  WarningKind kind;
  const char* program;
};

// One program per kind that gives that warning (and may give others). All
// but shared-subroutine: the inliner copies a subroutine several tasks run
// into each of them (ir/calls.cpp), so no program reaches that warning
// today; tests/ir/passes_test.cpp checks its kind on an IR program.
const Sample kSamples[] = {
    {WarningKind::UnusedVariable, "task main()\n{\n  int spare;\n}\n"},
    {WarningKind::UnusedValue, "int x;\ntask main()\n{\n  x == 1;\n}\n"},
    {WarningKind::UnreachableCode, "task main()\n{\n  while (true) {\n    break;\n    Wait(1);\n  }\n}\n"},
    {WarningKind::UnstartedTask, "task helper()\n{\n}\ntask main()\n{\n}\n"},
    {WarningKind::AssignInCondition, "int x;\ntask main()\n{\n  if (x = 2) Wait(1);\n}\n"},
    {WarningKind::DivisionByZero, "int x;\ntask main()\n{\n  x = x / 0;\n}\n"},
    {WarningKind::Overflow, "int x;\ntask main()\n{\n  x = 70000;\n}\n"},
    {WarningKind::Range, "task main()\n{\n  PlaySound(7);\n}\n"},
    {WarningKind::Source, "int g;\ntask main()\n{\n  g = __source(6, 0);\n}\n"},
    {WarningKind::Uninitialized, "int seen;\nsub s()\n{\n  int k;\n  seen = k;\n  k = 3;\n}\ntask main()\n{\n  s();\n}\n"},
    {WarningKind::UnconfiguredSensor, "task main()\n{\n  if (SENSOR_1 == 1) Off(OUT_A);\n}\n"},
    {WarningKind::MacroRedefined, "#define A 1\n#define A 2\ntask main()\n{\n}\n"},
    {WarningKind::MacroDefinition, "#define F(a, a) a\ntask main()\n{\n}\n"},
    {WarningKind::ExtraTokens, "#ifdef X\n#endif X\ntask main()\n{\n}\n"},
    {WarningKind::Pragma, "#pragma nothing_known\ntask main()\n{\n}\n"},
    {WarningKind::WarningDirective, "#warning look here\ntask main()\n{\n}\n"},
};

std::set<WarningKind> kinds_given(const std::string& program, const WarningPolicy& policy, bool* errors = nullptr) {
  SourceManager sm;
  Diagnostics diags;
  diags.policy = policy;
  ir::Log log;
  backend::compile_source("w.nqc", program, frontend::Options{}, ir::OptLevel::O2, sm, diags, log);
  std::set<WarningKind> kinds;
  for (const auto& d : diags.all())
    if (d.warning) kinds.insert(*d.warning);
  if (errors) *errors = diags.has_errors();
  return kinds;
}

TEST(WarningKinds, EveryKindHasASampleThatGivesIt) {
  std::set<WarningKind> sampled;
  for (const auto& s : kSamples) {
    sampled.insert(s.kind);
    EXPECT_TRUE(kinds_given(s.program, {}).contains(s.kind)) << warning_name(s.kind) << ":\n" << s.program;
  }
  sampled.insert(WarningKind::SharedSubroutine);
  EXPECT_EQ(sampled.size(), kWarningKinds.size());
}

TEST(WarningKinds, NoNameLeavesOutThatKindAlone) {
  for (const auto& s : kSamples) {
    WarningPolicy policy;
    ASSERT_FALSE(apply_warning_option(policy, "no-" + std::string(warning_name(s.kind))));
    auto with = kinds_given(s.program, {});
    auto without = kinds_given(s.program, policy);
    with.erase(s.kind);
    EXPECT_EQ(without, with) << warning_name(s.kind);
  }
}

TEST(WarningKinds, ErrorEqualsNameMakesThatKindAnError) {
  for (const auto& s : kSamples) {
    WarningPolicy policy;
    ASSERT_FALSE(apply_warning_option(policy, "error=" + std::string(warning_name(s.kind))));
    bool errors = false;
    auto kinds = kinds_given(s.program, policy, &errors);
    EXPECT_TRUE(errors) << warning_name(s.kind);
    EXPECT_TRUE(kinds.contains(s.kind)) << "the error keeps its kind: " << warning_name(s.kind);
  }
}

}  // namespace
}  // namespace rcxc
