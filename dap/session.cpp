#include "dap/session.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>

#include "frontend/parse.h"
#include "lsp/jsonrpc.h"
#include "runtime/report.h"
#include "runtime/scenario.h"
#include "tomlfile/longest_run.h"

namespace rcxc::dap {

using nlohmann::json;

namespace {

// Machine events shown as output, at most; a long run's millions would
// bury the console (the rest are counted once).
constexpr std::size_t kMostEventsShown = 10'000;
constexpr std::int64_t kDefaultForMs = 60'000;

constexpr int kGlobalsRef = 1;
constexpr int kBrickRef = 2;
constexpr int kSensorRef = 10;     // + sensor 0..2
constexpr int kLocalsRef = 1000;   // + frame id

int fragment_key(const FragmentLines& f) { return f.type == rcx::FragmentType::Task ? f.index : 100 + f.index; }

// call_depth 3 is back in the outer subroutine (its return address spent).
int depth_of(const rcx::TaskState& t) { return t.call_depth == 3 ? 1 : t.call_depth; }

int frame_id(int task, int level) { return (task + 1) * 16 + level; }

// A message's field, whatever the client put there: a request's seq is
// echoed as request_seq, and a seq that is no integer is echoed as 0.
std::int64_t integer_at(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_number_integer()) return 0;
  return object[key].get<std::int64_t>();
}
std::string string_at(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_string()) return "";
  return object[key].get<std::string>();
}
json arguments_of(const json& request) {
  return request.is_object() && request.contains("arguments") ? request["arguments"] : json::object();
}

json response(Session& s, const json& request, bool success, json body = json::object(), const std::string& message = "") {
  json r = {{"seq", ++s.seq},
            {"type", "response"},
            {"request_seq", integer_at(request, "seq")},
            {"success", success},
            {"command", string_at(request, "command")}};
  if (!success) {
    r["message"] = message;
    body["error"] = {{"id", 1}, {"format", message}, {"showUser", true}};
  }
  r["body"] = std::move(body);
  return r;
}

json failure(Session& s, const json& request, const std::string& message) {
  return response(s, request, false, json::object(), message);
}

json event(Session& s, const std::string& name, json body = json::object()) {
  return {{"seq", ++s.seq}, {"type", "event"}, {"event", name}, {"body", std::move(body)}};
}

json output(Session& s, const std::string& category, const std::string& text) {
  return event(s, "output", {{"category", category}, {"output", text}});
}

std::string task_name(const Session& s, int task) {
  std::string name = s.program ? s.program->image.name_of(rcx::SymbolType::Task, task) : "";
  return name.empty() ? fmt::format("task {}", task) : name;
}

json source_of(const DebugProgram& p, const Place& place) {
  const std::string& path = p.files[static_cast<std::size_t>(place.file)];
  return {{"name", std::filesystem::path(path).filename().string()}, {"path", path}};
}

// ------------------------------------------------------------ launch

