// From IR with chosen variable slots to RCX bytecode and an .rcx image.
//
// Instruction selection maps each IR instruction onto its opcode through
// the opcode table; branches are selected per the block layout (a jump to
// the next block disappears) and then relaxed: every branch starts in its
// near form and grows to the far form only when its target is out of the
// near range (the seed's offset formulas), repeated until nothing changes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "frontend/diagnostics.h"
#include "ir/ir.h"
#include "runtime/image.h"

namespace rcxc::backend {

// The firmware's limits that the backend checks.
inline constexpr int kMaxTasks = rcx::kMaxTasks;
inline constexpr int kMaxSubroutines = rcx::kMaxSubroutines;
// Largest fragment a download can announce (the length is a 16-bit short).
inline constexpr int kMaxFragmentBytes = 32767;
// Program memory of the RCX 1.0/2.0 firmware shared by one program's
// fragments (the brick has about 6 KB for all user programs; one program
// may use all of it).
inline constexpr int kProgramMemoryBytes = 6000;

// One emitted instruction, for listings.
struct Emitted {
  int address = 0;
  std::vector<std::uint8_t> bytes;
  SourceSpan span{};
};

struct FragmentCode {
  ir::FuncId function = 0;
  rcx::FragmentType type = rcx::FragmentType::Task;
  int index = 0;
  std::string name;
  std::vector<std::uint8_t> code;
  std::vector<Emitted> instrs;
};

struct Output {
  std::vector<FragmentCode> fragments;
  rcx::Image image;
  int code_bytes = 0;
  int slots_used = 0;
};

// `slots` gives the slot of every VarId (-1 if unused), from allocate_slots.
std::optional<Output> generate(const ir::Program& p, const std::vector<int>& slots, Diagnostics& diags);

}  // namespace rcxc::backend
