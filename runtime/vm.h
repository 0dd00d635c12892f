// The RCX virtual machine: the brick as the firmware reference (seeds/000)
// describes it, running bytecode in virtual time.
//
// One `Machine` is one brick: 5 program slots (10 tasks + 8 subroutines
// each), 32 variables, 4 timers, 3 sensors, 3 outputs, a message buffer, a
// datalog, a sound queue and a virtual clock. It owns no global state and is
// fully deterministic given its `Config` (the random source is seeded), so two
// machines fed the same inputs produce the same events.
//
// Three kinds of callers drive it:
//  - `rcxc run` / semantic tests: load an image, schedule inputs, `run_until`,
//    then read `state()` and `stop()`.
//  - the IR-link virtual brick: the host-side operations below (downloads,
//    memory map, datalog upload, `execute_direct` for direct commands) answer
//    requests, while `run_until` is called repeatedly with the wall clock
//    mapped to virtual time. Advancing in many small steps gives exactly the
//    same result as one big step.
//  - the debug adapter (`rcxc debug`, dap/): `run` with a Hold, which stops
//    the run before an instruction; resumed, it computes what an unheld
//    run does, at the same times.
//
// Time: the machine counts microseconds (`Micros`). Each executed bytecode
// instruction costs `Config::instruction_cost_us` of virtual time; tasks take
// turns one instruction at a time (round-robin). Waiting tasks cost nothing.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "rcx/image.h"
#include "rcx/decode.h"
#include "rcx/machine.h"
#include "rcx/opcodes.h"

