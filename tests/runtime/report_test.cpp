// The JSON report and traces built from a finished run.
#include "runtime/report.h"

#include <gtest/gtest.h>

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
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0], (nlohmann::json{{"t", 5}, {"kind", "sensor"}, {"sensor", 1}, {"raw", 300}}));
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
