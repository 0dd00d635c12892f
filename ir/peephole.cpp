// Merging of motor commands and dropping of sensor modes the type already
// set (see passes.h).
#include <algorithm>
#include <array>
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
// A value per output, output bit 1, 2 and 4 at index 0, 1 and 2 (in that
// order, as a map by bit would list them). Arrays, not maps: a window of a
// few commands made a dozen maps, a node allocated per entry.
template <class T>
using PerOutput = std::array<std::optional<T>, 3>;
constexpr int kOutputs = 3;

struct Settings {
  std::array<PerOutput<int>, 3> value;  // [field][output] -> value

  // Records `in`; false (recording nothing) if it sets a field to another
  // value than an earlier command did.
  bool add(const Instr& in) {
    FieldSet set = field_set(in);
    PerOutput<int>& field = value[static_cast<std::size_t>(set.field)];
    for (int o = 0; o < kOutputs; ++o)
      if (set.outputs & (1 << o))
        if (const auto& old = field[static_cast<std::size_t>(o)]; old && *old != set.value) return false;
    for (int o = 0; o < kOutputs; ++o)
      if (set.outputs & (1 << o)) field[static_cast<std::size_t>(o)] = set.value;
    return true;
  }
};

// The outputs of each value in `m` as (value, output mask), in the order the
// window first set them (`at`: the index of each output's first setting):
// `OnFwd(OUT_A); OnRev(OUT_C);` keeps A's direction first, so A changes as
// early as in the code as written (and as in nqc's), where ordering by
// value put C's first.
struct ValueMasks {
  std::array<std::pair<int, int>, kOutputs> items{};
  std::size_t size = 0;
  const std::pair<int, int>* begin() const { return items.data(); }
  const std::pair<int, int>* end() const { return items.data() + size; }
};
ValueMasks group(const PerOutput<int>& m, const PerOutput<std::size_t>& at) {
  ValueMasks g;
  std::array<std::size_t, kOutputs> first{};  // per group: its earliest setting
  for (int o = 0; o < kOutputs; ++o) {
    const auto& v = m[static_cast<std::size_t>(o)];
    if (!v) continue;
    std::size_t when = at[static_cast<std::size_t>(o)].value_or(0);
    std::size_t k = 0;
    while (k < g.size && g.items[k].first != *v) ++k;
    if (k < g.size) {
      g.items[k].second |= 1 << o;
      first[k] = std::min(first[k], when);
    } else {
      g.items[g.size] = {*v, 1 << o};
      first[g.size++] = when;
    }
  }
  // Insertion sort by first setting; a stable order keeps output order for ties.
  for (std::size_t i = 1; i < g.size; ++i)
    for (std::size_t j = i; j > 0 && first[j] < first[j - 1]; --j) {
      std::swap(g.items[j], g.items[j - 1]);
      std::swap(first[j], first[j - 1]);
    }
  return g;
}

