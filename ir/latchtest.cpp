// A loop's jump back to its test runs a copy of the test (see passes.h).
#include <fmt/format.h>

#include <optional>
#include <vector>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

constexpr int kJump = 2, kTest = 7;
// Latches tried per function: each try walks the blocks once.
constexpr int kTries = 64;

// Whether `to` can be reached from `from` without passing through `avoid`.
bool reaches_avoiding(const Function& f, BlockId from, BlockId to, BlockId avoid) {
  if (from == avoid) return false;
  std::vector<bool> seen(f.blocks.size(), false);
  std::vector<BlockId> work{from};
  seen[static_cast<std::size_t>(from)] = true;
  while (!work.empty()) {
    BlockId b = work.back();
    work.pop_back();
    if (b == to) return true;
    for (BlockId s : successors(f.blocks[static_cast<std::size_t>(b)].term)) {
      auto u = static_cast<std::size_t>(s);
      if (s == avoid || seen[u]) continue;
      seen[u] = true;
      work.push_back(s);
    }
  }
  return false;
}

bool has_raw_asm(const Function& f) {
  for (const Block& b : f.blocks)
    for (const Instr& in : b.instrs)
      if (in.raw) return true;
  return false;
}

// The copy of test `t` for latch `x`: the side that leads back to x
// without passing t (the loop's body) as `then`, tested by a comparison
// that branches there in one instruction; nullopt when there is no such
// side, or both sides are one.
std::optional<Branch> copy_for(const Function& f, BlockId x, BlockId t) {
  const Branch& br = std::get<Branch>(f.blocks[static_cast<std::size_t>(t)].term);
  if (br.then == br.otherwise) return std::nullopt;
  bool then_loops = reaches_avoiding(f, br.then, x, t), otherwise_loops = reaches_avoiding(f, br.otherwise, x, t);
  if (then_loops == otherwise_loops) return std::nullopt;
  Branch copy = br;
  if (otherwise_loops) copy = Branch{negate(br.cmp), br.a, br.b, br.otherwise, br.then};
  if (!branches_directly(copy.cmp, copy.a, copy.b)) return std::nullopt;
  return copy;
}

}  // namespace

int copy_tests_into_latches(Function& f, Log& log, int bytes_to_spend) {
  // Raw asm may branch by offset over the code a copy would move.
  if (f.blocks.empty() || has_raw_asm(f)) return 0;
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  const std::vector<int> components = cycle_components(f);
  int spent = 0, tries = 0;
  bool copied = false;
  for (std::size_t x = 0; x < f.blocks.size() && tries < kTries; ++x) {
    const auto* jump = std::get_if<Jump>(&f.blocks[x].term);
    if (jump == nullptr || loop_blocks[x]) continue;
    BlockId t = jump->target;
    auto tu = static_cast<std::size_t>(t);
    // A jump to the next block is no instruction; only a test alone, on a
    // loop with the jump, outside the blocks of a counter loop.
    const Block& test = f.blocks[tu];
    if (t == static_cast<BlockId>(x + 1) || !test.instrs.empty() || !std::holds_alternative<Branch>(test.term) ||
        loop_blocks[tu] || components[x] != components[tu])
      continue;
    ++tries;
    // A loop's own latch: every way to it passes the test (elsewhere the
    // copy would save a jump on a path into the loop, not on its pass).
    if (t != 0 && reaches_avoiding(f, 0, static_cast<BlockId>(x), t)) continue;
    auto copy = copy_for(f, static_cast<BlockId>(x), t);
    if (!copy) continue;
    // The test, and a jump to the way out unless it follows; the jump to
    // the test goes.
    int added = kTest + (copy->otherwise != static_cast<BlockId>(x + 1) ? kJump : 0) - kJump;
    if (added > bytes_to_spend - spent) continue;
    spent += added;
    copied = true;
    f.blocks[x].term = *copy;
    log.push_back(fmt::format("{}: a loop's jump back to its test runs a copy of the test ({} bytes more, one "
                              "instruction less a pass)",
                              f.name, added));
  }
  // A test that only its latch jumped to is left unreached.
  if (copied) remove_unreachable(f);
  return spent;
}

}  // namespace rcxc::ir
