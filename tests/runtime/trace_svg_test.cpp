// The run drawn as SVG/HTML: the document's structure and what it holds.
// tests/cli/trace_browser_test.cpp looks at the pixels a browser draws.
#include "runtime/trace_svg.h"

#include <gtest/gtest.h>

#include <regex>

#include "tests/runtime/vm_support.h"

using namespace vmtest;

namespace {

// Well-formed XML as far as a browser's parser cares: every tag closed in
// order, attributes quoted, `&` only in entities, no `<` in text. Returns
// "" or what is wrong.
std::string xml_problem(const std::string& doc) {
  std::vector<std::string> open;
  static const std::regex kEntity(R"(^&(amp|lt|gt|quot|apos|#[0-9]+|#x[0-9a-fA-F]+);)");
  for (std::size_t i = 0; i < doc.size();) {
    if (doc[i] == '&') {
      std::string rest = doc.substr(i, 12);
      if (!std::regex_search(rest, kEntity)) return "bare & at " + std::to_string(i);
      ++i;
      continue;
    }
    if (doc[i] != '<') {
      if (static_cast<unsigned char>(doc[i]) >= 0x80) return "non-ASCII byte at " + std::to_string(i);
      ++i;
      continue;
    }
    std::size_t end = doc.find('>', i);
    if (end == std::string::npos) return "unclosed tag at " + std::to_string(i);
    std::string tag = doc.substr(i + 1, end - i - 1);
    i = end + 1;
    if (tag.starts_with("!") || tag.starts_with("?")) continue;
    if (tag.starts_with("/")) {
      std::string name = tag.substr(1);
      if (open.empty() || open.back() != name) return "</" + name + "> closes " + (open.empty() ? "nothing" : open.back());
      open.pop_back();
      continue;
    }
    bool self_closing = tag.ends_with("/");
    if (self_closing) tag.pop_back();
    std::string name = tag.substr(0, tag.find_first_of(" \n"));
    std::string attrs = tag.substr(name.size());
    static const std::regex kAttrs(R"(^(\s+[a-zA-Z:-][a-zA-Z0-9:-]*="[^"<]*")*\s*$)");
    if (!std::regex_match(attrs, kAttrs)) return "bad attributes in <" + name + ">: " + attrs;
    if (!self_closing) open.push_back(name);
  }
  return open.empty() ? "" : "unclosed <" + open.back() + ">";
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

rcx::EventNames sound_names() {
  rcx::EventNames names;
  names.sounds = {{0, "SOUND_CLICK"}, {1, "SOUND_DOUBLE_BEEP"}};
  names.sensor_types = {{1, "SENSOR_TYPE_TOUCH"}};
  return names;
}

}  // namespace

TEST(TraceSvg, IsWellFormedWithOneLanePerOutputUsed) {
  // A and C run, B never changes; touch sensor 1 pressed at 300 ms.
  auto img = image({{0, code({senstype(0, 1), out(0x81), out(0x84), wait(50), dir(0x01), out(0x41), sound(1),
                              msgsend(IMM, 7), display(IMM, 4), logsize(2), lognext(TIMER, 0), wait(50)})}});
  img.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  rcx::Machine m(ms_config());
  m.load(0, img);
  m.schedule({300'000, rcx::SensorRawInput{0, 100}});
  m.schedule({400'000, rcx::MessageInput{9}});
  m.start_program();
  m.run(2'000'000);
  std::string svg = rcx::trace_svg(m, img, sound_names(), "prog.nqc");
  EXPECT_EQ(xml_problem(svg), "") << svg;
  EXPECT_TRUE(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
  EXPECT_EQ(count(svg, "<script"), 0);
  EXPECT_EQ(count(svg, "href"), 0);  // nothing outside the file

  auto layout = rcx::trace_layout(m, img, sound_names());
  ASSERT_NE(layout.find(rcx::LaneKind::Output, 0), nullptr);
  EXPECT_EQ(layout.find(rcx::LaneKind::Output, 1), nullptr);
  ASSERT_NE(layout.find(rcx::LaneKind::Output, 2), nullptr);
  ASSERT_NE(layout.find(rcx::LaneKind::Sensor, 0), nullptr);
  EXPECT_EQ(layout.find(rcx::LaneKind::Sensor, 0)->label, "SENSOR_1 (touch)");
  EXPECT_EQ(layout.find(rcx::LaneKind::Sensor, 1), nullptr);
  ASSERT_NE(layout.find(rcx::LaneKind::Task, 0), nullptr);
  EXPECT_EQ(layout.find(rcx::LaneKind::Task, 0)->label, "task main");
  for (auto kind : {rcx::LaneKind::Sound, rcx::LaneKind::Message, rcx::LaneKind::Display, rcx::LaneKind::Datalog})
    EXPECT_NE(layout.find(kind), nullptr) << static_cast<int>(kind);
  EXPECT_EQ(count(svg, ">output A</text>"), 1);
  EXPECT_EQ(count(svg, ">output B</text>"), 0);
  EXPECT_EQ(count(svg, ">output C</text>"), 1);

  // Tooltips say what happened, with names.
  EXPECT_NE(svg.find("<title>output A on forward power 7: 0.001 s to 0.503 s</title>"), std::string::npos) << svg;
  EXPECT_NE(svg.find("sound SOUND_DOUBLE_BEEP"), std::string::npos);
  EXPECT_NE(svg.find("sent 7"), std::string::npos);
  EXPECT_NE(svg.find("received 9"), std::string::npos);
  EXPECT_NE(svg.find("display 4"), std::string::npos);  // no display names given
  EXPECT_NE(svg.find("datalog Timer(0) = 5"), std::string::npos) << svg;
  // C was reversed while on: its bar has the reverse colour.
  EXPECT_NE(svg.find(std::string("fill=\"") + std::string(rcx::trace_colors::kReverse)), std::string::npos);
}

TEST(TraceSvg, AxisIsLabelledInSeconds) {
  auto m = run_task(code({out(0x81), wait(400), out(0x41)}));  // ~4 s
  std::string svg = rcx::trace_svg(m, image({}), {}, "t");
  for (const char* label : {">0 s<", ">0.5 s<", ">1 s<", ">2 s<", ">3.5 s<", ">4 s<"})
    EXPECT_EQ(count(svg, label), 1) << label;
  EXPECT_EQ(count(svg, ">4.5 s<"), 0);
  auto short_run = run_task(code({out(0x81), wait(3), out(0x41)}));  // ~33 ms
  std::string short_svg = rcx::trace_svg(short_run, image({}), {}, "t");
  EXPECT_EQ(count(short_svg, ">0.010 s<"), 1) << short_svg;
}

TEST(TraceSvg, NamesFromTheImageAreEscaped) {
  auto img = image({{0, code({out(0x81)})}});
  img.symbols.push_back({rcx::SymbolType::Task, 0, "a<b&\"c\"\x1b\xff"});
  auto m = run(img);
  std::string svg = rcx::trace_svg(m, img, {}, "x<y>.nqc");
  EXPECT_EQ(xml_problem(svg), "") << svg;
  EXPECT_NE(svg.find("task a&lt;b&amp;&quot;c&quot;\\x1b\\xff"), std::string::npos) << svg;
  std::string html = rcx::trace_html(m, img, {}, "x<y>.nqc");
  EXPECT_NE(html.find("<title>rcxc run: x&lt;y&gt;.nqc</title>"), std::string::npos);
}

TEST(TraceSvg, SensorPlotFollowsTheReadingTheProgramSees) {
  // Light sensor (percent): raw 1023 reads 0, raw 500 reads 83.
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({senstype(1, 3), wait(100)})}}));
  m.schedule({500'000, rcx::SensorRawInput{1, 500}});
  m.start_program();
  m.run(2'000'000);
  auto readings = events_of(m, rcx::EventKind::SensorReading);
  ASSERT_EQ(readings.size(), 2u);
  EXPECT_EQ(readings[0].value, 0);  // light configured: raw 1023 reads 0 %
  EXPECT_EQ(readings[1].value, 83);
  std::string svg = rcx::trace_svg(m, image({}), {}, "t");
  // Configured before any input: plotted from then on, without the open input's 1023.
  EXPECT_NE(svg.find("SENSOR_2 (3): values 0 to 83, 83 at the end (1 change)"), std::string::npos) << svg;
  // An input to an unconfigured sensor: its raw values from the start.
  rcx::Machine raw(ms_config());
  raw.schedule({500'000, rcx::SensorRawInput{2, 300}});
  raw.run_until(1'000'000);
  EXPECT_NE(rcx::trace_svg(raw, image({}), {}, "t").find("SENSOR_3 (raw): values 0 to 1023, 300 at the end (1 change)"),
            std::string::npos);
}

TEST(TraceSvg, HtmlEmbedsTheSvgWithTitleAndLegend) {
  auto m = run_task(code({out(0x81), wait(10)}));
  std::string html = rcx::trace_html(m, image({}), {}, "prog.nqc");
  EXPECT_TRUE(html.starts_with("<!DOCTYPE html>"));
  EXPECT_EQ(count(html, "<svg "), 1);
  EXPECT_NE(html.find("<h1>prog.nqc</h1>"), std::string::npos);
  EXPECT_NE(html.find("output forward"), std::string::npos);
  EXPECT_EQ(count(html, "<script"), 0);
  std::string body = html.substr(html.find("<html"));
  EXPECT_EQ(xml_problem(body), "");
}

TEST(TraceSvg, ManyEventsStaySmall) {
  // Output A on and off and a click, 20,000 times in about 100 s, draw as at
  // most a rectangle per pixel column and a mark per bucket.
  // 0 loops 100; 3 loopc -> 20; 5 loops 200; 8 loopc -> 18; 10 on; 12 off;
  // 14 sound; 16 jmp -> 8 (17 - 137 + 128); 18 jmp -> 3 (19 - 144 + 128).
  auto m = run_task(code({loops(IMM, 100), loopc(16), loops(IMM, 200), loopc(9), out(0x81), out(0x41), sound(0),
                          jmp(137), jmp(144)}),
                    300'000);
  ASSERT_EQ(m.stop().kind, rcx::StopKind::Ended);
  ASSERT_GE(events_of(m, rcx::EventKind::Output).size(), 40'000u);
  std::string svg = rcx::trace_svg(m, image({}), {}, "t");
  EXPECT_LT(count(svg, "<rect"), 1200);
  EXPECT_LT(count(svg, "<circle"), 300);
  EXPECT_LT(svg.size(), 400'000u);
  EXPECT_EQ(xml_problem(svg), "");
}
