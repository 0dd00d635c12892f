// Control-flow clean-up (see passes.h).
#include <algorithm>
#include <cstdint>
#include <span>

#include "ir/passes.h"
#include "ir/predecessors.h"

namespace rcxc::ir {
namespace {

// Where control really goes when it enters `b`: past empty blocks that
// only jump on (bounded, so a cycle of empty jumps ends).
// `loop_blocks` is repeat_blocks(f).
BlockId final_target(const Function& f, const std::vector<bool>& loop_blocks, BlockId b) {
  for (std::size_t hops = 0; hops < f.blocks.size(); ++hops) {
    const Block& block = f.blocks[static_cast<std::size_t>(b)];
    const auto* j = std::get_if<Jump>(&block.term);
    if (!block.instrs.empty() || j == nullptr || j->target == b || loop_blocks[static_cast<std::size_t>(b)]) return b;
    b = j->target;
  }
  return b;
}

// Reading the random source moves it on: such a test stays, so the
// numbers drawn after it are the ones drawn without optimisation.
bool draws_random(const Branch& br) { return reads_random(br.a) || reads_random(br.b); }

// A branch whose two sides end up at the same place becomes a jump, which
// can make the block before it branch to one place too: an if/else-if
// chain whose bodies all went (their stores were dead) folds from its end.
// Blocks are visited last first, so a chain laid out in order folds in one
// sweep; sweeps repeat while something changes.
void thread_jumps(Function& f) {
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t b = f.blocks.size(); b-- > 0;) {
      Block& block = f.blocks[b];
      const auto* loop = std::get_if<LoopTest>(&block.term);
      for (BlockId s : successors(block.term)) {
        BlockId to = final_target(f, loop_blocks, s);
        // The loop counter only branches forward: an exit threaded back past
        // the test would cost two jumps where the empty block costs one.
        if (loop && s == loop->exit && to <= static_cast<BlockId>(b)) continue;
        retarget(block.term, s, to);
      }
      if (auto* br = std::get_if<Branch>(&block.term); br && br->then == br->otherwise && !draws_random(*br)) {
        block.term = Jump{br->then};
        changed = true;
      }
    }
  }
}

// Appends a block to its only predecessor when that one jumps to it, so
// straight-line code (an inline function's body and what follows the
// call) is one block for the passes that work inside blocks.
void merge_straight_lines(Function& f) {
  std::vector<int> preds = predecessor_counts(f);
  std::vector<bool> keep(f.blocks.size(), true), head(f.blocks.size(), false);
  std::vector<std::vector<std::size_t>> setup_of(f.blocks.size());  // repeats whose setup each block is
  for (std::size_t r = 0; r < f.repeats.size(); ++r) {
    head[static_cast<std::size_t>(f.repeats[r].head)] = true;
    setup_of[static_cast<std::size_t>(f.repeats[r].setup)].push_back(r);
  }
  for (std::size_t a = 0; a < f.blocks.size(); ++a) {
    if (!keep[a]) continue;
    for (;;) {
      const auto* j = std::get_if<Jump>(&f.blocks[a].term);
      if (j == nullptr) break;
      BlockId b = j->target;
      auto bi = static_cast<std::size_t>(b);
      if (b == 0 || bi == a || preds[bi] != 1 || head[bi] || !keep[bi]) break;
      Block& from = f.blocks[bi];
      Block& to = f.blocks[a];
      for (auto& in : from.instrs) to.instrs.push_back(std::move(in));
      to.term = from.term;
      from.instrs.clear();
      from.term = Exit{};
      keep[bi] = false;
      for (std::size_t r : setup_of[bi]) f.repeats[r].setup = static_cast<BlockId>(a);
      setup_of[a].insert(setup_of[a].end(), setup_of[bi].begin(), setup_of[bi].end());
      setup_of[bi].clear();
    }
  }
  remove_blocks(f, keep);
}

