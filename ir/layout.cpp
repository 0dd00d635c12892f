// Block order that saves jumps (see passes.h).
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// Test-and-branch compares with <=, >=, == or !=; a strict comparison
// works only against a constant (c < x is c+1 <= x).
bool encodable(Cmp c, const Operand& a, const Operand& b) {
  return !((c == Cmp::LT || c == Cmp::GT) && !a.is_imm() && !b.is_imm());
}

// Bytes of the control transfers the layout needs: a jump to a block that
// does not follow, a test whose fall-through is not where it should go.
int transfer_bytes(const Function& f) {
  constexpr int kJump = 2, kTest = 7;
  int bytes = 0;
  for (std::size_t i = 0; i < f.blocks.size(); ++i) {
    auto next = static_cast<BlockId>(i + 1);
    const Terminator& t = f.blocks[i].term;
    if (const auto* j = std::get_if<Jump>(&t)) {
      bytes += j->target != next ? kJump : 0;
    } else if (const auto* br = std::get_if<Branch>(&t)) {
      bool direct = encodable(br->cmp, br->a, br->b), negated = encodable(negate(br->cmp), br->a, br->b);
      bool one_test = (br->otherwise == next && direct) || (br->then == next && negated);
      bytes += kTest + (one_test ? 0 : kJump);
    } else if (const auto* l = std::get_if<LoopTest>(&t)) {
      // The loop counter only branches forward: an exit behind it costs
      // two more jumps.
      bytes += kJump + (l->body != next ? kJump : 0) + (l->exit <= static_cast<BlockId>(i) ? 2 * kJump : 0);
    }
  }
  return bytes;
}

}  // namespace

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
