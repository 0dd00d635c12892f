// `rcxc test FILE...|DIR...`: semantic tests. Each .nqc file's `// @`
// directives (docs/testing.md) say what inputs it sees and what must
// happen; the program is compiled, run on the emulator, and checked.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "cli/commands.h"
#include "cli/large_stack.h"
#include "savefile/savefile.h"
#include "verify/external_nqc.h"
#include "cli/program_loader.h"
#include "rcx/file_read.h"
#include "verify/junit.h"
#include "verify/testspec.h"
#include "runtime/room.h"
#include "runtime/vm.h"

namespace rcxc::cli {
namespace {

namespace fs = std::filesystem;
using rcx::semtest::Failure;

struct TestOptions {
  std::vector<std::string> paths;
  std::string nqc;  // non-empty: compile with this nqc instead of rcxc
  bool verbose = false;
  CompilerArgs compiler;  // for every file; a file's @options add to them
  unsigned jobs = 0;  // tests run at once; 0: one per core
  std::string junit;  // non-empty: also write a JUnit XML report there
};

constexpr rcx::Micros kDefaultRunUs = 60'000'000;

bool has_nqc_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".nqc";
}

// The .nqc files under `folder`, searched with a work list of folders.
// Links to folders are not followed (a link loop cannot trap the search);
// a folder or link that cannot be read is added to `problems` and the
// search goes on with the rest.
void search_folder(const fs::path& folder, std::vector<std::string>& found, std::vector<std::string>& problems) {
  std::vector<fs::path> pending{folder};
  while (!pending.empty()) {
    fs::path dir = std::move(pending.back());
    pending.pop_back();
    std::error_code ec;
    fs::directory_iterator it(dir, ec);
    for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
      const fs::path& path = it->path();
      std::error_code link_ec, target_ec;
      auto link = it->symlink_status(link_ec);
      if (!link_ec && fs::is_directory(link)) {
        pending.push_back(path);
        continue;
      }
      if (!has_nqc_extension(path)) continue;
      auto target = it->status(target_ec);
      if (target_ec)
        problems.push_back(fmt::format("cannot read {}: {}", path.string(), rcx::cannot_open_reason(path.string())));
      else if (fs::is_regular_file(target))
        found.push_back(path.string());
      // A pipe or device named .nqc was passed over without a word, where
      // one named on the command line is refused: the count of tests run
      // then hid a file that never was.
      else if (auto special = special_file_problem(path.string(), Takes::Files, "rcxc test reads .nqc test files"))
        problems.push_back(*special);
    }
    if (ec) problems.push_back(fmt::format("cannot read folder {}: {}", dir.string(), ec.message()));
  }
}

// The files named and the .nqc files (any case: FOO.NQC) in the folders
// named, searched recursively, in a stable order.
std::vector<std::string> collect(const std::vector<std::string>& paths, std::vector<std::string>& problems) {
  std::vector<std::string> files;
  for (const auto& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<std::string> found;
      search_folder(p, found, problems);
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p, ec)) {
      files.push_back(p);
    } else if (p == frontend::kStandardInput) {
      // A test names its @scenario and @options folders relative to itself.
      problems.push_back("'-': rcxc test reads test files, not the standard input (save the program to a file)");
    } else if (auto special = special_file_problem(p, Takes::FilesAndFolders, "rcxc test reads .nqc test files")) {
      problems.push_back(*special);
    } else if (fs::exists(fs::symlink_status(p, ec))) {
      // The name is there but leads nowhere: a link to nothing, or a loop.
      problems.push_back(fmt::format("cannot read {}: {}", p, rcx::cannot_open_reason(p)));
    } else {
      problems.push_back("no such file or folder: " + p);
    }
  }
  return files;
}

struct Compiled {
  std::optional<rcx::Image> image;
  std::vector<rcx::semtest::CompilerMessage> messages;
  std::string failure;  // could not compile for a reason that is not the program's
};

Compiled compile(const TestOptions& o, const std::string& file, const CompilerArgs& args,
                 const rcx::semtest::Spec& spec) {
  if (!o.nqc.empty()) {
    auto r = rcx::semtest::compile_with_nqc(o.nqc, file, nqc_arguments(args));
    return {std::move(r.image), std::move(r.messages), std::move(r.failure)};
  }
  CompileRequest request = compile_request(args);
  // Task expectations hold at every level: a tail-started task (-Os) would
  // run inside main and never start (docs/testing.md).
  request.passes.tail_starts = !spec.expects_task_events();
  auto r = compile_nqc_file(file, request);
  return {std::move(r.image), std::move(r.messages), {}};
}

