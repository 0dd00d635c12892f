// The host client against the virtual NXT in process, on a virtual clock:
// a round trip for every command of the table, then the firmware behaviour
// spec/nxt.md describes (expected values are the spec's, not the brick's).
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <set>

#include <fmt/format.h>

#include "nxt/client.h"
#include "nxt/virtual_nxt.h"
#include "runtime/sensors.h"
#include "tests/nxt/round_trips.h"

namespace nxt {
namespace {

using V = std::vector<Value>;

struct Rig {
  VirtualNxt brick;
  InProcessTransport link;
  Client client;
  explicit Rig(std::vector<ScenarioInput> scenario = {})
      : brick(make_virtual_nxt(std::move(scenario))),
        link([this](std::span<const std::uint8_t> t) { return answer(brick, t); }),
        client(link) {
    client.pause = [this](Millis m) { advance_ms(static_cast<int>(m.count())); };
  }
  void advance_ms(std::int64_t ms) { advance_to(brick, brick.now_us + ms * 1000); }
  // The reply (any status); fails the test if there is none.
  Decoded reply(std::string_view name, V values = {}) {
    auto r = call(client, *find_command(name), values);
    if (auto* e = std::get_if<CallError>(&r)) {
      ADD_FAILURE() << name << ": " << e->message;
      return {};
    }
    return std::get<Decoded>(r);
  }
  std::uint8_t status_of(std::string_view name, V values = {}) { return reply(name, std::move(values)).status; }
  void put_file(const std::string& name, const Bytes& data) {
    ASSERT_FALSE(upload_file(client, name, data)) << name;
  }
  void start_program() {
    put_file("prog.rxe", Bytes(10, 1));
    ASSERT_EQ(status_of("StartProgram", {std::string("prog.rxe")}), 0);
  }
};

Value n(std::int64_t v) { return v; }

// A scenario input at `ms` on `port` (-1: none), its value set by the caller.
ScenarioInput input_at(std::int64_t ms, int port = -1) {
  ScenarioInput in;
  in.at_ms = ms;
  in.port = port;
  return in;
}
ScenarioInput raw_at(std::int64_t ms, int port, int raw) {
  ScenarioInput in = input_at(ms, port);
  in.raw = raw;
  return in;
}
Value s(std::string v) { return v; }

TEST(VirtualNxt, EveryCommandOfTheTableMakesARoundTrip) {
  Rig rig;
  test::every_command_round_trip(rig.client);
  EXPECT_EQ(rig.brick.name, "Robo");
  EXPECT_TRUE(rig.brick.files.empty());  // DeleteUserFlash
}

TEST(VirtualNxt, FilesUploadListDownloadDelete) {
  Rig rig;
  Bytes data(200);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7);
  std::vector<std::size_t> seen;
  ASSERT_FALSE(upload_file(rig.client, "big.dat", data, [&](std::size_t done, std::size_t) { seen.push_back(done); }));
  EXPECT_EQ(seen, (std::vector<std::size_t>{58, 116, 174, 200}));
  rig.put_file("x.rxe", Bytes(3, 9));
  auto listed = std::get<std::vector<FileEntry>>(list_files(rig.client, "*.*"));
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[0].name, "big.dat");
  EXPECT_EQ(listed[0].size, 200u);
  EXPECT_EQ(std::get<std::vector<FileEntry>>(list_files(rig.client, "*.rxe")).size(), 1u);
  EXPECT_EQ(std::get<std::vector<FileEntry>>(list_files(rig.client, "big.*")).size(), 1u);
  EXPECT_TRUE(std::get<std::vector<FileEntry>>(list_files(rig.client, "*.rso")).empty());  // 0x87, not an error
  EXPECT_EQ(std::get<Bytes>(download_file(rig.client, "big.dat")), data);
  EXPECT_TRUE(rig.brick.files["x.rxe"].linear);  // OpenWrite makes .rxe linear by itself
  EXPECT_FALSE(rig.brick.files["big.dat"].linear);
  EXPECT_EQ(rig.status_of("Delete", {s("big.dat")}), 0);
  EXPECT_EQ(rig.status_of("Delete", {s("big.dat")}), status::kFileNotFound);
  // Every handle is free again.
  for (const auto& h : rig.brick.handles) EXPECT_FALSE(h.has_value());
}

TEST(VirtualNxt, FileSystemErrorCodes) {
  Rig rig;
  rig.put_file("a.txt", Bytes{1});
  EXPECT_EQ(rig.status_of("OpenWrite", {s("a.txt"), n(1)}), status::kFileExists);
  EXPECT_EQ(rig.status_of("OpenWrite", {s("sixteen_chars_xx.tx"), n(1)}), status::kIllegalFileName);  // 16.2
  EXPECT_EQ(rig.status_of("OpenWriteData", {s("p.rxe"), n(1)}), status::kIllegalFileName);
  EXPECT_EQ(rig.status_of("OpenWrite", {s("huge.dat"), n(10'000'000)}), status::kNoSpace);
  EXPECT_EQ(rig.status_of("OpenRead", {s("none.txt")}), status::kFileNotFound);
  EXPECT_EQ(rig.status_of("Close", {n(3)}), status::kHandleClosed);
  EXPECT_EQ(rig.status_of("Close", {n(200)}), status::kIllegalHandle);
  // Reading past the end: 0x85, and the firmware has closed the handle.
  auto open = rig.reply("OpenRead", {s("a.txt")});
  auto h = *open.number("handle");
  EXPECT_EQ(rig.status_of("OpenRead", {s("a.txt")}), status::kFileBusy);
  EXPECT_EQ(rig.status_of("Read", {n(h), n(10)}), 0);
  EXPECT_EQ(rig.status_of("Read", {n(h), n(10)}), status::kEndOfFile);
  EXPECT_EQ(rig.status_of("Close", {n(h)}), status::kHandleClosed);
  // Writing more than declared: file full, handle closed.
  auto w = *rig.reply("OpenWrite", {s("b.txt"), n(2)}).number("handle");
  EXPECT_EQ(rig.status_of("Write", {n(w), Bytes{1, 2, 3}}), status::kFileFull);
  EXPECT_EQ(rig.status_of("Write", {n(w), Bytes{1}}), status::kHandleClosed);
  // Sixteen handles, then no more.
  for (int i = 0; i < 16; ++i) EXPECT_EQ(rig.status_of("OpenWrite", {s(fmt::format("f{}.txt", i)), n(1)}), 0);
  EXPECT_EQ(rig.status_of("OpenWrite", {s("g.txt"), n(1)}), status::kNoMoreHandles);
}

TEST(VirtualNxt, DataFilesAppend) {
  Rig rig;
  auto h = *rig.reply("OpenWriteData", {s("log.dat"), n(10)}).number("handle");
  EXPECT_EQ(rig.status_of("Write", {n(h), Bytes{1, 2}}), 0);
  EXPECT_EQ(rig.status_of("Close", {n(h)}), 0);
  auto a = rig.reply("OpenAppendData", {s("log.dat")});
  EXPECT_EQ(a.status, 0);
  EXPECT_EQ(a.number("available"), 8);
  EXPECT_EQ(rig.status_of("Write", {n(*a.number("handle")), Bytes{3}}), 0);
  EXPECT_EQ(rig.brick.files["log.dat"].data, (Bytes{1, 2, 3}));
}