namespace rcx {

using Micros = std::int64_t;
inline constexpr Micros kMicrosPerMs = 1000;

// Default firmware timing: about 2 ms per instruction (measured on the
// original firmware; see docs/emulator.md).
inline constexpr Micros kDefaultInstructionCostUs = 2000;

// The most events a run keeps (about 200 MB). A program that switches an
// output on every pass makes over a hundred a second at the brick's speed,
// so a run asked for days of virtual time would otherwise grow until the
// host has no memory left; it stops here instead (StopKind::EventLimit).
inline constexpr std::size_t kDefaultEventLimit = 5'000'000;

struct Config {
  std::uint64_t seed = 1;                           // random source
  Micros instruction_cost_us = kDefaultInstructionCostUs;
  int battery_mv = 9300;                            // a fresh set of alkalines
  bool trace_variables = false;                     // record Variable events (for traces)
  std::size_t event_limit = kDefaultEventLimit;
};

// ---------------------------------------------------------------- state

enum class OutputMode : std::uint8_t { Float, Off, On };
enum class Direction : std::uint8_t { Forward, Reverse };

struct Output {
  OutputMode mode = OutputMode::Float;
  Direction dir = Direction::Forward;
  int power = 7;
};

// Sensor types and modes as the seed numbers them.
enum class SensorType : std::uint8_t { Raw = 0, Touch = 1, Temperature = 2, Light = 3, Rotation = 4 };
enum class SensorMode : std::uint8_t {
  Raw = 0, Boolean = 1, EdgeCount = 2, PulseCount = 3, Percent = 4, Celsius = 5, Fahrenheit = 6, Angle = 7
};

struct Sensor {
  SensorType type = SensorType::Raw;
  SensorMode mode = SensorMode::Raw;
  int slope = 0;           // 0 = 460/562 hysteresis, 1..31 = slope rule
  int raw = 1023;          // an open input reads high
  bool boolean = false;    // high raw = 0
  int transitions = 0;     // boolean transitions since the last clear
  int rotation = 0;        // absolute shaft position, 1/16 turns
  int rotation_zero = 0;   // position at the last clear
};

struct DatalogEntry {
  std::uint8_t type = 0;   // 0xff size, 0x00-0x1f var, 0x20-0x23 timer, 0x40-0x42 sensor, 0x80 clock
  std::int16_t value = 0;
};

enum class EventKind : std::uint8_t {
  Output,      // output `index` changed: mode, dir, power
  Sound,       // system sound `value` started playing
  Tone,        // tone `value` Hz for `duration` (1/100 s) started playing
  Display,     // display shows device `value`
  MessageSent, // `value` broadcast
  Datalog,     // entry `type`/`value` added
  TaskStart,   // task `index` started
  TaskStop,    // task `index` stopped (ended, stopped or killed)
  Sensor,      // an input reached sensor `index`: `value` = raw (type 0) or rotation position (type 1)
  Variable,    // variable `index` set to `value` (only with Config::trace_variables)
  SensorReading,   // the value a program reads from sensor `index` became `value`
                   // (after an input, a type/mode change or a clear)
  MessageReceived, // `value` arrived by infrared (an input, or the host's Set message)
};

struct Event {
  Micros t_us = 0;
  EventKind kind = EventKind::Output;
  int index = 0;      // output / task / sensor number
  int value = 0;      // sound, frequency, display device, message, datalog value
  int duration = 0;   // tone duration (1/100 s)
  int type = 0;       // datalog entry type
  Output output{};    // Output: the new state
};

// Why a run stopped.
enum class StopKind : std::uint8_t { Running, Ended, TimeLimit, PowerOff, Fault, EventLimit };

struct Fault {
  int task = 0;             // the task that faulted
  int sub = -1;             // subroutine being executed, or -1 for the task body
  int address = 0;          // byte address in that task/sub
  int opcode = -1;          // byte at that address (-1: past the end)
  std::string message;      // what went wrong
};

struct StopInfo {
  StopKind kind = StopKind::Running;
  std::optional<Fault> fault;
};

// Inputs a scenario (or a test, or the IR link) applies at a time.
struct SensorRawInput { int sensor = 0; int raw = 0; };          // sensor 0..2, raw 0..1023
struct RotationInput { int sensor = 0; int position = 0; };      // absolute 1/16 turns
struct MessageInput { int value = 0; };                          // 0..255, as if received
struct BatteryInput { int millivolts = 0; };
using Input = std::variant<SensorRawInput, RotationInput, MessageInput, BatteryInput>;

struct TimedInput {
  Micros at_us = 0;
  Input input;
};

// One program slot: bytecode per task/sub (nullopt = not defined).
struct ProgramSlot {
  std::array<std::optional<std::vector<std::uint8_t>>, kMaxTasks> tasks;
  std::array<std::optional<std::vector<std::uint8_t>>, kMaxSubroutines> subs;
};

// Where a task executes: its own code or a subroutine's.
struct TaskState {
  bool active = false;
  Micros wake_us = 0;             // waiting until (active tasks only)
  int sub = -1;                   // executing subroutine, -1 = task body
  int pc = 0;
  // The firmware keeps ONE return address per task. call_depth: 0 = in the
  // task body, 1 = in a subroutine called from it, 2 = in a subroutine called
  // from a subroutine (the return address now points into the outer one),
  // 3 = back in the outer one with no return address left: its return stops
  // every task.
  int call_depth = 0;
  int return_sub = -1;
  int return_pc = 0;
  std::array<int, kLoopDepth> loops{};
  int loop_depth = 0;
};

struct SoundItem {
  bool tone = false;
  int value = 0;      // sound number or frequency
  int duration = 0;   // 1/100 s
  Micros queued_us = 0;
};

// Everything observable about the brick.
struct State {
  std::array<std::int16_t, kMaxVariables> vars{};
  std::array<Micros, kTimers> timer_zero{};     // time each timer was cleared
  std::array<Output, kOutputs> outputs{};
  std::array<Sensor, kSensors> sensors{};
  int message = 0;
  int display = 0;                              // 0 watch, 1..3 sensors, 4..6 outputs
  int transmitter_range = 0;
  int power_down_minutes = 15;
  int battery_mv = 9300;
  int watch_minutes = 0;                        // clock value at `watch_set_us`
  Micros watch_set_us = 0;
  bool firmware_present = true;
  int program = 0;                              // current program slot
  // Datalog: `datalog_capacity` data entries allocated (plus the size
  // entry, always present), `datalog` holds the ones written so far.
  int datalog_capacity = 0;
  std::vector<DatalogEntry> datalog;
  std::vector<Event> events;
};

// Result of a direct command / request executed by the host.
struct DirectReply {
  bool ok = false;
  std::vector<std::uint8_t> payload;   // reply bytes after the reply opcode
  std::string error;                   // when !ok: why it was not executed
};

// Reply codes of the start download requests (seed).
enum class DownloadStatus : std::uint8_t { Ok = 0, NoMemory = 1, BadIndex = 2 };

class Machine {
 public:
  explicit Machine(Config config = {});

