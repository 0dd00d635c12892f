// Bytes as NQC source: the whole compiler at -O0 and -Os, then the image it
// produced runs on the emulator for a bounded virtual time.
#include <cstddef>
#include <cstdint>
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
  if (out) rcxc::fuzz::run_bounded(out->image);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  compile_and_run(text, rcxc::ir::OptLevel::O0);
  compile_and_run(text, rcxc::ir::OptLevel::Os);
  return 0;
}
