// Choosing between the firmware loop counter and a variable for `repeat`
// (see passes.h).
#include <fmt/format.h>

#include <algorithm>
#include <optional>

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

// Whether f may leave counters pushed: a task that no instruction starts
// (main, which the Run button starts), so it starts each run with an empty
// counter stack and nothing below its own, with no raw asm (which may push
// or pop counters the walk cannot see).
bool may_leave_counters_pushed(const Program& p, const Function& f, FuncId id) {
  if (f.kind != FuncKind::Task) return false;
  for (const auto& g : p.functions)
    for (const auto& b : g.blocks)
      for (const auto& in : b.instrs) {
        if (in.raw && &g == &f) return false;
        if (in.op != rcx::Op::StartTask) continue;
        for (const auto& a : in.args)
          if (a.kind != Operand::Kind::Func || a.value == id) return false;  // by number, or f
      }
  return true;
}

// The counter stack where a jump out of counter loops leaves their
// counters pushed: the counters of the loops still running (which loop
// pushed each), and below them counters no loop test will read again.
struct CounterStack {
  std::vector<int> live;
  int left = 0;
  int height() const { return static_cast<int>(live.size()) + left; }
  friend bool operator==(const CounterStack&, const CounterStack&) = default;
};

// counter_depths for a function whose counter loops may be left by a jump
// (std::nullopt where that is unsafe): every loop test must find its own
// loop's counter on top, and the stack never holds more than the
// firmware's four. Where two ways into a block differ in the loops they
// have running, none is running there (all of it is left), so a loop test
// there needing one fails the walk: a jump out of an inner loop into the
// body of an outer one leaves the inner counter where the outer test
// reads. A jump out that can come round again (inside any loop) leaves a
// counter each time, and the walk fails once they pass four.
std::optional<CounterDepths> counter_depths_leaving_counters(const Function& f) {
  std::vector<int> setup_of(f.blocks.size(), -1), head_of(f.blocks.size(), -1);
  for (std::size_t r = 0; r < f.repeats.size(); ++r)
    if (f.repeats[r].counter) {
      setup_of[static_cast<std::size_t>(f.repeats[r].setup)] = static_cast<int>(r);
      head_of[static_cast<std::size_t>(f.repeats[r].head)] = static_cast<int>(r);
    }
  std::vector<std::optional<CounterStack>> at(f.blocks.size());
  std::vector<BlockId> work;
  bool ok = true;
  auto reach = [&](BlockId b, const CounterStack& s) {
    auto& here = at[static_cast<std::size_t>(b)];
    CounterStack merged = s;
    if (here) {
      if (here->live == s.live) {
        merged.left = std::max(here->left, s.left);
      } else {
        merged.live.clear();
        merged.left = std::max(here->height(), s.height());
      }
      if (merged == *here) return;
    }
    if (merged.height() > kLoopCounters) ok = false;
    here = merged;
    work.push_back(b);
  };
  reach(0, {});
  CounterDepths d;
  while (!work.empty() && ok) {
    BlockId b = work.back();
    work.pop_back();
    const Block& block = f.blocks[static_cast<std::size_t>(b)];
    CounterStack s = *at[static_cast<std::size_t>(b)];
    for (std::size_t i = 0; i < block.instrs.size(); ++i) {
      const Instr& in = block.instrs[i];
      if (in.raw) ok = false;
      if (is_loopset(in)) {
        bool known = i + 1 == block.instrs.size() && setup_of[static_cast<std::size_t>(b)] >= 0;
        s.live.push_back(known ? setup_of[static_cast<std::size_t>(b)] : -1);
        if (s.height() > kLoopCounters) ok = false;
      }
    }
    if (const auto* l = std::get_if<LoopTest>(&block.term)) {
      int mine = head_of[static_cast<std::size_t>(b)];
      if (mine < 0 || s.live.empty() || s.live.back() != mine) {
        ok = false;
        break;
      }
      reach(l->body, s);
      s.live.pop_back();
      reach(l->exit, s);
    } else if (std::holds_alternative<CoinToss>(block.term)) {
      ok = false;
    } else {
      for (BlockId next : successors(block.term)) reach(next, s);
    }
  }
  if (!ok) return std::nullopt;
  // What the other passes and the subroutine check read: the height at
  // each block's start and at each call, counters left included.
  d.at_block.assign(f.blocks.size(), -1);
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    if (!at[b]) continue;
    CounterStack s = *at[b];
    d.at_block[b] = s.height();
    d.max = std::max(d.max, s.height());
    for (const auto& in : f.blocks[b].instrs) {
      if (is_loopset(in)) d.max = std::max(d.max, ++s.left);
      if (FuncId g = callee_of(in); g >= 0) d.calls.emplace_back(s.height(), g);
    }
  }
  return d;
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
  // The depths of the tasks that keep counters a jump leaves pushed.
  std::vector<std::optional<CounterDepths>> leaving(p.functions.size());
  for (std::size_t i = 0; i < p.functions.size(); ++i) {
    Function& f = p.functions[i];
    if (f.blocks.empty()) continue;
    bool escaping = std::any_of(f.repeats.begin(), f.repeats.end(), [](const Repeat& r) { return r.counter && r.escapes; });
    if (escaping && may_leave_counters_pushed(p, f, static_cast<FuncId>(i)))
      leaving[i] = counter_depths_leaving_counters(f);
    if (leaving[i]) {
      log.push_back(fmt::format("{}: a jump out of a repeat leaves its counter pushed (no loop test reads it again)",
                                f.name));
      continue;
    }
    for (std::size_t r = 0; r < f.repeats.size(); ++r)
      if (f.repeats[r].counter && f.repeats[r].escapes) demote_repeat(p, f, r);
    if (!counter_depths(f).consistent) demote_all(p, f);
    while (demote_deep(p, f, kLoopCounters)) {
    }
  }
  auto depths = [&](std::size_t i) { return leaving[i] ? *leaving[i] : counter_depths(p.functions[i]); };
  // A subroutine runs on its caller's counter stack: its own depth plus the
  // depth at any call must fit, else the subroutine counts in variables.
  std::vector<int> max_depth(p.functions.size(), 0);
  for (std::size_t i = 0; i < p.functions.size(); ++i)
    if (!p.functions[i].blocks.empty()) max_depth[i] = depths(i).max;
  for (std::size_t i = 0; i < p.functions.size(); ++i) {
    if (p.functions[i].blocks.empty()) continue;
    for (auto [depth, callee] : depths(i).calls) {
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