TEST(VirtualNxt, ProgramsStartOnlyFromExistingFilesAndResetTheMotors) {
  Rig rig;
  // The firmware answers 0xC0 for a missing file (the seed says 0xBD).
  EXPECT_EQ(rig.status_of("StartProgram", {s("none.rxe")}), status::kOutOfRange);
  EXPECT_EQ(rig.status_of("StopProgram"), status::kNoProgram);
  auto none = rig.reply("GetCurrentProgramName");
  EXPECT_EQ(none.status, status::kNoProgram);
  EXPECT_EQ(none.text("name"), "");  // zero-filled
  rig.status_of("SetOutputState", {n(0), n(50), n(1), n(0), n(0), n(0x20), n(0)});
  rig.advance_ms(100);
  rig.start_program();
  EXPECT_EQ(rig.reply("GetCurrentProgramName").text("name"), "prog.rxe");
  auto m = rig.reply("GetOutputState", {n(0)});
  EXPECT_EQ(m.number("power"), 0);
  EXPECT_EQ(m.number("tacho_count"), 0);
}

// spec/nxt.md: starting or stopping a program resets all motors and sensors.
TEST(VirtualNxt, StartingAndStoppingAProgramResetMotorsAndSensors) {
  Rig rig;
  auto configure = [&] {
    rig.status_of("SetInputMode", {n(1), n(0x01), n(0x20)});  // SWITCH, BOOLEANMODE
    rig.status_of("SetOutputState", {n(2), n(-40), n(0x01), n(0), n(0), n(0x20), n(0)});
    rig.advance_ms(50);
    ASSERT_EQ(rig.reply("GetInputValues", {n(1)}).number("type"), 0x01);
    ASSERT_EQ(rig.reply("GetOutputState", {n(2)}).number("power"), -40);
  };
  auto expect_reset = [&](const char* when) {
    auto in = rig.reply("GetInputValues", {n(1)});
    EXPECT_EQ(in.number("type"), 0) << when;
    EXPECT_EQ(in.number("mode"), 0) << when;
    auto out = rig.reply("GetOutputState", {n(2)});
    EXPECT_EQ(out.number("power"), 0) << when;
    EXPECT_EQ(out.number("mode"), 0) << when;
    EXPECT_EQ(out.number("run_state"), 0) << when;
    EXPECT_EQ(out.number("tacho_count"), 0) << when;
  };
  configure();
  rig.start_program();
  expect_reset("after StartProgram");
  configure();
  ASSERT_EQ(rig.status_of("StopProgram"), 0);
  expect_reset("after StopProgram");
}

TEST(VirtualNxt, MailboxesNeedAProgramAndHoldFiveMessages) {
  Rig rig;
  EXPECT_EQ(rig.status_of("MessageWrite", {n(0), n(0), message_text("a")}), status::kNoProgram);
  rig.start_program();
  EXPECT_EQ(rig.status_of("MessageRead", {n(0), n(0), n(1)}), status::kQueueEmpty);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(rig.status_of("MessageWrite", {n(2), n(0), message_text(std::to_string(i))}), 0);
  // Six written into a queue of five: the oldest ("0") was dropped.
  auto first = rig.reply("MessageRead", {n(2), n(7), n(1)});
  EXPECT_EQ(first.number("local_inbox"), 7);
  EXPECT_EQ(first.number("size"), 2);
  EXPECT_EQ(first.bytes("data")->at(0), '1');
  // remove = false leaves it there.
  EXPECT_EQ(rig.reply("MessageRead", {n(2), n(2), n(0)}).bytes("data")->at(0), '2');
  EXPECT_EQ(rig.reply("MessageRead", {n(2), n(2), n(1)}).bytes("data")->at(0), '2');
  EXPECT_EQ(rig.status_of("MessageWrite", {n(20), n(0), message_text("a")}), status::kIllegalQueue);
  EXPECT_EQ(rig.status_of("MessageRead", {n(20), n(0), n(1)}), status::kIllegalQueue);
  EXPECT_EQ(rig.status_of("MessageWrite", {n(0), n(0), Bytes{'n', 'o'}}), status::kOutOfRange);  // no NUL
  EXPECT_EQ(rig.status_of("MessageWrite", {n(0), n(0), Bytes{}}), status::kOutOfRange);          // size 0
  EXPECT_EQ(rig.status_of("MessageWrite", {n(0), n(0), Bytes(60, 0)}), status::kOutOfRange);     // over 59
  // Numbers as NXC (int32 LE + NUL) and NXT-G (float32 LE + NUL) send them.
  EXPECT_EQ(message_int(-2), (Bytes{0xFE, 0xFF, 0xFF, 0xFF, 0}));
  EXPECT_EQ(message_float(1.0f), (Bytes{0x00, 0x00, 0x80, 0x3F, 0}));
  EXPECT_EQ(show_message(message_text("hi")), "hi");
}

TEST(VirtualNxt, MotorsTurnWithPowerAndTimeAndStopAtTheLimit) {
  Rig rig;
  // Power 50: 500 degrees a second in this model.
  rig.status_of("SetOutputState", {n(0), n(50), n(kMotorOn), n(0), n(0), n(0x20), n(0)});
  rig.advance_ms(1000);
  EXPECT_EQ(rig.reply("GetOutputState", {n(0)}).number("tacho_count"), 500);
  rig.status_of("SetOutputState", {n(0), n(-100), n(kMotorOn | kBrake), n(0), n(0), n(0x20), n(360)});
  rig.advance_ms(200);
  auto mid = rig.reply("GetOutputState", {n(0)});
  EXPECT_EQ(mid.number("tacho_count"), 300);
  EXPECT_EQ(mid.number("run_state"), 0x20);
  rig.advance_ms(1000);
  auto done = rig.reply("GetOutputState", {n(0)});
  EXPECT_EQ(done.number("tacho_count"), 140);  // 500 - 360
  EXPECT_EQ(done.number("run_state"), kRunStateIdle);
  EXPECT_EQ(done.number("mode"), kMotorOn | kBrake);
  EXPECT_EQ(done.number("tacho_limit"), 360);
  rig.status_of("ResetMotorPosition", {n(0), n(1)});
  auto reset = rig.reply("GetOutputState", {n(0)});
  EXPECT_EQ(reset.number("block_tacho_count"), 0);
  EXPECT_EQ(reset.number("rotation_count"), 140);
  rig.status_of("UpdateResetCount", {n(0)});
  EXPECT_EQ(rig.reply("GetOutputState", {n(0)}).number("tacho_count"), 0);
  // Port 0xFF drives all three.
  rig.status_of("SetOutputState", {n(0xFF), n(10), n(kMotorOn), n(0), n(0), n(0x20), n(0)});
  rig.advance_ms(1000);
  EXPECT_EQ(rig.reply("GetOutputState", {n(2)}).number("tacho_count"), 100);
}

TEST(VirtualNxt, AnIllegalPortAnswersC0WithAFullZeroBody) {
  Rig rig;
  auto r = *answer(rig.brick, Bytes{0x00, 0x06, 0x03});
  EXPECT_EQ(r.size(), 25u);
  EXPECT_EQ(r[2], status::kOutOfRange);
  EXPECT_TRUE(std::all_of(r.begin() + 3, r.end(), [](auto b) { return b == 0; }));
  EXPECT_EQ(rig.status_of("GetInputValues", {n(4)}), status::kOutOfRange);
  EXPECT_EQ(rig.status_of("SetOutputState", {n(3), n(0), n(0), n(0), n(0), n(0), n(0)}), status::kOutOfRange);
}

