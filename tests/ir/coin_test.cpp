// Coin tosses on the loop counter (ir/coin.cpp): which tests of Random(1)
// become a toss, and which must stay a set and a test.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

const Operand kRandom1 = Operand::src(static_cast<int>(rcx::Source::Random), 1);

// if (c == 0) sound(1); else sound(2); sound(3); with c = Random(1) set at
// the end of block 0: 1 is the zero side, 2 the one side, 3 the join.
struct Toss {
  Builder b;
  FuncId f = 0;
  VarId c = 0;
};

Toss coin_if(VarId (*make)(Builder&), std::vector<Instr> before = {}, Cmp cmp = Cmp::EQ, int against = 0) {
  Toss t;
  t.c = make(t.b);
  t.f = t.b.function("main");
  before.push_back(set(t.c, kRandom1));
  t.b.block(t.f, before, Branch{cmp, V(t.c), I(against), 1, 2});
  t.b.block(t.f, {sound(1)}, Jump{3});
  t.b.block(t.f, {sound(2)}, Jump{3});
  t.b.block(t.f, {sound(3)});
  return t;
}

// The same test as the body of subroutine s.
void toss_in_sub(Builder& b, FuncId s, VarId c) {
  b.block(s, {set(c, kRandom1)}, Branch{Cmp::EQ, V(c), I(0), 1, 2});
  b.block(s, {sound(1)}, Jump{3});
  b.block(s, {sound(2)}, Jump{3});
  b.block(s, {sound(3)});
}

VarId a_temp(Builder& b) { return b.temp(); }
VarId a_local(Builder& b) { return b.local("c"); }
VarId a_global(Builder& b) { return b.global("c"); }

const CoinToss* tossed(Toss& t) {
  Log log;
  toss_coins_on_loop_counter(t.b.p, log);
  EXPECT_EQ(log.size(), std::get_if<CoinToss>(&t.b.at(t.f, 0).term) ? 1u : 0u);
  return std::get_if<CoinToss>(&t.b.at(t.f, 0).term);
}

}  // namespace

TEST(Coin, ATestOfRandomOneBecomesATossWithoutTheVariable) {
  Toss t = coin_if(a_temp);
  const CoinToss* c = tossed(t);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->zero, 1);
  EXPECT_EQ(c->one, 2);
  EXPECT_TRUE(t.b.at(t.f, 0).instrs.empty());  // the set went with the test
}

TEST(Coin, EachComparisonSendsEachFaceToItsSide) {
  // c != 0 and c > 0 go to `then` on a 1; c < 1 and c == 0 on a 0; c == 1 with the
  // constant first as well.
  struct Case {
    Cmp cmp;
    int against;
    BlockId zero, one;
  };
  for (Case k : {Case{Cmp::NE, 0, 2, 1}, Case{Cmp::GT, 0, 2, 1}, Case{Cmp::LT, 1, 1, 2}, Case{Cmp::EQ, 1, 2, 1},
                 Case{Cmp::GE, 1, 2, 1}, Case{Cmp::LE, 0, 1, 2}}) {
    Toss t = coin_if(a_local, {}, k.cmp, k.against);
    const CoinToss* c = tossed(t);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->zero, k.zero) << static_cast<int>(k.cmp) << " " << k.against;
    EXPECT_EQ(c->one, k.one) << static_cast<int>(k.cmp) << " " << k.against;
  }
  Toss swapped = coin_if(a_temp);
  std::get<Branch>(swapped.b.at(swapped.f, 0).term) = Branch{Cmp::GT, I(1), V(swapped.c), 1, 2};  // 1 > c: c is 0
  const CoinToss* c = tossed(swapped);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->zero, 1);
  EXPECT_EQ(c->one, 2);
}

TEST(Coin, AGlobalKeepsItsSet) {
  // Another task or a PC may read the global.
  Toss t = coin_if(a_global);
  EXPECT_EQ(tossed(t), nullptr);
}

TEST(Coin, AVariableReadAfterTheTestKeepsItsSet) {
  Toss t = coin_if(a_local);
  t.b.at(t.f, 3).instrs.push_back(wait(V(t.c)));
  EXPECT_EQ(tossed(t), nullptr);
}

TEST(Coin, OnlyRandomOfOne) {
  // Random(2) has three faces; the counter holds two apart.
  Toss t = coin_if(a_temp);
  t.b.at(t.f, 0).instrs.back().args[1] = Operand::src(static_cast<int>(rcx::Source::Random), 2);
  EXPECT_EQ(tossed(t), nullptr);
}

TEST(Coin, NotWhereTheCounterStackIsFull) {
  // Three counters pushed: the toss is the fourth, and fits.
  Toss three = coin_if(a_temp, {loopset(I(2)), loopset(I(2)), loopset(I(2))});
  EXPECT_NE(tossed(three), nullptr);
  // Four pushed: a fifth loopset would overwrite the innermost count.
  Toss four = coin_if(a_temp, {loopset(I(2)), loopset(I(2)), loopset(I(2)), loopset(I(2))});
  EXPECT_EQ(tossed(four), nullptr);
}

