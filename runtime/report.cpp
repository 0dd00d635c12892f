#include "runtime/report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <ostream>
#include <string>
#include <vector>

namespace rcx {
namespace {

constexpr const char* kOutputNames[kOutputs] = {"A", "B", "C"};

// Milliseconds as an integer when whole, else fractional.
nlohmann::json ms(Micros us) {
  if (us % kMicrosPerMs == 0) return us / kMicrosPerMs;
  return static_cast<double>(us) / static_cast<double>(kMicrosPerMs);
}

std::string task_label(const Image& image, int task) {
  std::string name = printable_name(image.name_of(SymbolType::Task, task));
  return name.empty() ? fmt::format("task {}", task) : fmt::format("task {} ({})", task, name);
}

std::string var_label(const Image& image, int index) {
  std::string name = printable_name(image.name_of(SymbolType::Variable, index));
  return name.empty() ? fmt::format("var{}", index) : name;
}

// VCD identifiers end at whitespace: keep names to [A-Za-z0-9_].
std::string vcd_name(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  return name;
}

nlohmann::json output_json(const Output& o) {
  return {{"mode", to_string(o.mode)}, {"dir", to_string(o.dir)}, {"power", o.power}};
}

std::string event_text(const Event& e, const Image& image, const EventNames& names) {
  switch (e.kind) {
    case EventKind::Output:
      return fmt::format("output {} {} {} power {}", kOutputNames[e.index], to_string(e.output.mode),
                         to_string(e.output.dir), e.output.power);
    case EventKind::Sound: return "sound " + name_or_number(names.sounds, e.value);
    case EventKind::Tone: return fmt::format("tone {} Hz for {} ms", e.value, e.duration * 10);
    case EventKind::Display: return "display " + name_or_number(names.displays, e.value);
    case EventKind::MessageSent: return fmt::format("message sent {}", e.value);
    case EventKind::MessageReceived: return fmt::format("message received {}", e.value);
    case EventKind::Datalog: return fmt::format("datalog {} = {}", datalog_source(e.type, image), e.value);
    case EventKind::SensorReading: return fmt::format("SENSOR_{} reads {}", e.index + 1, e.value);
    case EventKind::TaskStart: return task_label(image, e.index) + " started";
    case EventKind::TaskStop: return task_label(image, e.index) + " stopped";
    case EventKind::Sensor:
      return fmt::format("input: sensor {} {} {}", e.index + 1, e.type == 0 ? "raw" : "rotation", e.value);
    case EventKind::Variable: return fmt::format("{} = {}", var_label(image, e.index), e.value);
  }
  return "?";
}

std::string format_ms(Micros us) { return fmt::format("{}.{:03d}", us / kMicrosPerMs, us % kMicrosPerMs); }

}  // namespace

std::string name_or_number(const std::map<int, std::string>& names, int value) {
  auto it = names.find(value);
  return it == names.end() ? std::to_string(value) : it->second;
}

std::vector<bool> named_variables(const Image& image) {
  std::vector<bool> named(kMaxVariables, false);
  bool any = false;
  for (const auto& sym : image.symbols)
    if (sym.type == SymbolType::Variable && sym.index < kMaxVariables) named[sym.index] = any = true;
  if (!any) named.assign(kMaxVariables, true);
  return named;
}

std::string datalog_source(int type, const Image& image) {
  if (type < 0x20) return var_label(image, type);
  if (type < 0x40) return fmt::format("Timer({})", type & 3);
  if (type < 0x80) return fmt::format("SENSOR_{}", (type & 3) + 1);
  return "Watch()";
}

nlohmann::json event_json(const Event& e, const Image& image) {
  nlohmann::json j = {{"t", ms(e.t_us)}, {"kind", to_string(e.kind)}};
  switch (e.kind) {
    case EventKind::Output:
      j["output"] = kOutputNames[e.index];
      j.update(output_json(e.output));
      break;
    case EventKind::Sound: j["sound"] = e.value; break;
    case EventKind::Tone: j["freq"] = e.value, j["duration"] = e.duration; break;
    case EventKind::Display: j["display"] = e.value; break;
    case EventKind::MessageSent: j["value"] = e.value; break;
    case EventKind::Datalog: j["type"] = e.type, j["value"] = e.value; break;
    case EventKind::TaskStart:
    case EventKind::TaskStop: {
      j["task"] = e.index;
      std::string name = image.name_of(SymbolType::Task, e.index);
      if (!name.empty()) j["name"] = name;
      break;
    }
    case EventKind::Sensor:
      j["sensor"] = e.index + 1;
      j[e.type == 0 ? "raw" : "rotation"] = e.value;
      break;
    case EventKind::Variable: j["var"] = e.index, j["value"] = e.value; break;
    case EventKind::SensorReading: j["sensor"] = e.index + 1, j["value"] = e.value; break;
    case EventKind::MessageReceived: j["value"] = e.value; break;
  }
  return j;
}

namespace {

// Symbol names come from the image and may be any bytes: invalid UTF-8 is
// replaced rather than thrown about.
std::string dumped(const nlohmann::json& j) { return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace); }

// What the report lists of a run's events: what the program did; inputs
// and what follows from them are in the trace.
bool reported(const Event& e) {
  return e.kind != EventKind::Sensor && e.kind != EventKind::Variable && e.kind != EventKind::SensorReading &&
         e.kind != EventKind::MessageReceived;
}

// `events` as the JSON array dump(2) writes at `depth` (each level two
// spaces deeper), one event's tree at a time. An event's values are numbers
// and strings, and a dumped string holds no line break, so its lines are
// indented as they are.
void write_events(std::ostream& out, const std::vector<Event>& events, const Image& image, bool (*keep)(const Event&),
                  int depth) {
  const std::string inner(static_cast<std::size_t>(2 * (depth + 1)), ' ');
  bool first = true;
  for (const Event& e : events) {
    if (!keep(e)) continue;
    out << (first ? "[\n" : ",\n") << inner;
    first = false;
    std::string text = dumped(event_json(e, image));
    for (char c : text) {
      out << c;
      if (c == '\n') out << inner;
    }
  }
  out << (first ? "[]" : "\n" + std::string(static_cast<std::size_t>(2 * depth), ' ') + "]");
}

bool every_event(const Event&) { return true; }

// The report without its events, then where they go: "events" is the one
// key whose value is an array of objects, dumped as `[]` here and written
// in its place.
nlohmann::json report_without_events(const Machine& m, const Image& image);

}  // namespace

