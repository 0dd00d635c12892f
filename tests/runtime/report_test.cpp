// The JSON report and traces built from a finished run.
#include "runtime/report.h"

#include <gtest/gtest.h>

#include <sstream>

#include "tests/runtime/vm_support.h"

using namespace vmtest;

namespace {

rcx::Image named(rcx::Image img) {
  img.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  img.symbols.push_back({rcx::SymbolType::Variable, 0, "count"});
  img.symbols.push_back({rcx::SymbolType::Variable, 2, "speed"});
  return img;
}

}  // namespace

TEST(Report, JsonHasEveryField) {
  auto img = named(image({{0, code({set(0, 5), set(2, -3), out(0x81), dir(0x04), sound(2), display(IMM, 4), logsize(3),
                                    lognext(VAR, 0), set(1, 65), msgsend(VAR, 1)})}}));
  auto m = run(img);
  auto j = rcx::report_json(m, img);
  EXPECT_EQ(j["stop"], "ended");
  EXPECT_EQ(j["time_ms"], 10);
  EXPECT_FALSE(j.contains("fault"));
  ASSERT_EQ(j["vars"].size(), 32u);
  EXPECT_EQ(j["vars"][2], -3);
  EXPECT_EQ(j["globals"]["count"], 5);
  EXPECT_EQ(j["globals"]["speed"], -3);
  EXPECT_EQ(j["outputs"]["A"]["mode"], "on");
  EXPECT_EQ(j["outputs"]["A"]["dir"], "fwd");
  EXPECT_EQ(j["outputs"]["A"]["power"], 7);
  EXPECT_EQ(j["outputs"]["C"]["mode"], "float");
  EXPECT_EQ(j["outputs"]["C"]["dir"], "rev");
  EXPECT_EQ(j["message"], 0);
  EXPECT_EQ(j["display"], 4);
  EXPECT_EQ(j["datalog"], nlohmann::json::array({5}));
  const auto& ev = j["events"];
  ASSERT_EQ(ev.size(), 8u);
  EXPECT_EQ(ev[0], (nlohmann::json{{"t", 0}, {"kind", "task_start"}, {"task", 0}, {"name", "main"}}));
  EXPECT_EQ(ev[1], (nlohmann::json{{"t", 2}, {"kind", "output"}, {"output", "A"}, {"mode", "on"}, {"dir", "fwd"}, {"power", 7}}));
  EXPECT_EQ(ev[2], (nlohmann::json{{"t", 3}, {"kind", "output"}, {"output", "C"}, {"mode", "float"}, {"dir", "rev"}, {"power", 7}}));
  EXPECT_EQ(ev[3], (nlohmann::json{{"t", 4}, {"kind", "sound"}, {"sound", 2}}));
  EXPECT_EQ(ev[4], (nlohmann::json{{"t", 5}, {"kind", "display"}, {"display", 4}}));
  EXPECT_EQ(ev[5], (nlohmann::json{{"t", 7}, {"kind", "datalog"}, {"type", 0}, {"value", 5}}));
  EXPECT_EQ(ev[6], (nlohmann::json{{"t", 9}, {"kind", "message_sent"}, {"value", 65}}));
  EXPECT_EQ(ev[7], (nlohmann::json{{"t", 10}, {"kind", "task_stop"}, {"task", 0}, {"name", "main"}}));
}

TEST(Report, FaultIsReported) {
  auto img = named(image({{0, code({set(0, 1), Bytes{0x10}})}}));
  auto m = run(img);
  auto j = rcx::report_json(m, img);
  EXPECT_EQ(j["stop"], "fault");
  EXPECT_EQ(j["fault"]["task"], 0);
  EXPECT_EQ(j["fault"]["address"], 5);
  EXPECT_EQ(j["fault"]["opcode"], 0x10);
  EXPECT_FALSE(j["fault"].contains("sub"));
  EXPECT_NE(rcx::timeline_text(m, img).find("fault: task 0 (main), address 5, opcode 0x10"), std::string::npos);
}

TEST(Report, TimelineIsReadable) {
  auto img = named(image({{0, code({out(0x81), wait(100), out(0x41)})}}));
  auto m = run(img);
  std::string text = rcx::timeline_text(m, img);
  EXPECT_NE(text.find("0.000 ms  output A on fwd power 7"), std::string::npos) << text;
  EXPECT_NE(text.find("1001.000 ms  output A off fwd power 7"), std::string::npos) << text;
  EXPECT_NE(text.find("stopped: ended at 1002.000 ms"), std::string::npos) << text;
  EXPECT_NE(text.find("var[0] count = 0"), std::string::npos) << text;
}