// The program of an `@brick FILE` line, compiled as the test is (its own
// @options added), loaded and started with its own @input lines and
// @scenario as its inputs; or why it cannot run, at the @brick line.
std::variant<std::unique_ptr<rcx::Machine>, Failure> start_other_brick(const TestOptions& o,
                                                                       const rcx::semtest::OtherBrick& brick,
                                                                       const std::string& test_file,
                                                                       const rcx::Config& config) {
  const std::string path = rcx::semtest::brick_path(brick, test_file);
  auto fail = [&](const std::string& why) { return Failure{brick.line, "@brick " + brick.file + ": " + why}; };
  if (!is_nqc_source(path).has_value()) {
    // A folder or a device: in `rcxc run`'s words, which name what it is
    // ("it could not be read" does not). Never "-": a test reads no input.
    if (auto special = special_file_problem(path, Takes::Files, "give an NQC source file or an .rcx image"))
      return fail(*special);
    std::error_code ec;
    if (path != "-" && std::filesystem::is_directory(path, ec)) {
      auto loaded = load_program(path, {});
      if (auto* error = std::get_if<std::string>(&loaded)) return fail(*error);
    }
    return fail("cannot read " + path + ": " + rcx::cannot_open_reason(path));
  }
  rcx::semtest::Spec own;
  if (*is_nqc_source(path)) {
    auto parsed = rcx::semtest::parse_spec_file(path);
    if (auto* errors = std::get_if<std::vector<rcx::semtest::SpecError>>(&parsed))
      return fail(fmt::format("line {}: bad directive: {}", errors->front().line, errors->front().message));
    own = std::get<rcx::semtest::Spec>(std::move(parsed));
  }
  auto args = with_file_options(o.compiler, own.options, path);
  if (auto* error = std::get_if<std::string>(&args)) return fail(*error);
  std::optional<rcx::Image> image;
  if (*is_nqc_source(path)) {
    Compiled c = compile(o, path, std::get<CompilerArgs>(args), own);
    if (!c.failure.empty()) return fail(c.failure);
    if (!c.image) {
      auto error = std::ranges::find_if(c.messages, [](const auto& m) { return m.error; });
      return fail("does not compile" + (error == c.messages.end() ? std::string() : fmt::format(": line {}: {}", error->line, error->message)));
    }
    image = std::move(c.image);
  } else {
    auto loaded = load_program(path, compile_request(std::get<CompilerArgs>(args)));
    if (auto* error = std::get_if<std::string>(&loaded)) return fail(*error);
    image = std::get<rcx::Image>(std::move(loaded));
  }
  auto inputs = rcx::semtest::all_inputs(own, path);
  if (auto* error = std::get_if<std::string>(&inputs)) return fail(*error);
  auto machine = std::make_unique<rcx::Machine>(config);
  if (auto error = machine->load(0, *image)) return fail("cannot load the program: " + *error);
  for (const auto& input : std::get<std::vector<rcx::TimedInput>>(inputs)) machine->schedule(input);
  machine->start_program();
  return machine;
}