void write_report_json(std::ostream& out, const Machine& m, const Image& image) {
  std::string text = dumped(report_without_events(m, image));
  const std::string key = "\n  \"events\": []";
  std::size_t at = text.find(key);
  out << text.substr(0, at + key.size() - 2);
  write_events(out, m.state().events, image, reported, 1);
  out << text.substr(at + key.size());
}

void write_trace_json(std::ostream& out, const Machine& m, const Image& image) {
  write_events(out, m.state().events, image, every_event, 0);
}

nlohmann::json report_json(const Machine& m, const Image& image) {
  nlohmann::json j = report_without_events(m, image);
  for (const auto& e : m.state().events)
    if (reported(e)) j["events"].push_back(event_json(e, image));
  return j;
}

namespace {

nlohmann::json report_without_events(const Machine& m, const Image& image) {
  const State& s = m.state();
  nlohmann::json j;
  j["time_ms"] = ms(m.now_us());
  j["stop"] = to_string(m.stop().kind);
  if (m.stop().fault) {
    const Fault& f = *m.stop().fault;
    j["fault"] = {{"task", f.task}, {"address", f.address}, {"opcode", f.opcode}, {"message", f.message}};
    if (f.sub >= 0) j["fault"]["sub"] = f.sub;
  }
  j["vars"] = nlohmann::json::array();
  for (auto v : s.vars) j["vars"].push_back(v);
  j["globals"] = nlohmann::json::object();
  // Both compilers list file-scope globals before locals, so the first symbol
  // of a name is the global; a task's local of the same name must not hide it.
  for (const auto& sym : image.symbols)
    if (sym.type == SymbolType::Variable && sym.index < kMaxVariables && !j["globals"].contains(sym.name))
      j["globals"][sym.name] = s.vars[sym.index];
  for (int i = 0; i < kOutputs; ++i) j["outputs"][kOutputNames[i]] = output_json(s.outputs[static_cast<std::size_t>(i)]);
  j["message"] = s.message;
  j["display"] = s.display;
  j["datalog"] = nlohmann::json::array();
  for (const auto& e : s.datalog) j["datalog"].push_back(e.value);
  j["events"] = nlohmann::json::array();
  return j;
}

}  // namespace

nlohmann::json trace_json(const Machine& m, const Image& image) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& e : m.state().events) j.push_back(event_json(e, image));
  return j;
}

std::string time_ms(Micros us) { return format_ms(us); }

std::vector<TimelineLine> timeline_events(const Machine& m, const Image& image, const EventNames& names) {
  std::vector<TimelineLine> lines;
  for (const auto& e : m.state().events)
    if (e.kind != EventKind::Variable) lines.push_back({e.t_us, event_text(e, image, names)});
  return lines;
}