TEST(VirtualNxt, SensorsFollowTheScenarioAfterTheValidDelay) {
  ScenarioInput battery = input_at(400);
  battery.battery_mv = 7100;
  std::vector<ScenarioInput> scenario{raw_at(100, 0, 200), raw_at(300, 0, 800), battery};
  Rig rig(scenario);
  rig.status_of("SetInputMode", {n(0), n(0x01), n(0x20)});
  EXPECT_EQ(rig.reply("GetInputValues", {n(0)}).number("valid"), 0);
  rig.advance_ms(19);
  EXPECT_EQ(rig.reply("GetInputValues", {n(0)}).number("valid"), 0);
  rig.advance_ms(1);
  auto v = rig.reply("GetInputValues", {n(0)});
  EXPECT_EQ(v.number("valid"), 1);
  EXPECT_EQ(v.number("raw"), 1023);
  EXPECT_EQ(v.number("scaled"), 0);
  rig.advance_ms(100);  // 120 ms: raw 200, pressed
  v = rig.reply("GetInputValues", {n(0)});
  EXPECT_EQ(v.number("raw"), 200);
  EXPECT_EQ(v.number("scaled"), 1);
  EXPECT_EQ(v.number("calibrated_value"), 200);  // the firmware returns the normalized value here
  rig.advance_ms(300);
  EXPECT_EQ(rig.reply("GetInputValues", {n(0)}).number("scaled"), 0);
  EXPECT_EQ(rig.reply("GetBatteryLevel").number("millivolts"), 7100);
  // Transition count mode counts the edges since the mode was set.
  rig.status_of("SetInputMode", {n(1), n(0x01), n(0x40)});
  EXPECT_EQ(rig.reply("GetInputValues", {n(1)}).number("scaled"), 0);
  // Sound sensors take 300 ms to become valid.
  rig.status_of("SetInputMode", {n(2), n(kSoundDb), n(0x80)});
  rig.advance_ms(299);
  EXPECT_EQ(rig.reply("GetInputValues", {n(2)}).number("valid"), 0);
  rig.advance_ms(1);
  EXPECT_EQ(rig.reply("GetInputValues", {n(2)}).number("valid"), 1);
  // Colour sensors (types 0x0D-0x11) take 400 ms.
  for (int type = 0x0D; type <= 0x11; ++type) {
    rig.status_of("SetInputMode", {n(3), n(type), n(0)});
    rig.advance_ms(399);
    EXPECT_EQ(rig.reply("GetInputValues", {n(3)}).number("valid"), 0) << type;
    rig.advance_ms(1);
    EXPECT_EQ(rig.reply("GetInputValues", {n(3)}).number("valid"), 1) << type;
  }
}

// An RCX temperature sensor on an NXT (type TEMPERATURE): the firmware holds
// the raw value to 290..928, converts it to tenths of a degree, maps that
// onto the normalized 0..1023 ((t + 200) x 1023 / 900) and works every mode
// from there. The virtual NXT used the line (785 - raw) / 8 on the raw
// value, up to 8 degrees off, read 63.1 °C for an open input and passed raw
// values outside the sensor's range through.
TEST(VirtualNxt, ARcxTemperatureSensorReadsAsTheNxtFirmwareConvertsIt) {
  Rig rig({raw_at(100, 1, 290), raw_at(200, 1, 600), raw_at(300, 1, 100)});
  rig.status_of("SetInputMode", {n(1), n(0x02), n(0xA0)});  // TEMPERATURE, CELSIUSMODE
  rig.advance_ms(20);
  auto open = rig.reply("GetInputValues", {n(1)});  // raw 1023, held to 928: -19.8 °C
  EXPECT_EQ(open.number("raw"), 1023);
  EXPECT_EQ(open.number("normalized"), 2);
  EXPECT_EQ(open.number("scaled"), -199);
  rig.advance_ms(100);
  auto hot = rig.reply("GetInputValues", {n(1)});  // 69.5 °C
  EXPECT_EQ(hot.number("normalized"), 1017);
  EXPECT_EQ(hot.number("calibrated_value"), 1017);
  EXPECT_EQ(hot.number("scaled"), 694);
  rig.advance_ms(100);
  EXPECT_EQ(rig.reply("GetInputValues", {n(1)}).number("scaled"), 209);  // 21.0 °C, 20.9 after the mapping
  rig.status_of("SetInputMode", {n(1), n(0x02), n(0xC0)});  // FAHRENHEITMODE
  rig.advance_ms(20);
  EXPECT_EQ(rig.reply("GetInputValues", {n(1)}).number("scaled"), 696);  // 69.6 °F
  rig.advance_ms(100);  // raw 100, held to 290
  EXPECT_EQ(rig.reply("GetInputValues", {n(1)}).number("scaled"), 1569);
}

// Below 0 °C the firmware's Fahrenheit sum, done in unsigned 32-bit
// arithmetic and kept to 16 bits, wraps: the NXT reads thousands of degrees.
TEST(VirtualNxt, FahrenheitBelowFreezingWrapsAsTheFirmwaresSumDoes) {
  Rig rig;
  rig.status_of("SetInputMode", {n(0), n(0x02), n(0xC0)});  // open input: -19.9 °C after the mapping
  rig.advance_ms(20);
  EXPECT_EQ(rig.reply("GetInputValues", {n(0)}).number("scaled"), 23554);
}

// Every raw value in the sensor's range reads within two tenths of a degree
// of what the RCX emulator reads for it (the same curve; the NXT's mapping
// onto 0..1023 and back loses up to two tenths).
TEST(VirtualNxt, TheTemperatureCurveIsTheRcxEmulatorsOne) {
  for (int raw = 290; raw <= 928; raw += 1) {
    Rig rig({raw_at(10, 0, raw)});
    rig.status_of("SetInputMode", {n(0), n(0x02), n(0xA0)});
    rig.advance_ms(20);
    int nxt_tenths = static_cast<int>(rig.reply("GetInputValues", {n(0)}).number("scaled").value_or(-9999));
    int rcx_tenths = rcx::celsius_tenths_of_raw(raw);
    EXPECT_LE(std::abs(nxt_tenths - rcx_tenths), 2) << "raw " << raw << ": " << nxt_tenths << " vs " << rcx_tenths;
  }
}

TEST(VirtualNxt, AnAngleSensorCountsRotationSinceItsModeWasSet) {
  ScenarioInput turned = input_at(100, 2), back = input_at(200, 2);
  turned.rotation = 40;
  back.rotation = 24;
  Rig rig({turned, back});
  rig.status_of("SetInputMode", {n(2), n(0x04), n(0xE0)});  // ANGLE, ANGLESTEPSMODE
  rig.advance_ms(150);
  EXPECT_EQ(rig.reply("GetInputValues", {n(2)}).number("scaled"), 40);
  rig.status_of("ResetInputScaledValue", {n(2)});
  EXPECT_EQ(rig.reply("GetInputValues", {n(2)}).number("scaled"), 0);
  rig.advance_ms(100);  // the shaft went back 16 steps
  EXPECT_EQ(rig.reply("GetInputValues", {n(2)}).number("scaled"), -16);
  // Setting the mode again zeroes the count, as the reset does.
  rig.status_of("SetInputMode", {n(2), n(0x04), n(0xE0)});
  EXPECT_EQ(rig.reply("GetInputValues", {n(2)}).number("scaled"), 0);
}