bool is_identifier(std::string_view name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// A list of strings, or why not.
std::optional<std::string> strings_of(const json& args, const char* key, std::vector<std::string>& out) {
  if (!args.contains(key)) return std::nullopt;
  const json& v = args[key];
  if (!v.is_array()) return fmt::format("'{}' must be a list of strings", key);
  for (const auto& item : v) {
    if (!item.is_string()) return fmt::format("'{}' must be a list of strings", key);
    out.push_back(item.get<std::string>());
  }
  return std::nullopt;
}

std::vector<json> launch(Session& s, const json& request) {
  std::vector<json> out;
  json args = arguments_of(request);
  if (!args.is_object()) return {failure(s, request, "launch: the arguments must be an object")};
  if (s.phase != Phase::Start) return {failure(s, request, "launch: a program is already launched in this session")};
  s.stop_on_entry = s.no_debug = false;  // a launch refused before may have set them
  if (!args.contains("program") || !args["program"].is_string() || args["program"].get<std::string>().empty())
    return {failure(s, request, "launch: 'program' must name an .nqc file")};
  std::string program = args["program"];
  std::string optimize = "0";
  if (args.contains("optimize")) {
    const json& o = args["optimize"];
    if (o.is_number_integer()) optimize = std::to_string(o.get<long long>());
    else if (o.is_string()) optimize = o.get<std::string>();
    else optimize = "?";
    if (optimize != "0" && optimize != "1" && optimize != "2" && optimize != "s")
      return {failure(s, request, "launch: 'optimize' must be \"0\", \"1\", \"2\" or \"s\"")};
  }
  std::int64_t for_ms = kDefaultForMs;
  if (args.contains("for")) {
    const json& f = args["for"];
    if (!f.is_number_integer() || f.get<long long>() < 1 || f.get<long long>() > kLongestRunMs)
      return {failure(s, request, fmt::format("launch: 'for' must be a whole number of ms, 1..{}", kLongestRunMs))};
    for_ms = f.get<std::int64_t>();
  }
  if (args.contains("stopOnEntry")) {
    if (!args["stopOnEntry"].is_boolean()) return {failure(s, request, "launch: 'stopOnEntry' must be true or false")};
    s.stop_on_entry = args["stopOnEntry"];
  }
  if (args.contains("noDebug")) {
    if (!args["noDebug"].is_boolean()) return {failure(s, request, "launch: 'noDebug' must be true or false")};
    s.no_debug = args["noDebug"];
  }
  frontend::Options options;
  std::vector<std::string> defines;
  if (auto bad = strings_of(args, "includePath", options.include_dirs)) return {failure(s, request, "launch: " + *bad)};
  if (auto bad = strings_of(args, "defines", defines)) return {failure(s, request, "launch: " + *bad)};
  for (const auto& d : defines) {
    std::string name = d.substr(0, d.find('='));
    if (!is_identifier(name) || frontend::not_a_macro_name(name))
      return {failure(s, request, fmt::format("launch: defines: '{}' cannot be a macro name", name))};
    options.define(d);
  }
  std::vector<rcx::TimedInput> inputs;
  if (args.contains("scenario") && !args["scenario"].is_null()) {
    if (!args["scenario"].is_string()) return {failure(s, request, "launch: 'scenario' must name a TOML file")};
    std::string scenario = args["scenario"];
    if (!scenario.empty()) {
      auto parsed = rcx::read_scenario_file(scenario);
      if (auto* e = std::get_if<rcx::ScenarioError>(&parsed)) return {failure(s, request, "launch: " + e->message)};
      inputs = std::get<std::vector<rcx::TimedInput>>(std::move(parsed));
    }
  }
  ir::OptLevel level = optimize == "0"   ? ir::OptLevel::O0
                       : optimize == "1" ? ir::OptLevel::O1
                       : optimize == "s" ? ir::OptLevel::Os
                                         : ir::OptLevel::O2;
  CompileOutcome compiled = compile_for_debug(program, options, level);
  if (!compiled.messages.empty()) out.push_back(output(s, compiled.program ? "console" : "stderr", compiled.messages));
  if (!compiled.program) {
    std::string first = compiled.messages.substr(0, compiled.messages.find('\n'));
    out.push_back(failure(s, request, first.empty() ? "launch: " + program + " does not compile" : first));
    return out;
  }
  s.program = std::move(compiled.program);
  s.machine.emplace(rcx::Config{});
  if (auto error = s.machine->load(0, s.program->image)) {
    out.push_back(failure(s, request, "launch: " + program + ": " + *error));
    s.program.reset();
    s.machine.reset();
    return out;
  }
  if (!s.program->image.find(rcx::FragmentType::Task, 0)) {
    out.push_back(failure(s, request, "launch: " + program + " has no task main to start"));
    s.program.reset();
    s.machine.reset();
    return out;
  }
  for (const auto& in : inputs) s.machine->schedule(in);
  s.machine->start_program();
  s.limit_us = for_ms * rcx::kMicrosPerMs;
  s.phase = Phase::Launched;
  out.push_back(response(s, request, true));
  // Now breakpoints can be placed: the client sends them, then configurationDone.
  out.push_back(event(s, "initialized"));
  return out;
}

// ------------------------------------------------------------ breakpoints

void place_breakpoints(Session& s) {
  s.break_at.clear();
  if (!s.program) return;
  for (const auto& [file, list] : s.breakpoints)
    for (const auto& bp : list) {
      if (bp.used_line == 0) continue;
      for (const auto& f : s.program->fragments)
        for (std::size_t i = 0; i < f.places.size(); ++i)
          if (f.starts[i] && f.places[i] == Place{file, bp.used_line})
            s.break_at[{fragment_key(f), f.addresses[i]}].push_back(bp.id);
    }
}

// The first line at or after `line` in `file` where a statement starts.
int line_with_code(const DebugProgram& p, int file, int line) {
  int best = 0;
  for (const auto& f : p.fragments)
    for (std::size_t i = 0; i < f.places.size(); ++i)
      if (f.starts[i] && f.places[i].file == file && f.places[i].line >= line && (best == 0 || f.places[i].line < best))
        best = f.places[i].line;
  return best;
}

json set_breakpoints(Session& s, const json& request) {
  json args = arguments_of(request);
  if (!args.is_object() || !args.contains("source") || !args["source"].is_object())
    return failure(s, request, "setBreakpoints: 'source' is missing");
  std::string path = string_at(args["source"], "path");
  std::vector<int> lines;
  if (args.contains("breakpoints") && args["breakpoints"].is_array()) {
    for (const auto& b : args["breakpoints"])
      if (b.is_object() && b.contains("line") && b["line"].is_number_integer()) lines.push_back(b["line"]);
  } else if (args.contains("lines") && args["lines"].is_array()) {
    for (const auto& l : args["lines"])
      if (l.is_number_integer()) lines.push_back(l);
  }
  int file = s.program ? s.program->file_index(path) : -1;
  json result = json::array();
  std::vector<Breakpoint> placed;
  for (int line : lines) {
    Breakpoint bp{s.next_breakpoint_id++, line, 0};
    json b = {{"id", bp.id}, {"verified", false}, {"line", line}};
    if (!s.program) {
      b["message"] = "the program is not launched yet";
    } else if (s.no_debug) {
      b["message"] = "the program runs without debugging";
    } else if (file < 0) {
      b["message"] = "the program does not use " + path;
    } else if (line < 1) {
      b["message"] = fmt::format("there is no line {}: lines count from 1", line);
    } else if ((bp.used_line = line_with_code(*s.program, file, line)) == 0) {
      b["message"] = fmt::format("no code at line {} or after it", line);
    } else {
      b["verified"] = true;
      b["line"] = bp.used_line;
      b["source"] = source_of(*s.program, {file, bp.used_line});
    }
    placed.push_back(bp);
    result.push_back(std::move(b));
  }
  if (file >= 0) s.breakpoints[file] = std::move(placed);
  place_breakpoints(s);
  return response(s, request, true, {{"breakpoints", result}});
}

// ------------------------------------------------------------ running

// The task a thread id names, when it is running; else nullopt.
std::optional<int> task_of_thread(const Session& s, const json& args) {
  if (!s.machine || !args.is_object() || !args.contains("threadId") || !args["threadId"].is_number_integer()) return std::nullopt;
  long long id = args["threadId"];
  if (id < 1 || id > rcx::kMaxTasks || !s.machine->task(static_cast<int>(id - 1)).active) return std::nullopt;
  return static_cast<int>(id - 1);
}

void thread_events(Session& s, std::vector<json>& out) {
  if (!s.machine) return;
  for (int t = 0; t < rcx::kMaxTasks; ++t) {
    bool active = s.machine->task(t).active, told = (s.threads_told >> t) & 1u;
    if (active == told) continue;
    out.push_back(event(s, "thread", {{"reason", active ? "started" : "exited"}, {"threadId", t + 1}}));
    s.threads_told ^= 1u << t;
  }
}

void event_output(Session& s, std::vector<json>& out) {
  const auto& events = s.machine->state().events;
  for (; s.events_sent < events.size(); ++s.events_sent) {
    if (s.events_sent == kMostEventsShown) {
      out.push_back(output(s, "console", fmt::format("(further events are not shown here: the first {} were)\n", kMostEventsShown)));
      s.events_sent = events.size();
      break;
    }
    const rcx::Event& e = events[s.events_sent];
    json j = rcx::event_json(e, s.program->image);
    j.erase("t");
    out.push_back(output(s, "console", fmt::format("{:>9.3f} s  {}\n", static_cast<double>(e.t_us) / 1e6, j.dump())));
  }
}

void stopped(Session& s, std::vector<json>& out, const std::string& reason, int task, const std::vector<int>& ids = {}) {
  s.phase = Phase::Stopped;
  s.stopped_task = task;
  s.pass_task = task;
  s.goal = Goal::Continue;
  s.goal_task = -1;
  thread_events(s, out);
  json body = {{"reason", reason}, {"threadId", task + 1}, {"allThreadsStopped", true}};
  if (!ids.empty()) body["hitBreakpointIds"] = ids;
  out.push_back(event(s, "stopped", body));
}

void finish(Session& s, std::vector<json>& out) {
  const rcx::StopInfo& stop = s.machine->stop();
  int code = kExitEnded;
  std::string why;
  switch (stop.kind) {
    case rcx::StopKind::Fault: {
      code = kExitFault;
      // The line first: the editor's user knows the source, not the addresses.
      std::string at = fmt::format("address {}", stop.fault->address);
      if (const FragmentLines* f = s.program->fragment(stop.fault->task, stop.fault->sub)) {
        Place place = s.program->place_at(*f, stop.fault->address);
        if (place.valid())
          at = fmt::format("{}:{} (address {})", s.program->files[static_cast<std::size_t>(place.file)], place.line,
                           stop.fault->address);
      }
      why = fmt::format("the program faulted in {} at {}: {}", task_name(s, stop.fault->task), at, stop.fault->message);
      break;
    }
    case rcx::StopKind::TimeLimit:
      code = kExitTimeLimit;
      why = fmt::format("the time limit ({} ms of virtual time) passed with tasks still running", s.limit_us / rcx::kMicrosPerMs);
      break;
    case rcx::StopKind::EventLimit:
      code = kExitEventLimit;
      why = "the run stopped: " + rcx::event_limit_reason(*s.machine);
      break;
    case rcx::StopKind::PowerOff: why = "the program turned the brick off"; break;
    default: why = "the program ended"; break;
  }
  s.phase = Phase::Ended;
  thread_events(s, out);
  out.push_back(output(s, code == kExitEnded ? "console" : "stderr",
                       fmt::format("{} at {} ms\n", why, s.machine->now_us() / rcx::kMicrosPerMs)));
  out.push_back(event(s, "exited", {{"exitCode", code}}));
  out.push_back(event(s, "terminated"));
}

void resume(Session& s, Goal goal, int task) {
  s.goal = goal;
  s.goal_task = goal == Goal::Continue ? -1 : task;
  s.goal_moved = false;
  if (goal != Goal::Continue) {
    const rcx::TaskState& t = s.machine->task(task);
    const FragmentLines* f = s.program->fragment(task, t.sub);
    s.goal_place = f ? s.program->place_at(*f, t.pc) : Place{};
    s.goal_depth = depth_of(t);
    // Out of the task body is out of the task: as continue.
    if (goal == Goal::StepOut && s.goal_depth == 0) s.goal = Goal::Continue, s.goal_task = -1;
  }
  s.pause_asked = false;
  s.phase = Phase::Running;
}

// ------------------------------------------------------------ inspection

// The frames of a running task, the innermost first.
json frames_of(const Session& s, std::optional<int> task) {
  const DebugProgram& p = *s.program;
  const rcx::TaskState& t = s.machine->task(*task);
  json frames = json::array();
  auto add = [&](int level, const FragmentLines* f, int pc, bool caller) {
    json frame = {{"id", frame_id(*task, level)}, {"line", 0}, {"column", 0}};
    std::string name = f ? f->name : "?";
    if (f) {
      Place place = p.place_at(*f, caller ? pc - 1 : pc);
      if (place.valid()) {
        frame["line"] = place.line;
        frame["column"] = 1;
        frame["source"] = source_of(p, place);
      }
    }
    frame["name"] = name;
    frames.push_back(frame);
  };
  add(0, p.fragment(*task, t.sub), t.pc, false);
  if (t.sub >= 0 && (t.call_depth == 1 || t.call_depth == 2)) {
    add(1, p.fragment(*task, t.return_sub), t.return_pc, true);
    if (t.call_depth == 2)
      frames.push_back({{"id", frame_id(*task, 2)},
                        {"name", task_name(s, *task) + " (the call into the outer subroutine: the RCX keeps one return address)"},
                        {"line", 0},
                        {"column", 0},
                        {"presentationHint", "label"}});
  } else if (t.sub >= 0) {
    frames.push_back({{"id", frame_id(*task, 1)},
                      {"name", task_name(s, *task) + " (returns nowhere: its return address was spent by a nested call)"},
                      {"line", 0},
                      {"column", 0},
                      {"presentationHint", "label"}});
  }
  return frames;
}

json stack_trace(Session& s, const json& request) {
  json args = arguments_of(request);
  auto task = task_of_thread(s, args);
  if (!task) return failure(s, request, "stackTrace: no such thread running");
  json frames = frames_of(s, task);
  std::size_t total = frames.size();
  // A client may ask for a page of the frames: from startFrame, at most
  // `levels` of them (0 or none: all).
  std::size_t start = 0, levels = 0;
  if (args.contains("startFrame") && args["startFrame"].is_number_integer())
    start = static_cast<std::size_t>(std::max<long long>(args["startFrame"].get<long long>(), 0));
  if (args.contains("levels") && args["levels"].is_number_integer())
    levels = static_cast<std::size_t>(std::max<long long>(args["levels"].get<long long>(), 0));
  json page = json::array();
  for (std::size_t i = start; i < total && (levels == 0 || page.size() < levels); ++i) page.push_back(frames[i]);
  return response(s, request, true, {{"stackFrames", page}, {"totalFrames", total}});
}

// Whether `frame` is a frame a stackTrace of its task now shows.
bool frame_exists(const Session& s, long long frame) {
  if (!s.machine || frame < 16 || frame >= 16 * (rcx::kMaxTasks + 1)) return false;
  int task = static_cast<int>(frame / 16 - 1);
  if (!s.machine->task(task).active) return false;
  for (const auto& f : frames_of(s, task))
    if (f["id"] == frame) return true;
  return false;
}

// The function a frame is in (for its locals), or nullptr.
const Function* function_of_frame(const Session& s, int frame) {
  int task = frame / 16 - 1, level = frame % 16;
  if (!s.machine || task < 0 || task >= rcx::kMaxTasks || !s.machine->task(task).active) return nullptr;
  const rcx::TaskState& t = s.machine->task(task);
  const FragmentLines* f = nullptr;
  if (level == 0) f = s.program->fragment(task, t.sub);
  else if (level == 1 && t.sub >= 0 && (t.call_depth == 1 || t.call_depth == 2)) f = s.program->fragment(task, t.return_sub);
  if (!f || f->function < 0) return nullptr;
  return &s.program->functions[static_cast<std::size_t>(f->function)];
}

json value_json(const std::string& name, const std::string& value, int ref = 0) {
  return {{"name", name}, {"value", value}, {"variablesReference", ref}};
}

std::string var_value(const Session& s, int slot) { return std::to_string(s.machine->state().vars[static_cast<std::size_t>(slot)]); }

const char* sensor_type_name(rcx::SensorType t) {
  static const char* names[] = {"raw", "touch", "temperature", "light", "rotation"};
  auto i = static_cast<std::size_t>(t);
  return i < std::size(names) ? names[i] : "?";
}
const char* sensor_mode_name(rcx::SensorMode m) {
  static const char* names[] = {"raw", "boolean", "edge count", "pulse count", "percent", "celsius", "fahrenheit", "angle"};
  auto i = static_cast<std::size_t>(m);
  return i < std::size(names) ? names[i] : "?";
}

json brick_variables(const Session& s) {
  const rcx::Machine& m = *s.machine;
  const rcx::State& st = m.state();
  json v = json::array();
  v.push_back(value_json("time", fmt::format("{:.3f} s", static_cast<double>(m.now_us()) / 1e6)));
  for (int o = 0; o < rcx::kOutputs; ++o) {
    const rcx::Output& out = st.outputs[static_cast<std::size_t>(o)];
    v.push_back(value_json(fmt::format("output {}", static_cast<char>('A' + o)),
                           fmt::format("{} {} power {}", rcx::to_string(out.mode), rcx::to_string(out.dir), out.power)));
  }
  for (int i = 0; i < rcx::kSensors; ++i)
    v.push_back(value_json(fmt::format("sensor {}", i + 1), std::to_string(m.sensor_value(i)), kSensorRef + i));
  for (int t = 0; t < rcx::kTimers; ++t) v.push_back(value_json(fmt::format("timer {}", t), std::to_string(m.timer_value(t))));
  v.push_back(value_json("display", std::to_string(st.display)));
  v.push_back(value_json("message", std::to_string(st.message)));
  v.push_back(value_json("watch", fmt::format("{:02}:{:02}", m.clock_minutes() / 60, m.clock_minutes() % 60)));
  v.push_back(value_json("datalog", fmt::format("{} of {}", st.datalog.size(), st.datalog_capacity)));
  return v;
}

json sensor_variables(const Session& s, int sensor) {
  const rcx::Sensor& x = s.machine->state().sensors[static_cast<std::size_t>(sensor)];
  return json::array({value_json("value", std::to_string(s.machine->sensor_value(sensor))),
                      value_json("type", sensor_type_name(x.type)), value_json("mode", sensor_mode_name(x.mode)),
                      value_json("raw", std::to_string(x.raw)), value_json("boolean", x.boolean ? "1" : "0")});
}

json variables(Session& s, const json& request) {
  json args = arguments_of(request);
  if (!s.machine || !args.is_object() || !args.contains("variablesReference") || !args["variablesReference"].is_number_integer())
    return failure(s, request, "variables: no such variables");
  long long ref = args["variablesReference"];
  json v = json::array();
  if (ref == kGlobalsRef) {
    for (const auto& g : s.program->globals) v.push_back(value_json(g.name, var_value(s, g.slot)));
  } else if (ref == kBrickRef) {
    v = brick_variables(s);
  } else if (ref >= kSensorRef && ref < kSensorRef + rcx::kSensors) {
    v = sensor_variables(s, static_cast<int>(ref - kSensorRef));
  } else if (ref >= kLocalsRef) {
    const Function* fn = function_of_frame(s, static_cast<int>(ref - kLocalsRef));
    if (!fn) return failure(s, request, "variables: that frame is gone");
    for (const auto& l : fn->locals) v.push_back(value_json(l.name, var_value(s, l.slot)));
  } else {
    return failure(s, request, "variables: no such variables");
  }
  return response(s, request, true, {{"variables", v}});
}

json scopes(Session& s, const json& request) {
  json args = arguments_of(request);
  if (!s.machine || !args.is_object() || !args.contains("frameId") || !args["frameId"].is_number_integer())
    return failure(s, request, "scopes: no such frame");
  long long frame = args["frameId"];
  if (!frame_exists(s, frame)) return failure(s, request, fmt::format("scopes: no frame {} (frames change when the program runs)", frame));
  int id = static_cast<int>(frame);
  json list = json::array();
  if (const Function* fn = function_of_frame(s, id); fn && !fn->locals.empty())
    list.push_back({{"name", "Locals"}, {"presentationHint", "locals"}, {"variablesReference", kLocalsRef + id}, {"expensive", false}});
  list.push_back({{"name", "Globals"}, {"variablesReference", kGlobalsRef}, {"expensive", false}});
  list.push_back({{"name", "Brick"}, {"variablesReference", kBrickRef}, {"expensive", false}});
  return response(s, request, true, {{"scopes", list}});
}

json evaluate(Session& s, const json& request) {
  json args = arguments_of(request);
  if (!s.machine || !args.is_object() || !args.contains("expression") || !args["expression"].is_string())
    return failure(s, request, "evaluate: nothing to evaluate");
  std::string name = args["expression"];
  name.erase(0, name.find_first_not_of(" \t"));
  name.erase(name.find_last_not_of(" \t") + 1);
  if (args.contains("frameId") && args["frameId"].is_number_integer())
    if (const Function* fn = function_of_frame(s, args["frameId"]))
      for (const auto& l : fn->locals)
        if (l.name == name) return response(s, request, true, {{"result", var_value(s, l.slot)}, {"variablesReference", 0}});
  for (const auto& g : s.program->globals)
    if (g.name == name) return response(s, request, true, {{"result", var_value(s, g.slot)}, {"variablesReference", 0}});
  return failure(s, request, "evaluate: '" + name + "' is no variable of the program (only names are evaluated)");
}

json threads(Session& s, const json& request) {
  json list = json::array();
  if (s.machine)
    for (int t = 0; t < rcx::kMaxTasks; ++t)
      if (s.machine->task(t).active) list.push_back({{"id", t + 1}, {"name", task_name(s, t)}});
  return response(s, request, true, {{"threads", list}});
}

std::vector<json> step(Session& s, const json& request, Goal goal) {
  json args = arguments_of(request);
  const std::string command = string_at(request, "command");
  if (s.phase != Phase::Stopped) return {failure(s, request, command + ": the program is not stopped")};
  auto task = task_of_thread(s, args);
  if (!task && goal != Goal::Continue) return {failure(s, request, command + ": no such thread running")};
  json body = json::object();
  if (goal == Goal::Continue) body["allThreadsContinued"] = true;
  std::vector<json> out{response(s, request, true, body)};
  resume(s, goal, task.value_or(0));
  return out;
}

}  // namespace

