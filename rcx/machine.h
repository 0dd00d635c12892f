// The brick's fixed sizes: what every program, image and link transfer
// must fit, and what the emulator models. The compiler checks programs
// against these; the emulator and the virtual brick are built to them.
#pragma once

namespace rcx {

inline constexpr int kPrograms = 5;
inline constexpr int kTimers = 4;
inline constexpr int kSensors = 3;
inline constexpr int kOutputs = 3;
inline constexpr int kLoopDepth = 4;
inline constexpr int kMemoryMapEntries = 94;

// User memory (programs + datalog). The RCX keeps user programs in a 6 KB
// region (RCX Internals, Kekoa Proudfoot); addresses below are the ones the
// memory map reports. Every downloaded subroutine takes one extra byte for
// the return opcode the firmware appends; every datalog entry takes 3 bytes.
inline constexpr int kMemoryBase = 0xCC00;
inline constexpr int kMemoryBytes = 6144;
inline constexpr int kDatalogEntryBytes = 3;

}  // namespace rcx
