// The order the passes run in (see passes.h).
#include "ir/passes.h"

namespace rcxc::ir {

bool optimize(Program& p, OptLevel level, Diagnostics& diags, Log& log, const PassOptions& passes) {
  // Before any pass, so every level reports the same reads.
  warn_reads_before_writes(p, diags);
  if (!resolve_calls(p, level, diags, log)) return false;
  if (level == OptLevel::Os && passes.tail_starts) run_tail_started_tasks_in_main(p, log);
  if (level != OptLevel::O0) {
    for (int round = 0; round < 3; ++round) {
      fold_constants(p);
      remove_dead_stores(p);
      for (auto& f : p.functions) simplify_cfg(f);
    }
    for (auto& f : p.functions) merge_nested_repeats(f, log);
    if (level == OptLevel::Os) {
      halve_back_and_forth_loops(p, log);
      for (auto& f : p.functions) {
        merge_motor_commands(f, p.vars);
        drop_redundant_sensor_modes(f);
        speculate_assignments(f, p.vars);
      }
      remove_redundant_motor_commands(p);
    }
  }
  // Needed at every level: a counter loop left by a jump must not keep its
  // counter pushed.
  assign_loop_counters(p, log);
  if (level != OptLevel::O0)
    for (auto& f : p.functions) {
      simplify_cfg(f);
      rotate_loops(f);
      place_branch_targets(f);
      place_exit_last(f);
    }
  if (level == OptLevel::Os) toss_coins_on_loop_counter(p, log);
  return true;
}

}  // namespace rcxc::ir
