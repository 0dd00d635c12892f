// Merging `repeat (a) repeat (b) S` into one counter loop (ir/nested_repeat.cpp),
// judged by what the compiler makes of source text: the decision in the log
// and the code size against the same body written as one repeat. What the
// merged loops compute is checked by the semantic tests (statements/repeat_*).
#include <gtest/gtest.h>

#include <algorithm>

#include "backend/compile.h"

using namespace rcxc;

namespace {

struct Compiled {
  int bytes = -1;
  int merges = 0;
};

Compiled compile(const std::string& body, ir::OptLevel level = ir::OptLevel::Os) {
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  auto out = backend::compile_source("nested.nqc", "int n, m, k;\ntask main() {\n" + body + "\n}\n", {}, level, sm,
                                     diags, log);
  Compiled c;
  if (out && !diags.has_errors()) c.bytes = out->code_bytes;
  c.merges = static_cast<int>(std::count_if(log.begin(), log.end(), [](const std::string& l) {
    return l.find("in one loop") != l.npos;
  }));
  return c;
}

// Compiles (the case is not refused) without merging.
::testing::AssertionResult kept_apart(const std::string& body) {
  Compiled c = compile(body);
  if (c.bytes <= 0) return ::testing::AssertionFailure() << "does not compile";
  if (c.merges != 0) return ::testing::AssertionFailure() << c.merges << " merges";
  return ::testing::AssertionSuccess();
}

}  // namespace

// One loopset (3 bytes), loop test (2) and back jump (2) less.
TEST(NestedRepeat, TwoConstantLoopsBecomeOne) {
  Compiled nested = compile("repeat (10) repeat (4) { PlaySound(1); n++; }");
  Compiled single = compile("repeat (40) { PlaySound(1); n++; }");
  ASSERT_GT(single.bytes, 0);
  EXPECT_EQ(nested.merges, 1);
  EXPECT_EQ(nested.bytes, single.bytes);
  Compiled kept = compile("repeat (10) repeat (4) { PlaySound(1); n++; }", ir::OptLevel::O0);
  EXPECT_EQ(kept.merges, 0);
  EXPECT_EQ(kept.bytes - compile("repeat (40) { PlaySound(1); n++; }", ir::OptLevel::O0).bytes, 7);
}

TEST(NestedRepeat, ThreeDeepBecomeOne) {
  Compiled nested = compile("repeat (2) { repeat (3) { repeat (4) n++; } }");
  EXPECT_EQ(nested.merges, 2);
  EXPECT_EQ(nested.bytes, compile("repeat (24) n++;").bytes);
}

// `continue` goes to the next run of the body in both forms.
TEST(NestedRepeat, ContinueStillMerges) {
  EXPECT_EQ(compile("repeat (3) repeat (4) { n++; if (n == 2) continue; m++; }").merges, 1);
}

TEST(NestedRepeat, LoopsThatDoMoreOrOtherwiseAreKept) {
  // break leaves only the inner loop.
  EXPECT_TRUE(kept_apart("repeat (3) repeat (4) { n++; if (n == 2) break; }"));
  // The outer body does something besides the inner loop.
  EXPECT_TRUE(kept_apart("repeat (3) { m++; repeat (4) n++; }"));
  EXPECT_TRUE(kept_apart("repeat (3) { repeat (4) n++; m++; }"));
  // A count known only at run time.
  EXPECT_TRUE(kept_apart("repeat (k) repeat (4) n++;"));
  EXPECT_TRUE(kept_apart("repeat (3) repeat (k) n++;"));
  // 400 does not fit the loopset's byte argument.
  EXPECT_TRUE(kept_apart("repeat (20) repeat (20) n++;"));
  // A loop that runs no time.
  EXPECT_TRUE(kept_apart("repeat (0) repeat (4) n++;"));
  // goto into the inner loop from outside both.
  EXPECT_TRUE(kept_apart("if (k) goto in; repeat (3) repeat (4) { in: n++; }"));
}
