// Removal of motor commands that change nothing (see passes.h).
//
// The firmware keeps each output's direction, on/off/float mode and power.
// `OnFwd(OUT_A)` right after the startup code sets direction forward again,
// macros like `forwards(s, t)` repeat `SetPower` with the power already set,
// and so on. An output is tracked only inside the one task that commands it
// (with the subroutines only that task calls): there no other task can
// change it between two instructions, so a command that sets what the
// output already has is removed.
#include <algorithm>
#include <array>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

constexpr int kOutputs = 3;
constexpr int kUnknown = -1;

struct OutputState {
  int dir = kUnknown;    // 0 reverse, 1 forward
  int mode = kUnknown;   // 0 float, 1 off, 2 on
  int power = kUnknown;  // 0..7
  friend bool operator==(const OutputState&, const OutputState&) = default;
};
struct State {
  bool reached = false;
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
  for (int o = 0; o < kOutputs; ++o) {
    into.out[o].dir = merge_field(into.out[o].dir, from.out[o].dir);
    into.out[o].mode = merge_field(into.out[o].mode, from.out[o].mode);
    into.out[o].power = merge_field(into.out[o].power, from.out[o].power);
  }
}

bool is_motor_op(const Instr& in) {
  return !in.raw && (in.op == rcx::Op::SetMotorDirection || in.op == rcx::Op::SetMotorOnOff ||
                     in.op == rcx::Op::SetMotorPower);
}

// Outputs an instruction may change (raw bytes: any).
int touched(const Instr& in) {
  if (in.raw) return 7;
  if (is_motor_op(in)) return in.args.at(0).is_imm() ? (in.args[0].value & 7) : 7;
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

struct MotorPass {
  const Program& p;
  std::vector<int> touches;  // per function: outputs it (and its callees) command
  int tracked = 0;           // outputs this function may track

  // Applies `in` to `s`; returns whether it changed nothing at all.
  bool apply(const Instr& in, State& s) const {
    if (FuncId g = callee_of(in); g >= 0) {
      for (int o = 0; o < kOutputs; ++o)
        if ((touches[static_cast<std::size_t>(g)] >> o) & 1) s.out[o] = {};
      return false;
    }
    int mask = touched(in);
    if (mask == 0) return false;
    if (in.raw || !is_motor_op(in) || !in.args[0].is_imm()) {
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
      if (e.flip || next == kUnknown || field != next || !((tracked >> o) & 1)) redundant = false;
      field = next;
    }
    for (int o = 0; o < kOutputs; ++o)
      if (!((tracked >> o) & 1)) s.out[o] = {};
    return redundant;
  }

  void run(Function& f) {
    std::size_t n = f.blocks.size();
    std::vector<State> in(n);
    in[0].reached = true;
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t b = 0; b < n; ++b) {
        if (!in[b].reached) continue;
        State s = in[b];
        for (const auto& instr : f.blocks[b].instrs) apply(instr, s);
        for (BlockId succ : successors(f.blocks[b].term)) {
          State before = in[static_cast<std::size_t>(succ)];
          merge_into(in[static_cast<std::size_t>(succ)], s);
          changed |= !(before == in[static_cast<std::size_t>(succ)]);
        }
      }
    }
    for (std::size_t b = 0; b < n; ++b) {
      State s = in[b];
      std::vector<Instr> kept;
      for (auto& instr : f.blocks[b].instrs)
        if (!apply(instr, s) || !in[b].reached) kept.push_back(std::move(instr));
      f.blocks[b].instrs = std::move(kept);
    }
  }
};

// Whether some instruction starts task `f` (for main: restarts it, so its
// startup code can run while other tasks run).
bool started_anywhere(const Program& p, FuncId f) {
  for (const auto& fn : p.functions)
    for (const auto& b : fn.blocks)
      for (const auto& in : b.instrs)
        if (!in.raw && in.op == rcx::Op::StartTask && in.args[0].kind == Operand::Kind::Func && in.args[0].value == f)
          return true;
  return false;
}

std::vector<int> function_touches(const Program& p) {
  std::vector<int> t(p.functions.size(), 0);
  for (std::size_t f = 0; f < p.functions.size(); ++f) {
    const Function& fn = p.functions[f];
    // Main's startup code runs before any other task exists, unless
    // something restarts main.
    int skip = started_anywhere(p, static_cast<FuncId>(f)) ? 0 : fn.startup;
    for (std::size_t b = 0; b < fn.blocks.size(); ++b)
      for (std::size_t i = 0; i < fn.blocks[b].instrs.size(); ++i)
        if (!(b == 0 && static_cast<int>(i) < skip)) t[f] |= touched(fn.blocks[b].instrs[i]);
  }
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

}  // namespace

void remove_redundant_motor_commands(Program& p) {
  MotorPass pass{p, function_touches(p), 0};
  // Which tasks command each output, and which tasks run each function.
  std::vector<std::vector<FuncId>> runners(p.functions.size());
  std::array<int, kOutputs> commanders{};
  std::array<FuncId, kOutputs> owner{-1, -1, -1};
  for (std::size_t t = 0; t < p.functions.size(); ++t) {
    if (p.functions[t].kind != FuncKind::Task || p.functions[t].blocks.empty()) continue;
    for (int o = 0; o < kOutputs; ++o)
      if ((pass.touches[t] >> o) & 1) {
        ++commanders[o];
        owner[o] = static_cast<FuncId>(t);
      }
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
  for (std::size_t f = 0; f < p.functions.size(); ++f) {
    if (p.functions[f].blocks.empty() || runners[f].size() != 1) continue;
    pass.tracked = 0;
    for (int o = 0; o < kOutputs; ++o)
      if (commanders[o] <= 1 && (commanders[o] == 0 || owner[o] == runners[f][0])) pass.tracked |= 1 << o;
    pass.run(p.functions[f]);
  }
}

}  // namespace rcxc::ir
