// Merging nested constant repeats (see passes.h).
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
BlockId through_empty(const Function& f, BlockId b, std::vector<BlockId>& chain) {
  for (std::size_t hops = 0; hops < f.blocks.size(); ++hops) {
    const Block& here = block(f, b);
    const auto* j = std::get_if<Jump>(&here.term);
    bool loop_block = false;
    for (const auto& r : f.repeats) loop_block |= r.head == b || r.setup == b;
    if (!here.instrs.empty() || j == nullptr || loop_block) return b;
    chain.push_back(b);
    b = j->target;
  }
  return b;
}

std::vector<int> predecessor_edges(const Function& f) {
  std::vector<int> preds(f.blocks.size(), 0);
  for (const auto& b : f.blocks)
    for (BlockId s : successors(b.term)) ++preds[static_cast<std::size_t>(s)];
  return preds;
}

bool single_entry(const std::vector<int>& preds, const std::vector<BlockId>& blocks) {
  for (BlockId b : blocks)
    if (preds[static_cast<std::size_t>(b)] != 1) return false;
  return true;
}

// Merges one outer/inner pair; false when none qualifies.
bool merge_one(Function& f, Log& log) {
  std::vector<int> preds = predecessor_edges(f);
  for (std::size_t i = 0; i < f.repeats.size(); ++i) {
    const Repeat inner = f.repeats[i];
    if (!inner.counter || inner.escapes) continue;
    const Block& inner_setup = block(f, inner.setup);
    auto inner_count = constant_count(inner_setup);
    // The outer body must be the inner loop alone: its setup holds nothing
    // but the loopset, and leaving the inner loop goes straight back to the
    // outer test.
    if (!inner_count || inner_setup.instrs.size() != 1) continue;
    const auto* to_inner = std::get_if<Jump>(&inner_setup.term);
    std::vector<BlockId> chain;
    if (to_inner == nullptr || through_empty(f, to_inner->target, chain) != inner.head) continue;
    const auto* inner_test = std::get_if<LoopTest>(&block(f, inner.head).term);
    if (inner_test == nullptr) continue;
    std::vector<BlockId> exit_chain;
    BlockId outer_head = through_empty(f, inner_test->exit, exit_chain);
    for (std::size_t o = 0; o < f.repeats.size(); ++o) {
      const Repeat outer = f.repeats[o];
      if (o == i || outer.head != outer_head || !outer.counter || outer.escapes) continue;
      const auto* outer_test = std::get_if<LoopTest>(&block(f, outer.head).term);
      auto outer_count = constant_count(block(f, outer.setup));
      const auto* to_outer = std::get_if<Jump>(&block(f, outer.setup).term);
      if (outer_test == nullptr || !outer_count || to_outer == nullptr) continue;
      std::vector<BlockId> body_chain, setup_chain;
      if (through_empty(f, outer_test->body, body_chain) != inner.setup) continue;
      if (through_empty(f, to_outer->target, setup_chain) != outer.head) continue;
      // Nothing else may enter the outer test or the inner setup: only the
      // two loops' own edges (no goto into the middle).
      body_chain.push_back(inner.setup);
      if (!single_entry(preds, body_chain) || !single_entry(preds, exit_chain) || !single_entry(preds, setup_chain) ||
          preds[static_cast<std::size_t>(outer.head)] != 2)
        continue;
      int product = *outer_count * *inner_count;
      if (*outer_count < 1 || *inner_count < 1 || !accepts(rcx::Op::SetLoopCounter, 0, Operand::imm(product)))
        continue;
      // repeat (a) repeat (b) S runs S a*b times, as repeat (a*b) S does:
      // the outer setup counts the product and enters the inner test, whose
      // exit is the outer one. The outer test and inner setup are left
      // unreachable for simplify_cfg to delete.
      Block& setup = f.blocks[static_cast<std::size_t>(outer.setup)];
      setup.instrs.back().args[0] = Operand::imm(product);
      setup.term = Jump{inner.head};
      BlockId after = outer_test->exit;
      std::get<LoopTest>(f.blocks[static_cast<std::size_t>(inner.head)].term).exit = after;
      f.blocks[static_cast<std::size_t>(inner.setup)].instrs.clear();
      f.repeats[i].setup = outer.setup;
      f.repeats[o].setup = f.repeats[o].head;  // dropped with its head
      log.push_back(fmt::format("{}: repeat ({}) of repeat ({}) counts {} in one loop", f.name, *outer_count,
                                *inner_count, product));
      return true;
    }
  }
  return false;
}

}  // namespace

void merge_nested_repeats(Function& f, Log& log) {
  if (f.blocks.empty()) return;  // a subroutine inlined everywhere
  while (merge_one(f, log)) simplify_cfg(f);
}

}  // namespace rcxc::ir
