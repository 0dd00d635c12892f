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

}  // namespace

void rotate_loops(Function& f) {
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
