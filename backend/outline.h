// Outlining: the opposite of inlining. An instruction sequence repeated in
// the tasks (OnFwd(OUT_A); Wait(100); in a tutorial program, say) moves into
// a new subroutine that every copy calls, when that makes the code smaller:
// n copies of s bytes cost n*s; a subroutine costs s + 1 (the firmware
// appends a return) plus a 2-byte call per copy.
#pragma once

#include <string>
#include <vector>

#include "backend/branch.h"

namespace rcxc::backend {

// One function's machine code before assembly.
struct Selected {
  int function = -1;  // FuncId, -1 for an outlined subroutine
  rcx::FragmentType type = rcx::FragmentType::Task;
  int index = 0;
  std::string name;
  std::vector<MInstr> code;
  std::vector<int> block_start;
};

inline bool is_branch(const MInstr& m) { return m.kind != MInstr::Kind::Fixed; }

// Whether an instruction may run in a subroutine instead of in the task
// that had it: not a branch, call, return or raw asm.
bool movable_into_subroutine(const MInstr& m);

// Where each branch of a fragment goes, as an instruction index
// (code.size() for the end of the code), and which branches enter each
// instruction.
struct Flow {
  std::vector<int> target;                // per instruction; -1 when not a branch
  std::vector<std::vector<int>> entered;  // per instruction: indices branching there
};
int target_index(const Selected& f, const Target& t);
// Makes `code` the fragment's code, where map[i] is the new index of old
// instruction i (map[old size]: the new end): block starts and branches
// to instruction indices follow.
void install_code(Selected& frag, std::vector<MInstr> code, const std::vector<int>& map);
Flow flow_of(const Selected& f);

// Outlines into new subroutines while it saves bytes and subroutine
// indices are free (at most `kMaxSubroutines` in all). Only task code is
// outlined (a subroutine cannot call another); sequences never contain
// calls or raw asm, contain branches only to their own instructions
// (`until (sem == 0); sem = 1;` moves whole) or just past their end (a
// whole repeat loop, counter included), and only their first instruction
// may be entered from outside. Each decision is appended to `log`.
void outline(std::vector<Selected>& fragments, std::vector<std::string>& log);

}  // namespace rcxc::backend
