// The IR passes, one per file, and the pipeline that runs them.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "frontend/diagnostics.h"
#include "ir/ir.h"

namespace rcxc::ir {

class LivenessCache;

// -O0 nothing; -O1 the clean-ups every compiler does; -O2 (the default)
// the fastest code: on top of -O1 the size passes that never add an
// instruction to any path the program runs; -Os also the size passes that
// trade time for bytes (outlining, rerolling, speculation, coin tosses,
// back-and-forth loops, splitting waits into subroutines), each of which
// may run an instruction more (a call and a return per outlined copy).
enum class OptLevel { O0, O1, O2, Os };

// Passes that save bytes or instructions and never add an executed one.
inline bool shrinks_without_slowing(OptLevel level) { return level == OptLevel::O2 || level == OptLevel::Os; }
// Passes that save bytes at the cost of executed instructions.
inline bool trades_time_for_size(OptLevel level) { return level == OptLevel::Os; }

// What the passes did, for `rcxc compile -v`.
using Log = std::vector<std::string>;

// fold.cpp: propagates constants held in task-private variables (locals
// and temporaries; never globals, which other tasks may change), folds
// arithmetic and branches on constants, and drops instructions that do
// nothing (x += 0, x = x, ...).
// The passes that ask for liveness take it from `cache` when given, which
// keeps it while a function does not change (the clean-up rounds share one).
void fold_constants(Program& p, LivenessCache* cache = nullptr);

// deadstore.cpp: removes writes to locals and temporaries whose value is
// never read.
void remove_dead_stores(Program& p, LivenessCache* cache = nullptr);

// motors.cpp: removes motor commands (direction, on/off, power) that set
// what the output already has. Knowledge survives where other tasks cannot
// change it (they never set that field, or only to the same value) and in
// main before it starts a task. Subroutines are entered with the merge of
// their call sites' states.
void remove_redundant_motor_commands(Program& p);

// overwritten.cpp: a motor command that ends a block is dropped when the
// block it jumps to begins with motor commands (reading no output) of
// which one sets the same field of the same outputs (or more) to the same
// value again: `if (c) { ...; Off(OUT_B); } Off(OUT_B+OUT_C);` keeps the
// second. One instruction less on that path, and no output state that
// lasted a jump's time changes. Each drop is reported in `log`.
void drop_motor_commands_overwritten_next(Function& f, Log& log);

// peephole.cpp: within a block, runs of motor commands (with only
// instructions between that neither read nor change outputs nor write a
// global) become the fewest commands giving the same final output states
// (OnRev(OUT_A); OnFwd(OUT_C) needs one on/off command, not two); a sensor
// mode equal to the default the sensor type just set (slope 0) is dropped.
void merge_motor_commands(Function& f, const std::vector<Var>& vars);
void drop_redundant_sensor_modes(Function& f);
// peephole.cpp: `set t, x; mul t, -1; sub t, 1` (~x once x was computed
// into t) becomes `set t, -1; sub t, x`: one instruction and 5 bytes less.
// Not where t is a global another task may read (`other_tasks`): it would
// see -1, which the source never gives t.
void shorten_complements(Function& f, const std::vector<Var>& vars, bool other_tasks);

// coalesce.cpp: computes into the assigned variable instead of into a
// temporary copied there at the end, where the temporary is read nowhere
// after: `t op= V; V = t` (op one of + * & |) becomes `V op= t`, `t -= V;
// t *= -1; V = t` (V - t, the end of a `%`) becomes `V -= t`, `t -= X;
// t *= -1; V = t` becomes `V = X; V -= t`, `t = X; t -= V; V = t` becomes
// `V -= X; V *= -1`, `t = X; V op= t` becomes `V op= X`, and `t = X; t ±=
// Y...; V ±= t` becomes `V ±= X; V ±= Y...`. Each is fewer instructions on
// the same path. Rewrites that take V through a value the source never
// gives it are made only where no other task can read V.
void compute_into_targets(Program& p, LivenessCache* cache = nullptr);

// gather.cpp: neighbouring constant steps on one variable become one:
// `x - 100 - 10` is `x -= 110`, `+ -` by their sum, `*` by their product
// (the firmware's arithmetic wraps at 16 bits, so both are exact), `&` and
// `|` of the two constants, two divisions by positive constants one by
// their product while it fits (truncating division); a pair that does
// nothing goes. A sum into a temporary or local that starts with a
// constant (`2 + b + 5`: `t = 2; t += b; t += 5`) starts with its first
// variable and adds the constants once (`t = b; t += 7`), the variables
// read in the order they were; into a global only where no other task
// runs (`other_tasks`), as it then holds b, which the source never gives
// it. One instruction less per constant gathered.
void gather_constant_arithmetic(Function& f, const std::vector<Var>& vars, bool other_tasks);

// waits.cpp: consecutive constant waits in a block become one wait of
// their sum (Wait(20); Wait(30); is Wait(50)): one instruction less, the
// second wait no longer 2 ms late.
void merge_consecutive_waits(Function& f);

// negtest.cpp: a test of a temporary or local against a constant, where
// the value is computed just before by one-to-one arithmetic and read
// nowhere after, tests what that arithmetic started from: `x % 3 != 0`
// needs no negation (`t *= -1`), `x + 5 == 7` is `x == 2`, `x * 3 != 0` is
// `x != 0` (3 has an inverse modulo 2^16), `10 - x == 4` is `x == 6`, and
// `~x <= 5` (an order-reversing map that never wraps) is `x >= -6`. The
// ordered tests only through `~` or a plain copy: `x + 1 <= 0` and `x <=
// -1` differ at 32767. A plain copy may be of a source a test reads (`v =
// SENSOR_2; if (v > 50)` tests the sensor, read once, when the copy read
// it; not a random number, which a test cannot read).
void test_before_one_to_one_arithmetic(Program& p, LivenessCache* cache = nullptr);

// joinconst.cpp: a block that begins with constant arithmetic on a
// temporary or local (`t *= 3`) that every way in has just set to a
// constant (`t = 0;` before a test, `t = 1;` on its other side: `(a < b)
// * 3`) starts without it, the constants set being the results: one
// instruction less on every path. Never on a global (another task may
// write it between).
void push_constant_ops_into_predecessors(Function& f, const std::vector<Var>& vars);

// joinconst.cpp: a join whose first instruction is `V op= t`, where t (a
// temporary or local) was set to a constant on every way in (`t = 0;`
// before a test, `t = 1;` on its other side: `V += (a < b)`), and read
// nowhere after: each way in applies its constant to V instead (`V += 1`
// on the side that set 1; nothing where the constant changes nothing:
// + - | of 0, * of 1, & of -1, / of 0 or 1, as the firmware leaves a
// division by zero). The sets of t and the join's instruction go: two
// instructions fewer on the side that set 1, two on the other.
void apply_constants_in_predecessors(Program& p);

// nonzero.cpp: `d = (v != 0)` as lowered (`d = 0;`, a test of v against
// 0, `d = 1;` on the nonzero side) becomes `d = abs(v); d = sign(d);`:
// two instructions on every path instead of two or three, 10 bytes
// instead of 17. d holds |v| for an instruction, which nqc's code never
// shows: not into a global another task may read (`other_tasks`).
void compute_nonzero_by_sign(Function& f, const std::vector<Var>& vars, bool other_tasks);

// shiftright.cpp: `d >>= 15` as lowered (a test of d's sign, `d = 1` on
// one side and `d = 0` on the other) becomes `d &= -32768; d /= -32768`:
// no branch, never an instruction more. With `constant_shifts` (-Os) also
// `d >>= n` for n in 1..14 (the sign's test, `d &= 32767; d /= 2^n; d |=
// 2^(15-n)` on the negative side, `d /= 2^n` on the other) becomes `d &=
// -2^n; d /= 2^n; d &= 2^(16-n) - 1`: 15 bytes instead of 29, three
// instructions on every path where a non-negative d ran two. The steps
// hold values nqc's code never shows (-32768 for a negative d): not into a
// variable another task may read (`other_tasks`).
void shift_right_without_branches(Function& f, const std::vector<Var>& vars, bool other_tasks, bool constant_shifts);

// tailstart.cpp: a task that main starts as the last thing it does before
// ending (`start a; start b;` at main's end: b), that nothing else starts
// and nothing stops, runs in main instead: main jumps into its code,
// saving the start and the task. Only where that keeps the order of turns
// anyone could see: main's turn comes first, so the task must not move
// ahead of a task numbered before it that may run beside it, unless the
// two share nothing (outputs, variables, sounds, ...). Never when main is started or stopped
// anywhere, inside one of main's counter loops, or with raw asm or task
// numbers in asm (they may name tasks the IR cannot see). Each move is
// reported in `log`.
// Without `may_add_an_exit` (-O2), only where main gains no second way to
// end, which would cost a jump on one path.
void run_tail_started_tasks_in_main(Program& p, Log& log, bool may_add_an_exit = true);

// flip.cpp: a task's endless loop whose body goes one way and then back,
// two halves alike but for one direction command (OnFwd(OUT_A); Wait(t);
// OnRev(OUT_A); Wait(t);), becomes a loop over one half whose direction
// command flips the outputs. The first pass sets the direction as written.
// Only when nothing else in the loop, no subroutine and no other task
// (main's startup code aside) may turn those outputs: the flip counts on
// the direction the last pass left.
void halve_back_and_forth_loops(Program& p, Log& log);

// speculate.cpp: `if (c) t = X; else t = Y;` on a local or temporary t
// (X, Y constants or other variables) becomes `t = Y; if (c) t = X;`: the
// else side's block and the jump over it go (2 bytes; one more instruction
// runs when c holds). Globals are left alone: another task could see Y.
void speculate_assignments(Function& f, const std::vector<Var>& vars);

// hoist.cpp: an instruction both sides of a test begin with, where each
// side is entered from the test alone, runs once before the test instead:
// `if (d == 1) { SetPower(OUT_A+OUT_C, 3); Rev(OUT_A); } else {
// SetPower(OUT_A+OUT_C, 3); Rev(OUT_C); }` keeps one SetPower. Every path
// runs as many instructions; the one moved runs an instruction earlier.
// Only motor commands (unless the test reads an output's state), sounds,
// and arithmetic into a variable the test does not read. In a program of
// several tasks, a motor command or an assignment to a global stays after
// a test of a global or a source: another task could answer it before the
// test. Each move is reported in `log`.
void hoist_common_heads(Program& p, Log& log);

// invariant.cpp: a poll (a block that tests and branches back to itself:
// `until (SENSOR_2 <= last + 3);`) that begins by computing what it
// compares with from constants and variables it does not change (locals
// and temporaries; globals only in a program of one task) computes that
// once, in the block that jumps into it: `t = last; t += 3;` no longer
// runs on every pass, and the poll is its test alone. Each poll is
// reported in `log`.
void compute_poll_thresholds_once(Program& p, Log& log);

// cfg.cpp: threads jumps through empty blocks, turns branches whose both
// targets agree into jumps, and deletes blocks no path reaches (dead code
// after unconditional jumps). With `share_short_ends` (the last clean-up,
// once the motor pass has run) also an end as short as one motor command
// is shared where every other copy is all of its branch: sharing one
// earlier would keep a command the motor pass drops on one path only.
void simplify_cfg(Function& f, bool share_short_ends = false);

// rotate.cpp: places the test of a while/for loop (one block or several:
// `while (a && b)`) after its body, so the body falls into the test and
// the test branches back (one branch per iteration instead of two), when
// that needs no more jump and test bytes.
void rotate_loops(Function& f);

// cfg.cpp: drops the blocks no path from the entry reaches.
void remove_unreachable(Function& f);
// cfg.cpp: for each block, the number of its strongly connected component:
// two blocks with the same number lie on a loop together.
std::vector<int> cycle_components(const Function& f);

// entrytest.cpp: a jump to a test alone whose outcome the jumping block
// fixes (it set the variables tested to constants: locals and temporaries,
// which no other task writes) goes where the test would go. `int i = 0;
// while (i < 10) ...`, rotated, enters the body directly instead of
// jumping to the test at the bottom: one instruction and the jump's bytes
// less each time the loop is entered. A loop the way in skips is dropped;
// returns whether a block was, which can leave the constant's `set` dead.
bool enter_past_known_tests(Function& f, const std::vector<Var>& vars);

// layout.cpp: where a test can only branch when its comparison holds
// (a < b of two variables has no single-instruction negation) and the
// block after it is the true side, moves the false side there when that
// needs fewer jumps in all.
void place_branch_targets(Function& f);

// layout.cpp: an exit in the middle of a function costs a jump to the end
// (in a subroutine, a return). The exit block, with the blocks that only
// jump into it, moves to the end when all jumps and tests then take fewer
// bytes: `if (c) { loop forever } else { ...; }` at a task's end then
// needs no jump over the loop.
void place_exit_last(Function& f);

// tailcopy.cpp (-O2 only): a jump on a loop to a short block (quick
// commands, no wait, then a jump) becomes a copy of that block:
// one instruction, the jump, less on that path every pass, for at most 7
// bytes more. `if (c) a; else b; SetPower(OUT_A, 7); }` at a loop's end
// runs the power command on each side and goes straight back. Only where
// the block has another way in, so nothing is left unreached; each copy is
// reported in `log`. The copies of one block add at most 7 bytes in all,
// and the copies in `f` at most `bytes_to_spend` (what the other passes
// saved in it: a loop whose code nothing else shortens, an if/else setting
// a power, came out 4 bytes over nqc's with its copy).
void copy_short_jump_targets(Function& f, Log& log, int bytes_to_spend);

// latchtest.cpp (-O2 only): a loop's jump back to its test (a block that
// is a test alone: `while (c) X;` whose way out is not the next block, so
// that rotating it would cost a jump on the way in) becomes a copy of the
// test, branching back to the body in one instruction: `X; test` a pass
// instead of `test; X; jump`, and no path runs an instruction more (the
// way out is the copy and a jump where it was the jump and the test). An
// `until (c);` that ends a loop's body then polls in place. Only where the
// copy branches to the body directly; each copy adds 5 or 7 bytes, at most
// `bytes_to_spend` in all (returns what it spent); each is reported in
// `log`.
int copy_tests_into_latches(Function& f, Log& log, int bytes_to_spend);

// A block order being decided for `f`, kept as positions so that moving
// a run of blocks costs its length, not a renumbering of the function.
struct BlockOrder {
  const Function& f;
  std::vector<BlockId> order;  // the block at each position
  std::vector<BlockId> pos;    // the position of each block

