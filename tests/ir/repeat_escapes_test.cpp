// Which `repeat` loops a goto leaves or enters (ir/lower.cpp): those keep a
// variable counter, since the firmware's counter would stay pushed or be
// popped unpushed; every other repeat keeps the firmware's loop counter, as
// nqc's code does, whatever gotos the function has elsewhere.
#include <gtest/gtest.h>

#include "frontend/frontend.h"
#include "ir/lower.h"

using namespace rcxc;
using namespace rcxc::ir;

namespace {

// Function::repeats of main, in source order: whether each escapes.
std::vector<bool> escapes(const std::string& body) {
  SourceManager sm;
  Diagnostics diags;
  auto ast = frontend::parse_source("goto.nqc", "int n, m;\ntask main() {\n" + body + "\n}\n", {}, sm, diags);
  EXPECT_TRUE(ast && !diags.has_errors());
  if (!ast) return {};
  auto p = lower(*ast, diags);
  EXPECT_TRUE(p);
  if (!p) return {};
  std::vector<bool> out;
  for (const auto& r : p->functions[static_cast<std::size_t>(p->find_function("main"))].repeats)
    out.push_back(r.escapes);
  return out;
}

}  // namespace

TEST(RepeatEscapes, AGotoBesideTheLoopLeavesItACounterLoop) {
  EXPECT_EQ(escapes("if (n > 3) goto skip;\nn = 1;\nskip: repeat (4) n++;"), std::vector<bool>{false});
  EXPECT_EQ(escapes("repeat (4) n++;\nif (n > 3) goto done;\nm = 1;\ndone: ;"), std::vector<bool>{false});
}

TEST(RepeatEscapes, AGotoWithinTheBodyLeavesItACounterLoop) {
  EXPECT_EQ(escapes("repeat (3) { if (n) goto next; n++; next: m++; }"), std::vector<bool>{false});
}

TEST(RepeatEscapes, AGotoOutOfALoopMakesItAndOnlyItEscape) {
  // Out of the inner loop to a label in the outer one: the outer stays.
  EXPECT_EQ(escapes("repeat (2) { repeat (5) { n++; if (n == 3) goto next; } next: m++; }"),
            (std::vector<bool>{false, true}));
  // Out of both.
  EXPECT_EQ(escapes("repeat (2) { repeat (5) { if (n == 3) goto out; } }\nout: m = 1;"),
            (std::vector<bool>{true, true}));
}

TEST(RepeatEscapes, AGotoIntoALoopMakesItEscape) {
  EXPECT_EQ(escapes("if (n) goto in;\nrepeat (3) { m++; in: n++; }"), std::vector<bool>{true});
}