TEST(VirtualNxt, ScenarioMessagesReachAMailboxOnlyWhileAProgramRuns) {
  ScenarioInput early = input_at(10), late = input_at(100);
  early.message = 5;
  late.message = 150;
  late.queue = 2;
  Rig rig({early, late});
  rig.advance_ms(20);  // no program yet: the firmware would refuse a MessageWrite
  EXPECT_EQ(rig.brick.counters.messages_dropped, 1u);
  ASSERT_FALSE(start_program(rig.brick, "idle.rxe"));
  EXPECT_EQ(rig.reply("GetCurrentProgramName").text("name"), "idle.rxe");
  rig.advance_ms(100);
  auto m = rig.reply("MessageRead", {n(2), n(0), n(1)});
  ASSERT_EQ(m.status, 0);
  EXPECT_EQ(m.number("size"), 5);
  Bytes data = m.bytes("data").value_or(Bytes{});
  data.resize(5);
  EXPECT_EQ(data, message_int(150));
  EXPECT_EQ(rig.status_of("MessageRead", {n(0), n(0), n(1)}), status::kQueueEmpty);
  EXPECT_TRUE(start_program(rig.brick, "a.txt").has_value());
  EXPECT_TRUE(start_program(rig.brick, "a_very_long_name.rxe").has_value());
}

TEST(VirtualNxt, UltrasonicOverI2C) {
  ScenarioInput echo = input_at(0, 3);
  echo.distance_cm = 42;
  std::vector<ScenarioInput> scenario{echo};
  Rig rig(scenario);
  // Before the port is LOWSPEED and valid, LS commands fail with 0xE0.
  EXPECT_EQ(rig.status_of("LSWrite", {n(3), n(2), n(1), Bytes{2, 0x42}}), status::kChannelBusy);
  auto cm = read_ultrasonic(rig.client, 3);
  ASSERT_TRUE(std::holds_alternative<int>(cm)) << std::get<CallError>(cm).message;
  EXPECT_EQ(std::get<int>(cm), 42);
  // The product id register reads "LEGO"; a transaction is pending for a few ms.
  EXPECT_EQ(rig.status_of("LSWrite", {n(3), n(2), n(8), Bytes{2, 0x08}}), 0);
  EXPECT_EQ(rig.status_of("LSGetStatus", {n(3)}), status::kPending);
  rig.advance_ms(20);
  EXPECT_EQ(rig.reply("LSGetStatus", {n(3)}).number("bytes_ready"), 8);
  auto read = rig.reply("LSRead", {n(3)});
  EXPECT_EQ(read.number("bytes_read"), 8);
  EXPECT_EQ(text_of(*read.bytes("rx_data")), "LEGO");
  EXPECT_EQ(rig.status_of("LSWrite", {n(3), n(17), n(1), Bytes(17, 2)}), status::kIllegalSize);
  EXPECT_EQ(rig.status_of("LSWrite", {n(3), n(2), n(17), Bytes{2, 0x42}}), status::kIllegalSize);
  // A device at another address does not answer: bus error.
  rig.status_of("LSWrite", {n(3), n(2), n(1), Bytes{4, 0x42}});
  rig.advance_ms(20);
  EXPECT_EQ(rig.status_of("LSGetStatus", {n(3)}), status::kBusError);
}

TEST(VirtualNxt, KeepAliveAndTheSleepTimer) {
  Rig rig;
  EXPECT_EQ(rig.reply("KeepAlive").number("sleep_limit_ms"), 600'000);
  // The firmware keeps whole minutes: 90 s reads back as 60 s.
  rig.status_of("SetProperty", {n(2), Bytes{0x90, 0x5F, 0x01, 0x00}});
  EXPECT_EQ(rig.reply("KeepAlive").number("sleep_limit_ms"), 60'000);
  rig.advance_ms(59'000);
  rig.status_of("GetBatteryLevel");  // ordinary commands do not reset the timer
  rig.advance_ms(2'000);
  rig.client.timeout = Millis(5);
  auto r = call(rig.client, *find_command("KeepAlive"), V{});
  ASSERT_TRUE(std::holds_alternative<CallError>(r));
  EXPECT_EQ(std::get<CallError>(r).kind, CallError::Kind::NoReply);
  EXPECT_TRUE(rig.brick.asleep);
}

TEST(VirtualNxt, TelegramsTheFirmwareDoesNotTake) {
  Rig rig;
  EXPECT_FALSE(answer(rig.brick, Bytes{0x05, 0x0B}));                                 // unknown type: silence
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x55}), (Bytes{0x02, 0x55, 0xBE}));         // unknown opcode
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x12}), (Bytes{0x02, 0x12, 0xBE}));         // GetButtonState
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x03, 0x01}), (Bytes{0x02, 0x03, 0xBF}));   // truncated PlayTone
  EXPECT_FALSE(answer(rig.brick, Bytes{0x80, 0x03, 0xB8, 0x01, 0xF4, 0x01}));          // no reply wanted...
  EXPECT_EQ(rig.brick.sounds.size(), 1u);                                              // ...but it played
  // PlayTone is not range-checked by the brick.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x03, 0x01, 0x00, 0x01, 0x00}), (Bytes{0x02, 0x03, 0x00}));
}

TEST(VirtualNxt, ALateReplyIsDrainedNotTakenForTheNextCommand) {
  Rig rig;
  rig.client.timeout = Millis(1);
  rig.link.late_by = 2;  // the reply comes after the host gave up
  auto r = call(rig.client, *find_command("GetBatteryLevel"), V{});
  ASSERT_TRUE(std::holds_alternative<CallError>(r));
  EXPECT_EQ(std::get<CallError>(r).kind, CallError::Kind::NoReply);
  rig.link.late_by = 0;
  auto fw = call(rig.client, *find_command("GetFirmwareVersion"), V{});
  ASSERT_TRUE(std::holds_alternative<Decoded>(fw));
  EXPECT_EQ(std::get<Decoded>(fw).command->name, "GetFirmwareVersion");
  EXPECT_EQ(rig.client.dropped, 1);
  // A stray reply to another opcode waiting in the line is skipped too.
  rig.link.inbox.push_back(Bytes{0x02, 0x0B, 0x00, 0x10, 0x10});
  rig.link.late_by = 0;
  auto k = call(rig.client, *find_command("KeepAlive"), V{});
  ASSERT_TRUE(std::holds_alternative<Decoded>(k));
  EXPECT_EQ(rig.client.dropped, 2);
}

TEST(VirtualNxt, AReplyThatDoesNotParseSaysWhatCameBack) {
  InProcessTransport link([](std::span<const std::uint8_t>) { return std::optional<Bytes>(Bytes{0x02, 0x0B, 0x00, 0x01}); });
  Client client(link);
  auto r = call(client, *find_command("GetBatteryLevel"), V{});
  ASSERT_TRUE(std::holds_alternative<CallError>(r));
  EXPECT_EQ(std::get<CallError>(r).kind, CallError::Kind::BadReply);
  EXPECT_NE(std::get<CallError>(r).message.find("02 0b 00 01"), std::string::npos) << std::get<CallError>(r).message;
}

