// Choosing between the firmware loop counter and a variable for `repeat`
// (see passes.h).
#include <fmt/format.h>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

bool is_loopset(const Instr& in) { return !in.raw && in.op == rcx::Op::SetLoopCounter; }

void demote_all(Program& p, Function& f) {
  for (std::size_t r = 0; r < f.repeats.size(); ++r)
    if (f.repeats[r].counter) demote_repeat(p, f, r);
}

// Demotes the loops that push past the counter stack (depth > limit).
bool demote_deep(Program& p, Function& f, int limit) {
  CounterDepths d = counter_depths(f);
  for (std::size_t r = 0; r < f.repeats.size(); ++r) {
    const Repeat& rep = f.repeats[r];
    if (!rep.counter) continue;
    int depth = d.at_block[static_cast<std::size_t>(rep.setup)];
    if (depth >= 0 && depth + 1 > limit) {
      demote_repeat(p, f, r);
      return true;
    }
  }
  return false;
}

}  // namespace

CounterDepths counter_depths(const Function& f) {
  CounterDepths d;
  d.at_block.assign(f.blocks.size(), -1);
  if (f.blocks.empty()) return d;
  d.at_block[0] = 0;
  std::vector<BlockId> work{0};
  auto reach = [&](BlockId b, int depth) {
    int& at = d.at_block[static_cast<std::size_t>(b)];
    if (at < 0) {
      at = depth;
      work.push_back(b);
    } else if (at != depth) {
      d.consistent = false;
    }
  };
  while (!work.empty()) {
    BlockId b = work.back();
    work.pop_back();
    const Block& block = f.blocks[static_cast<std::size_t>(b)];
    int depth = d.at_block[static_cast<std::size_t>(b)];
    for (const auto& in : block.instrs) {
      if (is_loopset(in)) d.max = std::max(d.max, ++depth);
      if (FuncId g = callee_of(in); g >= 0) d.calls.emplace_back(depth, g);
    }
    if (const auto* l = std::get_if<LoopTest>(&block.term)) {
      reach(l->body, depth);
      reach(l->exit, depth - 1);
    } else {
      for (BlockId s : successors(block.term)) reach(s, depth);
    }
  }
  return d;
}

void demote_repeat(Program& p, Function& f, std::size_t repeat_index) {
  Repeat& rep = f.repeats[repeat_index];
  rep.counter = false;
  Block& setup = f.blocks[static_cast<std::size_t>(rep.setup)];
  VarId count = p.add_var(fmt::format("repeat{}", repeat_index), VarKind::Temp);
  for (auto& in : setup.instrs)
    if (is_loopset(in)) {
      in.op = rcx::Op::SetVariable;
      in.args = {Operand::var(count), in.args.at(0)};
    }
  auto test = std::get<LoopTest>(f.blocks[static_cast<std::size_t>(rep.head)].term);
  // head: if (count <= 0) goto exit; else { count -= 1; goto body; }
  BlockId step = add_block(f);
  f.blocks[static_cast<std::size_t>(step)].instrs.push_back(
      Instr{rcx::Op::SubtractFromVariable, {Operand::var(count), Operand::imm(1)}});
  f.blocks[static_cast<std::size_t>(step)].term = Jump{test.body};
  f.blocks[static_cast<std::size_t>(rep.head)].term = Branch{Cmp::LE, Operand::var(count), Operand::imm(0), test.exit, step};
  move_block(f, step, rep.head + 1);
}

void assign_loop_counters(Program& p, Log& log) {
  for (auto& f : p.functions) {
    if (f.blocks.empty()) continue;
    for (std::size_t r = 0; r < f.repeats.size(); ++r)
      if (f.repeats[r].counter && f.repeats[r].escapes) demote_repeat(p, f, r);
    if (!counter_depths(f).consistent) demote_all(p, f);
    while (demote_deep(p, f, kLoopCounters)) {
    }
  }
  // A subroutine runs on its caller's counter stack: its own depth plus the
  // depth at any call must fit, else the subroutine counts in variables.
  std::vector<int> max_depth(p.functions.size(), 0);
  for (std::size_t i = 0; i < p.functions.size(); ++i)
    if (!p.functions[i].blocks.empty()) max_depth[i] = counter_depths(p.functions[i]).max;
  for (std::size_t i = 0; i < p.functions.size(); ++i) {
    if (p.functions[i].blocks.empty()) continue;
    for (auto [depth, callee] : counter_depths(p.functions[i]).calls) {
      auto c = static_cast<std::size_t>(callee);
      if (depth + max_depth[c] > kLoopCounters) {
        log.push_back(fmt::format("repeat loops of sub {} count in variables (called {} loops deep from {})",
                                  p.functions[c].name, depth, p.functions[i].name));
        demote_all(p, p.functions[c]);
        max_depth[c] = 0;
      }
    }
  }
  for (const auto& f : p.functions)
    for (const auto& r : f.repeats)
      if (r.counter) log.push_back(fmt::format("{}: repeat uses the firmware loop counter", f.name));
}

}  // namespace rcxc::ir
