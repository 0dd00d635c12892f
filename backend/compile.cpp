#include "backend/compile.h"

#include <fmt/format.h>

#include <algorithm>

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

namespace {

// Rerolling is judged on the final code: the copies it folds into a loop
// may have been worth more to outlining, and its temporary needs a slot.
// It also rescues a task that is too long written out. Each alternative
// reports into its own copy of the diagnostics so far; the chosen one's
// diagnostics and log are kept.
std::optional<Output> compile_at(ir::Program program, ir::OptLevel level, Diagnostics& diags, ir::Log& log,
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

bool out_of_slots(const Diagnostics& diags) {
  return std::any_of(diags.all().begin(), diags.all().end(),
                     [](const Diagnostic& d) { return ir::reports_no_slot_left(d); });
}

}  // namespace

// -Os's own passes can keep more values alive at once than -O2's code
// does (speculation sets a result before the test that decides it), so
// -Os's code can need more variable slots than the RCX has where -O2's
// fits: then the program is compiled as at -O2, which is never refused
// for what -Os does on top of it.
std::optional<Output> compile(ir::Program program, ir::OptLevel level, Diagnostics& diags, ir::Log& log,
                              const ir::PassOptions& passes) {
  if (level != ir::OptLevel::Os) return compile_at(std::move(program), level, diags, log, passes);
  ir::Program copy = program;
  Diagnostics os_diags = diags;
  ir::Log os_log;
  auto out = compile_at(std::move(program), level, os_diags, os_log, passes);
  if (!out && out_of_slots(os_diags) && !out_of_slots(diags)) {
    Diagnostics o2_diags = diags;
    ir::Log o2_log;
    auto o2 = compile_at(std::move(copy), ir::OptLevel::O2, o2_diags, o2_log, passes);
    if (o2 && !o2_diags.has_errors()) {
      diags = std::move(o2_diags);
      log.push_back("-Os's code needs more variable slots than the RCX has: compiled as at -O2");
      log.insert(log.end(), o2_log.begin(), o2_log.end());
      return o2;
    }
  }
  diags = std::move(os_diags);
  log.insert(log.end(), os_log.begin(), os_log.end());
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
