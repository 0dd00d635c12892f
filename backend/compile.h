// The compiler's back half in one call: IR passes, slot allocation, code
// generation. The front half (lowering from the AST) produces the Program.
#pragma once

#include <optional>

#include "backend/codegen.h"
#include "ir/passes.h"

namespace rcxc::backend {

// Consumes `program` (the passes rewrite it). Diagnostics go to `diags`,
// what the passes decided to `log`.
std::optional<Output> compile(ir::Program program, ir::OptLevel level, Diagnostics& diags, ir::Log& log);

}  // namespace rcxc::backend
