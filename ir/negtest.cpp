// Tests of a value negated just before (see passes.h).
#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {

void test_before_negating(Program& p) {
  std::optional<CallEffects> calls;
  for (auto& f : p.functions) {
    // Only functions with the shape pay for liveness.
    auto candidate = [&](const Block& b) -> std::optional<VarId> {
      const auto* br = std::get_if<Branch>(&b.term);
      if (!br || b.instrs.empty() || (br->cmp != Cmp::EQ && br->cmp != Cmp::NE)) return std::nullopt;
      const Instr& last = b.instrs.back();
      if (last.raw || last.op != rcx::Op::MultiplyVariable || last.args.size() != 2 || !last.args[0].is_var() ||
          !(last.args[1] == Operand::imm(-1)))
        return std::nullopt;
      VarId t = last.args[0].value;
      if (p.vars[static_cast<std::size_t>(t)].kind == VarKind::Global) return std::nullopt;
      bool a = br->a.is_var(t) && br->b.is_imm(), bb = br->b.is_var(t) && br->a.is_imm();
      if (!a && !bb) return std::nullopt;
      return t;
    };
    bool any = false;
    for (const auto& b : f.blocks) any |= candidate(b).has_value();
    if (!any) continue;
    if (!calls) calls = call_effects(p);
    Liveness L = compute_liveness(p, f, *calls);
    for (std::size_t b = 0; b < f.blocks.size(); ++b) {
      Block& block = f.blocks[b];
      auto t = candidate(block);
      if (!t || L.live_out[b].has(*t)) continue;
      // -t == K exactly when t == -K, in 16 bits as everywhere (negation
      // is one-to-one, -32768 its own negative). The ordered comparisons
      // are not: -(-32768) < 0 holds, -32768 > 0 does not.
      auto& br = std::get<Branch>(block.term);
      Operand& k = br.a.is_imm() ? br.a : br.b;
      k = Operand::imm(wrap16(-static_cast<long>(k.value)));
      block.instrs.pop_back();
    }
  }
}

}  // namespace rcxc::ir
