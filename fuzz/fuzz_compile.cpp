// Bytes as NQC source: the whole compiler at -O0, -O1, -O2 and -Os, then each
// image it produced runs on the emulator for a bounded virtual time. An
// accepted program the emulator refuses or faults on is a compiler bug,
// unless the source has `asm` (the one way to write arbitrary bytes): the
// target aborts so libFuzzer keeps the input. A program whose run depends
// on nothing outside it (one task; no timer, random, sensor, clock or
// message read) must also show at -O1 and -Os what it shows at -O0:
// outputs, sounds, display, messages, datalog and final globals, as
// `rcxc compare` judges them.
// A first line `//! -n -DNAME=VALUE -UNAME` sets the front end's options
// (the rest of the line is ignored), so the fuzzer reaches -n, -D and -U.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>
#include <sstream>
#include <string>

#include "backend/compile.h"
#include "backend/disasm.h"
#include "frontend/frontend.h"
#include "frontend/stdlib_cache.h"
#include "ir/lower.h"
#include "fuzz/fuzz_run.h"
#include "verify/compare.h"

namespace {

// Virtual time per instruction for the comparison: small against any
// Wait, so -O0's extra instructions barely move events in time.
constexpr rcx::Micros kCompareInstructionUs = 10;

// The options of a leading `//!` line (-I is left out: it reads folders).
rcxc::frontend::Options options_of(const std::string& text) {
  rcxc::frontend::Options options;
  if (text.rfind("//!", 0) != 0) return options;
  std::istringstream line(text.substr(3, text.find('\n') - 3));
  for (std::string word; line >> word;) {
    if (word == "-n") options.no_stdlib = true;
    if (word.size() > 2 && word.rfind("-U", 0) == 0) options.undefines.push_back(word.substr(2));
    if (word.size() > 2 && word.rfind("-D", 0) == 0) options.define(word.substr(2));
  }
  return options;
}

// The front end and lowering run once per input; each level compiles its
// own copy of the lowered program (the passes rewrite it). Every
// diagnostic is rendered, as the command line would.
struct Lowered {
  rcxc::SourceManager sm;
  rcxc::Diagnostics diags;
  std::optional<rcxc::ir::Program> program;
  std::set<std::string> globals;
};

// rcx.nqh read and parsed once for the whole run (a `//!` line with -D,
// -U or -n reads it again, as it must).
const rcxc::frontend::StdlibCache* stdlib() {
  static const auto cache = rcxc::frontend::make_stdlib_cache({});
  return cache.get();
}

void lower(const std::string& text, Lowered& out) {
  auto program = rcxc::frontend::parse_source("fuzz.nqc", text, options_of(text), stdlib(), out.sm, out.diags);
  if (program) {
    for (const auto& g : program->globals) out.globals.insert(g.name);
    out.program = rcxc::ir::lower(*program, out.diags);
  }
  for (const auto& d : out.diags.all()) (void)rcxc::render_text(d, out.sm);
}

std::optional<rcx::Image> compile_and_run(const std::string& text, const Lowered& lowered, rcxc::ir::OptLevel level) {
  if (!lowered.program) return std::nullopt;
  rcxc::Diagnostics diags = lowered.diags;
  rcxc::ir::Log log;
  auto out = rcxc::backend::compile(*lowered.program, level, diags, log);
  for (std::size_t i = lowered.diags.all().size(); i < diags.all().size(); ++i)
    (void)rcxc::render_text(diags.all()[i], lowered.sm);
  if (!out) return std::nullopt;
  auto outcome = rcxc::fuzz::run_bounded(out->image);
  if (text.find("asm") != std::string::npos) return std::nullopt;
  if (outcome.refused) {
    std::fprintf(stderr, "fuzz_compile: the emulator refuses the image: %s\n", outcome.refused->c_str());
    std::abort();
  }
  if (outcome.stop.kind == rcx::StopKind::Fault) {
    std::fprintf(stderr, "fuzz_compile: the compiled program faults: %s\n", outcome.stop.fault->message.c_str());
    std::abort();
  }
  return out->image;
}

// Whether the only task start is main's last instruction: main has ended
// when the task runs, so nothing runs beside it (the task runs in main's
// place at -Os, ir/tailstart.cpp).
bool only_main_ends_starting_a_task(const std::string& code) {
  auto start = code.find("start ");
  if (start == std::string::npos) return true;
  if (code.find("start ", start + 1) != std::string::npos) return false;
  auto gap = code.rfind("\n\n", start);
  auto section = gap == std::string::npos ? 0 : gap + 2;
  if (code.compare(section, 7, "task 0 ") != 0) return false;
  auto end = code.find('\n', start);
  return end == std::string::npos || end + 1 == code.size() || code[end + 1] == '\n';
}

// Whether the run can depend only on the program: judged on the -O0 code,
// where nothing the source reads has been optimised away.
bool self_contained(const rcx::Image& image) {
  std::string code = rcxc::backend::disassemble(image);
  for (const char* outside : {"timer[", "random(", "sensor[", "sensraw[", "sensbool[", "clock", "message", "stop "})
    if (code.find(outside) != std::string::npos) return false;
  return only_main_ends_starting_a_task(code);
}

rcx::Machine run_for_comparison(const rcx::Image& image) {
  rcx::Config config;
  config.instruction_cost_us = kCompareInstructionUs;
  rcx::Machine machine(config);
  machine.load(0, image);  // both images already ran: the loader takes them
  machine.start_program();
  machine.run(rcxc::fuzz::kRunLimitUs);
  return machine;
}

// The image with only the program's globals named: a slot named for a
// local may hold another variable at the other level once the local is
// dead, and what a dead local last held is no behaviour.
rcx::Image globals_named(rcx::Image image, const std::set<std::string>& globals) {
  std::erase_if(image.symbols, [&](const rcx::Symbol& s) {
    return s.type == rcx::SymbolType::Variable && globals.count(s.name) == 0;
  });
  return image;
}

// -O0's run, once for the three comparisons; none when it does not end
// within the limit (a run cut off by the time limit stops at a different
// point at each level, so nothing is compared). Running it again for each
// level, and the level's own run after an -O0 run that never ended, made a
// program looping for ever cost six runs of 200,000 instructions for no
// comparison (about 4 s under the sanitizers: fuzz_compile's one timeout in
// the seventeenth run, docs/fuzzing.md).
struct Baseline {
  rcx::Image image;
  rcx::Machine machine;
};

std::optional<Baseline> ended_baseline(const std::set<std::string>& globals, const rcx::Image& unoptimised_image) {
  rcx::Image image = globals_named(unoptimised_image, globals);
  rcx::Machine machine = run_for_comparison(image);
  if (machine.stop().kind != rcx::StopKind::Ended) return std::nullopt;
  return Baseline{std::move(image), std::move(machine)};
}

void compare_level(const std::set<std::string>& globals, const Baseline& unoptimised,
                   const rcx::Image& optimised_image, const char* level) {
  rcx::Image optimised = globals_named(optimised_image, globals);
  rcx::Machine b = run_for_comparison(optimised);
  if (b.stop().kind != rcx::StopKind::Ended) return;
  rcx::TimeTolerance tolerance{kCompareInstructionUs * 500, 0.005, kCompareInstructionUs * 5};
  auto c = rcx::compare_runs({&unoptimised.machine, &unoptimised.image, "-O0"}, {&b, &optimised, level}, tolerance);
  if (c.same) return;
  std::fprintf(stderr, "fuzz_compile: -O0 and %s differ: %s\n%s\n", level, c.differences.front().c_str(),
               c.side_by_side.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Lowered lowered;
  lower(text, lowered);
  auto unoptimised = compile_and_run(text, lowered, rcxc::ir::OptLevel::O0);
  auto o1 = compile_and_run(text, lowered, rcxc::ir::OptLevel::O1);
  auto o2 = compile_and_run(text, lowered, rcxc::ir::OptLevel::O2);
  auto os = compile_and_run(text, lowered, rcxc::ir::OptLevel::Os);
  if (!unoptimised || !self_contained(*unoptimised)) return 0;
  auto baseline = ended_baseline(lowered.globals, *unoptimised);
  if (!baseline) return 0;
  if (o1) compare_level(lowered.globals, *baseline, *o1, "-O1");
  if (o2) compare_level(lowered.globals, *baseline, *o2, "-O2");
  if (os) compare_level(lowered.globals, *baseline, *os, "-Os");
  return 0;
}
