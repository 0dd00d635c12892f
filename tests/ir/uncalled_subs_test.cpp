// A subroutine whose only calls are in code that never runs is dropped once
// the clean-up passes have removed that code (ir/calls.cpp): kept, it took
// bytes and, called by no task, slots no other code could share, so -O1
// ran out of slots on programs -O0 compiled.
#include <gtest/gtest.h>

#include <algorithm>

#include "frontend/frontend.h"
#include "ir/lower.h"
#include "ir/passes.h"

using namespace rcxc;
using namespace rcxc::ir;

namespace {

// Whether sub `name` still has code after optimising `text` at `level`,
// and what the passes logged.
std::pair<bool, Log> sub_kept(const std::string& text, const std::string& name, OptLevel level) {
  SourceManager sm;
  Diagnostics diags;
  auto ast = frontend::parse_source("subs.nqc", text, {}, sm, diags);
  EXPECT_TRUE(ast);
  if (!ast) return {};
  auto p = lower(*ast, diags);
  EXPECT_TRUE(p);
  if (!p) return {};
  Log log;
  EXPECT_TRUE(optimize(*p, level, diags, log, {}));
  FuncId s = p->find_function(name);
  EXPECT_GE(s, 0);
  return {s >= 0 && !p->functions[static_cast<std::size_t>(s)].blocks.empty(), log};
}

bool logged(const Log& log, const std::string& text) {
  return std::any_of(log.begin(), log.end(), [&](const std::string& l) { return l.find(text) != l.npos; });
}

}  // namespace

TEST(UncalledSubs, ASubCalledOnlyFromCodeThatNeverRunsIsDropped) {
  const std::string text = "int n;\nsub s() { n = 5; }\ntask main() { repeat (0) s(); n = 1; }\n";
  auto [kept, log] = sub_kept(text, "s", OptLevel::O1);
  EXPECT_FALSE(kept);
  EXPECT_TRUE(logged(log, "sub s is not called: dropped"));
  // -O0 removes no code, so the call, and the sub, stay.
  EXPECT_TRUE(sub_kept(text, "s", OptLevel::O0).first);
}

TEST(UncalledSubs, ASubCalledFromCodeThatRunsStays) {
  auto [kept, log] = sub_kept("int n;\nsub s() { n = 5; }\ntask main() { repeat (2) s(); s(); }\n", "s", OptLevel::O1);
  EXPECT_TRUE(kept);
  EXPECT_FALSE(logged(log, "dropped"));
}

// A sub that calls itself through an inline function (`void f() { s(); }`)
// was only "s -> s" at the sub, the inline function gone by the time calls
// are resolved: a note at each step's call now shows the way, here the
// call of f inside s (f's code carries its call's place).
TEST(UncalledSubs, RecursionThroughAnInlineFunctionNotesEachCall) {
  SourceManager sm;
  Diagnostics diags;
  auto ast = frontend::parse_source("rec.nqc", "int r;\nvoid f()\n{\n  s();\n}\nsub s()\n{\n  r++;\n  if (r < 3) f();\n}\n"
                                    "task main() { s(); }\n", {}, sm, diags);
  ASSERT_TRUE(ast);
  auto p = lower(*ast, diags);
  ASSERT_TRUE(p);
  Log log;
  EXPECT_FALSE(optimize(*p, OptLevel::O0, diags, log, {}));
  ASSERT_EQ(diags.error_count(), 1u);
  const auto& e = diags.all()[0];
  EXPECT_EQ(e.message, "recursive subroutine calls are not possible on the RCX: s -> s");
  ASSERT_EQ(e.notes.size(), 1u);
  EXPECT_EQ(e.notes[0].message, "'s' calls 's' here");
  EXPECT_EQ(e.notes[0].span.begin.line, 9u);  // `if (r < 3) f();`
}
