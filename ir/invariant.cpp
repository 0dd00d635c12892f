// Polls that compute their threshold once (see passes.h).
#include <algorithm>

#include <fmt/format.h>

#include "ir/passes.h"
#include "ir/predecessors.h"

namespace rcxc::ir {
namespace {

bool has(const std::vector<VarId>& set, VarId v) { return std::find(set.begin(), set.end(), v) != set.end(); }

// The length of the run of instructions `code` begins with that compute
// the same values on every pass of the poll: arithmetic into locals and
// temporaries, each first set by a `set`, from constants and from
// variables nothing in the poll writes (globals only when no other task
// runs, since the poll calls nothing), reading no source (a sensor, a
// timer or a random number changes between passes).
std::size_t invariant_prefix(const std::vector<Instr>& code, const std::vector<Var>& vars, bool other_tasks) {
  std::vector<VarId> prefix_sets;    // set so far in the prefix
  std::size_t n = 0;
  for (; n < code.size(); ++n) {
    const Instr& in = code[n];
    if (in.raw || !computes_into_variable(in.op) || !in.args.at(0).is_var()) break;
    VarId dest = in.args[0].value;
    if (vars.at(static_cast<std::size_t>(dest)).kind == VarKind::Global) break;
    if (in.op != rcx::Op::SetVariable && !has(prefix_sets, dest)) break;
    const Operand& src = in.args.at(1);
    if (src.kind == Operand::Kind::Src) break;
    if (src.is_var() && !has(prefix_sets, src.value) && other_tasks &&
        shared_between_tasks(vars.at(static_cast<std::size_t>(src.value))))
      break;
    prefix_sets.push_back(dest);
  }
  // What the prefix reads from before it must be written neither by the
  // prefix after the read nor by the rest of the poll, and what it
  // writes not by the rest: the next pass would compute something else.
  for (;;) {
    std::vector<VarId> inputs, outputs;
    bool rereads = false;
    for (std::size_t i = 0; i < n; ++i) {
      const Operand& src = code[i].args[1];
      if (src.is_var() && !has(outputs, src.value)) inputs.push_back(src.value);
      rereads |= has(inputs, code[i].args[0].value);
      outputs.push_back(code[i].args[0].value);
    }
    bool clash = rereads;
    for (std::size_t i = n; i < code.size() && !clash; ++i) {
      if (code[i].raw || code[i].op == rcx::Op::CallSubroutine) clash = true;
      for (VarId w : uses_of(code[i]).writes) clash |= has(inputs, w) || has(outputs, w);
    }
    if (!clash || n == 0) return n;
    --n;  // a shorter prefix may still do
  }
}

// Moves the first `n` instructions of poll block `b` out of it, onto the
// one way in, `from`: at its end when it jumps in, else (a test entering
// the poll) into a new block laid out right before the poll, which the
// test enters and which falls into the poll.
void move_out(Function& f, BlockId b, BlockId from, std::size_t n) {
  auto& code = f.blocks[static_cast<std::size_t>(b)].instrs;
  std::vector<Instr> moved(code.begin(), code.begin() + static_cast<long>(n));
  code.erase(code.begin(), code.begin() + static_cast<long>(n));
  Block& way_in = f.blocks[static_cast<std::size_t>(from)];
  if (std::holds_alternative<Jump>(way_in.term)) {
    way_in.instrs.insert(way_in.instrs.end(), moved.begin(), moved.end());
    return;
  }
  BlockId head = add_block(f);
  Block& h = f.blocks[static_cast<std::size_t>(head)];
  h.instrs = std::move(moved);
  h.term = Jump{b};
  h.span = f.blocks[static_cast<std::size_t>(b)].span;
  retarget(f.blocks[static_cast<std::size_t>(from)].term, b, head);
  move_block(f, head, b);
}

// A poll of `f` whose threshold can move out: its block, the one way in
// and how many instructions move; nullopt when there is none.
struct Poll {
  BlockId block = 0, from = 0;
  std::size_t moves = 0;
};
std::optional<Poll> next_poll(const Function& f, const std::vector<Var>& vars, bool other_tasks) {
  const PredecessorLists preds(f, true);
  const std::vector<bool> loop_blocks = repeat_blocks(f);
  for (std::size_t b = 1; b < f.blocks.size(); ++b) {
    const Block& poll = f.blocks[b];
    const auto* br = std::get_if<Branch>(&poll.term);
    auto self = static_cast<BlockId>(b);
    if (br == nullptr || (br->then == self) == (br->otherwise == self) || preds[b].size() != 2 || loop_blocks[b])
      continue;
    BlockId from = preds[b][0] == self ? preds[b][1] : preds[b][0];
    const Terminator& in = f.blocks[static_cast<std::size_t>(from)].term;
    // A test entering the poll gets a block between; only one that lies
    // before it, so the new block falls into the poll in the layout.
    bool enters = std::holds_alternative<Jump>(in) || (std::holds_alternative<Branch>(in) && from < self);
    if (from == self || !enters || loop_blocks[static_cast<std::size_t>(from)]) continue;
    if (std::size_t n = invariant_prefix(poll.instrs, vars, other_tasks); n > 0) return Poll{self, from, n};
  }
  return std::nullopt;
}

}  // namespace

void compute_poll_thresholds_once(Program& p, Log& log) {
  const bool other_tasks = runs_several_tasks(p);
  for (auto& f : p.functions)
    while (auto poll = next_poll(f, p.vars, other_tasks)) {
      log.push_back(fmt::format("{}: a poll computes what it compares with once, before it ({} instruction{})",
                                f.name, poll->moves, poll->moves == 1 ? "" : "s"));
      move_out(f, poll->block, poll->from, poll->moves);
    }
}

}  // namespace rcxc::ir
