// `rcxc run a.nqc b.nqc`: several bricks in one room, their IR messages
// reaching each other; one timeline, each brick's final state, exit codes.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "rcx/image.h"
#include "tests/support/process.h"

using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {

// The master sends 5 when its touch sensor is pressed and waits for the
// answer; the slave answers what it got plus one.
constexpr const char* kMaster =
    "int reply;\n"
    "task main() {\n"
    "  SetSensor(SENSOR_1, SENSOR_TOUCH); ClearMessage();\n"
    "  until (SENSOR_1 == 1); SendMessage(5);\n"
    "  until (Message() != 0); reply = Message(); PlaySound(SOUND_CLICK);\n"
    "}\n";
constexpr const char* kSlave =
    "int got;\n"
    "task main() {\n"
    "  ClearMessage(); until (Message() != 0); got = Message();\n"
    "  On(OUT_A); SendMessage(got + 1);\n"
    "}\n";
constexpr const char* kPress = "[[input]]\nat_ms = 300\nsensor = 1\nraw = 100\n";

}  // namespace

TEST(RunRoomCli, AMasterAndASlaveTalk) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("master.nqc", kMaster), d.write("slave.nqc", kSlave), "--scenario",
                     d.write("press.toml", kPress), "--for", "3000"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Sent at 302 ms, on the air 41.25 ms, seen at the slave's next instruction.
  EXPECT_NE(r.out.find("     302.000 ms  1 master  message sent 5\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("     344.000 ms  2 slave   message received 5\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 slave   message sent 6\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 master  message received 6\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n1 master:\nstopped: ended at"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("var[0] reply = 6\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n2 slave:\nstopped: ended at"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("var[0] got = 5\n"), std::string::npos) << r.out;
  // Without the press the master never sends: the slave waits to the limit.
  auto idle = run_rcxc({"run", (d.path + "/master.nqc"), (d.path + "/slave.nqc"), "--for", "1000"});
  ASSERT_EQ(idle.exit_code, 0) << idle.err;
  EXPECT_EQ(idle.out.find("message sent"), std::string::npos) << idle.out;
  EXPECT_NE(idle.out.find("\n2 slave:\nstopped: time_limit at 1000.000 ms"), std::string::npos) << idle.out;
}

TEST(RunRoomCli, TheReportHasEachBrickAndEveryMessage) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("a.nqc", "task main() { SendMessage(9); }\n"),
                     d.write("b.nqc", "task main() { SendMessage(4); }\n"), "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["bricks"].size(), 2u);
  EXPECT_EQ(j["bricks"][0]["label"], "1 a");
  EXPECT_EQ(j["bricks"][1]["report"]["stop"], "ended");
  ASSERT_EQ(j["messages"].size(), 2u);
  // Both on the air from 4 ms (after the start-up's power and direction):
  // each garbles the other.
  EXPECT_EQ(j["messages"][0]["collided"], true);
  EXPECT_EQ(j["messages"][1]["collided"], true);
  EXPECT_EQ(j["messages"][0]["end"], 45.25);
  auto text = run_rcxc({"run", (d.path + "/a.nqc"), (d.path + "/b.nqc")});
  EXPECT_NE(text.out.find("IR   message 9 from 1 a lost: another brick sent at the same time (on the air 4.000 "
                          "to 45.250 ms)\n"),
            std::string::npos)
      << text.out;
}

