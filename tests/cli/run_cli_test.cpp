// `rcxc run` end to end: loading, options, scenario errors, report, traces,
// exit codes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rcx/image.h"
#include "tests/support/process.h"
#include "tomlfile/longest_run.h"

using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {

// task 0 "main": var0 = 5; A on; Wait(10); A off.  Variable 0 is "count".
std::vector<std::uint8_t> program_bytes() {
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0,
                           {0x14, 0x00, 0x02, 0x05, 0x00, 0x21, 0x81, 0x43, 0x02, 0x0a, 0x00, 0x21, 0x41}});
  img.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  img.symbols.push_back({rcx::SymbolType::Variable, 0, "count"});
  return rcx::write_image(img);
}


}  // namespace

TEST(RunCli, ReportJson) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("p.rcx", program_bytes()), "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["stop"], "ended");
  EXPECT_EQ(j["globals"]["count"], 5);
  EXPECT_EQ(j["outputs"]["A"]["mode"], "off");
  // 2 ms per instruction: A on at 2 ms, the wait at 4 ms, A off at 104 ms, end at 106 ms.
  EXPECT_EQ(j["time_ms"], 106);
  EXPECT_EQ(j["events"][1]["t"], 2);
  EXPECT_EQ(j["events"][2]["t"], 104);
}

TEST(RunCli, TimelineByDefault) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("p.rcx", program_bytes())});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("output A on fwd power 7"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("stopped: ended at 106.000 ms"), std::string::npos) << r.out;
}

TEST(RunCli, TimeLimitAndInstructionCost) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("p.rcx", program_bytes()), "--for", "50", "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["stop"], "time_limit");
  EXPECT_EQ(j["time_ms"], 50);
  r = run_rcxc({"run", d.write("p.rcx", program_bytes()), "--instruction-us", "1000", "--report", "json"});
  EXPECT_EQ(nlohmann::json::parse(r.out)["time_ms"], 103);
}

