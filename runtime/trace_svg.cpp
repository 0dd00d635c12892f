#include "runtime/trace_svg.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "runtime/sensors.h"

namespace rcx {
namespace {

constexpr int kWidth = 1200;
constexpr int kLeft = 170;    // the label column
constexpr int kRight = 24;
constexpr int kTop = 44;      // under the heading
constexpr int kGap = 6;
constexpr int kAxisHeight = 36;
constexpr int kMarkBucketPx = 4;        // marks closer than this share one symbol
constexpr int kTooltipLines = 6;        // a merged mark lists this many events
constexpr double kLabelCharPx = 6.6;    // rough width of a character at font-size 11
constexpr int kSensorOutOfRange = 0x7fff;

constexpr const char* kOutputNames[kOutputs] = {"A", "B", "C"};

int lane_height(LaneKind kind) {
  switch (kind) {
    case LaneKind::Output: return 34;
    case LaneKind::Sensor: return 78;
    case LaneKind::Task: return 20;
    default: return 30;
  }
}

// Text for XML content and attributes. Names from an image are any bytes:
// printable_name escapes control characters, and bytes past ASCII become
// \xNN here too, so the document is always well-formed UTF-8.
std::string xml(std::string_view text) {
  std::string out;
  for (char c : printable_name(text)) {
    auto u = static_cast<unsigned char>(c);
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        if (u >= 0x80) out += fmt::format("\\x{:02x}", u);
        else out += c;
    }
  }
  return out;
}

std::string seconds(Micros t) { return fmt::format("{}.{:03d} s", t / 1'000'000, (t / 1000) % 1000); }

std::string span_text(Micros from, Micros to) {
  return from == to ? seconds(from) : fmt::format("{} to {}", seconds(from), seconds(to));
}

std::string coord(double v) { return fmt::format("{:.1f}", v); }

bool sensor_used(const Machine& m, int sensor) {
  if (m.state().sensors[static_cast<std::size_t>(sensor)].type != SensorType::Raw) return true;
  for (const auto& e : m.state().events)
    if ((e.kind == EventKind::Sensor || e.kind == EventKind::SensorReading) && e.index == sensor) return true;
  return false;
}

std::string sensor_label(const Machine& m, const EventNames& names, int sensor) {
  auto type = m.state().sensors[static_cast<std::size_t>(sensor)].type;
  std::string kind = type == SensorType::Raw ? "raw" : name_or_number(names.sensor_types, static_cast<int>(type));
  constexpr std::string_view kPrefix = "SENSOR_TYPE_";
  if (kind.starts_with(kPrefix)) kind = kind.substr(kPrefix.size());
  for (char& c : kind) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return fmt::format("SENSOR_{} ({})", sensor + 1, kind);
}

// ------------------------------------------------------------ drawing per pixel column

// A state that holds over [from, to): what an output, a task or a tone does.
// Where several share one pixel column the higher rank wins, then the one
// covering more of it, so a short pulse stays visible in a long run.
struct Interval {
  Micros from = 0, to = 0;
  int rank = 0;
  int state = 0;
};

struct Run {
  int col0 = 0, col1 = 0;  // columns [col0, col1)
  int rank = 0, state = 0;
  Micros from = 0, to = 0;
};

std::vector<Run> runs_of(const TraceLayout& layout, const std::vector<Interval>& intervals) {
  struct Best {
    int rank = -1, state = 0;
    double cover = 0;
    Micros from = 0, to = 0;
  };
  std::vector<Best> cols(static_cast<std::size_t>(layout.plot_width));
  for (const auto& iv : intervals) {
    double x0 = layout.x_of(iv.from) - layout.left, x1 = layout.x_of(iv.to) - layout.left;
    int c0 = std::clamp(static_cast<int>(std::floor(x0)), 0, layout.plot_width - 1);
    int c1 = std::clamp(static_cast<int>(std::ceil(x1)), c0 + 1, layout.plot_width);
    for (int c = c0; c < c1; ++c) {
      double cover = std::min<double>(c + 1, x1) - std::max<double>(c, x0);
      Best& b = cols[static_cast<std::size_t>(c)];
      if (iv.rank > b.rank || (iv.rank == b.rank && cover > b.cover)) b = {iv.rank, iv.state, cover, iv.from, iv.to};
    }
  }
  std::vector<Run> runs;
  for (int c = 0; c < layout.plot_width; ++c) {
    const Best& b = cols[static_cast<std::size_t>(c)];
    if (b.rank < 0) continue;
    if (!runs.empty() && runs.back().col1 == c && runs.back().rank == b.rank && runs.back().state == b.state) {
      runs.back().col1 = c + 1;
      runs.back().to = std::max(runs.back().to, b.to);
    } else {
      runs.push_back({c, c + 1, b.rank, b.state, b.from, b.to});
    }
  }
  return runs;
}

struct Mark {
  Micros t = 0;
  std::string label;    // drawn beside the symbol when there is room
  std::string detail;   // the tooltip line
};

// One symbol per bucket of kMarkBucketPx columns; its tooltip lists what
// happened there. `symbol` is an SVG element with {0} x, {1} y and {2} colour.
void draw_marks(std::string& out, const TraceLayout& layout, const std::vector<Mark>& marks, double y,
                std::string_view color, std::string_view symbol) {
  auto bucket_of = [&](const Mark& mark) { return static_cast<int>((layout.x_of(mark.t) - layout.left) / kMarkBucketPx); };
  std::vector<std::size_t> starts;  // first mark of each bucket
  double free_x = 0;                 // right of the last symbol or label drawn
  for (std::size_t i = 0; i < marks.size(); ++i)
    if (i == 0 || bucket_of(marks[i]) != bucket_of(marks[i - 1])) starts.push_back(i);
  for (std::size_t b = 0; b < starts.size(); ++b) {
    std::size_t i = starts[b], j = b + 1 < starts.size() ? starts[b + 1] : marks.size();
    double x = layout.x_of(marks[i].t);
    std::string tip;
    for (std::size_t k = i; k < j && k < i + kTooltipLines; ++k)
      tip += fmt::format("{}{}: {}", k == i ? "" : "\n", seconds(marks[k].t), marks[k].detail);
    if (j - i > static_cast<std::size_t>(kTooltipLines)) tip += fmt::format("\n... {} more", j - i - kTooltipLines);
    out += fmt::format("<g><title>{}</title>", xml(tip));
    std::string sx = coord(x), sy = coord(y);
    out += fmt::vformat(symbol, fmt::make_format_args(sx, sy, color));
    // A label only where it fits before the next mark: dense marks keep
    // their details in the tooltips.
    std::string label = j - i > 1 ? fmt::format("{} (+{})", marks[i].label, j - i - 1) : marks[i].label;
    // Beside the mark on the right, else on the left (the last marks of a run).
    double label_width = static_cast<double>(label.size()) * kLabelCharPx;
    double next_x = j < marks.size() ? layout.x_of(marks[j].t) - 6 : kWidth;
    if (x + 7 + label_width <= std::min<double>(next_x, kWidth)) {
      out += fmt::format(R"(<text x="{}" y="{}" font-size="11" fill="#333">{}</text>)", coord(x + 7), coord(y + 4),
                         xml(label));
      free_x = x + 7 + label_width;
    } else if (j == marks.size() && x - 7 - label_width >= std::max<double>(free_x, layout.left)) {
      out += fmt::format(R"(<text x="{}" y="{}" font-size="11" fill="#333" text-anchor="end">{}</text>)",
                         coord(x - 7), coord(y + 4), xml(label));
    }
    free_x = std::max(free_x, x + 6);
    out += "</g>\n";
  }
}

constexpr std::string_view kCircle = R"(<circle cx="{0}" cy="{1}" r="4.5" fill="{2}"/>)";
constexpr std::string_view kUp = R"(<path d="M{0} {1} m-5 4 l5 -9 l5 9 z" fill="{2}"/>)";
constexpr std::string_view kDown = R"(<path d="M{0} {1} m-5 -4 l5 9 l5 -9 z" fill="{2}"/>)";
constexpr std::string_view kDiamond = R"(<path d="M{0} {1} m0 -5 l5 5 l-5 5 l-5 -5 z" fill="{2}"/>)";
constexpr std::string_view kSquare = R"(<path d="M{0} {1} m-4 -4 h8 v8 h-8 z" fill="{2}"/>)";

// ------------------------------------------------------------ lanes

void draw_output(std::string& out, const TraceLayout& layout, const Lane& lane, const Machine& m) {
  std::vector<Interval> intervals;
  Output current;
  Micros since = 0;
  auto close = [&](Micros until) {
    if (current.mode == OutputMode::Float || until <= since) return;
    int state = static_cast<int>(current.mode) * 16 + static_cast<int>(current.dir) * 8 + current.power;
    intervals.push_back({since, until, current.mode == OutputMode::On ? 2 : 1, state});
  };
  for (const auto& e : m.state().events) {
    if (e.kind != EventKind::Output || e.index != lane.index) continue;
    close(e.t_us);
    current = e.output, since = e.t_us;
  }
  close(layout.end_us);
  double bottom = lane.top + lane.height - 3, full = lane.height - 6;
  // Float is the resting state: a thin line along the whole lane.
  out += fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{}" stroke-width="1"/>)" "\n", layout.left,
                     coord(bottom - 0.5), layout.left + layout.plot_width, coord(bottom - 0.5), trace_colors::kFloat);
  for (const auto& r : runs_of(layout, intervals)) {
    auto mode = static_cast<OutputMode>(r.state / 16);
    bool reverse = (r.state / 8) % 2 != 0;
    int power = r.state % 8;
    double x = layout.left + r.col0, w = r.col1 - r.col0;
    std::string tip;
    if (mode == OutputMode::On) {
      double h = full * (power + 1) / 8.0;
      tip = fmt::format("output {} on {} power {}: {}", kOutputNames[lane.index], reverse ? "reverse" : "forward", power,
                        span_text(r.from, r.to));
      out += fmt::format(R"(<g><title>{}</title><rect x="{}" y="{}" width="{}" height="{}" fill="{}"/>)", xml(tip),
                         coord(x), coord(bottom - h), coord(w), coord(h),
                         reverse ? trace_colors::kReverse : trace_colors::kForward);
      if (w >= 16 && h >= 10) {  // an arrow says the direction without colour
        double cy = bottom - h / 2, ax = reverse ? x + 11 : x + 5;
        out += fmt::format(R"(<path d="M{} {} l0 8 l{} -4 z" fill="#ffffff"/>)", coord(ax), coord(cy - 4),
                           reverse ? -6 : 6);
      }
      out += "</g>\n";
    } else {
      tip = fmt::format("output {} off (brake): {}", kOutputNames[lane.index], span_text(r.from, r.to));
      out += fmt::format(R"(<g><title>{}</title><rect x="{}" y="{}" width="{}" height="8" fill="{}"/></g>)" "\n",
                         xml(tip), coord(x), coord(bottom - 8), coord(w), trace_colors::kBrake);
    }
  }
}

