#include "runtime/vm.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>

#include "runtime/sensors.h"

namespace rcx {
namespace {

constexpr Micros kTickUs = 10'000;          // 1/100 s: waits, tone durations, a timer's count
// A timer counts 1/100 s but reads in tenths: the firmware's timers have
// 100 ms resolution, whatever the seed says (docs/emulator.md, "Timers").
constexpr int kTimerTicksPerReading = 10;
constexpr Micros kMinuteUs = 60'000'000;
constexpr int kSoundQueueDepth = 8;
constexpr unsigned kAllTasks = (1u << kMaxTasks) - 1;
// How long each system sound plays, in 1/100 s (our choice, see docs).
constexpr int kSoundDuration[6] = {10, 30, 50, 50, 30, 40};
constexpr std::uint8_t kFirmwareKey[5] = {1, 3, 5, 7, 11};

std::int16_t wrap16(int v) { return static_cast<std::int16_t>(static_cast<std::uint16_t>(v)); }

std::uint64_t splitmix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

bool compare(int op, int a, int b) {
  switch (op & 3) {
    case 0: return a <= b;
    case 1: return a >= b;
    case 2: return a != b;
    default: return a == b;
  }
}

int sign_of(int v) { return (v > 0) - (v < 0); }

// Writes reply fields described by `layout` from `values` (one per field).
std::vector<std::uint8_t> encode_reply(std::span<const Operand> layout, std::span<const int> values) {
  std::vector<std::uint8_t> out;
  std::size_t next = 0;
  for (const auto& field : layout)
    for (int i = 0; i < field.count && next < values.size(); ++i) {
      std::size_t at = out.size();
      out.resize(at + static_cast<std::size_t>(field_size(field.type)));
      write_field(field.type, values[next++], out.data() + at);
    }
  return out;
}

}  // namespace


// ------------------------------------------------------------ construction

Machine::Machine(Config config) : config_(config), rng_(config.seed) {
  state_.battery_mv = config.battery_mv;
  if (config_.instruction_cost_us < 1) config_.instruction_cost_us = 1;
  for (std::size_t i = 0; i < kSensors; ++i) noted_reading_[i] = sensor_reading(state_.sensors[i]);
}

const char* to_string(StopKind kind) {
  switch (kind) {
    case StopKind::Running: return "running";
    case StopKind::Ended: return "ended";
    case StopKind::TimeLimit: return "time_limit";
    case StopKind::PowerOff: return "power_off";
    case StopKind::Fault: return "fault";
    case StopKind::EventLimit: return "event_limit";
  }
  return "?";
}

std::string event_limit_reason(const Machine& machine) {
  return fmt::format("it recorded {} events, the most a run keeps", machine.state().events.size());
}

const char* to_string(OutputMode mode) {
  switch (mode) {
    case OutputMode::On: return "on";
    case OutputMode::Off: return "off";
    case OutputMode::Float: return "float";
  }
  return "?";
}
const char* to_string(Direction dir) { return dir == Direction::Forward ? "fwd" : "rev"; }
const char* to_string(EventKind kind) {
  switch (kind) {
    case EventKind::Output: return "output";
    case EventKind::Sound: return "sound";
    case EventKind::Tone: return "tone";
    case EventKind::Display: return "display";
    case EventKind::MessageSent: return "message_sent";
    case EventKind::Datalog: return "datalog";
    case EventKind::TaskStart: return "task_start";
    case EventKind::TaskStop: return "task_stop";
    case EventKind::Sensor: return "sensor";
    case EventKind::Variable: return "variable";
    case EventKind::SensorReading: return "sensor_reading";
    case EventKind::MessageReceived: return "message_received";
  }
  return "?";
}

// ------------------------------------------------------------ memory

int Machine::slot_bytes(const ProgramSlot& slot) const {
  int n = 0;
  for (const auto& t : slot.tasks)
    if (t) n += static_cast<int>(t->size());
  for (const auto& s : slot.subs)
    if (s) n += static_cast<int>(s->size()) + 1;  // the appended return opcode
  return n;
}

int Machine::used_memory() const {
  int n = (state_.datalog_capacity + 1) * kDatalogEntryBytes;
  for (const auto& slot : slots_) n += slot_bytes(slot);
  return n;
}

int Machine::free_memory() const { return kMemoryBytes - used_memory(); }

std::array<std::uint16_t, kMemoryMapEntries> Machine::memory_map() const {
  std::array<std::uint16_t, kMemoryMapEntries> map{};
  int cursor = kMemoryBase;
  auto place = [&](std::size_t i, const std::optional<std::vector<std::uint8_t>>& code, int extra) {
    map[i] = static_cast<std::uint16_t>(cursor);
    if (code) cursor += static_cast<int>(code->size()) + extra;
  };
  for (std::size_t p = 0; p < kPrograms; ++p)
    for (std::size_t s = 0; s < kMaxSubroutines; ++s) place(p * 8 + s, slots_[p].subs[s], 1);
  for (std::size_t p = 0; p < kPrograms; ++p)
    for (std::size_t t = 0; t < kMaxTasks; ++t) place(40 + p * 10 + t, slots_[p].tasks[t], 0);
  int entries = 1 + static_cast<int>(state_.datalog.size());
  map[90] = static_cast<std::uint16_t>(cursor);
  map[91] = static_cast<std::uint16_t>(cursor + entries * kDatalogEntryBytes);
  map[92] = static_cast<std::uint16_t>(cursor + (state_.datalog_capacity + 1) * kDatalogEntryBytes);
  map[93] = static_cast<std::uint16_t>(kMemoryBase + kMemoryBytes - 1);
  return map;
}

// ------------------------------------------------------------ programs

std::optional<std::string> Machine::load(int slot, const Image& image) {
  if (slot < 0 || slot >= kPrograms) return fmt::format("program slot {} is not 0..4", slot);
  ProgramSlot next;
  for (const auto& f : image.fragments) {
    bool task = f.type == FragmentType::Task;
    if (f.index >= (task ? kMaxTasks : kMaxSubroutines))
      return fmt::format("{} index {} is out of range", task ? "task" : "subroutine", f.index);
    auto& place = task ? next.tasks[f.index] : next.subs[f.index];
    place = f.code;
  }
  int need = slot_bytes(next);
  int available = free_memory() + slot_bytes(slots_[static_cast<std::size_t>(slot)]);
  if (need > available)
    return fmt::format("insufficient memory: the program needs {} bytes, {} are free", need, available);
  if (slot == state_.program) stop_everything();
  slots_[static_cast<std::size_t>(slot)] = std::move(next);
  invalidate_code();
  return std::nullopt;
}

void Machine::select_program(int slot) {
  if (slot < 0 || slot >= kPrograms) return;
  stop_everything();
  state_.program = slot;
  invalidate_code();
}

void Machine::start_program() { start_task(0); }

void Machine::invalidate_code() {
  for (auto& d : decoded_) d.clear();
}

// ------------------------------------------------------------ downloads

DownloadStatus Machine::begin_task_download(int task, int length) {
  if (task < 0 || task >= kMaxTasks) return DownloadStatus::BadIndex;
  auto& place = slots_[static_cast<std::size_t>(state_.program)].tasks[static_cast<std::size_t>(task)];
  int old = place ? static_cast<int>(place->size()) : 0;
  if (length < 0 || length > free_memory() + old) return DownloadStatus::NoMemory;
  if (tasks_[static_cast<std::size_t>(task)].active) stop_everything();
  place = std::vector<std::uint8_t>(static_cast<std::size_t>(length), 0);
  invalidate_code();
  dl_kind_ = 0, dl_index_ = task, dl_cursor_ = 0;
  return DownloadStatus::Ok;
}

DownloadStatus Machine::begin_sub_download(int sub, int length) {
  if (sub < 0 || sub >= kMaxSubroutines) return DownloadStatus::BadIndex;
  auto& place = slots_[static_cast<std::size_t>(state_.program)].subs[static_cast<std::size_t>(sub)];
  int old = place ? static_cast<int>(place->size()) + 1 : 0;
  if (length < 0 || length + 1 > free_memory() + old) return DownloadStatus::NoMemory;
  delete_sub(sub);
  place = std::vector<std::uint8_t>(static_cast<std::size_t>(length), 0);
  invalidate_code();
  dl_kind_ = 1, dl_index_ = sub, dl_cursor_ = 0;
  return DownloadStatus::Ok;
}

bool Machine::write_download(std::span<const std::uint8_t> bytes) {
  if (dl_kind_ < 0) return false;
  auto& slot = slots_[static_cast<std::size_t>(state_.program)];
  auto& place = dl_kind_ == 0 ? slot.tasks[static_cast<std::size_t>(dl_index_)]
                              : slot.subs[static_cast<std::size_t>(dl_index_)];
  if (!place) return false;
  for (std::uint8_t b : bytes) {
    if (dl_cursor_ >= place->size()) break;  // extra bytes are dropped (see docs)
    (*place)[dl_cursor_++] = b;
  }
  invalidate_code();
  return true;
}

void Machine::end_download() { dl_kind_ = -1; }

void Machine::delete_task(int task) {
  if (task < 0 || task >= kMaxTasks) return;
  if (tasks_[static_cast<std::size_t>(task)].active) stop_everything();
  slots_[static_cast<std::size_t>(state_.program)].tasks[static_cast<std::size_t>(task)].reset();
  invalidate_code();
}

void Machine::delete_sub(int sub) {
  if (sub < 0 || sub >= kMaxSubroutines) return;
  for (int i = 0; i < kMaxTasks; ++i) {
    const TaskState& t = tasks_[static_cast<std::size_t>(i)];
    // A sub that called another is still being executed: the task's return
    // address points into it (call_depth 2).
    bool returns_into = t.call_depth == 2 && t.return_sub == sub;
    if (t.active && (t.sub == sub || returns_into)) end_task(i);
  }
  slots_[static_cast<std::size_t>(state_.program)].subs[static_cast<std::size_t>(sub)].reset();
  invalidate_code();
}

void Machine::delete_all_tasks() {
  stop_everything();
  for (int i = 0; i < kMaxTasks; ++i)
    slots_[static_cast<std::size_t>(state_.program)].tasks[static_cast<std::size_t>(i)].reset();
  invalidate_code();
}

void Machine::delete_all_subs() {
  for (int s = 0; s < kMaxSubroutines; ++s) delete_sub(s);
}

// ------------------------------------------------------------ datalog

bool Machine::set_datalog_size(int size) {
  if (size < 0) return false;
  int available = free_memory() + (state_.datalog_capacity + 1) * kDatalogEntryBytes;
  if ((size + 1) * kDatalogEntryBytes > available) return false;
  state_.datalog_capacity = size;
  state_.datalog.clear();
  return true;
}

std::vector<DatalogEntry> Machine::upload_datalog(int first, int count) const {
  int entries = 1 + static_cast<int>(state_.datalog.size());
  if (first < 0 || count < 0 || first + count > entries) return {};
  std::vector<DatalogEntry> out;
  for (int i = first; i < first + count; ++i) {
    if (i == 0)
      out.push_back({0xff, wrap16(entries)});
    else
      out.push_back(state_.datalog[static_cast<std::size_t>(i - 1)]);
  }
  return out;
}

// Returns the reply code: 0 added, 1 full.
int Machine::datalog_next(int source, int argument) {
  if (static_cast<int>(state_.datalog.size()) >= state_.datalog_capacity) return 1;
  int type = 0;
  switch (source) {
    case 0: type = argument & 0x1f; break;
    case 1: type = 0x20 | (argument & 0x03); break;
    case 9: type = 0x40 | (argument & 0x03); break;
    default: type = 0x80; break;
  }
  DatalogEntry e{static_cast<std::uint8_t>(type), wrap16(value_of(source, argument))};
  state_.datalog.push_back(e);
  Event ev{now_us_, EventKind::Datalog};
  ev.type = type, ev.value = e.value;
  emit(ev);
  return 0;
}

// ------------------------------------------------------------ misc host ops

void Machine::set_firmware_present(bool present) {
  if (!present) stop_everything();
  state_.firmware_present = present;
}

std::array<int, 4> Machine::versions() const {
  return state_.firmware_present ? std::array<int, 4>{3, 1, 3, 9} : std::array<int, 4>{3, 1, 0, 0};
}

void Machine::start_task(int task) {
  if (task < 0 || task >= kMaxTasks) return;
  if (!slots_[static_cast<std::size_t>(state_.program)].tasks[static_cast<std::size_t>(task)]) return;
  if (stop_.kind == StopKind::Fault || stop_.kind == StopKind::PowerOff) stop_ = {};
  start_task_now(task);
}

void Machine::stop_task(int task) {
  if (task < 0 || task >= kMaxTasks) return;
  if (tasks_[static_cast<std::size_t>(task)].active) end_task(task);
}

void Machine::stop_all_tasks() { stop_everything(); }

void Machine::set_power_down_delay(int minutes) { state_.power_down_minutes = minutes; }

void Machine::power_off() {
  if (state_.power_down_minutes == 0) return;
  stop_everything();
  halt(StopKind::PowerOff);
}

int Machine::get_value(int source, int argument) { return value_of(source, argument); }

void Machine::set_message(int value) {
  state_.message = value & 0xff;
  Event e{now_us_, EventKind::MessageReceived};
  e.value = state_.message;
  emit(e);
}

// ------------------------------------------------------------ tasks

void Machine::start_task_now(int task) {
  TaskState& t = tasks_[static_cast<std::size_t>(task)];
  if (!t.active) ++active_count_;
  active_mask_ |= 1u << task;
  t = TaskState{};
  t.active = true;
  t.wake_us = now_us_;
  Event e{now_us_, EventKind::TaskStart};
  e.index = task;
  emit(e);
}

void Machine::end_task(int task) {
  TaskState& t = tasks_[static_cast<std::size_t>(task)];
  if (!t.active) return;
  t.active = false;
  --active_count_;
  active_mask_ &= ~(1u << task);
  Event e{now_us_, EventKind::TaskStop};
  e.index = task;
  emit(e);
}

void Machine::stop_everything() {
  for (int i = 0; i < kMaxTasks; ++i) end_task(i);
}

void Machine::halt(StopKind kind) {
  if (stop_.kind == StopKind::Fault) return;  // the first reason wins
  stop_.kind = kind;
}

bool Machine::any_task_active() const { return active_count_ > 0; }

Micros Machine::next_activity_us() const {
  Micros next_input = next_input_ < inputs_.size() ? inputs_[next_input_].at_us : INT64_MAX;
  return std::max(now_us_, std::min(next_wake(), next_input));
}

void Machine::fault(int task, const TaskState& t, int opcode, std::string message) {
  Fault f{task, t.sub, t.pc, opcode, std::move(message)};
  stop_everything();
  stop_.kind = StopKind::Fault;
  stop_.fault = std::move(f);
}

const std::vector<std::uint8_t>* Machine::code_of(int task, const TaskState& t) const {
  const ProgramSlot& slot = slots_[static_cast<std::size_t>(state_.program)];
  const auto& code = t.sub >= 0 ? slot.subs[static_cast<std::size_t>(t.sub)] : slot.tasks[static_cast<std::size_t>(task)];
  return code ? &*code : nullptr;
}

// One return address per task: see TaskState::call_depth.
void Machine::do_return(int task, TaskState& t) {
  if (t.sub < 0) {  // a return in a task body ends the task
    end_task(task);
    return;
  }
  if (t.call_depth >= 3 || t.call_depth == 0) {  // the return address was consumed by a nested call
    stop_everything();
    return;
  }
  t.sub = t.return_sub;
  t.pc = t.return_pc;
  t.call_depth = t.call_depth == 1 ? 0 : 3;
}

// ------------------------------------------------------------ values

int Machine::timer_value(int timer) const {
  if (timer < 0 || timer >= kTimers) return 0;
  const Micros ticks = (now_us_ - state_.timer_zero[static_cast<std::size_t>(timer)]) / kTickUs;
  return wrap16(static_cast<int>(ticks / kTimerTicksPerReading));
}

int Machine::clock_minutes() const {
  return static_cast<int>((state_.watch_minutes + (now_us_ - state_.watch_set_us) / kMinuteUs) % 1440);
}

int Machine::sensor_value(int sensor) const {
  if (sensor < 0 || sensor >= kSensors) return 0;
  return sensor_reading(state_.sensors[static_cast<std::size_t>(sensor)]);
}

int Machine::motor_state(int output) const {
  if (output < 0 || output >= kOutputs) return 0;
  const Output& o = state_.outputs[static_cast<std::size_t>(output)];
  int s = o.power & 7;
  if (o.dir == Direction::Reverse) s |= 0x08;
  if (o.mode == OutputMode::Off) s |= 0x40;
  if (o.mode == OutputMode::On) s |= 0x80;
  return s;
}

int Machine::value_of(int source, int argument) {
  auto sensor = [&](auto f) {
    return (argument >= 0 && argument < kSensors) ? f(state_.sensors[static_cast<std::size_t>(argument)]) : 0;
  };
  switch (source) {
    case 0: return (argument >= 0 && argument < kMaxVariables) ? state_.vars[static_cast<std::size_t>(argument)] : 0;
    case 1: return timer_value(argument);
    case 2: return wrap16(argument);
    case 3: return motor_state(argument);
    case 4: return argument <= 0 ? 0 : static_cast<int>(splitmix(rng_) % static_cast<std::uint64_t>(argument + 1));
    case 8: return state_.program;
    case 9: return sensor([](const Sensor& s) { return sensor_reading(s); });
    case 10: return sensor([](const Sensor& s) { return static_cast<int>(s.type); });
    case 11: return sensor([](const Sensor& s) { return (static_cast<int>(s.mode) << 5) | s.slope; });
    case 12: return sensor([](const Sensor& s) { return s.raw; });
    case 13: return sensor([](const Sensor& s) { return s.boolean ? 1 : 0; });
    case 14: return clock_minutes();
    case 15: return state_.message;
    default: return 0;  // Cybermaster-only sources read as 0
  }
}

void Machine::set_var(int index, int value) {
  if (index < 0 || index >= kMaxVariables) return;
  state_.vars[static_cast<std::size_t>(index)] = wrap16(value);
  if (config_.trace_variables) {
    Event e{now_us_, EventKind::Variable};
    e.index = index, e.value = state_.vars[static_cast<std::size_t>(index)];
    emit(e);
  }
}

// ------------------------------------------------------------ devices

void Machine::emit(Event e) {
  if (state_.events.size() >= config_.event_limit) {
    halt(StopKind::EventLimit);
    return;
  }
  state_.events.push_back(e);
}

void Machine::forget_events() { state_.events = {}; }

void Machine::note_reading(int sensor) {
  int reading = sensor_reading(state_.sensors[static_cast<std::size_t>(sensor)]);
  int& noted = noted_reading_[static_cast<std::size_t>(sensor)];
  if (reading == noted) return;
  noted = reading;
  Event e{now_us_, EventKind::SensorReading};
  e.index = sensor, e.value = reading;
  emit(e);
}

void Machine::set_output(int index, Output next) {
  Output& o = state_.outputs[static_cast<std::size_t>(index)];
  if (o.mode == next.mode && o.dir == next.dir && o.power == next.power) return;
  o = next;
  Event e{now_us_, EventKind::Output};
  e.index = index, e.output = next;
  emit(e);
}

void Machine::clear_sensor(int sensor) {
  Sensor& s = state_.sensors[static_cast<std::size_t>(sensor)];
  s.transitions = 0;
  s.rotation_zero = s.rotation;
  note_reading(sensor);
}

void Machine::set_sensor_raw(int sensor, int raw) {
  Sensor& s = state_.sensors[static_cast<std::size_t>(sensor)];
  feed_raw(s, std::clamp(raw, 0, 1023));
}

void Machine::enqueue_sound(const SoundItem& item) {
  if (static_cast<int>(sound_queue_.size()) >= kSoundQueueDepth) return;  // queue full: dropped
  sound_queue_.push_back(item);
  sound_queue_.back().queued_us = now_us_;
  start_due_sounds();
}

// Starts queued sounds whose turn has come (each at the exact time the
// previous one ends), so chunked and single runs log identical times.
void Machine::start_due_sounds() {
  while (!sound_queue_.empty() && sound_free_us_ <= now_us_) {
    SoundItem item = sound_queue_.front();
    sound_queue_.erase(sound_queue_.begin());
    Micros start = std::max(sound_free_us_, item.queued_us);
    Event e{start, item.tone ? EventKind::Tone : EventKind::Sound};
    e.value = item.value, e.duration = item.duration;
    emit(e);
    sound_free_us_ = start + item.duration * kTickUs;
  }
}

// ------------------------------------------------------------ shared opcodes

bool Machine::shared_command(Op op, const std::array<int, 5>& v, int& error_code) {
  auto var = [&](int i) { return (i >= 0 && i < kMaxVariables) ? int{state_.vars[static_cast<std::size_t>(i)]} : 0; };
  auto each_output = [&](int mask, auto change) {
    for (int i = 0; i < kOutputs; ++i)
      if (mask & (1 << i)) {
        Output next = state_.outputs[static_cast<std::size_t>(i)];
        change(next);
        set_output(i, next);
      }
  };
  switch (op) {
    case Op::SetVariable: set_var(v[0], value_of(v[1], v[2])); return true;
    case Op::AddToVariable: set_var(v[0], var(v[0]) + value_of(v[1], v[2])); return true;
    case Op::SubtractFromVariable: set_var(v[0], var(v[0]) - value_of(v[1], v[2])); return true;
    case Op::MultiplyVariable: set_var(v[0], var(v[0]) * value_of(v[1], v[2])); return true;
    case Op::DivideVariable: {
      int d = value_of(v[1], v[2]);
      if (d != 0) set_var(v[0], var(v[0]) / d);  // division by zero leaves the variable unchanged
      return true;
    }
    case Op::AndVariable: set_var(v[0], var(v[0]) & value_of(v[1], v[2])); return true;
    case Op::OrVariable: set_var(v[0], var(v[0]) | value_of(v[1], v[2])); return true;
    case Op::AbsoluteValue: {
      int x = value_of(v[1], v[2]);
      set_var(v[0], x == -32768 ? 32767 : (x < 0 ? -x : x));
      return true;
    }
    case Op::SignVariable: set_var(v[0], sign_of(value_of(v[1], v[2]))); return true;
    case Op::SetMotorOnOff: {
      int code = v[0];
      OutputMode mode = (code & 0x80) ? OutputMode::On : (code & 0x40) ? OutputMode::Off : OutputMode::Float;
      each_output(code, [&](Output& o) { o.mode = mode; });
      return true;
    }
    case Op::SetMotorDirection: {
      int code = v[0];
      each_output(code, [&](Output& o) {
        if (code & 0x40)
          o.dir = o.dir == Direction::Forward ? Direction::Reverse : Direction::Forward;
        else
          o.dir = (code & 0x80) ? Direction::Forward : Direction::Reverse;
      });
      return true;
    }
    case Op::SetMotorPower: {
      int power = value_of(v[1], v[2]);
      if (power >= 0 && power <= 7) each_output(v[0], [&](Output& o) { o.power = power; });
      return true;
    }
    case Op::SetSensorType: {
      int sensor = v[0], type = v[1];
      if (sensor < 0 || sensor >= kSensors || type < 0 || type > 4) return true;
      Sensor& s = state_.sensors[static_cast<std::size_t>(sensor)];
      s.type = static_cast<SensorType>(type);
      s.mode = default_mode(s.type);
      s.slope = 0;
      clear_sensor(sensor);
      return true;
    }
    case Op::SetSensorMode: {
      int sensor = v[0], code = v[1];
      if (sensor < 0 || sensor >= kSensors) return true;
      Sensor& s = state_.sensors[static_cast<std::size_t>(sensor)];
      s.mode = static_cast<SensorMode>((code >> 5) & 7);
      s.slope = code & 0x1f;
      clear_sensor(sensor);
      return true;
    }
    case Op::ClearSensorValue:
      if (v[0] >= 0 && v[0] < kSensors) clear_sensor(v[0]);
      return true;
    case Op::ClearTimer:
      if (v[0] >= 0 && v[0] < kTimers) state_.timer_zero[static_cast<std::size_t>(v[0])] = now_us_;
      return true;
    case Op::PlaySound:
      if (v[0] >= 0 && v[0] <= 5) enqueue_sound({false, v[0], kSoundDuration[v[0]]});
      return true;
    case Op::PlayTone: enqueue_sound({true, v[0], v[1]}); return true;
    case Op::SetDisplay: {
      int device = value_of(v[0], v[1]);
      if (device >= 0 && device <= 6 && device != state_.display) {
        state_.display = device;
        Event e{now_us_, EventKind::Display};
        e.value = device;
        emit(e);
      }
      return true;
    }
    case Op::SetMessage: set_message(v[0]); return true;
    case Op::SetDatalogSize: error_code = set_datalog_size(v[0]) ? 0 : 1; return true;
    case Op::DatalogNext: error_code = datalog_next(v[0], v[1]); return true;
    case Op::SetTime:
      if (v[0] >= 0 && v[0] <= 23 && v[1] >= 0 && v[1] <= 59) {
        state_.watch_minutes = v[0] * 60 + v[1];
        state_.watch_set_us = now_us_;
      }
      return true;
    case Op::SetPowerDownDelay: set_power_down_delay(v[0]); return true;
    case Op::PowerOff: power_off(); return true;
    case Op::SetTransmitterRange:
      if (v[0] == 0 || v[0] == 1) state_.transmitter_range = v[0];
      return true;
    case Op::SetProgramNumber:
      if (v[0] >= 0 && v[0] < kPrograms) select_program(v[0]);
      return true;
    case Op::StartTask: start_task(v[0]); return true;
    case Op::StopTask: stop_task(v[0]); return true;
    case Op::StopAllTasks: stop_everything(); return true;
    case Op::DeleteTask: delete_task(v[0]); return true;
    case Op::DeleteSubroutine: delete_sub(v[0]); return true;
    case Op::DeleteAllTasks: delete_all_tasks(); return true;
    case Op::DeleteAllSubroutines: delete_all_subs(); return true;
    case Op::DeleteFirmware:
      if (std::equal(std::begin(kFirmwareKey), std::end(kFirmwareKey), v.begin())) set_firmware_present(false);
      return true;
    default:
      return false;
  }
}

// ------------------------------------------------------------ execution

// Runs one instruction of `task` at now_us_; false if none ran (the task
// ended without executing anything, which takes no time).
bool Machine::step(int task) {
  TaskState& t = tasks_[static_cast<std::size_t>(task)];
  const std::vector<std::uint8_t>* code = code_of(task, t);
  if (code == nullptr) {  // the code vanished under the task (deleted)
    end_task(task);
    return false;
  }
  int size = static_cast<int>(code->size());
  if (t.pc >= size) {
    // Running off a task's end ends it at once; a subroutine ends in the
    // return opcode the firmware appends, which costs an instruction.
    if (t.sub < 0) {
      end_task(task);
      return false;
    }
    do_return(task, t);
    return true;
  }
  auto& cache = decoded_[static_cast<std::size_t>(t.sub < 0 ? task : kMaxTasks + t.sub)];
  if (cache.size() != code->size()) cache.assign(code->size(), Decoded{});
  Decoded& cached = cache[static_cast<std::size_t>(t.pc)];
  if (cached.size == 0) cached = decode_command(*code, t.pc);
  // A copy: the instruction may delete or replace code, which drops the cache.
  const Decoded d = cached;
  int opcode = (*code)[static_cast<std::size_t>(t.pc)];
  if (d.error != 0) {
    fault(task, t, opcode, to_string(static_cast<DecodeError>(d.error)));
    return true;
  }
  auto jump = [&](int target) {
    if (target < 0 || target > size) {
      fault(task, t, opcode, fmt::format("branch to {} is outside the code (0..{})", target, size));
      return;
    }
    t.pc = target;
  };
  const auto& v = d.v;
  switch (d.op) {
    case Op::BranchAlwaysNear:
    case Op::BranchAlwaysFar:
      jump(d.target);
      return true;
    case Op::TestAndBranchNear:
    case Op::TestAndBranchFar: {
      int a = value_of(v[0] & 0x0f, v[2]);
      int b = value_of(v[1], v[3]);
      if (compare(v[0] >> 6, a, b)) jump(d.target); else t.pc += d.size;
      return true;
    }
    case Op::SetLoopCounter: {
      if (t.loop_depth < kLoopDepth) ++t.loop_depth;  // a 5th push overwrites the top
      t.loops[static_cast<std::size_t>(t.loop_depth - 1)] = value_of(v[0], v[1]);
      t.pc += d.size;
      return true;
    }
    case Op::DecrementLoopCounterNear:
    case Op::DecrementLoopCounterFar: {
      auto top = static_cast<std::size_t>(std::max(t.loop_depth - 1, 0));
      if (--t.loops[top] < 0) {
        if (t.loop_depth > 0) --t.loop_depth;
        jump(d.target);
      } else {
        t.pc += d.size;
      }
      return true;
    }
    case Op::CallSubroutine: {
      t.pc += d.size;
      int s = v[0];
      if (s < 0 || s >= kMaxSubroutines || !slots_[static_cast<std::size_t>(state_.program)].subs[static_cast<std::size_t>(s)])
        return true;  // undefined subroutine: nothing happens
      t.return_sub = t.sub;
      t.return_pc = t.pc;
      t.call_depth = t.call_depth == 0 ? 1 : 2;
      t.sub = s;
      t.pc = 0;
      return true;
    }
    case Op::ReturnFromSubroutine:
      do_return(task, t);
      return true;
    case Op::Wait: {
      int ticks = std::max(value_of(v[0], v[1]), 0);
      t.pc += d.size;
      t.wake_us = now_us_ + ticks * kTickUs;
      return true;
    }
    case Op::SendMessage: {
      t.pc += d.size;
      Event e{now_us_, EventKind::MessageSent};
      e.value = value_of(v[0], v[1]) & 0xff;
      emit(e);
      return true;
    }
    case Op::ClearMessage:
      t.pc += d.size;
      state_.message = 0;
      return true;
    case Op::SetMessage:  // the program fills its own buffer: nothing arrived
      t.pc += d.size;
      state_.message = v[0] & 0xff;
      return true;
    default: {
      // Advance first: the opcode may restart, stop or delete this very task.
      t.pc += d.size;
      int error_code = 0;
      shared_command(d.op, v, error_code);
      return true;
    }
  }
}

Micros Machine::next_wake() const {
  Micros wake = INT64_MAX;
  for (const auto& t : tasks_)
    if (t.active) wake = std::min(wake, t.wake_us);
  return wake;
}

void Machine::schedule(const TimedInput& input) {
  auto at = std::upper_bound(inputs_.begin() + static_cast<std::ptrdiff_t>(next_input_), inputs_.end(), input.at_us,
                             [](Micros t, const TimedInput& x) { return t < x.at_us; });
  inputs_.insert(at, input);
}

void Machine::apply(const Input& input) {
  if (auto* s = std::get_if<SensorRawInput>(&input)) {
    if (s->sensor < 0 || s->sensor >= kSensors) return;
    set_sensor_raw(s->sensor, s->raw);
  } else if (auto* r = std::get_if<RotationInput>(&input)) {
    if (r->sensor < 0 || r->sensor >= kSensors) return;
    state_.sensors[static_cast<std::size_t>(r->sensor)].rotation = r->position;
  } else if (auto* m = std::get_if<MessageInput>(&input)) {
    set_message(m->value);
    return;
  } else if (auto* b = std::get_if<BatteryInput>(&input)) {
    state_.battery_mv = b->millivolts;
    return;
  }
  Event e{now_us_, EventKind::Sensor};
  if (auto* s = std::get_if<SensorRawInput>(&input))
    e.index = s->sensor, e.value = state_.sensors[static_cast<std::size_t>(s->sensor)].raw, e.type = 0;
  if (auto* r = std::get_if<RotationInput>(&input)) e.index = r->sensor, e.value = r->position, e.type = 1;
  emit(e);
  note_reading(e.index);
}

void Machine::apply_due_inputs() {
  while (next_input_ < inputs_.size() && inputs_[next_input_].at_us <= now_us_) apply(inputs_[next_input_++].input);
}

// The scheduler: round-robin, one instruction per turn, each costing
// instruction_cost_us; when every task waits, time jumps to the next wake-up,
// input or sound start.
bool Machine::loop(Micros until_us, bool stop_when_idle, const Hold* hold) {
  if (stop_.kind != StopKind::Fault && stop_.kind != StopKind::PowerOff && stop_.kind != StopKind::EventLimit)
    stop_.kind = StopKind::Running;
  const Micros cost = config_.instruction_cost_us;
  while (stop_.kind == StopKind::Running) {
    // The last instruction ended past `until_us`: what comes at its end
    // (inputs that arrived while it ran, sounds due) is the next call's.
    if (now_us_ > until_us) return false;
    Micros next_input = next_input_ < inputs_.size() ? inputs_[next_input_].at_us : INT64_MAX;
    if (next_input <= now_us_) apply_due_inputs();
    if (!sound_queue_.empty() && sound_free_us_ <= now_us_) start_due_sounds();
    if (active_count_ == 0 && stop_when_idle) {
      stop_.kind = StopKind::Ended;
      return false;
    }
    if (now_us_ >= until_us) return false;
    // The first active, awake task at or after the round-robin cursor:
    // rotate the active-task bit mask so the cursor is bit 0.
    int chosen = -1;
    unsigned rotated = ((active_mask_ >> next_task_) | (active_mask_ << (kMaxTasks - next_task_))) & kAllTasks;
    while (rotated != 0) {
      int k = std::countr_zero(rotated);
      int i = next_task_ + k >= kMaxTasks ? next_task_ + k - kMaxTasks : next_task_ + k;
      if (tasks_[static_cast<std::size_t>(i)].wake_us <= now_us_) {
        chosen = i;
        break;
      }
      rotated &= rotated - 1;
    }
    if (chosen < 0) {  // everyone waits: jump to the next thing that happens
      Micros next = std::min({next_wake(), next_input, until_us});
      if (!sound_queue_.empty()) next = std::min(next, std::max(sound_free_us_, now_us_));
      now_us_ = std::max(next, now_us_);
      continue;
    }
    // Held before anything of the turn changed: the next call chooses this
    // task again, at this time.
    if (hold && (*hold)(chosen, tasks_[static_cast<std::size_t>(chosen)])) return true;
    // A fault is dated at the start of the instruction that faulted, as
    // every event is, and that instruction never ran: it costs no time, so
    // the run stops when it began (a fault in the first instruction at 0 ms).
    if (step(chosen) && stop_.kind != StopKind::Fault) {
      now_us_ += cost;
      ++instructions_executed_;
    }
    next_task_ = chosen + 1 == kMaxTasks ? 0 : chosen + 1;
  }
  return false;
}

const StopInfo& Machine::run_until(Micros until_us) {
  loop(until_us, false);
  if (stop_.kind == StopKind::Running && active_count_ == 0) stop_.kind = StopKind::Ended;
  return stop_;
}

const StopInfo& Machine::run_while_active(Micros until_us) {
  loop(until_us, true, nullptr);
  return stop_;
}

const StopInfo& Machine::run(Micros limit_us) { return run(limit_us, Hold{}); }

const StopInfo& Machine::run(Micros limit_us, const Hold& hold) {
  if (loop(limit_us, true, hold ? &hold : nullptr)) return stop_;
  if (stop_.kind == StopKind::Running) stop_.kind = StopKind::TimeLimit;
  // An instruction that began before the limit runs whole (its effects are
  // dated at its start), but the run asked for ends at the limit: with 1 s
  // instructions, a 10 ms run is one instruction and stops at 10 ms, not at
  // 1000 ms; a program whose last instruction was still going then had not
  // ended, and inputs that came during it are not applied.
  if (now_us_ > limit_us && (stop_.kind == StopKind::TimeLimit || stop_.kind == StopKind::Ended)) {
    stop_.kind = StopKind::TimeLimit;
    now_us_ = limit_us;
  }
  // Sounds still queued when the program ends keep playing on a real brick:
  // log them at the times they start (up to the limit).
  if (stop_.kind != StopKind::TimeLimit) {
    Micros saved = now_us_;
    while (!sound_queue_.empty() && sound_free_us_ < limit_us) {
      now_us_ = std::max(now_us_, sound_free_us_);
      start_due_sounds();
    }
    now_us_ = saved;
  }
  return stop_;
}

// ------------------------------------------------------------ direct commands

DirectReply Machine::execute_direct(std::span<const std::uint8_t> bytes) {
  DirectReply r;
  if (bytes.empty()) return {false, {}, "empty request"};
  const OpcodeInfo* info = request_at(bytes[0]);
  if (info == nullptr) return {false, {}, fmt::format("0x{:02x} is not a request opcode", bytes[0])};
  auto size = command_size(*info);
  if (!size) return {false, {}, fmt::format("{}: use the download interface", info->name)};
  if (static_cast<int>(bytes.size()) != *size)
    return {false, {}, fmt::format("{}: {} bytes given, {} expected", info->name, bytes.size(), *size)};
  std::array<int, 5> v{};
  std::size_t n = 0;
  int at = 1;
  for (const auto& operand : info->operands)
    for (int i = 0; i < operand.count; ++i) {
      int x = read_field(operand.type, bytes.data() + at);
      at += field_size(operand.type);
      if (n < v.size()) v[n++] = x;
    }
  if (int source = disallowed_source(*info, v); source >= 0)
    return {false, {}, fmt::format("{}: source {} is not allowed", info->name, source)};
  r.ok = true;
  int error_code = 0;
  switch (info->op) {
    case Op::Alive: return r;
    case Op::GetValue: {
      int x = value_of(v[0], v[1]);
      r.payload = encode_reply(info->reply, std::span<const int>(&x, 1));
      return r;
    }
    case Op::GetBatteryPower: {
      int x = state_.battery_mv;
      r.payload = encode_reply(info->reply, std::span<const int>(&x, 1));
      return r;
    }
    case Op::GetMemoryMap: {
      auto map = memory_map();
      std::vector<int> values(map.begin(), map.end());
      r.payload = encode_reply(info->reply, values);
      return r;
    }
    case Op::GetVersions: {
      if (!std::equal(std::begin(kFirmwareKey), std::end(kFirmwareKey), v.begin()))
        return {false, {}, "Get versions: wrong key (the brick does not reply)"};
      auto ver = versions();
      r.payload = encode_reply(info->reply, ver);
      return r;
    }
    case Op::UploadDatalog: {
      for (const auto& e : upload_datalog(v[0], v[1])) {
        r.payload.push_back(e.type);
        std::uint8_t value[2];
        write_field(FieldType::Short, e.value, value);
        r.payload.insert(r.payload.end(), value, value + 2);
      }
      return r;
    }
    case Op::StartTaskDownload:
    case Op::StartSubroutineDownload: {
      auto status = info->op == Op::StartTaskDownload ? begin_task_download(v[1], v[2]) : begin_sub_download(v[1], v[2]);
      int x = static_cast<int>(status);
      r.payload = encode_reply(info->reply, std::span<const int>(&x, 1));
      return r;
    }
    default:
      break;
  }
  if (!info->is_command() || is_branch(info->op) || !shared_command(info->op, v, error_code))
    return {false, {}, fmt::format("{}: not executed as a direct command by this emulator", info->name)};
  if (!info->reply.empty()) r.payload = encode_reply(info->reply, std::span<const int>(&error_code, 1));
  return r;
}

}  // namespace rcx