TEST(RunCli, ScenarioFeedsInputs) {
  TempDir d;
  // task 0: var0 = SENSOR_1 raw after Wait(100).
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x43, 0x02, 0x64, 0x00, 0x14, 0x00, 0x0c, 0x00, 0x00}});
  auto scenario = d.write("s.toml", "[[input]]\nat_ms = 300\nsensor = 1\nraw = 444\n");
  auto r = run_rcxc({"run", d.write("p.rcx", rcx::write_image(img)), "--scenario", scenario, "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["vars"][0], 444);
}

// `--scenario /dev/null` read as a scenario of no inputs without a word. It
// still is one (so it leaves out a source's own // @input lines), and stderr
// says so, whatever makes it empty.
TEST(RunCli, AnEmptyScenarioIsARunWithoutInputsAndSaysSo) {
  TempDir d;
  auto src = d.write("p.nqc", "// @input at 10ms: message 7\n// @for 100ms\ntask main() { Wait(5); }\n");
  for (std::string scenario : {std::string("/dev/null"), d.write("e.toml", ""), d.write("c.toml", "# later\n")}) {
    auto r = run_rcxc({"run", src, "--scenario", scenario});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("rcxc run: note: " + scenario + " holds no [[input]] tables: the run has no inputs"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.out.find("message received"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("message: 0"), std::string::npos) << r.out;
  }
}

// With 1 s instructions, `--for 10` stopped at 1000 ms (the end of the
// first instruction) and showed an input of 5 ms there. It stops at 10 ms.
TEST(RunCli, ARunStopsAtForEvenWhenAnInstructionTakesLonger) {
  TempDir d;
  auto scenario = d.write("s.toml", "[[input]]\nat_ms = 5\nmessage = 3\n");
  auto r = run_rcxc({"run", d.write("p.rcx", program_bytes()), "--instruction-us", "1000000", "--for", "10",
                     "--scenario", scenario, "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["stop"], "time_limit");
  EXPECT_EQ(j["time_ms"], 10);
  for (const auto& e : j["events"]) EXPECT_LE(e["t"].get<double>(), 10) << e.dump();
  r = run_rcxc({"run", d.write("p.rcx", program_bytes()), "--instruction-us", "1000000", "--for", "10"});
  EXPECT_NE(r.out.find("stopped: time_limit at 10.000 ms"), std::string::npos) << r.out;
}

TEST(RunCli, ScenarioErrorNamesTheLine) {
  TempDir d;
  auto scenario = d.write("s.toml", "[[input]]\nat_ms = 300\nsensor = 1\nraw = 5000\n");
  auto r = run_rcxc({"run", d.write("p.rcx", program_bytes()), "--scenario", scenario});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("s.toml:4: 'raw' = 5000 is out of range 0..1023"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

TEST(RunCli, BadImageIsAClearError) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("bad.rcx", std::string("RCXI\x02\x01"))});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.rcx"), std::string::npos) << r.err;
  r = run_rcxc({"run", d.path + "/missing.rcx"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot open"), std::string::npos) << r.err;
}

TEST(RunCli, NqcSourceIsCompiledInMemory) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("p.nqc", "int speed;\ntask main() { speed = 3; On(OUT_B); Wait(20); Off(OUT_B); }\n"),
                     "--report", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["stop"], "ended");
  EXPECT_EQ(j["globals"]["speed"], 3);
  EXPECT_EQ(j["outputs"]["B"]["mode"], "off");
  int b_changes = 0;
  for (const auto& e : j["events"]) b_changes += e["kind"] == "output" && e["output"] == "B";
  EXPECT_EQ(b_changes, 2);  // on, then off 0.2 s later
}

TEST(RunCli, NqcCompileErrorsAreReported) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("bad.nqc", "task main() { x = ; }\n")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.nqc:1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("does not compile"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

TEST(RunCli, FaultExitsWithFailureAndReports) {
  TempDir d;
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x27, 0x7f}});
  auto r = run_rcxc({"run", d.write("f.rcx", rcx::write_image(img)), "--report", "json"});
  EXPECT_EQ(r.exit_code, 1);
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["stop"], "fault");
  EXPECT_EQ(j["fault"]["opcode"], 0x27);
  // Dated at the start of the instruction that faulted, which never ran
  // (it said 2.000 ms: the time after it).
  EXPECT_EQ(j["time_ms"], 0);
  r = run_rcxc({"run", d.write("f.rcx", rcx::write_image(img))});
  EXPECT_NE(r.out.find("stopped: fault at 0.000 ms\n"), std::string::npos) << r.out;
}

// A source's @for keeps its fraction of a millisecond, as `rcxc test` does:
// `rcxc run` cut it to whole milliseconds, so "@for 0.5ms" ran no time at all
// and "@for 2.5ms" 2 ms.
TEST(RunCli, ASourcesForKeepsItsFractionOfAMillisecond) {
  TempDir d;
  for (auto [given, shown] : {std::pair{"0.5ms", "0.500"}, std::pair{"2.5ms", "2.500"}, std::pair{"0.0125s", "12.500"}}) {
    auto src = d.write("p.nqc", std::string("// @for ") + given + "\ntask main() { while (true) { PlaySound(1); } }\n");
    auto r = run_rcxc({"run", src});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(std::string("stopped: time_limit at ") + shown + " ms\n"), std::string::npos) << given << r.out;
  }
}

TEST(RunCli, BadOptionsAreUsageErrors) {
  TempDir d;
  auto p = d.write("p.rcx", program_bytes());
  EXPECT_EQ(run_rcxc({"run", p, "--report", "xml"}).exit_code, 2);
  EXPECT_EQ(run_rcxc({"run", p, "--for", "-5"}).exit_code, 2);
  EXPECT_EQ(run_rcxc({"run", p, "--trace", d.path + "/t.txt"}).exit_code, 2);
  EXPECT_EQ(run_rcxc({"run"}).exit_code, 2);
}

