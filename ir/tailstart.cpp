// Tasks that main ends by starting run in main's place (see passes.h).
#include <optional>
#include <fmt/format.h>

#include "ir/liveness.h"
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

// Kinds of state besides outputs and variables that a task's instructions
// change: two tasks changing the same kind show the order of their turns
// (which sound plays first), and so does one task changing what the other
// reads (a timer cleared before or after the other reads it).
enum Change : unsigned {
  kSound = 1u << 0,
  kDisplay = 1u << 1,
  kSend = 1u << 2,
  kMessageBuffer = 1u << 3,
  kTimers = 1u << 4,
  kSensorSetup = 1u << 5,
  kDatalog = 1u << 6,
  kTasks = 1u << 7,
  kRandom = 1u << 8,  // a draw: who draws first gets which number
  kAnything = 1u << 9,  // raw bytes or an instruction not sorted here
};

unsigned change_of(const Instr& in) {
  if (in.raw) return kAnything;
  if (computes_into_variable(in.op)) return 0;  // the variables count apart
  switch (in.op) {
    case rcx::Op::PlaySound:
    case rcx::Op::PlayTone: return kSound;
    case rcx::Op::SetDisplay: return kDisplay;
    case rcx::Op::SendMessage: return kSend;
    case rcx::Op::ClearMessage:
    case rcx::Op::SetMessage: return kMessageBuffer;
    case rcx::Op::ClearTimer:
    case rcx::Op::SetTime: return kTimers;
    case rcx::Op::SetSensorType:
    case rcx::Op::SetSensorMode:
    case rcx::Op::ClearSensorValue: return kSensorSetup;
    case rcx::Op::SetDatalogSize:
    case rcx::Op::DatalogNext: return kDatalog;
    case rcx::Op::StartTask:
    case rcx::Op::StopTask:
    case rcx::Op::StopAllTasks: return kTasks;
    case rcx::Op::SetMotorOnOff:
    case rcx::Op::SetMotorDirection:
    case rcx::Op::SetMotorPower:
    case rcx::Op::Wait:
    case rcx::Op::CallSubroutine:
    case rcx::Op::SetLoopCounter: return 0;
    default: return kAnything;
  }
}

// What one task's turns can show another task, or be shown by it: through
// its own instructions, the subroutines it calls and the tasks it starts.
struct Footprint {
  unsigned outputs = 0;      // bit per output it sets
  rcx::SourceSet reads = 0;  // the sources it reads, variables apart
  unsigned changes = 0;      // Change bits
  VarSet vars;               // the variables it reads or writes
};

void note_reads(Footprint& f, const Operand& o) {
  if (o.kind != Operand::Kind::Src) return;
  if (reads_random(o)) f.changes |= kRandom;
  else f.reads = static_cast<rcx::SourceSet>(f.reads | (1u << o.source));
}

// One function's own footprint, and the functions it enters (calls) or
// starts, whose footprints count as its own.
Footprint own_footprint(const Function& fn, std::vector<FuncId>& reached) {
  Footprint f;
  for (const auto& b : fn.blocks) {
    for (const auto& in : b.instrs) {
      f.changes |= change_of(in);
      bool motor = in.op == rcx::Op::SetMotorOnOff || in.op == rcx::Op::SetMotorDirection ||
                   in.op == rcx::Op::SetMotorPower;
      if (motor && !in.raw) f.outputs |= in.args[0].is_imm() ? static_cast<unsigned>(in.args[0].value) & 7u : 7u;
      for (const Operand& o : in.args) note_reads(f, o);
      VarUse use = uses_of(in);
      for (VarId v : use.reads) f.vars.add(v);
      for (VarId v : use.writes) f.vars.add(v);
      if (FuncId callee = callee_of(in); callee >= 0) reached.push_back(callee);
      if (in.op == rcx::Op::StartTask && task_named(in) >= 0) reached.push_back(task_named(in));
    }
    if (const auto* br = std::get_if<Branch>(&b.term)) {
      note_reads(f, br->a);
      note_reads(f, br->b);
    }
    if (std::holds_alternative<CoinToss>(b.term)) f.changes |= kRandom;
    for (VarId v : reads_of(b.term)) f.vars.add(v);
  }
  return f;
}

Footprint footprint(const Program& p, FuncId task) {
  Footprint f;
  std::vector<bool> seen(p.functions.size(), false);
  std::vector<FuncId> todo{task};
  while (!todo.empty()) {
    FuncId id = todo.back();
    todo.pop_back();
    if (seen[static_cast<std::size_t>(id)]) continue;
    seen[static_cast<std::size_t>(id)] = true;
    Footprint own = own_footprint(p.functions[static_cast<std::size_t>(id)], todo);
    f.outputs |= own.outputs;
    f.reads = static_cast<rcx::SourceSet>(f.reads | own.reads);
    f.changes |= own.changes;
    f.vars.merge(own.vars);
  }
  return f;
}