TEST(RunRoomCli, EachScenarioGoesToItsProgram) {
  TempDir d;
  const char* reader = "int seen;\ntask main() { SetSensor(SENSOR_1, SENSOR_TOUCH); until (SENSOR_1 == 1); seen = 1; }\n";
  auto r = run_rcxc({"run", d.write("x.nqc", reader), d.write("y.nqc", reader), "--scenario",
                     d.write("none.toml", "# no inputs\n"), "--scenario", d.write("press.toml", kPress), "--for",
                     "1000"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("     300.000 ms  2 y  input: sensor 1 raw 100\n"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("1 x  input"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n2 y:\nstopped: ended at"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n1 x:\nstopped: time_limit at"), std::string::npos) << r.out;
}

TEST(RunRoomCli, WhatARoomCannotDoIsAUsageError) {
  TempDir d;
  std::string a = d.write("a.nqc", "task main() { }\n"), b = d.write("b.nqc", "task main() { }\n");
  std::string s = d.write("s.toml", kPress);
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"run", a, b, "--scenario", s, "--scenario", s, "--scenario", s},
       "3 scenarios for 2 programs: give at most one --scenario per program, in the programs' order"},
      {{"run", a, "--scenario", s, "--scenario", s}, "2 scenarios for one program: give one --scenario"},
      {{"run", a, b, "--trace", (d.path + "/t.vcd")}, "a room's trace is an HTML page, a drawing per brick on one time axis: --trace F.html"},
      {{"run", a, b, "--nxt", "usb"}, "--nxt drives one NXT with one program, not 2"},
      {{"run", a, b, a, b, a, b, a, b, a}, "9 programs: a room holds at most 8 bricks"},
      {{"run", "-", a, "-"}, "'-' given more than once: the standard input holds one program"},
  };
  for (const auto& [args, said] : cases) {
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << said << ": " << r.err;
    EXPECT_NE(r.err.find("rcxc run: " + said), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

TEST(RunRoomCli, AProgramThatDoesNotCompileStopsTheRoomBeforeItRuns) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("good.nqc", "task main() { SendMessage(1); }\n"),
                     d.write("bad.nqc", "task main() { Wiat(1); }\n")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.nqc:1:15: error: 'Wiat' is not declared"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
}

TEST(RunRoomCli, AFaultInOneBrickIsExit1AndNamesIt) {
  TempDir d;
  // Task 0 branches past its end.
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x27, 0x40}});
  auto r = run_rcxc({"run", d.write("ok.nqc", "task main() { Wait(50); }\n"), d.write("x.rcx", rcx::write_image(img))});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("rcxc run: brick 2 x faulted: branch to"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("\n2 x:\nstopped: fault at 0.000 ms\nfault: task 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n1 ok:\nstopped: ended at 504.000 ms"), std::string::npos) << r.out;
  // An image that does not read stops the room before it runs.
  auto unread = run_rcxc({"run", (d.path + "/ok.nqc"), d.write("y.rcx", std::string("RCXI"))});
  EXPECT_EQ(unread.exit_code, 1) << unread.err;
  EXPECT_NE(unread.err.find("y.rcx"), std::string::npos) << unread.err;
  EXPECT_EQ(unread.out, "");
}

