// Framing, ports, and the virtual NXT served on a real pseudo-terminal:
// split and glued frames, a brick that stays silent, Ctrl-C while waiting.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "nxt/client.h"
#include "nxt/scenario.h"
#include "nxt/transport.h"
#include "nxt/usb_library.h"
#include "nxt/virtual_nxt.h"
#include "tests/nxt/round_trips.h"
#include "tests/support/served_thread.h"

namespace nxt {
namespace {

using namespace std::chrono_literals;

TEST(NxtFraming, PrefixIsTwoBytesLittleEndianWithoutItself) {
  EXPECT_EQ(frame(Bytes{0x00, 0x13, 0x0A, 0x00, 0x01}), (Bytes{0x05, 0x00, 0x00, 0x13, 0x0A, 0x00, 0x01}));
  EXPECT_EQ(frame(Bytes(300, 1))[0], 0x2C);
  EXPECT_EQ(frame(Bytes(300, 1))[1], 0x01);
}

TEST(NxtFraming, SplitAndGluedFramesAreReassembled) {
  FrameReader r;
  r.feed(Bytes{0x03});  // half a prefix
  EXPECT_FALSE(r.next());
  r.feed(Bytes{0x00, 0x02, 0x0B});
  EXPECT_FALSE(r.next());
  // The rest of the first and the whole second, glued.
  r.feed(Bytes{0x00, 0x02, 0x00, 0x02, 0x0D});
  EXPECT_EQ(r.next(), (Bytes{0x02, 0x0B, 0x00}));
  EXPECT_EQ(r.next(), (Bytes{0x02, 0x0D}));
  EXPECT_FALSE(r.next());
  EXPECT_TRUE(r.pending.empty());
}

TEST(NxtFraming, AnImpossibleLengthDropsTheGarbage) {
  FrameReader r;
  r.feed(Bytes{0xFF, 0xFF, 1, 2, 3});
  EXPECT_FALSE(r.next());
  r.feed(Bytes{0x01, 0x00, 0x02});
  EXPECT_EQ(r.next(), (Bytes{0x02}));
}

TEST(NxtPort, Syntax) {
  auto usb = std::get<PortSpec>(parse_port(std::nullopt, std::nullopt));
  EXPECT_EQ(usb.kind, PortKind::Usb);
  EXPECT_EQ(usb.address, "");
  EXPECT_EQ(std::get<PortSpec>(parse_port(std::string("usb:00165312AB34"), std::nullopt)).address, "00165312AB34");
  auto bt = std::get<PortSpec>(parse_port(std::string("bt:00:16:53:12:AB:34"), std::nullopt));
  EXPECT_EQ(bt.kind, PortKind::Bluetooth);
  EXPECT_EQ(bt.address, "00:16:53:12:AB:34");
  auto env = std::get<PortSpec>(parse_port(std::nullopt, std::string("/dev/rfcomm0")));
  EXPECT_EQ(env.kind, PortKind::Path);
  EXPECT_EQ(std::get<PortSpec>(parse_port(std::string("usb"), std::string("/dev/rfcomm0"))).kind, PortKind::Usb);
  EXPECT_TRUE(std::holds_alternative<LinkError>(parse_port(std::string("bt:00:16:53"), std::nullopt)));
  EXPECT_TRUE(std::holds_alternative<LinkError>(parse_port(std::string(""), std::nullopt)));
}

TEST(NxtPort, AUsbSerialIsTwelveHexDigitsColonsAndCaseAsGiven) {
  // The docs' own spelling, and the Bluetooth form, are one serial.
  EXPECT_EQ(std::get<PortSpec>(parse_port(std::string("usb:00:16:53:12:ab:34"), std::nullopt)).address,
            "00:16:53:12:ab:34");
  // "usb:zz" was looked for on USB and ended as "no NXT on USB" (exit 3).
  for (std::string bad : {"usb:zz", "usb:", "usb:0016531234", "usb:00165312345678", "usb:00165312345g",
                          "usb:/dev/ttyACM0"}) {
    auto r = parse_port(bad, std::nullopt);
    ASSERT_TRUE(std::holds_alternative<LinkError>(r)) << bad;
    const std::string& m = std::get<LinkError>(r).message;
    EXPECT_NE(m.find("\"" + bad.substr(4) + "\" is not an NXT's USB serial number"), std::string::npos) << m;
    EXPECT_NE(m.find("(usb:001653123456; colons and case do not matter)"), std::string::npos) << m;
  }
  // From NXT_PORT, the message says so: nothing typed shows the bad value.
  auto env = parse_port(std::nullopt, std::string("usb:zz"));
  ASSERT_TRUE(std::holds_alternative<LinkError>(env));
  EXPECT_EQ(std::get<LinkError>(env).message.rfind("NXT_PORT: \"zz\"", 0), 0u) << std::get<LinkError>(env).message;
}

TEST(NxtPort, BluetoothAddressesGoToTheSocketLastByteFirst) {
  // The byte order BlueZ's str2ba gives (checked against it): a wrong one
  // would page another brick, or none.
  using B = std::array<std::uint8_t, 6>;
  EXPECT_EQ(bluetooth_address_bytes("00:16:53:0A:0B:0C"), (B{0x0C, 0x0B, 0x0A, 0x53, 0x16, 0x00}));
  EXPECT_EQ(bluetooth_address_bytes("fe:dc:BA:98:76:54"), (B{0x54, 0x76, 0x98, 0xBA, 0xDC, 0xFE}));
}

TEST(NxtUsb, LibusbIsLoadedWhenAUsbPortIsOpenedWithEveryFunctionTheTransportCalls) {
  auto loaded = load_usb_library();
  ASSERT_TRUE(std::holds_alternative<UsbLibrary>(loaded)) << std::get<std::string>(loaded);
  const auto& usb = std::get<UsbLibrary>(loaded);
  EXPECT_TRUE(usb.handle && usb.init && usb.exit && usb.strerror && usb.get_device_list && usb.free_device_list &&
              usb.get_device_descriptor && usb.open && usb.close && usb.get_string_descriptor_ascii &&
              usb.set_auto_detach_kernel_driver && usb.claim_interface && usb.release_interface && usb.bulk_transfer);
  EXPECT_STREQ(usb.strerror(LIBUSB_ERROR_TIMEOUT), "Operation timed out");
}

TEST(NxtUsb, AMissingOrWrongLibusbSaysWhatIsMissing) {
  auto missing = load_usb_library("libno-such-usb.so.0");
  ASSERT_TRUE(std::holds_alternative<std::string>(missing));
  EXPECT_NE(std::get<std::string>(missing).find("cannot load libno-such-usb.so.0"), std::string::npos);
  EXPECT_NE(std::get<std::string>(missing).find("apt-get install libusb-1.0-0"), std::string::npos);
  auto wrong = load_usb_library("libm.so.6");
  ASSERT_TRUE(std::holds_alternative<std::string>(wrong));
  EXPECT_EQ(std::get<std::string>(wrong), "libm.so.6 has no libusb_init: USB needs libusb-1.0.16 or later");
}

TEST(NxtPort, AMissingTtySaysWhatToCheck) {
  auto r = open_port({PortKind::Path, "/dev/no-such-rfcomm"}, -1);
  ASSERT_TRUE(std::holds_alternative<LinkError>(r));
  EXPECT_EQ(std::get<LinkError>(r).kind, LinkError::Kind::Open);
  EXPECT_NE(std::get<LinkError>(r).message.find("rfcomm bind"), std::string::npos);
}

TEST(NxtPort, APathThatIsNoTtyIsRefusedWhenOpened) {
  // /dev/null would read as a hang-up, a plain file as garbage frames.
  for (const char* path : {"/dev/null", "/etc/hostname"}) {
    auto r = open_port({PortKind::Path, path}, -1);
    ASSERT_TRUE(std::holds_alternative<LinkError>(r)) << path;
    EXPECT_EQ(std::get<LinkError>(r).kind, LinkError::Kind::Open) << path;
    EXPECT_NE(std::get<LinkError>(r).message.find(std::string(path) + " is not a tty"), std::string::npos)
        << std::get<LinkError>(r).message;
  }
}

// The virtual NXT served on a pty in a thread, the host on the slave.
struct PtyNxt : ::testing::Test {
  VirtualNxt brick = make_virtual_nxt();
  PtyPair pty;
  rcxc::test::ServedThread server;
  std::vector<std::string> log;

