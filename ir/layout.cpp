// Block order that saves jumps (see passes.h).
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// Test-and-branch compares with <=, >=, == or !=; a strict comparison
// works only against a constant (c < x is c+1 <= x).
bool encodable(Cmp c, const Operand& a, const Operand& b) {
  return !((c == Cmp::LT || c == Cmp::GT) && !a.is_imm() && !b.is_imm());
}

}  // namespace

int transfer_bytes(const Function& f, std::size_t b, BlockId next) {
  constexpr int kJump = 2, kTest = 7;
  const Terminator& t = f.blocks[b].term;
  if (const auto* j = std::get_if<Jump>(&t)) return j->target != next ? kJump : 0;
  if (const auto* br = std::get_if<Branch>(&t)) {
    bool direct = encodable(br->cmp, br->a, br->b), negated = encodable(negate(br->cmp), br->a, br->b);
    bool one_test = (br->otherwise == next && direct) || (br->then == next && negated);
    return kTest + (one_test ? 0 : kJump);
  }
  if (const auto* l = std::get_if<LoopTest>(&t)) {
    // The loop counter only branches forward: an exit behind it costs
    // two more jumps.
    return kJump + (l->body != next ? kJump : 0) + (l->exit <= static_cast<BlockId>(b) ? 2 * kJump : 0);
  }
  // An exit anywhere but last returns (1 byte) or jumps to the end.
  if (next == static_cast<BlockId>(f.blocks.size())) return 0;
  return f.kind == FuncKind::Sub ? 1 : kJump;
}

int transfer_bytes(const Function& f) {
  int bytes = 0;
  for (std::size_t i = 0; i < f.blocks.size(); ++i) bytes += transfer_bytes(f, i, static_cast<BlockId>(i + 1));
  return bytes;
}


void place_branch_targets(Function& f) {
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    const auto* br = std::get_if<Branch>(&f.blocks[b].term);
    if (br == nullptr) continue;
    auto here = static_cast<BlockId>(b);
    // Only the direct test exists, yet the block after is where it goes
    // when true: the false side must follow instead, or a jump is needed.
    if (br->then != here + 1 || encodable(negate(br->cmp), br->a, br->b) || br->otherwise <= here + 1) continue;
    Function moved = f;
    move_block(moved, br->otherwise, here + 1);
    if (transfer_bytes(moved) < transfer_bytes(f)) f = std::move(moved);
  }
}

}  // namespace rcxc::ir