TEST(RunCli, TracesAreWritten) {
  TempDir d;
  auto p = d.write("p.rcx", program_bytes());
  auto r = run_rcxc({"run", p, "--trace", d.path + "/t.vcd"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream vcd(d.path + "/t.vcd");
  std::string text((std::istreambuf_iterator<char>(vcd)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("$enddefinitions $end"), std::string::npos);
  EXPECT_NE(text.find(" count $end"), std::string::npos);
  r = run_rcxc({"run", p, "--trace", d.path + "/t.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream js(d.path + "/t.json");
  auto j = nlohmann::json::parse(js);
  ASSERT_TRUE(j.is_array());
  EXPECT_EQ(j[0]["kind"], "task_start");
  r = run_rcxc({"run", p, "--trace", d.path + "/no/such/dir/t.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot write trace"), std::string::npos);
  EXPECT_EQ(r.out, "") << "the trace's folder is checked before the run, which reports on stdout";
}

TEST(RunCli, DrawnTracesAreWrittenAndStaySmallForLongRuns) {
  TempDir d;
  // Ten minutes of output A changing every 10 ms, a click, a message and a
  // display change each round: tens of thousands of events.
  auto p = d.write("busy.nqc",
                   "int n;\ntask main() { while (true) { OnFwd(OUT_A); Wait(1); OnRev(OUT_A); Wait(1); Off(OUT_A);\n"
                   "  PlaySound(SOUND_CLICK); SendMessage(n % 255); n++; SelectDisplay(n % 7); } }\n");
  for (std::string name : {"run.svg", "run.html"}) {
    auto r = run_rcxc({"run", p, "--for", "600000", "--trace", d.path + "/" + name});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::string text = rcxc::test::read_text_file(d.path + "/" + name);
    EXPECT_NE(text.find("<svg xmlns="), std::string::npos);
    EXPECT_NE(text.find(">600 s</text>"), std::string::npos);
    EXPECT_NE(text.find("sound SOUND_CLICK"), std::string::npos);
    EXPECT_LT(text.size(), 1'000'000u) << name;
  }
  // The text timeline of the same run has every event.
  auto r = run_rcxc({"run", p, "--for", "600000"});
  EXPECT_GT(r.out.size(), 2'000'000u);
  EXPECT_NE(r.out.find("ms  sound SOUND_CLICK\n"), std::string::npos);
  EXPECT_NE(r.out.find("ms  display DISPLAY_OUT_A\n"), std::string::npos);
  EXPECT_NE(r.out.find("var[0] n = "), std::string::npos);
}

TEST(RunCli, CompilerTemporariesAreNotShown) {
  TempDir d;
  // The products need temporaries (slots 3..5 here) that end non-zero.
  auto p = d.write("t.nqc", "int a, b, c;\ntask main() { a = 3; b = 4; c = (a * b) + (a * 7 - b) * (b - a * 2); }\n");
  auto r = run_rcxc({"run", p, "--trace", d.path + "/t.vcd"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("var[0] a = 3\nvar[1] b = 4\nvar[2] c = -22\nmessage:"), std::string::npos) << r.out;
  std::string vcd = rcxc::test::read_text_file(d.path + "/t.vcd");
  for (const char* name : {" a $end", " b $end", " c $end"}) EXPECT_NE(vcd.find(name), std::string::npos) << name;
  EXPECT_EQ(vcd.find(" var3 $end"), std::string::npos) << vcd;
  EXPECT_EQ(vcd.find(" var31 $end"), std::string::npos) << vcd;
}

TEST(RunCli, SeedChangesRandomValues) {
  TempDir d;
  rcx::Image img;
  std::vector<std::uint8_t> c;
  for (int i = 0; i < 8; ++i) c.insert(c.end(), {0x14, static_cast<std::uint8_t>(i), 0x04, 0xe8, 0x03});  // Random(1000)
  img.fragments.push_back({rcx::FragmentType::Task, 0, c});
  auto p = d.write("r.rcx", rcx::write_image(img));
  auto a = nlohmann::json::parse(run_rcxc({"run", p, "--report", "json", "--seed", "7"}).out)["vars"];
  auto b = nlohmann::json::parse(run_rcxc({"run", p, "--report", "json", "--seed", "7"}).out)["vars"];
  auto c2 = nlohmann::json::parse(run_rcxc({"run", p, "--report", "json", "--seed", "8"}).out)["vars"];
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c2);
}

TEST(RunCli, OddSymbolNamesDoNotBreakReportsOrTraces) {
  TempDir d;
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x14, 0x00, 0x02, 0x05, 0x00}});
  img.symbols.push_back({rcx::SymbolType::Variable, 0, std::string("bad \xff name")});
  auto p = d.write("odd.rcx", rcx::write_image(img));
  auto r = run_rcxc({"run", p, "--report", "json", "--trace", d.path + "/t.vcd"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["vars"][0], 5);
  EXPECT_EQ(j["globals"].size(), 1u);
  std::ifstream vcd(d.path + "/t.vcd");
  std::string text((std::istreambuf_iterator<char>(vcd)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find(" bad___name $end"), std::string::npos) << text;
}

TEST(RunCli, ScenarioThatIsADirectoryIsExit1) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("p.rcx", program_bytes()), "--scenario", d.path});
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.err.find(d.path + ": is a directory, not a scenario file"), std::string::npos) << r.err;
}