TEST(Coin, ASubroutineCountsItsDeepestCall) {
  // The toss in sub s; main calls s two counters deep, then three deep.
  Builder b;
  VarId c = b.temp();
  FuncId main = b.function("main");
  FuncId s = b.function("s", FuncKind::Sub);
  toss_in_sub(b, s, c);
  b.block(main, {loopset(I(2)), loopset(I(2)), call(s)});
  Log log;
  toss_coins_on_loop_counter(b.p, log);
  EXPECT_TRUE(std::holds_alternative<CoinToss>(b.at(s, 0).term));

  b.at(s, 0).term = Branch{Cmp::EQ, V(c), I(0), 1, 2};
  b.at(s, 0).instrs = {set(c, kRandom1)};
  b.at(main, 0).instrs = {loopset(I(2)), call(s), loopset(I(2)), loopset(I(2)), loopset(I(2)), call(s)};
  toss_coins_on_loop_counter(b.p, log);
  EXPECT_TRUE(std::holds_alternative<Branch>(b.at(s, 0).term));
}

TEST(Coin, NotWhenASideLiesBehind) {
  // A loop back to block 0 on a 1: the counter cannot branch backward.
  Toss t = coin_if(a_temp);
  std::get<Branch>(t.b.at(t.f, 0).term).otherwise = 0;
  EXPECT_EQ(tossed(t), nullptr);
}

TEST(Coin, NotInAFunctionWithRawAsm) {
  // Raw asm may push or pop counters the walk cannot see.
  Instr raw = sound(4);
  raw.raw = true;
  Toss t = coin_if(a_temp);
  t.b.at(t.f, 3).instrs.push_back(raw);
  EXPECT_EQ(tossed(t), nullptr);
  // ... nor in a subroutine a function with raw asm calls: the depth at
  // the call is unknown.
  Builder b;
  VarId c = b.temp();
  FuncId main = b.function("main");
  FuncId s = b.function("s", FuncKind::Sub);
  toss_in_sub(b, s, c);
  b.block(main, {raw, call(s)});
  Log log;
  toss_coins_on_loop_counter(b.p, log);
  EXPECT_TRUE(std::holds_alternative<Branch>(b.at(s, 0).term));
}

namespace {

// c = Random(1) with `between` after it, at the end of block 0.
Toss coin_if_after(std::vector<Instr> between) {
  Toss t;
  t.c = t.b.temp();
  t.f = t.b.function("main");
  std::vector<Instr> code{set(t.c, kRandom1)};
  code.insert(code.end(), between.begin(), between.end());
  t.b.block(t.f, code, Branch{Cmp::EQ, V(t.c), I(0), 1, 2});
  t.b.block(t.f, {sound(1)}, Jump{3});
  t.b.block(t.f, {sound(2)}, Jump{3});
  t.b.block(t.f, {sound(3)});
  return t;
}

}  // namespace

TEST(Coin, ACommandHoistedBetweenTheDrawAndTheTestStillTosses) {
  // `if (Random(1) == 0) { x *= 2; ... } else { x *= 2; ... }`: hoist.cpp
  // moves `x *= 2` between the draw and the test.
  Toss t = coin_if_after({mul(1, I(2)), sound(4)});  // var 0 is c, 1 x
  t.b.global("x");
  const CoinToss* c = tossed(t);
  ASSERT_NE(c, nullptr);
  const auto& left = t.b.at(t.f, 0).instrs;
  ASSERT_EQ(left.size(), 2u);  // the draw went; the two commands stay in order
  EXPECT_EQ(left[0].op, rcx::Op::MultiplyVariable);
  EXPECT_EQ(left[1].op, rcx::Op::PlaySound);
}

TEST(Coin, ADrawThatWouldChangePlacesWithAnotherStays) {
  // The toss draws at the test: a second draw between would then come first.
  Toss other = coin_if_after({set(1, Operand::src(static_cast<int>(rcx::Source::Random), 9))});
  other.b.global("y");
  EXPECT_EQ(tossed(other), nullptr);
  // An instruction that reads the drawn value needs the variable.
  Toss reads = coin_if_after({add(1, V(0))});
  reads.b.global("y");
  EXPECT_EQ(tossed(reads), nullptr);
}

TEST(Coin, AWaitOrATaskStartBetweenTheDrawAndTheTestStays) {
  // `c = Random(1); Wait(10); if (c == 0)`: tossed at the test, the draw
  // would come 100 ms later, after the draws other tasks make meanwhile
  // (a task started between may draw first too), and each would get
  // another number.
  Toss waits = coin_if_after({wait(I(10))});
  EXPECT_EQ(tossed(waits), nullptr);
  Toss starts = coin_if_after({start(1)});
  VarId y = starts.b.global("y");
  FuncId other = starts.b.function("other");
  starts.b.block(other, {set(y, Operand::src(static_cast<int>(rcx::Source::Random), 9))});
  EXPECT_EQ(tossed(starts), nullptr);
}

TEST(Coin, WithOtherTasksWhatTheyCanSeeBetweenTheDrawAndTheTestStays) {
  // `if (Random(1) == 0) { On(OUT_A); ... } else { On(OUT_A); ... }` with
  // On(OUT_A) hoisted between the draw and the test: a task waiting for A
  // to run, then drawing, would draw before the toss.
  auto with_other_task = [](Toss t) {
    FuncId other = t.b.function("other");
    t.b.block(other, {sound(7)});
    return t;
  };
  Toss motor = with_other_task(coin_if_after({out(0x81)}));
  EXPECT_EQ(tossed(motor), nullptr);
  Toss global = coin_if_after({add(1, I(1))});
  global.b.global("x");
  global = with_other_task(std::move(global));
  EXPECT_EQ(tossed(global), nullptr);
  // A sound and arithmetic into a local no task can see: still a toss.
  Toss unseen = coin_if_after({sound(4), add(1, I(1))});
  unseen.b.local("y");
  unseen = with_other_task(std::move(unseen));
  EXPECT_NE(tossed(unseen), nullptr);
}
