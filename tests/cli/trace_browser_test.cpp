// `rcxc run --trace F.svg / F.html` as a person sees it: headless Chromium
// draws the files, and the test reads pixels of the screenshot where the
// timeline says something known happened. Skipped without chromium (CI has
// it: scripts/deps).
#include <png.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>

#include "rcx/image.h"
#include "runtime/trace_svg.h"
#include "runtime/vm.h"
#include "tests/support/process.h"

using rcxc::test::run_process;
using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {

// Task 0: touch sensor on input 1; after 1 s output A forward, after 2 s
// reverse, after 3 s off (brake); then waits past the 4 s limit.
rcx::Image program() {
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0,
                           {0x32, 0x00, 0x01,               // SetSensorType(0, touch)
                            0x43, 0x02, 100, 0x00,          // Wait(100)
                            0x21, 0x81,                     // A on (forward)
                            0x43, 0x02, 100, 0x00,          // Wait(100)
                            0xe1, 0x01,                     // A reverse
                            0x43, 0x02, 100, 0x00,          // Wait(100)
                            0x21, 0x41,                     // A off
                            0x43, 0x02, 200, 0x00}});       // Wait(200)
  img.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  return img;
}

constexpr const char* kScenario = "[[input]]\nat_ms = 1500\nsensor = 1\nraw = 100\n";
constexpr rcx::Micros kRunUs = 4'000'000;

// The same run in process, for where the drawing put its lanes.
rcx::TraceLayout layout_of_run() {
  rcx::Machine m;
  m.load(0, program());
  m.schedule({1'500'000, rcx::SensorRawInput{0, 100}});
  m.start_program();
  m.run(kRunUs);
  return rcx::trace_layout(m, program(), {});
}

std::optional<std::string> find_chromium() {
  for (const char* name : {"chromium", "chromium-browser"}) {
    auto r = run_process({"/bin/sh", "-c", std::string("command -v ") + name});
    if (r.exit_code == 0 && !r.out.empty()) return r.out.substr(0, r.out.find('\n'));
  }
  return std::nullopt;
}

struct Rgb {
  int r = 0, g = 0, b = 0;
};

Rgb parse_color(std::string_view hex) {
  auto byte = [&](std::size_t at) { return std::stoi(std::string(hex.substr(at, 2)), nullptr, 16); };
  return {byte(1), byte(3), byte(5)};
}

struct Picture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  Rgb at(double x, double y) const {
    int ix = static_cast<int>(x), iy = static_cast<int>(y);
    if (ix < 0 || iy < 0 || ix >= width || iy >= height) return {-1, -1, -1};
    auto i = static_cast<std::size_t>((iy * width + ix) * 3);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

std::optional<Picture> read_png(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return std::nullopt;
  image.format = PNG_FORMAT_RGB;
  Picture p;
  p.width = static_cast<int>(image.width), p.height = static_cast<int>(image.height);
  p.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, p.rgb.data(), 0, nullptr)) return std::nullopt;
  return p;
}

bool near(Rgb a, Rgb b) { return std::abs(a.r - b.r) <= 8 && std::abs(a.g - b.g) <= 8 && std::abs(a.b - b.b) <= 8; }

std::string text(Rgb c) { return "rgb(" + std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b) + ")"; }

#define EXPECT_COLOR(picture, x, y, color) \
  EXPECT_TRUE(near((picture).at(x, y), parse_color(color))) \
      << "at (" << (x) << ", " << (y) << "): " << text((picture).at(x, y)) << ", expected " << (color)

class TraceBrowser : public ::testing::Test {
 protected:
  void SetUp() override {
    chromium_ = find_chromium();
    if (!chromium_) {
      const char* ci = std::getenv("CI");
      if (ci && std::string(ci) == "true") FAIL() << "CI must have chromium (scripts/deps installs it)";
      GTEST_SKIP() << "chromium is not installed";
    }
  }