void draw_sensor(std::string& out, const TraceLayout& layout, const Lane& lane, const Machine& m) {
  // A sensor the program configures before any input is drawn from the
  // configuration on: the open input's raw 1023 before it is not a value
  // the program meant to read (and would squash a touch sensor's 0..1).
  std::vector<std::pair<Micros, int>> changes;
  int initial = sensor_reading(Sensor{});
  Micros plot_from = 0;
  bool seen = false;
  for (const auto& e : m.state().events) {
    if (e.index != lane.index || (e.kind != EventKind::Sensor && e.kind != EventKind::SensorReading)) continue;
    if (e.kind == EventKind::SensorReading && !seen) initial = e.value, plot_from = e.t_us;
    else if (e.kind == EventKind::SensorReading) changes.emplace_back(e.t_us, e.value);
    seen = true;
  }
  int lo = 0, hi = 0;
  if (initial != kSensorOutOfRange) lo = std::min(lo, initial), hi = std::max(hi, initial);
  for (const auto& [t, v] : changes)
    if (v != kSensorOutOfRange) lo = std::min(lo, v), hi = std::max(hi, v);
  if (hi == lo) hi = lo + 1;
  double bottom = lane.top + lane.height - 3, span = lane.height - 12;
  auto y_of = [&](int v) {
    int clamped = std::clamp(v, lo, hi);
    return bottom - span * (clamped - lo) / static_cast<double>(hi - lo);
  };
  // A step line, at most four points per pixel column: the value coming in,
  // the column's lowest and highest, and the value going out.
  double start_x = layout.x_of(plot_from);
  std::vector<std::pair<double, double>> points{{start_x, y_of(initial)}};
  auto add = [&](double x, double y) {
    if (points.back().first != x || points.back().second != y) points.emplace_back(x, y);
  };
  int current = initial;
  for (std::size_t i = 0; i < changes.size();) {
    double x = layout.x_of(changes[i].first);
    int col = static_cast<int>(x - layout.left);
    int low = current, high = current;
    std::size_t j = i;
    for (; j < changes.size() && static_cast<int>(layout.x_of(changes[j].first) - layout.left) == col; ++j) {
      low = std::min(low, changes[j].second), high = std::max(high, changes[j].second);
      current = changes[j].second;
    }
    add(x, points.back().second);
    add(x, y_of(low));
    add(x, y_of(high));
    add(x, y_of(current));
    i = j;
  }
  add(layout.left + layout.plot_width, points.back().second);
  std::string line;
  for (const auto& [x, y] : points) line += fmt::format("{},{} ", coord(x), coord(y));
  std::string tip = fmt::format("{}: values {} to {}, {} at the end ({} change{})", lane.label, lo, hi, current,
                                changes.size(), changes.size() == 1 ? "" : "s");
  out += fmt::format(R"(<g><title>{}</title>)", xml(tip));
  out += fmt::format(R"(<polygon points="{}{},{} {},{}" fill="{}"/>)", line, layout.left + layout.plot_width,
                     coord(bottom), coord(start_x), coord(bottom), trace_colors::kSensorFill);
  out += fmt::format(R"(<polyline points="{}" fill="none" stroke="{}" stroke-width="1.5"/>)", line,
                     trace_colors::kSensorLine);
  out += "</g>\n";
  // The scale: highest and lowest value beside the plot.
  out += fmt::format(R"(<text x="{}" y="{}" font-size="10" fill="#666" text-anchor="end">{}</text>)" "\n",
                     layout.left - 4, coord(bottom - span + 4), hi);
  out += fmt::format(R"(<text x="{}" y="{}" font-size="10" fill="#666" text-anchor="end">{}</text>)" "\n",
                     layout.left - 4, coord(bottom), lo);
}

