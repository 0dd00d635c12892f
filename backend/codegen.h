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
#include "rcx/image.h"
#include "rcx/machine.h"

namespace rcxc::backend {

// The firmware's limits that the backend checks.
inline constexpr int kMaxTasks = rcx::kMaxTasks;
inline constexpr int kMaxSubroutines = rcx::kMaxSubroutines;
// Largest fragment a download can announce (the length is a 16-bit short).
inline constexpr int kMaxFragmentBytes = 32767;
// User program memory of the brick (rcx/machine.h);
// one program may use all of it. Subroutines take one more byte each for
// the return the firmware appends.
inline constexpr int kProgramMemoryBytes = rcx::kMemoryBytes;

// The most operands a row of the opcode table has (a unit test checks every
// row): code selection fills an instruction's fields in place.
inline constexpr std::size_t kMaxTableOperands = 16;

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

struct GenerateOptions {
  // From -O1: leave out a copy between two variables that share a slot.
  bool drop_self_copies = false;
  // -O2: move an instruction every call of a subroutine has beside it into
  // the subroutine (the same instructions run).
  bool absorb = false;
  // -Os: also move repeated task code into new subroutines (a call and a
  // return more per pass) and split differing waits beside calls (one
  // instruction more).
  bool outline = false;
};

// `slots` gives the slot of every VarId (-1 if unused), from allocate_slots.
// Decisions (outlining) are appended to `log` when given.
std::optional<Output> generate(const ir::Program& p, const std::vector<int>& slots, Diagnostics& diags,
                               const GenerateOptions& options = {}, std::vector<std::string>* log = nullptr);

}  // namespace rcxc::backend
