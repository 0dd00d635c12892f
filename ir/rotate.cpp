// Loop rotation (see passes.h).
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// A loop test: an empty block that branches into the block laid out right
// after it (the body) or out of the loop.
bool is_loop_test(const Function& f, BlockId h) {
  const Block& b = f.blocks[static_cast<std::size_t>(h)];
  const auto* br = std::get_if<Branch>(&b.term);
  return b.instrs.empty() && br && (br->then == h + 1 || br->otherwise == h + 1);
}

// The last block that jumps back to `h`, when it is laid out after `h`
// and followed by the loop's exit; -1 otherwise.
BlockId rotatable_latch(const Function& f, BlockId h) {
  const auto& br = std::get<Branch>(f.blocks[static_cast<std::size_t>(h)].term);
  BlockId exit = br.then == h + 1 ? br.otherwise : br.then;
  BlockId latch = -1;
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    const auto* j = std::get_if<Jump>(&f.blocks[b].term);
    if (j && j->target == h && static_cast<BlockId>(b) > h) latch = static_cast<BlockId>(b);
  }
  if (latch < 0 || latch + 1 != exit) return -1;
  return latch;
}

// The last block after `h` that jumps back to it; -1 when there is none.
BlockId back_jump_to(const Function& f, BlockId h) {
  BlockId latch = -1;
  for (std::size_t b = static_cast<std::size_t>(h) + 1; b < f.blocks.size(); ++b) {
    const auto* j = std::get_if<Jump>(&f.blocks[b].term);
    if (j && j->target == h) latch = static_cast<BlockId>(b);
  }
  return latch;
}

// Whether a loop counter test in [from, to] has its body or exit on the
// other side of `split`: moving blocks would change which way it branches.
bool counter_crosses(const Function& f, BlockId from, BlockId split, BlockId to) {
  for (BlockId b = from; b <= to; ++b)
    if (const auto* l = std::get_if<LoopTest>(&f.blocks[static_cast<std::size_t>(b)].term))
      for (BlockId t : {l->body, l->exit})
        if ((b < split) != (t < split) || t < from || t > to + 1) return true;
  return false;
}

bool branches_to(const Function& f, BlockId b, BlockId target) {
  const auto* br = std::get_if<Branch>(&f.blocks[static_cast<std::size_t>(b)].term);
  return br && (br->then == target || br->otherwise == target);
}

// A loop whose test spans blocks h..k-1 (`while (a && b)`, a test that
// computes into temporaries): moving the whole test after the latch makes
// the last test branch back to the body. Done when the jump and test bytes
// at the three seams that change add up to fewer.
void rotate_long_test(Function& f, BlockId h, BlockId latch) {
  constexpr BlockId kMaxTestBlocks = 8;
  auto seam = [&](BlockId b, BlockId next) { return transfer_bytes(f, static_cast<std::size_t>(b), next); };
  int best_saving = -1;
  BlockId best_k = -1;
  for (BlockId k = h + 2; k <= latch && k - h <= kMaxTestBlocks; ++k) {
    if (counter_crosses(f, h, k, latch)) continue;
    int before = seam(h - 1, h) + seam(k - 1, k) + seam(latch, latch + 1);
    int after = seam(h - 1, k) + seam(latch, h) + seam(k - 1, latch + 1);
    // At equal bytes the rotated loop still wins when the blocks moved
    // are the test, ending in a branch into the body: the jump in then
    // spans only the body, so it stays near where the other may not.
    int saving = before - after;
    if (saving == 0 && !branches_to(f, k - 1, k)) continue;
    if (saving > best_saving) {
      best_saving = saving;
      best_k = k;
    }
  }
  if (best_k < 0) return;
  std::vector<BlockId> order;
  auto append = [&](BlockId from, BlockId to) {
    for (BlockId b = from; b < to; ++b) order.push_back(b);
  };
  append(0, h);
  append(best_k, latch + 1);
  append(h, best_k);
  append(latch + 1, static_cast<BlockId>(f.blocks.size()));
  permute_blocks(f, order);
}

}  // namespace

void rotate_loops(Function& f) {
  for (BlockId h = 1; h < static_cast<BlockId>(f.blocks.size()); ++h)
    if (BlockId latch = back_jump_to(f, h); latch > h + 1) rotate_long_test(f, h, latch);
  for (BlockId h = 1; h < static_cast<BlockId>(f.blocks.size()); ++h) {
    if (!is_loop_test(f, h)) continue;
    BlockId latch = rotatable_latch(f, h);
    if (latch < 0) continue;
    // After the move the latch falls into the test, the test branches back
    // to the body and falls out of the loop; the way in becomes one jump.
    move_block(f, h, latch);
  }
}

}  // namespace rcxc::ir
