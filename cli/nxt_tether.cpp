#include "cli/nxt_tether.h"

#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <optional>

#include <fmt/format.h>

#include "nxt/commands.h"

namespace rcxc::cli {
namespace {

using Clock = std::chrono::steady_clock;
using nxt::Value;

constexpr std::int64_t kStepUs = 2'000;          // emulator steps between looks at the link
constexpr std::int64_t kPollEveryUs = 50'000;    // sensor poll period
constexpr std::int64_t kKeepAliveEveryUs = 30'000'000;  // well inside the shortest sleep limit (1 min)
constexpr int kNxtMinToneHz = 200;

bool stop_requested(int stop_fd) {
  if (stop_fd < 0) return false;
  pollfd p{stop_fd, POLLIN, 0};
  return ::poll(&p, 1, 0) > 0;
}

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
                        std::vector<Value>{std::int64_t{0xFF}, std::int64_t{0}, std::int64_t{nxt::kMotorOn | nxt::kBrake},
                                           std::int64_t{0}, std::int64_t{0}, std::int64_t{nxt::kRunStateRunning},
                                           std::int64_t{0}});
  if (auto* e = std::get_if<nxt::CallError>(&r)) return "stopping the motors failed: " + e->message;
  return "";
}

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
  switch (type) {
    case rcx::SensorType::Touch: return 0x01;        // SWITCH
    case rcx::SensorType::Temperature: return 0x02;  // TEMPERATURE
    case rcx::SensorType::Light: return 0x03;        // REFLECTION
    case rcx::SensorType::Rotation: return 0x04;     // ANGLE
    case rcx::SensorType::Raw: break;
  }
  return 0x09;  // CUSTOM: passive, raw
}

std::string run_tethered(rcx::Machine& machine, nxt::Client& client, std::int64_t limit_us, int stop_fd,
                         TetherStats& stats) {
  // The battery once, with a reply: it also proves the brick is there.
  auto battery = nxt::call_ok(client, "GetBatteryLevel", {});
  if (auto* e = std::get_if<nxt::CallError>(&battery)) return e->message;
  machine.set_battery_mv(static_cast<int>(*std::get<nxt::Decoded>(battery).number("millivolts")));

  std::array<std::optional<NxtDrive>, 3> sent_drive{};
  std::array<std::optional<rcx::SensorType>, 3> sent_type{};
  std::array<int, 3> last_raw{-1, -1, -1};
  std::size_t seen_events = machine.state().events.size();
  const auto start = Clock::now();
  const std::int64_t base_us = machine.now_us();
  std::int64_t next_poll_us = 0, next_keepalive_us = 0;
  std::string error;
  auto send = [&](std::string_view name, std::vector<Value> values) {
    if (!error.empty()) return;
    ++stats.writes;
    if (auto e = nxt::send_only(client, name, values)) error = e->message;
  };

  while (error.empty()) {
    if (stop_requested(stop_fd)) {
      error = "interrupted";
      break;
    }
    std::int64_t wall_us =
        std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start).count();
    const auto& stop = machine.run_until(base_us + std::min(wall_us, limit_us));
    // Outputs, tones, sounds and messages the program made since the last look.
    const auto& events = machine.state().events;
    for (; seen_events < events.size(); ++seen_events) {
      const rcx::Event& ev = events[seen_events];
      switch (ev.kind) {
        case rcx::EventKind::Output: {
          NxtDrive d = nxt_drive(ev.output);
          auto& last = sent_drive[static_cast<std::size_t>(ev.index)];
          if (last && *last == d) break;  // only changes go out
          last = d;
          send("SetOutputState", {std::int64_t{ev.index}, std::int64_t{d.power}, std::int64_t{d.mode}, std::int64_t{0},
                                  std::int64_t{0}, std::int64_t{d.run_state}, std::int64_t{0}});
          break;
        }
        case rcx::EventKind::Tone:
          // RCX tones last in 1/100 s; the NXT plays from 200 Hz.
          send("PlayTone", {std::int64_t{std::clamp(ev.value, kNxtMinToneHz, 14000)}, std::int64_t{ev.duration * 10}});
          break;
        case rcx::EventKind::Sound: {
          auto [hz, ms] = system_sound_tone(ev.value);
          send("PlayTone", {std::int64_t{hz}, std::int64_t{ms}});
          break;
        }
        case rcx::EventKind::MessageSent:
          // NXC's form of a number: int32 LE + NUL, into mailbox 1.
          send("MessageWrite", {std::int64_t{0}, std::int64_t{0}, nxt::message_int(ev.value)});
          break;
        default: break;
      }
    }
    // Sensors the program configured: set the NXT port, then poll its raw value.
    for (std::size_t i = 0; i < 3 && error.empty(); ++i) {
      auto type = machine.state().sensors[i].type;
      if (type == rcx::SensorType::Raw && !sent_type[i]) continue;
      if (!sent_type[i] || *sent_type[i] != type) {
        sent_type[i] = type;
        send("SetInputMode", {static_cast<std::int64_t>(i), std::int64_t{nxt_sensor_type(type)}, std::int64_t{0}});
      }
    }
    if (wall_us >= next_poll_us && error.empty()) {
      next_poll_us = wall_us + kPollEveryUs;
      for (std::size_t i = 0; i < 3 && error.empty(); ++i) {
        if (!sent_type[i]) continue;
        ++stats.polls;
        auto r = nxt::call_ok(client, "GetInputValues", std::vector<Value>{static_cast<std::int64_t>(i)});
        if (auto* e = std::get_if<nxt::CallError>(&r)) {
          error = e->message;
          break;
        }
        const auto& d = std::get<nxt::Decoded>(r);
        int raw = static_cast<int>(d.number("raw").value_or(1023));
        if (d.number("valid").value_or(0) != 0 && raw != last_raw[i]) {
          last_raw[i] = raw;
          machine.schedule({machine.now_us(), rcx::SensorRawInput{static_cast<int>(i), raw}});
        }
      }
    }
    if (wall_us >= next_keepalive_us) {
      next_keepalive_us = wall_us + kKeepAliveEveryUs;
      send("KeepAlive", {});
    }
    if (stop.kind != rcx::StopKind::Running || !machine.any_task_active() || wall_us >= limit_us) break;
    ::poll(nullptr, 0, static_cast<int>(kStepUs / 1000));
  }
  std::string stopped = stop_motors(client);
  if (!error.empty()) return error;
  // Settle the stop state as an emulator-only run does: Ended when the
  // program ended, TimeLimit when the limit came first.
  machine.run(base_us + limit_us);
  return stopped;
}

}  // namespace rcxc::cli