  void SetUp() override {
    auto opened = open_pty_pair();
    ASSERT_TRUE(std::holds_alternative<PtyPair>(opened)) << std::get<LinkError>(opened).message;
    pty = std::get<PtyPair>(opened);
    ASSERT_TRUE(server.start([this](int stop_fd) {
      ServeOptions options;
      options.stop_fd = stop_fd;
      options.on_log = [this](const std::string& line) { log.push_back(line); };
      serve(brick, pty.master_fd, options);
    }));
  }
  void TearDown() override {
    server.stop();
    close_pty_pair(pty);
  }
  std::unique_ptr<Transport> host(int stop_fd = -1) {
    auto port = open_port({PortKind::Path, pty.slave_path}, stop_fd);
    EXPECT_TRUE(std::holds_alternative<std::unique_ptr<Transport>>(port));
    return std::move(std::get<std::unique_ptr<Transport>>(port));
  }
};

TEST_F(PtyNxt, RoundTripsOverThePty) {
  auto port = host();
  Client client(*port);
  auto r = call_ok(client, "GetBatteryLevel", {});
  ASSERT_TRUE(std::holds_alternative<Decoded>(r)) << std::get<CallError>(r).message;
  EXPECT_EQ(std::get<Decoded>(r).number("millivolts"), 7800);
  Bytes data(150, 0x5A);
  ASSERT_FALSE(upload_file(client, "t.rxe", data));
  EXPECT_EQ(std::get<Bytes>(download_file(client, "t.rxe")), data);
  TearDown();
  // -v logs decoded telegrams, not only hex.
  EXPECT_EQ(log.at(0), "-> GetBatteryLevel");
  EXPECT_EQ(log.at(1), "<- GetBatteryLevel -> ok millivolts=7800");
}

TEST_F(PtyNxt, EveryCommandOfTheTableMakesARoundTripOverThePty) {
  auto port = host();
  Client client(*port);
  test::every_command_round_trip(client);
  TearDown();  // stop the server before looking at the brick
  EXPECT_EQ(brick.name, "Robo");
  EXPECT_TRUE(brick.files.empty());
}

TEST_F(PtyNxt, FramesWrittenByteByByteAreReassembled) {
  int fd = ::open(pty.slave_path.c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(fd, 0);
  Bytes req = frame(Bytes{0x00, 0x0B});
  for (auto b : req) {
    ASSERT_EQ(::write(fd, &b, 1), 1);
    std::this_thread::sleep_for(2ms);
  }
  auto port = framed_fd_transport(fd, "pty", -1);
  auto got = port->receive(2000ms);
  ASSERT_TRUE(std::holds_alternative<std::optional<Bytes>>(got));
  auto& reply = std::get<std::optional<Bytes>>(got);
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Bytes{0x02, 0x0B, 0x00, 0x78, 0x1E}));
}

TEST(NxtFraming, RepliesLongerThan64BytesComeWholeOverAPty) {
  // spec/nxt.md: Bluetooth replies may exceed 64 bytes (a Read over
  // Bluetooth brings up to 122 data bytes); their size is the prefix's.
  // A 106-byte Read reply (100 data bytes), prefix 0x6A 0x00, written to the
  // brick's end of a pty in pieces that split the prefix.
  auto opened = open_pty_pair();
  ASSERT_TRUE(std::holds_alternative<PtyPair>(opened)) << std::get<LinkError>(opened).message;
  auto pty = std::get<PtyPair>(opened);
  auto port = open_port({PortKind::Path, pty.slave_path}, -1);
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<Transport>>(port));
  auto& host = std::get<std::unique_ptr<Transport>>(port);
  Bytes reply{0x02, 0x82, 0x00, 0x00, 0x64, 0x00};
  for (int i = 0; i < 100; ++i) reply.push_back(static_cast<std::uint8_t>(i));
  Bytes framed = frame(reply);
  ASSERT_EQ(framed[0], 0x6A);
  ASSERT_EQ(framed.size(), 108u);
  for (auto [from, to] : {std::pair{0, 1}, std::pair{1, 50}, std::pair{50, 108}}) {
    ASSERT_EQ(::write(pty.master_fd, framed.data() + from, static_cast<std::size_t>(to - from)), to - from);
    std::this_thread::sleep_for(5ms);
  }
  auto got = host->receive(2000ms);
  ASSERT_TRUE(std::holds_alternative<std::optional<Bytes>>(got));
  auto& t = std::get<std::optional<Bytes>>(got);
  ASSERT_TRUE(t);
  EXPECT_EQ(*t, reply);
  host.reset();
  close_pty_pair(pty);
}

