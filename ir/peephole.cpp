// Merging of motor commands and dropping of sensor modes the type already
// set (see passes.h).
#include <algorithm>
#include <map>
#include <optional>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

using rcx::Op;

// A motor command whose effect is known: code/power immediates, no flip.
bool mergeable(const Instr& in) {
  if (in.raw || in.args.empty() || !in.args[0].is_imm()) return false;
  switch (in.op) {
    case Op::SetMotorDirection: return (in.args[0].value & 0x40) == 0;
    case Op::SetMotorOnOff: return true;
    case Op::SetMotorPower: return in.args[1].is_imm() && in.args[1].value >= 0 && in.args[1].value <= 7;
    default: return false;
  }
}

bool reads_motor_state(const Instr& in) {
  for (const auto& a : in.args)
    if (a.kind == Operand::Kind::Src && a.source == 3) return true;
  return false;
}

// Instructions a motor command may move across: they neither depend on
// nor change the outputs, and take no time to speak of. A write to a global
// is not: another task may be waiting for it (`sem = 0;` ends a critical
// section, and the commands inside must stay inside).
bool neutral(const Instr& in, const std::vector<Var>& vars) {
  if (in.raw || reads_motor_state(in)) return false;
  switch (in.op) {
    case Op::SetVariable: case Op::AddToVariable: case Op::SubtractFromVariable: case Op::MultiplyVariable:
    case Op::DivideVariable: case Op::AndVariable: case Op::OrVariable: case Op::AbsoluteValue:
    case Op::SignVariable:
      // args[0] is the destination variable of each of these.
      return in.args.at(0).kind == Operand::Kind::Var &&
             vars[static_cast<std::size_t>(in.args[0].value)].kind != VarKind::Global;
    case Op::SetSensorType: case Op::SetSensorMode: case Op::ClearSensorValue:
    case Op::ClearTimer: case Op::PlaySound: case Op::PlayTone: case Op::ClearMessage: case Op::SendMessage:
      return true;
    default: return false;
  }
}

// What one mergeable motor command sets: a field, its value (as the
// command encodes it) and the outputs (bits 1, 2, 4).
enum class Field { Power, Direction, Switch };
struct FieldSet {
  Field field;
  int value;
  int outputs;
};

FieldSet field_set(const Instr& in) {
  int code = in.args[0].value;
  switch (in.op) {
    case Op::SetMotorPower: return {Field::Power, in.args[1].value, code & 7};
    case Op::SetMotorDirection: return {Field::Direction, code & 0x80, code & 7};
    default: return {Field::Switch, code & 0xc0, code & 7};
  }
}

// What the commands of a window set, per output and field. Merging keeps
// only each field's last value, so a window must never set one field of
// one output to two values: `On(OUT_A); Off(OUT_A);` in a loop runs the
// motor a third of the time (a slow motor, a common NQC idiom), and
// merged it would never run.
struct Settings {
  std::map<std::pair<Field, int>, int> value;  // (field, output bit) -> value

  // Records `in`; false (recording nothing) if it sets a field to another
  // value than an earlier command did.
  bool add(const Instr& in) {
    FieldSet set = field_set(in);
    for (int bit = 1; bit <= 4; bit <<= 1)
      if (set.outputs & bit)
        if (auto it = value.find({set.field, bit}); it != value.end() && it->second != set.value) return false;
    for (int bit = 1; bit <= 4; bit <<= 1)
      if (set.outputs & bit) value[{set.field, bit}] = set.value;
    return true;
  }
};

