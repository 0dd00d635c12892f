// The whole path over a real pseudo-terminal: the brick served on the pty
// master (echoing like a serial tower), the host on the slave as a serial
// port. The brick answers at full speed so the test does not wait for 2400 baud.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <thread>

#include "link/brick_server.h"
#include "link/download.h"
#include "link/remote.h"
#include "tests/support/served_thread.h"
#include "tests/link/broadcasting_program.h"

namespace rcx {
namespace {

// A brick served on a pty in a thread until the fixture ends.
struct PtyBrick : ::testing::Test {
  Brick brick = make_brick();
  Pty pty;
  rcxc::test::ServedThread server;
  std::optional<TransportError> server_error;
  std::vector<std::string> logged;  // the brick's log lines (`rcxc brick -v`); read after TearDown

  void start(double noise = 0.0) {
    auto opened = open_pty();
    ASSERT_TRUE(std::holds_alternative<Pty>(opened)) << std::get<TransportError>(opened).message;
    pty = std::move(std::get<Pty>(opened));
    ASSERT_TRUE(server.start([this, noise](int stop_fd) {
      ServeOptions options;
      options.pace = false;
      options.noise = noise;
      options.seed = 11;
      options.stop_fd = stop_fd;
      options.on_log = [this](const std::string& line) { logged.push_back(line); };
      server_error = serve(brick, *pty.master, options);
    }));
  }
  void TearDown() override {
    server.stop();
    close_pty(pty);
  }
  std::unique_ptr<Transport> host() {
    auto port = open_port({pty.slave_path, PortKind::Serial});
    EXPECT_TRUE(std::holds_alternative<std::unique_ptr<Transport>>(port));
    return std::move(std::get<std::unique_ptr<Transport>>(port));
  }
};

Image program() {
  // task 0: var 4 = 1234; start task 3. task 3: var 5 = var 4.
  Image image;
  image.fragments.push_back({FragmentType::Task, 0, {0x14, 0x04, 0x02, 0xD2, 0x04, 0x71, 0x03}});
  image.fragments.push_back({FragmentType::Task, 3, {0x14, 0x05, 0x00, 0x04, 0x00}});
  return image;
}

TEST_F(PtyBrick, ResolvesThePtyAsASerialTower) {
  start();
  EXPECT_EQ(resolve_port(pty.slave_path, std::nullopt).kind, PortKind::Serial);
  auto port = host();
  ASSERT_TRUE(port);
  EXPECT_TRUE(port->echoes());
}

TEST_F(PtyBrick, DownloadRunAndReadAVariable) {
  start();
  auto port = host();
  ASSERT_TRUE(port);
  Link link = make_link(*port);
  DownloadOptions options;
  options.run = true;
  auto result = download(link, program(), options);
  ASSERT_TRUE(std::holds_alternative<DownloadReport>(result)) << std::get<DownloadError>(result).message;
  // The program runs in real time on the brick; give it a moment.
  std::string value;
  for (int i = 0; i < 50 && value != "1234\n"; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    auto r = run_remote(link, {"get", "var", "5"});
    ASSERT_TRUE(std::holds_alternative<std::string>(r)) << std::get<RemoteError>(r).message;
    value = std::get<std::string>(r);
  }
  EXPECT_EQ(value, "1234\n");
  EXPECT_EQ(link.stats.attempts, link.stats.requests);  // a clean line: no retries
}

TEST_F(PtyBrick, NoisyLineStillVerifiesOrFailsCleanly) {
  start(0.05);
  auto port = host();
  ASSERT_TRUE(port);
  LinkOptions fast;
  fast.reply_grace = Millis(15);
  fast.backoff = Millis(1);
  fast.max_backoff = Millis(5);
  fast.byte_seconds = 0;  // the brick answers at full speed
  int verified = 0;
  for (int run = 0; run < 3; ++run) {
    Link link = make_link(*port, fast);
    auto result = download(link, program(), {});
    if (!std::holds_alternative<DownloadReport>(result)) continue;
    ++verified;
  }
  TearDown();  // stop the server before looking at the brick
  ASSERT_FALSE(server_error) << server_error->message;
  EXPECT_GE(verified, 1);
  if (verified > 0) {
    EXPECT_EQ(brick.vm.slot(0).tasks[0], program().fragments[0].code);
    EXPECT_EQ(brick.vm.slot(0).tasks[3], program().fragments[1].code);
  }
}

// Send message broadcasts a Set message request over the infrared link
// (seed): a host at the tower hears the packet, framed like any other. The
// program sends again and again: opening the port flushes what the line
// held, so a single message sent before the host opened it was lost (the
// test failed under load).
TEST_F(PtyBrick, AProgramsSendMessageReachesTheTowerAsSetMessage) {
  ASSERT_FALSE(brick.vm.load(brick.vm.program(), test::broadcasting_program()));  // message 42 every 1/100 s
  brick.vm.start_program();
  start();
  auto port = host();
  ASSERT_TRUE(port);
  Bytes heard;
  const Bytes expected = frame(Bytes{0xF7, 42});
  auto found = [&] { return std::search(heard.begin(), heard.end(), expected.begin(), expected.end()) != heard.end(); };
  for (int i = 0; i < 300 && !found(); ++i) {
    auto got = port->read(Millis(10));
    ASSERT_TRUE(std::holds_alternative<Bytes>(got));
    const auto& bytes = std::get<Bytes>(got);
    heard.insert(heard.end(), bytes.begin(), bytes.end());
  }
  EXPECT_TRUE(found()) << hex(heard);
}

// `rcxc brick -v` logs every request and reply; a program's broadcasts went
// out unlogged (and a log line waited for the next request to be handed on).
TEST_F(PtyBrick, ATracedBrickLogsTheBroadcastsItSends) {
  Image image;
  image.fragments.push_back({FragmentType::Task, 0, {0xB2, 0x02, 42}});  // send message 42
  ASSERT_FALSE(brick.vm.load(brick.vm.program(), image));
  brick.vm.start_program();
  brick.trace = true;
  start();
  auto port = host();
  ASSERT_TRUE(port);
  Bytes heard;
  for (int i = 0; i < 100 && heard.size() < frame(Bytes{0xF7, 42}).size(); ++i) {
    auto got = port->read(Millis(10));
    ASSERT_TRUE(std::holds_alternative<Bytes>(got));
    heard.insert(heard.end(), std::get<Bytes>(got).begin(), std::get<Bytes>(got).end());
  }
  TearDown();  // stop the server before reading its log
  EXPECT_EQ(logged, (std::vector<std::string>{"send    f7 2a (the program's Send message)"}));
}

// A host at a serial tower (which echoes its bytes) still gets its replies at
// the first try while a program broadcasts a message every 1/100 s.
TEST_F(PtyBrick, BroadcastsDoNotCostTheHostRetries) {
  ASSERT_FALSE(brick.vm.load(brick.vm.program(), test::broadcasting_program()));
  brick.vm.start_program();
  start();
  auto port = host();
  ASSERT_TRUE(port);
  Link link = make_link(*port);
  for (int i = 0; i < 40; ++i) {  // about 200 ms: some 20 broadcasts
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    auto r = run_remote(link, {"get", "var", "3"});
    ASSERT_TRUE(std::holds_alternative<std::string>(r)) << std::get<RemoteError>(r).message;
    EXPECT_EQ(std::get<std::string>(r), "7\n");
  }
  EXPECT_EQ(link.stats.attempts, link.stats.requests);
}

TEST(LinkPort, ResolvesAliasesAndTheEnvironment) {
  EXPECT_EQ(resolve_port(std::nullopt, std::nullopt).path, kUsbTowerPath);
  EXPECT_EQ(resolve_port(std::nullopt, std::nullopt).kind, PortKind::Usb);
  EXPECT_EQ(resolve_port(std::string("serial"), std::nullopt).path, kSerialTowerPath);
  EXPECT_EQ(resolve_port(std::nullopt, std::string("serial")).kind, PortKind::Serial);
  EXPECT_EQ(resolve_port(std::string("usb"), std::string("serial")).kind, PortKind::Usb);  // --port wins
  EXPECT_EQ(resolve_port(std::string("usb:/dev/x"), std::nullopt).path, "/dev/x");
  EXPECT_EQ(resolve_port(std::string("serial:/dev/y"), std::nullopt).kind, PortKind::Serial);
}

TEST(LinkPort, MissingDeviceSaysWhatToCheck) {
  auto r = open_port({"/dev/nonexistent-tower", PortKind::Usb});
  ASSERT_TRUE(std::holds_alternative<TransportError>(r));
  EXPECT_NE(std::get<TransportError>(r).message.find("does not exist"), std::string::npos);
  // nqc mode names the port with -S, not --port.
  EXPECT_NE(std::get<TransportError>(r).message.find("--port, -S in nqc mode, or RCX_PORT"), std::string::npos);
}

// /dev/null opened as a USB tower "was closed" at the first read (exit 4,
// the RCX did not answer); /dev/zero talked until the retries ran out. Both
// are character devices, neither a terminal nor the tower driver's.
TEST(LinkPort, ACharacterDeviceThatIsNoTowerIsRefusedWhenOpened) {
  for (const char* path : {"/dev/null", "/dev/zero"}) {
    if (!std::filesystem::exists(path)) continue;
    for (PortKind kind : {PortKind::Usb, PortKind::Serial}) {
      auto r = open_port({path, kind});
      ASSERT_TRUE(std::holds_alternative<TransportError>(r)) << path;
      EXPECT_NE(std::get<TransportError>(r).message.find(std::string(path) + " is not a tower: a character device"),
                std::string::npos)
          << std::get<TransportError>(r).message;
    }
  }
}

TEST(LinkPort, APtyNobodyServesTimesOutCleanly) {
  auto opened = open_pty();
  ASSERT_TRUE(std::holds_alternative<Pty>(opened));
  Pty pty = std::move(std::get<Pty>(opened));
  auto port = open_port({pty.slave_path, PortKind::Serial});
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<Transport>>(port));
  LinkOptions quick;
  quick.retries = 1;
  quick.reply_grace = Millis(5);
  quick.backoff = Millis(1);
  Link link = make_link(*std::get<std::unique_ptr<Transport>>(port), quick);
  auto r = transact(link, Bytes{0x10});
  ASSERT_TRUE(std::holds_alternative<LinkError>(r));
  EXPECT_NE(std::get<LinkError>(r).message.find("not even the echo"), std::string::npos);
  close_pty(pty);
}

}  // namespace
}  // namespace rcx