std::string final_state_text(const Machine& m, const Image& image) {
  const State& s = m.state();
  std::string out = fmt::format("stopped: {} at {} ms\n", to_string(m.stop().kind), format_ms(m.now_us()));
  if (m.stop().fault) {
    const Fault& f = *m.stop().fault;
    out += fmt::format("fault: {}{}, address {}, opcode 0x{:02x}: {}\n", task_label(image, f.task),
                       f.sub >= 0 ? fmt::format(" in sub {}", f.sub) : "", f.address, f.opcode & 0xff, f.message);
  }
  for (int i = 0; i < kOutputs; ++i) {
    const Output& o = s.outputs[static_cast<std::size_t>(i)];
    out += fmt::format("output {}: {} {} power {}\n", kOutputNames[i], to_string(o.mode), to_string(o.dir), o.power);
  }
  std::vector<bool> shown = named_variables(image);
  for (int i = 0; i < kMaxVariables; ++i) {
    std::string name = printable_name(image.name_of(SymbolType::Variable, i));
    if (shown[static_cast<std::size_t>(i)] && (!name.empty() || s.vars[static_cast<std::size_t>(i)] != 0))
      out += fmt::format("var[{}]{} = {}\n", i, name.empty() ? "" : " " + name, s.vars[static_cast<std::size_t>(i)]);
  }
  out += fmt::format("message: {}  display: {}\n", s.message, s.display);
  if (!s.datalog.empty()) {
    out += "datalog:";
    for (const auto& e : s.datalog) out += fmt::format(" {}", e.value);
    out += "\n";
  }
  return out;
}

std::size_t time_column_width(Micros latest) { return std::max<std::size_t>(12, format_ms(latest).size()); }

std::string timeline_text(const Machine& m, const Image& image, const EventNames& names) {
  // As wide as the latest time shown (a run may last 2^40 ms; sounds still
  // queued at the end are shown when they start, after it), 12 at least so
  // that short runs keep their usual layout.
  Micros latest = m.now_us();
  for (const auto& e : m.state().events) latest = std::max(latest, e.t_us);
  const std::size_t width = time_column_width(latest);
  std::string out;
  for (const TimelineLine& line : timeline_events(m, image, names))
    out += fmt::format("{:>{}} ms  {}\n", format_ms(line.t_us), width, line.text);
  return out + final_state_text(m, image);
}

// ------------------------------------------------------------ rooms

std::string room_timeline_text(std::span<const RoomBrick> bricks, std::span<const Transmission> sent,
                               const EventNames& names) {
  struct Line {
    Micros t_us;
    std::string text;
  };
  std::vector<Line> lines;
  std::size_t label_width = 0;
  for (const RoomBrick& b : bricks) label_width = std::max(label_width, b.label.size());
  auto labelled = [&](const std::string& label, const std::string& text) {
    return fmt::format("{:<{}}  {}", label, label_width, text);
  };
  Micros latest = 0;
  for (const RoomBrick& b : bricks) {
    latest = std::max(latest, b.machine->now_us());
    for (const TimelineLine& line : timeline_events(*b.machine, *b.image, names))
      lines.push_back({line.t_us, labelled(b.label, line.text)});
  }
  for (const Transmission& t : sent) {
    const std::string& from = bricks[static_cast<std::size_t>(t.from)].label;
    if (t.collided)
      lines.push_back({t.end_us, labelled("IR", fmt::format("message {} from {} lost: another brick sent at the same "
                                                             "time (on the air {} to {} ms)",
                                                             t.value, from, format_ms(t.start_us), format_ms(t.end_us)))});
    else if (t.switched_off)
      lines.push_back({t.end_us, labelled("IR", fmt::format("message {} from {} never went out whole: its brick "
                                                             "switched off",
                                                             t.value, from))});
    else if (t.received_by.empty() && !t.unfinished)
      lines.push_back({t.end_us, labelled("IR", fmt::format("message {} from {} reached no brick: no other program "
                                                             "was running",
                                                             t.value, from))});
  }
  std::ranges::stable_sort(lines, {}, &Line::t_us);
  for (const Line& line : lines) latest = std::max(latest, line.t_us);
  const std::size_t width = time_column_width(latest);
  std::string out;
  for (const Line& line : lines) out += fmt::format("{:>{}} ms  {}\n", format_ms(line.t_us), width, line.text);
  for (const RoomBrick& b : bricks) out += fmt::format("\n{}:\n{}", b.label, final_state_text(*b.machine, *b.image));
  return out;
}

nlohmann::json room_report_json(std::span<const RoomBrick> bricks, std::span<const Transmission> sent) {
  nlohmann::json j = {{"bricks", nlohmann::json::array()}, {"messages", nlohmann::json::array()}};
  for (const RoomBrick& b : bricks)
    j["bricks"].push_back({{"label", b.label}, {"report", report_json(*b.machine, *b.image)}});
  for (const Transmission& t : sent) {
    nlohmann::json m = {{"from", t.from + 1},     {"value", t.value},         {"sent", ms(t.sent_us)},
                        {"start", ms(t.start_us)}, {"end", ms(t.end_us)},       {"collided", t.collided},
                        {"received_by", nlohmann::json::array()}, {"unfinished", t.unfinished}, {"switched_off", t.switched_off}};
    for (int r : t.received_by) m["received_by"].push_back(r + 1);
    j["messages"].push_back(std::move(m));
  }
  return j;
}