TEST(VirtualNxt, HostChecksFileNames) {
  EXPECT_FALSE(check_file_name("prog.rxe"));
  EXPECT_FALSE(check_file_name("fifteen_chars_x.rxe"));
  EXPECT_TRUE(check_file_name("sixteen_chars_xx.rxe"));
  EXPECT_TRUE(check_file_name("a.rxe4"));
  EXPECT_TRUE(check_file_name("dir/a.rxe"));
  EXPECT_TRUE(check_file_name(""));
  Rig rig;
  auto e = upload_file(rig.client, "sixteen_chars_xx.rxe", Bytes{1});
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind, CallError::Kind::Input);
  EXPECT_EQ(rig.brick.counters.requests, 0u);  // nothing was sent
}

// What LEGO's firmware (c_cmd.c, cCmdHandleRemoteCommands and the functions
// it calls) answers where the virtual NXT answered otherwise. Every expected
// telegram below is written by hand from that handler's code.

// A reply of `head` followed by `zeros` zero bytes.
Bytes padded(Bytes head, std::size_t zeros) {
  head.insert(head.end(), zeros, 0);
  return head;
}

TEST(VirtualNxtFirmware, MessageWriteChecksTheSizeThenTheQueueThenTheProgram) {
  Rig rig;
  // No program runs, yet a bad size or a bad queue is what the brick reports.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x09, 0x00, 0x00}), (Bytes{0x02, 0x09, 0xC0}));              // size 0
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x09, 0x00, 0x02, 'A', 'B'}), (Bytes{0x02, 0x09, 0xC0}));    // no NUL
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x09, 0x14, 0x02, 'A', 0x00}), (Bytes{0x02, 0x09, 0xEE}));   // queue 20
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x09, 0x00, 0x02, 'A', 0x00}), (Bytes{0x02, 0x09, 0xEC}));   // all fine but no program
  rig.start_program();
  // The size byte says how much of the data is the message: the rest is ignored.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x09, 0x00, 0x02, 'A', 0x00, 'B', 'C'}), (Bytes{0x02, 0x09, 0x00}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x13, 0x00, 0x05, 0x01}),
            padded({0x02, 0x13, 0x00, 0x05, 0x02, 'A', 0x00}, 57));
}

TEST(VirtualNxtFirmware, MessageReadErrorsEchoTheLocalInboxInAFullReply) {
  Rig rig;
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x13, 0x00, 0x07, 0x01}), padded({0x02, 0x13, 0xEC, 0x07, 0x00}, 59));
  rig.start_program();
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x13, 0x03, 0x09, 0x01}), padded({0x02, 0x13, 0x40, 0x09, 0x00}, 59));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x13, 0x14, 0x04, 0x01}), padded({0x02, 0x13, 0xEE, 0x04, 0x00}, 59));
}

TEST(VirtualNxtFirmware, LsCommandsOnABadPortAnswerTheStatusAlone) {
  Rig rig;
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0E, 0x04}), (Bytes{0x02, 0x0E, 0xC0}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x10, 0x04}), (Bytes{0x02, 0x10, 0xC0}));
  // Port 1 made ready, so a port taken modulo 4 would be accepted.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x05, 0x00, 0x0B, 0x00}), (Bytes{0x02, 0x05, 0x00}));
  rig.advance_ms(100);
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0F, 0x04, 0x02, 0x01, 0x02, 0x42}), (Bytes{0x02, 0x0F, 0xC0}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0F, 0x00, 0x02, 0x01, 0x02, 0x42}), (Bytes{0x02, 0x0F, 0x00}));
}

TEST(VirtualNxtFirmware, LsStatusAndReadOnAPortThatIsNotReadyAnswerE0WithTheirBody) {
  Rig rig;
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0E, 0x00}), (Bytes{0x02, 0x0E, 0xE0, 0x00}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x10, 0x00}), padded({0x02, 0x10, 0xE0, 0x00}, 16));
  // LOWSPEED_9V but not valid yet (the first 20 ms): still not ready.
  answer(rig.brick, Bytes{0x00, 0x05, 0x00, 0x0B, 0x00});
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0E, 0x00}), (Bytes{0x02, 0x0E, 0xE0, 0x00}));
  rig.advance_ms(100);
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0E, 0x00}), (Bytes{0x02, 0x0E, 0x00, 0x00}));
}

TEST(VirtualNxtFirmware, LsWriteWhileATransactionIsOnTheBusIsE0AndItsSizeIsTheLengthByte) {
  Rig rig;
  answer(rig.brick, Bytes{0x00, 0x05, 0x02, 0x0B, 0x00});
  rig.advance_ms(100);
  // tx_length 17 with two bytes sent: the firmware checks the length byte.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0F, 0x02, 0x11, 0x01, 0x02, 0x42}), (Bytes{0x02, 0x0F, 0xED}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0F, 0x02, 0x02, 0x08, 0x02, 0x00}), (Bytes{0x02, 0x0F, 0x00}));
  // Ten bytes at 9600 bit/s are still on the bus: cCmdLSWrite has no 0x20.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0F, 0x02, 0x02, 0x01, 0x02, 0x42}), (Bytes{0x02, 0x0F, 0xE0}));
}

TEST(VirtualNxtFirmware, BytesAfterADirectCommandsFieldsAreIgnored) {
  Rig rig;
  // 7800 mV = 0x1E78, as if the extra byte were not there.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x0B, 0x01}), (Bytes{0x02, 0x0B, 0x00, 0x78, 0x1E}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x06, 0x05, 0xFF}), padded({0x02, 0x06, 0xC0}, 22));
}

TEST(VirtualNxtFirmware, StartProgramOfAFileThatIsNoProgramIsAcceptedAndRunsNothing) {
  Rig rig;
  rig.put_file("a.rso", Bytes(4, 0));
  // The handler only looks the file up; the UI then fails to run it.
  EXPECT_EQ(rig.status_of("StartProgram", {s("a.rso")}), 0);
  EXPECT_EQ(rig.status_of("GetCurrentProgramName"), status::kNoProgram);
}

// From LEGO's c_loader.c (one module search, apart from the file handles)
// and the reply assembly of its c_comm.c.
TEST(VirtualNxtFirmware, OneModuleSearchAtATimeWithHandleZero) {
  Rig rig;
  auto first = rig.reply("FindFirstModule", {s("*.mod")});
  EXPECT_EQ(first.status, 0);
  EXPECT_EQ(first.number("handle"), 0);
  EXPECT_EQ(first.text("name"), "Command.mod");
  // A second search before CloseModuleHandle: no more handles, zero body.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x90, '*', '.', '*', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}),
            padded({0x02, 0x90, 0x81}, 31));
  // FindNextModule goes on with the one search whatever handle it names.
  auto next = rig.reply("FindNextModule", {n(9)});
  EXPECT_EQ(next.status, 0);
  EXPECT_EQ(next.number("handle"), 0);
  EXPECT_EQ(next.text("name"), "Output.mod");
  // File handles are untouched by module searches: the first file gets 0.
  rig.put_file("a.txt", Bytes{1});
  EXPECT_EQ(rig.reply("OpenRead", {s("a.txt")}).number("handle"), 0);
  // Running out of modules does not end the search; CloseModuleHandle does, always with 0x00.
  for (int i = 0; i < 10; ++i) rig.reply("FindNextModule", {n(0)});
  EXPECT_EQ(rig.status_of("FindNextModule", {n(0)}), status::kModuleNotFound);
  EXPECT_EQ(rig.status_of("FindFirstModule", {s("*.mod")}), status::kNoMoreHandles);
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x92, 0x07}), (Bytes{0x02, 0x92, 0x00, 0x00}));
  EXPECT_EQ(rig.reply("FindFirstModule", {s("Ui.*")}).number("module_id"), 0x000C0001);
}