  // ---- programs
  // Replaces slot `slot` with the image's tasks and subs. Returns an error
  // text (insufficient memory, bad slot) and leaves the slot unchanged.
  std::optional<std::string> load(int slot, const Image& image);
  void select_program(int slot);         // like Set program number: stops all tasks
  int program() const { return state_.program; }
  // Start task 0 of the current program (the Run button).
  void start_program();

  // ---- host-side operations (the IR link's requests)
  DownloadStatus begin_task_download(int task, int length);
  DownloadStatus begin_sub_download(int sub, int length);
  // Writes downloaded bytes at the download cursor of the last begin_*.
  // Returns false when no download is open. Extra bytes are dropped.
  bool write_download(std::span<const std::uint8_t> bytes);
  void end_download();
  void delete_task(int task);
  void delete_sub(int sub);
  void delete_all_tasks();
  void delete_all_subs();
  std::array<std::uint16_t, kMemoryMapEntries> memory_map() const;
  int free_memory() const;               // bytes still available
  // Set datalog size: true on success, false = insufficient memory (reply 1).
  bool set_datalog_size(int size);
  // Entries [first, first+count) with entry 0 = size; empty when out of range.
  std::vector<DatalogEntry> upload_datalog(int first, int count) const;
  int battery_mv() const { return state_.battery_mv; }
  void set_battery_mv(int mv) { state_.battery_mv = mv; }
  bool firmware_present() const { return state_.firmware_present; }
  void set_firmware_present(bool present);
  // ROM 3.1 always; firmware 3.9 when present, else 0.0.
  std::array<int, 4> versions() const;
  void start_task(int task);
  void stop_task(int task);
  void stop_all_tasks();
  void set_power_down_delay(int minutes);
  void power_off();                       // ignored when the delay is 0
  int get_value(int source, int argument);
  void set_message(int value);
  // Executes one request or direct command (opcode + operands, either toggle
  // form) at the current virtual time, outside any task, and returns the
  // reply payload. Opcodes that need a task (branches, waits, loops) and the
  // download protocol are refused with an error.
  DirectReply execute_direct(std::span<const std::uint8_t> bytes);

  // ---- running
  void schedule(const TimedInput& input);
  // Runs until virtual time `until_us` (or earlier stop). Returns the stop
  // state; StopKind::Running means "reached until_us and still running".
  const StopInfo& run_until(Micros until_us);
  // Runs until nothing is active or `limit_us`, whichever first; a run that
  // reaches the limit reports StopKind::TimeLimit.
  const StopInfo& run(Micros limit_us);
  // Runs until `until_us` or until nothing is active (StopKind::Ended, the
  // clock left where the last task ended), whichever first, and nothing
  // more: run(limit) still closes the run. Several machines in one room
  // (room.h) go forward side by side this way.
  const StopInfo& run_while_active(Micros until_us);
  // A debugger's hold: asked before each instruction a task is about to
  // execute (the task, and its state with `sub`/`pc` at that instruction);
  // true stops the run before it, without executing it or spending time.
  using Hold = std::function<bool(int task, const TaskState& state)>;
  // run(limit_us), stopped early by `hold`: then StopKind::Running is
  // returned, and calling again (with a hold that now lets the instruction
  // pass) goes on exactly as if nothing had stopped, so a run held any
  // number of times computes what an unheld run does, at the same times.
  const StopInfo& run(Micros limit_us, const Hold& hold);
  Micros now_us() const { return now_us_; }
  // Bytecode instructions this machine has executed, all tasks together.
  std::int64_t instructions_executed() const { return instructions_executed_; }
  const StopInfo& stop() const { return stop_; }
  bool any_task_active() const;
  // The earliest virtual time at which a task may execute an instruction:
  // now when one is awake, else the next wake-up or input. Nothing the
  // program does (a Send message, an output) can happen before it.
  Micros next_activity_us() const;