TEST_F(PtyNxt, ASilentBrickTimesOut) {
  auto port = host();
  Client client(*port);
  client.timeout = 50ms;
  auto t0 = std::chrono::steady_clock::now();
  // Telegram type 0x05: the firmware does not answer at all.
  ASSERT_FALSE(port->send(Bytes{0x05, 0x0B}));
  auto got = port->receive(50ms);
  EXPECT_FALSE(std::get<std::optional<Bytes>>(got));
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 45ms);
  // The line is still good afterwards.
  EXPECT_TRUE(std::holds_alternative<Decoded>(call_ok(client, "KeepAlive", {})));
}

// What came but was not the reply is said when the reply never comes: the
// message was "no reply" alone, as if the brick had been silent.
TEST(NxtFraming, ANoReplyMessageSaysWhatCameInstead) {
  struct Case {
    Bytes answer;     // what the "brick" writes back, framing included
    std::string says;
  };
  const Case cases[] = {
      {{0x05, 0x00, 0x02, 0x0B, 0x00, 0x78}, "; 4 of a 5-byte telegram came: 05 00 02 0b 00 78"},
      {{0xFF, 0xFF, 0x02, 0x0B}, "; 4 bytes came under a length prefix of 65535, more than any telegram, and were "
                                 "dropped: ff ff 02 0b"},
      {{0x07, 0x00, 0x02, 0x0D, 0x00, 0x60, 0xEA, 0x00, 0x00},
       "; what came instead was dropped: a reply to KeepAlive (02 0d 00 60 ea 00 00)"},
  };
  for (const auto& c : cases) {
    auto opened = open_pty_pair();
    ASSERT_TRUE(std::holds_alternative<PtyPair>(opened));
    auto pty = std::get<PtyPair>(opened);
    auto port = open_port({PortKind::Path, pty.slave_path}, -1);
    ASSERT_TRUE(std::holds_alternative<std::unique_ptr<Transport>>(port));
    auto& host = std::get<std::unique_ptr<Transport>>(port);
    std::thread brick([&] {
      pollfd p{pty.master_fd, POLLIN, 0};
      if (::poll(&p, 1, 5000) != 1) return;
      std::uint8_t buf[64];
      [[maybe_unused]] auto in = ::read(pty.master_fd, buf, sizeof buf);
      [[maybe_unused]] auto out = ::write(pty.master_fd, c.answer.data(), c.answer.size());
    });
    Client client(*host);
    client.timeout = 300ms;
    auto r = call_ok(client, "GetBatteryLevel", {});
    brick.join();
    ASSERT_TRUE(std::holds_alternative<CallError>(r));
    const auto& e = std::get<CallError>(r);
    EXPECT_EQ(e.kind, CallError::Kind::NoReply);
    EXPECT_EQ(e.message, "no reply to GetBatteryLevel from NXT on " + pty.slave_path + " within 300 ms" + c.says);
    host.reset();
    close_pty_pair(pty);
  }
}

