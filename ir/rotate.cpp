// Loop rotation (see passes.h).
#include "ir/passes.h"

#include <algorithm>
#include <vector>

namespace rcxc::ir {
namespace {

constexpr int kMaxTestBlocks = 8;

struct Rotation {
  const Function& f;
  BlockOrder& o;
  std::vector<std::vector<BlockId>> jumps_to;  // per block: blocks ending in a jump to it

  const Terminator& term_at(int p) const {
    return f.blocks[static_cast<std::size_t>(o.order[static_cast<std::size_t>(p)])].term;
  }

  // The positions of the blocks after p that jump back to it, the last
  // first: the loop's own latch, then those of loops that share its test
  // (`while (true) { while (c) ...; ... }` jumps to c from both ends).
  std::vector<int> latches_of(int p) const {
    std::vector<int> latches;
    for (BlockId b : jumps_to[static_cast<std::size_t>(o.order[static_cast<std::size_t>(p)])])
      if (o.position(b) > p) latches.push_back(o.position(b));
    std::sort(latches.rbegin(), latches.rend());
    return latches;
  }

  // Whether a loop counter test in positions [first, last] has its body or
  // exit on the other side of `split`, or outside: moving the blocks would
  // change which way it branches.
  bool counter_crosses(int first, int split, int last) const {
    for (int p = first; p <= last; ++p)
      if (const auto* l = std::get_if<LoopTest>(&term_at(p)))
        for (BlockId t : {l->body, l->exit}) {
          int q = o.position(t);
          if ((p < split) != (q < split) || q < first || q > last + 1) return true;
        }
    return false;
  }

  // Whether the block at p is a loop test: a branch one of whose targets
  // lies after the latch (the way out of the loop).
  bool leaves_loop(int p, int latch) const {
    const auto* br = std::get_if<Branch>(&term_at(p));
    return br && (o.position(br->then) > latch || o.position(br->otherwise) > latch);
  }

  bool branches_into(int p, BlockId target) const {
    const auto* br = std::get_if<Branch>(&term_at(p));
    return br && (br->then == target || br->otherwise == target);
  }

  // The loop at positions [h, latch], whose latch jumps back to h: moves
  // its first blocks [h, k) — the test — after the latch, so the latch
  // falls into the test and the test's last branch goes back to the body.
  // Chosen when the jump and test bytes at the three seams that change
  // add up to fewer; at equal bytes only when the blocks moved are a test
  // ending in a branch into the body (the jump in then spans only the
  // body, so it stays a near jump longer).
  bool rotate(int h, int latch) {
    if (!leaves_loop(h, latch)) return false;
    auto at = [&](int p) { return o.order[static_cast<std::size_t>(p)]; };
    // Tried in this order so that at equal bytes the whole test of a
    // `while (a && b)` moves rather than its first block alone.
    std::vector<int> ends;
    for (int k = h + 2; k <= latch && k - h <= kMaxTestBlocks; ++k) ends.push_back(k);
    ends.push_back(h + 1);
    int best_saving = -1, best_k = -1;
    for (int k : ends) {
      if (counter_crosses(h, k, latch)) continue;
      int before = o.bytes(at(h - 1), at(h)) + o.bytes(at(k - 1), at(k)) + o.bytes(at(latch), o.after(latch));
      int after = o.bytes(at(h - 1), at(k)) + o.bytes(at(latch), at(h)) + o.bytes(at(k - 1), o.after(latch));
      int saving = before - after;
      if (saving == 0 && !branches_into(k - 1, at(k))) continue;
      if (saving > best_saving) {
        best_saving = saving;
        best_k = k;
      }
    }
    if (best_k < 0) return false;
    o.rotate(h, best_k, latch + 1);
    return true;
  }
};

}  // namespace

void rotate_loops(Function& f) {
  BlockOrder o(f);
  Rotation r{f, o, std::vector<std::vector<BlockId>>(f.blocks.size())};
  for (std::size_t b = 0; b < f.blocks.size(); ++b)
    if (const auto* j = std::get_if<Jump>(&f.blocks[b].term))
      r.jumps_to[static_cast<std::size_t>(j->target)].push_back(static_cast<BlockId>(b));
  // A loop sharing its test with an outer one that has no test of its own
  // (`while (true) { while (c) ...; ... }`: both latches jump to c) is
  // rotated on its own latch: its pass runs no jump, the outer latch still
  // jumps to the test, and the test's way out falls into what follows the
  // inner loop as before. Only when the block before the test is on no
  // loop with it, so the jump in that the rotation may add runs once; and
  // never in a subroutine, whose way in runs on each call, maybe from a
  // loop of its caller's, maybe to leave before the loop turns once.
  const std::vector<int> component = cycle_components(f);
  auto on_a_loop_with = [&](int p, int q) {
    return component[static_cast<std::size_t>(o.order[static_cast<std::size_t>(p)])] ==
           component[static_cast<std::size_t>(o.order[static_cast<std::size_t>(q)])];
  };
  for (int h = 1; h < static_cast<int>(f.blocks.size()); ++h) {
    std::vector<int> latches = r.latches_of(h);
    if (latches.empty() || r.rotate(h, latches[0])) continue;
    if (f.kind != FuncKind::Task || r.leaves_loop(h, latches[0]) || on_a_loop_with(h - 1, h)) continue;
    for (std::size_t i = 1; i < latches.size(); ++i)
      if (r.rotate(h, latches[i])) break;
  }
  o.apply(f);
}

}  // namespace rcxc::ir