  // ---- state
  const State& state() const { return state_; }
  // Drops the events recorded so far, for hosts that hand them on as they
  // come (the virtual brick serving for days), so the log never fills.
  void forget_events();
  const TaskState& task(int index) const { return tasks_[static_cast<std::size_t>(index)]; }
  const ProgramSlot& slot(int index) const { return slots_[static_cast<std::size_t>(index)]; }
  int timer_value(int timer) const;       // 1/10 s since cleared (the brick's reading)
  int clock_minutes() const;
  int sensor_value(int sensor) const;
  int motor_state(int output) const;      // the seed's motor state byte

 private:
  void start_task_now(int task);
  void end_task(int task);
  void stop_everything();
  void halt(StopKind kind);
  // True when `hold` stopped it before an instruction.
  bool loop(Micros until_us, bool stop_when_idle, const Hold* hold = nullptr);
  bool step(int task);
  void do_return(int task, TaskState& t);
  const std::vector<std::uint8_t>* code_of(int task, const TaskState& t) const;
  void invalidate_code();
  void apply_due_inputs();
  void apply(const Input& input);
  void start_due_sounds();
  void enqueue_sound(const SoundItem& item);
  void set_output(int index, Output next);
  void fault(int task, const TaskState& t, int opcode, std::string message);
  int datalog_next(int source, int argument);
  int value_of(int source, int argument);
  int used_memory() const;
  int slot_bytes(const ProgramSlot& slot) const;
  void set_sensor_raw(int sensor, int raw);
  void clear_sensor(int sensor);
  void set_var(int index, int value);
  void emit(Event e);
  // Emits SensorReading when sensor's reading differs from the last one emitted.
  void note_reading(int sensor);
  // Executes an opcode that programs and hosts share; false if `op` is not one.
  bool shared_command(Op op, const std::array<int, 5>& v, int& error_code);
  Micros next_wake() const;

  Config config_;
  State state_;
  std::array<ProgramSlot, kPrograms> slots_{};
  std::array<TaskState, kMaxTasks> tasks_{};
  int active_count_ = 0;
  std::int64_t instructions_executed_ = 0;
  unsigned active_mask_ = 0;              // bit n = task n active
  // Decoded instruction caches for the current program: tasks, then subs.
  std::array<std::vector<Decoded>, kMaxTasks + kMaxSubroutines> decoded_{};
  std::vector<TimedInput> inputs_;        // sorted by time; consumed from `next_input_`
  std::size_t next_input_ = 0;
  std::vector<SoundItem> sound_queue_;    // waiting to play, oldest first
  Micros sound_free_us_ = 0;              // when the current sound ends
  Micros now_us_ = 0;
  std::uint64_t rng_;
  int next_task_ = 0;                     // round-robin cursor
  std::array<int, kSensors> noted_reading_;  // last SensorReading value per sensor
  StopInfo stop_;
  int dl_kind_ = -1;                      // open download: -1 none, 0 task, 1 sub
  int dl_index_ = 0;
  std::size_t dl_cursor_ = 0;
};

// Human-readable names used by reports and listings.
const char* to_string(StopKind kind);
// Why a run that stopped with StopKind::EventLimit stopped, for messages:
// "it recorded 5000000 events, the most a run keeps".
std::string event_limit_reason(const Machine& machine);
const char* to_string(OutputMode mode);
const char* to_string(Direction dir);
const char* to_string(EventKind kind);

}  // namespace rcx
