// `rcxc test FILE...|DIR...`: semantic tests. Each .nqc file's `// @`
// directives (docs/testing.md) say what inputs it sees and what must
// happen; the program is compiled, run on the emulator, and checked.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "cli/commands.h"
#include "verify/external_nqc.h"
#include "cli/program_loader.h"
#include "verify/testspec.h"
#include "runtime/vm.h"

namespace rcxc::cli {
namespace {

namespace fs = std::filesystem;
using rcx::semtest::Failure;

struct TestOptions {
  std::vector<std::string> paths;
  std::string nqc;  // non-empty: compile with this nqc instead of rcxc
  bool verbose = false;
};

constexpr rcx::Micros kDefaultRunUs = 60'000'000;

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
      if (path.extension() != ".nqc") continue;
      auto target = it->status(target_ec);
      if (target_ec)
        problems.push_back(fmt::format("cannot read {}: {}", path.string(), target_ec.message()));
      else if (fs::is_regular_file(target))
        found.push_back(path.string());
    }
    if (ec) problems.push_back(fmt::format("cannot read folder {}: {}", dir.string(), ec.message()));
  }
}

// The .nqc files named, folders searched recursively, in a stable order.
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

Compiled compile(const TestOptions& o, const std::string& file) {
  if (!o.nqc.empty()) {
    auto r = rcx::semtest::compile_with_nqc(o.nqc, file);
    return {std::move(r.image), std::move(r.messages), std::move(r.failure)};
  }
  auto r = compile_nqc_file(file);
  return {std::move(r.image), std::move(r.messages), {}};
}

// Runs one test file; returns its failures (empty = pass).
std::vector<Failure> run_test(const TestOptions& o, const std::string& file, std::string& log) {
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
  Compiled c = compile(o, file);
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
  machine.run(spec.run_for_us.value_or(kDefaultRunUs));
  auto run_failures = rcx::semtest::check_run(spec, machine, *c.image);
  failures.insert(failures.end(), run_failures.begin(), run_failures.end());
  if (o.verbose || !failures.empty())
    log = fmt::format("    run stopped with '{}' at {} ms\n", rcx::to_string(machine.stop().kind),
                      machine.now_us() / rcx::kMicrosPerMs);
  return failures;
}

int run(const TestOptions& o) {
  std::vector<std::string> problems;
  auto files = collect(o.paths, problems);
  for (const auto& m : problems) std::cerr << "rcxc test: " << m << "\n";
  if (files.empty() && problems.empty()) std::cerr << "rcxc test: no .nqc files found\n";
  int passed = 0, failed = 0;
  for (const auto& file : files) {
    std::string log;
    auto failures = run_test(o, file, log);
    std::cout << (failures.empty() ? "PASS " : "FAIL ") << file << "\n";
    for (const auto& f : failures) {
      std::string where = f.line > 0 ? fmt::format("{}:{}: ", file, f.line) : file + ": ";
      std::cout << "  " << where << f.message << "\n";
    }
    std::cout << log;
    (failures.empty() ? passed : failed)++;
  }
  std::cout << fmt::format("{} passed, {} failed\n", passed, failed);
  return (failed == 0 && problems.empty() && !files.empty()) ? kExitOk : kExitFailure;
}

}  // namespace

void register_test(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("test", "Run semantic tests: .nqc programs with // @expect directives");
  auto o = std::make_shared<TestOptions>();
  cmd->add_option("PATHS", o->paths, ".nqc files, or folders to search for them")->required();
  auto use_nqc = std::make_shared<bool>(false);
  auto nqc_path = std::make_shared<std::string>("nqc");
  cmd->add_flag("--nqc", *use_nqc, "compile with nqc instead of rcxc, for comparison");
  cmd->add_option("--nqc-path", *nqc_path, "the nqc to use with --nqc (path or name; default: nqc on PATH)");
  cmd->add_flag("-v,--verbose", o->verbose, "say how every run ended");
  cmd->callback([&exit_code, o, use_nqc, nqc_path] {
    o->nqc = *use_nqc ? *nqc_path : std::string();
    exit_code = run(*o);
  });
}

}  // namespace rcxc::cli
