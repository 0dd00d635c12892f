// Constant propagation and folding (see passes.h).
#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cstdint>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// What is known at a point: the variables holding a known constant (sorted
// by VarId; any variable not listed may hold anything), or nothing yet for
// a block no path has reached.
struct State {
  bool reached = false;
  std::vector<std::pair<VarId, int>> consts;

  std::optional<int> get(VarId v) const {
    auto it = std::lower_bound(consts.begin(), consts.end(), std::pair<VarId, int>{v, INT32_MIN});
    if (it != consts.end() && it->first == v) return it->second;
    return std::nullopt;
  }
  void vary(VarId v) {
    auto it = std::lower_bound(consts.begin(), consts.end(), std::pair<VarId, int>{v, INT32_MIN});
    if (it != consts.end() && it->first == v) consts.erase(it);
  }
  void set(VarId v, int c) {
    auto it = std::lower_bound(consts.begin(), consts.end(), std::pair<VarId, int>{v, INT32_MIN});
    if (it != consts.end() && it->first == v)
      it->second = c;
    else
      consts.insert(it, {v, c});
  }
};

// What is known on entry to each block, all in one array: a block's
// constants are one run of `pool`, written when a path first reaches the
// block and only shortened after (a meet only drops entries), so a long
// function's states cost one allocation, not one per block.
struct EntryStates {
  std::vector<std::pair<VarId, int>> pool;
  std::vector<std::uint32_t> start, size;  // per block: its run of `pool`
  std::vector<bool> reached;

  explicit EntryStates(std::size_t blocks) : start(blocks, 0), size(blocks, 0), reached(blocks, false) {}

  void copy_to(std::size_t b, State& s) const {
    s.reached = reached[b];
    s.consts.assign(pool.begin() + start[b], pool.begin() + start[b] + size[b]);
  }

  // Merges into block b's state what arrives along one more edge, `s`
  // restricted to the variables in `live` (a constant nobody reads again is
  // no use, and keeping them all would make the states of a long program,
  // every inline copy's parameters, grow with its length). Returns whether
  // b's state changed.
  bool meet(std::size_t b, const State& s, VarSpan live) {
    if (!reached[b]) {
      reached[b] = true;
      start[b] = static_cast<std::uint32_t>(pool.size());
      for (const auto& entry : s.consts)
        if (live.has(entry.first)) pool.push_back(entry);
      size[b] = static_cast<std::uint32_t>(pool.size() - start[b]);
      return true;
    }
    // The run holds only variables of `live` already (it was built here):
    // keep those `s` agrees with, in order, in place.
    auto first = pool.begin() + start[b];
    auto last = std::remove_if(first, first + size[b], [&](const std::pair<VarId, int>& entry) {
      auto other = s.get(entry.first);
      return !other || *other != entry.second;
    });
    auto kept = static_cast<std::uint32_t>(last - first);
    bool changed = kept != size[b];
    size[b] = kept;
    return changed;
  }
};

// Per opcode, whether any of its operand slots is a variable it writes:
// an instruction of another opcode leaves every constant as it was, and
// folding asks about every instruction twice.
std::array<bool, rcx::kOpcodeCount> opcodes_writing() {
  std::array<bool, rcx::kOpcodeCount> writes{};
  for (std::size_t i = 0; i < rcx::kOpcodeCount; ++i)
    for (const rcx::Operand* o : operand_slots(static_cast<rcx::Op>(i)))
      writes[i] = writes[i] || o->role == rcx::Role::Variable;
  return writes;
}

struct Folder {
  const Program& p;
  // What each function may write of the private variables (CallEffects's
  // touches): a call makes those unknown.
  const std::vector<VarSet>& footprints;
  std::array<bool, rcx::kOpcodeCount> writing = opcodes_writing();

  bool private_var(VarId v) const { return !shared_between_tasks(p.vars[static_cast<std::size_t>(v)]); }

  std::optional<int> known(const State& s, const Operand& o) const {
    if (o.is_imm()) return o.value;
    if (o.is_var() && private_var(o.value)) return s.get(o.value);
    return std::nullopt;
  }

  void vary(State& s, VarId v) const { s.vary(v); }

  // The constant `in` leaves in `dest` (its private destination), given
  // the state before it; nullopt when not known.
  std::optional<int> folded(const Instr& in, const State& s) const {
    std::optional<int> result;
    if (in.args.size() == 2) {
      auto src = known(s, in.args[1]);
      auto old = known(s, in.args[0]);
      if (src && (old || in.op == rcx::Op::SetVariable || in.op == rcx::Op::AbsoluteValue ||
                  in.op == rcx::Op::SignVariable))
        result = arithmetic(in.op, old.value_or(0), *src);
      // x*0 and x&0 are 0 whatever x was.
      if (src && *src == 0 && (in.op == rcx::Op::MultiplyVariable || in.op == rcx::Op::AndVariable)) result = 0;
    }
    return result;
  }

  // The effect of one instruction on the state.
  void transfer(const Instr& in, State& s) const {
    FuncId g = callee_of(in);
    if (g >= 0)
      for (VarId v : footprints[static_cast<std::size_t>(g)].members()) vary(s, v);
    if (in.raw) {
      for (const auto& a : in.args)
        if (a.is_var()) vary(s, a.value);
      return;
    }
    if (!writing[static_cast<std::size_t>(in.op)]) return;
    VarUse u = uses_of(in);
    if (u.writes.empty()) return;
    VarId dest = u.writes.front();
    if (!private_var(dest)) return;
    if (auto result = folded(in, s))
      s.set(dest, *result);
    else
      s.vary(dest);
  }

