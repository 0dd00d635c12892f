// Helpers for frontend tests: run the frontend on text held in memory and
// look at the diagnostics in a compact "line:col: severity: message" form.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "frontend/frontend.h"

namespace rcxc::test {

struct FrontendRun {
  SourceManager sm;
  Diagnostics diags;
  std::optional<ast::Program> program;

  // Every diagnostic as "line:col: severity: message" (file left out).
  std::vector<std::string> brief() const {
    std::vector<std::string> out;
    for (const auto& d : diags.all())
      out.push_back(std::to_string(d.span.begin.line) + ":" + std::to_string(d.span.begin.column) + ": " +
                    std::string(severity_name(d.severity)) + ": " + d.message);
    return out;
  }
  std::string text() const {
    std::string s;
    for (const auto& d : diags.all()) s += render_text(d, sm);
    return s;
  }
};

// Runs the frontend on `text` (named "test.nqc") with the stdlib unless
// `no_stdlib`.
inline FrontendRun run_frontend(const std::string& text, bool no_stdlib = false,
                                frontend::Options options = {}) {
  FrontendRun r;
  options.no_stdlib = no_stdlib;
  r.program = frontend::parse_source("test.nqc", text, options, r.sm, r.diags);
  return r;
}

}  // namespace rcxc::test
