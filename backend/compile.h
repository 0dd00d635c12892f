// The compiler's back half in one call: IR passes, slot allocation, code
// generation. The front half (lowering from the AST) produces the Program.
#pragma once

#include <optional>

#include "backend/codegen.h"
#include "frontend/frontend.h"
#include "ir/passes.h"

namespace rcxc::backend {

// Consumes `program` (the passes rewrite it). Diagnostics go to `diags`,
// what the passes decided to `log`.
std::optional<Output> compile(ir::Program program, ir::OptLevel level, Diagnostics& diags, ir::Log& log,
                              const ir::PassOptions& passes = {});

// The whole compiler: NQC source file to image (frontend, lowering, the
// above). `sm` and `diags` receive the files read and every problem.
std::optional<Output> compile_file(const std::string& path, const frontend::Options& options, ir::OptLevel level,
                                   SourceManager& sm, Diagnostics& diags, ir::Log& log,
                                   const ir::PassOptions& passes = {});

// The same for source text in memory (`name` for diagnostics and includes).
std::optional<Output> compile_source(const std::string& name, std::string text, const frontend::Options& options,
                                     ir::OptLevel level, SourceManager& sm, Diagnostics& diags, ir::Log& log);

}  // namespace rcxc::backend
