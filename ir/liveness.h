// Which variables hold a value that may still be read, at every point of a
// function (backward dataflow over the blocks, solved one variable at a
// time from its reads, so the work is the size of the answer). Globals are left
// out: they are visible to every task and are never considered dead. A
// local the function reads before writing stays live past its exit: the
// next call or run reads it.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "ir/ir.h"

namespace rcxc::ir {

// A sorted run of VarIds that lives in a larger array (one block's set in
// a Liveness, a VarSet's members).
struct VarSpan {
  std::span<const VarId> items;

  bool has(VarId v) const;
  std::span<const VarId> members() const { return items; }
};

// A set of VarIds, kept as a sorted vector: the sets the passes handle
// (variables live at one point, a function's footprint) are small, so this
// stays small where a bit per program variable and block would not.
struct VarSet {
  std::vector<VarId> items;

  explicit VarSet(std::size_t = 0) {}
  VarSet(VarSpan s) : items(s.items.begin(), s.items.end()) {}  // NOLINT: a copy of the span's members
  operator VarSpan() const { return {items}; }                   // NOLINT
  bool has(VarId v) const;
  void add(VarId v);
  void remove(VarId v);
  // Adds `o`; returns whether anything changed.
  bool merge(VarSpan o);
  const std::vector<VarId>& members() const { return items; }
  friend bool operator==(const VarSet&, const VarSet&) = default;
};

// One sorted set of VarIds per block of a function, all in one array (the
// passes ask for them for every block of long functions: one allocation,
// not one per block and set).
class BlockVarSets {
 public:
  BlockVarSets() = default;
  // From (block, variable) entries listed in increasing variable order; the
  // entries of each block are kept in that order, so each set is sorted.
  BlockVarSets(std::size_t blocks, const std::vector<std::pair<std::uint32_t, VarId>>& entries);
  VarSpan operator[](std::size_t b) const {
    return {std::span<const VarId>(vars_).subspan(start_[b], start_[b + 1] - start_[b])};
  }
  std::size_t size() const { return start_.empty() ? 0 : start_.size() - 1; }

 private:
  std::vector<std::uint32_t> start_;  // block b's set is vars_[start_[b], start_[b + 1])
  std::vector<VarId> vars_;
};

// Variables each function may read or write, including through the
// subroutines it calls (the calls are followed transitively).
std::vector<VarSet> function_footprints(const Program& p);

struct Liveness {
  BlockVarSets live_in;   // per block
  BlockVarSets live_out;  // per block
};

// What a call does to the variables, per callee. A subroutine shares no
// local or temporary with its callers (inlined copies get their own), so a
// call overwrites the callee's variables (`touches`) and needs from before
// the call only those it reads before writing (`reads`: a local a
// subroutine keeps from one call to the next).
struct CallEffects {
  std::vector<VarSet> touches;  // a task's is empty: no call enters a task
  std::vector<VarSet> reads;
};
CallEffects call_effects(const Program& p);

Liveness compute_liveness(const Program& p, const Function& f, const CallEffects& calls);

// Sorts `keys`, each below 2^bits (bits at most 64), in increasing order.
// Liveness sorts one key per variable and block that reads it first, for
// every function after every change: on a long program hundreds of
// thousands, where a comparison sort took half of liveness's instructions.
// A long list is sorted by its digits, a few passes over it each; a short
// one by comparison.
void sort_keys(std::vector<std::uint64_t>& keys, unsigned bits);

// Each function's liveness, kept from one client pass to the next while
// neither the function's code nor the call effects change: the clean-up
// rounds ask for it in folding, dead-store removal and computing into
// targets, one after the other, and most of those passes change nothing
// in most functions (in the last round, nothing at all). Whether the code
// is the same is decided by comparing a copy of everything liveness reads
// (every opcode, the variables and functions operands name, every
// terminator), not a hash, so a collision can never hand back a stale
// answer.
class LivenessCache {
 public:
  // The liveness of `f`, computed afresh or kept from the last call for
  // the same function. The reference holds until the next call. A function
  // that is not one of p.functions is computed every time. One cache
  // serves one Program (another one clears it).
  const Liveness& of(const Program& p, const Function& f, const CallEffects& calls);
  // How many times `of` computed rather than reused (tests, -v).
  std::size_t computations() const { return computations_; }

 private:
  struct Entry {
    std::vector<std::int32_t> code;  // what the liveness was computed from
    Liveness live;
  };
  std::vector<std::unique_ptr<Entry>> entries_;  // per FuncId; stable addresses
  std::vector<std::int32_t> effects_;            // the CallEffects the entries assumed
  const Program* program_ = nullptr;
  std::vector<std::int32_t> scratch_;
  Liveness uncached_;
  std::size_t computations_ = 0;
};

// Steps backward through a block: `live` starts as the block's live-out and
// after step(i) holds the set live before instruction i.
void step_back(const Program& p, const Instr& in, const CallEffects& calls, VarSet& live);

// The function a call-like instruction enters in the same task (call), or
// -1. Inline: asked of every instruction by many passes.
inline FuncId callee_of(const Instr& in) {
  if (in.raw || in.op != rcx::Op::CallSubroutine || in.args.empty()) return -1;
  return in.args[0].kind == Operand::Kind::Func ? in.args[0].value : -1;
}

}  // namespace rcxc::ir
