// `rcxc run prog.nqc --nxt PORT`: the program runs on the RCX emulator in
// real time while its outputs, sensors, sounds and messages are an NXT's
// (docs/nxt.md, "NQC programs on an NXT"). The emulator stays the judge of
// what the program does; the NXT is its body.
#pragma once

#include <cstdint>
#include <string>

#include "nxt/client.h"
#include "runtime/vm.h"

namespace rcxc::cli {

struct TetherStats {
  int writes = 0;  // telegrams sent without reply
  int polls = 0;   // sensor reads
};

// The NXT side of one RCX output state: port, power -100..100, mode, run state.
struct NxtDrive {
  std::int8_t power = 0;
  std::uint8_t mode = 0;
  std::uint8_t run_state = 0;
  bool operator==(const NxtDrive&) const = default;
};
NxtDrive nxt_drive(const rcx::Output& output);
// NXT sensor type for an RCX sensor type (read in raw mode: the emulator's
// own sensor logic turns raw values into readings).
std::uint8_t nxt_sensor_type(rcx::SensorType type);

// SIGINT/SIGTERM/SIGHUP blocked and turned into a readable descriptor that
// every wait polls (no global flag); -1 if that fails.
int stop_signal_descriptor();

// Runs `machine` (program loaded and started) until it ends, faults or
// `limit_us` passes, in real time, mirroring it on the NXT behind `client`.
// Every motor is stopped at the end, on Ctrl-C and after a link error.
// Returns an error message, or "" when the run went to its end.
std::string run_tethered(rcx::Machine& machine, nxt::Client& client, std::int64_t limit_us, int stop_fd,
                         TetherStats& stats);

}  // namespace rcxc::cli