  // Runs the program with --trace and screenshots the file at `width` x `height`.
  Picture draw(const std::string& trace_name, int width, int height) {
    std::string image = dir_.write("prog.rcx", rcx::write_image(program()));
    std::string scenario = dir_.write("inputs.toml", kScenario);
    std::string trace = dir_.path + "/" + trace_name;
    auto r = run_rcxc({"run", image, "--scenario", scenario, "--for", "4000", "--trace", trace});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::string png = dir_.path + "/" + trace_name + ".png";
    auto shot = run_process({*chromium_, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                             "--force-device-scale-factor=1", "--user-data-dir=" + dir_.path + "/profile",
                             "--screenshot=" + png,
                             "--window-size=" + std::to_string(width) + "," + std::to_string(height),
                             "file://" + trace},
                            "", 120'000);
    EXPECT_EQ(shot.exit_code, 0) << shot.err;
    auto picture = read_png(png);
    EXPECT_TRUE(picture.has_value()) << "no PNG from chromium: " << shot.err;
    return picture.value_or(Picture{});
  }

  TempDir dir_;
  std::optional<std::string> chromium_;
};

}  // namespace

TEST_F(TraceBrowser, SvgShowsOutputDirectionSensorAndTaskWhereTheyHappened) {
  auto layout = layout_of_run();
  ASSERT_EQ(layout.end_us, kRunUs);
  Picture p = draw("run.svg", layout.width, layout.height);
  ASSERT_EQ(p.width, layout.width);
  // Sampled between the grid lines (every 0.5 s).
  namespace c = rcx::trace_colors;

  const rcx::Lane* a = layout.find(rcx::LaneKind::Output, 0);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(layout.find(rcx::LaneKind::Output, 1), nullptr);  // B never moved: no lane
  double bar = a->top + a->height - 7;     // inside a full-power bar and the brake block
  double above = a->top + 5;               // above the brake block
  EXPECT_COLOR(p, layout.x_of(700'000), bar, c::kLaneBackground);  // before A turned on
  EXPECT_COLOR(p, layout.x_of(1'700'000), bar, c::kForward);
  EXPECT_COLOR(p, layout.x_of(2'700'000), bar, c::kReverse);
  EXPECT_COLOR(p, layout.x_of(3'700'000), bar, c::kBrake);
  EXPECT_COLOR(p, layout.x_of(3'700'000), above, c::kLaneBackground);
  EXPECT_COLOR(p, layout.x_of(1'700'000), above, c::kForward);  // power 7 fills the lane

  const rcx::Lane* s = layout.find(rcx::LaneKind::Sensor, 0);
  ASSERT_NE(s, nullptr);
  double middle = s->top + s->height / 2.0;
  EXPECT_COLOR(p, layout.x_of(1'200'000), middle, c::kLaneBackground);  // not pressed: reads 0
  EXPECT_COLOR(p, layout.x_of(2'200'000), middle, c::kSensorFill);      // pressed at 1.5 s: reads 1

  const rcx::Lane* t = layout.find(rcx::LaneKind::Task, 0);
  ASSERT_NE(t, nullptr);
  EXPECT_COLOR(p, layout.x_of(2'200'000), t->top + t->height / 2.0, c::kTask);  // main runs all along
}

TEST_F(TraceBrowser, HtmlPageShowsTheTimelineAndTheLegend) {
  auto layout = layout_of_run();
  Picture p = draw("run.html", layout.width + 60, layout.height + 260);
  // The drawing sits under the heading and legend; count its colours.
  int forward = 0, reverse = 0, sensor = 0;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      Rgb px = p.at(x, y);
      forward += near(px, parse_color(rcx::trace_colors::kForward));
      reverse += near(px, parse_color(rcx::trace_colors::kReverse));
      sensor += near(px, parse_color(rcx::trace_colors::kSensorFill));
    }
  // A full-power second is ~250 px wide and ~28 px high.
  EXPECT_GT(forward, 4000);
  EXPECT_GT(reverse, 4000);
  EXPECT_GT(sensor, 4000);
}