std::vector<json> advance(Session& s, int instructions) {
  std::vector<json> out;
  if (s.phase != Phase::Running) return out;
  int budget = instructions;
  bool yielded = false;
  struct Stop {
    std::string reason;
    int task = 0;
    std::vector<int> ids;
  };
  std::optional<Stop> stop;
  const DebugProgram& p = *s.program;
  rcx::Machine::Hold hold = [&](int task, const rcx::TaskState& t) {
    if (task == s.pass_task) {
      s.pass_task = -1;
      if (task == s.goal_task) s.goal_moved = true;
      s.last_task = task;
      return false;
    }
    if (budget-- <= 0) return yielded = true;
    if (task == s.goal_task && !s.goal_moved) {
      s.goal_moved = true;
      s.last_task = task;
      return false;
    }
    if (const FragmentLines* f = p.fragment(task, t.sub)) {
      if (auto it = s.break_at.find({fragment_key(*f), t.pc}); it != s.break_at.end()) {
        stop = Stop{"breakpoint", task, it->second};
        return true;
      }
      if (task == s.goal_task) {
        Place here = p.place_at(*f, t.pc);
        int depth = depth_of(t);
        bool new_line = here.valid() && !(here == s.goal_place) && p.starts_statement(*f, t.pc);
        bool done = s.goal == Goal::StepOut ? depth < s.goal_depth
                    : s.goal == Goal::Next  ? new_line && depth <= s.goal_depth
                                            : new_line;
        if (done) {
          stop = Stop{"step", task, {}};
          return true;
        }
      }
    }
    s.last_task = task;
    return false;
  };
  const rcx::StopInfo& info = s.machine->run(s.limit_us, hold);
  event_output(s, out);
  if (stop) {
    stopped(s, out, stop->reason, stop->task, stop->ids);
  } else if (!yielded || info.kind != rcx::StopKind::Running) {
    finish(s, out);
  } else {
    thread_events(s, out);
  }
  return out;
}

