// Merging nested constant repeats (see passes.h).
#include <map>

#include <fmt/format.h>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

const Block& block(const Function& f, BlockId b) { return f.blocks[static_cast<std::size_t>(b)]; }

// The loop counter a setup block pushes, when it is a constant.
std::optional<int> constant_count(const Block& setup) {
  if (setup.instrs.empty()) return std::nullopt;
  const Instr& last = setup.instrs.back();
  if (last.raw || last.op != rcx::Op::SetLoopCounter || !last.args.at(0).is_imm()) return std::nullopt;
  return last.args[0].value;
}

// Follows empty blocks that only jump on; `chain` collects them. Stops at
// loop blocks, which keep their identity.
BlockId through_empty(const Function& f, const std::vector<bool>& loop_block, BlockId b, std::vector<BlockId>& chain) {
  for (std::size_t hops = 0; hops < f.blocks.size(); ++hops) {
    const Block& here = block(f, b);
    const auto* j = std::get_if<Jump>(&here.term);
    if (!here.instrs.empty() || j == nullptr || loop_block[static_cast<std::size_t>(b)]) return b;
    chain.push_back(b);
    b = j->target;
  }
  return b;
}

// What the search needs about the function, computed once. A merge leaves
// every count it looks at unchanged: the outer setup's jump replaces the
// inner setup's into the inner test, the inner test's exit replaces the
// outer test's, and the blocks between become unreachable.
struct Shape {
  std::vector<int> preds;         // edges into each block
  std::vector<bool> loop_block;   // a repeat's setup or head
  std::map<BlockId, std::size_t> repeat_at_head;
};

Shape shape_of(const Function& f) {
  Shape s;
  s.preds.assign(f.blocks.size(), 0);
  s.loop_block.assign(f.blocks.size(), false);
  for (const auto& b : f.blocks)
    for (BlockId t : successors(b.term)) ++s.preds[static_cast<std::size_t>(t)];
  for (std::size_t r = 0; r < f.repeats.size(); ++r) {
    s.loop_block[static_cast<std::size_t>(f.repeats[r].setup)] = true;
    s.loop_block[static_cast<std::size_t>(f.repeats[r].head)] = true;
    s.repeat_at_head[f.repeats[r].head] = r;
  }
  return s;
}

bool single_entry(const std::vector<int>& preds, const std::vector<BlockId>& blocks) {
  for (BlockId b : blocks)
    if (preds[static_cast<std::size_t>(b)] != 1) return false;
  return true;
}

// Merges repeat `i` into the repeat around it, if that one holds nothing
// else.
bool merge_into_outer(Function& f, std::size_t i, const Shape& shape, Log& log) {
  const Repeat inner = f.repeats[i];
  if (!inner.counter || inner.escapes) return false;
  const Block& inner_setup = block(f, inner.setup);
  auto inner_count = constant_count(inner_setup);
  // The outer body must be the inner loop alone: its setup holds nothing
  // but the loopset, and leaving the inner loop goes straight back to the
  // outer test.
  if (!inner_count || inner_setup.instrs.size() != 1) return false;
  const auto* to_inner = std::get_if<Jump>(&inner_setup.term);
  std::vector<BlockId> chain, exit_chain, body_chain, setup_chain;
  if (to_inner == nullptr || through_empty(f, shape.loop_block, to_inner->target, chain) != inner.head) return false;
  const auto* inner_test = std::get_if<LoopTest>(&block(f, inner.head).term);
  if (inner_test == nullptr) return false;
  auto at = shape.repeat_at_head.find(through_empty(f, shape.loop_block, inner_test->exit, exit_chain));
  if (at == shape.repeat_at_head.end() || at->second == i) return false;
  std::size_t o = at->second;
  const Repeat outer = f.repeats[o];
  if (!outer.counter || outer.escapes) return false;
  const auto* outer_test = std::get_if<LoopTest>(&block(f, outer.head).term);
  auto outer_count = constant_count(block(f, outer.setup));
  const auto* to_outer = std::get_if<Jump>(&block(f, outer.setup).term);
  if (outer_test == nullptr || !outer_count || to_outer == nullptr) return false;
  if (through_empty(f, shape.loop_block, outer_test->body, body_chain) != inner.setup) return false;
  if (through_empty(f, shape.loop_block, to_outer->target, setup_chain) != outer.head) return false;
  // Nothing else may enter the outer test, the inner setup or the way
  // between the loops: only the two loops' own edges (no goto into the
  // middle).
  body_chain.push_back(inner.setup);
  for (const auto* blocks : {&chain, &exit_chain, &body_chain, &setup_chain})
    if (!single_entry(shape.preds, *blocks)) return false;
  if (shape.preds[static_cast<std::size_t>(outer.head)] != 2) return false;
  int product = *outer_count * *inner_count;
  if (*outer_count < 1 || *inner_count < 1 || !accepts(rcx::Op::SetLoopCounter, 0, Operand::imm(product)))
    return false;
  // repeat (a) repeat (b) S runs S a*b times, as repeat (a*b) S does: the
  // outer setup counts the product and enters the inner test, whose exit
  // is the outer one. The outer test and inner setup are left unreachable
  // for simplify_cfg to delete.
  Block& setup = f.blocks[static_cast<std::size_t>(outer.setup)];
  setup.instrs.back().args[0] = Operand::imm(product);
  setup.term = Jump{inner.head};
  BlockId after = outer_test->exit;
  std::get<LoopTest>(f.blocks[static_cast<std::size_t>(inner.head)].term).exit = after;
  f.blocks[static_cast<std::size_t>(inner.setup)].instrs.clear();
  f.repeats[i].setup = outer.setup;
  f.repeats[o].setup = f.repeats[o].head;  // no loopset: never matches again, dropped with its head
  log.push_back(fmt::format("{}: repeat ({}) of repeat ({}) counts {} in one loop", f.name, *outer_count, *inner_count,
                            product));
  return true;
}

}  // namespace

void merge_nested_repeats(Function& f, Log& log) {
  if (f.blocks.empty()) return;  // a subroutine inlined everywhere
  Shape shape = shape_of(f);
  bool merged = false;
  // Each pass merges every pair it can; a loop three deep needs a second.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < f.repeats.size(); ++i)
      if (merge_into_outer(f, i, shape, log)) changed = merged = true;
  }
  if (merged) simplify_cfg(f);
}

}  // namespace rcxc::ir
