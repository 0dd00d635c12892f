#include "ir/liveness.h"

#include <algorithm>
#include <iterator>

namespace rcxc::ir {

bool VarSet::has(VarId v) const { return std::binary_search(items.begin(), items.end(), v); }

void VarSet::add(VarId v) {
  auto it = std::lower_bound(items.begin(), items.end(), v);
  if (it == items.end() || *it != v) items.insert(it, v);
}

void VarSet::remove(VarId v) {
  auto it = std::lower_bound(items.begin(), items.end(), v);
  if (it != items.end() && *it == v) items.erase(it);
}

bool VarSet::merge(const VarSet& o) {
  // The data-flow passes merge mostly what is already there (every round
  // after the first): those merges allocate nothing.
  if (o.items.empty() || std::includes(items.begin(), items.end(), o.items.begin(), o.items.end())) return false;
  if (items.empty()) {
    items = o.items;
    return true;
  }
  std::vector<VarId> out;
  out.reserve(items.size() + o.items.size());
  std::set_union(items.begin(), items.end(), o.items.begin(), o.items.end(), std::back_inserter(out));
  bool changed = out.size() != items.size();
  items = std::move(out);
  return changed;
}

FuncId callee_of(const Instr& in) {
  if (in.raw || in.op != rcx::Op::CallSubroutine || in.args.empty()) return -1;
  return in.args[0].kind == Operand::Kind::Func ? in.args[0].value : -1;
}

std::vector<VarSet> function_footprints(const Program& p) {
  std::vector<VarSet> own(p.functions.size(), VarSet(p.vars.size()));
  for (std::size_t f = 0; f < p.functions.size(); ++f)
    for (const auto& b : p.functions[f].blocks) {
      for (const auto& in : b.instrs)
        for (const auto& a : in.args)
          if (a.is_var()) own[f].add(a.value);
      for (VarId v : reads_of(b.term)) own[f].add(v);
    }
  // Follow calls until nothing changes (recursion, if any, terminates too).
  bool changed = true;
  while (changed) {
    changed = false;
    for (std::size_t f = 0; f < p.functions.size(); ++f)
      for (const auto& b : p.functions[f].blocks)
        for (const auto& in : b.instrs) {
          FuncId g = callee_of(in);
          if (g >= 0 && static_cast<std::size_t>(g) != f) changed |= own[f].merge(own[static_cast<std::size_t>(g)]);
        }
  }
  return own;
}

namespace {
bool tracked(const Program& p, VarId v) { return p.vars[static_cast<std::size_t>(v)].kind != VarKind::Global; }
}  // namespace

void step_back(const Program& p, const Instr& in, const CallEffects& calls, VarSet& live) {
  VarUse u = uses_of(in);
  for (VarId v : u.writes)
    if (tracked(p, v)) live.remove(v);
  for (VarId v : u.reads)
    if (tracked(p, v)) live.add(v);
  FuncId g = callee_of(in);
  if (g < 0 || static_cast<std::size_t>(g) >= calls.touches.size()) return;
  for (VarId v : calls.touches[static_cast<std::size_t>(g)].members()) live.remove(v);
  for (VarId v : calls.reads[static_cast<std::size_t>(g)].members()) live.add(v);
}

namespace {

// What one block does to the set live after it, read once per block: the
// set live before it is gen | (after - kill). The data-flow rounds then
// cost a few set operations per block instead of a step per instruction
// (a task's `while (true)` body takes three rounds).
struct BlockEffect {
  VarSet gen;
  VarSet kill;
};

// The steps of step_back, last instruction first, applied to "after"
// without knowing it: removing v kills it (and ungens it), adding v gens it.
BlockEffect block_effect(const Program& p, const Block& b, const CallEffects& calls) {
  BlockEffect e;
  auto remove = [&](VarId v) {
    e.gen.remove(v);
    e.kill.add(v);
  };
  for (VarId v : reads_of(b.term))
    if (tracked(p, v)) e.gen.add(v);
  for (std::size_t k = b.instrs.size(); k-- > 0;) {
    const Instr& in = b.instrs[k];
    VarUse u = uses_of(in);
    for (VarId v : u.writes)
      if (tracked(p, v)) remove(v);
    for (VarId v : u.reads)
      if (tracked(p, v)) e.gen.add(v);
    FuncId g = callee_of(in);
    if (g < 0 || static_cast<std::size_t>(g) >= calls.touches.size()) continue;
    for (VarId v : calls.touches[static_cast<std::size_t>(g)].members()) remove(v);
    for (VarId v : calls.reads[static_cast<std::size_t>(g)].members()) e.gen.add(v);
  }
  return e;
}

// gen | (after - kill) into `live` (its storage reused).
void live_before(const BlockEffect& e, const std::vector<VarId>& after, std::vector<VarId>& live) {
  live.clear();
  auto g = e.gen.items.begin(), k = e.kill.items.begin();
  for (VarId v : after) {
    while (k != e.kill.items.end() && *k < v) ++k;
    if (k != e.kill.items.end() && *k == v) continue;
    while (g != e.gen.items.end() && *g < v) live.push_back(*g++);
    if (g != e.gen.items.end() && *g == v) ++g;
    live.push_back(v);
  }
  live.insert(live.end(), g, e.gen.items.end());
}

}  // namespace

Liveness compute_liveness(const Program& p, const Function& f, const CallEffects& calls) {
  std::size_t n = f.blocks.size();
  Liveness L{std::vector<VarSet>(n, VarSet(p.vars.size())), std::vector<VarSet>(n, VarSet(p.vars.size()))};
  std::vector<BlockEffect> effects;
  std::vector<std::vector<BlockId>> succs;
  effects.reserve(n);
  succs.reserve(n);
  for (const Block& b : f.blocks) {
    effects.push_back(block_effect(p, b, calls));
    succs.push_back(successors(b.term));
    // What the code reads before writing it is read again when the code
    // next runs (the next call of a subroutine, a task started again), so
    // its last value stays live past the exit.
    if (std::holds_alternative<Exit>(b.term)) succs.back().push_back(0);
  }
  // A block whose live-out did not change since it was last visited has
  // the same live-in: only the first visit and changes cost a step.
  std::vector<bool> visited(n, false);
  VarSet out;
  std::vector<VarId> live;
  bool changed = true;
  while (changed) {
    changed = false;
    for (std::size_t i = n; i-- > 0;) {
      out.items.clear();
      for (BlockId s : succs[i]) out.merge(L.live_in[static_cast<std::size_t>(s)]);
      if (visited[i] && out.items == L.live_out[i].items) continue;
      visited[i] = true;
      L.live_out[i].items.assign(out.items.begin(), out.items.end());
      live_before(effects[i], out.items, live);
      // Live-outs only grow from round to round, so live-ins do too: a
      // different size is a change.
      if (live.size() != L.live_in[i].items.size()) {
        L.live_in[i].items.assign(live.begin(), live.end());
        changed = true;
      }
    }
  }
  return L;
}

CallEffects call_effects(const Program& p) {
  CallEffects calls;
  calls.touches = function_footprints(p);
  for (auto& t : calls.touches) {
    VarSet own;
    for (VarId v : t.members())
      if (tracked(p, v)) own.add(v);
    t = std::move(own);
  }
  // What each subroutine reads before writing, found by its own liveness,
  // which depends on its callees': repeated until nothing changes (it only
  // grows, and subroutines are not recursive by the time this runs). Tasks
  // are left out: a task is started, never called, so its own liveness is
  // no call's effect. Every subroutine counts, called now or not: inlining
  // removes a call before it copies the body, and the last copy must keep
  // the same variables as the earlier ones.
  calls.reads.assign(p.functions.size(), VarSet());
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t f = 0; f < p.functions.size(); ++f) {
      if (p.functions[f].blocks.empty() || p.functions[f].kind != FuncKind::Sub) continue;
      Liveness L = compute_liveness(p, p.functions[f], calls);
      changed |= calls.reads[f].merge(L.live_in[0]);
    }
  }
  return calls;
}

}  // namespace rcxc::ir
