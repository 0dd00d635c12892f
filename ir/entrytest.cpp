// Loops entered past a test whose outcome the way in fixes (see passes.h).
#include <map>
#include <optional>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// The constants `b` leaves in its function's own variables (locals and
// temporaries, which no other task writes): the last instruction writing
// each was a `set` of a constant. A call, or raw asm, may write any.
std::map<VarId, int> constants_left(const Block& b, const std::vector<Var>& vars) {
  std::map<VarId, int> known;
  for (const Instr& in : b.instrs) {
    if (in.raw || in.op == rcx::Op::CallSubroutine) {
      known.clear();
      continue;
    }
    if (!computes_into_variable(in.op)) continue;
    if (!in.args.at(0).is_var()) {  // a slot by number (`@3 = 0`) may be any variable
      known.clear();
      continue;
    }
    VarId v = static_cast<VarId>(in.args[0].value);
    known.erase(v);
    const Operand& value = in.args.at(1);
    if (in.op == rcx::Op::SetVariable && value.is_imm() && !shared_between_tasks(vars.at(static_cast<std::size_t>(v))))
      known[v] = value.value;
  }
  return known;
}

std::optional<int> value_of(const Operand& o, const std::map<VarId, int>& known) {
  if (o.is_imm()) return o.value;
  if (!o.is_var()) return std::nullopt;
  auto it = known.find(static_cast<VarId>(o.value));
  if (it == known.end()) return std::nullopt;
  return it->second;
}

}  // namespace

bool enter_past_known_tests(Function& f, const std::vector<Var>& vars) {
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  bool changed = false;
  for (std::size_t x = 0; x < f.blocks.size(); ++x) {
    auto* jump = std::get_if<Jump>(&f.blocks[x].term);
    if (jump == nullptr || loop_blocks[x]) continue;
    const Block& test = f.blocks[static_cast<std::size_t>(jump->target)];
    const auto* br = std::get_if<Branch>(&test.term);
    // Only a test alone: instructions before it would have to run too.
    if (br == nullptr || !test.instrs.empty() || loop_blocks[static_cast<std::size_t>(jump->target)]) continue;
    auto known = constants_left(f.blocks[x], vars);
    auto a = value_of(br->a, known), b = value_of(br->b, known);
    if (!a || !b) continue;
    BlockId to = evaluate(br->cmp, *a, *b) ? br->then : br->otherwise;
    // Falling into the test costs nothing: a jump past it would.
    auto next = static_cast<BlockId>(x + 1);
    if (jump->target == next && to != next) continue;
    jump->target = to;
    changed = true;
  }
  if (!changed) return false;
  const std::size_t blocks = f.blocks.size();
  remove_unreachable(f);
  return f.blocks.size() < blocks;
}

}  // namespace rcxc::ir