TEST(VirtualNxtFirmware, DeleteEchoesTheNameEvenWhenItFails) {
  Rig rig;
  Bytes request{0x01, 0x85, 'n', 'o', '.', 't', 'x', 't'};
  request.resize(22, 0);
  EXPECT_EQ(*answer(rig.brick, request), padded({0x02, 0x85, 0x87, 'n', 'o', '.', 't', 'x', 't'}, 14));
}

TEST(VirtualNxtFirmware, FindNextsLastAnswerLeavesTheHandleOpenAndListingClosesIt) {
  Rig rig;
  rig.put_file("a.txt", Bytes{1});
  rig.put_file("b.txt", Bytes{2});
  auto first = rig.reply("FindFirst", {s("*.txt")});
  ASSERT_EQ(first.status, 0);
  EXPECT_EQ(rig.status_of("FindNext", {first.number("handle").value_or(0)}), 0);
  EXPECT_EQ(rig.status_of("FindNext", {first.number("handle").value_or(0)}), status::kFileNotFound);
  EXPECT_EQ(rig.status_of("Close", {first.number("handle").value_or(0)}), 0);  // it was still open
  // FindFirst without a match closes its own handle.
  EXPECT_EQ(rig.status_of("FindFirst", {s("*.rso")}), status::kFileNotFound);
  EXPECT_TRUE(std::none_of(rig.brick.handles.begin(), rig.brick.handles.end(), [](const auto& h) { return h.has_value(); }));
  // Twenty listings on a brick of 16 handles: each gives its handle back.
  for (int i = 0; i < 20; ++i) {
    auto listed = list_files(rig.client, "*.*");
    ASSERT_TRUE(std::holds_alternative<std::vector<FileEntry>>(listed)) << i << ": " << std::get<CallError>(listed).message;
    EXPECT_EQ(std::get<std::vector<FileEntry>>(listed).size(), 2u);
  }
  EXPECT_TRUE(std::none_of(rig.brick.handles.begin(), rig.brick.handles.end(), [](const auto& h) { return h.has_value(); }));
}

TEST(VirtualNxtFirmware, FileNamesMatchWithoutRegardToCase) {
  Rig rig;
  rig.put_file("prog.rxe", Bytes(10, 1));
  // The same name in capitals is the same file: it exists, it can be opened and started.
  EXPECT_EQ(rig.status_of("OpenWrite", {s("PROG.RXE"), n(4)}), status::kFileExists);
  auto opened = rig.reply("OpenRead", {s("Prog.Rxe")});
  EXPECT_EQ(opened.status, 0);
  EXPECT_EQ(opened.number("size"), 10);
  EXPECT_EQ(rig.status_of("Close", {opened.number("handle").value_or(0)}), 0);
  EXPECT_EQ(rig.status_of("StartProgram", {s("PROG.RXE")}), 0);
  EXPECT_EQ(rig.reply("FindFirst", {s("*.RXE")}).text("name"), "prog.rxe");
  // OpenWriteData refuses an executable whatever the case of its extension.
  EXPECT_EQ(rig.status_of("OpenWriteData", {s("X.RXE"), n(4)}), status::kIllegalFileName);
  EXPECT_EQ(rig.status_of("Delete", {s("PROG.RXE")}), 0);
  EXPECT_TRUE(rig.brick.files.empty());
}

TEST(VirtualNxtFirmware, ReadEchoesTheCountAskedAndSendsAtMost58BytesPaddedWithZeros) {
  Rig rig;
  Bytes content(70);
  for (std::size_t i = 0; i < content.size(); ++i) content[i] = static_cast<std::uint8_t>(i + 1);
  rig.put_file("d.bin", content);
  auto h = static_cast<std::uint8_t>(rig.reply("OpenRead", {s("d.bin")}).number("handle").value_or(0));
  // 100 asked: the count says 100 (0x64), 58 bytes come (bytes 1..58).
  Bytes head{0x02, 0x82, 0x00, h, 0x64, 0x00};
  for (std::uint8_t i = 1; i <= 58; ++i) head.push_back(i);
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x82, h, 0x64, 0x00}), head);
  // 20 asked with 12 left: the count says 20, 12 real bytes and 8 zeros.
  Bytes tail{0x02, 0x82, 0x00, h, 0x14, 0x00};
  for (std::uint8_t i = 59; i <= 70; ++i) tail.push_back(i);
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x82, h, 0x14, 0x00}), padded(tail, 8));
  EXPECT_EQ(rig.status_of("Close", {n(h)}), 0);
  // The host reads by the file's size, not the telegram's length, and gets the file.
  auto back = download_file(rig.client, "d.bin");
  ASSERT_TRUE(std::holds_alternative<Bytes>(back)) << std::get<CallError>(back).message;
  EXPECT_EQ(std::get<Bytes>(back), content);
}

TEST(VirtualNxtFirmware, AMessageReadReplySentToTheBrickLandsInItsMailboxUnanswered) {
  Rig rig;
  // Without a program the reply is dropped (as MessageWrite would refuse it).
  EXPECT_FALSE(answer(rig.brick, padded({0x02, 0x13, 0x00, 0x02, 0x03, 'h', 'i', 0x00}, 56)));
  EXPECT_TRUE(rig.brick.queues[2].empty());
  rig.start_program();
  EXPECT_FALSE(answer(rig.brick, padded({0x02, 0x13, 0x00, 0x02, 0x03, 'h', 'i', 0x00}, 56)));
  // An error status, a message without its NUL and another opcode are not taken.
  EXPECT_FALSE(answer(rig.brick, padded({0x02, 0x13, 0xEC, 0x02, 0x03, 'n', 'o', 0x00}, 56)));
  EXPECT_FALSE(answer(rig.brick, padded({0x02, 0x13, 0x00, 0x02, 0x02, 'n', 'o'}, 57)));
  EXPECT_FALSE(answer(rig.brick, Bytes{0x02, 0x0B, 0x00, 0x78, 0x1E}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x00, 0x13, 0x02, 0x00, 0x01}), padded({0x02, 0x13, 0x00, 0x00, 0x03, 'h', 'i', 0x00}, 56));
  EXPECT_EQ(rig.status_of("MessageRead", {n(2), n(0), n(1)}), status::kQueueEmpty);
}

// The reply assembly of c_comm.c for Boot and PollCommand.
TEST(VirtualNxtFirmware, BootIsRefusedWith8AAndPollCommandPadsToTheCountAsked) {
  Rig rig;
  Bytes boot{0x01, 0x97};
  for (char c : std::string("Let's dance: SAMBA")) boot.push_back(static_cast<std::uint8_t>(c));
  boot.push_back(0);
  EXPECT_EQ(*answer(rig.brick, boot), (Bytes{0x02, 0x97, 0x8A, 0x00, 0x00, 0x00, 0x00}));
  // Ten asked from an empty buffer: count 0, ten zero bytes.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0xA2, 0x00, 0x0A}), padded({0x02, 0xA2, 0x00, 0x00, 0x00}, 10));
  // More than a USB packet holds: 0x8A, buffer, count 0 and nothing else.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0xA2, 0x01, 0x3C}), (Bytes{0x02, 0xA2, 0x8A, 0x01, 0x00}));
}

