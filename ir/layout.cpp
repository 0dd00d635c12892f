// Block order that saves jumps (see passes.h).
#include "ir/passes.h"

#include <algorithm>

namespace rcxc::ir {

BlockOrder::BlockOrder(const Function& fn) : f(fn), order(fn.blocks.size()), pos(fn.blocks.size()) {
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = pos[i] = static_cast<BlockId>(i);
}

BlockId BlockOrder::after(int p) const {
  auto next = static_cast<std::size_t>(p) + 1;
  return next < order.size() ? order[next] : static_cast<BlockId>(order.size());
}

int BlockOrder::bytes(BlockId b, BlockId next) const {
  constexpr int kJump = 2, kTest = 7;
  const Terminator& t = f.blocks[static_cast<std::size_t>(b)].term;
  if (const auto* j = std::get_if<Jump>(&t)) return j->target != next ? kJump : 0;
  if (const auto* br = std::get_if<Branch>(&t)) {
    bool direct = branches_directly(br->cmp, br->a, br->b), negated = branches_directly(negate(br->cmp), br->a, br->b);
    bool one_test = (br->otherwise == next && direct) || (br->then == next && negated);
    return kTest + (one_test ? 0 : kJump);
  }
  if (const auto* l = std::get_if<LoopTest>(&t)) {
    // The loop counter only branches forward: an exit behind it costs
    // two more jumps.
    bool behind = position(l->exit) <= position(b);
    return kJump + (l->body != next ? kJump : 0) + (behind ? 2 * kJump : 0);
  }
  if (const auto* c = std::get_if<CoinToss>(&t)) {
    // loopset and two loop tests; a side behind them needs a jump.
    int behind = (position(c->zero) <= position(b)) + (position(c->one) <= position(b));
    return 3 + 2 * kJump + behind * kJump;
  }
  // An exit anywhere but last returns (1 byte) or jumps to the end.
  if (next == static_cast<BlockId>(order.size())) return 0;
  return f.kind == FuncKind::Sub ? 1 : kJump;
}

int BlockOrder::total() const {
  int sum = 0;
  for (std::size_t p = 0; p < order.size(); ++p) sum += bytes(order[p], after(static_cast<int>(p)));
  return sum;
}

int code_bytes(const Function& f) {
  int sum = BlockOrder(f).total();
  for (const Block& b : f.blocks)
    for (const Instr& in : b.instrs) sum += instr_size(in);
  return sum;
}

void BlockOrder::rotate(int first, int middle, int last) {
  std::rotate(order.begin() + first, order.begin() + middle, order.begin() + last);
  for (int p = first; p < last; ++p) pos[static_cast<std::size_t>(order[static_cast<std::size_t>(p)])] = p;
}

void BlockOrder::apply(Function& fn) const {
  for (std::size_t p = 0; p < order.size(); ++p)
    if (order[p] != static_cast<BlockId>(p)) return permute_blocks(fn, order);
}

void place_branch_targets(Function& f) {
  BlockOrder o(f);
  for (int p = 0; p + 1 < static_cast<int>(f.blocks.size()); ++p) {
    const auto* br = std::get_if<Branch>(&f.blocks[static_cast<std::size_t>(o.order[static_cast<std::size_t>(p)])].term);
    if (br == nullptr) continue;
    // Only the direct test exists, yet the block after is where it goes
    // when true: the false side must follow instead, or a jump is needed.
    BlockId here = o.order[static_cast<std::size_t>(p)], then = o.after(p), side = br->otherwise;
    int x = o.position(side);
    if (br->then != then || branches_directly(negate(br->cmp), br->a, br->b) || x <= p + 1) continue;
    // Loop counters between would change direction: leave those alone.
    bool counter = std::holds_alternative<LoopTest>(f.blocks[static_cast<std::size_t>(side)].term);
    for (int q = p + 1; q < x && !counter; ++q) {
      const auto* l = std::get_if<LoopTest>(&f.blocks[static_cast<std::size_t>(o.order[static_cast<std::size_t>(q)])].term);
      counter = l && l->exit == side;
    }
    if (counter) continue;
    BlockId before_side = o.order[static_cast<std::size_t>(x - 1)], after_side = o.after(x);
    int before = o.bytes(here, then) + o.bytes(before_side, side) + o.bytes(side, after_side);
    int after = o.bytes(here, side) + o.bytes(side, then) + o.bytes(before_side, after_side);
    if (after < before) o.rotate(p + 1, x, x + 1);
  }
  o.apply(f);
}

namespace {

// Whether block b only jumps to `next`: it must stay right before it.
bool jumps_to(const Function& f, BlockId b, BlockId next) {
  const auto* j = std::get_if<Jump>(&f.blocks[static_cast<std::size_t>(b)].term);
  return j && j->target == next;
}

// Exits tried per function: each try costs a pass over the blocks.
constexpr int kExitTries = 64;

}  // namespace

void place_exit_last(Function& f) {
  BlockOrder o(f);
  auto n = static_cast<int>(f.blocks.size());
  int tries = 0;
  for (int p = 1; p + 1 < n && tries < kExitTries; ++p) {
    if (!std::holds_alternative<Exit>(f.blocks[static_cast<std::size_t>(o.order[static_cast<std::size_t>(p)])].term)) continue;
    // The exit moves with the blocks that only jump into it.
    int s = p;
    while (s > 0 && jumps_to(f, o.order[static_cast<std::size_t>(s - 1)], o.order[static_cast<std::size_t>(s)])) --s;
    if (s == 0) continue;
    ++tries;
    int before = o.total();
    o.rotate(s, p + 1, n);
    if (o.total() < before) return o.apply(f);
    o.rotate(s, n - (p + 1 - s), n);
  }
}

}  // namespace rcxc::ir
