// Bytes as an `rcxc test` file: its `@` directives are parsed, the program
// compiled, its inputs scheduled and the run checked against every
// expectation, as `rcxc test` does, in memory (no file is read or written:
// a test naming a @scenario file is taken only as far as its directives).
// Everything must end with failures or a pass, never a crash; the run is
// cut at a bounded virtual time whatever `@for` asks. `@options` -O0/-O1/
// -O2/-Os and -n pick the level and the stdlib.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "backend/compile.h"
#include "frontend/frontend.h"
#include "frontend/stdlib_cache.h"
#include "ir/lower.h"
#include "fuzz/fuzz_run.h"
#include "runtime/vm.h"
#include "verify/testspec.h"

namespace {

namespace semtest = rcx::semtest;

// The level and front-end options of the spec's @options words that need
// no folder (-I would read the machine's folders).
rcxc::ir::OptLevel options_of(const semtest::Spec& spec, rcxc::frontend::Options& options) {
  rcxc::ir::OptLevel level = rcxc::ir::OptLevel::O2;
  for (const auto& w : spec.options) {
    if (w == "-n") options.no_stdlib = true;
    if (w == "-O0") level = rcxc::ir::OptLevel::O0;
    if (w == "-O1") level = rcxc::ir::OptLevel::O1;
    if (w == "-O2") level = rcxc::ir::OptLevel::O2;
    if (w == "-Os") level = rcxc::ir::OptLevel::Os;
    if (w.size() > 2 && w.rfind("-D", 0) == 0) options.define(w.substr(2));
    if (w.size() > 2 && w.rfind("-U", 0) == 0) options.undefines.push_back(w.substr(2));
  }
  return level;
}

// rcx.nqh read and parsed once for the whole run.
const rcxc::frontend::StdlibCache* stdlib() {
  static const auto cache = rcxc::frontend::make_stdlib_cache({});
  return cache.get();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto parsed = semtest::parse_spec(text);
  if (std::holds_alternative<std::vector<semtest::SpecError>>(parsed)) return 0;
  const auto& spec = std::get<semtest::Spec>(parsed);
  if (!spec.scenario_file.empty()) return 0;

  rcxc::frontend::Options options;
  rcxc::ir::OptLevel level = options_of(spec, options);
  rcxc::SourceManager sm;
  rcxc::Diagnostics diags;
  rcxc::ir::Log log;
  std::optional<rcxc::backend::Output> out;
  if (auto program = rcxc::frontend::parse_source("test.nqc", text, options, stdlib(), sm, diags))
    if (auto lowered = rcxc::ir::lower(*program, diags)) out = rcxc::backend::compile(std::move(*lowered), level, diags, log);
  std::vector<semtest::CompilerMessage> messages;
  for (const auto& d : diags.all()) {
    if (d.severity == rcxc::Severity::Note) continue;
    bool in_file = d.span.begin.valid() && d.span.begin.file < sm.size() && sm.path(d.span.begin.file) == "test.nqc";
    messages.push_back({d.severity == rcxc::Severity::Error, in_file ? static_cast<int>(d.span.begin.line) : 0,
                        d.message});
  }
  auto failures = semtest::check_diagnostics(spec, messages);
  if (!out || spec.expects_compile_error()) return 0;

  rcx::Config config;
  config.seed = spec.seed;
  rcx::Machine machine(config);
  if (machine.load(0, out->image)) return 0;
  for (const auto& input : spec.inputs) machine.schedule(input);
  machine.start_program();
  machine.run(std::min(spec.run_for_us.value_or(rcxc::fuzz::kRunLimitUs), rcxc::fuzz::kRunLimitUs));
  auto run_failures = semtest::check_run(spec, machine, out->image);
  failures.insert(failures.end(), run_failures.begin(), run_failures.end());
  // Every failure says what went wrong.
  for (const auto& f : failures)
    if (f.message.empty()) __builtin_trap();
  return 0;
}
