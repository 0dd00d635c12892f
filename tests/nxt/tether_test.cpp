// `rcxc run --nxt` in process: the tether (cli/nxt_tether.h) between the
// emulator and a virtual NXT, on a virtual clock, with a link that counts
// what crosses it and can lose replies or fail.
#include "cli/nxt_tether.h"

#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <functional>
#include <map>

#include "nxt/commands.h"
#include "nxt/virtual_nxt.h"
#include "rcx/image.h"
#include "tests/support/process.h"

namespace {

using rcxc::cli::run_tethered;
using rcxc::cli::TetherOptions;
using rcxc::cli::TetherStats;
using rcxc::test::TempDir;

// NQC source compiled by the rcxc under test.
rcx::Image compile(const std::string& source) {
  TempDir dir;
  std::string src = dir.write("prog.nqc", source);
  auto r = rcxc::test::run_rcxc({"compile", src, "-o", dir.path + "/prog.rcx"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  auto image = rcx::read_image_file(dir.path + "/prog.rcx");
  EXPECT_TRUE(std::holds_alternative<rcx::Image>(image));
  return std::get<rcx::Image>(image);
}

// The virtual NXT behind a link that counts direct commands by opcode and
// port, and can lose a reply or fail a send.
class CountingLink final : public nxt::Transport {
 public:
  explicit CountingLink(nxt::VirtualNxt& brick) : brick_(brick) {}
  std::optional<nxt::LinkError> send(std::span<const std::uint8_t> t) override {
    if (fail_sends > 0) {
      --fail_sends;
      return nxt::LinkError{nxt::LinkError::Kind::Lost, "the link went down"};
    }
    if (t.size() >= 2 && (t[0] & ~nxt::kNoReplyBit) == nxt::kDirectWithReply)
      ++sent[{t[1], t.size() >= 3 ? t[2] : kNoBody}];
    auto reply = nxt::answer(brick_, t);
    if (reply && lose_reply_to && t.size() >= 2 && t[1] == *lose_reply_to) {
      lose_reply_to.reset();
      return std::nullopt;
    }
    if (reply) replies_.push_back(std::move(*reply));
    return std::nullopt;
  }
  std::variant<std::optional<nxt::Bytes>, nxt::LinkError> receive(nxt::Millis) override {
    if (replies_.empty()) return std::optional<nxt::Bytes>{};
    nxt::Bytes r = std::move(replies_.front());
    replies_.pop_front();
    return std::optional<nxt::Bytes>(std::move(r));
  }
  std::string describe() const override { return "counting link"; }
  static constexpr std::uint8_t kNoBody = 0xFF;
  // Direct telegrams, with or without reply, by (opcode, first body byte:
  // the port or queue, kNoBody without a body).
  int count(std::uint8_t opcode, std::uint8_t port) const {
    auto it = sent.find({opcode, port});
    return it == sent.end() ? 0 : it->second;
  }
  std::map<std::pair<std::uint8_t, std::uint8_t>, int> sent;
  std::optional<std::uint8_t> lose_reply_to;
  int fail_sends = 0;

 private:
  nxt::VirtualNxt& brick_;
  std::deque<nxt::Bytes> replies_;
};

constexpr std::uint8_t kGetInputValues = 0x07;

struct Rig {
  nxt::VirtualNxt brick;
  CountingLink link{brick};
  nxt::Client client{link};
  rcx::Machine machine;
  TetherOptions options;
  TetherStats stats;
  std::int64_t now_us = 0;
  std::function<void(std::int64_t)> at_each_step;  // what happens outside as time goes by

  Rig(const rcx::Image& image, std::vector<nxt::ScenarioInput> scenario, std::int64_t limit_ms)
      : brick(nxt::make_virtual_nxt(std::move(scenario))) {
    EXPECT_FALSE(machine.load(0, image));
    machine.start_program();
    options.limit_us = limit_ms * 1000;
    options.io = rcx::program_io(image);
    options.clock_us = [this] { return now_us; };
    options.pause_us = [this](std::int64_t us) {
      now_us += us;
      nxt::advance_to(brick, now_us);
      if (at_each_step) at_each_step(now_us);
    };
    client.timeout = nxt::Millis(5);
  }
  std::string run() { return run_tethered(machine, client, options, stats); }
  int global(const rcx::Image& image, const std::string& name) const {
    for (const auto& s : image.symbols)
      if (s.type == rcx::SymbolType::Variable && s.name == name) return machine.state().vars[s.index];
    ADD_FAILURE() << "no global " << name;
    return 0;
  }
  // Every motor braked at power 0: what the tether leaves behind.
  void expect_motors_stopped() const {
    for (const auto& m : brick.motors) {
      EXPECT_EQ(m.power, 0);
      EXPECT_EQ(m.mode, nxt::kMotorOn | nxt::kBrake);
    }
  }
};

nxt::ScenarioInput input_at(std::int64_t ms, int port = -1) {
  nxt::ScenarioInput in;
  in.at_ms = ms;
  in.port = port;
  return in;
}
nxt::ScenarioInput raw_at(std::int64_t ms, int port, int raw) {
  nxt::ScenarioInput in = input_at(ms, port);
  in.raw = raw;
  return in;
}

TEST(NxtTether, PollsOnlyTheSensorsTheProgramReads) {
  // Sensors 1 and 3 are configured (their NXT ports get a type, for power)
  // but never read; sensor 2 is read without a type.
  auto image = compile(R"(
int seen;
task main() {
  SetSensor(SENSOR_1, SENSOR_TOUCH);
  SetSensor(SENSOR_3, SENSOR_LIGHT);
  until (SENSOR_2 < 500);
  seen = SENSOR_2;
  OnFwd(OUT_A);
  Wait(20);
}
)");
  Rig rig(image, {raw_at(300, 1, 321)}, 1000);
  ASSERT_EQ(rig.run(), "");
  EXPECT_EQ(rig.global(image, "seen"), 321);
  EXPECT_GT(rig.link.count(kGetInputValues, 1), 5);
  EXPECT_EQ(rig.link.count(kGetInputValues, 0), 0);
  EXPECT_EQ(rig.link.count(kGetInputValues, 2), 0);
  EXPECT_EQ(rig.link.count(kGetInputValues, 3), 0);
  EXPECT_EQ(rig.stats.polls_per_input, (std::array<int, 3>{0, rig.link.count(kGetInputValues, 1), 0}));
  EXPECT_EQ(rig.brick.sensors[0].type, *nxt::sensor_type_named("SWITCH"));
  EXPECT_EQ(rig.brick.sensors[2].type, *nxt::sensor_type_named("REFLECTION"));
  EXPECT_EQ(rig.brick.sensors[1].type, *nxt::sensor_type_named("CUSTOM"));
  // The reading came within one poll period of the change at 300 ms.
  const auto& events = rig.machine.state().events;
  auto on = std::find_if(events.begin(), events.end(), [](const rcx::Event& e) {
    return e.kind == rcx::EventKind::Output && e.output.mode == rcx::OutputMode::On;
  });
  ASSERT_NE(on, events.end());
  EXPECT_GE(on->t_us, 300'000);
  EXPECT_LE(on->t_us, 300'000 + rcxc::cli::kTetherPollUs + 10'000);
}

TEST(NxtTether, AHostThatStalledReadsAtThePresentNotAtTheGridPointsItMissed) {
  // The host gets no CPU from 400 to 1000 ms; the sensor changes at 800.
  // Polling for the missed grid point at 450 would hand the program at
  // 450 ms what the brick only saw at 800.
  auto image = compile(R"(
task main() {
  until (SENSOR_2 < 500);
  OnFwd(OUT_A);
  Wait(20);
}
)");
  Rig rig(image, {raw_at(800, 1, 321)}, 2000);
  bool stalled = false;
  rig.at_each_step = [&](std::int64_t now) {
    if (stalled || now < 400'000) return;
    stalled = true;
    rig.now_us = 1'000'000;
    nxt::advance_to(rig.brick, rig.now_us);
  };
  ASSERT_EQ(rig.run(), "");
  const auto& events = rig.machine.state().events;
  auto on = std::find_if(events.begin(), events.end(), [](const rcx::Event& e) {
    return e.kind == rcx::EventKind::Output && e.output.mode == rcx::OutputMode::On;
  });
  ASSERT_NE(on, events.end());
  EXPECT_GE(on->t_us, 800'000);
  EXPECT_LE(on->t_us, 1'000'000 + 10'000);
  // How far behind the grid it fell is reported (cmd_run prints it).
  EXPECT_GE(rig.stats.worst_poll_lag_us, 500'000);
}

TEST(NxtTether, AProgramThatReadsNoSensorPollsNone) {
  auto image = compile("task main() { SetSensor(SENSOR_1, SENSOR_TOUCH); OnFwd(OUT_B); Wait(30); }");
  Rig rig(image, {}, 1000);
  ASSERT_EQ(rig.run(), "");
  EXPECT_EQ(rig.stats.polls, 0);
  for (std::uint8_t port = 0; port < 4; ++port) EXPECT_EQ(rig.link.count(kGetInputValues, port), 0);
}

TEST(NxtTether, ARotationSensorIsTheNxtAngleCount) {
  auto image = compile(R"(
int turns;
task main() {
  SetSensor(SENSOR_3, SENSOR_ROTATION);
  until (SENSOR_3 >= 32);
  turns = SENSOR_3;
}
)");
  nxt::ScenarioInput turned = input_at(200, 2);
  turned.rotation = 40;
  Rig rig(image, {turned}, 1000);
  ASSERT_EQ(rig.run(), "");
  EXPECT_EQ(rig.brick.sensors[2].type, *nxt::sensor_type_named("ANGLE"));
  EXPECT_EQ(rig.brick.sensors[2].mode, *nxt::sensor_mode_named("ANGLESTEPSMODE"));
  EXPECT_EQ(rig.global(image, "turns"), 40);
  EXPECT_EQ(rig.machine.stop().kind, rcx::StopKind::Ended);
}

TEST(NxtTether, LightIsPrimedSoTheProgramNeverSeesAnOpenInput) {
  // Without a first reading before the start, the program would see the
  // emulator's open input (raw 1023, light 0) at time 0.
  auto image = compile(R"(
int first;
task main() {
  SetSensor(SENSOR_2, SENSOR_LIGHT);
  first = SENSOR_2;
}
)");
  Rig rig(image, {raw_at(0, 1, 500)}, 500);
  ASSERT_EQ(rig.run(), "");
  EXPECT_GT(rig.global(image, "first"), 0);
}

TEST(NxtTether, MessagesBothWays) {
  auto image = compile(R"(
int got;
task main() {
  until (Message() != 0);
  got = Message();
  SendMessage(got + 1);
  Wait(10);
}
)");
  Rig rig(image, {}, 2000);
  ASSERT_FALSE(nxt::start_program(rig.brick, "idle.rxe"));
  // Another host writes 41 into mailbox 1 at 300 ms, over its own link.
  nxt::InProcessTransport other_link([&](std::span<const std::uint8_t> t) { return nxt::answer(rig.brick, t); });
  nxt::Client other(other_link);
  bool written = false;
  rig.at_each_step = [&](std::int64_t now) {
    if (written || now < 300'000) return;
    written = true;
    auto r = nxt::call_ok(other, "MessageWrite", std::vector<nxt::Value>{std::int64_t{0}, std::int64_t{0}, nxt::message_int(41)});
    EXPECT_TRUE(std::holds_alternative<nxt::Decoded>(r));
  };
  ASSERT_EQ(rig.run(), "");
  EXPECT_EQ(rig.global(image, "got"), 41);
  EXPECT_EQ(rig.stats.messages_received, 1);
  EXPECT_TRUE(rig.stats.notes.empty());
  // The program's SendMessage(42) waits in mailbox 11 (queue 10) for a master.
  auto r = nxt::call_ok(other, "MessageRead", std::vector<nxt::Value>{std::int64_t{10}, std::int64_t{0}, std::int64_t{1}});
  ASSERT_TRUE(std::holds_alternative<nxt::Decoded>(r));
  const auto& d = std::get<nxt::Decoded>(r);
  EXPECT_EQ(d.number("size"), 5);
  auto data = *d.bytes("data");
  data.resize(5);
  EXPECT_EQ(data, nxt::message_int(42));
}

TEST(NxtTether, WithoutAProgramOnTheNxtMessagesGoNowhereAndTheUserIsTold) {
  auto image = compile("task main() { SendMessage(3); Wait(100); }");
  Rig rig(image, {}, 500);
  ASSERT_EQ(rig.run(), "");
  ASSERT_EQ(rig.stats.notes.size(), 1u);
  EXPECT_NE(rig.stats.notes[0].find("no program runs on the NXT"), std::string::npos);
  EXPECT_EQ(rig.link.count(0x09, 10), 0);  // no MessageWrite the brick would refuse
  EXPECT_EQ(rig.link.count(0x11, CountingLink::kNoBody), 1);  // it asked GetCurrentProgramName
}

TEST(NxtTether, RcxMessagesFromMailboxForms) {
  using rcxc::cli::rcx_message;
  EXPECT_EQ(rcx_message(nxt::message_int(7)), 7);
  EXPECT_EQ(rcx_message(nxt::message_float(150.0f)), 150);
  EXPECT_EQ(rcx_message(nxt::message_text("42")), 42);
  EXPECT_EQ(rcx_message(nxt::message_int(256)), std::nullopt);
  EXPECT_EQ(rcx_message(nxt::message_float(1.5f)), std::nullopt);
  EXPECT_EQ(rcx_message(nxt::message_text("hello")), std::nullopt);
  EXPECT_EQ(rcx_message(nxt::message_text("300")), std::nullopt);
  EXPECT_EQ(rcx_message(nxt::Bytes{7, 0, 0, 0}), std::nullopt);  // no NUL
}

// A motor left running on a robot is the failure that matters: every way a
// run can end leaves every motor braked at power 0.
const char* kDrivesAndReads = R"(
task main() {
  SetSensor(SENSOR_1, SENSOR_TOUCH);
  OnFwd(OUT_A + OUT_C);
  until (SENSOR_1 == 1);
}
)";

TEST(NxtTether, ALostReplyEndsTheRunAndStillStopsTheMotors) {
  auto image = compile(kDrivesAndReads);
  Rig rig(image, {}, 2000);
  rig.at_each_step = [&](std::int64_t now) {
    if (now >= 200'000 && now < 202'000) {
      rig.link.lose_reply_to = kGetInputValues;
    }
  };
  std::string error = rig.run();
  EXPECT_NE(error.find("no reply to GetInputValues"), std::string::npos) << error;
  rig.expect_motors_stopped();
}

TEST(NxtTether, ALinkThatFailsEndsTheRunAndTheStopIsStillTried) {
  auto image = compile(kDrivesAndReads);
  Rig rig(image, {}, 2000);
  rig.at_each_step = [&](std::int64_t now) {
    if (now >= 200'000 && now < 202'000) {
      rig.link.fail_sends = 1;
    }
  };
  EXPECT_EQ(rig.run(), "the link went down");
  // The link came back for the stop (a Bluetooth hiccup): the motors stopped.
  rig.expect_motors_stopped();
}

TEST(NxtTether, AProgramFaultStopsTheMotors) {
  auto image = compile("task main() { OnFwd(OUT_B); Wait(20); }");
  // A byte that is no opcode after the Wait: the emulator faults there.
  for (auto& f : image.fragments) f.code.push_back(0xFF);
  Rig rig(image, {}, 1000);
  ASSERT_EQ(rig.run(), "");
  EXPECT_EQ(rig.machine.stop().kind, rcx::StopKind::Fault);
  rig.expect_motors_stopped();
  EXPECT_GT(rig.brick.motors[1].tacho_count, 0.0);  // it did run before
}

TEST(NxtTether, InterruptedRunsStopTheMotors) {
  auto image = compile(kDrivesAndReads);
  Rig rig(image, {}, 5000);
  int stop = ::eventfd(0, EFD_CLOEXEC);
  ASSERT_GE(stop, 0);
  rig.options.stop_fd = stop;
  rig.at_each_step = [&](std::int64_t now) {
    std::uint64_t one = 1;
    if (now >= 300'000 && now < 302'000) {
      EXPECT_EQ(::write(stop, &one, sizeof one), 8);
    }
  };
  EXPECT_EQ(rig.run(), "interrupted");
  EXPECT_LT(rig.now_us, 400'000);
  rig.expect_motors_stopped();
  ::close(stop);
}

TEST(NxtTether, KeepAliveAndBatteryEveryThirtySeconds) {
  auto image = compile("task main() { Wait(7000); }");  // 70 s
  nxt::ScenarioInput low = input_at(40'000);
  low.battery_mv = 6900;
  Rig rig(image, {low}, 70'000);
  rig.brick.sleep_minutes = 1;
  ASSERT_EQ(rig.run(), "");
  EXPECT_EQ(rig.link.count(0x0D, CountingLink::kNoBody), 3);  // KeepAlive at 0, 30 and 60 s
  EXPECT_EQ(rig.link.count(0x0B, CountingLink::kNoBody), 3);  // the battery at 0, 30 and 60 s
  EXPECT_EQ(rig.machine.state().battery_mv, 6900);
  EXPECT_FALSE(rig.brick.asleep);  // a one-minute sleep limit, 70 s of run
}

}  // namespace