// The wait must end within 100 ms of the stop. It is measured from the
// moment the stop was written (not from a sleep before it), and on a loaded
// machine one try may be scheduled late: the wait passes when any of five
// tries ends within 100 ms, and every try must end by the stop, none by the
// 5 s timeout. A wait that looked at the stop only at the end of a slice or
// of the timeout fails every try.
TEST(NxtInterrupt, AStopDescriptorEndsAWaitWithin100ms) {
  auto opened = open_pty_pair();
  ASSERT_TRUE(std::holds_alternative<PtyPair>(opened));
  auto pty = std::get<PtyPair>(opened);
  auto fastest = std::chrono::steady_clock::duration::max();
  for (int attempt = 0; attempt < 5 && fastest >= 100ms; ++attempt) {
    int stop[2];
    ASSERT_EQ(::pipe(stop), 0);
    auto port = std::get<std::unique_ptr<Transport>>(open_port({PortKind::Path, pty.slave_path}, stop[0]));
    std::chrono::steady_clock::time_point signalled;
    std::thread ctrl_c([&] {
      std::this_thread::sleep_for(30ms);
      signalled = std::chrono::steady_clock::now();
      (void)!::write(stop[1], "x", 1);
    });
    auto t0 = std::chrono::steady_clock::now();
    auto got = port->receive(5000ms);  // nobody answers
    auto ended = std::chrono::steady_clock::now();
    ctrl_c.join();
    ASSERT_TRUE(std::holds_alternative<LinkError>(got));
    EXPECT_EQ(std::get<LinkError>(got).kind, LinkError::Kind::Interrupted);
    EXPECT_LT(ended - t0, 4000ms);  // the stop ended it, not the timeout
    fastest = std::min(fastest, ended - signalled);
    port.reset();
    ::close(stop[0]);
    ::close(stop[1]);
  }
  EXPECT_LT(fastest, 100ms);
  close_pty_pair(pty);
}

