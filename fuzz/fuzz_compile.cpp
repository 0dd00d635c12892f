// Bytes as NQC source: the whole compiler at -O0 and -Os, then the image it
// produced runs on the emulator for a bounded virtual time. An accepted
// program the emulator refuses or faults on is a compiler bug, unless the
// source has `asm` (the one way to write arbitrary bytes): the target
// aborts so libFuzzer keeps the input.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "backend/compile.h"
#include "fuzz/fuzz_run.h"

namespace {

void compile_and_run(const std::string& text, rcxc::ir::OptLevel level) {
  rcxc::SourceManager sm;
  rcxc::Diagnostics diags;
  rcxc::ir::Log log;
  rcxc::frontend::Options options;
  auto out = rcxc::backend::compile_source("fuzz.nqc", text, options, level, sm, diags, log);
  for (const auto& d : diags.all()) (void)rcxc::render_text(d, sm);
  if (!out) return;
  auto outcome = rcxc::fuzz::run_bounded(out->image);
  if (text.find("asm") != std::string::npos) return;
  if (outcome.refused) {
    std::fprintf(stderr, "fuzz_compile: the emulator refuses the image: %s\n", outcome.refused->c_str());
    std::abort();
  }
  if (outcome.stop.kind == rcx::StopKind::Fault) {
    std::fprintf(stderr, "fuzz_compile: the compiled program faults: %s\n", outcome.stop.fault->message.c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  compile_and_run(text, rcxc::ir::OptLevel::O0);
  compile_and_run(text, rcxc::ir::OptLevel::Os);
  return 0;
}
