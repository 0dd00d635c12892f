// Removal of motor commands that change nothing (see passes.h).
//
// The firmware keeps each output's direction, on/off/float mode and power.
// `OnFwd(OUT_A)` right after the startup code sets direction forward again,
// macros like `forwards(s, t)` repeat `SetPower` with the power already set,
// and so on. What a task knows of an output survives between its
// instructions only where no other task can change it: the other tasks
// never command that output, or only ever set the same value (all tasks
// only switch A on: once on, A stays on). Before main starts a task, main
// knows everything. A command that sets what the output already has is
// removed.
#include <algorithm>
#include <array>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

constexpr int kOutputs = 3;
constexpr int kUnknown = -1;
constexpr int kNoWrite = -2;  // in Writes: the field is never set

struct OutputState {
  int dir = kUnknown;    // 0 reverse, 1 forward
  int mode = kUnknown;   // 0 float, 1 off, 2 on
  int power = kUnknown;  // 0..7
  friend bool operator==(const OutputState&, const OutputState&) = default;
};
struct State {
  bool reached = false;
  bool alone = false;  // no other task can be running
  std::array<OutputState, kOutputs> out{};
  friend bool operator==(const State&, const State&) = default;
};

int merge_field(int a, int b) { return a == b ? a : kUnknown; }

void merge_into(State& into, const State& from) {
  if (!from.reached) return;
  if (!into.reached) {
    into = from;
    return;
  }
  into.alone = into.alone && from.alone;
  for (int o = 0; o < kOutputs; ++o) {
    into.out[o].dir = merge_field(into.out[o].dir, from.out[o].dir);
    into.out[o].mode = merge_field(into.out[o].mode, from.out[o].mode);
    into.out[o].power = merge_field(into.out[o].power, from.out[o].power);
  }
}

// Outputs an instruction may change (raw bytes: any).
int touched(const Instr& in) {
  if (in.raw) return 7;
  if (is_motor_command(in)) return in.args.at(0).is_imm() ? (in.args[0].value & 7) : 7;
  return 0;
}

// What one motor instruction sets: field pointer member and value per
// output, or nothing known (kUnknown) when the value is not constant.
struct Effect {
  int OutputState::*field = nullptr;
  int value = kUnknown;
  bool flip = false;
};

Effect effect_of(const Instr& in) {
  int code = in.args.at(0).is_imm() ? in.args[0].value : 0;
  switch (in.op) {
    case rcx::Op::SetMotorDirection:
      if (code & 0x40) return {&OutputState::dir, kUnknown, true};
      return {&OutputState::dir, (code & 0x80) ? 1 : 0, false};
    case rcx::Op::SetMotorOnOff: return {&OutputState::mode, (code & 0x80) ? 2 : ((code & 0x40) ? 1 : 0), false};
    default: {
      const Operand& p = in.args.at(1);
      if (!p.is_imm()) return {&OutputState::power, kUnknown, false};
      // The firmware ignores powers outside 0..7: nothing changes then.
      if (p.value < 0 || p.value > 7) return {nullptr, kUnknown, false};
      return {&OutputState::power, p.value, false};
    }
  }
}

// What a task (or all other tasks) may set each output field to: kNoWrite,
// the one value it is ever set to, or kUnknown.
using Writes = std::array<OutputState, kOutputs>;

Writes nothing_written() {
  Writes w;
  for (auto& o : w) o = {kNoWrite, kNoWrite, kNoWrite};
  return w;
}

int combine_write(int a, int b) {
  if (a == kNoWrite) return b;
  if (b == kNoWrite) return a;
  return a == b ? a : kUnknown;
}

void combine_into(Writes& into, const Writes& from) {
  for (int o = 0; o < kOutputs; ++o) {
    into[o].dir = combine_write(into[o].dir, from[o].dir);
    into[o].mode = combine_write(into[o].mode, from[o].mode);
    into[o].power = combine_write(into[o].power, from[o].power);
  }
}