std::vector<json> dispatch(Session& s, const json& message);

std::vector<json> handle(Session& s, const json& message) {
  // Every field is checked where it is read; this is the net under a
  // check forgotten: a failed response rather than an adapter gone.
  try {
    return dispatch(s, message);
  } catch (const json::exception& e) {
    return {failure(s, message, std::string("rcxc debug: a malformed request: ") + e.what())};
  }
}

std::vector<json> dispatch(Session& s, const json& message) {
  if (string_at(message, "type") != "request")
    return {output(s, "stderr", "rcxc debug: a message that is no request was ignored: " + message.dump().substr(0, 200) + "\n")};
  // A request without a command still has a seq the client waits on.
  if (string_at(message, "command").empty()) return {failure(s, message, "rcxc debug: a request needs a 'command' (a string)")};
  const std::string command = message["command"];
  if (command == "initialize") {
    s.initialized = true;
    json caps = {{"supportsConfigurationDoneRequest", true},
                 {"supportsEvaluateForHovers", true},
                 {"supportsTerminateRequest", true}};
    return {response(s, message, true, caps)};
  }
  if (command == "launch") return launch(s, message);
  if (command == "attach") return {failure(s, message, "attach: rcxc debug runs programs on its emulator; use launch")};
  if (command == "setBreakpoints") return {set_breakpoints(s, message)};
  if (command == "setExceptionBreakpoints" || command == "setFunctionBreakpoints")
    return {response(s, message, true, {{"breakpoints", json::array()}})};
  if (command == "configurationDone") {
    std::vector<json> out{response(s, message, true)};
    if (s.phase == Phase::Launched) {
      if (s.stop_on_entry && !s.no_debug) {
        stopped(s, out, "entry", 0);
      } else {
        s.phase = Phase::Running;
        thread_events(s, out);
      }
    }
    return out;
  }
  if (command == "threads") return {threads(s, message)};
  if (command == "stackTrace") return {stack_trace(s, message)};
  if (command == "scopes") return {scopes(s, message)};
  if (command == "variables") return {variables(s, message)};
  if (command == "evaluate") return {evaluate(s, message)};
  if (command == "continue") return step(s, message, Goal::Continue);
  if (command == "next") return step(s, message, Goal::Next);
  if (command == "stepIn") return step(s, message, Goal::StepIn);
  if (command == "stepOut") return step(s, message, Goal::StepOut);
  if (command == "pause") {
    std::vector<json> out{response(s, message, true)};
    if (s.phase == Phase::Running) {
      int task = s.last_task >= 0 && s.machine->task(s.last_task).active ? s.last_task : -1;
      for (int t = 0; task < 0 && t < rcx::kMaxTasks; ++t)
        if (s.machine->task(t).active) task = t;
      event_output(s, out);
      stopped(s, out, "pause", std::max(task, 0));
    }
    return out;
  }
  if (command == "disconnect" || command == "terminate") {
    std::vector<json> out{response(s, message, true)};
    if (command == "terminate" && s.phase != Phase::Ended && s.phase != Phase::Start) {
      s.phase = Phase::Ended;
      out.push_back(event(s, "terminated"));
    }
    if (command == "disconnect") s.disconnected = true;
    return out;
  }
  return {failure(s, message, "rcxc debug does not know the request '" + command + "'")};
}