// The fewest commands giving every output the final direction, mode and
// power the commands in `window` leave, or nothing when no such order
// shows what the window shows. An output shows its direction and power
// while it runs, so each output's switch (on, off, float) must stay on the
// same side of its new settings as in the window: `Rev(OUT_C); Off(OUT_C);`
// runs C backwards before stopping it, `Float(OUT_C); Rev(OUT_C);` never
// does. The order is: switches that came first, power and direction (in
// the order a running output saw them), switches that came last.
std::optional<std::vector<Instr>> net_commands(const std::vector<const Instr*>& window) {
  PerOutput<int> power, dir, mode;
  PerOutput<std::size_t> mode_at, first_setting, last_setting;  // first/last index in window
  PerOutput<std::size_t> power_at, dir_at;                      // index of that setting
  for (std::size_t i = 0; i < window.size(); ++i) {
    FieldSet set = field_set(*window[i]);
    for (std::size_t o = 0; o < kOutputs; ++o) {
      if (!(set.outputs & (1 << o))) continue;
      if (set.field == Field::Switch) {
        // A window switches one output to one value only (Settings), so
        // its first switch says whether the output has that value while
        // its settings change: `Off(B); SetPower(B, 1); Off(B);` keeps B
        // stopped throughout.
        mode[o] = set.value;
        if (!mode_at[o]) mode_at[o] = i;
        continue;
      }
      (set.field == Field::Power ? power : dir)[o] = set.value;
      auto& at = (set.field == Field::Power ? power_at : dir_at)[o];
      if (!at) at = i;
      if (!first_setting[o]) first_setting[o] = i;
      last_setting[o] = i;
    }
  }
  PerOutput<int> early, late;  // switches before / after the settings
  for (std::size_t o = 0; o < kOutputs; ++o) {
    if (!mode[o]) continue;
    int v = *mode[o];
    bool first = v != 0x80;  // no settings of its own: stop early, start late
    if (first_setting[o]) {
      if (*mode_at[o] < *first_setting[o]) first = true;
      else if (*mode_at[o] > *last_setting[o]) first = false;
      else return std::nullopt;  // a switch between two settings of one output
    }
    (first ? early : late)[o] = v;
  }
  // An output that may run while its power and direction both change shows
  // them in the order they came (`Rev(C); SetPower(C, 3)` runs C backwards
  // at full power, then at 3, never forwards at 3): the merged commands
  // keep that order, which all such outputs must share.
  bool direction_first = false, power_first = false;
  for (std::size_t o = 0; o < kOutputs; ++o) {
    if (!power_at[o]) continue;
    bool stopped = early[o] && *early[o] != 0x80;  // off or floating while its settings change
    if (!dir_at[o] || stopped) continue;
    (*dir_at[o] < *power_at[o] ? direction_first : power_first) = true;
  }
  if (direction_first && power_first) return std::nullopt;
  std::vector<Instr> out;
  SpanId span = window.back()->span;
  auto switches = [&](const PerOutput<int>& m) {
    for (auto [v, mask] : group(m, mode_at))
      out.push_back(Instr{Op::SetMotorOnOff, {Operand::imm(mask | v)}, false, span});
  };
  auto powers = [&] {
    for (auto [v, mask] : group(power, power_at))
      out.push_back(Instr{Op::SetMotorPower, {Operand::imm(mask), Operand::imm(v)}, false, span});
  };
  auto directions = [&] {
    for (auto [v, mask] : group(dir, dir_at))
      out.push_back(Instr{Op::SetMotorDirection, {Operand::imm(mask | v)}, false, span});
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
// The block is rewritten in place, each instruction kept moved down over
// the commands merged away: merging never writes more instructions than
// it has read (a new list per block was most of this pass's work).
void merge_block(Block& b, std::size_t first, const std::vector<Var>& vars) {
  std::vector<Instr>& code = b.instrs;
  std::size_t n = code.size();
  std::size_t kept = std::min(first, n);
  auto keep = [&](std::size_t j) {
    if (kept != j) code[kept] = std::move(code[j]);  // never onto itself: that empties it
    ++kept;
  };
  std::vector<const Instr*> motors;
  for (std::size_t i = kept; i < n;) {
    if (!mergeable(code[i])) {
      keep(i++);
      continue;
    }
    // The window: from i to the last motor command reachable across
    // neutral instructions, up to a command that would undo one before it.
    // Nothing from i on has been moved yet.
    std::size_t last = i;
    Settings settings;
    for (std::size_t j = i; j < n && (mergeable(code[j]) || neutral(code[j], vars)); ++j) {
      if (!mergeable(code[j])) continue;
      if (!settings.add(code[j])) break;
      last = j;
    }
    motors.clear();
    for (std::size_t j = i; j <= last; ++j)
      if (mergeable(code[j])) motors.push_back(&code[j]);
    auto merged = net_commands(motors);
    if (merged && merged->size() < motors.size()) {
      // Moving an instruction down only overwrites ones already read.
      for (std::size_t j = i; j <= last; ++j)
        if (!mergeable(code[j])) keep(j);
      for (auto& m : *merged) code[kept++] = std::move(m);
    } else {
      for (std::size_t j = i; j <= last; ++j) keep(j);
    }
    i = last + 1;
  }
  code.erase(code.begin() + static_cast<std::ptrdiff_t>(kept), code.end());
}

// The mode Set sensor type gives each type (seed: raw, boolean, celsius,
// percent, angle), as a mode byte with slope 0.
int default_mode_code(int type) {
  static constexpr int kModes[] = {0, 1, 5, 4, 7};
  return (type >= 0 && type <= 4) ? kModes[type] << 5 : -1;
}

// Whether instruction i sets the mode the type set just before gives.
bool default_mode_after_type(const std::vector<Instr>& code, std::size_t i) {
  const Instr& in = code[i];
  if (in.raw || in.op != Op::SetSensorMode || i == 0) return false;
  const Instr& prev = code[i - 1];
  return !prev.raw && prev.op == Op::SetSensorType && prev.args[0] == in.args[0] && in.args[1].is_imm() &&
         prev.args[1].is_imm() && default_mode_code(prev.args[1].value) == in.args[1].value;
}

void drop_default_modes(Block& b) {
  // Most blocks have none: those are left as they are, not copied.
  std::size_t i = 0;
  while (i < b.instrs.size() && !default_mode_after_type(b.instrs, i)) ++i;
  if (i == b.instrs.size()) return;
  std::vector<Instr> kept;
  for (i = 0; i < b.instrs.size(); ++i)
    if (!default_mode_after_type(b.instrs, i)) kept.push_back(b.instrs[i]);
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
void shorten_complements(Function& f, const std::vector<Var>& vars, bool other_tasks) {
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
      if (other_tasks && shared_between_tasks(vars.at(static_cast<std::size_t>(t)))) continue;
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