void draw_task(std::string& out, const TraceLayout& layout, const Lane& lane, const Machine& m) {
  std::vector<Interval> intervals;
  Micros started = -1;  // -1: not running
  for (const auto& e : m.state().events) {
    if (e.index != lane.index) continue;
    if (e.kind == EventKind::TaskStart && started < 0) started = e.t_us;
    if (e.kind == EventKind::TaskStop && started >= 0) intervals.push_back({started, e.t_us, 1, 0}), started = -1;
  }
  if (started >= 0) intervals.push_back({started, layout.end_us, 1, 0});
  for (auto& iv : intervals) iv.to = std::max(iv.to, iv.from + 1);  // a task that ran no time still shows
  for (const auto& r : runs_of(layout, intervals))
    out += fmt::format(R"(<g><title>{} running: {}</title><rect x="{}" y="{}" width="{}" height="{}" fill="{}"/></g>)"
                       "\n",
                       xml(lane.label), span_text(r.from, r.to), layout.left + r.col0, lane.top + 3, r.col1 - r.col0,
                       lane.height - 6, trace_colors::kTask);
}

void draw_sound(std::string& out, const TraceLayout& layout, const Lane& lane, const Machine& m,
                const EventNames& names) {
  std::vector<Interval> tones;
  std::vector<Mark> sounds;
  for (const auto& e : m.state().events) {
    if (e.kind == EventKind::Tone) tones.push_back({e.t_us, e.t_us + Micros{e.duration} * 10'000, 1, e.value});
    if (e.kind == EventKind::Sound) {
      std::string name = name_or_number(names.sounds, e.value);
      sounds.push_back({e.t_us, name, "sound " + name});
    }
  }
  for (const auto& r : runs_of(layout, tones))
    out += fmt::format(R"(<g><title>tone {} Hz: {}</title><rect x="{}" y="{}" width="{}" height="8" fill="{}"/></g>)"
                       "\n",
                       r.state, span_text(r.from, r.to), layout.left + r.col0, lane.top + lane.height - 11,
                       r.col1 - r.col0, trace_colors::kSound);
  draw_marks(out, layout, sounds, lane.top + 10.0, trace_colors::kSound, kCircle);
}

void draw_messages(std::string& out, const TraceLayout& layout, const Lane& lane, const Machine& m) {
  std::vector<Mark> sent, received;
  for (const auto& e : m.state().events) {
    if (e.kind == EventKind::MessageSent) sent.push_back({e.t_us, std::to_string(e.value), fmt::format("sent {}", e.value)});
    if (e.kind == EventKind::MessageReceived)
      received.push_back({e.t_us, std::to_string(e.value), fmt::format("received {}", e.value)});
  }
  draw_marks(out, layout, sent, lane.top + 8.0, trace_colors::kSent, kUp);
  draw_marks(out, layout, received, lane.top + lane.height - 8.0, trace_colors::kReceived, kDown);
}

void draw_display(std::string& out, const TraceLayout& layout, const Lane& lane, const Machine& m,
                  const EventNames& names) {
  std::vector<Mark> marks;
  for (const auto& e : m.state().events)
    if (e.kind == EventKind::Display) {
      std::string name = name_or_number(names.displays, e.value);
      marks.push_back({e.t_us, name, "display " + name});
    }
  draw_marks(out, layout, marks, lane.top + lane.height / 2.0, trace_colors::kDisplay, kDiamond);
}

void draw_datalog(std::string& out, const TraceLayout& layout, const Lane& lane, const Machine& m,
                  const Image& image) {
  std::vector<Mark> marks;
  for (const auto& e : m.state().events)
    if (e.kind == EventKind::Datalog) {
      std::string entry = fmt::format("{} = {}", datalog_source(e.type, image), e.value);
      marks.push_back({e.t_us, entry, "datalog " + entry});
    }
  draw_marks(out, layout, marks, lane.top + lane.height / 2.0, trace_colors::kDatalog, kSquare);
}

// Seconds between labelled ticks: 1, 2 or 5 times a power of ten, so that
// about ten fit the run.
Micros tick_step(Micros end_us) {
  Micros step = 1000;  // 1 ms
  for (;;) {
    for (int f : {1, 2, 5})
      if (end_us / (step * f) <= 10) return step * f;
    step *= 10;
  }
}

std::string tick_label(Micros t, Micros step) {
  if (t % 1'000'000 == 0) return fmt::format("{} s", t / 1'000'000);
  int decimals = step % 100'000 == 0 ? 1 : step % 10'000 == 0 ? 2 : 3;
  return fmt::format("{:.{}f} s", static_cast<double>(t) / 1e6, decimals);
}

std::string stop_summary(const Machine& m) {
  std::string s = fmt::format("{} at {}", to_string(m.stop().kind), seconds(m.now_us()));
  if (m.stop().fault) s += ": " + m.stop().fault->message;
  return s;
}

}  // namespace

const Lane* TraceLayout::find(LaneKind kind, int index) const {
  for (const auto& lane : lanes)
    if (lane.kind == kind && lane.index == index) return &lane;
  return nullptr;
}

TraceLayout trace_layout(const Machine& m, const Image& image, const EventNames& names, Micros end_us) {
  TraceLayout layout;
  layout.width = kWidth, layout.left = kLeft, layout.plot_width = kWidth - kLeft - kRight;
  const auto& events = m.state().events;
  layout.end_us = end_us > 0 ? end_us : std::max<Micros>({m.now_us(), events.empty() ? 0 : events.back().t_us, 1000});
  int y = kTop;
  auto add = [&](LaneKind kind, int index, std::string label) {
    layout.lanes.push_back({kind, index, std::move(label), y, lane_height(kind)});
    y += lane_height(kind) + kGap;
  };
  auto any = [&](auto pred) { return std::any_of(events.begin(), events.end(), pred); };
  for (int i = 0; i < kOutputs; ++i)
    if (any([i](const Event& e) { return e.kind == EventKind::Output && e.index == i; }))
      add(LaneKind::Output, i, fmt::format("output {}", kOutputNames[i]));
  for (int i = 0; i < kSensors; ++i)
    if (sensor_used(m, i)) add(LaneKind::Sensor, i, sensor_label(m, names, i));
  for (int i = 0; i < kMaxTasks; ++i)
    if (any([i](const Event& e) { return e.kind == EventKind::TaskStart && e.index == i; })) {
      std::string name = image.name_of(SymbolType::Task, i);
      add(LaneKind::Task, i, name.empty() ? fmt::format("task {}", i) : fmt::format("task {}", name));
    }
  auto has = [&](std::initializer_list<EventKind> kinds) {
    return any([&](const Event& e) { return std::find(kinds.begin(), kinds.end(), e.kind) != kinds.end(); });
  };
  if (has({EventKind::Sound, EventKind::Tone})) add(LaneKind::Sound, 0, "sound");
  if (has({EventKind::MessageSent, EventKind::MessageReceived})) add(LaneKind::Message, 0, "messages");
  if (has({EventKind::Display})) add(LaneKind::Display, 0, "display");
  if (has({EventKind::Datalog})) add(LaneKind::Datalog, 0, "datalog");
  layout.height = y + kAxisHeight;
  return layout;
}

std::string trace_svg(const Machine& m, const Image& image, const EventNames& names, std::string_view title,
                      Micros end_us) {
  TraceLayout layout = trace_layout(m, image, names, end_us);
  int axis_y = layout.height - kAxisHeight + 4;
  std::string out = fmt::format(
      R"(<svg xmlns="http://www.w3.org/2000/svg" width="{0}" height="{1}" viewBox="0 0 {0} {1}" )"
      R"(font-family="DejaVu Sans, Liberation Sans, Arial, sans-serif" font-size="12">)" "\n",
      layout.width, layout.height);
  out += fmt::format("<title>{}</title>\n", xml(fmt::format("{}: {}", title, stop_summary(m))));
  out += R"(<rect x="0" y="0" width="100%" height="100%" fill="#ffffff"/>)" "\n";
  out += fmt::format(R"(<text x="12" y="26" font-size="15" font-weight="bold" fill="#222">{}</text>)", xml(title));
  out += fmt::format(R"(<text x="{}" y="26" font-size="12" fill="#555" text-anchor="end">{}</text>)" "\n",
                     layout.width - kRight, xml(stop_summary(m)));
  for (const auto& lane : layout.lanes) {
    out += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="{}"/>)", layout.left, lane.top,
                       layout.plot_width, lane.height, trace_colors::kLaneBackground);
    // A sensor's label is two lines (SENSOR_1 / (touch)) beside its scale.
    std::string label = xml(lane.label);
    std::size_t split = lane.kind == LaneKind::Sensor ? label.find(" (") : std::string::npos;
    if (split != std::string::npos)
      label = fmt::format(R"({}<tspan x="{}" dy="15">{}</tspan>)", label.substr(0, split), layout.left - 26,
                          label.substr(split + 1));
    out += fmt::format(R"(<text x="{}" y="{}" text-anchor="end" fill="#222">{}</text>)" "\n",
                       layout.left - (lane.kind == LaneKind::Sensor ? 26 : 8),
                       lane.top + lane.height / 2 + (split != std::string::npos ? -3 : 4), label);
  }
  // Grid and time axis.
  Micros step = tick_step(layout.end_us);
  out += fmt::format(R"(<line x1="{0}" y1="{1}" x2="{2}" y2="{1}" stroke="#444"/>)" "\n", layout.left, axis_y,
                     layout.left + layout.plot_width);
  for (Micros t = 0; t <= layout.end_us; t += step) {
    double x = layout.x_of(t);
    out += fmt::format(R"(<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#dddddd"/>)", coord(x), kTop - 4, axis_y);
    out += fmt::format(R"(<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#444"/>)", coord(x), axis_y, axis_y + 5);
    out += fmt::format(R"(<text x="{}" y="{}" text-anchor="middle" font-size="11" fill="#333">{}</text>)" "\n",
                       coord(x), axis_y + 18, tick_label(t, step));
  }
  for (const auto& lane : layout.lanes) {
    switch (lane.kind) {
      case LaneKind::Output: draw_output(out, layout, lane, m); break;
      case LaneKind::Sensor: draw_sensor(out, layout, lane, m); break;
      case LaneKind::Task: draw_task(out, layout, lane, m); break;
      case LaneKind::Sound: draw_sound(out, layout, lane, m, names); break;
      case LaneKind::Message: draw_messages(out, layout, lane, m); break;
      case LaneKind::Display: draw_display(out, layout, lane, m, names); break;
      case LaneKind::Datalog: draw_datalog(out, layout, lane, m, image); break;
    }
  }
  out += "</svg>\n";
  return out;
}

