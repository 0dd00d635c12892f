#include "ir/liveness.h"

#include <algorithm>
#include <array>
#include <bit>
#include <functional>
#include <iterator>
#include <utility>

namespace rcxc::ir {

bool VarSpan::has(VarId v) const { return std::binary_search(items.begin(), items.end(), v); }

bool VarSet::has(VarId v) const { return std::binary_search(items.begin(), items.end(), v); }

void VarSet::add(VarId v) {
  auto it = std::lower_bound(items.begin(), items.end(), v);
  if (it == items.end() || *it != v) items.insert(it, v);
}

void VarSet::remove(VarId v) {
  auto it = std::lower_bound(items.begin(), items.end(), v);
  if (it != items.end() && *it == v) items.erase(it);
}

bool VarSet::merge(VarSpan o) {
  // The data-flow passes merge mostly what is already there (every round
  // after the first): those merges allocate nothing.
  if (o.items.empty() || std::includes(items.begin(), items.end(), o.items.begin(), o.items.end())) return false;
  if (items.empty()) {
    items.assign(o.items.begin(), o.items.end());
    return true;
  }
  std::vector<VarId> out;
  out.reserve(items.size() + o.items.size());
  std::set_union(items.begin(), items.end(), o.items.begin(), o.items.end(), std::back_inserter(out));
  bool changed = out.size() != items.size();
  items = std::move(out);
  return changed;
}

// A counting sort of the entries by block: stable, so each block's
// variables stay in the increasing order they were listed in.
BlockVarSets::BlockVarSets(std::size_t blocks, const std::vector<std::pair<std::uint32_t, VarId>>& entries)
    : start_(blocks + 1, 0), vars_(entries.size()) {
  for (const auto& e : entries) ++start_[e.first + 1];
  for (std::size_t b = 0; b < blocks; ++b) start_[b + 1] += start_[b];
  std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
  for (const auto& e : entries) vars_[next[e.first]++] = e.second;
}

void sort_keys(std::vector<std::uint64_t>& keys, unsigned bits) {
  // Below this, a comparison sort is as quick and needs no second array.
  constexpr std::size_t kComparisonUpTo = 1024;
  // 2 048 counters: they stay in the first-level cache while the keys stream by.
  constexpr unsigned kDigitBits = 11;
  constexpr std::uint64_t kDigitMask = (std::uint64_t{1} << kDigitBits) - 1;
  if (keys.size() <= kComparisonUpTo) {
    std::sort(keys.begin(), keys.end());
    return;
  }
  // Least significant digit first, each pass stable: after the pass of a
  // digit the keys are in order of it and of every digit below it.
  std::vector<std::uint64_t> moved(keys.size());
  std::array<std::size_t, std::size_t{1} << kDigitBits> start{};
  for (unsigned shift = 0; shift < bits; shift += kDigitBits) {
    start.fill(0);
    for (std::uint64_t k : keys) ++start[(k >> shift) & kDigitMask];
    if (start[(keys[0] >> shift) & kDigitMask] == keys.size()) continue;  // one digit for all: no move
    std::size_t sum = 0;
    for (auto& s : start) sum += std::exchange(s, sum);
    for (std::uint64_t k : keys) moved[start[(k >> shift) & kDigitMask]++] = k;
    keys.swap(moved);
  }
}

namespace {

// The footprints of every function, or of the subroutines only (a call
// enters a subroutine, and subroutines call only subroutines, so what a
// call does never needs a task's footprint: the passes that only want
// call effects skip walking the tasks, most of a program).
std::vector<VarSet> footprints(const Program& p, bool subs_only) {
  const std::size_t n = p.functions.size();
  std::vector<VarSet> own(n);
  std::vector<std::vector<FuncId>> callees(n);
  for (std::size_t f = 0; f < n; ++f) {
    if (subs_only && p.functions[f].kind != FuncKind::Sub) continue;
    // Gathered, then sorted once: inserting each in order cost a search
    // per operand.
    std::vector<VarId>& vars = own[f].items;
    for (const auto& b : p.functions[f].blocks) {
      for (const auto& in : b.instrs) {
        for (const auto& a : in.args)
          if (a.is_var()) vars.push_back(a.value);
        FuncId g = callee_of(in);
        if (g >= 0 && static_cast<std::size_t>(g) != f) callees[f].push_back(g);
      }
      for (VarId v : reads_of(b.term)) vars.push_back(v);
    }
    std::sort(vars.begin(), vars.end());
    vars.erase(std::unique(vars.begin(), vars.end()), vars.end());
    std::sort(callees[f].begin(), callees[f].end());
    callees[f].erase(std::unique(callees[f].begin(), callees[f].end()), callees[f].end());
  }
  // Follow calls until nothing changes (recursion, if any, terminates too).
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t f = 0; f < n; ++f)
      for (FuncId g : callees[f]) changed |= own[f].merge(own[static_cast<std::size_t>(g)]);
  }
  return own;
}

}  // namespace

