// The one way the CLI turns an NQC source file into a program image in
// memory: `rcxc test`, `rcxc run FILE.nqc` and `rcxc download FILE.nqc` all
// compile through here, so they behave exactly like `rcxc compile`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "backend/codegen.h"
#include "frontend/diagnostics.h"
#include "frontend/frontend.h"
#include "ir/passes.h"
#include "rcx/image.h"
#include "verify/testspec.h"

namespace rcxc::cli {

struct CompileRequest {
  frontend::Options frontend;
  ir::OptLevel level = ir::OptLevel::O2;
};

struct CompileResult {
  SourceManager sources;
  Diagnostics diagnostics;
  std::optional<backend::Output> output;  // nullopt when there were errors
  ir::Log log;                            // what the passes decided (-v)
};

// Frontend, lowering, passes and code generation for the file at `path`.
// `diags` may come preconfigured (-Werror, -w).
CompileResult compile_file(const std::string& path, const CompileRequest& request, Diagnostics diags = {});

// The same, reduced to what `rcxc test` needs: the image and the messages.
struct CompiledForTest {
  std::optional<rcx::Image> image;
  std::vector<rcx::semtest::CompilerMessage> messages;
};
CompiledForTest compile_nqc_file(const std::string& path);

}  // namespace rcxc::cli
