#include "backend/compile.h"

#include <fmt/format.h>

namespace rcxc::backend {

std::optional<Output> compile(ir::Program program, ir::OptLevel level, Diagnostics& diags, ir::Log& log) {
  if (!ir::optimize(program, level, diags, log)) return std::nullopt;
  auto slots = ir::allocate_slots(program, diags);
  if (slots.empty() && !program.vars.empty()) return std::nullopt;
  auto out = generate(program, slots, diags);
  if (out) log.push_back(fmt::format("{} bytes of code, {} variable slots", out->code_bytes, out->slots_used));
  return out;
}

}  // namespace rcxc::backend
