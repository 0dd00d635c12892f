// `rcxc run prog.nqc --nxt PORT`: the program runs on the RCX emulator in
// real time while its outputs, sensors, sounds and messages are an NXT's
// (docs/nxt.md, "NQC programs on an NXT"). The emulator stays the judge of
// what the program does; the NXT is its body.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "nxt/client.h"
#include "rcx/program_io.h"
#include "runtime/vm.h"

namespace rcxc::cli {

// The sensor poll period: a reading reaches the program at most this late.
inline constexpr std::int64_t kTetherPollUs = 50'000;
// The program's SendMessage goes to this NXT queue (mailbox 11, the first
// outbox a master reads); Message() is fed from queue 0 (mailbox 1).
inline constexpr int kTetherOutbox = 10;
inline constexpr int kTetherInbox = 0;

struct TetherStats {
  int writes = 0;                  // telegrams sent without reply
  int polls = 0;                   // sensor reads (GetInputValues)
  std::array<int, 3> polls_per_input{};
  int message_reads = 0;           // MessageRead of the inbox
  int messages_received = 0;       // fed to the program's Message()
  // How far behind the poll grid the host was at its worst poll: a busy
  // machine delays readings by one poll period plus this.
  std::int64_t worst_poll_lag_us = 0;
  std::vector<std::string> notes;  // what the user should know (no program on the NXT, ...)
};

struct TetherOptions {
  std::int64_t limit_us = 0;
  int stop_fd = -1;       // readable: stop (Ctrl-C)
  rcx::ProgramIo io;      // what the program reads and sends: only that is polled
  // Time: both empty for real time (the steady clock, waits on stop_fd);
  // tests give a virtual clock.
  std::function<std::int64_t()> clock_us;
  std::function<void(std::int64_t)> pause_us;
};

// The NXT side of one RCX output state: port, power -100..100, mode, run state.
struct NxtDrive {
  std::int8_t power = 0;
  std::uint8_t mode = 0;
  std::uint8_t run_state = 0;
  bool operator==(const NxtDrive&) const = default;
};
NxtDrive nxt_drive(const rcx::Output& output);
// NXT sensor type and mode for an RCX sensor type: raw mode, so the
// emulator's own sensor logic turns raw values into readings, except the
// rotation sensor, whose steps the NXT counts (ANGLESTEPSMODE).
std::uint8_t nxt_sensor_type(rcx::SensorType type);
std::uint8_t nxt_sensor_mode(rcx::SensorType type);
// A mailbox message as the RCX's one-byte message (1..255): NXC's int32,
// NXT-G's float32 or text digits, each with its NUL; nullopt for anything else.
std::optional<int> rcx_message(std::span<const std::uint8_t> data);

// SIGINT/SIGTERM/SIGHUP blocked and turned into a readable descriptor that
// every wait polls (no global flag); -1 if that fails.
int stop_signal_descriptor();

// Runs `machine` (program loaded and started) until it ends, faults or the
// limit passes, mirroring it on the NXT behind `client`. Every motor is
// stopped at the end, on Ctrl-C and after a link error. Returns an error
// message ("interrupted" for the stop descriptor), or "" when the run went
// to its end.
std::string run_tethered(rcx::Machine& machine, nxt::Client& client, const TetherOptions& options,
                         TetherStats& stats);

}  // namespace rcxc::cli
