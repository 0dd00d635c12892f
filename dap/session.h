// The debug adapter: Debug Adapter Protocol requests in, responses and
// events out, for one program running on the emulator in virtual time.
// All state is in `Session`; `handle` and `advance` do no I/O, and `serve`
// adds the stream (lsp/jsonrpc.h's framing, which DAP shares).
//
// Tasks are threads (id = task number + 1); a task inside a subroutine has
// the subroutine's frame over its caller's. Stopping holds the machine
// before an instruction (rcx::Machine::Hold): nothing of what the program
// computes, or when, changes by being stopped.
#pragma once

#include <cstdint>
#include <istream>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dap/program.h"
#include "runtime/vm.h"

namespace rcxc::dap {

// The exit codes the `exited` event reports (docs/editors.md).
inline constexpr int kExitEnded = 0;      // every task ended (or the program turned the brick off)
inline constexpr int kExitFault = 1;      // an instruction faulted
inline constexpr int kExitTimeLimit = 2;  // `for` ms of virtual time passed with tasks still running
inline constexpr int kExitEventLimit = 3; // the run recorded the most events a run keeps

// Instructions run between looks at the input while running (so `pause`
// and `disconnect` are taken during a long run).
inline constexpr int kSliceInstructions = 20'000;

struct Breakpoint {
  int id = 0;
  int line = 0;       // the line asked for
  int used_line = 0;  // the line with code it moved to (0: none)
};

enum class Phase : std::uint8_t { Start, Launched, Stopped, Running, Ended };
enum class Goal : std::uint8_t { Continue, Next, StepIn, StepOut };

struct Session {
  std::int64_t seq = 0;  // of the last message sent
  bool initialized = false;
  Phase phase = Phase::Start;
  std::optional<DebugProgram> program;
  std::optional<rcx::Machine> machine;
  rcx::Micros limit_us = 0;
  bool stop_on_entry = false;
  bool no_debug = false;     // launched with noDebug (VS Code's Run Without Debugging): nothing stops it
  std::map<int, std::vector<Breakpoint>> breakpoints;  // by file index
  std::map<std::pair<int, int>, std::vector<int>> break_at;  // (fragment key, address) -> breakpoint ids
  int next_breakpoint_id = 1;
  // What the run in progress is for.
  Goal goal = Goal::Continue;
  int goal_task = -1;
  Place goal_place;
  int goal_depth = 0;
  bool goal_moved = false;
  int pass_task = -1;       // runs its next instruction unchecked once (the one it stopped before)
  int stopped_task = 0;     // the thread of the last stop
  int last_task = -1;       // the task that ran last
  bool pause_asked = false;
  std::size_t events_sent = 0;
  unsigned threads_told = 0;  // bit n: a `thread started` event was sent for task n
  bool disconnected = false;
};

// Handles one request; returns the responses and events to send, in order.
std::vector<nlohmann::json> handle(Session& session, const nlohmann::json& message);
// The same for a message body as read: text that is not JSON, or no
// request, gets an error `output` event (there is no request to answer).
std::vector<nlohmann::json> handle_text(Session& session, const std::string& body);
// While the program runs: runs up to `instructions` more, and returns the
// events that brings (stopped, output, thread, terminated, exited).
std::vector<nlohmann::json> advance(Session& session, int instructions = kSliceInstructions);
inline bool running(const Session& session) { return session.phase == Phase::Running; }

// Reads requests from `in` until `disconnect` or the end of input, answering
// on `out`; a bad header is said on `log` and in an `output` event. Returns
// the process exit code (0; 1 when the input ended inside a message).
// Requests are read on a thread of their own, so that `pause` is taken
// while the program runs; after a disconnect it may still wait on `in`, so
// `in` must live as long as the process (standard input does).
int serve(Session& session, std::istream& in, std::ostream& out, std::ostream& log);

}  // namespace rcxc::dap