// Runs one test file; returns its failures (empty = pass).
std::vector<Failure> run_test(const TestOptions& o, const std::string& file, std::string& log) {
  if (is_nqc_source(file) == false) return {{0, non_source_kind(file) + ", not an NQC test program"}};
  auto parsed = rcx::semtest::parse_spec_file(file);
  if (auto* errors = std::get_if<std::vector<rcx::semtest::SpecError>>(&parsed)) {
    std::vector<Failure> out;
    for (const auto& e : *errors) out.push_back({e.line, e.line > 0 ? "bad directive: " + e.message : e.message});
    return out;
  }
  const auto& spec = std::get<rcx::semtest::Spec>(parsed);
  auto gathered = rcx::semtest::all_inputs(spec, file);
  if (auto* error = std::get_if<std::string>(&gathered)) return {{0, *error}};
  const auto& inputs = std::get<std::vector<rcx::TimedInput>>(gathered);
  if (!o.nqc.empty() && spec.nqc_differs) {
    log = "    skipped: marked @nqc-differs\n";
    return {};
  }
  auto args = with_file_options(o.compiler, spec.options, file);
  if (auto* error = std::get_if<std::string>(&args)) return {{spec.options_line, *error}};
  Compiled c = compile(o, file, std::get<CompilerArgs>(args), spec);
  if (!c.failure.empty()) return {{0, c.failure}};
  std::vector<Failure> failures = rcx::semtest::check_diagnostics(spec, c.messages);
  if (!c.image || spec.expects_compile_error()) {
    if (c.image && spec.expects_compile_error()) failures.push_back({0, "the program compiled"});
    return failures;
  }

  rcx::Config config;
  config.seed = spec.seed;
  rcx::Machine machine(config);
  if (auto error = machine.load(0, *c.image)) {
    failures.push_back({0, "cannot load the program: " + *error});
    return failures;
  }
  for (const auto& input : inputs) machine.schedule(input);
  machine.start_program();
  const rcx::Micros run_us = spec.run_for_us.value_or(kDefaultRunUs);
  if (spec.bricks.empty()) {
    machine.run(run_us);
  } else {
    std::vector<std::unique_ptr<rcx::Machine>> others;
    for (std::size_t i = 0; i < spec.bricks.size(); ++i) {
      rcx::Config other_config = config;
      other_config.seed = spec.seed + i + 1;  // as `rcxc run`'s brick i + 2
      auto other = start_other_brick(o, spec.bricks[i], file, other_config);
      if (auto* failure = std::get_if<Failure>(&other)) {
        failures.push_back(*failure);
        return failures;
      }
      others.push_back(std::get<std::unique_ptr<rcx::Machine>>(std::move(other)));
    }
    std::vector<rcx::Machine*> room{&machine};
    for (auto& other : others) room.push_back(other.get());
    rcx::run_room(room, run_us);
    // The expectations are about this test's brick, but a room whose other
    // brick broke down is not the room the test describes: without this a
    // fault there reads as "no matching event" here, or passes unseen.
    for (std::size_t i = 0; i < others.size(); ++i) {
      const rcx::StopInfo& stop = others[i]->stop();
      if (stop.kind == rcx::StopKind::Fault)
        failures.push_back({spec.bricks[i].line, fmt::format("@brick {}: its program faulted at {} ms: {}",
                                                             spec.bricks[i].file, others[i]->now_us() / rcx::kMicrosPerMs,
                                                             stop.fault->message)});
      else if (stop.kind == rcx::StopKind::EventLimit)
        failures.push_back({spec.bricks[i].line, fmt::format("@brick {}: its run stopped at {} ms: {}",
                                                             spec.bricks[i].file, others[i]->now_us() / rcx::kMicrosPerMs,
                                                             rcx::event_limit_reason(*others[i]))});
    }
  }
  auto run_failures = rcx::semtest::check_run(spec, machine, *c.image);
  failures.insert(failures.end(), run_failures.begin(), run_failures.end());
  if (o.verbose || !failures.empty())
    log = fmt::format("    run stopped with '{}' at {} ms\n", rcx::to_string(machine.stop().kind),
                      machine.now_us() / rcx::kMicrosPerMs);
  return failures;
}

struct TestResult {
  std::vector<Failure> failures;
  std::string log;
  double seconds = 0;  // compiling and running it (a report's time)
};