// The fewest commands giving every output the final direction, mode and
// power the commands in `window` leave, or nothing when no such order
// shows what the window shows. An output shows its direction and power
// while it runs, so each output's switch (on, off, float) must stay on the
// same side of its new settings as in the window: `Rev(OUT_C); Off(OUT_C);`
// runs C backwards before stopping it, `Float(OUT_C); Rev(OUT_C);` never
// does. The order is: switches that came first, power and direction (in
// the order a running output saw them), switches that came last.
std::optional<std::vector<Instr>> net_commands(const std::vector<const Instr*>& window) {
  std::map<int, int> power, dir, mode;  // output bit -> value
  std::map<int, std::size_t> mode_at, first_setting, last_setting;  // output bit -> first/last index in window
  std::map<int, std::size_t> power_at, dir_at;                      // output bit -> index of that setting
  for (std::size_t i = 0; i < window.size(); ++i) {
    FieldSet set = field_set(*window[i]);
    for (int bit = 1; bit <= 4; bit <<= 1) {
      if (!(set.outputs & bit)) continue;
      if (set.field == Field::Switch) {
        // A window switches one output to one value only (Settings), so
        // its first switch says whether the output has that value while
        // its settings change: `Off(B); SetPower(B, 1); Off(B);` keeps B
        // stopped throughout.
        mode[bit] = set.value;
        if (!mode_at.contains(bit)) mode_at[bit] = i;
        continue;
      }
      (set.field == Field::Power ? power : dir)[bit] = set.value;
      (set.field == Field::Power ? power_at : dir_at).try_emplace(bit, i);
      if (!first_setting.contains(bit)) first_setting[bit] = i;
      last_setting[bit] = i;
    }
  }
  std::map<int, int> early, late;  // switches before / after the settings
  for (auto [bit, v] : mode) {
    bool first = v != 0x80;  // no settings of its own: stop early, start late
    if (first_setting.contains(bit)) {
      if (mode_at[bit] < first_setting[bit]) first = true;
      else if (mode_at[bit] > last_setting[bit]) first = false;
      else return std::nullopt;  // a switch between two settings of one output
    }
    (first ? early : late)[bit] = v;
  }
  // An output that may run while its power and direction both change shows
  // them in the order they came (`Rev(C); SetPower(C, 3)` runs C backwards
  // at full power, then at 3, never forwards at 3): the merged commands
  // keep that order, which all such outputs must share.
  bool direction_first = false, power_first = false;
  for (auto [bit, at] : power_at) {
    auto d = dir_at.find(bit);
    auto e = early.find(bit);
    bool stopped = e != early.end() && e->second != 0x80;  // off or floating while its settings change
    if (d == dir_at.end() || stopped) continue;
    (d->second < at ? direction_first : power_first) = true;
  }
  if (direction_first && power_first) return std::nullopt;
  auto group = [](const std::map<int, int>& m) {
    std::map<int, int> by_value;  // value -> output mask
    for (auto [bit, v] : m) by_value[v] |= bit;
    return by_value;
  };
  std::vector<Instr> out;
  SpanId span = window.back()->span;
  auto switches = [&](const std::map<int, int>& m) {
    for (auto [v, mask] : group(m)) out.push_back(Instr{Op::SetMotorOnOff, {Operand::imm(mask | v)}, false, span});
  };
  auto powers = [&] {
    for (auto [v, mask] : group(power))
      out.push_back(Instr{Op::SetMotorPower, {Operand::imm(mask), Operand::imm(v)}, false, span});
  };
  auto directions = [&] {
    for (auto [v, mask] : group(dir)) out.push_back(Instr{Op::SetMotorDirection, {Operand::imm(mask | v)}, false, span});
  };
  switches(early);
  if (direction_first) {
    directions();
    powers();
  } else {
    powers();
    directions();
  }
  switches(late);
  return out;
}