namespace {

// A page's head, its title, a line under it and the legend.
std::string html_head(std::string_view title, std::string_view summary) {
  namespace c = trace_colors;
  std::string out = fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>rcxc run: {}</title>\n"
      "<style>\nbody {{ font-family: sans-serif; margin: 16px; color: #222; background: #fff; }}\n"
      "h1 {{ font-size: 20px; margin: 0 0 4px; }}\n"
      "h2 {{ font-size: 16px; margin: 14px 0 4px; }}\n"
      "ul.legend {{ list-style: none; padding: 0; margin: 8px 0 12px; }}\n"
      "ul.legend li {{ display: inline-block; margin-right: 18px; font-size: 13px; }}\n"
      "ul.legend span {{ display: inline-block; width: 14px; height: 12px; margin-right: 5px; vertical-align: -1px; }}\n"
      "</style>\n</head>\n<body>\n<h1>{}</h1>\n<p>{}; hover over a bar or mark for its details.</p>\n",
      xml(title), xml(title), xml(summary));
  out += "<ul class=\"legend\">\n";
  auto item = [&](std::string_view color, std::string_view text) {
    out += fmt::format("<li><span style=\"background: {}\"></span>{}</li>\n", color, text);
  };
  item(c::kForward, "output forward (height = power)");
  item(c::kReverse, "output reverse");
  item(c::kBrake, "output off (brake)");
  item(c::kFloat, "output float (thin line)");
  item(c::kSensorLine, "sensor value as the program reads it");
  item(c::kTask, "task running");
  item(c::kSound, "sound (dot) and tone (bar)");
  item(c::kSent, "message sent (&#9650;)");
  item(c::kReceived, "message received (&#9660;)");
  item(c::kDisplay, "display");
  item(c::kDatalog, "datalog entry");
  out += "</ul>\n";
  return out;
}

}  // namespace

std::string trace_html(const Machine& m, const Image& image, const EventNames& names, std::string_view title) {
  return html_head(title, stop_summary(m)) + trace_svg(m, image, names, title) + "</body>\n</html>\n";
}

std::string trace_html_room(std::span<const RoomBrick> bricks, const EventNames& names, std::string_view title) {
  Micros end_us = 1;
  for (const RoomBrick& b : bricks) end_us = std::max(end_us, trace_layout(*b.machine, *b.image, names).end_us);
  std::string out = html_head(title, fmt::format("{} bricks in one room, their IR messages reaching each other",
                                                  bricks.size()));
  for (const RoomBrick& b : bricks) {
    out += fmt::format("<h2>{}</h2>\n", xml(b.label));
    out += trace_svg(*b.machine, *b.image, names, b.label, end_us);
  }
  return out + "</body>\n</html>\n";
}

}  // namespace rcx
