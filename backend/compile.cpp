#include "backend/compile.h"

#include <fmt/format.h>

#include "ir/lower.h"

namespace rcxc::backend {

namespace {

std::optional<Output> allocate_and_generate(const ir::Program& program, ir::OptLevel level, Diagnostics& diags,
                                            ir::Log& log) {
  auto slots = ir::allocate_slots(program, diags);
  if (slots.empty() && !program.vars.empty()) return std::nullopt;
  GenerateOptions options;
  options.drop_self_copies = level != ir::OptLevel::O0;
  options.absorb = ir::shrinks_without_slowing(level);
  options.outline = ir::trades_time_for_size(level);
  return generate(program, slots, diags, options, &log);
}

}  // namespace

// Rerolling is judged on the final code: the copies it folds into a loop
// may have been worth more to outlining, and its temporary needs a slot.
// It also rescues a task that is too long written out. Each alternative
// reports into its own copy of the diagnostics so far; the chosen one's
// diagnostics and log are kept.
std::optional<Output> compile(ir::Program program, ir::OptLevel level, Diagnostics& diags, ir::Log& log,
                              const ir::PassOptions& passes) {
  if (!ir::optimize(program, level, diags, log, passes)) return std::nullopt;
  Diagnostics chosen_diags = diags;
  ir::Log chosen_log;
  auto out = allocate_and_generate(program, level, chosen_diags, chosen_log);
  // A rerolled loop runs two instructions more per step: -Os only.
  if (ir::trades_time_for_size(level)) {
    ir::Program rerolled = std::move(program);
    ir::Log steps;
    if (ir::reroll_sequences(rerolled, steps)) {
      Diagnostics rerolled_diags = diags;
      auto alternative = allocate_and_generate(rerolled, level, rerolled_diags, steps);
      bool straight_failed = !out || chosen_diags.has_errors();
      if (alternative && !rerolled_diags.has_errors() &&
          (straight_failed || alternative->code_bytes < out->code_bytes)) {
        out = std::move(alternative);
        chosen_diags = std::move(rerolled_diags);
        chosen_log = std::move(steps);
      }
    }
  }
  diags = std::move(chosen_diags);
  log.insert(log.end(), chosen_log.begin(), chosen_log.end());
  if (out) log.push_back(fmt::format("{} bytes of code, {} variable slot{}", out->code_bytes, out->slots_used,
                                     out->slots_used == 1 ? "" : "s"));
  return out;
}

std::optional<Output> compile_file(const std::string& path, const frontend::Options& options, ir::OptLevel level,
                                   SourceManager& sm, Diagnostics& diags, ir::Log& log,
                                   const ir::PassOptions& passes) {
  auto program = frontend::parse_program(path, options, sm, diags);
  if (!program) return std::nullopt;
  auto lowered = ir::lower(*program, diags);
  if (!lowered) return std::nullopt;
  return compile(std::move(*lowered), level, diags, log, passes);
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