TEST(RunCli, ControlCharactersInSymbolNamesAreEscapedInText) {
  // Names come from the image: an escape sequence could colour the
  // terminal, a newline forge a line of the timeline.
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x14, 0x00, 0x02, 0x05, 0x00}});
  img.symbols.push_back({rcx::SymbolType::Task, 0, "ma\x1b[31min"});
  img.symbols.push_back({rcx::SymbolType::Variable, 0, "n\n  99 ms  output A on\\"});
  TempDir d;
  auto bytes = rcx::write_image(img);
  auto r = run_rcxc({"run", d.write("p.rcx", bytes)});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("task 0 (ma\\x1b[31min) started"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("n\\x0a  99 ms  output A on\\x5c = 5"), std::string::npos) << r.out;
  auto dis = run_rcxc({"disasm", d.path + "/p.rcx"});
  ASSERT_EQ(dis.exit_code, 0) << dis.err;
  EXPECT_NE(dis.out.find("task 0 ma\\x1b[31min"), std::string::npos) << dis.out;
}

// With --nxt naming a port that is not there, the run never started, yet the
// timeline of a machine at 0 ms ("stopped: running at 0.000 ms", every
// output floating) was printed before exit 3 as if it had run.
TEST(RunCli, AnNxtPortThatCannotBeOpenedPrintsNoTimeline) {
  TempDir d;
  auto r = run_rcxc({"run", d.write("p.rcx", program_bytes()), "--nxt", d.path + "/no-such-nxt"});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("no-such-nxt does not exist"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
}

// A --for past 64 bits was "more than 18446744073709551615" and a negative
// one "not a whole number 0 or more", where 0 said "outside 1..2^40": each
// names the range the option takes now.
TEST(RunCli, AForOutOfRangeNamesTheRangeItTakes) {
  TempDir d;
  std::string image = d.write("p.rcx", program_bytes());
  for (const std::string value : {"99999999999999999999", "-5", "0", "1099511627777"})
    for (const std::string command : {"run", "compare"}) {
      auto r = run_rcxc({command, image, "--for", value});
      EXPECT_EQ(r.exit_code, 2) << command << " " << value << ": " << r.err;
      EXPECT_NE(r.err.find("--for: '" + value + "' is outside 1..1099511627776 ms"), std::string::npos) << r.err;
    }
  // A time with a unit, as a test's @for takes it, is told the unit --for takes.
  auto seconds = run_rcxc({"run", image, "--for", "10s"});
  EXPECT_EQ(seconds.exit_code, 2);
  EXPECT_NE(seconds.err.find("--for: '10s' is not a whole number (1..1099511627776 ms)"), std::string::npos)
      << seconds.err;
}

// The longest run is one bound (tomlfile/longest_run.h) that every way of
// naming a run's time meets: --for of run and compare, a scenario's at_ms
// and a test's @for each take it and refuse a millisecond more, saying so.
// The three used to be three constants that only agreed by care.
TEST(RunCli, EveryRunTimeStopsAtTheOneLongestRun) {
  TempDir d;
  const std::string longest = std::to_string(rcxc::kLongestRunMs);
  const std::string beyond = std::to_string(rcxc::kLongestRunMs + 1);
  std::string image = d.write("p.rcx", program_bytes());
  for (const std::string command : {"run", "compare"}) {
    auto r = run_rcxc({command, image, "--for", beyond});
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find("--for: '" + beyond + "' is outside 1.." + longest), std::string::npos) << r.err;
  }
  EXPECT_EQ(run_rcxc({"run", image, "--for", longest}).exit_code, 0) << "the program ends at once";

  std::string late = d.write("late.toml", "[[input]]\nat_ms = " + beyond + "\nmessage = 1\n");
  auto r = run_rcxc({"run", image, "--scenario", late});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(late + ":2: 'at_ms' = " + beyond + " is later than the longest run (" + longest +
                       " ms, about 35 years)"),
            std::string::npos)
      << r.err;
  std::string last = d.write("last.toml", "[[input]]\nat_ms = " + longest + "\nmessage = 1\n");
  EXPECT_EQ(run_rcxc({"run", image, "--scenario", last}).exit_code, 0);

  std::string test = d.write("t.nqc", "// @for " + beyond + "\ntask main() {}\n");
  r = run_rcxc({"test", test});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find(test + ":1: error: bad directive: expected run length (like 500ms or 2s), found '" + beyond +
                                 "', which is later than the longest run (" + longest + " ms, about 35 years)"),
            std::string::npos)
      << r.out << r.err;
  std::string ok = d.write("ok.nqc", "// @for " + longest + "\ntask main() {}\n");
  r = run_rcxc({"test", ok});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
}

