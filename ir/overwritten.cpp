// Motor commands the next block sets again at once (see passes.h).
#include <fmt/format.h>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// The outputs a motor command names (bits 0..2), when constant.
std::optional<int> outputs_of(const Instr& in) {
  if (!in.args.at(0).is_imm()) return std::nullopt;
  return in.args[0].value & 7;
}

// Whether `later` sets, on every output `earlier` names, the field
// `earlier` sets, to the same value: then `earlier` changed nothing anyone
// could see even for the time of a jump. (An off dropped before an on
// would no longer brake the output for that instant: `rcxc compare` and a
// program pulsing a lamp both tell.) A direction flip or a power in a
// variable has no value known here.
bool sets_again(const Instr& later, const Instr& earlier) {
  if (!is_motor_command(later) || !is_motor_command(earlier) || later.op != earlier.op) return false;
  auto mine = outputs_of(earlier), theirs = outputs_of(later);
  if (!mine || !theirs || (*mine & ~*theirs) != 0) return false;
  if (later.op == rcx::Op::SetMotorPower) {
    const Operand& power = later.args.at(1);
    return power.is_imm() && power.value >= 0 && power.value <= 7 && power == earlier.args.at(1);
  }
  int value = later.args[0].value & 0xc0;
  return value == (earlier.args[0].value & 0xc0) && !(later.op == rcx::Op::SetMotorDirection && (value & 0x40));
}

// Whether the motor commands `next` begins with (only motor commands,
// which read no output) set again what `in` sets, none acting on those
// outputs before.
bool overwritten_at_start(const Block& next, const Instr& in) {
  for (const Instr& later : next.instrs) {
    if (!is_motor_command(later)) return false;
    if (sets_again(later, in)) return true;
    // A command on those outputs first would act while `in`'s setting
    // holds: another value of its field would show it change, and a
    // direction or power set while `in` keeps an output off shows only
    // because of `in`.
    auto mine = outputs_of(in), theirs = outputs_of(later);
    if (!mine || !theirs || (*mine & *theirs) != 0) return false;
  }
  return false;
}

}  // namespace

void drop_motor_commands_overwritten_next(Function& f, Log& log) {
  for (auto& block : f.blocks) {
    const auto* j = std::get_if<Jump>(&block.term);
    if (j == nullptr) continue;
    const Block& next = f.blocks[static_cast<std::size_t>(j->target)];
    if (&next == &block) continue;
    while (!block.instrs.empty() && is_motor_command(block.instrs.back()) &&
           overwritten_at_start(next, block.instrs.back())) {
      log.push_back(fmt::format("{}: `{}` goes: the block it jumps to sets it again", f.name,
                                rcx::info(block.instrs.back().op).mnemonic));
      block.instrs.pop_back();
    }
  }
}

}  // namespace rcxc::ir