// ------------------------------------------------------------ VCD

namespace {

std::string bits(int value, int width) {
  std::string b;
  for (int i = width - 1; i >= 0; --i) b += ((value >> i) & 1) ? '1' : '0';
  return b;
}

struct VcdSignal {
  std::string id, name;
  int width;
};

}  // namespace

std::string trace_vcd(const Machine& m, const Image& image) {
  // Identifiers: printable ASCII from '!' on, one per signal.
  std::vector<VcdSignal> signals;
  auto add = [&](std::string name, int width) {
    int n = static_cast<int>(signals.size());
    std::string id(1, static_cast<char>('!' + n % 90));
    if (n >= 90) id += static_cast<char>('!' + n / 90);
    signals.push_back({id, std::move(name), width});
    return n;
  };
  int out_mode[kOutputs], out_dir[kOutputs], out_power[kOutputs], raw[kSensors], rot[kSensors], vars[kMaxVariables];
  for (int i = 0; i < kOutputs; ++i) {
    out_mode[i] = add(fmt::format("out_{}_mode", kOutputNames[i]), 2);  // 0 float, 1 off, 2 on
    out_dir[i] = add(fmt::format("out_{}_rev", kOutputNames[i]), 1);
    out_power[i] = add(fmt::format("out_{}_power", kOutputNames[i]), 3);
  }
  for (int i = 0; i < kSensors; ++i) {
    raw[i] = add(fmt::format("sensor_{}_raw", i + 1), 10);
    rot[i] = add(fmt::format("sensor_{}_rotation", i + 1), 16);
  }
  std::vector<bool> named = named_variables(image);
  for (int i = 0; i < kMaxVariables; ++i) vars[i] = named[static_cast<std::size_t>(i)] ? add(vcd_name(var_label(image, i)), 16) : -1;
  int sound = add("sound", 8);
  int tone = add("tone_hz", 16);
  int message = add("message_sent", 8);
  int received = add("message_received", 8);

  std::string out = "$date rcxc run $end\n$version rcxc emulator $end\n$timescale 1us $end\n$scope module rcx $end\n";
  for (const auto& s : signals) out += fmt::format("$var wire {} {} {} $end\n", s.width, s.id, s.name);
  out += "$upscope $end\n$enddefinitions $end\n";
  auto value = [&](int signal, int v) {
    const VcdSignal& s = signals[static_cast<std::size_t>(signal)];
    return s.width == 1 ? fmt::format("{}{}\n", v & 1, s.id) : fmt::format("b{} {}\n", bits(v, s.width), s.id);
  };
  out += "#0\n$dumpvars\n";
  Output initial;
  for (int i = 0; i < kOutputs; ++i)
    out += value(out_mode[i], static_cast<int>(initial.mode)) + value(out_dir[i], 0) + value(out_power[i], initial.power);
  for (int i = 0; i < kSensors; ++i) out += value(raw[i], Sensor{}.raw) + value(rot[i], 0);
  for (int i = 0; i < kMaxVariables; ++i)
    if (vars[i] >= 0) out += value(vars[i], 0);
  out += value(sound, 0) + value(tone, 0) + value(message, 0) + value(received, 0) + "$end\n";
  Micros last = 0;
  for (const auto& e : m.state().events) {
    std::string change;
    switch (e.kind) {
      case EventKind::Output:
        change = value(out_mode[e.index], static_cast<int>(e.output.mode)) +
                 value(out_dir[e.index], e.output.dir == Direction::Reverse) + value(out_power[e.index], e.output.power);
        break;
      case EventKind::Sensor: change = value(e.type == 0 ? raw[e.index] : rot[e.index], e.value); break;
      case EventKind::Variable:
        if (vars[e.index] >= 0) change = value(vars[e.index], e.value);
        break;
      case EventKind::Sound: change = value(sound, e.value + 1); break;  // 0 = silence, n+1 = sound n
      case EventKind::Tone: change = value(tone, e.value); break;
      case EventKind::MessageSent: change = value(message, e.value); break;
      case EventKind::MessageReceived: change = value(received, e.value); break;
      default: break;
    }
    if (change.empty()) continue;
    if (e.t_us > last) out += fmt::format("#{}\n", e.t_us), last = e.t_us;
    out += change;
  }
  out += fmt::format("#{}\n", std::max(m.now_us(), last));
  return out;
}

}  // namespace rcx
