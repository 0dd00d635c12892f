// Machine instructions before addresses are known, and branch relaxation.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "backend/codegen.h"

namespace rcxc::backend {

// Pseudo block id: the end of the fragment's code (where a task stops).
inline constexpr int kEndOfCode = -2;

// A branch target: a block of the function (its first instruction), or an
// instruction index when `block` is -1.
struct Target {
  int block = -1;
  int instr = -1;
};

struct MInstr {
  // Fixed: `bytes` are final. Jump / Test / Loop: a branch whose near or
  // far form is chosen by `far` during relaxation.
  enum class Kind : std::uint8_t { Fixed, Jump, Test, Loop } kind = Kind::Fixed;
  rcx::Op op = rcx::Op::SetVariable;
  bool raw = false;
  std::vector<std::uint8_t> bytes;  // Fixed
  std::vector<int> values;          // Test: opsrc1, src2, arg1, arg2
  Target target;
  bool far = false;
  SourceSpan span{};
};

// The opcode a branch uses in its current form.
rcx::Op branch_op(const MInstr& m);
// Byte distance from the instruction's address to the origin its offset
// is measured from (the offset field's address).
int offset_origin(rcx::Op op);
// Whether a branch from `origin` to `target` fits `op`'s offset (seed).
bool reaches(rcx::Op op, int origin, int target);
// Encodes the offset fields of a branch to `target` measured from `origin`.
std::vector<int> offset_fields(rcx::Op op, int origin, int target);

// Lays out `code` (block b starts at instruction block_start[b]) choosing
// near forms wherever they reach, and appends the bytes to `bytes` and one
// Emitted per instruction to `listing`, which takes each instruction's
// bytes (they are moved out of `code`). Returns an error text if a branch
// cannot reach even in its far form.
std::string assemble(std::vector<MInstr>& code, const std::vector<int>& block_start, std::vector<std::uint8_t>& bytes,
                     std::vector<Emitted>& listing);

}  // namespace rcxc::backend
