// Tail starts (ir/tailstart.cpp): which tasks main ends by starting run in
// main's place, and which must stay tasks of their own.
#include <gtest/gtest.h>

#include "ir/passes.h"
#include "tests/ir/ir_builder.h"

using namespace rcxc;
using namespace rcxc::ir;
using namespace rcxc::ir::test;

namespace {

Instr stop(FuncId f) { return op(rcx::Op::StopTask, {Operand::func(f)}); }

// main: sound 1, then `tail` and the end; worker: an endless loop of sound 2.
struct Tasks {
  Builder b;
  FuncId main = 0, worker = 0;
};

Tasks tasks_ending_with(std::vector<Instr> (*tail)(FuncId worker)) {
  Tasks t;
  t.main = t.b.function("main");
  t.worker = t.b.function("worker");
  std::vector<Instr> body{sound(1)};
  for (auto& in : tail(t.worker)) body.push_back(in);
  t.b.block(t.main, body);
  t.b.block(t.worker, {sound(2)}, Jump{0});
  return t;
}

std::vector<Instr> just_start(FuncId w) { return {start(w)}; }

Log run(Tasks& t) {
  Log log;
  run_tail_started_tasks_in_main(t.b.p, log);
  return log;
}

}  // namespace

TEST(TaskNamed, StartsAndStopsByNameOnly) {
  // Task numbers are chosen by the backend: a start by number (asm) names
  // no function, and neither does raw asm.
  EXPECT_EQ(task_named(start(3)), 3);
  EXPECT_EQ(task_named(stop(2)), 2);
  EXPECT_EQ(task_named(op(rcx::Op::StartTask, {I(3)})), -1);
  EXPECT_EQ(task_named(call(3)), -1);
  EXPECT_FALSE(starts_or_stops_unnamed_task(start(3)));
  EXPECT_FALSE(starts_or_stops_unnamed_task(call(3)));
  EXPECT_TRUE(starts_or_stops_unnamed_task(op(rcx::Op::StartTask, {I(3)})));
  EXPECT_TRUE(starts_or_stops_unnamed_task(op(rcx::Op::StopTask, {I(0)})));
  EXPECT_TRUE(starts_or_stops_unnamed_task(Instr{rcx::Op::SetVariable, {I(0x71), I(1)}, true, {}}));
}

TEST(TailStart, MainRunsTheTaskItEndsByStarting) {
  Tasks t = tasks_ending_with(just_start);
  Log log = run(t);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("task worker runs in main"), std::string::npos);
  EXPECT_TRUE(t.b.fn(t.worker).blocks.empty());
  const Function& m = t.b.fn(t.main);
  ASSERT_EQ(m.blocks.size(), 2u);
  // The start is gone; main goes on into the worker's loop.
  ASSERT_EQ(m.blocks[0].instrs.size(), 1u);
  EXPECT_EQ(m.blocks[0].instrs[0].op, rcx::Op::PlaySound);
  EXPECT_EQ(std::get<Jump>(m.blocks[0].term).target, 1);
  EXPECT_EQ(m.blocks[1].instrs[0].args[0], I(2));
  EXPECT_EQ(std::get<Jump>(m.blocks[1].term).target, 1);  // its loop, moved along
}

TEST(TailStart, AStartBeforeOtherWorkStays) {
  Tasks t = tasks_ending_with([](FuncId w) { return std::vector<Instr>{start(w), sound(3)}; });
  EXPECT_TRUE(run(t).empty());
  EXPECT_FALSE(t.b.fn(t.worker).blocks.empty());
}

TEST(TailStart, ATaskStoppedAnywhereStays) {
  // `stop worker` must stop the worker's code, not main.
  Tasks t = tasks_ending_with(just_start);
  FuncId other = t.b.function("other");
  t.b.block(other, {stop(t.worker)});
  EXPECT_TRUE(run(t).empty());
}

TEST(TailStart, ATaskStartedTwiceStays) {
  // A second start would restart the worker beside main.
  Tasks t = tasks_ending_with(just_start);
  FuncId other = t.b.function("other");
  t.b.block(other, {start(t.worker)});
  EXPECT_TRUE(run(t).empty());
}

TEST(TailStart, NothingMovesWhenMainIsStartedOrStopped) {
  for (auto op_on_main : {rcx::Op::StartTask, rcx::Op::StopTask}) {
    Tasks t = tasks_ending_with(just_start);
    FuncId other = t.b.function("other");
    t.b.block(other, {op(op_on_main, {Operand::func(t.main)})});
    EXPECT_TRUE(run(t).empty());
  }
}

TEST(TailStart, NothingMovesBesideRawAsmOrATaskNumber) {
  // Either could start or stop the worker by its number.
  Tasks raw = tasks_ending_with(just_start);
  FuncId other = raw.b.function("other");
  raw.b.block(other, {Instr{rcx::Op::SetVariable, {I(0x81), I(1)}, true, {}}});
  EXPECT_TRUE(run(raw).empty());

  Tasks numbered = tasks_ending_with(just_start);
  other = numbered.b.function("other");
  numbered.b.block(other, {op(rcx::Op::StopTask, {I(1)})});
  EXPECT_TRUE(run(numbered).empty());
}