  // Rewrites `in` given the state before it; returns false to delete it.
  bool rewrite(Instr& in, const State& s) const {
    if (in.raw) return true;
    auto slots = operand_slots(in.op);
    for (std::size_t i = 0; i < in.args.size() && i < slots.size(); ++i) {
      if (slots[i]->role == rcx::Role::Variable) continue;
      auto c = known(s, in.args[i]);
      if (c && !in.args[i].is_imm() && accepts(in.op, i, Operand::imm(*c))) in.args[i] = Operand::imm(*c);
    }
    if (in.args.size() != 2 || slots.empty() || slots[0]->role != rcx::Role::Variable) return true;
    const Operand& dest = in.args[0];
    const Operand& src = in.args[1];
    if (in.op == rcx::Op::SetVariable && src == dest) return false;
    if (src.is_imm()) {
      int v = src.value;
      switch (in.op) {
        case rcx::Op::AddToVariable:
        case rcx::Op::SubtractFromVariable:
        case rcx::Op::OrVariable: if (v == 0) return false; break;
        case rcx::Op::MultiplyVariable:
        case rcx::Op::DivideVariable: if (v == 1) return false; break;
        case rcx::Op::AndVariable: if (v == -1) return false; break;
        default: break;
      }
    }
    // An arithmetic step whose result is known becomes a plain set: same
    // size, and the steps before it may then be dead.
    if (dest.is_var() && private_var(dest.value) && in.op != rcx::Op::SetVariable) {
      if (auto c = folded(in, s)) {
        in.op = rcx::Op::SetVariable;
        in.args[1] = Operand::imm(*c);
      }
    }
    return true;
  }
};

void fold_function(const Program& p, Function& f, const CallEffects& calls, LivenessCache& cache) {
  Folder folder{p, calls.touches};
  const Liveness& live = cache.of(p, f, calls);
  std::size_t n = f.blocks.size();
  EntryStates in(n);
  in.reached[0] = true;
  // Blocks wait in reverse postorder, so a join is visited once all the
  // paths into it are (a sequence of if/else statements costs one visit
  // per block, not one per path through the ones before).
  std::vector<int> order = reverse_postorder_index(f);
  std::vector<BlockId> block_at(n, 0);  // the block at each place of that order
  for (std::size_t b = 0; b < n; ++b)
    if (order[b] >= 0) block_at[static_cast<std::size_t>(order[b])] = static_cast<BlockId>(b);
  // The waiting blocks as one bit per place in that order, the lowest
  // taken first: what a min-heap of (place, block) pairs did, without its
  // comparisons at every level of every push and pop (a fifth of folding
  // on long functions).
  std::vector<std::uint64_t> waiting((n + 63) / 64, 0);
  std::size_t word = 0;  // no block waits in a word below this one
  auto wait = [&](BlockId b) {
    auto place = static_cast<std::size_t>(order[static_cast<std::size_t>(b)]);
    waiting[place / 64] |= std::uint64_t{1} << (place % 64);
    word = std::min(word, place / 64);
  };
  wait(0);
  State s;  // reused: assigning keeps its capacity
  for (;;) {
    while (word < waiting.size() && waiting[word] == 0) ++word;
    if (word == waiting.size()) break;
    std::size_t place = word * 64 + static_cast<std::size_t>(std::countr_zero(waiting[word]));
    waiting[word] &= waiting[word] - 1;
    BlockId b = block_at[place];
    in.copy_to(static_cast<std::size_t>(b), s);
    for (const auto& instr : f.blocks[static_cast<std::size_t>(b)].instrs) folder.transfer(instr, s);
    for (BlockId succ : successors(f.blocks[static_cast<std::size_t>(b)].term))
      if (in.meet(static_cast<std::size_t>(succ), s, live.live_in[static_cast<std::size_t>(succ)])) wait(succ);
  }
  for (std::size_t b = 0; b < n; ++b) {
    Block& block = f.blocks[b];
    in.copy_to(b, s);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < block.instrs.size(); ++k) {
      Instr& instr = block.instrs[k];
      bool keep = folder.rewrite(instr, s);
      folder.transfer(instr, s);
      if (!keep) continue;
      if (kept != k) block.instrs[kept] = std::move(instr);  // never onto itself: that empties it
      ++kept;
    }
    block.instrs.erase(block.instrs.begin() + static_cast<long>(kept), block.instrs.end());
    if (auto* br = std::get_if<Branch>(&block.term)) {
      auto a = folder.known(s, br->a), c = folder.known(s, br->b);
      if (a) br->a = Operand::imm(*a);
      if (c) br->b = Operand::imm(*c);
      if (a && c) block.term = Jump{evaluate(br->cmp, *a, *c) ? br->then : br->otherwise};
    }
  }
}

}  // namespace

void fold_constants(Program& p, LivenessCache* cache) {
  CallEffects calls = call_effects(p);
  LivenessCache own;
  for (auto& f : p.functions)
    if (!f.blocks.empty()) fold_function(p, f, calls, cache ? *cache : own);
}

}  // namespace rcxc::ir