std::vector<VarSet> function_footprints(const Program& p) { return footprints(p, false); }

namespace {
bool tracked(const Program& p, VarId v) { return p.vars[static_cast<std::size_t>(v)].kind != VarKind::Global; }
}  // namespace

namespace {

// step_back's effect on any set-like `live`: what an instruction writes
// (or a call overwrites) is removed, what it reads is added, in that order.
template <class Live>
void step_back_through(const Program& p, const Instr& in, const CallEffects& calls, Live& live) {
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

// A block's effect on liveness as two sets: live-in = gen + (live-out -
// kill). Stepping back through the block builds them the way step_back
// changes a live set.
struct GenKill {
  VarSet gen;   // read before any write in the block
  VarSet kill;  // written (or overwritten by a call) in the block
  void remove(VarId v) {
    gen.remove(v);
    kill.add(v);
  }
  void add(VarId v) { gen.add(v); }
};

// The predecessors of every block, in one array: block b's are
// from[start[b], start[b + 1]).
struct Predecessors {
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> from;
};

// Each exit also counts as an edge to the entry (see compute_liveness).
Predecessors predecessors_of(const Function& f) {
  const std::size_t n = f.blocks.size();
  Predecessors p{std::vector<std::uint32_t>(n + 1, 0), {}};
  auto each_edge = [&](auto&& edge) {
    for (std::size_t i = 0; i < n; ++i) {
      const Terminator& t = f.blocks[i].term;
      for (BlockId s : successors(t)) edge(static_cast<std::size_t>(s), i);
      if (std::holds_alternative<Exit>(t)) edge(0, i);
    }
  };
  each_edge([&](std::size_t to, std::size_t) { ++p.start[to + 1]; });
  for (std::size_t b = 0; b < n; ++b) p.start[b + 1] += p.start[b];
  p.from.resize(p.start[n]);
  std::vector<std::uint32_t> next(p.start.begin(), p.start.end() - 1);
  each_edge([&](std::size_t to, std::size_t from) { p.from[next[to]++] = static_cast<std::uint32_t>(from); });
  return p;
}

}  // namespace

void step_back(const Program& p, const Instr& in, const CallEffects& calls, VarSet& live) {
  step_back_through(p, in, calls, live);
}

// One variable at a time: from the blocks that read it first, backward
// along the edges, through every block that does not write it. Each
// variable is followed only where it is live, so the work is the size of
// the answer. Iterating the equations over all blocks until nothing changes
// took a round per level of loop nesting, each round the whole function:
// 1000 nested loops took minutes.
Liveness compute_liveness(const Program& p, const Function& f, const CallEffects& calls) {
  const std::size_t n = f.blocks.size();
  Liveness L;
  if (n == 0) return L;
  // Each block's summary: what it reads first, as (variable, block) keys
  // to sort by variable, and what it overwrites, one sorted run per block.
  // A key is the variable above the block's index, which takes
  // `block_bits`: sorted, the keys list each variable's blocks in order.
  const auto block_bits = static_cast<unsigned>(std::bit_width(n));
  const std::uint64_t block_mask = (std::uint64_t{1} << block_bits) - 1;
  std::vector<std::uint64_t> first_reads;
  VarId most = 0;
  std::vector<std::uint32_t> kill_start(n + 1, 0);
  std::vector<VarId> kills;
  GenKill e;
  for (std::size_t i = 0; i < n; ++i) {
    const Block& b = f.blocks[i];
    e.gen.items.clear();
    e.kill.items.clear();
    for (VarId v : reads_of(b.term))
      if (tracked(p, v)) e.add(v);
    for (std::size_t k = b.instrs.size(); k-- > 0;) step_back_through(p, b.instrs[k], calls, e);
    for (VarId v : e.gen.members()) first_reads.push_back(static_cast<std::uint64_t>(v) << block_bits | i);
    if (!e.gen.items.empty()) most = std::max(most, e.gen.items.back());
    kills.insert(kills.end(), e.kill.items.begin(), e.kill.items.end());
    kill_start[i + 1] = static_cast<std::uint32_t>(kills.size());
  }
  auto kills_in = [&](std::size_t b, VarId v) {
    return std::binary_search(kills.begin() + kill_start[b], kills.begin() + kill_start[b + 1], v);
  };
  // What the code reads before writing it is read again when the code
  // next runs (the next call of a subroutine, a task started again), so
  // its last value stays live past the exit: an edge from each exit to
  // the entry.
  Predecessors preds = predecessors_of(f);
  // In order of variable, so each block's sets are listed already sorted.
  sort_keys(first_reads, block_bits + static_cast<unsigned>(std::bit_width(static_cast<std::uint32_t>(most))));
  std::vector<std::pair<std::uint32_t, VarId>> ins, outs;  // (block, variable)
  std::vector<VarId> in_stamp(n, -1), out_stamp(n, -1);
  std::vector<std::uint32_t> work;
  for (std::size_t r = 0; r < first_reads.size();) {
    const auto v = static_cast<VarId>(first_reads[r] >> block_bits);
    for (; r < first_reads.size() && static_cast<VarId>(first_reads[r] >> block_bits) == v; ++r) {
      auto b = static_cast<std::uint32_t>(first_reads[r] & block_mask);
      in_stamp[b] = v;
      ins.emplace_back(b, v);
      work.push_back(b);
    }
    while (!work.empty()) {
      std::uint32_t b = work.back();
      work.pop_back();
      for (std::uint32_t k = preds.start[b]; k < preds.start[b + 1]; ++k) {
        std::uint32_t q = preds.from[k];
        if (out_stamp[q] != v) {
          out_stamp[q] = v;
          outs.emplace_back(q, v);
        }
        if (in_stamp[q] == v || kills_in(q, v)) continue;
        in_stamp[q] = v;
        ins.emplace_back(q, v);
        work.push_back(q);
      }
    }
  }
  L.live_in = BlockVarSets(n, ins);
  L.live_out = BlockVarSets(n, outs);
  return L;
}

CallEffects call_effects(const Program& p) {
  CallEffects calls;
  calls.touches = footprints(p, true);
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

namespace {

// Walks everything compute_liveness reads of a function, as numbers, until
// `put` returns false: equal sequences give equal answers (variable kinds,
// the other input, never change once lowering made the variable). Only
// which variables and functions an instruction names counts, not its
// constants: folding rewrites constants without changing any liveness.
template <class Put>
bool each_code_word(const Function& f, Put&& put) {
  auto operand = [](const Operand& o) -> std::int32_t {
    if (o.is_var()) return o.value * 4 + 1;
    if (o.kind == Operand::Kind::Func) return o.value * 4 + 2;
    return 0;
  };
  if (!put(static_cast<std::int32_t>(f.blocks.size()))) return false;
  for (const Block& b : f.blocks) {
    if (!put(static_cast<std::int32_t>(b.instrs.size()))) return false;
    for (const Instr& in : b.instrs) {
      if (!put((static_cast<std::int32_t>(in.op) * 2 + (in.raw ? 1 : 0)) * 256 +
               static_cast<std::int32_t>(in.args.size())))
        return false;
      for (const Operand& a : in.args)
        if (!put(operand(a))) return false;
    }
    if (!put(static_cast<std::int32_t>(b.term.index()))) return false;
    if (const auto* br = std::get_if<Branch>(&b.term))
      if (!put(operand(br->a)) || !put(operand(br->b))) return false;
    for (BlockId s : successors(b.term))
      if (!put(s)) return false;
  }
  return true;
}

bool same_code(const Function& f, const std::vector<std::int32_t>& code) {
  std::size_t i = 0;
  return each_code_word(f, [&](std::int32_t w) { return i < code.size() && code[i++] == w; }) && i == code.size();
}

void encode_code(const Function& f, std::vector<std::int32_t>& out) {
  out.clear();
  each_code_word(f, [&](std::int32_t w) {
    out.push_back(w);
    return true;
  });
}

void encode_effects(const CallEffects& calls, std::vector<std::int32_t>& out) {
  out.clear();
  for (const auto* sets : {&calls.touches, &calls.reads}) {
    out.push_back(static_cast<std::int32_t>(sets->size()));
    for (const VarSet& s : *sets) {
      out.push_back(static_cast<std::int32_t>(s.items.size()));
      out.insert(out.end(), s.items.begin(), s.items.end());
    }
  }
}

}  // namespace

const Liveness& LivenessCache::of(const Program& p, const Function& f, const CallEffects& calls) {
  const Function* first = p.functions.data();
  std::less<const Function*> before;
  if (before(&f, first) || !before(&f, first + p.functions.size())) {
    ++computations_;
    uncached_ = compute_liveness(p, f, calls);
    return uncached_;
  }
  // Another program, or other call effects: nothing kept applies.
  encode_effects(calls, scratch_);
  if (&p != program_ || scratch_ != effects_) {
    entries_.clear();
    effects_.swap(scratch_);
    program_ = &p;
  }
  if (entries_.size() < p.functions.size()) entries_.resize(p.functions.size());
  auto& entry = entries_[static_cast<std::size_t>(&f - first)];
  if (entry && same_code(f, entry->code)) return entry->live;
  if (!entry) entry = std::make_unique<Entry>();
  entry->live = compute_liveness(p, f, calls);
  encode_code(f, entry->code);
  ++computations_;
  return entry->live;
}

}  // namespace rcxc::ir
