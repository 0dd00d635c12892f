// Absorption: an instruction that every call of a subroutine has right
// before it (or right after it) moves into the subroutine, where it is
// written once instead of at each call. Three calls of `turn_around`, each
// after `Wait(100)`, leave three 2-byte calls and one wait in the
// subroutine: 8 bytes saved for 4 added.
//
// Constant waits also move when they differ: every call needs a wait at
// least as long as the shortest, which moves; the longer ones keep the
// rest (`Wait(200); turn()` becomes `Wait(100); turn()` with the other
// 100 in the subroutine). Two waits in a row end when one wait of their
// sum would, one instruction later, the same as any instruction between.
#pragma once

#include <string>
#include <vector>

#include "backend/outline.h"

namespace rcxc::backend {

// Moves instructions into subroutines while that saves bytes: only where
// no branch enters between the instruction and the call (a path reaching
// the call without the instruction would run it too), and after the call
// only into subroutines without an early return (which would skip it).
// Programs with raw asm are left alone: their calls cannot all be seen.
// Each move is appended to `log`. Differing waits are split only when
// `waits` allows it (-Os): the split runs one wait instruction more.
enum class WaitSplit { Never, Allowed };
void absorb_call_neighbours(std::vector<Selected>& fragments, std::vector<std::string>& log, WaitSplit waits);

}  // namespace rcxc::backend
