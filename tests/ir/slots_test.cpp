// Slot allocation's report when the 32 slots run out: where it points.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

SourceSpan line(std::uint32_t n) { return {{0, n, 3, 0}, {0, n, 20, 0}}; }

// A temporary has no declaration: the error names the first code that uses
// it. Here that is a test (a branch), whose block has the statement's span,
// while the instruction that sets it has none.
TEST(SlotReport, ATemporaryFirstReadByATestPointsAtTheTest) {
  Builder b;
  VarId t = b.temp();
  FuncId f = b.function("main");
  BlockId head = b.block(f, {set(t, Operand::src(1, 0))});
  BlockId yes = b.block(f, {sound(1)});
  BlockId no = b.block(f, {});
  b.at(f, head).term = Branch{Cmp::LT, V(t), I(10), yes, no};
  b.at(f, head).span = b.p.add_span(line(7));
  b.at(f, yes).span = b.p.add_span(line(8));
  b.p.reserved_slots = 0xFFFFFFFFu;  // every slot taken: t gets none
  Diagnostics d;
  allocate_slots(b.p, d);
  ASSERT_TRUE(d.has_errors());
  const Diagnostic& e = d.all().front();
  EXPECT_NE(e.message.find("no variable slot left for a compiler temporary"), std::string::npos) << e.message;
  EXPECT_EQ(e.span.begin.line, 7u);
}

// An instruction that uses it comes first where it does.
TEST(SlotReport, ATemporaryFirstUsedByAnInstructionPointsThere) {
  Builder b;
  VarId t = b.temp();
  FuncId f = b.function("main");
  BlockId head = b.block(f, {set(t, Operand::src(1, 0)), wait(V(t))});
  BlockId yes = b.block(f, {sound(1)});
  b.at(f, head).instrs[1].span = b.p.add_span(line(5));
  b.at(f, head).term = Branch{Cmp::LT, V(t), I(10), yes, yes};
  b.at(f, head).span = b.p.add_span(line(7));
  b.p.reserved_slots = 0xFFFFFFFFu;
  Diagnostics d;
  allocate_slots(b.p, d);
  ASSERT_TRUE(d.has_errors());
  EXPECT_EQ(d.all().front().span.begin.line, 5u);
}

}  // namespace
