// A run drawn as a timeline (`rcxc run --trace F.svg` / `F.html`): one lane
// per output used, a plot per sensor, tasks as bars, sounds, messages,
// display and datalog as marks, over a time axis in seconds. The SVG stands
// alone (no scripts, no external resources); details are in <title>
// tooltips. Everything is drawn per pixel column, so the file stays small
// however long the run (docs/emulator.md, "Drawing a run").
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rcx/image.h"
#include "runtime/report.h"
#include "runtime/vm.h"

namespace rcx {

enum class LaneKind : std::uint8_t { Output, Sensor, Task, Sound, Message, Display, Datalog };

struct Lane {
  LaneKind kind = LaneKind::Output;
  int index = 0;        // output, sensor or task number
  std::string label;    // what the left column says
  int top = 0, height = 0;
};

// Where things are: lanes top to bottom, and the time axis from `left`
// (t = 0) to `left + plot_width` (t = end_us).
struct TraceLayout {
  int width = 0, height = 0;
  int left = 0, plot_width = 0;
  Micros end_us = 1;
  std::vector<Lane> lanes;

  double x_of(Micros t) const {
    return left + static_cast<double>(plot_width) * static_cast<double>(t) / static_cast<double>(end_us);
  }
  const Lane* find(LaneKind kind, int index = 0) const;
};

// The colours the drawing uses (the HTML legend and tests name them).
namespace trace_colors {
inline constexpr std::string_view kForward = "#2e9e44";
inline constexpr std::string_view kReverse = "#d9482b";
inline constexpr std::string_view kBrake = "#3a3a3a";
inline constexpr std::string_view kFloat = "#9a9a9a";
inline constexpr std::string_view kSensorLine = "#1f5fbf";
inline constexpr std::string_view kSensorFill = "#c9dcf5";
inline constexpr std::string_view kTask = "#7a5cc4";
inline constexpr std::string_view kSound = "#d99a00";
inline constexpr std::string_view kSent = "#0077aa";
inline constexpr std::string_view kReceived = "#aa3377";
inline constexpr std::string_view kDisplay = "#555555";
inline constexpr std::string_view kDatalog = "#119977";
inline constexpr std::string_view kLaneBackground = "#f4f4f4";
}  // namespace trace_colors

// The time axis ends at `end_us`, or (0) where the run's last event or its
// stop is: bricks drawn one above another share one axis.
TraceLayout trace_layout(const Machine& machine, const Image& image, const EventNames& names, Micros end_us = 0);
// `title` heads the drawing (e.g. the program's file name).
std::string trace_svg(const Machine& machine, const Image& image, const EventNames& names, std::string_view title,
                      Micros end_us = 0);
// A page holding the SVG, a title, what the run ended with and a legend.
std::string trace_html(const Machine& machine, const Image& image, const EventNames& names, std::string_view title);
// The same page for several bricks run together (room.h): one drawing per
// brick, headed by its label, all on one time axis.
std::string trace_html_room(std::span<const RoomBrick> bricks, const EventNames& names, std::string_view title);

}  // namespace rcx