TEST(VirtualNxtFirmware, IoMapRepliesEchoTheModuleIdAndReadsPadToTheCountAsked) {
  Rig rig;
  // Comm.mod (0x00050001, a 64-byte stand-in), 4 bytes from offset 62 of its 64: out of boundary,
  // the ID echoed, count 0, four zero bytes.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x94, 0x01, 0x00, 0x05, 0x00, 0x3E, 0x00, 0x04, 0x00}),
            (Bytes{0x02, 0x94, 0x91, 0x01, 0x00, 0x05, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}));
  // No module 0x00990001: 0x90, the ID echoed.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x94, 0x01, 0x00, 0x99, 0x00, 0x00, 0x00, 0x02, 0x00}),
            (Bytes{0x02, 0x94, 0x90, 0x01, 0x00, 0x99, 0x00, 0x00, 0x00, 0x00, 0x00}));
  // 60 asked: 55 come (count 0x37).
  auto r = *answer(rig.brick, Bytes{0x01, 0x94, 0x01, 0x00, 0x05, 0x00, 0x00, 0x00, 0x3C, 0x00});
  EXPECT_EQ(Bytes(r.begin(), r.begin() + 9), (Bytes{0x02, 0x94, 0x00, 0x01, 0x00, 0x05, 0x00, 0x37, 0x00}));
  EXPECT_EQ(r.size(), 9u + 55u);
  // WriteIOMap writes as many bytes as its count says; an error echoes the ID.
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x95, 0x01, 0x00, 0x05, 0x00, 0x00, 0x00, 0x01, 0x00, 0xAA, 0xBB}),
            (Bytes{0x02, 0x95, 0x00, 0x01, 0x00, 0x05, 0x00, 0x01, 0x00}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x94, 0x01, 0x00, 0x05, 0x00, 0x00, 0x00, 0x02, 0x00}),
            (Bytes{0x02, 0x94, 0x00, 0x01, 0x00, 0x05, 0x00, 0x02, 0x00, 0xAA, 0x00}));
  EXPECT_EQ(*answer(rig.brick, Bytes{0x01, 0x95, 0x01, 0x00, 0x05, 0x00, 0x40, 0x00, 0x01, 0x00, 0xAA}),
            (Bytes{0x02, 0x95, 0x91, 0x01, 0x00, 0x05, 0x00, 0x00, 0x00}));
}

TEST(VirtualNxtFirmware, AnUltrasonicReadWithNoSensorSaysWhereItLooked) {
  // A real port with nothing plugged in: the bus transaction fails (0xDD).
  VirtualNxt brick = make_virtual_nxt();
  InProcessTransport link([&brick](std::span<const std::uint8_t> t) -> std::optional<Bytes> {
    if (t.size() >= 2 && t[1] == 0x0E) return Bytes{0x02, 0x0E, 0xDD, 0x00};
    return answer(brick, t);
  });
  Client client(link);
  client.pause = [&brick](Millis m) { advance_to(brick, brick.now_us + m.count() * 1000); };
  auto r = read_ultrasonic(client, 2);
  ASSERT_TRUE(std::holds_alternative<CallError>(r));
  const auto& e = std::get<CallError>(r);
  EXPECT_EQ(e.kind, CallError::Kind::Refused);
  EXPECT_EQ(e.status, status::kBusError);
  EXPECT_NE(e.message.find("LSGetStatus refused: 0xdd communication bus error: no I2C device answered at address 0x02 "
                           "(is the ultrasonic sensor on input port 3?)"),
            std::string::npos)
      << e.message;
}

// SetBrickName holds 15 characters and a NUL; GetDeviceInfo copies 15
// bytes of the name (c_comm.c), so such a name comes back without a NUL.
// The reply's encoder wanted room for one and the brick answered 0xFF.
TEST(VirtualNxtFirmware, AFifteenCharacterNameComesBackWithoutItsNul) {
  Rig rig;
  ASSERT_EQ(rig.status_of("SetBrickName", {std::string("ABCDEFGHIJKLMNO")}), 0);
  auto d = rig.reply("GetDeviceInfo");
  EXPECT_EQ(d.status, 0);
  EXPECT_EQ(d.text("name"), "ABCDEFGHIJKLMNO");
  // A request's names still need their NUL: 20 characters do not fit 20 bytes.
  auto r = encode_request(*find_command("OpenRead"), V{std::string(20, 'a')});
  EXPECT_TRUE(std::holds_alternative<TelegramError>(r));
}


// The actions past the seed (rcxc nxt volume, sleep, bluetooth, modules,
// iomap): the client's operations against the virtual NXT, and the bytes
// they send, checked against the firmware's layouts by hand.

// A link to the virtual NXT that keeps every request sent.
struct Recording {
  VirtualNxt brick = make_virtual_nxt();
  std::vector<Bytes> sent;
  InProcessTransport link{[this](std::span<const std::uint8_t> t) {
    sent.emplace_back(t.begin(), t.end());
    return answer(brick, t);
  }};
  Client client{link};
};

