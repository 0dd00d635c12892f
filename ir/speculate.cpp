// If/else speculation (see passes.h).
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// `set v, X` on a local or temporary v, with X a constant or another
// variable: setting it early changes nothing another task or the random
// source could tell.
std::optional<VarId> private_set(const Block& b, const std::vector<Var>& vars) {
  if (b.instrs.size() != 1) return std::nullopt;
  const Instr& in = b.instrs[0];
  if (in.raw || in.op != rcx::Op::SetVariable || !in.args[0].is_var()) return std::nullopt;
  VarId v = in.args[0].value;
  if (vars[static_cast<std::size_t>(v)].kind == VarKind::Global) return std::nullopt;
  const Operand& x = in.args[1];
  if (!(x.is_imm() || (x.is_var() && !x.is_var(v)))) return std::nullopt;
  return v;
}

std::optional<BlockId> jump_target(const Block& b) {
  if (const auto* j = std::get_if<Jump>(&b.term)) return j->target;
  return std::nullopt;
}

}  // namespace

void speculate_assignments(Function& f, const std::vector<Var>& vars) {
  std::vector<int> preds = predecessor_counts(f);
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    auto* br = std::get_if<Branch>(&f.blocks[b].term);
    if (br == nullptr || br->then == br->otherwise || loop_blocks[b]) continue;
    for (bool hoist_else : {true, false}) {
      BlockId early = hoist_else ? br->otherwise : br->then;
      BlockId kept = hoist_else ? br->then : br->otherwise;
      const Block& e = f.blocks[static_cast<std::size_t>(early)];
      const Block& k = f.blocks[static_cast<std::size_t>(kept)];
      auto v = private_set(e, vars), w = private_set(k, vars);
      auto join = jump_target(e);
      if (!v || v != w || !join || join != jump_target(k) || *join == early || *join == kept ||
          *join == static_cast<BlockId>(b) || early == static_cast<BlockId>(b) || kept == static_cast<BlockId>(b) ||
          preds[static_cast<std::size_t>(early)] != 1 || loop_blocks[static_cast<std::size_t>(early)] || br->a.is_var(*v) ||
          br->b.is_var(*v))
        continue;
      f.blocks[b].instrs.push_back(e.instrs[0]);
      --preds[static_cast<std::size_t>(early)];
      ++preds[static_cast<std::size_t>(*join)];
      retarget(f.blocks[b].term, early, *join);
      break;
    }
  }
}

}  // namespace rcxc::ir