TEST(NxtScenario, ReadsNxtPortsAndRefusesWhatItCannotUse) {
  auto ok = parse_scenario(R"([[input]]
at_ms = 500
sensor = 4
raw = 300
[[input]]
at_ms = 100
sensor = 1
distance_cm = 40
[[input]]
at_ms = 200
battery_mv = 7000
[[input]]
at_ms = 600
sensor = 3
rotation = -16
[[input]]
at_ms = 700
message = 101
mailbox = 2
)",
                           "s.toml");
  ASSERT_TRUE(std::holds_alternative<std::vector<ScenarioInput>>(ok)) << std::get<ScenarioError>(ok).message;
  const auto& in = std::get<std::vector<ScenarioInput>>(ok);
  ASSERT_EQ(in.size(), 5u);
  EXPECT_EQ(in[3].port, 2);
  EXPECT_EQ(in[3].rotation, -16);
  EXPECT_EQ(in[4].port, -1);
  EXPECT_EQ(in[4].message, 101);
  EXPECT_EQ(in[4].queue, 1);
  EXPECT_EQ(in[0].at_ms, 100);  // sorted by time
  EXPECT_EQ(in[0].distance_cm, 40);
  EXPECT_EQ(in[2].port, 3);
  EXPECT_EQ(in[2].raw, 300);
  auto bad = [](const char* text) {
    auto r = parse_scenario(text, "s.toml");
    return std::holds_alternative<ScenarioError>(r) ? std::get<ScenarioError>(r).message : std::string("accepted");
  };
  EXPECT_NE(bad("[[input]]\nat_ms = 1\nsensor = 5\nraw = 1\n").find("s.toml:3: 'sensor' = 5 is out of range 1..4"),
            std::string::npos);
  EXPECT_NE(bad("[[input]]\nat_ms = 1\nsensor = 1\npressed = true\n").find("unknown key 'pressed'"), std::string::npos);
  EXPECT_NE(bad("[[input]]\nat_ms = 1\nmessage = 5\nsensor = 1\n").find("'sensor' (1-4) goes with"), std::string::npos);
  EXPECT_NE(bad("[[input]]\nat_ms = 1\nsensor = 1\nraw = 5\nmailbox = 2\n").find("'mailbox' goes with 'message'"),
            std::string::npos);
  EXPECT_NE(bad("[[input]]\nat_ms = 1\nmessage = 5\nmailbox = 11\n").find("'mailbox' = 11 is out of range 1..10"),
            std::string::npos);
  EXPECT_NE(bad("[[input]]\nat_ms = 1\nraw = 1\n").find("'sensor' (1-4) goes with"), std::string::npos);
  EXPECT_NE(bad("[[input]]\nsensor = 1\nraw = 1\n").find("without 'at_ms'"), std::string::npos);
  EXPECT_NE(bad("x = 1\n").find("[[input]]"), std::string::npos);
  EXPECT_NE(bad("[[input]\n").find("s.toml:1"), std::string::npos);
}

