// `rcxc run FILE`: runs a program on the emulator in virtual time and prints
// a timeline, or a JSON report, and optionally writes a trace file.
#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <variant>

#include "cli/commands.h"
#include "cli/nxt_tether.h"
#include "savefile/savefile.h"
#include "cli/program_loader.h"
#include "rcx/image.h"
#include "rcx/program_io.h"
#include "runtime/report.h"
#include "runtime/room.h"
#include "runtime/scenario.h"
#include "runtime/trace_svg.h"
#include "stdlib/stdlib.h"
#include "verify/testspec.h"
#include "runtime/vm.h"

namespace rcxc::cli {
namespace {

struct RunOptions {
  std::vector<std::string> files;      // one program, or several bricks in one room
  std::vector<std::string> scenarios;  // in the programs' order
  std::string file;                    // the one program (files[0]) ...
  std::string scenario;                // ... and its scenario
  std::int64_t for_ms = 60'000;
  bool for_given = false;
  std::uint64_t seed = 1;
  std::string report;
  std::string trace;
  std::int64_t instruction_us = rcx::kDefaultInstructionCostUs;
  CompilerArgs compiler;  // for a source FILE, as `rcxc compile` takes them
  std::optional<std::string> nxt_port;  // --nxt: tethered to an NXT, in real time
};

// The program on the emulator in real time, its outputs, sensors, sounds and
// messages an NXT's (cli/nxt_tether.h). 0, or the exit code of a failure.
int run_on_nxt(rcx::Machine& machine, const rcx::Image& image, const std::string& port, rcx::Micros run_us) {
  auto spec = nxt::parse_port(port, std::nullopt);
  if (auto* e = std::get_if<nxt::LinkError>(&spec)) {
    std::cerr << "rcxc run: " << e->message << "\n";
    return kExitUsage;
  }
  int stop = stop_signal_descriptor();
  auto opened = nxt::open_port(std::get<nxt::PortSpec>(spec), stop);
  if (auto* e = std::get_if<nxt::LinkError>(&opened)) {
    std::cerr << "rcxc run: " << e->message << "\n";
    if (stop >= 0) ::close(stop);
    return kExitNoPort;
  }
  auto transport = std::move(std::get<std::unique_ptr<nxt::Transport>>(opened));
  nxt::Client client(*transport);
  TetherOptions options;
  options.limit_us = run_us;
  options.stop_fd = stop;
  options.io = rcx::program_io(image);
  // Bytes that do not decode hide what they read: poll every sensor.
  if (!options.io.complete) options.io.sensors_read = {true, true, true};
  TetherStats stats;
  std::string error = run_tethered(machine, client, options, stats);
  if (stop >= 0) ::close(stop);
  for (const auto& note : stats.notes) std::cerr << "rcxc run: note: " << note << "\n";
  std::cerr << fmt::format("rcxc run: tethered to {}: {} writes, {} sensor reads (inputs 1-3: {}), {} message reads, "
                           "{} messages received, polls up to {} ms behind the {} ms grid\n",
                           transport->describe(), stats.writes, stats.polls, fmt::join(stats.polls_per_input, "/"),
                           stats.message_reads, stats.messages_received, stats.worst_poll_lag_us / 1000,
                           kTetherPollUs / 1000);
  if (!error.empty()) {
    std::cerr << "rcxc run: " << error << "\n";
    return error == "interrupted" ? 130 : kExitNoReply;
  }
  return kExitOk;
}

bool ends_with(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The trace formats, by the file's extension.
constexpr std::string_view kTraceExtensions[] = {".vcd", ".json", ".svg", ".html"};

bool known_trace_file(const std::string& path) {
  return std::any_of(std::begin(kTraceExtensions), std::end(kTraceExtensions),
                     [&](std::string_view ext) { return ends_with(path, ext); });
}

// Sounds, displays and sensor types as the standard library names them.
rcx::EventNames event_names() {
  rcx::EventNames names;
  for (const auto& [name, value] : stdlib::defined_numbers("SOUND_")) names.sounds.emplace(value, name);
  for (const auto& [name, value] : stdlib::defined_numbers("DISPLAY_")) names.displays.emplace(value, name);
  for (const auto& [name, value] : stdlib::defined_numbers("SENSOR_TYPE_")) names.sensor_types.emplace(value, name);
  return names;
}

std::string trace_text(const std::string& path, const rcx::Machine& machine, const rcx::Image& image,
                       const rcx::EventNames& names, const std::string& program) {
  if (ends_with(path, ".vcd")) return rcx::trace_vcd(machine, image);
  if (ends_with(path, ".svg")) return rcx::trace_svg(machine, image, names, program);
  if (ends_with(path, ".html")) return rcx::trace_html(machine, image, names, program);
  std::ostringstream json;
  rcx::write_trace_json(json, machine, image);
  json << "\n";
  return std::move(json).str();
}

// A program with test directives (docs/testing.md) carries its own inputs:
// without --scenario they drive the run, and @for sets the time limit unless
// --for is given, to the microsecond as `rcxc test` runs it ("@for 0.5ms" is
// half a millisecond, not none). Says so on stderr, so the timeline is never
// a surprise.
bool inputs_from_source(const RunOptions& o, const std::string& file, const rcx::semtest::Spec& spec,
                        std::vector<rcx::TimedInput>& inputs, std::optional<rcx::Micros>& run_for_us) {
  if (spec.inputs.empty() && spec.scenario_file.empty() && !spec.run_for_us) return true;
  auto gathered = rcx::semtest::all_inputs(spec, file);
  if (auto* error = std::get_if<std::string>(&gathered)) {
    std::cerr << "rcxc run: " << *error << "\n";
    return false;
  }
  inputs = std::get<std::vector<rcx::TimedInput>>(std::move(gathered));
  run_for_us = spec.run_for_us;
  if (o.nxt_port && !inputs.empty()) {
    // On an NXT the sensors, messages and battery are the brick's.
    inputs.clear();
    std::cerr << "rcxc run: --nxt: the inputs written in " << file
              << " are not used: the NXT's sensors and mailbox are the inputs (`rcxc nxt brick --pty --scenario "
              << file << "` replays them); @for sets the time limit\n";
    return true;
  }
  std::cerr << "rcxc run: using the inputs written in " << file << " (// @input, @for; --scenario overrides)\n";
  return true;
}

// A program ready to run: its image and the inputs that drive it.
struct Brick {
  std::string file;
  rcx::Image image;
  std::vector<rcx::TimedInput> inputs;
  std::optional<rcx::Micros> run_for_us;  // the source's // @for
};

// Compiles or reads `file` and gathers its inputs (`scenario`, else the
// source's own directives); or, after saying what is wrong, the exit code.
std::variant<Brick, int> prepare(const RunOptions& o, const std::string& file, const std::string& scenario) {
  // A test program's own directives: its @options compile it as `rcxc test`
  // does; its inputs drive the run unless --scenario is given. Bad
  // directives are `rcxc test`'s to report; a run goes on without them,
  // saying so (a misspelt @for would otherwise leave a minute-long run).
  std::optional<rcx::semtest::Spec> spec;
  if (is_nqc_source(file).value_or(false)) {
    auto parsed = rcx::semtest::parse_spec_file(file);
    if (auto* good = std::get_if<rcx::semtest::Spec>(&parsed)) {
      spec = std::move(*good);
    } else if (std::ranges::any_of(std::get<std::vector<rcx::semtest::SpecError>>(parsed),
                                   [](const rcx::semtest::SpecError& e) { return e.line > 0; })) {
      // Line 0 is the file itself (too large, unreadable): the compile
      // below says so, and there were no directives to blame.
      std::cerr << "rcxc run: note: the // @ directives in " << file
                << " have errors and are not used (rcxc test " << file << " names them)\n";
    }
  }
  // The @scenario file of the source is an input too, though --scenario
  // may stand in for it.
  std::string directive_scenario = spec ? rcx::semtest::scenario_path(*spec, file) : "";
  for (const std::string* input : {&file, &scenario, static_cast<const std::string*>(&directive_scenario)})
    if (!o.trace.empty() && !input->empty() && savefile::same_file(o.trace, *input)) {
      std::cerr << "rcxc run: refusing to write the trace to " << o.trace << ": it is the input " << *input
                << " (choose another name)\n";
      return kExitUsage;
    }
  CompilerArgs compiler = o.compiler;
  if (spec && !spec->options.empty()) {
    auto merged = with_file_options(o.compiler, spec->options, file);
    if (auto* e = std::get_if<std::string>(&merged)) {
      std::cerr << file << ":" << spec->options_line << ": error: " << *e << "\n";
      return kExitUsage;
    }
    compiler = std::get<CompilerArgs>(std::move(merged));
    std::cerr << "rcxc run: using the compiler options written in " << file << " (// @options)\n";
  }
  auto loaded = load_program(file, compile_request(compiler));
  if (auto* e = std::get_if<std::string>(&loaded)) {
    std::cerr << "rcxc run: " << *e << "\n";
    return kExitFailure;
  }
  if (auto note = unused_compiler_options(file, compiler)) std::cerr << "rcxc run: " << *note << "\n";
  Brick brick{file, std::get<rcx::Image>(std::move(loaded)), {}, std::nullopt};
  if (!scenario.empty()) {
    auto parsed = rcx::read_scenario_file(scenario);
    if (auto* e = std::get_if<rcx::ScenarioError>(&parsed)) {
      std::cerr << "rcxc run: " << e->message << "\n";
      return kExitFailure;
    }
    brick.inputs = std::get<std::vector<rcx::TimedInput>>(std::move(parsed));
    // Accepted (`--scenario /dev/null` leaves a source's own inputs out), but
    // an empty file given by mistake should not pass for a run with inputs.
    if (brick.inputs.empty())
      std::cerr << "rcxc run: note: " << scenario << " holds no [[input]] tables: the run has no inputs\n";
  } else if (spec && !inputs_from_source(o, file, *spec, brick.inputs, brick.run_for_us)) {
    return kExitFailure;
  }
  return brick;
}

rcx::Config machine_config(const RunOptions& o) {
  rcx::Config config;
  config.seed = o.seed;
  config.instruction_cost_us = o.instruction_us;
  config.trace_variables = ends_with(o.trace, ".vcd");
  return config;
}

// Loads the brick's program into slot 1 and starts it; false after saying
// why it cannot run.
bool load_and_start(rcx::Machine& machine, const Brick& brick) {
  if (auto error = machine.load(0, brick.image)) {
    std::cerr << "rcxc run: " << brick.file << ": " << *error << "\n";
    return false;
  }
  if (!brick.image.find(rcx::FragmentType::Task, 0))
    std::cerr << "rcxc run: warning: " << brick.file << " has no task 0 to start\n";
  for (const auto& in : brick.inputs) machine.schedule(in);
  machine.start_program();
  return true;
}

// The end of a run as the exit code says it (a fault, events past the limit).
int run_exit_code(const RunOptions& o, const rcx::Machine& machine, const std::string& who) {
  if (machine.stop().kind == rcx::StopKind::Fault) {
    if (o.report == "json" || !who.empty())
      std::cerr << "rcxc run: " << (who.empty() ? "the program" : who) << " faulted: " << machine.stop().fault->message
                << "\n";
    return kExitFailure;
  }
  if (machine.stop().kind == rcx::StopKind::EventLimit) {
    std::cerr << "rcxc run: " << (who.empty() ? "" : who + ": ") << "the run stopped at "
              << machine.now_us() / rcx::kMicrosPerMs << " ms, before the time asked for: "
              << rcx::event_limit_reason(machine) << "; ask for less with --for\n";
    return kExitFailure;
  }
  return kExitOk;
}

int run(const RunOptions& o) {
  if (!o.trace.empty() && !known_trace_file(o.trace)) {
    std::cerr << "rcxc run: --trace file must end in .vcd, .json, .svg or .html: " << o.trace << "\n";
    return kExitUsage;
  }
  // Said before the run, which may take minutes of virtual time.
  if (auto unwritable = o.trace.empty() ? std::nullopt : savefile::check_writable(o.trace)) {
    std::cerr << "rcxc run: cannot write trace file " << o.trace << ": " << *unwritable << "\n";
    return kExitFailure;
  }
  if (auto bad = bad_compiler_arguments(o.compiler)) {
    std::cerr << "rcxc run: " << *bad << "\n";
    return kExitUsage;
  }
  if (o.nxt_port && !o.scenario.empty()) {
    std::cerr << "rcxc run: --scenario and --nxt do not go together: on an NXT the sensors, messages and battery "
                 "come from the brick (give the scenario to the virtual NXT: rcxc nxt brick --pty --scenario "
              << o.scenario << ")\n";
    return kExitUsage;
  }
  auto prepared = prepare(o, o.file, o.scenario);
  if (auto* code = std::get_if<int>(&prepared)) return *code;
  const Brick& brick = std::get<Brick>(prepared);
  const rcx::Image& image = brick.image;
  rcx::Micros run_us = o.for_given || !brick.run_for_us ? o.for_ms * rcx::kMicrosPerMs : *brick.run_for_us;
  rcx::Machine machine(machine_config(o));
  if (!load_and_start(machine, brick)) return kExitFailure;
  int tether_code = kExitOk;
  if (o.nxt_port) {
    tether_code = run_on_nxt(machine, image, *o.nxt_port, run_us);
    // Without a port nothing ran: a timeline of time 0 would read as a run.
    if (tether_code == kExitNoPort || tether_code == kExitUsage) return tether_code;
  } else {
    machine.run(run_us);
  }

  rcx::EventNames names = event_names();
  if (o.report == "json") {
    rcx::write_report_json(std::cout, machine, image);
    std::cout << "\n";
  } else
    std::cout << rcx::timeline_text(machine, image, names);
  if (!o.trace.empty()) {
    std::string program = std::filesystem::path(o.file).filename().string();
    std::string text = trace_text(o.trace, machine, image, names, program);
    if (auto unwritten = savefile::write_file_atomically(o.trace, text)) {
      std::cerr << "rcxc run: cannot write trace file " << o.trace << ": " << *unwritten << "\n";
      return kExitFailure;
    }
  }
  if (tether_code != kExitOk) return tether_code;
  return run_exit_code(o, machine, "");
}

// Several programs, one brick each, in one room: what one sends by infrared
// the others receive (runtime/room.h).
int run_room(const RunOptions& o) {
  constexpr std::size_t kMostBricks = 8;
  if (o.files.size() > kMostBricks) {
    std::cerr << "rcxc run: " << o.files.size() << " programs: a room holds at most " << kMostBricks << " bricks\n";
    return kExitUsage;
  }
  if (std::ranges::count(o.files, std::string("-")) > 1) {
    std::cerr << "rcxc run: '-' given more than once: the standard input holds one program\n";
    return kExitUsage;
  }
  if (o.scenarios.size() > o.files.size()) {
    std::cerr << "rcxc run: " << o.scenarios.size() << " scenarios for " << o.files.size()
              << " programs: give at most one --scenario per program, in the programs' order\n";
    return kExitUsage;
  }
  if (!o.trace.empty() && !ends_with(o.trace, ".html")) {
    std::cerr << "rcxc run: a room's trace is an HTML page, a drawing per brick on one time axis: --trace F.html ("
              << o.trace << " names another format, which draws one brick)\n";
    return kExitUsage;
  }
  if (auto unwritable = o.trace.empty() ? std::nullopt : savefile::check_writable(o.trace)) {
    std::cerr << "rcxc run: cannot write trace file " << o.trace << ": " << *unwritable << "\n";
    return kExitFailure;
  }
  if (o.nxt_port) {
    std::cerr << "rcxc run: --nxt drives one NXT with one program, not " << o.files.size() << "\n";
    return kExitUsage;
  }
  if (auto bad = bad_compiler_arguments(o.compiler)) {
    std::cerr << "rcxc run: " << *bad << "\n";
    return kExitUsage;
  }
  std::vector<Brick> bricks;
  for (std::size_t i = 0; i < o.files.size(); ++i) {
    auto prepared = prepare(o, o.files[i], i < o.scenarios.size() ? o.scenarios[i] : "");
    if (auto* code = std::get_if<int>(&prepared)) return *code;
    bricks.push_back(std::get<Brick>(std::move(prepared)));
  }
  // --for, else the longest // @for of the programs, else a minute.
  rcx::Micros run_us = o.for_ms * rcx::kMicrosPerMs;
  if (!o.for_given) {
    std::optional<rcx::Micros> longest;
    for (const Brick& b : bricks)
      if (b.run_for_us) longest = std::max(longest.value_or(0), *b.run_for_us);
    if (longest) run_us = *longest;
  }
  std::vector<std::unique_ptr<rcx::Machine>> machines;
  std::vector<rcx::Machine*> room;
  std::vector<rcx::RoomBrick> shown;
  for (std::size_t i = 0; i < bricks.size(); ++i) {
    rcx::Config config = machine_config(o);
    // Each brick's own random numbers, as two real bricks have.
    config.seed = o.seed + i;
    machines.push_back(std::make_unique<rcx::Machine>(config));
    if (!load_and_start(*machines.back(), bricks[i])) return kExitFailure;
    room.push_back(machines.back().get());
    shown.push_back({machines.back().get(), &bricks[i].image,
                     fmt::format("{} {}", i + 1,
                                 bricks[i].file == "-" ? "stdin" : std::filesystem::path(bricks[i].file).stem().string())});
  }
  auto sent = rcx::run_room(room, run_us);
  if (o.report == "json")
    std::cout << rcx::room_report_json(shown, sent).dump(2) << "\n";
  else
    std::cout << rcx::room_timeline_text(shown, sent, event_names());
  if (!o.trace.empty()) {
    std::string title;
    for (const Brick& b : bricks) title += (title.empty() ? "" : " + ") + std::filesystem::path(b.file).filename().string();
    if (auto unwritten = savefile::write_file_atomically(o.trace, rcx::trace_html_room(shown, event_names(), title))) {
      std::cerr << "rcxc run: cannot write trace file " << o.trace << ": " << *unwritten << "\n";
      return kExitFailure;
    }
  }
  int code = kExitOk;
  for (const rcx::RoomBrick& b : shown)
    if (int c = run_exit_code(o, *b.machine, "brick " + b.label); c != kExitOk) code = c;
  return code;
}

}  // namespace

void register_run(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("run", "Run a program on the RCX emulator in virtual time");
  auto o = std::make_shared<RunOptions>();
  cmd->add_option("FILE", o->files,
                  ".rcx image or NQC source (compiled in memory); several: one brick each, in one room, "
                  "their IR messages reaching each other")
      ->required()
      ->check(not_empty());
  add_compiler_options(cmd, o->compiler);
  cmd->add_option("--scenario", o->scenarios,
                  "TOML file of timed inputs ([[input]] tables); with several programs one each, in their order")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(not_empty());
  cmd->add_option("--for", o->for_ms, "virtual time limit in ms (default 60000, or the source's // @for)")
      ->check(in_range(1, kLongestRunMs, "ms"));
  cmd->add_option("--seed", o->seed, "seed of the random source (default 1)")->check(whole_number());
  cmd->add_option("--report", o->report, "print a report instead of the timeline: json")->check(CLI::IsMember({"json"}));
  cmd->add_option("--trace", o->trace,
                  "write a trace: F.vcd (GTKWave), F.json (events), F.svg or F.html (the run drawn as a timeline)")
      ->check(not_empty());
  cmd->add_option("--instruction-us", o->instruction_us, "virtual cost of one instruction in microseconds (default 2000)")
      ->check(in_range(1, 1'000'000));
  cmd->add_option("--nxt", o->nxt_port,
                  "run in real time with an NXT's motors, sensors and speaker (usb, bt:ADDR, a tty; docs/nxt.md)")
      ->check(not_empty());
  auto* for_option = cmd->get_option("--for");
  cmd->callback([&exit_code, o, for_option] {
    o->for_given = for_option->count() > 0;
    if (o->files.size() > 1) {
      exit_code = run_room(*o);
      return;
    }
    if (o->scenarios.size() > 1) {
      std::cerr << "rcxc run: " << o->scenarios.size() << " scenarios for one program: give one --scenario\n";
      exit_code = kExitUsage;
      return;
    }
    o->file = o->files.front();
    o->scenario = o->scenarios.empty() ? "" : o->scenarios.front();
    exit_code = run(*o);
  });
}

}  // namespace rcxc::cli