// What one instruction (not a call) may set.
void add_writes(const Instr& in, Writes& w) {
  int mask = touched(in);
  if (mask == 0) return;
  bool known = !in.raw && is_motor_command(in) && in.args[0].is_imm();
  Effect e = known ? effect_of(in) : Effect{};
  if (known && e.field == nullptr) return;
  for (int o = 0; o < kOutputs; ++o) {
    if (!((mask >> o) & 1)) continue;
    if (!known) {
      w[o] = {kUnknown, kUnknown, kUnknown};
      continue;
    }
    int& field = w[o].*e.field;
    field = combine_write(field, e.flip ? kUnknown : e.value);
  }
}

// What is known where a subroutine is entered (all its calls merged) and
// where it returns (all its returns merged).
struct Summary {
  State entry;
  State exit;
  friend bool operator==(const Summary&, const Summary&) = default;
};

bool starts_a_task(const Instr& in) { return in.raw || in.op == rcx::Op::StartTask; }

struct MotorPass {
  const Program& p;
  std::vector<int> touches;      // per function: outputs it (and its callees) command
  std::vector<bool> starts;      // per function: it (or a callee) starts a task
  std::vector<Writes> others;    // per function: what tasks not running it may set
  std::vector<bool> analysed;    // functions exactly one task runs
  std::vector<Summary> summary;  // per analysed subroutine
  std::vector<State> started;    // per task but main: merged over its start sites
  bool recording = false;        // whether apply() records call and return states
  FuncId current = -1;

  // Drops what other tasks may change before this task's next instruction:
  // a field they set to anything but the value known here. Nothing is
  // dropped while main is the only task running (before it starts any,
  // when no task restarts it).
  void forget_untracked(State& s) const {
    if (s.alone) return;
    const Writes& w = others[static_cast<std::size_t>(current)];
    // Field by field, written out: a loop over member pointers cost more
    // than the test, and this runs after every motor command.
    auto forget = [](int other, int& field) {
      if (other != kNoWrite && (other == kUnknown || field != other)) field = kUnknown;
    };
    for (std::size_t o = 0; o < kOutputs; ++o) {
      forget(w[o].dir, s.out[o].dir);
      forget(w[o].mode, s.out[o].mode);
      forget(w[o].power, s.out[o].power);
    }
  }

  void apply_call(FuncId g, State& s) {
    auto gi = static_cast<std::size_t>(g);
    if (!analysed[gi]) {
      for (int o = 0; o < kOutputs; ++o)
        if ((touches[gi] >> o) & 1) s.out[o] = {};
      s.alone = s.alone && !starts[gi];
      forget_untracked(s);
      return;
    }
    if (recording) merge_into(summary[gi].entry, s);
    const State& back = summary[gi].exit;
    if (!back.reached) {  // not known to return (yet): nothing after it is reached
      s.reached = false;
      return;
    }
    for (int o = 0; o < kOutputs; ++o)
      if ((touches[gi] >> o) & 1) s.out[o] = back.out[o];
    s.alone = s.alone && back.alone;
    forget_untracked(s);
  }

  // Applies `in` to `s`; returns whether it changed nothing at all.
  bool apply(const Instr& in, State& s) {
    if (!s.reached) return false;
    // Most instructions neither command an output, call, nor start a
    // task: they change nothing here (asked of every instruction of the
    // program several times).
    if (!in.raw && !is_motor_command(in) && in.op != rcx::Op::CallSubroutine && in.op != rcx::Op::StartTask) return false;
    if (FuncId g = callee_of(in); g >= 0) {
      apply_call(g, s);
      return false;
    }
    if (starts_a_task(in)) {
      if (FuncId t = task_named(in); recording && t >= 0) {
        State at = s;
        at.alone = false;
        merge_into(started[static_cast<std::size_t>(t)], at);
      }
      if (s.alone) {
        s.alone = false;
        forget_untracked(s);
      }
    }
    int mask = touched(in);
    if (mask == 0) return false;
    if (in.raw || !is_motor_command(in) || !in.args[0].is_imm()) {
      for (int o = 0; o < kOutputs; ++o)
        if ((mask >> o) & 1) s.out[o] = {};
      return false;
    }
    Effect e = effect_of(in);
    if (e.field == nullptr) return true;
    bool redundant = true;
    for (int o = 0; o < kOutputs; ++o) {
      if (!((mask >> o) & 1)) continue;
      int& field = s.out[o].*e.field;
      int next = e.flip ? (field == kUnknown ? kUnknown : 1 - field) : e.value;
      if (e.flip || next == kUnknown || field != next) redundant = false;
      field = next;
    }
    forget_untracked(s);
    return redundant;
  }

