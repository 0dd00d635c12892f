// Hoisting what both sides of a test begin with (see passes.h).
#include <fmt/format.h>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

bool reads_source(const Branch& br, rcx::Source s) {
  auto is = [&](const Operand& o) { return o.kind == Operand::Kind::Src && o.source == static_cast<int>(s); };
  return is(br.a) || is(br.b);
}

// Whether the test reads what another task may change: a global, a slot
// by number, or any source (an output's state, a timer, the message, a
// sensor, the next random number).
bool reads_shared(const Branch& br, const std::vector<Var>& vars) {
  auto shared = [&](const Operand& o) {
    if (o.is_var()) return shared_between_tasks(vars.at(static_cast<std::size_t>(o.value)));
    return o.kind == Operand::Kind::Src;
  };
  return shared(br.a) || shared(br.b);
}

// Whether `in` may run before the test instead of after it. Only what
// cannot change the test's outcome or its timing: a motor command (unless
// the test reads an output's state), a sound, or arithmetic into a variable
// the test does not read (drawing a random number before a test that draws
// one too would swap the draws; a test reading a slot by number, `@0`,
// may read any variable: globals keep nqc's slots). A wait would delay the
// test's reading, a call or a task start could change anything: they stay.
// With other tasks running, what they can see stays after a test of what
// they can change: one copying a global into the one tested, or polling an
// output, could answer the moved command before the test, which it never
// could when the command came after.
bool may_run_before(const Instr& in, const Branch& br, const std::vector<Var>& vars, bool other_tasks) {
  if (!is_quick_command(in)) return false;
  if (in.op == rcx::Op::PlaySound || in.op == rcx::Op::PlayTone) return true;
  if (other_tasks && seen_by_other_tasks(in, vars) && reads_shared(br, vars)) return false;
  if (is_motor_command(in)) return !reads_source(br, rcx::Source::MotorState);
  if (reads_source(br, rcx::Source::Variable)) return false;
  const Operand& dest = in.args.at(0);
  if (dest.is_var() && (br.a.is_var(dest.value) || br.b.is_var(dest.value))) return false;
  bool draws = false;
  for (const Operand& o : in.args) draws |= reads_random(o);
  return !(draws && reads_source(br, rcx::Source::Random));
}

// Whether a side of the branch in block b is its own: entered from b alone.
bool entered_only_from(const Function& f, const std::vector<int>& preds, const std::vector<bool>& loop_blocks,
                       BlockId side, std::size_t b) {
  auto s = static_cast<std::size_t>(side);
  return side != 0 && s != b && preds[s] == 1 && !loop_blocks[s] && !f.blocks[s].instrs.empty();
}

void hoist_in(Function& f, const std::vector<Var>& vars, bool other_tasks, Log& log) {
  const std::vector<int> preds = predecessor_counts(f);
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    const auto* br = std::get_if<Branch>(&f.blocks[b].term);
    if (br == nullptr || br->then == br->otherwise || loop_blocks[b]) continue;
    auto& then_code = f.blocks[static_cast<std::size_t>(br->then)].instrs;
    auto& else_code = f.blocks[static_cast<std::size_t>(br->otherwise)].instrs;
    while (entered_only_from(f, preds, loop_blocks, br->then, b) &&
           entered_only_from(f, preds, loop_blocks, br->otherwise, b) &&
           same_instr(then_code.front(), else_code.front()) &&
           may_run_before(then_code.front(), *br, vars, other_tasks)) {
      log.push_back(fmt::format("{}: `{}` begins both sides of a test and runs once before the test", f.name,
                                rcx::info(then_code.front().op).mnemonic));
      f.blocks[b].instrs.push_back(then_code.front());
      then_code.erase(then_code.begin());
      else_code.erase(else_code.begin());
    }
  }
}

}  // namespace

void hoist_common_heads(Program& p, Log& log) {
  bool other_tasks = runs_several_tasks(p);
  for (auto& f : p.functions) hoist_in(f, p.vars, other_tasks, log);
}

}  // namespace rcxc::ir
