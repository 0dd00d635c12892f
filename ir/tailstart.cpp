// Tasks that main ends by starting run in main's place (see passes.h).
#include <optional>
#include <fmt/format.h>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// How many start and stop instructions name each task. `by_number` is set
// when some instruction could start or stop a task without naming it.
struct TaskRefs {
  std::vector<int> starts, stops;
  bool by_number = false;
};

TaskRefs task_refs(const Program& p) {
  TaskRefs r{std::vector<int>(p.functions.size(), 0), std::vector<int>(p.functions.size(), 0)};
  for (const auto& fn : p.functions)
    for (const auto& b : fn.blocks)
      for (const auto& in : b.instrs) {
        r.by_number |= starts_or_stops_unnamed_task(in);
        FuncId t = task_named(in);
        if (t >= 0) ++(in.op == rcx::Op::StartTask ? r.starts : r.stops)[static_cast<std::size_t>(t)];
      }
  return r;
}

bool starts_named_task(const Instr& in) { return in.op == rcx::Op::StartTask && task_named(in) >= 0; }

// A task main may become: started by this one instruction only, never
// stopped (a stop would now stop main's code, and a second start would
// restart it beside main).
bool can_take_over(const Program& p, const TaskRefs& refs, FuncId main, const Instr& start) {
  auto t = static_cast<std::size_t>(start.args[0].value);
  const Function& task = p.functions[t];
  return static_cast<FuncId>(t) != main && task.kind == FuncKind::Task && !task.blocks.empty() &&
         refs.starts[t] == 1 && refs.stops[t] == 0;
}

// Whether the task main would become comes before every other task that
// may run beside it (started anywhere) in task order. Tasks take turns in
// that order, one instruction each; main's code takes the first turn. A
// task started by main's last instruction runs its first instruction
// later in the same round, after every task numbered below it; in main's
// place it runs in main's next turn, before them. Only when no such task
// runs is the order of everyone's instructions the same: with `start a;
// start b;` at main's end, a (numbered first) would otherwise move an
// instruction behind b, and two tasks setting one output at the same
// moment would leave it set the other way round.
bool first_in_task_order(const Program& p, const TaskRefs& refs, FuncId main, FuncId task) {
  for (std::size_t f = 0; f < p.functions.size(); ++f) {
    auto id = static_cast<FuncId>(f);
    const Function& other = p.functions[f];
    if (id == main || id == task || other.kind != FuncKind::Task || other.blocks.empty()) continue;
    if (refs.starts[f] > 0 && id < task) return false;
  }
  return true;
}

// Block `from` of main ends the task with a start; the task it names, if
// main can become it. Only the last start: starting the tasks of a run in
// another order would change which runs first.
std::optional<FuncId> tail_started_task(const Program& p, const TaskRefs& refs, FuncId main, const Block& from) {
  if (from.instrs.empty() || !starts_named_task(from.instrs.back())) return std::nullopt;
  const Instr& start = from.instrs.back();
  if (!can_take_over(p, refs, main, start) || !first_in_task_order(p, refs, main, start.args[0].value))
    return std::nullopt;
  return start.args[0].value;
}

// Whether leaving block b ends the task: it exits, or jumps through empty
// blocks to an exit.
bool ends_task(const Function& f, BlockId b) {
  for (std::size_t steps = 0; steps <= f.blocks.size(); ++steps) {
    const Terminator& t = f.blocks[static_cast<std::size_t>(b)].term;
    if (std::holds_alternative<Exit>(t)) return true;
    const auto* j = std::get_if<Jump>(&t);
    if (!j || !f.blocks[static_cast<std::size_t>(j->target)].instrs.empty()) return false;
    b = j->target;
  }
  return false;  // a loop of empty blocks never ends
}

// Moves `task`'s blocks into main, entered from block `from` in place of
// that block's last instruction (the start of `task`).
void take_over(Function& main, Function& task, BlockId from) {
  auto base = static_cast<BlockId>(main.blocks.size());
  for (auto& b : task.blocks) {
    offset_targets(b.term, base);
    main.blocks.push_back(std::move(b));
  }
  append_repeats(main, task.repeats, base);
  Block& b = main.blocks[static_cast<std::size_t>(from)];
  b.instrs.pop_back();
  b.term = Jump{base};
  task.blocks.clear();
  task.repeats.clear();
}

// One task main ends by starting, moved into main; false when none is left.
bool take_over_one(Program& p, FuncId main, Log& log) {
  TaskRefs refs = task_refs(p);
  auto m = static_cast<std::size_t>(main);
  if (refs.by_number || refs.starts[m] != 0 || refs.stops[m] != 0) return false;
  Function& fn = p.functions[m];
  CounterDepths depths = counter_depths(fn);
  if (!depths.consistent) return false;
  for (std::size_t b = 0; b < fn.blocks.size(); ++b) {
    Block& block = fn.blocks[b];
    // Inside a counter loop main's counters would still be pushed under
    // the task's own.
    if (!ends_task(fn, static_cast<BlockId>(b)) || depths.at_block[b] != 0) continue;
    auto t = tail_started_task(p, refs, main, block);
    if (!t) continue;
    Function& task = p.functions[static_cast<std::size_t>(*t)];
    log.push_back(fmt::format("task {} runs in main, which ends by starting it (nothing else starts or stops it)",
                              task.name));
    take_over(fn, task, static_cast<BlockId>(b));
    return true;
  }
  return false;
}

}  // namespace

void run_tail_started_tasks_in_main(Program& p, Log& log) {
  FuncId main = p.find_function("main");
  if (main < 0 || p.functions[static_cast<std::size_t>(main)].kind != FuncKind::Task) return;
  while (take_over_one(p, main, log)) {
  }
}

}  // namespace rcxc::ir