TEST(VirtualNxtExtras, PropertiesGoOutInTheFirmwaresLayout) {
  Recording r;
  ASSERT_FALSE(set_property(r.client, Property::SleepMs, 120'000));
  ASSERT_FALSE(set_property(r.client, Property::Volume, 2));
  ASSERT_FALSE(set_property(r.client, Property::Bluetooth, 0));
  ASSERT_EQ(r.sent.size(), 3u);
  EXPECT_EQ(hex(r.sent[0]), "00 1f 02 c0 d4 01 00");  // 120000 ms, a u32
  EXPECT_EQ(hex(r.sent[1]), "00 1f 01 02");
  EXPECT_EQ(hex(r.sent[2]), "00 1f 00 00");
  EXPECT_EQ(std::get<std::uint32_t>(get_property(r.client, Property::SleepMs)), 120'000u);
  EXPECT_EQ(std::get<std::uint32_t>(get_property(r.client, Property::Volume)), 2u);
  EXPECT_EQ(std::get<std::uint32_t>(get_property(r.client, Property::Bluetooth)), 0u);
  EXPECT_EQ(hex(r.sent[3]), "00 20 02");
}

TEST(VirtualNxtExtras, APropertyReplyOfTheWrongLengthIsABadReply) {
  InProcessTransport link([](std::span<const std::uint8_t>) -> std::optional<Bytes> { return Bytes{0x02, 0x20, 0x00, 0x03, 0x00}; });
  Client client(link);
  auto v = get_property(client, Property::Volume);
  ASSERT_TRUE(std::holds_alternative<CallError>(v));
  EXPECT_EQ(std::get<CallError>(v).kind, CallError::Kind::BadReply);
  EXPECT_NE(std::get<CallError>(v).message.find("answered 2 bytes (03 00), not 1"), std::string::npos)
      << std::get<CallError>(v).message;
}

// leJOS answers GetFirmwareVersion 02 88 00 02 01 03 01 (its LCP.java):
// protocol 1.2. Nothing past that telegram may go to it.
TEST(VirtualNxtExtras, AFirmwareThatIsNotLegosIsToldApartAndSentNothingMore) {
  std::vector<Bytes> sent;
  InProcessTransport link([&](std::span<const std::uint8_t> t) -> std::optional<Bytes> {
    sent.emplace_back(t.begin(), t.end());
    if (t.size() >= 2 && t[1] == 0x88) return Bytes{0x02, 0x88, 0x00, 0x02, 0x01, 0x03, 0x01};
    return Bytes{0x02, t[1], 0x00};
  });
  Client client(link);
  auto e = require_lego_firmware(client, "GetProperty (0x20)");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind, CallError::Kind::Refused);
  EXPECT_NE(e->message.find("protocol 1.2, firmware 1.03 (leJOS NXJ answers so)"), std::string::npos) << e->message;
  EXPECT_NE(e->message.find("GetProperty (0x20) was not sent"), std::string::npos) << e->message;
  EXPECT_EQ(sent.size(), 1u);
  // LEGO's (the virtual NXT: 1.124, 1.31) passes.
  Rig rig;
  EXPECT_FALSE(require_lego_firmware(rig.client, "GetProperty (0x20)"));
  EXPECT_TRUE(is_lego_firmware({1, 124, 1, 5}));
  EXPECT_FALSE(is_lego_firmware({1, 2, 1, 3}));
}

TEST(VirtualNxtExtras, TheUiModulesBytesAreWhatThePropertiesSee) {
  Rig rig;
  ASSERT_FALSE(set_property(rig.client, Property::Volume, 1));
  ASSERT_FALSE(set_property(rig.client, Property::SleepMs, 5 * 60'000));
  auto ui = std::get<Bytes>(read_iomap(rig.client, 0x000C0001, 0, 40));
  EXPECT_EQ(ui[36], 1);                    // IOMAPUI Volume
  EXPECT_EQ(ui[33], 5);                    // SleepTimeout, minutes
  EXPECT_EQ(ui[4] | (ui[5] << 8), 7800);   // BatteryVoltage, as GetBatteryLevel
  EXPECT_EQ(ui[31] & 0x04, 0);             // Bluetooth on
  // Written into the map, seen by GetProperty and KeepAlive.
  ASSERT_FALSE(write_iomap(rig.client, 0x000C0001, 33, Bytes{2}));
  ASSERT_FALSE(write_iomap(rig.client, 0x000C0001, 36, Bytes{4}));
  ASSERT_FALSE(write_iomap(rig.client, 0x000C0001, 31, Bytes{0x04}));
  EXPECT_EQ(std::get<std::uint32_t>(get_property(rig.client, Property::Volume)), 4u);
  EXPECT_EQ(rig.reply("KeepAlive").number("sleep_limit_ms"), 120'000);
  EXPECT_EQ(std::get<std::uint32_t>(get_property(rig.client, Property::Bluetooth)), 0u);
  // The battery voltage is measured: a write does not change it.
  ASSERT_FALSE(write_iomap(rig.client, 0x000C0001, 4, Bytes{0, 0}));
  EXPECT_EQ(rig.reply("GetBatteryLevel").number("millivolts"), 7800);
  ui = std::get<Bytes>(read_iomap(rig.client, 0x000C0001, 4, 2));
  EXPECT_EQ(ui, (Bytes{0x78, 0x1E}));
  // Loader.mod's free flash is GetDeviceInfo's.
  auto loader = std::get<Bytes>(read_iomap(rig.client, 0x00090001, 4, 4));
  std::uint32_t free = loader[0] | (loader[1] << 8) | (loader[2] << 16) | (std::uint32_t{loader[3]} << 24);
  EXPECT_EQ(free, rig.reply("GetDeviceInfo").number("free_flash"));
}

TEST(VirtualNxtExtras, IoMapsAreReadAndWrittenInPiecesAPacketHolds) {
  Recording r;
  Bytes data(60);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i + 1);
  // Comm.mod (0x00050001), a 64-byte stand-in: 54 bytes, then 6.
  ASSERT_FALSE(write_iomap(r.client, 0x00050001, 2, data));
  ASSERT_EQ(r.sent.size(), 2u);
  EXPECT_EQ(hex(Bytes(r.sent[0].begin(), r.sent[0].begin() + 10)), "01 95 01 00 05 00 02 00 36 00");
  EXPECT_EQ(r.sent[0].size(), 10u + 54u);
  EXPECT_EQ(hex(r.sent[1]), "01 95 01 00 05 00 38 00 06 00 37 38 39 3a 3b 3c");
  auto back = read_iomap(r.client, 0x00050001, 2, 60);
  ASSERT_TRUE(std::holds_alternative<Bytes>(back));
  EXPECT_EQ(std::get<Bytes>(back), data);
  EXPECT_EQ(hex(r.sent[2]), "01 94 01 00 05 00 02 00 37 00");  // 55
  EXPECT_EQ(hex(r.sent[3]), "01 94 01 00 05 00 39 00 05 00");  // then 5
  // Past the map: the brick's 0x91, refused.
  auto past = read_iomap(r.client, 0x00050001, 60, 8);
  ASSERT_TRUE(std::holds_alternative<CallError>(past));
  EXPECT_EQ(std::get<CallError>(past).status, status::kOutOfBoundary);
}

TEST(VirtualNxtExtras, ModulesAreListedAndTheSearchIsClosed) {
  Rig rig;
  auto all = list_modules(rig.client, "*.*");
  ASSERT_TRUE(std::holds_alternative<std::vector<ModuleEntry>>(all));
  const auto& list = std::get<std::vector<ModuleEntry>>(all);
  ASSERT_EQ(list.size(), 12u);
  EXPECT_EQ(list.front().name, "Command.mod");
  EXPECT_EQ(list.back().name, "Ui.mod");
  EXPECT_EQ(list.back().id, 0x000C0001u);
  EXPECT_EQ(list.back().iomap_size, 40);
  EXPECT_FALSE(rig.brick.module_search.open);
  // A search another host left open (0x81 to the next FindFirstModule) is closed and asked again.
  ASSERT_EQ(rig.status_of("FindFirstModule", {s("*.*")}), 0);
  auto sound = list_modules(rig.client, "Sound.*");
  ASSERT_TRUE(std::holds_alternative<std::vector<ModuleEntry>>(sound));
  ASSERT_EQ(std::get<std::vector<ModuleEntry>>(sound).size(), 1u);
  EXPECT_EQ(std::get<std::vector<ModuleEntry>>(sound)[0].iomap_size, 30);
  auto none = list_modules(rig.client, "Nope.*");
  ASSERT_TRUE(std::holds_alternative<std::vector<ModuleEntry>>(none));
  EXPECT_TRUE(std::get<std::vector<ModuleEntry>>(none).empty());
}

TEST(VirtualNxtExtras, BluetoothTablesListTheSlotsThatHoldANameAndASlotPastTheTableIsC0) {
  Rig rig;
  rig.brick.contacts[3] = {0x04, "Laptop"};
  rig.brick.connections[0] = {0x02, "Phone"};
  auto contacts = std::get<std::vector<BtEntry>>(bluetooth_table(rig.client, true));
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].index, 3);
  EXPECT_EQ(contacts[0].name, "Laptop");
  EXPECT_EQ(contacts[0].device_type, 4);
  auto conns = std::get<std::vector<BtEntry>>(bluetooth_table(rig.client, false));
  ASSERT_EQ(conns.size(), 1u);
  EXPECT_EQ(conns[0].name, "Phone");
  EXPECT_EQ(rig.status_of("BTGetConnName", {n(4)}), status::kOutOfRange);
}

}  // namespace
}  // namespace nxt