std::vector<json> handle_text(Session& s, const std::string& body) {
  if (lsp::json_nesting(body) > lsp::kMostNesting)
    return {output(s, "stderr", fmt::format("rcxc debug: a message nested deeper than {} levels was ignored: {}\n", lsp::kMostNesting,
                                            body.substr(0, 200)))};
  json message = json::parse(body, nullptr, false);
  if (message.is_discarded())
    return {output(s, "stderr", "rcxc debug: a message that is not JSON was ignored: " + body.substr(0, 200) + "\n")};
  return handle(s, message);
}

int serve(Session& s, std::istream& in, std::ostream& out, std::ostream& log) {
  // The reader runs on: reading blocks, and requests (pause) must be taken
  // while the program runs. Its state is shared, so it may outlive this
  // call, blocked on an input that never ends.
  struct Shared {
    std::mutex m;
    std::condition_variable arrived;
    std::deque<lsp::Frame> frames;
  };
  auto shared = std::make_shared<Shared>();
  in.tie(nullptr);  // reading must not flush `out` from the reader's thread
  std::thread reader([shared, &in] {
    for (;;) {
      lsp::Frame frame = lsp::read_frame(in);
      bool end = frame.kind == lsp::Frame::Kind::End;
      {
        std::lock_guard lock(shared->m);
        shared->frames.push_back(std::move(frame));
      }
      shared->arrived.notify_one();
      if (end) return;
    }
  });
  reader.detach();
  auto send = [&](const std::vector<json>& messages) {
    for (const auto& m : messages) lsp::write_message(out, m);
  };
  int code = 0;
  while (!s.disconnected) {
    std::optional<lsp::Frame> frame;
    {
      std::unique_lock lock(shared->m);
      if (!running(s)) shared->arrived.wait(lock, [&] { return !shared->frames.empty(); });
      if (!shared->frames.empty()) {
        frame = std::move(shared->frames.front());
        shared->frames.pop_front();
      }
    }
    if (!frame) {
      send(advance(s));
      continue;
    }
    if (frame->kind == lsp::Frame::Kind::End) {
      if (!frame->error.empty()) {
        log << "rcxc debug: " << frame->error << "\n";
        code = 1;
      }
      break;
    }
    if (frame->kind == lsp::Frame::Kind::BadHeader) {
      log << "rcxc debug: " << frame->error << "\n";
      send({output(s, "stderr", "rcxc debug: " + frame->error + "\n")});
      continue;
    }
    send(handle_text(s, frame->body));
  }
  return code;
}

}  // namespace rcxc::dap