TestResult run_one(const TestOptions& o, const std::string& file) {
  TestResult r;
  auto start = std::chrono::steady_clock::now();
  try {
    r.failures = run_test(o, file, r.log);
  } catch (const std::exception& e) {
    // A bug or an exhausted machine: this test fails, the others still run.
    r.failures = {{0, std::string("internal error: ") + e.what()}};
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

// Runs the tests on `jobs` threads; `report(i, result)` is called for every
// file in the order of `files`, as soon as it and all before it are done,
// so the output is the same whatever the number of jobs.
void run_all(const TestOptions& o, const std::vector<std::string>& files, unsigned jobs,
             const std::function<void(std::size_t, const TestResult&)>& report) {
  std::vector<std::optional<TestResult>> results(files.size());
  std::mutex mutex;
  std::condition_variable done;
  std::size_t next = 0;
  auto work = [&] {
    for (;;) {
      std::size_t i;
      {
        std::lock_guard lock(mutex);
        if (next == files.size()) return;
        i = next++;
      }
      TestResult r = run_one(o, files[i]);
      std::lock_guard lock(mutex);
      results[i] = std::move(r);
      done.notify_one();
    }
  };
  std::vector<std::jthread> workers;
  // Each worker compiles as deeply as rcxc's main thread may (large_stack.h).
  for (unsigned k = 0; k < std::min<std::size_t>(jobs, files.size()); ++k)
    workers.emplace_back([&] { run_with_stack(kWorkStackBytes, work); });
  for (std::size_t i = 0; i < files.size(); ++i) {
    std::unique_lock lock(mutex);
    done.wait(lock, [&] { return results[i].has_value(); });
    TestResult r = std::move(*results[i]);
    results[i].reset();
    lock.unlock();
    report(i, r);
  }
}

// What a report at `junit` would overwrite among the tests' inputs: a test
// program or a test's @scenario file ("the test program FILE"), or nullopt.
std::optional<std::string> report_over_input(const std::string& junit, const std::vector<std::string>& files) {
  if (junit.empty()) return std::nullopt;
  for (const auto& file : files) {
    if (savefile::same_file(junit, file)) return "the test program " + file;
    auto parsed = rcx::semtest::parse_spec_file(file);
    auto* spec = std::get_if<rcx::semtest::Spec>(&parsed);
    std::string scenario = spec ? rcx::semtest::scenario_path(*spec, file) : "";
    if (!scenario.empty() && savefile::same_file(junit, scenario)) return "the scenario " + scenario + " of " + file;
  }
  return std::nullopt;
}

int run(const TestOptions& o) {
  std::vector<std::string> problems;
  auto files = collect(o.paths, problems);
  if (auto input = report_over_input(o.junit, files)) {
    std::cerr << "rcxc test: refusing to write the report to " << o.junit << ": it is " << *input
              << " (choose another name)\n";
    return kExitUsage;
  }
  // Said before the tests run: a class's thousand programs took their time
  // and then the report was lost ("Is a directory").
  if (auto unwritable = o.junit.empty() ? std::nullopt : savefile::check_writable(o.junit)) {
    std::cerr << "rcxc test: cannot write the report " << o.junit << ": " << *unwritable << "\n";
    return kExitFailure;
  }
  for (const auto& m : problems) std::cerr << "rcxc test: " << m << "\n";
  if (files.empty() && problems.empty()) std::cerr << "rcxc test: no .nqc files found\n";
  std::vector<rcx::semtest::JUnitCase> report;
  for (const auto& m : problems) report.push_back({m, {}, 0, m});
  int passed = 0, failed = 0;
  unsigned jobs = o.jobs > 0 ? o.jobs : std::max(1u, std::thread::hardware_concurrency());
  run_all(o, files, jobs, [&](std::size_t i, const TestResult& r) {
    const std::string& file = files[i];
    std::cout << (r.failures.empty() ? "PASS " : "FAIL ") << file << "\n";
    for (const auto& f : r.failures) {
      // The compiler's form, so editors' error matchers find the line.
      std::string where = f.line > 0 ? fmt::format("{}:{}: ", file, f.line) : file + ": ";
      std::cout << where << "error: " << f.message << "\n";
    }
    std::cout << r.log << std::flush;
    (r.failures.empty() ? passed : failed)++;
    if (!o.junit.empty()) report.push_back({file, r.failures, r.seconds, {}});
  });
  std::cout << fmt::format("{} passed, {} failed\n", passed, failed);
  auto unwritten = o.junit.empty() ? std::nullopt : savefile::write_file_atomically(o.junit, rcx::semtest::junit_xml(report));
  if (unwritten) {
    std::cerr << "rcxc test: cannot write the report " << o.junit << ": " << *unwritten << "\n";
    return kExitFailure;
  }
  return (failed == 0 && problems.empty() && !files.empty()) ? kExitOk : kExitFailure;
}

}  // namespace

void register_test(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("test", "Run semantic tests: .nqc programs with // @expect directives");
  auto o = std::make_shared<TestOptions>();
  cmd->add_option("PATHS", o->paths, "NQC test programs, or folders to search for .nqc files")
      ->required()
      ->check(not_empty());
  add_compiler_options(cmd, o->compiler);
  auto use_nqc = std::make_shared<bool>(false);
  auto nqc_path = std::make_shared<std::string>("nqc");
  auto* nqc_flag = cmd->add_flag("--nqc", *use_nqc, "compile with nqc instead of rcxc, for comparison");
  // Alone it would be taken and ignored: the tests would run on rcxc's code.
  cmd->add_option("--nqc-path", *nqc_path, "the nqc to use with --nqc (path or name; default: nqc on PATH)")
      ->check(not_empty())
      ->needs(nqc_flag);
  cmd->add_flag("-v,--verbose", o->verbose, "say how every run ended");
  cmd->add_option("--junit", o->junit, "also write the results to FILE as a JUnit XML report (for CI and grading)")
      ->check(not_empty());
  cmd->add_option("-j,--jobs", o->jobs, "tests run at once (default: the number of cores); the output order is the same")
      ->check(in_range(1, 1024).description(""));
  cmd->callback([&exit_code, o, use_nqc, nqc_path] {
    if (auto bad = bad_compiler_arguments(o->compiler)) {
      std::cerr << "rcxc test: " << *bad << "\n";
      exit_code = kExitUsage;
      return;
    }
    o->nqc = *use_nqc ? *nqc_path : std::string();
    exit_code = run(*o);
  });
}

}  // namespace rcxc::cli