// `first`: instructions before it stay as they are (main's startup code).
void merge_block(Block& b, std::size_t first, const std::vector<Var>& vars) {
  std::vector<Instr> result;
  std::size_t n = b.instrs.size();
  for (std::size_t i = 0; i < std::min(first, n); ++i) result.push_back(std::move(b.instrs[i]));
  for (std::size_t i = std::min(first, n); i < n;) {
    if (!mergeable(b.instrs[i])) {
      result.push_back(std::move(b.instrs[i++]));
      continue;
    }
    // The window: from i to the last motor command reachable across
    // neutral instructions, up to a command that would undo one before it.
    std::size_t last = i;
    Settings settings;
    for (std::size_t j = i; j < n && (mergeable(b.instrs[j]) || neutral(b.instrs[j], vars)); ++j) {
      if (!mergeable(b.instrs[j])) continue;
      if (!settings.add(b.instrs[j])) break;
      last = j;
    }
    std::vector<const Instr*> motors;
    for (std::size_t j = i; j <= last; ++j)
      if (mergeable(b.instrs[j])) motors.push_back(&b.instrs[j]);
    auto merged = net_commands(motors);
    if (merged && merged->size() < motors.size()) {
      for (std::size_t j = i; j <= last; ++j)
        if (!mergeable(b.instrs[j])) result.push_back(std::move(b.instrs[j]));
      for (auto& m : *merged) result.push_back(std::move(m));
    } else {
      for (std::size_t j = i; j <= last; ++j) result.push_back(std::move(b.instrs[j]));
    }
    i = last + 1;
  }
  b.instrs = std::move(result);
}

// The mode Set sensor type gives each type (seed: raw, boolean, celsius,
// percent, angle), as a mode byte with slope 0.
int default_mode_code(int type) {
  static constexpr int kModes[] = {0, 1, 5, 4, 7};
  return (type >= 0 && type <= 4) ? kModes[type] << 5 : -1;
}

void drop_default_modes(Block& b) {
  std::vector<Instr> kept;
  for (std::size_t i = 0; i < b.instrs.size(); ++i) {
    const Instr& in = b.instrs[i];
    bool redundant = false;
    if (!in.raw && in.op == Op::SetSensorMode && i > 0) {
      const Instr& prev = b.instrs[i - 1];
      redundant = !prev.raw && prev.op == Op::SetSensorType && prev.args[0] == in.args[0] &&
                  in.args[1].is_imm() && prev.args[1].is_imm() && default_mode_code(prev.args[1].value) == in.args[1].value;
    }
    if (!redundant) kept.push_back(in);
  }
  b.instrs = std::move(kept);
}

}  // namespace

void merge_motor_commands(Function& f, const std::vector<Var>& vars) {
  for (std::size_t b = 0; b < f.blocks.size(); ++b)
    merge_block(f.blocks[b], b == 0 ? static_cast<std::size_t>(f.startup) : 0, vars);
}

void drop_redundant_sensor_modes(Function& f) {
  for (auto& b : f.blocks) drop_default_modes(b);
}

}  // namespace rcxc::ir

namespace rcxc::ir {

// `~x` of an expression computed into t is `set t, x; mul t, -1; sub t, 1`
// (15 bytes); `set t, -1; sub t, x` (10 bytes, one instruction less) is the
// same 16-bit value and reads x once, as before.
void shorten_complements(Function& f) {
  auto is_imm_step = [](const Instr& in, rcx::Op op, VarId t, int value) {
    return !in.raw && in.op == op && in.args.size() == 2 && in.args[0].is_var(t) && in.args[1].is_imm() &&
           in.args[1].value == value;
  };
  for (auto& b : f.blocks) {
    auto& code = b.instrs;
    for (std::size_t i = 0; i + 2 < code.size(); ++i) {
      const Instr& set = code[i];
      if (set.raw || set.op != rcx::Op::SetVariable || set.args.size() != 2 || !set.args[0].is_var()) continue;
      VarId t = set.args[0].value;
      Operand x = set.args[1];
      if (x.is_var(t) || !accepts(rcx::Op::SubtractFromVariable, 1, x)) continue;
      if (!is_imm_step(code[i + 1], rcx::Op::MultiplyVariable, t, -1) ||
          !is_imm_step(code[i + 2], rcx::Op::SubtractFromVariable, t, 1))
        continue;
      code[i].args[1] = Operand::imm(-1);
      code[i + 1].op = rcx::Op::SubtractFromVariable;
      code[i + 1].args[1] = x;
      code.erase(code.begin() + static_cast<std::ptrdiff_t>(i) + 2);
    }
  }
}

}  // namespace rcxc::ir