// The sources a kind of change alters for a task that reads them.
rcx::SourceSet sources_changed(const Footprint& f) {
  using S = rcx::Source;
  auto bit = [](S s) { return static_cast<rcx::SourceSet>(1u << static_cast<int>(s)); };
  rcx::SourceSet s = 0;
  if (f.outputs) s |= bit(S::MotorState);
  if (f.changes & kTimers) s |= bit(S::Timer) | bit(S::Clock);
  if (f.changes & kMessageBuffer) s |= bit(S::Message);
  if (f.changes & kSensorSetup)
    s |= bit(S::SensorValue) | bit(S::SensorType) | bit(S::SensorMode) | bit(S::SensorRaw) | bit(S::SensorBool);
  return s;
}

bool share_a_variable(const Footprint& a, const Footprint& b) {
  for (VarId v : a.vars.members())
    if (b.vars.has(v)) return true;
  return false;
}

// Whether the order two tasks take turns in could show: they set an
// output, touch a variable or change a kind of state in common, or one
// changes what the other reads.
bool turn_order_shows(const Footprint& a, const Footprint& b) {
  if ((a.changes | b.changes) & kAnything) return true;
  return (a.outputs & b.outputs) != 0 || (a.changes & b.changes) != 0 || (sources_changed(a) & b.reads) != 0 ||
         (sources_changed(b) & a.reads) != 0 || share_a_variable(a, b);
}

// Whether main can become `task` without changing the order of turns
// anyone could see. Tasks take turns in task order, one instruction each,
// and main's turn comes first. A task started by main's last instruction
// runs its first instruction later in the same round, after every task
// numbered below it; in main's place it runs in main's next turn, before
// them, and stays ahead of them from then on. With `start a; start b;` at
// main's end, a (numbered first) would move an instruction behind b: if
// both set one output, it would be left set the other way round. So every
// other task that may run beside it (started anywhere) must be numbered
// after it, or share nothing with it whose order could show.
bool keeps_turn_order(const Program& p, const TaskRefs& refs, FuncId main, FuncId task) {
  std::optional<Footprint> mine;
  for (std::size_t f = 0; f < p.functions.size(); ++f) {
    auto id = static_cast<FuncId>(f);
    const Function& other = p.functions[f];
    if (id == main || id == task || other.kind != FuncKind::Task || other.blocks.empty()) continue;
    if (refs.starts[f] == 0 || id > task) continue;
    if (!mine) mine = footprint(p, task);
    if (turn_order_shows(*mine, footprint(p, id))) return false;
  }
  return true;
}

// Block `from` of main ends the task with a start; the task it names, if
// main can become it. Only the last start: starting the tasks of a run in
// another order would change which runs first.
std::optional<FuncId> tail_started_task(const Program& p, const TaskRefs& refs, FuncId main, const Block& from) {
  if (from.instrs.empty() || !starts_named_task(from.instrs.back())) return std::nullopt;
  const Instr& start = from.instrs.back();
  if (!can_take_over(p, refs, main, start) || !keeps_turn_order(p, refs, main, start.args[0].value))
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

// Whether an exit of `f` is reached from its entry without passing through
// block `avoid` (-1: none).
bool reaches_exit(const Function& f, BlockId avoid) {
  std::vector<bool> seen(f.blocks.size(), false);
  std::vector<BlockId> todo{0};
  while (!todo.empty()) {
    BlockId b = todo.back();
    todo.pop_back();
    if (b == avoid || seen[static_cast<std::size_t>(b)]) continue;
    seen[static_cast<std::size_t>(b)] = true;
    const Terminator& t = f.blocks[static_cast<std::size_t>(b)].term;
    if (std::holds_alternative<Exit>(t)) return true;
    for (BlockId next : successors(t)) todo.push_back(next);
  }
  return false;
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
// Unless `may_add_an_exit`, only where main then has no more ways to end
// than before: two ends cost a jump to the end on one of the paths, which
// may be one that ran none (`if (c) start a; else { start b; start k; }`
// with a ending: the side that still starts b would jump over a's code).
bool take_over_one(Program& p, FuncId main, bool may_add_an_exit, Log& log) {
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
    if (!may_add_an_exit && reaches_exit(task, -1) && reaches_exit(fn, static_cast<BlockId>(b))) continue;
    log.push_back(fmt::format("task {} runs in main, which ends by starting it (nothing else starts or stops it)",
                              task.name));
    take_over(fn, task, static_cast<BlockId>(b));
    return true;
  }
  return false;
}

}  // namespace

void run_tail_started_tasks_in_main(Program& p, Log& log, bool may_add_an_exit) {
  FuncId main = p.find_function("main");
  if (main < 0 || p.functions[static_cast<std::size_t>(main)].kind != FuncKind::Task) return;
  while (take_over_one(p, main, may_add_an_exit, log)) {
  }
}

}  // namespace rcxc::ir