  State entry_of(FuncId f, bool main_alone) {
    const Function& fn = p.functions[static_cast<std::size_t>(f)];
    if (fn.kind == FuncKind::Sub) return summary[static_cast<std::size_t>(f)].entry;
    State s;
    s.reached = true;
    if (fn.name == "main") {
      s.alone = main_alone;
      return s;
    }
    // A task other than main begins with what its starters knew when they
    // started it, less what other tasks may have changed since. Until a
    // start is seen, nothing of it is reached.
    s = started[static_cast<std::size_t>(f)];
    current = f;
    forget_untracked(s);
    return s;
  }

  // The state at the start of every block of `f`.
  std::vector<State> block_states(FuncId f, const State& entry) {
    current = f;
    const Function& fn = p.functions[static_cast<std::size_t>(f)];
    std::vector<State> in(fn.blocks.size());
    in[0] = entry;
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t b = 0; b < fn.blocks.size(); ++b) {
        if (!in[b].reached) continue;
        State s = in[b];
        for (const auto& instr : fn.blocks[b].instrs) apply(instr, s);
        if (recording && std::holds_alternative<Exit>(fn.blocks[b].term) && fn.kind == FuncKind::Sub)
          merge_into(summary[static_cast<std::size_t>(f)].exit, s);
        for (BlockId succ : successors(fn.blocks[b].term)) {
          State before = in[static_cast<std::size_t>(succ)];
          merge_into(in[static_cast<std::size_t>(succ)], s);
          changed |= !(before == in[static_cast<std::size_t>(succ)]);
        }
      }
    }
    return in;
  }

  void remove_redundant(Function& fn, FuncId f, const std::vector<State>& in) {
    current = f;
    // In place, each kept instruction moved down over the removed ones (a
    // new list per block was an allocation per block).
    for (std::size_t b = 0; b < fn.blocks.size(); ++b) {
      State s = in[b];
      std::vector<Instr>& code = fn.blocks[b].instrs;
      std::size_t kept = 0;
      for (std::size_t i = 0; i < code.size(); ++i) {
        if (apply(code[i], s)) continue;
        if (kept != i) code[kept] = std::move(code[i]);  // never onto itself: that empties it
        ++kept;
      }
      code.erase(code.begin() + static_cast<std::ptrdiff_t>(kept), code.end());
    }
  }
};

// What each function's own instructions may set (not its callees').
std::vector<Writes> own_writes(const Program& p, const std::vector<bool>& started) {
  std::vector<Writes> w(p.functions.size(), nothing_written());
  for (std::size_t f = 0; f < p.functions.size(); ++f)
    each_instr_beside_other_tasks(p.functions[f], started[f], [&](const Instr& in) { add_writes(in, w[f]); });
  return w;
}

std::vector<int> function_touches(const Program& p, const std::vector<bool>& started) {
  std::vector<int> t(p.functions.size(), 0);
  for (std::size_t f = 0; f < p.functions.size(); ++f)
    each_instr_beside_other_tasks(p.functions[f], started[f], [&](const Instr& in) { t[f] |= touched(in); });
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t f = 0; f < p.functions.size(); ++f)
      for (const auto& b : p.functions[f].blocks)
        for (const auto& in : b.instrs)
          if (FuncId g = callee_of(in); g >= 0) {
            int next = t[f] | t[static_cast<std::size_t>(g)];
            changed |= next != t[f];
            t[f] = next;
          }
  }
  return t;
}


std::vector<bool> function_starts(const Program& p) {
  std::vector<bool> starts(p.functions.size(), false);
  for (std::size_t f = 0; f < p.functions.size(); ++f)
    for (const auto& b : p.functions[f].blocks)
      for (const auto& in : b.instrs) starts[f] = starts[f] || starts_a_task(in);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t f = 0; f < p.functions.size(); ++f)
      for (const auto& b : p.functions[f].blocks)
        for (const auto& in : b.instrs)
          if (FuncId g = callee_of(in); g >= 0 && starts[static_cast<std::size_t>(g)] && !starts[f])
            changed = starts[f] = true;
  }
  return starts;
}

}  // namespace

