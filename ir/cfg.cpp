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

// Appends a block to its only predecessor when that one jumps to it, so
// straight-line code (an inline function's body and what follows the
// call) is one block for the passes that work inside blocks.
void merge_straight_lines(Function& f) {
  std::vector<int> preds(f.blocks.size(), 0);
  for (const auto& b : f.blocks)
    for (BlockId s : successors(b.term)) ++preds[static_cast<std::size_t>(s)];
  std::vector<bool> keep(f.blocks.size(), true);
  for (std::size_t a = 0; a < f.blocks.size(); ++a) {
    if (!keep[a]) continue;
    for (;;) {
      const auto* j = std::get_if<Jump>(&f.blocks[a].term);
      if (j == nullptr) break;
      BlockId b = j->target;
      auto bi = static_cast<std::size_t>(b);
      bool head = false;
      for (const auto& r : f.repeats) head |= r.head == b;
      if (b == 0 || bi == a || preds[bi] != 1 || head || !keep[bi]) break;
      Block& from = f.blocks[bi];
      Block& to = f.blocks[a];
      for (auto& in : from.instrs) to.instrs.push_back(std::move(in));
      to.term = from.term;
      from.instrs.clear();
      from.term = Exit{};
      keep[bi] = false;
      for (auto& r : f.repeats)
        if (r.setup == b) r.setup = static_cast<BlockId>(a);
    }
  }
  remove_blocks(f, keep);
}

}  // namespace

void simplify_cfg(Function& f) {
  if (f.blocks.empty()) return;
  thread_jumps(f);
  remove_unreachable(f);
  merge_straight_lines(f);
}

}  // namespace rcxc::ir
