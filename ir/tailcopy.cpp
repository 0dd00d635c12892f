// Jumps in loops to short blocks become copies of them (see passes.h).
#include <fmt/format.h>

#include <optional>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

constexpr int kJump = 2;
// The most bytes one copy may add: a power and a direction command (6),
// an assignment of a constant (5). More would take the code towards
// nqc's size for one instruction a pass.
constexpr int kMostBytesAdded = 7;

// Bytes a copy of `j` at the end of block `x` adds, less the jump it
// saves; nullopt when `j` may not be copied: only instructions that take
// an instruction's time and change outputs, sounds or variables (no wait,
// whose time dwarfs a jump's; no call, start, loop counter or raw asm),
// then a jump. A block ending in a test stays: its copy costs 7 bytes
// (the loop tests of a line follower's if/else three times over made its
// code a third larger than nqc's), and saves the jump on one outcome only.
std::optional<int> bytes_added(const Function& f, BlockId x, BlockId j) {
  const Block& to = f.blocks[static_cast<std::size_t>(j)];
  int bytes = -kJump;
  for (const Instr& in : to.instrs) {
    if (!is_quick_command(in)) return std::nullopt;
    bytes += instr_size(in);
  }
  BlockId next = x + 1;
  if (const auto* jump = std::get_if<Jump>(&to.term)) {
    if (jump->target == j) return std::nullopt;  // a block that loops on itself
    // A block that falls into the next one has no jump of its own to
    // spare: the copy would need one, and save nothing.
    if (jump->target == j + 1 && jump->target != next) return std::nullopt;
    return bytes + (jump->target != next ? kJump : 0);
  }
  return std::nullopt;
}

bool has_raw_asm(const Function& f) {
  for (const Block& b : f.blocks)
    for (const Instr& in : b.instrs)
      if (in.raw) return true;
  return false;
}

}  // namespace

void copy_short_jump_targets(Function& f, Log& log, int bytes_to_spend) {
  // Raw asm may branch by offset over the code a copy would move.
  if (f.blocks.empty() || has_raw_asm(f)) return;
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  std::vector<int> preds = predecessor_counts(f);
  // Copying a block's code and terminator into a block of its component
  // adds no loop: the components stay as they are.
  const std::vector<int> components = cycle_components(f);
  // Bytes the copies of each block have added so far: the cap holds for
  // all of a block's copies together, not for each, or a join that many
  // sides jump to (an else-if chain of eight) grows by a copy per side.
  std::vector<int> bytes_copied(f.blocks.size(), 0);
  for (std::size_t x = 0; x < f.blocks.size(); ++x) {
    const auto* jump = std::get_if<Jump>(&f.blocks[x].term);
    if (jump == nullptr || loop_blocks[x]) continue;
    BlockId j = jump->target;
    auto ju = static_cast<std::size_t>(j);
    // A jump to the next block is no instruction; a block only this one
    // enters stays where it is (the copy would leave it unreached); the
    // blocks of a counter loop stay whole.
    if (j == static_cast<BlockId>(x + 1) || j == static_cast<BlockId>(x) || preds[ju] < 2 || loop_blocks[ju])
      continue;
    // Only on a loop (the block jumped to leads back here): elsewhere the
    // jump runs once and the copy's bytes would buy nothing.
    auto added = bytes_added(f, static_cast<BlockId>(x), j);
    if (!added || bytes_copied[ju] + *added > kMostBytesAdded || *added > bytes_to_spend ||
        components[x] != components[ju])
      continue;
    bytes_copied[ju] += *added;
    bytes_to_spend -= *added;
    Block& from = f.blocks[x];
    const Block& to = f.blocks[ju];
    from.instrs.insert(from.instrs.end(), to.instrs.begin(), to.instrs.end());
    from.term = to.term;
    --preds[ju];
    for (BlockId s : successors(from.term)) ++preds[static_cast<std::size_t>(s)];
    log.push_back(fmt::format("{}: a jump in a loop to a short block runs a copy of it ({} bytes more, one "
                              "instruction less a pass)",
                              f.name, *added));
  }
}

}  // namespace rcxc::ir