TEST(Report, VcdDeclaresSignalsAndDumpsChanges) {
  rcx::Config c = ms_config();
  c.trace_variables = true;
  auto img = named(image({{0, code({set(0, 3), wait(1), out(0x81)})}}));
  auto m = run(img, 1000, c);
  std::string vcd = rcx::trace_vcd(m, img);
  EXPECT_EQ(vcd.rfind("$date", 0), 0u);
  EXPECT_NE(vcd.find("$timescale 1us $end"), std::string::npos);
  EXPECT_NE(vcd.find("$var wire 16 0 count $end"), std::string::npos) << vcd;
  EXPECT_NE(vcd.find("$enddefinitions $end"), std::string::npos);
  EXPECT_NE(vcd.find("#11000\nb10 !"), std::string::npos) << vcd;  // out_A_mode = on (2) at 11 ms
  EXPECT_NE(vcd.find("b0000000000000011 0"), std::string::npos) << vcd;  // count = 3
}

TEST(Report, TraceJsonIncludesInputs) {
  rcx::Machine m(ms_config());
  m.schedule({5000, rcx::SensorRawInput{0, 300}});
  m.run_until(10'000);
  rcx::Image img;
  auto j = rcx::trace_json(m, img);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0], (nlohmann::json{{"t", 5}, {"kind", "sensor"}, {"sensor", 1}, {"raw", 300}}));
  // An unconfigured sensor reads its raw value.
  EXPECT_EQ(j[1], (nlohmann::json{{"t", 5}, {"kind", "sensor_reading"}, {"sensor", 1}, {"value", 300}}));
}

TEST(Report, TraceJsonHasIncomingMessagesButTheReportLeavesInputsOut) {
  rcx::Machine m(ms_config());
  m.schedule({5000, rcx::MessageInput{42}});
  m.run_until(10'000);
  rcx::Image img;
  auto j = rcx::trace_json(m, img);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0], (nlohmann::json{{"t", 5}, {"kind", "message_received"}, {"value", 42}}));
  EXPECT_TRUE(rcx::report_json(m, img)["events"].empty());
  EXPECT_EQ(rcx::report_json(m, img)["message"], 42);
}

TEST(Report, TimelineNamesSoundsDisplaysDatalogSourcesAndIncomingMessages) {
  rcx::EventNames names;
  names.sounds = {{1, "SOUND_DOUBLE_BEEP"}};
  names.displays = {{4, "DISPLAY_OUT_A"}};
  auto img = named(image({{0, code({sound(1), sound(3), display(IMM, 4), logsize(5), set(0, 12), lognext(VAR, 0),
                                    lognext(VAR, 7), lognext(TIMER, 2), lognext(SENSOR, 1), lognext(14, 0),
                                    wait(100)})}}));
  rcx::Machine m(ms_config());
  m.load(0, img);
  m.schedule({50'000, rcx::MessageInput{42}});
  m.start_program();
  m.run(2'000'000);
  std::string text = rcx::timeline_text(m, img, names);
  EXPECT_NE(text.find("ms  sound SOUND_DOUBLE_BEEP\n"), std::string::npos) << text;
  EXPECT_NE(text.find("ms  sound 3\n"), std::string::npos) << text;  // no name given: the number
  EXPECT_NE(text.find("ms  display DISPLAY_OUT_A\n"), std::string::npos) << text;
  EXPECT_NE(text.find("ms  datalog count = 12\n"), std::string::npos) << text;
  EXPECT_NE(text.find("ms  datalog var7 = 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("ms  datalog Timer(2) = 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("ms  datalog SENSOR_2 = 1023\n"), std::string::npos) << text;
  EXPECT_NE(text.find("ms  datalog Watch() = 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("50.000 ms  message received 42\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("0x"), std::string::npos) << text;
}

TEST(Report, TimelineShowsWhatTheProgramReadsFromASensor) {
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({senstype(0, 1), wait(100)})}}));
  m.schedule({300'000, rcx::SensorRawInput{0, 100}});
  m.start_program();
  m.run(2'000'000);
  std::string text = rcx::timeline_text(m, image({}));
  EXPECT_NE(text.find("0.000 ms  SENSOR_1 reads 0\n"), std::string::npos) << text;  // touch: open reads 0
  EXPECT_NE(text.find("300.000 ms  input: sensor 1 raw 100\n     300.000 ms  SENSOR_1 reads 1\n"), std::string::npos)
      << text;
}

// The time column was 12 characters wide, so from 10^8 ms on (a run may go
// to 2^40 ms) the later lines stood out past the earlier ones. It is as wide
// as the latest time the run shows.
TEST(Report, TheTimeColumnStaysAlignedPastAThousandMillionMilliseconds) {
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({senstype(0, 1), wait(32767), jmp(133)})}}));  // waits for ever
  m.schedule({1'234'567'890'000, rcx::SensorRawInput{0, 100}});
  m.start_program();
  m.run(1'234'567'891'000);
  std::string text = rcx::timeline_text(m, image({}));
  EXPECT_NE(text.find("\n1234567890.000 ms  input: sensor 1 raw 100\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\n         0.000 ms  SENSOR_1 reads 0\n"), std::string::npos) << text;
  std::size_t column = text.find(" ms  ");
  for (std::size_t at = 0; at < text.size() && text.compare(at, 8, "stopped:") != 0; at = text.find('\n', at) + 1)
    EXPECT_EQ(text.find(" ms  ", at) - at, column) << text;
}