// Cross-jumping: when every way into a block is a jump from a block ending
// with the same instruction, that instruction moves into the join (an
// if/else whose branches both end with Wait(t) keeps one Wait).
void merge_tails(Function& f) {
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  const PredecessorLists preds(f, true);  // moving instructions leaves the edges
  for (std::size_t j = 1; j < f.blocks.size(); ++j) {
    auto from = preds[j];
    if (from.size() < 2 || loop_blocks[j]) continue;
    bool all_jumps = true;
    for (BlockId p : from) {
      const Block& pb = f.blocks[static_cast<std::size_t>(p)];
      // Main's startup code stays first in the entry block.
      bool startup_only = p == 0 && static_cast<int>(pb.instrs.size()) <= f.startup;
      all_jumps &= std::holds_alternative<Jump>(pb.term) && p != static_cast<BlockId>(j) &&
                   !loop_blocks[static_cast<std::size_t>(p)] && !startup_only;
    }
    if (!all_jumps) continue;
    for (;;) {
      const Block& first = f.blocks[static_cast<std::size_t>(from[0])];
      if (first.instrs.empty()) break;
      const Instr& tail = first.instrs.back();
      bool same = true;
      for (BlockId p : from) {
        const auto& instrs = f.blocks[static_cast<std::size_t>(p)].instrs;
        same &= !instrs.empty() && same_instr(instrs.back(), tail);
      }
      if (!same) break;
      Instr moved = tail;
      for (BlockId p : from) f.blocks[static_cast<std::size_t>(p)].instrs.pop_back();
      auto& join = f.blocks[j].instrs;
      join.insert(join.begin(), std::move(moved));
    }
  }
}

// Whether sharing the last `length` instructions of `group` empties every
// member but the last one laid out (which falls into the shared copy): an
// emptied member's ways in then go straight to the copy and its jump goes
// too, so no path runs an instruction more and each emptied member saves
// its copy and its jump (`if (max <= ambient) { Off(OUT_A+OUT_C); return; }`
// early in an inline function that also ends with `Off(OUT_A+OUT_C);`
// branches to that end: 6 bytes with the jump over it). Worth it even for
// a 2-byte copy, where a copy kept jumping to the shared one is not.
// An emptied member laid out just before the join fell into it: its ways
// in would need a jump to the copy, so it keeps its own.
bool emptied_into_last(const Function& f, const std::vector<BlockId>& group, std::size_t length, BlockId join) {
  BlockId last = *std::max_element(group.begin(), group.end());
  for (BlockId m : group)
    if (m != last && (f.blocks[static_cast<std::size_t>(m)].instrs.size() != length || m + 1 == join)) return false;
  return true;
}

// Cross-jumping among some of a block's predecessors (merge_tails needs all
// of them): blocks that jump to the same block and end with the same
// instructions keep one copy of those, in a new block that jumps on (three
// `case`s ending `PlaySound(1); Wait(1); break;` share one copy). The new
// block goes right after the last of them, which falls into it, and then
// jumps where that one jumped (or falls there): no jump more. Done when the
// copies saved are worth more than the others' jumps growing long.
void share_tails(Function& f, bool short_ends) {
  const std::vector<bool> loop_blocks = repeat_blocks(f);  // of the blocks before any shared tail
  const std::size_t n = f.blocks.size();
  // The blocks jumping to each block, in block order, all in one array:
  // block j's are jumpers[start[j], start[j + 1]) (a vector per block was
  // an allocation per jump target, every clean-up round).
  std::vector<std::uint32_t> start(n + 1, 0);
  auto jump_target = [&](std::size_t b) -> BlockId {
    const auto* j = std::get_if<Jump>(&f.blocks[b].term);
    if (b == 0 || !j || j->target == static_cast<BlockId>(b) || f.blocks[b].instrs.empty() || loop_blocks[b]) return -1;
    return j->target;
  };
  for (std::size_t b = 1; b < n; ++b)
    if (BlockId t = jump_target(b); t >= 0) ++start[static_cast<std::size_t>(t) + 1];
  for (std::size_t b = 0; b < n; ++b) start[b + 1] += start[b];
  std::vector<BlockId> jumpers(start[n]);
  {
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::size_t b = 1; b < n; ++b)
      if (BlockId t = jump_target(b); t >= 0) jumpers[next[static_cast<std::size_t>(t)]++] = static_cast<BlockId>(b);
  }
  std::vector<BlockId> after(n, -1);  // a shared tail to lay out after the block
  auto last = [&](BlockId b, std::size_t back) -> const Instr& {
    const auto& instrs = f.blocks[static_cast<std::size_t>(b)].instrs;
    return instrs[instrs.size() - 1 - back];
  };
  std::vector<bool> taken;
  std::vector<BlockId> group;
  for (std::size_t j = 0; j < n; ++j) {
    const std::span<const BlockId> from(jumpers.data() + start[j], start[j + 1] - start[j]);
    if (from.size() < 2 || loop_blocks[j]) continue;
    taken.assign(from.size(), false);
    for (std::size_t a = 0; a < from.size(); ++a) {
      // Raw asm may branch by offset: it stays where it was written.
      if (taken[a] || last(from[a], 0).raw) continue;
      group.assign(1, from[a]);
      for (std::size_t c = a + 1; c < from.size(); ++c)
        if (!taken[c] && same_instr(last(from[c], 0), last(from[a], 0))) {
          group.push_back(from[c]);
          taken[c] = true;
        }
      if (group.size() < 2) continue;
      std::size_t length = 1;
      for (bool longer = true; longer; ) {
        for (BlockId m : group) longer &= f.blocks[static_cast<std::size_t>(m)].instrs.size() > length;
        for (BlockId m : group)
          longer = longer && !last(m, length).raw && same_instr(last(m, length), last(group[0], length));
        if (longer) ++length;
      }
      int bytes = 0;
      for (std::size_t k = 0; k < length; ++k) bytes += instr_size(last(group[0], k));
      auto copies = static_cast<int>(group.size());
      bool worth = (copies - 1) * bytes > 2 + copies;
      if (!worth && !(short_ends && emptied_into_last(f, group, length, static_cast<BlockId>(j)))) continue;
      BlockId shared = add_block(f);
      auto& first = f.blocks[static_cast<std::size_t>(group[0])].instrs;
      Block& tail = f.blocks[static_cast<std::size_t>(shared)];
      tail.instrs.assign(first.end() - static_cast<long>(length), first.end());
      tail.term = Jump{static_cast<BlockId>(j)};
      tail.span = f.blocks[static_cast<std::size_t>(group[0])].span;
      for (BlockId m : group) {
        Block& mb = f.blocks[static_cast<std::size_t>(m)];
        mb.instrs.resize(mb.instrs.size() - length);
        mb.term = Jump{shared};
      }
      after[static_cast<std::size_t>(*std::max_element(group.begin(), group.end()))] = shared;
    }
  }
  if (f.blocks.size() == n) return;  // nothing shared
  std::vector<BlockId> order;
  order.reserve(f.blocks.size());
  for (std::size_t b = 0; b < after.size(); ++b) {
    order.push_back(static_cast<BlockId>(b));
    if (after[b] >= 0) order.push_back(after[b]);
  }
  if (order.size() != after.size()) permute_blocks(f, order);
}

}  // namespace

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