// at_ms named its bound as 9223372036854775 (INT64_MAX over 1000: exact, but
// no run reaches it), and the NXT reader said a negative one was "out of range
// 0..9223372036854775". The bound is the longest run, 2^40 ms, as for --for
// and a test's directives.
TEST(NxtScenario, AnAtMsOutOfRangeNamesTheLongestRun) {
  auto error = [](const std::string& text) {
    auto r = parse_scenario(text, "s.toml");
    return std::holds_alternative<ScenarioError>(r) ? std::get<ScenarioError>(r).message : std::string("accepted");
  };
  EXPECT_EQ(error("[[input]]\nat_ms = 1099511627777\nmessage = 3\n"),
            "s.toml:2: 'at_ms' = 1099511627777 is later than the longest run (1099511627776 ms, about 35 years)");
  EXPECT_EQ(error("[[input]]\nat_ms = -1\nmessage = 3\n"), "s.toml:2: 'at_ms' = -1 must be 0 or more");
  EXPECT_EQ(error("[[input]]\nat_ms = 1099511627776\nmessage = 3\n"), "accepted");
}

// The text toml++ 3.3 faults on (undefined behaviour on a Cyrillic letter
// it takes for a blank, an assertion on "[+") is refused before it parses,
// as in an RCX scenario (tomlfile/read.h).
TEST(NxtScenario, TextThatTomlPlusPlusCannotTakeIsRefusedFirst) {
  auto error = [](const std::string& text) {
    auto r = parse_scenario(text, "s.toml");
    return std::holds_alternative<ScenarioError>(r) ? std::get<ScenarioError>(r).message : std::string("accepted");
  };
  EXPECT_EQ(error("[[input]]\nat_ms = 5\xd1\x81\nmessage = 3\n"),
            "s.toml:2: a letter that is not ASCII outside a comment (an NXT scenario is [[input]] tables of keys and "
            "numbers)");
  EXPECT_EQ(error("[[input]]\nat_ms = 1\nmessage = 2\n[+\n"),
            "s.toml:4: a table header without a name (an NXT scenario is [[input]] tables of keys and numbers)");
  EXPECT_EQ(error("[[input]]\nat_ms = 1\nmessage = [\n}\n"),
            "s.toml:4: a '}' where an array expects a value (an NXT scenario is [[input]] tables of keys and numbers)");
  auto in = parse_scenario("# f\xc3\xbcr den Sensor\n[[input]]\nat_ms = 5\nmessage = 3\n", "s.toml");
  ASSERT_TRUE(std::holds_alternative<std::vector<ScenarioInput>>(in));
  EXPECT_EQ(std::get<std::vector<ScenarioInput>>(in).size(), 1u);
}

// A quoted key spelt with an escape was quoted raw in "unknown key".
TEST(NxtScenario, AKeysControlCharactersAreShownNotSent) {
  auto r = parse_scenario("[[input]]\n\"at\\u001b[2J\" = 5\nmessage = 3\n", "s.toml");
  ASSERT_TRUE(std::holds_alternative<ScenarioError>(r));
  EXPECT_NE(std::get<ScenarioError>(r).message.find("s.toml:2: unknown key 'at\\x1b[2J' "), std::string::npos)
      << std::get<ScenarioError>(r).message;
}

// Binary bytes given as an NXT scenario (an .rxe program, random data)
// said "a letter that is not ASCII" where an RCX scenario says it holds
// binary data; both name the file for what it is now.
TEST(NxtScenario, ABinaryFileIsNamedAsSuchNotAsALetter) {
  const std::string expected =
      "s.toml: holds binary data, not a scenario (an NXT scenario is [[input]] tables of keys and numbers)";
  auto error = [](const std::string& text) {
    auto r = parse_scenario(text, "s.toml");
    return std::holds_alternative<ScenarioError>(r) ? std::get<ScenarioError>(r).message : std::string("accepted");
  };
  EXPECT_EQ(error(std::string("MindstormsNXT\0\x05\x00\xff\xfe", 18)), expected);
  EXPECT_EQ(error(std::string("[[input]]\n\0at_ms = 1\n", 20)), expected);
  EXPECT_EQ(error(std::string("\x93\x11\0\xc8", 4)), expected);
}

}  // namespace
}  // namespace nxt