// A fault is dated at the start of the instruction that faulted, as every
// event is: that instruction never ran. A fault in a program's first
// instruction was reported at 2 ms (1 ms here), after the instruction.
TEST(Report, AFaultIsDatedAtTheStartOfItsInstruction) {
  auto first = named(image({{0, code({Bytes{0x10}})}}));
  auto m = run(first);
  EXPECT_EQ(rcx::report_json(m, first)["time_ms"], 0);
  EXPECT_NE(rcx::timeline_text(m, first).find("0.000 ms  task 0 (main) stopped\nstopped: fault at 0.000 ms\n"),
            std::string::npos)
      << rcx::timeline_text(m, first);
  EXPECT_EQ(m.instructions_executed(), 0);
  auto third = named(image({{0, code({set(0, 1), out(0x81), jmp(0x7f)})}}));  // a branch past the code
  auto n = run(third);
  ASSERT_EQ(n.stop().kind, rcx::StopKind::Fault);
  EXPECT_EQ(rcx::report_json(n, third)["time_ms"], 2);
  EXPECT_NE(rcx::timeline_text(n, third).find("2.000 ms  task 0 (main) stopped\nstopped: fault at 2.000 ms\n"),
            std::string::npos)
      << rcx::timeline_text(n, third);
  EXPECT_EQ(n.instructions_executed(), 2);
}

TEST(Report, TimelineAndVcdHideCompilerTemporaries) {
  // count (0) and speed (2) are the program's; slot 5 is a temporary.
  rcx::Config c = ms_config();
  c.trace_variables = true;
  auto img = named(image({{0, code({set(0, 1), set(2, 2), set(5, 9)})}}));
  auto m = run(img, 1000, c);
  std::string text = rcx::timeline_text(m, img);
  EXPECT_NE(text.find("var[0] count = 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("var[2] speed = 2\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("var[5]"), std::string::npos) << text;
  std::string vcd = rcx::trace_vcd(m, img);
  EXPECT_NE(vcd.find(" count $end"), std::string::npos) << vcd;
  EXPECT_NE(vcd.find(" speed $end"), std::string::npos) << vcd;
  EXPECT_EQ(vcd.find(" var5 $end"), std::string::npos) << vcd;
  int declared = 0;
  for (std::size_t at = vcd.find("$var wire 16"); at != std::string::npos; at = vcd.find("$var wire 16", at + 1)) ++declared;
  EXPECT_EQ(declared, 2 + 3 + 1) << vcd;  // count, speed, the three rotation sensors, tone_hz
}

TEST(Report, AnImageWithoutVariableNamesShowsEverySlotItUses) {
  auto img = image({{0, code({set(5, 9)})}});
  auto m = run(img);
  std::string text = rcx::timeline_text(m, img);
  EXPECT_NE(text.find("var[5] = 9\n"), std::string::npos) << text;
}

// A task's local may share a global's name; the image lists globals first,
// and the report's `globals` must show the global, not whichever came last.
TEST(Report, GlobalWinsOverALocalOfTheSameName) {
  auto img = image({{0, code({set(0, 4), set(7, 9)})}});
  img.symbols.push_back({rcx::SymbolType::Variable, 0, "n"});
  img.symbols.push_back({rcx::SymbolType::Variable, 7, "n"});
  auto m = run(img);
  auto j = rcx::report_json(m, img);
  EXPECT_EQ(j["globals"]["n"], 4);
  EXPECT_EQ(j["globals"].size(), 1u);
}

// The report and trace are written event by event, not built as one tree
// (5 000 000 events took 3.2 GB); the text is the tree's dump, byte for
// byte: with events (inputs left out of the report, kept in the trace),
// with none, and with a name that is no UTF-8.
TEST(Report, WrittenEventByEventAsTheTreeDumps) {
  auto dump = [](const nlohmann::json& j) { return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace); };
  auto img = named(image({{0, code({set(0, 5), out(0x81), sound(2), display(IMM, 4), wait(1), out(0x41)})}}));
  img.symbols.push_back({rcx::SymbolType::Variable, 3, "bad\xff\xfename"});
  rcx::Machine m(ms_config());
  m.load(0, img);
  m.schedule({3000, rcx::SensorRawInput{0, 300}});
  m.schedule({4000, rcx::MessageInput{9}});
  m.start_program();
  m.run_until(50'000);
  ASSERT_GT(m.state().events.size(), 4u);
  std::ostringstream report, trace;
  rcx::write_report_json(report, m, img);
  rcx::write_trace_json(trace, m, img);
  EXPECT_EQ(report.str(), dump(rcx::report_json(m, img)));
  EXPECT_EQ(trace.str(), dump(rcx::trace_json(m, img)));
  rcx::Machine idle(ms_config());
  rcx::Image none;
  std::ostringstream empty_report, empty_trace;
  rcx::write_report_json(empty_report, idle, none);
  rcx::write_trace_json(empty_trace, idle, none);
  EXPECT_EQ(empty_report.str(), dump(rcx::report_json(idle, none)));
  EXPECT_EQ(empty_trace.str(), "[]");
}
