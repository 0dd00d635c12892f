#include "nxt/virtual_nxt.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <tuple>

#include <fmt/format.h>

#include "nxt/client.h"

namespace nxt {
namespace {

// Model constants (docs/nxt.md, "The virtual NXT"): an unloaded NXT motor
// turns about 1000 degrees a second at full power.
constexpr double kDegreesPerSecondPerPower = 10.0;
// spec/nxt.md: after SetInputMode a port reads invalid for about 20 ms
// (sound 300 ms, colour 400 ms).
constexpr Micros kValidDelayUs = 20'000;
constexpr Micros kSoundValidDelayUs = 300'000;
constexpr Micros kColourValidDelayUs = 400'000;
// 9600 bit/s I2C: about a millisecond a byte, plus one for the start.
constexpr Micros kLsByteUs = 1'000;
// The firmware's boolean thresholds: true below 45 % of full scale, false above 55 %.
constexpr int kBooleanTrueBelow = 1023 * 45 / 100;
constexpr int kBooleanFalseAbove = 1023 * 55 / 100;
constexpr std::size_t kQueueDepth = 5;
// A Read's data over USB: a 64-byte packet less 0x02, opcode, status, handle, count.
constexpr std::size_t kUsbReadMax = 58;
// PollCommand's data over USB: a 64-byte packet less 0x02, opcode, status, buffer, count.
constexpr std::size_t kUsbPollMax = 59;
// ReadIOMap's data over USB: a 64-byte packet less 0x02, opcode, status, ID, count.
constexpr std::size_t kUsbIoMapMax = 55;
constexpr std::uint8_t kUltrasonicAddress = 0x02;
// Where LEGO's IO maps keep what the direct commands also see (the
// firmware's IOMAPUI and IOMAPLOADER, as NXC's headers give their offsets):
// the virtual NXT's one state is written into them before a ReadIOMap and
// read back after a WriteIOMap.
constexpr std::uint32_t kUiModule = 0x000C0001;
constexpr std::uint32_t kLoaderModule = 0x00090001;
constexpr std::size_t kUiBatteryVoltage = 4;   // u16, mV
constexpr std::size_t kUiBluetoothState = 31;  // bit 0x04: Bluetooth off
constexpr std::size_t kUiSleepTimeout = 33;    // minutes, 0 never
constexpr std::size_t kUiVolume = 36;          // 0-4
constexpr std::uint8_t kUiBtStateOff = 0x04;
constexpr std::size_t kLoaderFreeUserFlash = 4;  // u32

struct Outcome {
  std::uint8_t status = status::kOk;
  std::vector<Value> values;  // empty with a non-zero status: the body is zero-filled
  bool bare = false;          // the status alone, no body at all
};

Outcome ok(std::vector<Value> values = {}) { return {status::kOk, std::move(values)}; }
Outcome fail(std::uint8_t code) { return {code, {}}; }
// An error answered with a body that is not all zeros (the firmware echoes
// or fills in some fields).
Outcome fail_with(std::uint8_t code, std::vector<Value> values) { return {code, std::move(values)}; }
// The LS commands' port check breaks out before any body byte is written
// (c_cmd.c, RC_LS_GET_STATUS / RC_LS_READ): the reply is the status alone.
Outcome fail_bare(std::uint8_t code) { return {code, {}, true}; }

std::int64_t num(const Decoded& d, std::string_view f) { return d.number(f).value_or(0); }
std::string txt(const Decoded& d, std::string_view f) { return d.text(f).value_or(""); }

// A message into a mailbox queue: when it holds kQueueDepth, the oldest is
// dropped (whether MessageWrite, a MessageRead reply or a scenario put it there).
void enqueue(std::deque<Bytes>& q, Bytes message) {
  if (q.size() == kQueueDepth) q.pop_front();
  q.push_back(std::move(message));
}
Bytes raw_bytes(const Decoded& d, std::string_view f) { return d.bytes(f).value_or(Bytes{}); }

std::int64_t whole(double degrees) { return static_cast<std::int64_t>(std::trunc(degrees)); }

// Starting or stopping a program resets all motors and sensors (spec/nxt.md).
void reset_io(VirtualNxt& n) {
  for (auto& m : n.motors) m = Motor{};
  for (auto& s : n.sensors) {
    Sensor fresh;
    fresh.raw = s.raw;
    fresh.distance_cm = s.distance_cm;
    fresh.rotation = fresh.rotation_base = s.rotation;
    s = fresh;
  }
  for (auto& q : n.queues) q.clear();
}

// A program starts: it resets the sleep timer and all I/O.
void begin_program(VirtualNxt& n, const std::string& name) {
  n.program = name;
  n.awake_since_us = n.now_us;
  reset_io(n);
}

std::string upper(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

bool same_file_name(const std::string& a, const std::string& b) { return upper(a) == upper(b); }

bool is_executable(const std::string& name) {
  auto dot = name.rfind('.');
  std::string ext = upper(dot == std::string::npos ? "" : name.substr(dot + 1));
  return ext == "RXE" || ext == "SYS" || ext == "RTM";
}

bool matches(const std::string& pattern, const std::string& name) {
  auto split = [](const std::string& s) {
    auto dot = s.rfind('.');
    return dot == std::string::npos ? std::pair{s, std::string()} : std::pair{s.substr(0, dot), s.substr(dot + 1)};
  };
  auto [ps, pe] = split(upper(pattern));
  auto [ns, ne] = split(upper(name));
  return (ps == "*" || ps == ns) && (pe == "*" || pe == ne);
}

std::optional<std::uint8_t> free_handle(const VirtualNxt& n) {
  for (std::size_t i = 0; i < n.handles.size(); ++i)
    if (!n.handles[i]) return static_cast<std::uint8_t>(i);
  return std::nullopt;
}

bool file_open(const VirtualNxt& n, const std::string& name) {
  return std::any_of(n.handles.begin(), n.handles.end(), [&](const auto& h) {
    return h && (h->kind == Handle::Kind::Read || h->kind == Handle::Kind::Write) && same_file_name(h->name, name);
  });
}

// The handle a command names, or the status to answer.
std::variant<Handle*, std::uint8_t> handle_of(VirtualNxt& n, std::int64_t index, Handle::Kind kind) {
  if (index < 0 || index >= static_cast<std::int64_t>(n.handles.size())) return status::kIllegalHandle;
  auto& h = n.handles[static_cast<std::size_t>(index)];
  if (!h) return status::kHandleClosed;
  if (h->kind != kind) return status::kIllegalHandle;
  return &*h;
}

// The next match of a Find handle at or after its position.
template <typename Range, typename NameOf>
auto next_match(Handle& h, const Range& range, NameOf name_of) -> decltype(&*range.begin()) {
  std::size_t i = 0;
  for (const auto& item : range) {
    if (i++ < h.pos) continue;
    if (matches(h.name, name_of(item))) {
      h.pos = i;
      return &item;
    }
  }
  return nullptr;
}

// The RCX temperature sensor in tenths of a degree Celsius, from its raw
// value. The NXT firmware looks the raw value, held to 290..928, up in a
// table of its own spanning 70.0 to -20.0 °C; the RCX firmware's
// piecewise-linear curve (runtime/sensors.cpp, docs/emulator.md: nxt/ may
// not include runtime/, so the segments are repeated here and a test holds
// the two equal) follows that table within half a degree.
int temperature_tenths(int raw) {
  struct Segment {
    int upto, scale, offset;
  };
  constexpr Segment kCurve[] = {
      {340, -261, 145200}, {390, -194, 123000}, {478, -144, 103500}, {520, -123, 93600},
      {790, -107, 85200},  {886, -134, 106600}, {929, -175, 142600},
  };
  raw = std::clamp(raw, 290, 928);
  for (const auto& seg : kCurve)
    if (raw < seg.upto) return (raw * seg.scale + seg.offset) / 100;
  return -200;  // not reached: 928 is in the last segment
}

// The normalized value: the raw value, except for the temperature sensor,
// which the firmware turns into its temperature mapped onto 0..1023
// ((tenths + 200) x 1023 / 900). Every mode below works from it.
int normalized(const Sensor& s) {
  if (s.type == kTemperatureSensor) return (temperature_tenths(s.raw) + 200) * 1023 / 900;
  return s.raw;
}

// CELSIUSMODE: the normalized value back to tenths of a degree (-20.0..70.0).
int celsius_tenths(int norm) { return norm * 900 / 1023 - 200; }

// FAHRENHEITMODE: the firmware computes 180 x Celsius / 100 + 320 in
// unsigned 32-bit arithmetic and keeps the low 16 bits, so below 0 °C the
// reading wraps (-10.0 °C reads 23732); done the same way here.
int fahrenheit_tenths(int norm) {
  auto celsius = static_cast<std::uint32_t>(static_cast<std::int32_t>(celsius_tenths(norm)));
  std::uint32_t f = 180u * celsius / 100u + 320u;
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(f));
}

int scaled(const Sensor& s) {
  int norm = normalized(s);
  switch (s.mode & 0xE0) {
    case 0x20: return s.boolean ? 1 : 0;
    case 0x40: return s.transitions;
    case 0x60: return s.transitions / 2;
    case 0x80: return (1023 - norm) * 100 / 1023;
    case 0xA0: return celsius_tenths(norm);
    case 0xC0: return fahrenheit_tenths(norm);
    // ANGLESTEPSMODE: an RCX rotation sensor's count, 16 a turn.
    case 0xE0: return s.rotation - s.rotation_base;
    default: return norm;
  }
}

void set_raw(Sensor& s, int raw) {
  s.raw = raw;
  bool was = s.boolean;
  int norm = normalized(s);  // the firmware's thresholds apply to the normalized value
  if (norm < kBooleanTrueBelow) s.boolean = true;
  else if (norm > kBooleanFalseAbove) s.boolean = false;
  if (was != s.boolean) ++s.transitions;
}

// The ultrasonic sensor's registers, as read over I2C.
Bytes ultrasonic_read(const Sensor& s, std::uint8_t reg, std::size_t count) {
  Bytes regs(0x50, 0);
  auto put = [&](std::size_t at, std::string_view text) { std::copy(text.begin(), text.end(), regs.begin() + static_cast<std::ptrdiff_t>(at)); };
  put(0x00, "V1.0");
  put(0x08, "LEGO");
  put(0x10, "Sonar");
  regs[0x41] = s.us_command;
  regs[0x42] = static_cast<std::uint8_t>(s.distance_cm);
  for (int i = 0x43; i <= 0x49; ++i) regs[static_cast<std::size_t>(i)] = 0xFF;  // no further echoes
  Bytes out;
  for (std::size_t i = 0; i < count; ++i) out.push_back(reg + i < regs.size() ? regs[reg + i] : 0);
  return out;
}

Outcome direct(VirtualNxt& n, const Decoded& d) {
  const std::uint8_t op = d.command->opcode;
  switch (op) {
    case 0x00: {  // StartProgram
      // The firmware only looks the file up (a missing one answers 0xC0, not
      // the seed's 0xBD) and hands the name to the UI, which then fails to run
      // a file that is not a program: the reply is 0x00 either way.
      std::string name = txt(d, "name");
      if (!n.files.count(name)) return fail(status::kOutOfRange);
      if (is_executable(name)) begin_program(n, name);
      return ok();
    }
    case 0x01:  // StopProgram
      if (!n.program) return fail(status::kNoProgram);
      n.program.reset();
      reset_io(n);
      return ok();
    case 0x02: {  // PlaySoundFile
      std::string name = txt(d, "name");
      if (!n.files.count(name)) return fail(status::kOutOfRange);
      n.sounds.push_back({n.now_us, SoundEvent::Kind::File, 0, 0, name, num(d, "loop") != 0});
      return ok();
    }
    case 0x03:  // PlayTone: the firmware plays whatever it is given
      n.sounds.push_back({n.now_us, SoundEvent::Kind::Tone, static_cast<int>(num(d, "frequency_hz")),
                          static_cast<int>(num(d, "duration_ms")), "", false});
      return ok();
    case 0x04: {  // SetOutputState: not range-checked by the firmware
      std::int64_t port = num(d, "port");
      if (port > 2 && port != 0xFF) return fail(status::kOutOfRange);
      for (std::size_t i = 0; i < n.motors.size(); ++i) {
        if (port != 0xFF && static_cast<std::size_t>(port) != i) continue;
        Motor& m = n.motors[i];
        m.power = static_cast<std::int8_t>(num(d, "power"));
        m.mode = static_cast<std::uint8_t>(num(d, "mode"));
        m.regulation = static_cast<std::uint8_t>(num(d, "regulation"));
        m.turn_ratio = static_cast<std::int8_t>(num(d, "turn_ratio"));
        m.run_state = static_cast<std::uint8_t>(num(d, "run_state"));
        m.tacho_limit = static_cast<std::uint32_t>(num(d, "tacho_limit"));
        m.moved_this_run = 0;
      }
      return ok();
    }
    case 0x05: {  // SetInputMode
      std::int64_t port = num(d, "port");
      if (port > 3) return fail(status::kOutOfRange);
      Sensor& s = n.sensors[static_cast<std::size_t>(port)];
      s.type = static_cast<std::uint8_t>(num(d, "type"));
      s.mode = static_cast<std::uint8_t>(num(d, "mode"));
      Micros delay = kValidDelayUs;
      if (s.type == kSoundDb || s.type == kSoundDba) delay = kSoundValidDelayUs;
      if (s.type >= kFirstColourType && s.type <= kLastSensorType) delay = kColourValidDelayUs;
      s.valid_at = n.now_us + delay;
      s.transitions = 0;
      s.rotation_base = s.rotation;
      s.ls_ready_at = -1;
      s.ls_answer.clear();
      return ok();
    }
    case 0x06: {  // GetOutputState
      std::int64_t port = num(d, "port");
      if (port > 2) return fail(status::kOutOfRange);
      const Motor& m = n.motors[static_cast<std::size_t>(port)];
      return ok({port, std::int64_t{m.power}, std::int64_t{m.mode}, std::int64_t{m.regulation},
                 std::int64_t{m.turn_ratio}, std::int64_t{m.run_state}, std::int64_t{m.tacho_limit},
                 whole(m.tacho_count), whole(m.block_count), whole(m.rotation_count)});
    }
    case 0x07: {  // GetInputValues: "calibrated" is the normalized value (firmware)
      std::int64_t port = num(d, "port");
      if (port > 3) return fail(status::kOutOfRange);
      const Sensor& s = n.sensors[static_cast<std::size_t>(port)];
      bool valid = n.now_us >= s.valid_at;
      return ok({port, std::int64_t{valid}, std::int64_t{0}, std::int64_t{s.type}, std::int64_t{s.mode},
                 std::int64_t{s.raw}, std::int64_t{normalized(s)}, std::int64_t{scaled(s)},
                 std::int64_t{normalized(s)}});
    }
    case 0x08: {  // ResetInputScaledValue
      std::int64_t port = num(d, "port");
      if (port > 3) return fail(status::kOutOfRange);
      Sensor& s = n.sensors[static_cast<std::size_t>(port)];
      s.transitions = 0;
      s.rotation_base = s.rotation;
      return ok();
    }
    case 0x09: {  // MessageWrite
      // The firmware's order (c_cmd.c RC_MESSAGE_WRITE, cCmdMessageWrite):
      // the size byte and the NUL it points at (0xC0), the queue (0xEE), then
      // the program (0xEC). It takes `size` bytes: anything after them is ignored.
      auto size = static_cast<std::size_t>(num(d, "size"));
      Bytes sent = raw_bytes(d, "data");
      if (size == 0 || size > kMaxMessage) return fail(status::kOutOfRange);
      // Model: the firmware would read bytes that were never sent.
      if (size > sent.size()) return fail(status::kInsanePacket);
      Bytes data(sent.begin(), sent.begin() + static_cast<std::ptrdiff_t>(size));
      if (data.back() != 0) return fail(status::kOutOfRange);
      std::int64_t box = num(d, "inbox");
      if (box >= static_cast<std::int64_t>(n.queues.size())) return fail(status::kIllegalQueue);
      if (!n.program) return fail(status::kNoProgram);
      enqueue(n.queues[static_cast<std::size_t>(box)], std::move(data));
      return ok();
    }
    case 0x0A: {  // ResetMotorPosition
      std::int64_t port = num(d, "port");
      if (port > 2) return fail(status::kOutOfRange);
      Motor& m = n.motors[static_cast<std::size_t>(port)];
      (num(d, "relative") ? m.block_count : m.rotation_count) = 0;
      return ok();
    }
    case 0x0B: return ok({std::int64_t{n.battery_mv}});
    case 0x0C:
      n.sounds.push_back({n.now_us, SoundEvent::Kind::Stop, 0, 0, "", false});
      return ok();
    case 0x0D:  // KeepAlive
      n.awake_since_us = n.now_us;
      return ok({std::int64_t{n.sleep_minutes} * 60'000});
    case 0x0E:    // LSGetStatus
    case 0x10: {  // LSRead
      std::int64_t port = num(d, "port");
      if (port > 3) return fail_bare(status::kOutOfRange);
      Sensor& s = n.sensors[static_cast<std::size_t>(port)];
      // cCmdLSCheckStatus: a port that is not LOWSPEED(_9V) and valid is not
      // ready (0xE0); the body (bytes ready, padded data) comes all the same.
      std::uint8_t state = status::kOk;
      if ((s.type != kLowSpeed && s.type != kLowSpeed9V) || n.now_us < s.valid_at) state = status::kChannelBusy;
      else if (s.ls_ready_at >= 0 && n.now_us < s.ls_ready_at) state = status::kPending;
      else if (s.ls_ready_at >= 0 && s.ls_failed) state = status::kBusError;
      std::size_t ready = state == status::kOk && s.ls_ready_at >= 0 ? s.ls_answer.size() : 0;
      if (op == 0x0E) return {state, {static_cast<std::int64_t>(ready)}};
      Bytes data;
      if (ready > 0) {
        data = std::move(s.ls_answer);
        s.ls_answer.clear();
        s.ls_ready_at = -1;
      }
      return {state, {static_cast<std::int64_t>(data.size()), data}};
    }
    case 0x0F: {  // LSWrite
      // LEGO's firmware refuses ports 4-255 (0xC0); the enhanced NBC/NXC
      // firmware reads flags from bits 2-3 and the port from bits 0-1.
      std::int64_t port = num(d, "port");
      if (port > 3) return fail(status::kOutOfRange);
      Sensor& s = n.sensors[static_cast<std::size_t>(port)];
      // The firmware takes tx_length bytes, whatever the telegram carries after them.
      auto tx_length = static_cast<std::size_t>(num(d, "tx_length"));
      Bytes sent = raw_bytes(d, "tx_data");
      std::int64_t rx = num(d, "rx_length");
      if (tx_length > kLsMax || rx > static_cast<std::int64_t>(kLsMax)) return fail(status::kIllegalSize);
      // Model: the firmware would send bytes that never came.
      if (tx_length > sent.size()) return fail(status::kInsanePacket);
      Bytes tx(sent.begin(), sent.begin() + static_cast<std::ptrdiff_t>(tx_length));
      // Not configured, not valid yet, or a transaction still on the bus: 0xE0
      // (cCmdLSWrite has no 0x20 for a busy channel).
      if ((s.type != kLowSpeed && s.type != kLowSpeed9V) || n.now_us < s.valid_at ||
          (s.ls_ready_at >= 0 && n.now_us < s.ls_ready_at))
        return fail(status::kChannelBusy);
      s.ls_ready_at = n.now_us + kLsByteUs * static_cast<Micros>(1 + tx.size() + static_cast<std::size_t>(rx));
      // Only an ultrasonic sensor (it needs the 9 V supply) answers, at 0x02.
      s.ls_failed = s.type != kLowSpeed9V || tx.empty() || tx[0] != kUltrasonicAddress;
      s.ls_answer.clear();
      if (!s.ls_failed && tx.size() >= 2) {
        if (rx > 0) s.ls_answer = ultrasonic_read(s, tx[1], static_cast<std::size_t>(rx));
        else if (tx[1] == 0x41 && tx.size() >= 3) s.us_command = tx[2];
      }
      return ok();
    }
    case 0x11:
      if (!n.program) return fail(status::kNoProgram);
      return ok({*n.program});
    case 0x13: {  // MessageRead
      // Every reply echoes the local inbox and pads the data to 59 bytes,
      // errors included (c_cmd.c RC_MESSAGE_READ, cCmdMessageGetSize: the
      // program is checked before the queue).
      std::int64_t local = num(d, "local_inbox");
      auto refuse = [&](std::uint8_t code) { return fail_with(code, {local, std::int64_t{0}, Bytes{}}); };
      if (!n.program) return refuse(status::kNoProgram);
      std::int64_t box = num(d, "remote_inbox");
      if (box >= static_cast<std::int64_t>(n.queues.size())) return refuse(status::kIllegalQueue);
      auto& q = n.queues[static_cast<std::size_t>(box)];
      if (q.empty()) return refuse(status::kQueueEmpty);
      Bytes data = q.front();
      if (num(d, "remove")) q.pop_front();
      return ok({local, static_cast<std::int64_t>(data.size()), data});
    }
    case 0x19: return ok({std::int64_t{0}, Bytes{}});  // DatalogRead: nothing logged
    case 0x1A: return ok();                             // DatalogSetTimes
    case 0x1B: return ok({static_cast<std::int64_t>(n.contacts.size())});     // BTGetContactCount: table size
    case 0x1D: return ok({static_cast<std::int64_t>(n.connections.size())});  // BTGetConnCount: table size
    case 0x1C:
    case 0x1E: {  // BTGetContactName, BTGetConnName
      std::span<const BtSlot> table = op == 0x1C ? std::span<const BtSlot>(n.contacts) : std::span<const BtSlot>(n.connections);
      auto index = static_cast<std::size_t>(num(d, "index"));
      // Model: a slot past the table answers 0xC0, as an illegal port does.
      if (index >= table.size()) return fail(status::kOutOfRange);
      return ok({std::int64_t{table[index].device_type}, table[index].name});
    }
    case 0x1F: {  // SetProperty
      Bytes v = raw_bytes(d, "value");
      switch (num(d, "property")) {
        case 0:
          if (v.empty()) return fail(status::kInsanePacket);
          n.bluetooth_on = v[0] != 0;
          return ok();
        case 1:
          if (v.empty()) return fail(status::kInsanePacket);
          n.volume = std::min<std::uint8_t>(v[0], 4);
          return ok();
        case 2: {
          if (v.size() < 4) return fail(status::kInsanePacket);
          std::uint32_t ms = v[0] | (v[1] << 8) | (v[2] << 16) | (std::uint32_t{v[3]} << 24);
          // The firmware keeps whole minutes, in one byte (IOMAPUI's SleepTimeout).
          n.sleep_minutes = static_cast<std::uint8_t>(ms / 60'000);
          return ok();
        }
        default: return fail(status::kUnknownCommand);
      }
    }
    case 0x20: {  // GetProperty
      switch (num(d, "property")) {
        case 0: return ok({Bytes{static_cast<std::uint8_t>(n.bluetooth_on)}});
        case 1: return ok({Bytes{n.volume}});
        case 2: {
          std::uint32_t ms = n.sleep_minutes * 60'000;
          return ok({Bytes{static_cast<std::uint8_t>(ms), static_cast<std::uint8_t>(ms >> 8),
                           static_cast<std::uint8_t>(ms >> 16), static_cast<std::uint8_t>(ms >> 24)}});
        }
        default: return fail(status::kUnknownCommand);
      }
    }
    case 0x21: {  // UpdateResetCount
      std::int64_t port = num(d, "port");
      if (port > 2) return fail(status::kOutOfRange);
      n.motors[static_cast<std::size_t>(port)].tacho_count = 0;
      return ok();
    }
    default: return fail(status::kUnknownCommand);  // GetButtonState has no handler
  }
}

Outcome open_for_write(VirtualNxt& n, const Decoded& d, bool linear, bool data_file) {
  std::string name = txt(d, "name");
  auto size = static_cast<std::uint32_t>(num(d, "size"));
  if (check_file_name(name)) return fail(status::kIllegalFileName);
  if (data_file && is_executable(name)) return fail(status::kIllegalFileName);
  if (n.files.count(name)) return fail(status::kFileExists);
  if (size > free_flash(n)) return fail(status::kNoSpace);
  auto h = free_handle(n);
  if (!h) return fail(status::kNoMoreHandles);
  n.files[name] = StoredFile{{}, size, linear || is_executable(name), data_file};
  n.handles[*h] = Handle{Handle::Kind::Write, name, 0};
  return ok({std::int64_t{*h}});
}

// A search that finds nothing more: FindFirst's handle is closed at once,
// FindNext's stays open until Close (c_loader.c closes after a FINDFIRST
// error only).
Outcome found(VirtualNxt& n, std::uint8_t index, bool first) {
  Handle& h = *n.handles[index];
  auto* f = next_match(h, n.files, [](const auto& kv) { return kv.first; });
  if (!f) {
    if (first) n.handles[index].reset();
    return fail(status::kFileNotFound);
  }
  return ok({std::int64_t{index}, f->first, static_cast<std::int64_t>(f->second.data.size())});
}

Outcome found_module(VirtualNxt& n) {
  auto* m = next_match(n.module_search.cursor, n.modules, [](const Module& m) { return m.name; });
  if (!m) return fail(status::kModuleNotFound);
  return ok({std::int64_t{0}, m->name, std::int64_t{m->id}, std::int64_t{0},
             static_cast<std::int64_t>(m->iomap.size())});
}

Module* module_of(VirtualNxt& n, std::int64_t id) {
  for (auto& m : n.modules)
    if (m.id == id) return &m;
  return nullptr;
}

void put_u16(Bytes& map, std::size_t at, std::uint32_t v) {
  map[at] = static_cast<std::uint8_t>(v);
  map[at + 1] = static_cast<std::uint8_t>(v >> 8);
}
void put_u32(Bytes& map, std::size_t at, std::uint32_t v) {
  put_u16(map, at, v);
  put_u16(map, at + 2, v >> 16);
}

// The brick's state into the IO-map bytes that hold it.
void state_to_iomap(VirtualNxt& n, Module& m) {
  if (m.id == kUiModule) {
    put_u16(m.iomap, kUiBatteryVoltage, static_cast<std::uint32_t>(n.battery_mv));
    auto& bt = m.iomap[kUiBluetoothState];
    bt = static_cast<std::uint8_t>(n.bluetooth_on ? bt & ~kUiBtStateOff : bt | kUiBtStateOff);
    m.iomap[kUiSleepTimeout] = static_cast<std::uint8_t>(n.sleep_minutes);
    m.iomap[kUiVolume] = n.volume;
  } else if (m.id == kLoaderModule) {
    put_u32(m.iomap, kLoaderFreeUserFlash, free_flash(n));
  }
}

// After a WriteIOMap: what was written there is the brick's state. The
// battery voltage and free flash are measured, not set: the next read
// shows the measurement again.
void iomap_to_state(VirtualNxt& n, const Module& m) {
  if (m.id != kUiModule) return;
  n.bluetooth_on = (m.iomap[kUiBluetoothState] & kUiBtStateOff) == 0;
  n.sleep_minutes = m.iomap[kUiSleepTimeout];
  n.volume = m.iomap[kUiVolume];
}

Outcome system(VirtualNxt& n, const Decoded& d) {
  switch (d.command->opcode) {
    case 0x80: {  // OpenRead
      std::string name = txt(d, "name");
      if (check_file_name(name)) return fail(status::kIllegalFileName);
      auto f = n.files.find(name);
      if (f == n.files.end()) return fail(status::kFileNotFound);
      if (file_open(n, name)) return fail(status::kFileBusy);
      auto h = free_handle(n);
      if (!h) return fail(status::kNoMoreHandles);
      n.handles[*h] = Handle{Handle::Kind::Read, name, 0};
      return ok({std::int64_t{*h}, static_cast<std::int64_t>(f->second.data.size())});
    }
    case 0x81: return open_for_write(n, d, false, false);
    case 0x89: return open_for_write(n, d, true, false);
    case 0x8B: return open_for_write(n, d, false, true);
    case 0x8C: {  // OpenAppendData
      std::string name = txt(d, "name");
      auto f = n.files.find(name);
      if (f == n.files.end()) return fail(status::kFileNotFound);
      if (!f->second.data_file) return fail(status::kAppendNotPossible);
      if (file_open(n, name)) return fail(status::kFileBusy);
      auto h = free_handle(n);
      if (!h) return fail(status::kNoMoreHandles);
      n.handles[*h] = Handle{Handle::Kind::Write, name, f->second.data.size()};
      return ok({std::int64_t{*h}, static_cast<std::int64_t>(f->second.size - f->second.data.size())});
    }
    case 0x82: {  // Read
      auto index = num(d, "handle");
      auto h = handle_of(n, index, Handle::Kind::Read);
      if (auto* code = std::get_if<std::uint8_t>(&h)) return fail(*code);
      Handle& handle = *std::get<Handle*>(h);
      const Bytes& data = n.files[handle.name].data;
      // As over USB (c_comm.c): the count field echoes the count asked for,
      // at most 58 data bytes come, and where the file ends first the rest
      // of them are zeros: only the file's size tells real bytes from padding.
      auto asked = num(d, "count");
      std::size_t sent = std::min(static_cast<std::size_t>(asked), kUsbReadMax);
      std::size_t left = data.size() > handle.pos ? data.size() - handle.pos : 0;
      std::size_t real = std::min(sent, left);
      Bytes out(data.begin() + static_cast<std::ptrdiff_t>(handle.pos),
                data.begin() + static_cast<std::ptrdiff_t>(handle.pos + real));
      out.resize(sent, 0);
      handle.pos += real;
      if (real == 0 && sent > 0) {
        // Model: reading with nothing left is an error, after which the handle is closed.
        n.handles[static_cast<std::size_t>(index)].reset();
        return fail_with(status::kEndOfFile, {index, asked, out});
      }
      return ok({index, asked, out});
    }
    case 0x83: {  // Write
      auto index = num(d, "handle");
      auto h = handle_of(n, index, Handle::Kind::Write);
      if (auto* code = std::get_if<std::uint8_t>(&h)) return fail(*code);
      StoredFile& f = n.files[std::get<Handle*>(h)->name];
      Bytes data = raw_bytes(d, "data");
      if (f.data.size() + data.size() > f.size) {
        n.handles[static_cast<std::size_t>(index)].reset();
        return fail(status::kFileFull);
      }
      f.data.insert(f.data.end(), data.begin(), data.end());
      return ok({index, static_cast<std::int64_t>(data.size())});
    }
    case 0x84: {  // Close
      auto index = num(d, "handle");
      if (index < 0 || index >= static_cast<std::int64_t>(n.handles.size())) return fail(status::kIllegalHandle);
      auto& h = n.handles[static_cast<std::size_t>(index)];
      if (!h) return fail(status::kHandleClosed);
      h.reset();
      return ok({index});
    }
    case 0x85: {  // Delete
      // c_comm.c copies the name asked for into every reply, errors included.
      std::string name = txt(d, "name");
      auto refuse = [&](std::uint8_t code) { return fail_with(code, {name.substr(0, kNameField - 1)}); };
      if (check_file_name(name)) return refuse(status::kIllegalFileName);
      if (!n.files.count(name)) return refuse(status::kFileNotFound);
      if (file_open(n, name)) return refuse(status::kFileBusy);
      n.files.erase(name);
      return ok({name});
    }
    case 0x86: {  // FindFirst
      auto h = free_handle(n);
      if (!h) return fail(status::kNoMoreHandles);
      n.handles[*h] = Handle{Handle::Kind::Find, txt(d, "pattern"), 0};
      return found(n, *h, true);
    }
    case 0x87: {  // FindNext
      auto h = handle_of(n, num(d, "handle"), Handle::Kind::Find);
      if (auto* code = std::get_if<std::uint8_t>(&h)) return fail(*code);
      return found(n, static_cast<std::uint8_t>(num(d, "handle")), false);
    }
    case 0x90:  // FindFirstModule
      if (n.module_search.open) return fail(status::kNoMoreHandles);
      n.module_search = {true, Handle{Handle::Kind::Find, txt(d, "pattern"), 0}};
      return found_module(n);
    case 0x91:  // FindNextModule: the handle byte is not looked at
      return found_module(n);
    case 0x92:  // CloseModuleHandle: always succeeds
      n.module_search.open = false;
      return ok({std::int64_t{0}});
    case 0x88: return ok({std::int64_t{n.versions[0]}, std::int64_t{n.versions[1]}, std::int64_t{n.versions[2]},
                          std::int64_t{n.versions[3]}});
    case 0x94: {  // ReadIOMap
      // c_comm.c: the module ID is echoed, at most 55 data bytes come (a USB
      // packet), and after an error the count is 0 and the data zeros.
      auto id = num(d, "module_id");
      auto offset = static_cast<std::size_t>(num(d, "offset"));
      auto count = std::min(static_cast<std::size_t>(num(d, "count")), kUsbIoMapMax);
      Module* m = module_of(n, id);
      std::uint8_t code = !m ? status::kModuleNotFound
                          : offset + count > m->iomap.size() ? status::kOutOfBoundary
                                                             : status::kOk;
      if (code != status::kOk) return fail_with(code, {id, std::int64_t{0}, Bytes(count, 0)});
      state_to_iomap(n, *m);
      auto at = m->iomap.begin() + static_cast<std::ptrdiff_t>(offset);
      return ok({id, static_cast<std::int64_t>(count), Bytes(at, at + static_cast<std::ptrdiff_t>(count))});
    }
    case 0x95: {  // WriteIOMap
      // The count field says how many bytes to write (more sent are ignored);
      // the ID is echoed, the count is 0 after an error.
      auto id = num(d, "module_id");
      auto offset = static_cast<std::size_t>(num(d, "offset"));
      auto count = static_cast<std::size_t>(num(d, "count"));
      Bytes data = raw_bytes(d, "data");
      // Model: the firmware would write bytes that never came.
      if (count > data.size()) return fail_with(status::kInsanePacket, {id, std::int64_t{0}});
      Module* m = module_of(n, id);
      if (!m) return fail_with(status::kModuleNotFound, {id, std::int64_t{0}});
      if (offset + count > m->iomap.size()) return fail_with(status::kOutOfBoundary, {id, std::int64_t{0}});
      state_to_iomap(n, *m);
      std::copy(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(count),
                m->iomap.begin() + static_cast<std::ptrdiff_t>(offset));
      iomap_to_state(n, *m);
      return ok({id, static_cast<std::int64_t>(count)});
    }
    case 0x98:
      n.name = txt(d, "name").substr(0, 15);
      return ok();
    case 0x9B:
      return ok({n.name, Bytes(n.bt_address.begin(), n.bt_address.end()), std::int64_t{0},
                 std::int64_t{free_flash(n)}});
    case 0xA0:
      n.files.clear();
      for (auto& h : n.handles) h.reset();
      return ok();
    case 0xA1: return ok({num(d, "buffer"), std::int64_t{0}});
    case 0xA2: {  // PollCommand: the poll buffers are empty
      // c_comm.c: the data field is as long as the count asked, zeros where
      // the buffer ran dry; more than a USB packet holds (59) is 0x8A with
      // no data.
      auto asked = static_cast<std::size_t>(num(d, "count"));
      if (asked > kUsbPollMax) return fail_with(status::kUndefined, {num(d, "buffer"), std::int64_t{0}, Bytes{}});
      return ok({num(d, "buffer"), std::int64_t{0}, Bytes(asked, 0)});
    }
    // Boot: c_comm.c answers 0x8A and four zero bytes on any link but USB;
    // this brick answers so everywhere, as it never erases itself.
    case 0x97: return fail(status::kUndefined);
    default: return fail(status::kUnknownCommand);  // model: the firmware's reply here is stale bytes
  }
}

// The firmware's direct-command handler reads its fields at fixed offsets
// and never looks at the telegram's length: bytes after a fixed layout are
// ignored, not refused (c_cmd.c cCmdHandleRemoteCommands). A short telegram
// stays short (the firmware would read stale buffer bytes; here it is 0xBF).
std::span<const std::uint8_t> direct_command_as_read(std::span<const std::uint8_t> telegram) {
  if (telegram.size() < 2 || (telegram[0] & ~kNoReplyBit) != kDirectWithReply) return telegram;
  const Command* c = find_command(Group::Direct, telegram[1]);
  if (!c || has_rest(c->request)) return telegram;
  return telegram.first(std::min(telegram.size(), 2 + fixed_size(c->request)));
}

// c_cmd.c, its reply-telegram branch: a MessageRead reply whose status is
// not an error (below 0x80) and whose message is 1-59 bytes ending in its
// NUL goes into the local inbox it names, as MessageWrite would put it
// (queue and program checked there, silently: replies get no answer).
void take_message_read_reply(VirtualNxt& n, std::span<const std::uint8_t> t) {
  if (t.size() < 5 || t[1] != 0x13 || t[2] >= 0x80) return;
  std::size_t size = t[4];
  // Model: a reply shorter than its size byte says is dropped.
  if (size == 0 || size > kMaxMessage || t.size() < 5 + size || t[4 + size] != 0) return;
  if (t[3] >= n.queues.size() || !n.program) return;
  enqueue(n.queues[t[3]], Bytes(t.begin() + 5, t.begin() + 5 + static_cast<std::ptrdiff_t>(size)));
}

}  // namespace

bool FileNameLess::operator()(const std::string& a, const std::string& b) const { return upper(a) < upper(b); }

VirtualNxt make_virtual_nxt(std::vector<ScenarioInput> scenario) {
  VirtualNxt n;
  n.scenario = std::move(scenario);
  // The firmware's module names and IDs. The IO maps whose layout is known
  // here have their firmware size (IOMAPBUTTON 36, IOMAPIOCTRL 2, IOMAPSOUND
  // 30, IOMAPLOADER 8, IOMAPUI 40 bytes, from NXC's offsets); the others are
  // 64-byte zeroed stand-ins (docs/nxt.md, "The virtual NXT").
  const std::tuple<const char*, std::uint32_t, std::size_t> modules[] = {
      {"Command.mod", 0x00010001, 64}, {"Output.mod", 0x00020001, 64}, {"Input.mod", 0x00030001, 64},
      {"Button.mod", 0x00040001, 36},  {"Comm.mod", 0x00050001, 64},   {"IOCtrl.mod", 0x00060001, 2},
      {"Led.mod", 0x00070001, 64},     {"Sound.mod", 0x00080001, 30},  {"Loader.mod", kLoaderModule, 8},
      {"Display.mod", 0x000A0001, 64}, {"LowSpeed.mod", 0x000B0001, 64}, {"Ui.mod", kUiModule, 40}};
  for (const auto& [name, id, size] : modules) n.modules.push_back({name, id, Bytes(size, 0)});
  advance_to(n, 0);
  return n;
}

std::uint32_t free_flash(const VirtualNxt& n) {
  std::uint32_t used = 0;
  for (const auto& [name, f] : n.files) used += f.size;
  return used >= n.flash_bytes ? 0 : n.flash_bytes - used;
}

std::optional<std::string> start_program(VirtualNxt& n, const std::string& name) {
  if (auto bad = check_file_name(name)) return *bad;
  if (!is_executable(name)) return fmt::format("\"{}\" is not a program (.rxe)", name);
  if (!n.files.count(name)) {
    if (free_flash(n) == 0) return "the flash is full";
    n.files[name] = StoredFile{{}, 0, true, false};
  }
  begin_program(n, name);
  return std::nullopt;
}

void advance_to(VirtualNxt& n, Micros now_us) {
  while (n.scenario_origin_us && n.next_input < n.scenario.size() &&
         *n.scenario_origin_us + n.scenario[n.next_input].at_ms * 1000 <= now_us) {
    const auto& in = n.scenario[n.next_input++];
    if (in.battery_mv) n.battery_mv = *in.battery_mv;
    if (in.port >= 0) {
      Sensor& s = n.sensors[static_cast<std::size_t>(in.port)];
      if (in.raw) set_raw(s, *in.raw);
      if (in.distance_cm) s.distance_cm = *in.distance_cm;
      if (in.rotation) s.rotation = *in.rotation;
    }
    if (in.message) {
      // As a master's MessageWrite: the firmware refuses it without a program.
      if (!n.program) {
        ++n.counters.messages_dropped;
        continue;
      }
      enqueue(n.queues[static_cast<std::size_t>(in.queue)], message_int(*in.message));
    }
  }
  if (now_us <= n.now_us) return;
  double seconds = static_cast<double>(now_us - n.now_us) / 1e6;
  n.now_us = now_us;
  for (Motor& m : n.motors) {
    if (!(m.mode & kMotorOn) || m.run_state == kRunStateIdle || m.power == 0) continue;
    double step = m.power * kDegreesPerSecondPerPower * seconds;
    if (m.tacho_limit != 0) {
      double left = m.tacho_limit - std::abs(m.moved_this_run);
      if (std::abs(step) >= left) {
        step = step < 0 ? -left : left;
        // The movement is done: the motor stops (brake or coast as its mode says).
        m.run_state = kRunStateIdle;
        m.power = 0;
      }
    }
    m.moved_this_run += step;
    m.tacho_count += step;
    m.block_count += step;
    m.rotation_count += step;
  }
  if (n.sleep_minutes != 0 && now_us - n.awake_since_us > Micros{n.sleep_minutes} * 60'000'000) n.asleep = true;
}

std::optional<Bytes> answer(VirtualNxt& n, std::span<const std::uint8_t> telegram) {
  ++n.counters.requests;
  if (n.asleep || telegram.empty()) {
    ++n.counters.ignored;
    return std::nullopt;
  }
  // A reply sent to the brick is never answered; a MessageRead reply is
  // taken as a slave's answer to a master's read and put into the local
  // mailbox it names.
  if (telegram[0] == kReply) {
    take_message_read_reply(n, telegram);
    return std::nullopt;
  }
  std::uint8_t type = telegram[0] & static_cast<std::uint8_t>(~kNoReplyBit);
  // The firmware says nothing at all to a telegram type it does not know.
  if (type != kDirectWithReply && type != kSystemWithReply) {
    ++n.counters.ignored;
    return std::nullopt;
  }
  bool reply_wanted = (telegram[0] & kNoReplyBit) == 0;
  auto decoded = decode_request(direct_command_as_read(telegram));
  Bytes reply;
  if (auto* d = std::get_if<Decoded>(&decoded)) {
    Outcome o = d->command->group == Group::Direct ? direct(n, *d) : system(n, *d);
    auto encoded = o.bare ? std::variant<Bytes, TelegramError>(Bytes{kReply, d->command->opcode, o.status})
                          : encode_reply(*d->command, o.status, o.values);
    // A value that does not fit its field would be a bug here: answer
    // "bad arguments" rather than a wrong telegram.
    if (auto* r = std::get_if<Bytes>(&encoded)) reply = std::move(*r);
    else reply = {kReply, d->command->opcode, status::kBadArguments};
  } else if (telegram.size() < 2) {
    reply = {kReply, 0x00, status::kInsanePacket};
  } else {
    Group g = type == kDirectWithReply ? Group::Direct : Group::System;
    reply = {kReply, telegram[1], find_command(g, telegram[1]) ? status::kInsanePacket : status::kUnknownCommand};
  }
  if (!reply_wanted) return std::nullopt;
  ++n.counters.replies;
  return reply;
}

}  // namespace nxt