// `--for abc` (or 1e3, 1.5) was "Value abc not in range 1 to ...", as if
// abc were a number too large; it is no number at all.
TEST(RunCli, AForThatIsNoWholeNumberSaysSo) {
  TempDir d;
  std::string image = d.write("p.rcx", program_bytes());
  for (const std::string value : {"abc", "1e3", "1.5"})
    for (const std::string command : {"run", "compare"}) {
      auto r = run_rcxc({command, image, "--for", value});
      EXPECT_EQ(r.exit_code, 2) << command << " " << value << ": " << r.err;
      EXPECT_NE(r.err.find("--for: '" + value + "' is not a whole number"), std::string::npos) << r.err;
    }
}

// A JSON report or trace of many events was built as one tree, about 550
// bytes an event: 5 000 000 events (the most a run keeps) took 3.2 GB for
// `--report json` where the run took 530 MB. Written event by event, it
// stays near what the run itself takes; here 500 000 events (tree: ~330 MB).
TEST(RunCli, AJsonReportOrTraceOfManyEventsIsWrittenWithoutATree) {
  if (rcxc::test::built_with_asan()) GTEST_SKIP() << "memory is not measured under AddressSanitizer";
  TempDir d;
  std::string src = d.write("tones.nqc", "task main()\n{\n  while (true) { PlayTone(440, 1); }\n}\n");
  const std::string run = "'" RCXC_BINARY "' run '" + src + "' --for 5000000";
  for (const std::string& tail : {std::string(" --report json > /dev/null"), " --trace '" + d.path + "/t.json' > /dev/null"}) {
    auto r = rcxc::test::run_process({"/bin/sh", "-c", run + tail}, "", 120'000);
    EXPECT_EQ(r.exit_code, 0) << tail << "\n" << r.err;
    EXPECT_LT(r.max_rss_kb, 200 * 1024) << tail;
  }
  // The trace is whole: it parses, and holds every event.
  std::ifstream in(d.path + "/t.json");
  auto trace = nlohmann::json::parse(in, nullptr, false);
  ASSERT_TRUE(trace.is_array());
  EXPECT_GT(trace.size(), 400'000u);
}
