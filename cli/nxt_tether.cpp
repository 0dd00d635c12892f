#include "cli/nxt_tether.h"

#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "nxt/commands.h"

namespace rcxc::cli {
namespace {

using nxt::Value;

constexpr std::int64_t kStepUs = 2'000;                 // emulator steps between looks at the link
constexpr std::int64_t kKeepAliveEveryUs = 30'000'000;  // well inside the shortest sleep limit (1 min)
// A port reads invalid for 20 ms after SetInputMode (sound 300, colour 400):
// priming waits this long at most for the first valid reading.
constexpr std::int64_t kPrimeWaitUs = 500'000;
constexpr int kNxtMinToneHz = 200;
constexpr int kNxtMaxToneHz = 14'000;

std::int64_t I(std::int64_t v) { return v; }

// RCX system sounds have no NXT equivalent; each becomes one tone that
// recalls it (frequency Hz, ms).
std::pair<int, int> system_sound_tone(int sound) {
  static constexpr std::array<std::pair<int, int>, 6> kTones{
      {{1000, 20}, {1000, 100}, {400, 300}, {1500, 300}, {200, 500}, {2000, 300}}};
  return kTones[static_cast<std::size_t>(std::clamp(sound, 0, 5))];
}

std::string stop_motors(nxt::Client& client) {
  // Port 0xFF is all three; brake, as RCX "off" does. With a reply: this is
  // the one write whose failure matters now.
  auto r = nxt::call_ok(client, "SetOutputState",
                        std::vector<Value>{I(0xFF), I(0), I(nxt::kMotorOn | nxt::kBrake), I(0), I(0),
                                           I(nxt::kRunStateRunning), I(0)});
  if (auto* e = std::get_if<nxt::CallError>(&r)) return "stopping the motors failed: " + e->message;
  return "";
}

// Reads what made the stop descriptor readable (a signalfd's siginfo, an
// eventfd's count, a pipe's bytes), so it is quiet again until the next stop.
void take_stop(int stop_fd) {
  pollfd p{stop_fd, POLLIN, 0};
  if (stop_fd < 0 || ::poll(&p, 1, 0) <= 0) return;
  std::array<std::uint8_t, 128> buf{};  // a signalfd read takes at least one siginfo (128 bytes)
  [[maybe_unused]] auto n = ::read(stop_fd, buf.data(), buf.size());
}

// The one type a program gives a sensor, if it gives it exactly one.
std::optional<rcx::SensorType> only_type(std::uint8_t types) {
  if (std::popcount(types) != 1) return std::nullopt;
  int t = std::countr_zero(types);
  if (t > static_cast<int>(rcx::SensorType::Rotation)) return std::nullopt;
  return static_cast<rcx::SensorType>(t);
}

// One run: the machine, the brick, and what has been sent to it.
struct Tether {
  Tether(rcx::Machine& m, nxt::Client& c, const TetherOptions& o, TetherStats& s)
      : machine(m), client(c), options(o), stats(s) {}
  rcx::Machine& machine;
  nxt::Client& client;
  const TetherOptions& options;
  TetherStats& stats;
  std::int64_t start_us = 0;
  std::string error;
  std::array<std::optional<NxtDrive>, 3> sent_drive{};
  std::array<std::optional<rcx::SensorType>, 3> sent_type{};
  std::array<std::optional<int>, 3> last_reading{};
  bool mailboxes = false;  // a program runs on the NXT, so its mailboxes work