TEST(TailStart, StartsTogetherAtTheEndKeepTheirOrder) {
  // main ends `start worker; start keeper;` and keeper is stopped elsewhere:
  // starting keeper first so that main could become the worker would put
  // keeper's first instruction ahead of the worker's. Nothing moves.
  Tasks t = tasks_ending_with(just_start);
  FuncId keeper = t.b.function("keeper");
  t.b.block(keeper, {sound(4)});
  FuncId other = t.b.function("other");
  t.b.block(other, {stop(keeper)});
  t.b.at(t.main, 0).instrs.push_back(start(keeper));
  EXPECT_TRUE(run(t).empty());
  const auto& instrs = t.b.fn(t.main).blocks[0].instrs;
  ASSERT_EQ(instrs.size(), 3u);
  EXPECT_EQ(instrs[1].args[0], Operand::func(t.worker));
  EXPECT_EQ(instrs[2].args[0], Operand::func(keeper));
}

// main ends `start early; start late;` (or the other way round when
// `late_last` is false); each task runs its own body in an endless loop.
// Returns whether main became the task started last.
bool last_runs_in_main(std::vector<Instr> early_body, std::vector<Instr> late_body, bool late_last = true) {
  Builder b;
  FuncId m = b.function("main");
  FuncId early = b.function("early"), late = b.function("late");
  b.p.add_var("shared", VarKind::Global);
  b.block(m, late_last ? std::vector<Instr>{start(early), start(late)}
                       : std::vector<Instr>{start(late), start(early)});
  b.block(early, std::move(early_body), Jump{0});
  b.block(late, std::move(late_body), Jump{0});
  Log log;
  run_tail_started_tasks_in_main(b.p, log);
  return b.fn(late_last ? late : early).blocks.empty();
}

TEST(TailStart, ATaskNumberedAfterAnotherThatMayShowTheOrderOfTurnsStays) {
  // Tasks take turns in task order and main's turn comes first: late in
  // main's place would take its turns ahead of early's. Both play sounds,
  // set output A, use one variable, or one clears a timer the other waits
  // on: which goes first would show, so late stays a task.
  EXPECT_FALSE(last_runs_in_main({sound(1)}, {sound(2)}));
  EXPECT_FALSE(last_runs_in_main({out(0x81)}, {out(0x41)}));
  EXPECT_FALSE(last_runs_in_main({set(0, I(1))}, {wait(V(0))}));
  EXPECT_FALSE(last_runs_in_main({op(rcx::Op::ClearTimer, {I(0)})}, {wait(Operand::src(1, 0))}));
  EXPECT_FALSE(last_runs_in_main({out(0x81)}, {wait(Operand::src(3, 0))}));  // reads A's state
  // Started the other way round, `start late; start early;`, early already
  // came first: it runs in main whatever the two share.
  EXPECT_TRUE(last_runs_in_main({sound(1)}, {sound(2)}, false));
}

TEST(TailStart, ATaskNumberedAfterAnotherThatSharesNothingWithItRunsInMain) {
  // early sends messages, late drives output C and reads sensor 1: the
  // order of their turns shows nowhere.
  EXPECT_TRUE(last_runs_in_main({op(rcx::Op::SendMessage, {I(1)}), wait(I(10))},
                                {out(0x84), wait(Operand::src(9, 0)), out(0x44)}));
}

TEST(TailStart, ATaskNumberedLowerButNeverStartedDoesNotCount) {
  // idle is never started, so it never takes a turn: worker runs in main.
  Builder b;
  FuncId m = b.function("main");
  FuncId idle = b.function("idle"), worker = b.function("worker");
  b.block(m, {start(worker)});
  b.block(idle, {sound(1)});
  b.block(worker, {sound(2)}, Jump{0});
  Log log;
  run_tail_started_tasks_in_main(b.p, log);
  EXPECT_EQ(log.size(), 1u);
  EXPECT_TRUE(b.fn(worker).blocks.empty());
  EXPECT_FALSE(b.fn(idle).blocks.empty());
}

TEST(TailStart, BothEndsOfAnIfAndAChain) {
  // if (..) start a; else start b;  with a ending `start c`: main runs all three.
  Builder b;
  FuncId m = b.function("main");
  FuncId a = b.function("a"), bb = b.function("b"), c = b.function("c");
  b.block(m, {}, Branch{Cmp::EQ, Operand::src(15, 0), I(1), 1, 2});
  b.block(m, {start(a)}, Jump{3});
  b.block(m, {start(bb)}, Jump{3});
  b.block(m, {});  // the join: empty, ends main
  b.block(a, {sound(1), start(c)});
  b.block(bb, {sound(2)});
  b.block(c, {sound(3)});
  Log log;
  run_tail_started_tasks_in_main(b.p, log);
  EXPECT_EQ(log.size(), 3u);
  for (FuncId f : {a, bb, c}) EXPECT_TRUE(b.fn(f).blocks.empty()) << b.fn(f).name;
  int sounds = 0;
  for (const auto& block : b.fn(m).blocks)
    for (const auto& in : block.instrs) {
      EXPECT_NE(in.op, rcx::Op::StartTask);
      sounds += in.op == rcx::Op::PlaySound;
    }
  EXPECT_EQ(sounds, 3);
}

TEST(TailStart, NotInsideACounterLoop) {
  // repeat (3) { if (..) { start worker; return; } }: main's counter would
  // still be pushed under the worker's own loops.
  Tasks t;
  t.main = t.b.function("main");
  t.worker = t.b.function("worker");
  t.b.block(t.main, {loopset(I(3))}, Jump{1});
  t.b.block(t.main, {}, LoopTest{0, 2, 4});
  t.b.block(t.main, {}, Branch{Cmp::EQ, Operand::src(15, 0), I(1), 3, 1});
  t.b.block(t.main, {start(t.worker)});
  t.b.block(t.main, {sound(1)});
  t.b.fn(t.main).repeats.push_back(Repeat{0, 1, true, true});
  t.b.block(t.worker, {sound(2)}, Jump{0});
  EXPECT_TRUE(run(t).empty());
}
