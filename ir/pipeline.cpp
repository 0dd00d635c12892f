// The order the passes run in (see passes.h).
#include <map>
#include <string>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// A hash of every function's code, to see whether a round of the clean-up
// passes changed anything (a changed program hashing the same would only
// end the rounds early: less optimised, never wrong).
std::uint64_t code_hash(const Program& p) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](std::int64_t v) { h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull; };
  auto operand = [&](const Operand& o) {
    mix(static_cast<int>(o.kind));
    mix(o.source);
    mix(o.value);
  };
  for (const auto& f : p.functions) {
    mix(static_cast<std::int64_t>(f.blocks.size()));
    for (const auto& b : f.blocks) {
      mix(static_cast<std::int64_t>(b.instrs.size()));
      for (const auto& in : b.instrs) {
        mix(static_cast<int>(in.op));
        for (const auto& a : in.args) operand(a);
      }
      mix(static_cast<std::int64_t>(b.term.index()));
      for (BlockId s : successors(b.term)) mix(s);
      if (const auto* br = std::get_if<Branch>(&b.term)) {
        mix(static_cast<int>(br->cmp));
        operand(br->a);
        operand(br->b);
      }
    }
  }
  return h;
}

}  // namespace

bool optimize(Program& p, OptLevel level, Diagnostics& diags, Log& log, const PassOptions& passes) {
  // Most of the passes change nothing in most functions, and a round of
  // them that changes nothing changes nothing anywhere: each function's
  // liveness is kept until its code changes. The check for reads before
  // writes computes it first, and calls (inlining) and tail starts leave
  // most functions as they were for the first round to reuse it.
  LivenessCache liveness;
  // Before any pass, so every level reports the same reads (-O0 runs no
  // pass that would reuse its liveness).
  warn_reads_before_writes(p, diags, level != OptLevel::O0 ? &liveness : nullptr);
  warn_unconfigured_sensors(p, diags);
  if (!resolve_calls(p, level, diags, log)) return false;
  if (shrinks_without_slowing(level) && passes.tail_starts)
    run_tail_started_tasks_in_main(p, log, trades_time_for_size(level));
  // Each function's bytes as lowered: -O2's copies of short joins may
  // spend only what the other passes saved (by name: uncalled subroutines
  // go).
  const bool copies_joins = shrinks_without_slowing(level) && !trades_time_for_size(level);
  std::map<std::string, int> lowered_bytes;
  if (copies_joins)
    for (const auto& f : p.functions) lowered_bytes[f.name] = code_bytes(f);
  if (level != OptLevel::O0) {
    // Once: the shapes it rewrites come from the lowering alone.
    const bool several_tasks = runs_several_tasks(p);
    if (shrinks_without_slowing(level))
      for (auto& f : p.functions) shift_right_without_branches(f, p.vars, several_tasks, trades_time_for_size(level));
    // Up to three rounds, each finding what the last one's removals
    // exposed; a round that changes nothing ends them.
    std::uint64_t before = code_hash(p);
    for (int round = 0; round < 3; ++round) {
      fold_constants(p, &liveness);
      remove_dead_stores(p, &liveness);
      for (auto& f : p.functions) gather_constant_arithmetic(f, p.vars, several_tasks);
      if (shrinks_without_slowing(level)) {
        compute_into_targets(p, &liveness);
        test_before_one_to_one_arithmetic(p, &liveness);
        for (auto& f : p.functions) {
          push_constant_ops_into_predecessors(f, p.vars);
          compute_nonzero_by_sign(f, p.vars, several_tasks);
        }
        apply_constants_in_predecessors(p);
      }
      for (auto& f : p.functions) shorten_complements(f, p.vars, several_tasks);
      if (shrinks_without_slowing(level)) hoist_common_heads(p, log);
      for (auto& f : p.functions) simplify_cfg(f);
      if (shrinks_without_slowing(level)) compute_poll_thresholds_once(p, log);
      std::uint64_t after = code_hash(p);
      if (after == before) break;
      before = after;  // the next round starts from this code
    }
    drop_uncalled_subs(p, log);
    for (auto& f : p.functions) merge_nested_repeats(f, log);
    // The flip adds a jump per pass (each half loops back on its own) and
    // speculation an assignment when the condition holds: -Os only.
    if (trades_time_for_size(level)) halve_back_and_forth_loops(p, log);
    if (shrinks_without_slowing(level)) {
      for (auto& f : p.functions) {
        merge_motor_commands(f, p.vars);
        drop_redundant_sensor_modes(f);
        if (trades_time_for_size(level)) speculate_assignments(f, p.vars);
      }
      remove_redundant_motor_commands(p);
      // Removed motor commands can leave waits next to each other, and
      // merged ones the same command at the head of both sides of a test.
      for (auto& f : p.functions) merge_consecutive_waits(f);
      hoist_common_heads(p, log);
      for (auto& f : p.functions) drop_motor_commands_overwritten_next(f, log);
    }
  }
  // Needed at every level: a counter loop left by a jump must not keep its
  // counter pushed.
  assign_loop_counters(p, log);
  if (level != OptLevel::O0) {
    bool dropped_loops = false;
    for (auto& f : p.functions) {
      simplify_cfg(f, true);
      rotate_loops(f);
      dropped_loops |= enter_past_known_tests(f, p.vars);
      place_branch_targets(f);
      place_exit_last(f);
      // Bytes for time: -Os keeps the jumps.
      if (copies_joins) {
        int budget = lowered_bytes[f.name] - code_bytes(f);
        budget -= copy_tests_into_latches(f, log, budget);
        copy_short_jump_targets(f, log, budget);
      }
    }
    // `int k = 20; while (k < 10) ...`: the loop gone, so is the reason
    // for setting k.
    if (dropped_loops) remove_dead_stores(p);
  }
  // A coin toss runs one loop test more on one of its sides.
  if (trades_time_for_size(level)) toss_coins_on_loop_counter(p, log);
  return true;
}

}  // namespace rcxc::ir