std::vector<int> cycle_components(const Function& f) {
  // Tarjan's algorithm with an explicit stack (a long task has thousands
  // of blocks): one walk of every edge.
  const std::size_t n = f.blocks.size();
  std::vector<int> index(n, -1), low(n, 0), component(n, -1);
  std::vector<bool> on_stack(n, false);
  std::vector<BlockId> stack;
  struct Frame {
    BlockId block;
    Successors next;
    std::size_t edge = 0;
  };
  std::vector<Frame> walk;
  int counter = 0, components = 0;
  auto enter = [&](BlockId b) {
    auto u = static_cast<std::size_t>(b);
    index[u] = low[u] = counter++;
    stack.push_back(b);
    on_stack[u] = true;
    walk.push_back({b, successors(f.blocks[u].term)});
  };
  for (std::size_t root = 0; root < n; ++root) {
    if (index[root] >= 0) continue;
    enter(static_cast<BlockId>(root));
    while (!walk.empty()) {
      Frame& top = walk.back();
      auto u = static_cast<std::size_t>(top.block);
      if (top.edge < top.next.size()) {
        auto v = static_cast<std::size_t>(top.next[top.edge++]);
        if (index[v] < 0) enter(static_cast<BlockId>(v));
        else if (on_stack[v]) low[u] = std::min(low[u], index[v]);
        continue;
      }
      if (low[u] == index[u]) {
        for (BlockId w = -1; w != top.block;) {
          w = stack.back();
          stack.pop_back();
          on_stack[static_cast<std::size_t>(w)] = false;
          component[static_cast<std::size_t>(w)] = components;
        }
        ++components;
      }
      walk.pop_back();
      if (!walk.empty()) {
        auto parent = static_cast<std::size_t>(walk.back().block);
        low[parent] = std::min(low[parent], low[u]);
      }
    }
  }
  return component;
}

void simplify_cfg(Function& f, bool share_short_ends) {
  if (f.blocks.empty()) return;
  thread_jumps(f);
  remove_unreachable(f);
  merge_tails(f);
  share_tails(f, share_short_ends);
  // In the last clean-up nothing comes after to send the tests into an
  // emptied branch straight to the shared copy.
  if (share_short_ends) {
    thread_jumps(f);
    remove_unreachable(f);
  }
  merge_straight_lines(f);
}

}  // namespace rcxc::ir
