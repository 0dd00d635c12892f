// Dead store removal (see passes.h).
#include <algorithm>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

bool draws_random(const Instr& in) { return std::any_of(in.args.begin(), in.args.end(), reads_random); }

// Instructions whose only effect is the value they leave in a variable. A
// read of the random source also moves it on: dropping an unused
// `t = Random(10)` would change every later draw, and with it what a run
// with a given seed does (against -O0, or nqc's code in `rcxc compare`).
bool pure_variable_write(const Instr& in) { return !in.raw && !draws_random(in) && computes_into_variable(in.op); }

bool remove_in(const Program& p, Function& f, const CallEffects& calls, LivenessCache& cache) {
  const Liveness& L = cache.of(p, f, calls);
  bool removed = false;
  VarSet live;
  std::vector<bool> keep;
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    Block& block = f.blocks[b];
    live.items.assign(L.live_out[b].items.begin(), L.live_out[b].items.end());
    for (VarId v : reads_of(block.term))
      if (p.vars[static_cast<std::size_t>(v)].kind != VarKind::Global) live.add(v);
    keep.assign(block.instrs.size(), true);
    bool removed_here = false;
    for (std::size_t k = block.instrs.size(); k-- > 0;) {
      const Instr& in = block.instrs[k];
      if (pure_variable_write(in)) {
        VarId dest = in.args[0].value;
        if (p.vars[static_cast<std::size_t>(dest)].kind != VarKind::Global && !live.has(dest)) {
          keep[k] = false;
          removed_here = true;
          continue;
        }
      }
      step_back(p, in, calls, live);
    }
    if (!removed_here) continue;
    removed = true;
    std::size_t kept = 0;
    for (std::size_t k = 0; k < block.instrs.size(); ++k) {
      if (!keep[k]) continue;
      if (kept != k) block.instrs[kept] = std::move(block.instrs[k]);  // never onto itself: that empties it
      ++kept;
    }
    block.instrs.erase(block.instrs.begin() + static_cast<long>(kept), block.instrs.end());
  }
  return removed;
}

}  // namespace

void remove_dead_stores(Program& p, LivenessCache* cache) {
  LivenessCache own;
  LivenessCache& live = cache ? *cache : own;
  // Removing one store can make the stores feeding it dead: repeated, per
  // function, until nothing goes. Subroutines first: a call's effect on
  // its caller is what the subroutine reads and writes, so the callers
  // are done with the subroutines' final effects.
  constexpr int kRounds = 8;
  auto settle = [&](FuncKind kind, const CallEffects& calls) {
    bool any = false;
    for (auto& f : p.functions)
      if (f.kind == kind && !f.blocks.empty())
        for (int round = 0; round < kRounds && remove_in(p, f, calls, live); ++round) any = true;
    return any;
  };
  auto calls = call_effects(p);
  if (settle(FuncKind::Sub, calls)) calls = call_effects(p);
  settle(FuncKind::Task, calls);
}

}  // namespace rcxc::ir