  std::int64_t now_us() const {
    if (options.clock_us) return options.clock_us();
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  std::int64_t elapsed_us() const { return now_us() - start_us; }

  // Waits, or returns false when the stop descriptor fired.
  bool pause(std::int64_t us) {
    if (options.pause_us) {
      options.pause_us(us);
      return true;
    }
    pollfd p{options.stop_fd, POLLIN, 0};
    return ::poll(&p, options.stop_fd >= 0 ? 1 : 0, static_cast<int>((us + 999) / 1000)) <= 0;
  }
  bool stop_requested() const {
    if (options.stop_fd < 0) return false;
    pollfd p{options.stop_fd, POLLIN, 0};
    return ::poll(&p, 1, 0) > 0;
  }

  void send(std::string_view name, std::vector<Value> values) {
    if (!error.empty()) return;
    ++stats.writes;
    if (auto e = nxt::send_only(client, name, values)) error = e->message;
  }
  std::optional<nxt::Decoded> ask(std::string_view name, std::vector<Value> values) {
    if (!error.empty()) return std::nullopt;
    auto r = nxt::call_ok(client, name, values);
    if (auto* e = std::get_if<nxt::CallError>(&r)) {
      error = e->message;
      return std::nullopt;
    }
    return std::get<nxt::Decoded>(std::move(r));
  }

  void set_input(std::size_t i, rcx::SensorType type) {
    sent_type[i] = type;
    last_reading[i].reset();
    send("SetInputMode", {I(static_cast<std::int64_t>(i)), I(nxt_sensor_type(type)), I(nxt_sensor_mode(type))});
  }

  // A reading of input i, fed to the emulator at `at_us` if it is valid and
  // new. Returns whether the port read valid.
  bool poll_input(std::size_t i, rcx::Micros at_us) {
    ++stats.polls;
    ++stats.polls_per_input[i];
    auto d = ask("GetInputValues", {I(static_cast<std::int64_t>(i))});
    if (!d || d->number("valid").value_or(0) == 0) return false;
    // The NXT counts a rotation sensor's steps; other sensors go raw to the
    // emulator's own sensor logic.
    bool rotation = *sent_type[i] == rcx::SensorType::Rotation;
    int reading = static_cast<int>(rotation ? d->number("scaled").value_or(0) : d->number("raw").value_or(1023));
    if (last_reading[i] == reading) return true;
    last_reading[i] = reading;
    int sensor = static_cast<int>(i);
    if (rotation) machine.schedule({at_us, rcx::RotationInput{sensor, reading}});
    else machine.schedule({at_us, rcx::SensorRawInput{sensor, reading}});
    return true;
  }

  // Before the program starts: each sensor it reads gets the type the
  // program will give it and a first valid reading, applied at time 0, so
  // the program never sees an open input where the NXT has a sensor.
  void prime_sensors() {
    for (std::size_t i = 0; i < 3 && error.empty(); ++i)
      if (options.io.sensors_read[i])
        set_input(i, only_type(options.io.sensor_types[i]).value_or(rcx::SensorType::Raw));
    for (std::size_t i = 0; i < 3 && error.empty(); ++i) {
      if (!options.io.sensors_read[i]) continue;
      const std::int64_t give_up = elapsed_us() + kPrimeWaitUs;
      while (error.empty() && !poll_input(i, machine.now_us())) {
        if (elapsed_us() > give_up || !pause(kStepUs)) break;
      }
    }
  }

  void check_mailboxes() {
    if (!options.io.message_read && !options.io.message_sent) return;
    auto r = nxt::call(client, *nxt::find_command("GetCurrentProgramName"), {});
    if (auto* e = std::get_if<nxt::CallError>(&r)) {
      error = e->message;
      return;
    }
    mailboxes = std::get<nxt::Decoded>(r).status == nxt::status::kOk;
    if (!mailboxes)
      stats.notes.push_back(
          "no program runs on the NXT, and its firmware takes mailbox messages only while one runs: "
          "the program's messages go nowhere (start any program on the NXT, e.g. `rcxc nxt start NAME`)");
  }

  void read_message() {
    ++stats.message_reads;
    auto r = nxt::call(client, *nxt::find_command("MessageRead"),
                       std::vector<Value>{I(kTetherInbox), I(kTetherInbox), I(1)});
    if (auto* e = std::get_if<nxt::CallError>(&r)) {
      error = e->message;
      return;
    }
    const auto& d = std::get<nxt::Decoded>(r);
    if (d.status == nxt::status::kQueueEmpty) return;
    if (d.status != nxt::status::kOk) {
      // The program on the NXT ended (0xEC): no more messages.
      mailboxes = false;
      stats.notes.push_back(fmt::format("mailbox {} cannot be read any more: 0x{:02x} {}", kTetherInbox + 1, d.status,
                                        nxt::status_message(d.status)));
      return;
    }
    auto data = d.bytes("data").value_or(nxt::Bytes{});
    data.resize(std::min(data.size(), static_cast<std::size_t>(d.number("size").value_or(0))));
    if (auto value = rcx_message(data)) {
      ++stats.messages_received;
      machine.schedule({machine.now_us(), rcx::MessageInput{*value}});
    } else {
      stats.notes.push_back(fmt::format("a message in mailbox {} is no RCX message (a number 0-255): {}",
                                        kTetherInbox + 1, nxt::show_message(data)));
    }
  }

  // Outputs, tones, sounds and messages the program made since the last look.
  void mirror_events(std::size_t& seen) {
    const auto& events = machine.state().events;
    for (; seen < events.size(); ++seen) {
      const rcx::Event& ev = events[seen];
      switch (ev.kind) {
        case rcx::EventKind::Output: {
          NxtDrive d = nxt_drive(ev.output);
          auto& last = sent_drive[static_cast<std::size_t>(ev.index)];
          if (last && *last == d) break;  // only changes go out
          last = d;
          send("SetOutputState", {I(ev.index), I(d.power), I(d.mode), I(0), I(0), I(d.run_state), I(0)});
          break;
        }
        case rcx::EventKind::Tone:
          // RCX tones last in 1/100 s; the NXT plays from 200 Hz.
          send("PlayTone", {I(std::clamp(ev.value, kNxtMinToneHz, kNxtMaxToneHz)), I(ev.duration * 10)});
          break;
        case rcx::EventKind::Sound: {
          auto [hz, ms] = system_sound_tone(ev.value);
          send("PlayTone", {I(hz), I(ms)});
          break;
        }
        case rcx::EventKind::MessageSent:
          // NXC's form of a number, int32 LE + NUL, into the outbox a master reads.
          if (mailboxes) send("MessageWrite", {I(kTetherOutbox), I(0), nxt::message_int(ev.value)});
          break;
        default: break;
      }
    }
  }

  // Sensors the program configured get their NXT type (an active sensor
  // needs the port's power); a type set back to raw keeps the last one.
  void follow_sensor_types() {
    for (std::size_t i = 0; i < 3 && error.empty(); ++i) {
      auto type = machine.state().sensors[i].type;
      if (type == rcx::SensorType::Raw && (sent_type[i] || !options.io.sensors_read[i])) continue;
      if (sent_type[i] != type) set_input(i, type);
    }
  }
};

}  // namespace

int stop_signal_descriptor() {
  sigset_t set;
  sigemptyset(&set);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, s);
  if (pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) return -1;
  return signalfd(-1, &set, SFD_CLOEXEC);
}

NxtDrive nxt_drive(const rcx::Output& output) {
  switch (output.mode) {
    case rcx::OutputMode::Float: return {0, 0, nxt::kRunStateIdle};
    case rcx::OutputMode::Off: return {0, static_cast<std::uint8_t>(nxt::kMotorOn | nxt::kBrake), nxt::kRunStateRunning};
    case rcx::OutputMode::On: break;
  }
  // RCX power 0..7 onto 1/8 steps of 100: 0 -> 12, 7 -> 100.
  int power = (std::clamp(output.power, 0, 7) + 1) * 100 / 8;
  if (output.dir == rcx::Direction::Reverse) power = -power;
  return {static_cast<std::int8_t>(power), static_cast<std::uint8_t>(nxt::kMotorOn | nxt::kBrake), nxt::kRunStateRunning};
}

std::uint8_t nxt_sensor_type(rcx::SensorType type) {
  // RCX sensors on an NXT through LEGO's converter cable (spec/nxt.md).
  std::string_view name = "CUSTOM";  // passive, raw
  switch (type) {
    case rcx::SensorType::Touch: name = "SWITCH"; break;
    case rcx::SensorType::Temperature: name = "TEMPERATURE"; break;
    case rcx::SensorType::Light: name = "REFLECTION"; break;
    case rcx::SensorType::Rotation: name = "ANGLE"; break;
    case rcx::SensorType::Raw: break;
  }
  return *nxt::sensor_type_named(name);
}

std::uint8_t nxt_sensor_mode(rcx::SensorType type) {
  return *nxt::sensor_mode_named(type == rcx::SensorType::Rotation ? "ANGLESTEPSMODE" : "RAWMODE");
}

std::optional<int> rcx_message(std::span<const std::uint8_t> data) {
  if (data.empty() || data.back() != 0) return std::nullopt;
  auto body = data.first(data.size() - 1);
  auto in_range = [](double v) { return v >= 0 && v <= 255 && v == std::floor(v); };
  if (!body.empty() && body.size() <= 3 && std::all_of(body.begin(), body.end(), [](std::uint8_t b) { return b >= '0' && b <= '9'; })) {
    int v = 0;
    for (auto b : body) v = v * 10 + (b - '0');
    if (v <= 255) return v;
    return std::nullopt;
  }
  if (body.size() != 4) return std::nullopt;
  std::uint32_t u = body[0] | (body[1] << 8) | (body[2] << 16) | (std::uint32_t{body[3]} << 24);
  auto as_int = static_cast<std::int32_t>(u);
  if (in_range(as_int)) return as_int;
  // NXT-G sends float32: the same five bytes, read the other way.
  float f = std::bit_cast<float>(u);
  if (std::isfinite(f) && in_range(f)) return static_cast<int>(f);
  return std::nullopt;
}

std::string run_tethered(rcx::Machine& machine, nxt::Client& client, const TetherOptions& options,
                         TetherStats& stats) {
  Tether t(machine, client, options, stats);
  t.start_us = t.now_us();
  // The battery first, with a reply: it also proves the brick is there.
  if (auto battery = t.ask("GetBatteryLevel", {}))
    machine.set_battery_mv(static_cast<int>(battery->number("millivolts").value_or(0)));
  if (!t.error.empty()) return t.error;
  t.check_mailboxes();
  t.prime_sensors();

  std::size_t seen_events = machine.state().events.size();
  const std::int64_t base_us = machine.now_us();
  // Polls lie on a fixed grid of the run's time, and the emulator is held
  // at each grid point until its poll is done: a reading reaches the program
  // at most one poll period after the brick saw it, however late the host
  // got round to asking.
  std::int64_t next_poll_us = 0, next_keepalive_us = 0;
  auto poll_everything = [&] {
    for (std::size_t i = 0; i < 3 && t.error.empty(); ++i)
      if (options.io.sensors_read[i] && t.sent_type[i]) t.poll_input(i, machine.now_us());
    if (options.io.message_read && t.mailboxes && t.error.empty()) t.read_message();
  };
  bool running = true;
  while (t.error.empty() && running) {
    if (t.stop_requested()) {
      t.error = "interrupted";
      break;
    }
    // The emulator's clock follows the wall clock from the first telegram.
    const std::int64_t wall_us = std::min(t.elapsed_us(), options.limit_us);
    // More than a period behind (a link slower than the period, such as
    // Bluetooth's ~60 ms a reply, or a host that did not get the CPU): poll
    // at the present rather than at the grid points missed, since what the
    // brick reads now must not reach the program before the brick saw it.
    if (wall_us - next_poll_us > kTetherPollUs) {
      stats.worst_poll_lag_us = std::max(stats.worst_poll_lag_us, wall_us - next_poll_us);
      next_poll_us = wall_us;
    }
    while (t.error.empty() && running) {
      const std::int64_t to_us = std::min(wall_us, next_poll_us);
      const auto& stop = machine.run_until(base_us + to_us);
      t.mirror_events(seen_events);
      t.follow_sensor_types();
      if (to_us == next_poll_us) {
        stats.worst_poll_lag_us = std::max(stats.worst_poll_lag_us, wall_us - next_poll_us);
        poll_everything();
        // What the brick answered it saw when it answered: a reply that came
        // late under load is as far behind as a poll made late.
        stats.worst_poll_lag_us = std::max(stats.worst_poll_lag_us, t.elapsed_us() - next_poll_us);
        next_poll_us += kTetherPollUs;
        if (next_poll_us < wall_us) next_poll_us = wall_us;
      }
      running = stop.kind == rcx::StopKind::Running && machine.any_task_active() && wall_us < options.limit_us;
      if (to_us == wall_us) break;
    }
    if (wall_us >= next_keepalive_us && t.error.empty()) {
      // KeepAlive keeps the brick awake; the battery is read again with it.
      if (next_keepalive_us > 0)
        if (auto battery = t.ask("GetBatteryLevel", {}))
          machine.schedule({machine.now_us(), rcx::BatteryInput{static_cast<int>(battery->number("millivolts").value_or(0))}});
      next_keepalive_us = wall_us + kKeepAliveEveryUs;
      t.send("KeepAlive", {});
    }
    if (running && !t.pause(kStepUs)) t.error = "interrupted";
  }
  // Ctrl-C is still pending on the stop descriptor, and every wait of the
  // link polls it: the stop below would end as "interrupted" before it was
  // sent and leave the motors running. Take this one off; a second Ctrl-C
  // still cuts the stop short.
  if (t.error == "interrupted") take_stop(options.stop_fd);
  std::string stopped = stop_motors(client);
  if (!t.error.empty()) return t.error;
  // Settle the stop state as an emulator-only run does: Ended when the
  // program ended, TimeLimit when the limit came first.
  machine.run(base_us + options.limit_us);
  return stopped;
}

}  // namespace rcxc::cli
