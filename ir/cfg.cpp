// Control-flow clean-up (see passes.h).
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

bool is_repeat_block(const Function& f, BlockId b) {
  for (const auto& r : f.repeats)
    if (r.head == b || r.setup == b) return true;
  return false;
}

// Where control really goes when it enters `b`: past empty blocks that
// only jump on (bounded, so a cycle of empty jumps ends).
BlockId final_target(const Function& f, BlockId b) {
  for (std::size_t hops = 0; hops < f.blocks.size(); ++hops) {
    const Block& block = f.blocks[static_cast<std::size_t>(b)];
    const auto* j = std::get_if<Jump>(&block.term);
    if (!block.instrs.empty() || j == nullptr || j->target == b || is_repeat_block(f, b)) return b;
    b = j->target;
  }
  return b;
}

void thread_jumps(Function& f) {
  for (auto& block : f.blocks) {
    for (BlockId s : successors(block.term)) retarget(block.term, s, final_target(f, s));
    if (auto* br = std::get_if<Branch>(&block.term); br && br->then == br->otherwise)
      block.term = Jump{br->then};
  }
}

void remove_unreachable(Function& f) {
  std::vector<bool> seen(f.blocks.size(), false);
  std::vector<BlockId> work{0};
  seen[0] = true;
  while (!work.empty()) {
    BlockId b = work.back();
    work.pop_back();
    for (BlockId s : successors(f.blocks[static_cast<std::size_t>(b)].term))
      if (!seen[static_cast<std::size_t>(s)]) {
        seen[static_cast<std::size_t>(s)] = true;
        work.push_back(s);
      }
  }
  remove_blocks(f, seen);
}

}  // namespace

void simplify_cfg(Function& f) {
  if (f.blocks.empty()) return;
  thread_jumps(f);
  remove_unreachable(f);
}

}  // namespace rcxc::ir