  explicit BlockOrder(const Function& fn);
  int position(BlockId b) const { return pos[static_cast<std::size_t>(b)]; }
  // The block after position p; blocks.size() past the last.
  BlockId after(int p) const;
  // Bytes of the jumps and tests block b needs when `next` follows it.
  int bytes(BlockId b, BlockId next) const;
  // The bytes of all jumps and tests in this order.
  int total() const;
  // As std::rotate over positions: [middle, last) moves to `first`.
  void rotate(int first, int middle, int last);
  // Renumbers `fn` (the function this order was made from) to this order.
  void apply(Function& fn) const;
};

// layout.cpp: the bytes of f's code in its present order (instructions,
// jumps and tests, every branch near).
int code_bytes(const Function& f);

// nested_repeat.cpp: `repeat (a) repeat (b) S`, with constant counts and
// nothing else in the outer body, becomes one counter loop of a*b (when the
// product fits the loopset's argument): one loopset, one loop test and one
// jump less per nesting. `continue` in S means the same in both forms; a
// loop left early (break, return, goto) is not merged.
void merge_nested_repeats(Function& f, Log& log);

// The firmware's loop counter stack: four counters per task (seed); a fifth
// loopset overwrites the top one.
inline constexpr int kLoopCounters = 4;

// repeat.cpp: the loop counter stack depth at the start of every block
// (-1: not reached), found by walking the code from the entry at depth 0;
// `consistent` is false when some block is reached at two depths (a jump
// out of a counter loop). Raw asm is not counted.
struct CounterDepths {
  std::vector<int> at_block;
  bool consistent = true;
  int max = 0;
  std::vector<std::pair<int, FuncId>> calls;  // depth at each call, callee
};
CounterDepths counter_depths(const Function& f);

// repeat.cpp: keeps the firmware loop counter for `repeat` loops where it
// is safe (nesting, counted across subroutine calls, at most 4 deep; no
// exit other than the loop's end, except in a task no `start` names, where
// a jump out may leave counters that no loop test reads again, at most
// once per run and at most four in all with those pushed after) and
// rewrites the others to count in a variable.
void assign_loop_counters(Program& p, Log& log);
// Rewrites one counter loop to a variable counter.
void demote_repeat(Program& p, Function& f, std::size_t repeat_index);

// reroll.cpp: a task block that repeats one group of instructions, alike but
// for constants stepping by the same amount each copy (SetPower(OUT_A, 1);
// Wait(50); SetPower(OUT_A, 2); Wait(50); ...), becomes a loop over a new
// temporary when that is smaller: (copies - 1) x group bytes against the
// 17 bytes of setting, stepping and testing the temporary. Each copy then
// takes two more instructions' time. Returns whether anything changed; the
// caller keeps the result only if the final code is smaller (the copies
// may have been worth more to outlining) and a slot is free.
bool reroll_sequences(Program& p, Log& log);

// coin.cpp: `if (Random(1) == 0)` (a temporary or local set to Random(1),
// dead after the test) becomes a coin toss on the loop counter:
// `loopset random(1)` pushes 0 or 1, a first loop test pops a 0 and
// branches, a second pops what is then -1 and branches to the other side.
// 7 bytes instead of 12 (a set and a test), and no variable. Only where
// both sides lie after the test (the counter branches forward only) and
// the counter stack has room, counting the deepest call of a subroutine;
// never in a function with raw asm. Run last, once the layout is final.
// Each toss is reported in `log`.
void toss_coins_on_loop_counter(Program& p, Log& log);

// calls.cpp: makes subroutine calls fit the firmware: rejects recursion
// (naming the cycle), inlines subroutines called from subroutines (one
// return address per task), drops subroutines nobody calls, inlines
// subroutines while there are more than 8 (cheapest first) and, from -O2,
// wherever inlining is not larger than calling. Returns false on error.
bool resolve_calls(Program& p, OptLevel level, Diagnostics& diags, Log& log);

// calls.cpp: subroutines no task calls are dropped (their code would take
// bytes, and their variables slots no other code could share): after
// resolve_calls, and again once the clean-up passes have removed the
// calls in code that never runs.
void drop_uncalled_subs(Program& p, Log& log);
// Replaces the call at (block, index) of `caller` by a copy of `callee`.
void inline_call(Program& p, FuncId caller, BlockId block, std::size_t index);
// Bytes a function's code takes when every branch is near (an estimate).
int estimate_size(const Function& f);

// uninitialized.cpp: warns where a local may be read before it is written
// (once per variable, at the read). Such a local holds what the code left in
// it last time: a subroutine's and an inline function's locals are one
// variable for every call, as in nqc, at every optimisation level.
void warn_reads_before_writes(const Program& p, Diagnostics& diags, LivenessCache* cache = nullptr);

// sensor_setup.cpp: warns, once per sensor, where a program first reads the
// value of a sensor that nothing in it gives a type or mode: a beginner's
// `if (SENSOR_1 == 1)` without SetSensor compares the raw reading (about
// 1023 for an open touch sensor) and never holds. The setting persists on
// the brick, so an earlier program may have made it, which the message
// says. A program whose asm bytes may set a sensor up is not judged.
void warn_unconfigured_sensors(const Program& p, Diagnostics& diags);

// slots.cpp: binds every variable to one of the 32 slots. Each global has
// the slot nqc gives it (the lowest free one in declaration order, used or
// not). Other variables share a slot only when they are never live at once
// and can never be used by two tasks at the same time. Returns slot per
// VarId (-1: unused variable), or an empty vector after reporting which
// variables hold the slots.
std::vector<int> allocate_slots(const Program& p, Diagnostics& diags);
// Whether `d` is allocate_slots' report that the slots ran out (-Os falls
// back to -O2's code on it: backend/compile.cpp).
bool reports_no_slot_left(const Diagnostic& d);

// Passes a caller may turn off whatever the level.
struct PassOptions {
  // `rcxc test` keeps every task a task when a test expects task events: a
  // tail-started task runs in main and has no start of its own.
  bool tail_starts = true;
};

// pipeline.cpp: everything above in order. Returns false on error.
bool optimize(Program& p, OptLevel level, Diagnostics& diags, Log& log, const PassOptions& passes = {});

}  // namespace rcxc::ir
