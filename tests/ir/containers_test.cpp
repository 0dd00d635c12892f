// The small containers the passes use instead of heap vectors per block or
// instruction: Operands (an instruction's, inline up to three),
// InlineList (successors, a branch's reads, an opcode's operand slots),
// BlockVarSets (a set per block in one array) and VarSpan.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "ir/ir.h"
#include "ir/predecessors.h"
#include "ir/liveness.h"

namespace rcxc::ir {
namespace {

std::vector<Operand> as_vector(const Operands& o) { return {o.begin(), o.end()}; }

TEST(Operands, InlineUpToThreeThenOnTheHeapInOrder) {
  Operands o;
  EXPECT_TRUE(o.empty());
  std::vector<Operand> expected;
  for (int i = 0; i < 7; ++i) {
    o.push_back(Operand::imm(i));
    expected.push_back(Operand::imm(i));
    EXPECT_EQ(o.size(), expected.size());
    EXPECT_EQ(as_vector(o), expected) << "after " << i + 1;
  }
  EXPECT_EQ(o.at(6), Operand::imm(6));
  EXPECT_THROW((void)o.at(7), std::out_of_range);
}

TEST(Operands, CopiesAndMovesKeepTheOperandsEitherWay) {
  for (int n : {0, 2, 3, 4, 9}) {
    std::vector<Operand> list;
    for (int i = 0; i < n; ++i) list.push_back(Operand::var(i));
    Operands a = list;
    Operands copy = a;
    EXPECT_EQ(as_vector(copy), list);
    copy[0 % std::max(n, 1)] = n ? Operand::imm(99) : Operand{};
    if (n) {
      EXPECT_EQ(as_vector(a), list) << "a copy is its own";
    }
    Operands moved = std::move(copy);
    EXPECT_EQ(moved.size(), static_cast<std::size_t>(n));
    Operands assigned;
    assigned = a;
    EXPECT_EQ(assigned, a);
    EXPECT_EQ(assigned, Operands(list));
  }
}

// The spilled operands are one owned pointer: a move hands it over and
// leaves an empty list that can be filled again.
TEST(Operands, AMovedFromListIsEmptyAndTakesNewOperands) {
  for (int n : {2, 5}) {
    std::vector<Operand> list;
    for (int i = 0; i < n; ++i) list.push_back(Operand::src(9, i));
    Operands a = list;
    Operands b = std::move(a);
    EXPECT_TRUE(a.empty());  // NOLINT(bugprone-use-after-move): what a move leaves is the point
    a.push_back(Operand::imm(7));
    EXPECT_EQ(as_vector(a), std::vector<Operand>{Operand::imm(7)});
    Operands c;
    c = std::move(b);
    EXPECT_EQ(as_vector(c), list);
    EXPECT_TRUE(b.empty());  // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(c[static_cast<std::size_t>(n) - 1].source, 9);
  }
}

// Edges by hand: 0 branches to 1 both ways, 1 to 2 or 3, 2 jumps to 3,
// 3 loops back to 1 or exits through 4 (which is listed once more as its
// own loop's predecessor).
TEST(PredecessorLists, EveryBlocksEdgesInBlockOrderRepeatedOrNot) {
  Function f;
  for (int i = 0; i < 5; ++i) add_block(f);
  f.blocks[0].term = Branch{Cmp::EQ, Operand::imm(0), Operand::imm(0), 1, 1};
  f.blocks[1].term = Branch{Cmp::EQ, Operand::imm(0), Operand::imm(1), 2, 3};
  f.blocks[2].term = Jump{3};
  f.blocks[3].term = Branch{Cmp::EQ, Operand::imm(0), Operand::imm(1), 1, 4};
  f.blocks[4].term = Branch{Cmp::EQ, Operand::imm(0), Operand::imm(1), 4, 0};
  auto list = [](std::span<const BlockId> s) { return std::vector<BlockId>(s.begin(), s.end()); };
  const PredecessorLists repeated(f, true), once(f, false);
  EXPECT_EQ(list(repeated[0]), (std::vector<BlockId>{4}));
  EXPECT_EQ(list(repeated[1]), (std::vector<BlockId>{0, 0, 3}));
  EXPECT_EQ(list(repeated[2]), (std::vector<BlockId>{1}));
  EXPECT_EQ(list(repeated[3]), (std::vector<BlockId>{1, 2}));
  EXPECT_EQ(list(repeated[4]), (std::vector<BlockId>{3, 4}));
  EXPECT_EQ(list(once[1]), (std::vector<BlockId>{0, 3}));
  for (std::size_t b : {0u, 2u, 3u, 4u}) EXPECT_EQ(list(once[b]), list(repeated[b])) << b;
}

TEST(Operands, EqualityComparesSizeAndEachOperand) {
  EXPECT_EQ((Operands{Operand::var(1), Operand::imm(2)}), (Operands{Operand::var(1), Operand::imm(2)}));
  EXPECT_FALSE((Operands{Operand::var(1)}) == (Operands{Operand::var(1), Operand::imm(2)}));
  EXPECT_FALSE((Operands{Operand::var(1), Operand::imm(3)}) == (Operands{Operand::var(1), Operand::imm(2)}));
}

TEST(InlineList, HoldsUpToItsCapacityAndRefusesMore) {
  InlineList<int, 2> l;
  EXPECT_TRUE(l.empty());
  l.push_back(7);
  l.push_back(3);
  EXPECT_EQ(l.size(), 2u);
  EXPECT_EQ(std::vector<int>(l.begin(), l.end()), (std::vector<int>{7, 3}));
  EXPECT_THROW(l.push_back(1), std::length_error);
}

TEST(InlineList, SuccessorsOfEachTerminator) {
  auto list = [](const Terminator& t) {
    auto s = successors(t);
    return std::vector<BlockId>(s.begin(), s.end());
  };
  EXPECT_EQ(list(Jump{4}), (std::vector<BlockId>{4}));
  EXPECT_EQ(list(Branch{Cmp::EQ, Operand::imm(1), Operand::imm(2), 5, 6}), (std::vector<BlockId>{5, 6}));
  EXPECT_EQ(list(LoopTest{0, 2, 9}), (std::vector<BlockId>{2, 9}));
  EXPECT_EQ(list(CoinToss{3, 1}), (std::vector<BlockId>{3, 1}));
  EXPECT_TRUE(list(Exit{}).empty());
}

// operand_slots keeps its slots inline: every opcode of the table must fit.
TEST(InlineList, EveryOpcodesOperandSlotsFit) {
  for (const auto& row : rcx::opcodes()) {
    std::size_t slots = 0;
    for (const auto& o : row.operands)
      if (o.role != rcx::Role::Argument && o.role != rcx::Role::Offset && o.role != rcx::Role::Extension) ++slots;
    ASSERT_LE(slots, kMaxOperandSlots) << row.name;
    EXPECT_EQ(operand_slots(row.op).size(), slots) << row.name;
  }
}

TEST(BlockVarSets, EachBlockGetsItsEntriesInOrder) {
  // Listed in increasing variable order, blocks mixed, block 1 empty.
  std::vector<std::pair<std::uint32_t, VarId>> entries{{2, 1}, {0, 1}, {2, 4}, {3, 5}, {0, 8}, {2, 9}};
  BlockVarSets sets(4, entries);
  ASSERT_EQ(sets.size(), 4u);
  auto members = [&](std::size_t b) {
    auto m = sets[b].members();
    return std::vector<VarId>(m.begin(), m.end());
  };
  EXPECT_EQ(members(0), (std::vector<VarId>{1, 8}));
  EXPECT_TRUE(members(1).empty());
  EXPECT_EQ(members(2), (std::vector<VarId>{1, 4, 9}));
  EXPECT_EQ(members(3), (std::vector<VarId>{5}));
  EXPECT_TRUE(sets[2].has(4));
  EXPECT_FALSE(sets[2].has(5));
  EXPECT_FALSE(sets[1].has(1));
}

TEST(BlockVarSets, EmptyFunction) {
  BlockVarSets sets;
  EXPECT_EQ(sets.size(), 0u);
  BlockVarSets none(3, {});
  EXPECT_TRUE(none[0].members().empty());
  EXPECT_TRUE(none[2].members().empty());
}

TEST(VarSet, MergesASpanAndConvertsBothWays) {
  VarSet a;
  a.add(3);
  a.add(1);
  std::vector<VarId> more{1, 2, 5};
  EXPECT_TRUE(a.merge(VarSpan{more}));
  EXPECT_EQ(a.members(), (std::vector<VarId>{1, 2, 3, 5}));
  EXPECT_FALSE(a.merge(VarSpan{more}));  // nothing new
  VarSet copy = VarSpan(a);
  EXPECT_EQ(copy, a);
}

}  // namespace
}  // namespace rcxc::ir
