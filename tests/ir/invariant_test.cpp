// Polls that compute their threshold once (ir/invariant.cpp).
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

const Operand kSensor = Operand::src(static_cast<int>(rcx::Source::SensorValue), 1);

// Block 0 runs `setup` and enters block 1, the poll: `code`, then
// `until (SENSOR_2 <= t)` back to itself; block 2 is after the poll.
// Variables: 0 a local `last`, 1 a temporary `t`, 2 a global `g`.
struct Poll {
  Builder b;
  FuncId f = 0;
};

Poll poll(std::vector<Instr> code, Terminator into = Jump{1}, bool second_task = false) {
  Poll p;
  p.b.local("last");
  p.b.temp();
  p.b.global("g");
  p.f = p.b.function("main");
  p.b.block(p.f, {set(0, kSensor)}, into);
  p.b.block(p.f, std::move(code), Branch{Cmp::LE, kSensor, V(1), 2, 1});
  p.b.block(p.f, {sound(1)});
  if (second_task) {
    FuncId other = p.b.function("other");
    p.b.block(other, {add(2, I(1))});
  }
  return p;
}

std::size_t moved(Poll& p) {
  Log log;
  compute_poll_thresholds_once(p.b.p, log);
  return log.size();
}

}  // namespace

TEST(PollThreshold, AThresholdFromALocalIsComputedOnceBeforeThePoll) {
  // until (SENSOR_2 <= last + 3): t = last; t += 3 on every pass before.
  Poll p = poll({set(1, V(0)), add(1, I(3))});
  ASSERT_EQ(moved(p), 1u);
  const Function& f = p.b.fn(p.f);
  EXPECT_TRUE(f.blocks[1].instrs.empty());
  ASSERT_EQ(f.blocks[0].instrs.size(), 3u);  // set last, then the two
  EXPECT_TRUE(same_instr(f.blocks[0].instrs[1], set(1, V(0))));
  EXPECT_TRUE(same_instr(f.blocks[0].instrs[2], add(1, I(3))));
}

TEST(PollThreshold, ATestEnteringThePollGetsABlockBeforeIt) {
  // if (g > 0) until (...): the new block lies between the test and the
  // poll and falls into it.
  Poll p = poll({set(1, V(0)), add(1, I(3))}, Branch{Cmp::GT, V(2), I(0), 1, 2});
  ASSERT_EQ(moved(p), 1u);
  const Function& f = p.b.fn(p.f);
  ASSERT_EQ(f.blocks.size(), 4u);
  EXPECT_EQ(f.blocks[1].instrs.size(), 2u);
  EXPECT_EQ(std::get<Jump>(f.blocks[1].term).target, 2);
  const auto& test = std::get<Branch>(f.blocks[0].term);
  EXPECT_EQ(test.then, 1);
  EXPECT_EQ(test.otherwise, 3);  // past the poll, renumbered
  const auto& again = std::get<Branch>(f.blocks[2].term);
  EXPECT_EQ(again.otherwise, 2);  // the poll still branches to itself
  EXPECT_TRUE(f.blocks[2].instrs.empty());
}

TEST(PollThreshold, WhatChangesBetweenPassesStays) {
  // A sensor read each pass, a variable the poll itself changes, and an
  // arithmetic step with no set before it (it would add 3 on every pass).
  Poll sensor = poll({set(1, kSensor), add(1, I(3))});
  EXPECT_EQ(moved(sensor), 0u);
  Poll changed = poll({set(1, V(0)), add(1, I(3)), add(0, I(1))});
  EXPECT_EQ(moved(changed), 0u);
  Poll stepping = poll({add(1, I(3))});
  EXPECT_EQ(moved(stepping), 0u);
}

TEST(PollThreshold, AGlobalCountsAsUnchangedOnlyWithoutOtherTasks) {
  Poll alone = poll({set(1, V(2)), add(1, I(3))});
  EXPECT_EQ(moved(alone), 1u);
  Poll shared = poll({set(1, V(2)), add(1, I(3))}, Jump{1}, true);
  EXPECT_EQ(moved(shared), 0u);
}

TEST(PollThreshold, AReadBeforeTheSetThatFollowsKeepsThePrefixShort) {
  // last = t; t = 5: the first pass copies the old t, the next ones 5.
  Poll p = poll({set(0, V(1)), set(1, I(5))});
  EXPECT_EQ(moved(p), 0u);
}