// A room of waiting programs asked for the longest run goes from wake-up to
// wake-up, as one brick does; it went round every 41.25 ms of virtual time,
// 2.7e10 rounds for 2^40 ms.
TEST(RunRoomCli, WaitingBricksOverTheLongestRunEndQuickly) {
  TempDir d;
  std::string sleeper = d.write("s.nqc", "task main() { while (true) Wait(32767); }\n");
  auto r = run_rcxc({"run", sleeper, sleeper, "--for", "1099511627776"}, "", 60'000);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\n2 s:\nstopped: time_limit at 1099511627776.000 ms"), std::string::npos) << r.out;
}

// The NQC tutorial's own master and slave (read from the corpus, skipped
// when it is absent): the master's three messages drive the slave's motors
// forward, back and off, each 41.25 ms after it was sent and a few
// instructions later.
TEST(RunRoomCli, TheTutorialsMasterDrivesItsSlave) {
  const std::string dir = std::string(RCXC_CORPUS_DIR) + "/tutorial/";
  if (!std::filesystem::exists(dir + "11_master.nqc") || !std::filesystem::exists(dir + "11_slave.nqc"))
    GTEST_SKIP() << "no corpus at " << dir;
  auto r = run_rcxc({"run", dir + "11_master.nqc", dir + "11_slave.nqc", "--for", "5000", "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["messages"].size(), 3u);
  std::vector<std::pair<double, std::string>> slave_a;  // when output A changed, to what
  for (const auto& e : j["bricks"][1]["report"]["events"])
    if (e["kind"] == "output" && e["output"] == "A")
      slave_a.emplace_back(e["t"].get<double>(), e["mode"].get<std::string>() + " " + e["dir"].get<std::string>());
  ASSERT_EQ(slave_a.size(), 3u) << r.out;
  for (std::size_t i = 0; i < 3; ++i) {
    double sent = j["messages"][i]["sent"].get<double>();
    EXPECT_EQ(j["messages"][i]["received_by"], nlohmann::json::array({2}));
    EXPECT_GT(slave_a[i].first, sent + 41.25);
    EXPECT_LT(slave_a[i].first, sent + 41.25 + 20);
  }
  EXPECT_EQ(slave_a[0].second, "on fwd");
  EXPECT_EQ(slave_a[1].second, "on rev");
  EXPECT_EQ(slave_a[2].second, "off rev");
}

// `--trace F.html` of a room: one drawing per brick under its label, all on
// one time axis (the slave's run is longer; the master's drawing spans it too).
TEST(RunRoomCli, ARoomsTraceDrawsEachBrickOnOneAxis) {
  TempDir d;
  std::string page = d.path + "/room.html";
  auto r = run_rcxc({"run", d.write("master.nqc", kMaster), d.write("slave.nqc", kSlave), "--scenario",
                     d.write("press.toml", kPress), "--for", "3000", "--trace", page});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto bytes = d.read("room.html");
  std::string html(bytes.begin(), bytes.end());
  EXPECT_NE(html.find("<h1>master.nqc + slave.nqc</h1>"), std::string::npos);
  EXPECT_NE(html.find("<h2>1 master</h2>\n<svg"), std::string::npos);
  EXPECT_NE(html.find("<h2>2 slave</h2>\n<svg"), std::string::npos);
  EXPECT_EQ(html.find("<h2>"), html.rfind("<h2>1 master</h2>"));
  // Both drawings' axes end at the same tick: the last label is the same in each.
  auto last_tick = [&](std::size_t from, std::size_t to) {
    std::size_t at = html.rfind(" s</text>", to);
    EXPECT_NE(at, std::string::npos);
    EXPECT_GT(at, from);
    return html.substr(html.rfind('>', at) + 1, at - html.rfind('>', at) - 1);
  };
  std::size_t second = html.find("<h2>2 slave</h2>");
  EXPECT_EQ(last_tick(0, second), last_tick(second, html.size()));
}

// A message whose packet ends after every program has: the timeline ended
// where the last program did and left the message out without a word.
TEST(RunRoomCli, AMessageThatOutlivesEveryProgramStillSaysItReachedNoBrick) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("last.nqc", "task main() { SendMessage(3); }\n"),
                     d.write("gone.nqc", "task main() { }\n"), "--for", "1000"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("45.250 ms  IR      message 3 from 1 last reached no brick: no other program was running\n"),
            std::string::npos)
      << r.out;
  // One still going out when the room's time is up reached nobody yet: the
  // report says so apart from a collision or an empty room.
  auto cut = run_rcxc({"run", d.path + "/last.nqc", d.path + "/gone.nqc", "--for", "20", "--report", "json"});
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  auto j = nlohmann::json::parse(cut.out);
  ASSERT_EQ(j["messages"].size(), 1u);
  EXPECT_EQ(j["messages"][0]["unfinished"], true);
  EXPECT_EQ(j["messages"][0]["collided"], false);
  auto whole = nlohmann::json::parse(run_rcxc({"run", d.path + "/last.nqc", d.path + "/gone.nqc", "--report", "json"}).out);
  EXPECT_EQ(whole["messages"][0]["unfinished"], false);
  EXPECT_EQ(run_rcxc({"run", d.path + "/last.nqc", d.path + "/gone.nqc", "--for", "20"}).out.find("IR"),
            std::string::npos);
}
