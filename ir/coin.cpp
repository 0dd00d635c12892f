// Coin tosses on the loop counter (see passes.h).
#include <algorithm>

#include <fmt/format.h>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

bool has_raw(const Function& f) {
  for (const auto& b : f.blocks)
    for (const auto& in : b.instrs)
      if (in.raw) return true;
  return false;
}

bool is_random_one(const Operand& o) { return reads_random(o) && o.value == 1; }

// What the toss needs of one function: its counter depths, and whether
// they are known (no jump out of a counter loop, no raw asm).
struct Walked {
  CounterDepths depths;
  bool known = false;
};

// The deepest counter stack each function can start at: 0 for a task, the
// deepest call for a subroutine (only tasks call subroutines by now). -1:
// unknown (a caller's depths are not known).
std::vector<int> entry_depths(const std::vector<Walked>& walked) {
  std::vector<int> entry(walked.size(), 0);
  for (const auto& w : walked)
    for (auto [depth, callee] : w.depths.calls) {
      int& e = entry[static_cast<std::size_t>(callee)];
      if (e >= 0) e = w.known ? std::max(e, depth) : -1;
    }
  return entry;
}

// The side a coin showing `face` takes in `br`, whose operand `coin` is
// the variable holding the toss and the other an immediate.
BlockId side(const Branch& br, VarId coin, int face) {
  int a = br.a.is_var(coin) ? face : br.a.value;
  int b = br.b.is_var(coin) ? face : br.b.value;
  return evaluate(br.cmp, a, b) ? br.then : br.otherwise;
}

// Whether `in` may stand between a draw and the test that becomes its
// toss: what hoist.cpp moves there (a motor command, a sound, arithmetic),
// each an instruction's time. A wait or a task start between would let
// other tasks draw before the toss does, and swap their numbers; a call
// could draw or push a counter. With other tasks, neither may what they
// can see: one polling an output could draw in answer before the toss.
bool may_stand_between(const Instr& in, const std::vector<Var>& vars, bool other_tasks) {
  return is_quick_command(in) && !(other_tasks && seen_by_other_tasks(in, vars));
}

// The index of the block's `set v, Random(1)` that its test may toss
// instead: the last instruction, or followed only by commands that may
// stand between and neither touch v nor draw a number (the toss draws at
// the test).
std::optional<std::size_t> coin_draw(const Block& block, const std::vector<Var>& vars, bool other_tasks) {
  for (std::size_t i = block.instrs.size(); i-- > 0;) {
    const Instr& in = block.instrs[i];
    if (!in.raw && in.op == rcx::Op::SetVariable && in.args[0].is_var() && is_random_one(in.args[1])) {
      VarId coin = in.args[0].value;
      for (std::size_t k = i + 1; k < block.instrs.size(); ++k) {
        const Instr& after = block.instrs[k];
        VarUse use = uses_of(after);
        bool touches = std::find(use.reads.begin(), use.reads.end(), coin) != use.reads.end() ||
                       std::find(use.writes.begin(), use.writes.end(), coin) != use.writes.end();
        if (touches) return std::nullopt;
      }
      return i;
    }
    if (!may_stand_between(in, vars, other_tasks)) return std::nullopt;
    for (const Operand& o : in.args)
      if (reads_random(o)) return std::nullopt;
  }
  return std::nullopt;
}

void toss_in(const Program& p, Function& f, const CounterDepths& d, int entry, const CallEffects& calls, Log& log) {
  Liveness live = compute_liveness(p, f, calls);
  const bool other_tasks = runs_several_tasks(p);
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    Block& block = f.blocks[b];
    const auto* br = std::get_if<Branch>(&block.term);
    if (br == nullptr || block.instrs.empty() || d.at_block[b] < 0) continue;
    auto draw = coin_draw(block, p.vars, other_tasks);
    if (!draw) continue;
    VarId coin = block.instrs[*draw].args[0].value;
    if (shared_between_tasks(p.vars[static_cast<std::size_t>(coin)]) || live.live_out[b].has(coin)) continue;
    bool a_coin = br->a.is_var(coin), b_coin = br->b.is_var(coin);
    if (!((a_coin && br->b.is_imm()) || (b_coin && br->a.is_imm()))) continue;
    int depth = entry + d.at_block[b];
    for (const auto& in : block.instrs)
      if (in.op == rcx::Op::SetLoopCounter) ++depth;
    BlockId zero = side(*br, coin, 0), one = side(*br, coin, 1);
    auto here = static_cast<BlockId>(b);
    if (depth + 1 > kLoopCounters || zero == one || zero <= here || one <= here) continue;
    block.instrs.erase(block.instrs.begin() + static_cast<std::ptrdiff_t>(*draw));
    block.term = CoinToss{zero, one};
    log.push_back(fmt::format("{}: a test of Random(1) is a coin toss on the loop counter", f.name));
  }
}

}  // namespace

void toss_coins_on_loop_counter(Program& p, Log& log) {
  std::vector<Walked> walked(p.functions.size());
  for (std::size_t i = 0; i < p.functions.size(); ++i) {
    const Function& f = p.functions[i];
    if (f.blocks.empty()) continue;
    walked[i].depths = counter_depths(f);
    walked[i].known = walked[i].depths.consistent && !has_raw(f);
  }
  std::vector<int> entry = entry_depths(walked);
  CallEffects calls = call_effects(p);
  for (std::size_t i = 0; i < p.functions.size(); ++i)
    if (walked[i].known && entry[i] >= 0) toss_in(p, p.functions[i], walked[i].depths, entry[i], calls, log);
}

}  // namespace rcxc::ir
