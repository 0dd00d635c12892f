#include "backend/compile.h"

#include <fmt/format.h>

#include "ir/lower.h"

namespace rcxc::backend {

namespace {

std::optional<Output> allocate_and_generate(const ir::Program& program, ir::OptLevel level, Diagnostics& diags,
                                            ir::Log& log) {
  auto slots = ir::allocate_slots(program, diags);
  if (slots.empty() && !program.vars.empty()) return std::nullopt;
  return generate(program, slots, diags, GenerateOptions{level == ir::OptLevel::Os}, &log);
}

// Rerolling is judged on the final code: the copies it folds into a loop
// may have been worth more to outlining, and its temporary needs a slot.
// Either way the straight code stays. `log` is the generation's log, which
// the rerolled generation's replaces.
void try_rerolling(const ir::Program& program, std::optional<Output>& out, ir::Log& log) {
  ir::Program rerolled = program;
  ir::Log steps;
  if (!ir::reroll_sequences(rerolled, steps)) return;
  Diagnostics quiet;
  auto alternative = allocate_and_generate(rerolled, ir::OptLevel::Os, quiet, steps);
  if (!alternative || quiet.has_errors() || alternative->code_bytes >= out->code_bytes) return;
  out = std::move(alternative);
  log = std::move(steps);
}

}  // namespace

std::optional<Output> compile(ir::Program program, ir::OptLevel level, Diagnostics& diags, ir::Log& log) {
  if (!ir::optimize(program, level, diags, log)) return std::nullopt;
  ir::Log generation;
  auto out = allocate_and_generate(program, level, diags, generation);
  if (out && level == ir::OptLevel::Os && !diags.has_errors()) try_rerolling(program, out, generation);
  log.insert(log.end(), generation.begin(), generation.end());
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
