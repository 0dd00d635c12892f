#include "cli/program_loader.h"

#include "backend/compile.h"

namespace rcxc::cli {

CompileResult compile_file(const std::string& path, const CompileRequest& request, Diagnostics diags) {
  CompileResult r;
  r.diagnostics = std::move(diags);
  r.output = backend::compile_file(path, request.frontend, request.level, r.sources, r.diagnostics, r.log);
  if (r.diagnostics.has_errors()) r.output.reset();
  return r;
}

CompiledForTest compile_nqc_file(const std::string& path) {
  CompileResult r = compile_file(path, {});
  CompiledForTest t;
  if (r.output) t.image = std::move(r.output->image);
  for (const auto& d : r.diagnostics.all()) {
    if (d.severity == Severity::Note) continue;
    // Only diagnostics in the test file itself have lines a test can name.
    bool in_file = d.span.begin.valid() && r.sources.path(d.span.begin.file) == path;
    t.messages.push_back({d.severity == Severity::Error, in_file ? static_cast<int>(d.span.begin.line) : 0, d.message});
  }
  return t;
}

}  // namespace rcxc::cli
