#include "backend/compile.h"

#include <fmt/format.h>

#include "ir/lower.h"

namespace rcxc::backend {

std::optional<Output> compile(ir::Program program, ir::OptLevel level, Diagnostics& diags, ir::Log& log) {
  if (!ir::optimize(program, level, diags, log)) return std::nullopt;
  auto slots = ir::allocate_slots(program, diags);
  if (slots.empty() && !program.vars.empty()) return std::nullopt;
  auto out = generate(program, slots, diags, GenerateOptions{level == ir::OptLevel::Os}, &log);
  if (out) log.push_back(fmt::format("{} bytes of code, {} variable slots", out->code_bytes, out->slots_used));
  return out;
}

std::optional<Output> compile_file(const std::string& path, const frontend::Options& options, ir::OptLevel level,
                                   SourceManager& sm, Diagnostics& diags, ir::Log& log) {
  auto program = frontend::parse_program(path, options, sm, diags);
  if (!program) return std::nullopt;
  auto lowered = ir::lower(*program, diags);
  if (!lowered) return std::nullopt;
  return compile(std::move(*lowered), level, diags, log);
}

std::optional<Output> compile_source(const std::string& name, std::string text, const frontend::Options& options,
                                     ir::OptLevel level, SourceManager& sm, Diagnostics& diags, ir::Log& log) {
  auto program = frontend::parse_source(name, std::move(text), options, sm, diags);
  if (!program) return std::nullopt;
  auto lowered = ir::lower(*program, diags);
  if (!lowered) return std::nullopt;
  return compile(std::move(*lowered), level, diags, log);
}

}  // namespace rcxc::backend
