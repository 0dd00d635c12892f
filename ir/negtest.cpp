// Tests of a value computed just before by one-to-one arithmetic (see
// passes.h).
#include <optional>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// The inverse of an odd number modulo 2^16 (Newton's iteration doubles the
// correct low bits each step: 1, 2, 4, 8, 16).
int inverse_mod_65536(int k) {
  std::uint32_t x = static_cast<std::uint32_t>(k) & 0xffff, inv = x;
  for (int i = 0; i < 4; ++i) inv = (inv * (2 - x * inv)) & 0xffff;
  return wrap16(static_cast<long>(inv));
}

bool writes_only(const Instr& in, VarId t) { return !in.raw && in.args.size() == 2 && in.args[0].is_var(t); }

// What `t = x` may hand to the test in t's place: another variable, or a
// source a test can read (a sensor, a timer, the message; not a random
// number or the program number, and an argument within a byte). The copy
// is the block's last computation of t, so the test reads the source when
// the copy would have: one read, at the same time.
bool testable_copy(const Operand& x, VarId t) {
  if (x.is_var()) return !x.is_var(t);
  return x.kind == Operand::Kind::Src && x.source >= 0 && x.source != static_cast<int>(rcx::Source::Random) &&
         x.source != static_cast<int>(rcx::Source::Program) && x.value >= -128 && x.value <= 127;
}

// What the test of t against a constant becomes when the instructions at
// the end of the block computing t are left out: the operand to test
// instead, the constant, the comparison, and how many instructions go.
struct Rewrite {
  Operand tested;
  int constant = 0;
  Cmp cmp = Cmp::EQ;
  std::size_t dropped = 0;
};

// Peels the block's last instructions writing t while each is one-to-one
// on 16-bit values (t += K, t -= K, t *= K for an odd K, t *= -1), taking
// the constant back through each; then `t = X` (test X) or `t = K; t -=
// X` (K - X == c exactly when X == K - c) if they come next. Equality
// holds through every one-to-one map; an order only through none, or
// through `t = -1; t -= X` alone (~X, which reverses the order and never
// wraps).
std::optional<Rewrite> peel(const Block& block, VarId t, Cmp cmp, int c) {
  const auto& code = block.instrs;
  std::size_t k = code.size();
  bool ordered = cmp != Cmp::EQ && cmp != Cmp::NE;
  long value = c;
  while (k > 0 && !ordered) {
    const Instr& in = code[k - 1];
    if (!writes_only(in, t) || !in.args[1].is_imm()) break;
    long operand = in.args[1].value;
    if (in.op == rcx::Op::AddToVariable) value -= operand;
    else if (in.op == rcx::Op::SubtractFromVariable) value += operand;
    else if (in.op == rcx::Op::MultiplyVariable && (operand & 1)) value *= inverse_mod_65536(static_cast<int>(operand));
    else break;
    value = wrap16(value);
    --k;
  }
  Rewrite r{Operand::var(t), static_cast<int>(value), cmp, code.size() - k};
  if (k > 0 && writes_only(code[k - 1], t) && code[k - 1].op == rcx::Op::SetVariable &&
      testable_copy(code[k - 1].args[1], t)) {
    r.tested = code[k - 1].args[1];
    ++r.dropped;
  } else if (k > 1 && writes_only(code[k - 1], t) && code[k - 1].op == rcx::Op::SubtractFromVariable &&
             code[k - 1].args[1].is_var() && !code[k - 1].args[1].is_var(t) && writes_only(code[k - 2], t) &&
             code[k - 2].op == rcx::Op::SetVariable && code[k - 2].args[1].is_imm()) {
    int base = code[k - 2].args[1].value;
    if (ordered && base != -1) return std::nullopt;
    r.tested = code[k - 1].args[1];
    r.constant = wrap16(static_cast<long>(base) - value);
    if (ordered) r.cmp = swap(cmp);  // -1 - X <= c  <=>  X >= -1 - c
    r.dropped += 2;
  }
  if (r.dropped == 0) return std::nullopt;
  return r;
}

}  // namespace

void test_before_one_to_one_arithmetic(Program& p, LivenessCache* cache) {
  std::optional<CallEffects> calls;
  Liveness fresh;
  for (auto& f : p.functions) {
    // The temporary or local a block's test compares with a constant,
    // computed by the block's last instruction.
    auto candidate = [&](const Block& b) -> std::optional<VarId> {
      const auto* br = std::get_if<Branch>(&b.term);
      if (!br || b.instrs.empty()) return std::nullopt;
      const Operand& v = br->a.is_imm() ? br->b : br->a;
      const Operand& k = br->a.is_imm() ? br->a : br->b;
      if (!v.is_var() || !k.is_imm() || !writes_only(b.instrs.back(), v.value)) return std::nullopt;
      if (p.vars[static_cast<std::size_t>(v.value)].kind == VarKind::Global) return std::nullopt;
      return v.value;
    };
    bool any = false;
    for (const auto& b : f.blocks) any |= candidate(b).has_value();
    if (!any) continue;
    if (!calls) calls = call_effects(p);
    // Usually what computing into targets, just before, left.
    const Liveness& L = cache ? cache->of(p, f, *calls) : (fresh = compute_liveness(p, f, *calls));
    for (std::size_t b = 0; b < f.blocks.size(); ++b) {
      Block& block = f.blocks[b];
      auto t = candidate(block);
      if (!t || L.live_out[b].has(*t)) continue;
      auto& br = std::get<Branch>(block.term);
      bool constant_first = br.a.is_imm();
      // Seen as `t cmp c`.
      Cmp cmp = constant_first ? swap(br.cmp) : br.cmp;
      int c = (constant_first ? br.a : br.b).value;
      auto r = peel(block, *t, cmp, c);
      if (!r) continue;
      br.cmp = r->cmp;
      br.a = r->tested;
      br.b = Operand::imm(r->constant);
      block.instrs.resize(block.instrs.size() - r->dropped);
    }
  }
}

}  // namespace rcxc::ir