void remove_redundant_motor_commands(Program& p) {
  std::size_t n = p.functions.size();
  const std::vector<bool> started = started_functions(p);
  MotorPass pass{p,
                 function_touches(p, started),
                 function_starts(p),
                 std::vector<Writes>(n, nothing_written()),
                 std::vector<bool>(n, false),
                 std::vector<Summary>(n),
                 std::vector<State>(n)};
  // Which tasks run each function.
  std::vector<std::vector<FuncId>> runners(n);
  for (std::size_t t = 0; t < n; ++t) {
    if (p.functions[t].kind != FuncKind::Task || p.functions[t].blocks.empty()) continue;
    std::vector<FuncId> work{static_cast<FuncId>(t)};
    while (!work.empty()) {
      FuncId f = work.back();
      work.pop_back();
      auto& r = runners[static_cast<std::size_t>(f)];
      if (std::find(r.begin(), r.end(), static_cast<FuncId>(t)) != r.end()) continue;
      r.push_back(static_cast<FuncId>(t));
      for (const auto& b : p.functions[static_cast<std::size_t>(f)].blocks)
        for (const auto& in : b.instrs)
          if (FuncId g = callee_of(in); g >= 0) work.push_back(g);
    }
  }
  // What each task may set, with the subroutines it runs.
  auto own = own_writes(p, started);
  std::vector<Writes> by_task(n, nothing_written());
  for (std::size_t f = 0; f < n; ++f)
    for (FuncId t : runners[f]) combine_into(by_task[static_cast<std::size_t>(t)], own[f]);
  for (std::size_t f = 0; f < n; ++f) {
    if (p.functions[f].blocks.empty() || runners[f].size() != 1) continue;
    pass.analysed[f] = true;
    for (std::size_t t = 0; t < n; ++t)
      if (static_cast<FuncId>(t) != runners[f][0]) combine_into(pass.others[f], by_task[t]);
  }
  // A task begins knowing nothing when a start site is not followed (raw
  // code, a subroutine several tasks run) or when nothing in the program
  // starts it (the PC may).
  State unknown;
  unknown.reached = true;
  std::vector<bool> start_seen(n, false);
  for (std::size_t f = 0; f < n; ++f)
    for (const auto& b : p.functions[f].blocks)
      for (const auto& in : b.instrs) {
        if (starts_or_stops_unnamed_task(in)) std::fill(pass.started.begin(), pass.started.end(), unknown);
        FuncId named = task_named(in);
        if (in.op != rcx::Op::StartTask || named < 0 || runners[f].empty()) continue;
        auto target = static_cast<std::size_t>(named);
        start_seen[target] = true;
        if (!pass.analysed[f]) pass.started[target] = unknown;
      }
  for (std::size_t f = 0; f < n; ++f)
    if (!start_seen[f]) pass.started[f] = unknown;
  FuncId main = p.find_function("main");
  bool main_alone = main >= 0 && !started[static_cast<std::size_t>(main)];
  // Subroutine summaries depend on their callers and callers on the
  // summaries: iterate until nothing changes (states only ever widen).
  pass.recording = true;
  for (bool changed = true; changed;) {
    auto before = pass.summary;
    auto started_before = pass.started;
    for (std::size_t f = 0; f < n; ++f)
      if (pass.analysed[f]) pass.block_states(static_cast<FuncId>(f), pass.entry_of(static_cast<FuncId>(f), main_alone));
    changed = !(before == pass.summary) || !(started_before == pass.started);
  }
  pass.recording = false;
  for (std::size_t f = 0; f < n; ++f) {
    if (!pass.analysed[f]) continue;
    auto in = pass.block_states(static_cast<FuncId>(f), pass.entry_of(static_cast<FuncId>(f), main_alone));
    pass.remove_redundant(p.functions[f], static_cast<FuncId>(f), in);
  }
}

}  // namespace rcxc::ir
