// Loop rerolling (see passes.h): the opposite of unrolling, for code written
// out by hand (SetPower(OUT_A, 1); Wait(50); SetPower(OUT_A, 2); Wait(50); ...).
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <optional>

#include "ir/passes.h"

namespace rcxc::ir {
namespace {

// Longer groups are rare in hand-written code; the bound keeps the search
// linear in the block length.
constexpr std::size_t kMaxGroup = 16;
constexpr int kTestSize = 7;  // a near test-and-branch

// What a loop adds around one copy of the group: set the counter, step it,
// test it.
int loop_cost() {
  return *rcx::command_size(rcx::info(rcx::Op::SetVariable)) +
         *rcx::command_size(rcx::info(rcx::Op::AddToVariable)) + kTestSize;
}

// Instructions a loop may repeat: loop counter instructions belong to their
// `repeat`, and raw bytes are the user's.
bool repeatable(const Instr& in) {
  return !in.raw && in.op != rcx::Op::SetLoopCounter && in.op != rcx::Op::DecrementLoopCounterNear &&
         in.op != rcx::Op::DecrementLoopCounterFar;
}

// A run found in one block: `count` copies of `group` instructions from
// `start`, alike but for constants first + i * step at `varying` operands.
struct Run {
  std::size_t start = 0, group = 0, count = 0;
  int first = 0, step = 0;
  std::vector<std::pair<std::size_t, std::size_t>> varying;  // (instruction in group, operand)
  int saving = 0;
};

// Compares copy 0 and copy 1 of a group of `g` instructions at `s`: the
// operands that differ must all be constants a variable can replace, and
// all step the same way from the same value.
std::optional<Run> pattern(const std::vector<Instr>& ins, std::size_t s, std::size_t g) {
  Run r{s, g, 2, 0, 0, {}, 0};
  bool have = false;
  for (std::size_t j = 0; j < g; ++j) {
    const Instr& a = ins[s + j];
    const Instr& b = ins[s + g + j];
    if (!repeatable(a) || !repeatable(b) || a.op != b.op || a.args.size() != b.args.size()) return std::nullopt;
    for (std::size_t k = 0; k < a.args.size(); ++k) {
      if (a.args[k] == b.args[k]) continue;
      if (!a.args[k].is_imm() || !b.args[k].is_imm() || !accepts(a.op, k, Operand::var(0))) return std::nullopt;
      int step = wrap16(static_cast<long>(b.args[k].value) - a.args[k].value);
      if (have && (a.args[k].value != r.first || step != r.step)) return std::nullopt;
      r.first = a.args[k].value;
      r.step = step;
      have = true;
      r.varying.emplace_back(j, k);
    }
  }
  if (!have) return std::nullopt;
  return r;
}

// Whether copy i of the run's group is there.
bool copy_matches(const std::vector<Instr>& ins, const Run& r, std::size_t i) {
  std::size_t base = r.start + i * r.group;
  int value = wrap16(static_cast<long>(r.first) + static_cast<long>(i) * r.step);
  for (std::size_t j = 0; j < r.group; ++j) {
    const Instr& a = ins[r.start + j];
    const Instr& b = ins[base + j];
    if (!repeatable(b) || a.op != b.op || a.args.size() != b.args.size()) return false;
    for (std::size_t k = 0; k < a.args.size(); ++k) {
      bool varies = std::find(r.varying.begin(), r.varying.end(), std::make_pair(j, k)) != r.varying.end();
      if (varies ? !(b.args[k].is_imm() && b.args[k].value == value) : !(a.args[k] == b.args[k])) return false;
    }
  }
  return true;
}

// The most profitable run starting at `s`, if any saves bytes.
std::optional<Run> best_run_at(const std::vector<Instr>& ins, std::size_t s) {
  std::optional<Run> best;
  for (std::size_t g = 1; g <= kMaxGroup && s + 2 * g <= ins.size(); ++g) {
    auto r = pattern(ins, s, g);
    if (!r) continue;
    while (r->start + (r->count + 1) * g <= ins.size() && copy_matches(ins, *r, r->count)) ++r->count;
    // The counter must not pass its end value before the last copy.
    if (static_cast<long>(r->count) * std::abs(r->step) >= 0x8000) continue;
    int bytes = 0;
    for (std::size_t j = 0; j < g; ++j) bytes += instr_size(ins[s + j]);
    r->saving = static_cast<int>(r->count - 1) * bytes - loop_cost();
    if (r->saving > 0 && (!best || r->saving > best->saving)) best = r;
  }
  return best;
}

// The runs of a block, left to right, none overlapping.
std::vector<Run> runs_in(const std::vector<Instr>& ins, std::size_t from) {
  std::vector<Run> runs;
  for (std::size_t s = from; s < ins.size();) {
    auto r = best_run_at(ins, s);
    if (!r) {
      ++s;
      continue;
    }
    runs.push_back(*r);
    s = r->start + r->group * r->count;
  }
  return runs;
}

// Splits block b at its runs: b keeps what comes before the first and sets
// the counter; each run becomes a loop block holding one copy of the group
// and the test, followed by a block with what comes next (setting the
// counter again before the next run). The last block takes b's terminator.
// Returns the new blocks in the order they follow b.
std::vector<BlockId> split(Function& f, BlockId b, const std::vector<Run>& runs, VarId counter, Log& log) {
  auto at = [&f](BlockId x) -> Block& { return f.blocks[static_cast<std::size_t>(x)]; };
  std::vector<Instr> old = std::move(at(b).instrs);
  Terminator term = at(b).term;
  at(b).instrs.clear();
  std::vector<BlockId> added;
  BlockId cur = b;
  std::size_t pos = 0;
  for (const Run& r : runs) {
    SpanId span = old[r.start].span;
    for (; pos < r.start; ++pos) at(cur).instrs.push_back(std::move(old[pos]));
    at(cur).instrs.push_back(Instr{rcx::Op::SetVariable, {Operand::var(counter), Operand::imm(r.first)}, false, span});
    std::vector<Instr> body(old.begin() + static_cast<long>(r.start), old.begin() + static_cast<long>(r.start + r.group));
    for (auto [j, k] : r.varying) body[j].args[k] = Operand::var(counter);
    body.push_back(Instr{rcx::Op::AddToVariable, {Operand::var(counter), Operand::imm(r.step)}, false, span});
    int end = wrap16(static_cast<long>(r.first) + static_cast<long>(r.count) * r.step);
    BlockId loop = add_block(f);
    BlockId next = add_block(f);
    at(cur).term = Jump{loop};
    at(loop) = Block{std::move(body), Branch{Cmp::NE, Operand::imm(end), Operand::var(counter), loop, next}, span};
    added.insert(added.end(), {loop, next});
    cur = next;
    pos = r.start + r.group * r.count;
    log.push_back(fmt::format("{}: {} copies of {} instructions rerolled into a loop (the copies took {} bytes more)",
                              f.name, r.count, r.group, r.saving));
  }
  for (; pos < old.size(); ++pos) at(cur).instrs.push_back(std::move(old[pos]));
  at(cur).term = std::move(term);
  // A repeat's setup ends with its loopset and its head is the LoopTest:
  // both are now in the last block.
  for (auto& rep : f.repeats) {
    if (rep.setup == b) rep.setup = cur;
    if (rep.head == b) rep.head = cur;
  }
  return added;
}

}  // namespace

bool reroll_sequences(Program& p, Log& log) {
  bool changed = false;
  for (auto& f : p.functions) {
    // Two tasks may run one subroutine at once, and its counter would be
    // the same variable in both.
    if (f.kind == FuncKind::Sub) continue;
    // One counter serves every loop of the task: each is dead after its loop.
    VarId counter = -1;
    std::size_t original = f.blocks.size();
    std::vector<std::vector<BlockId>> added(original);
    for (std::size_t b = 0; b < original; ++b) {
      // main's startup code stays first and straight.
      auto runs = runs_in(f.blocks[b].instrs, b == 0 ? static_cast<std::size_t>(f.startup) : 0);
      if (runs.empty()) continue;
      if (counter < 0) counter = p.add_var(fmt::format("__reroll_{}", f.name), VarKind::Temp);
      added[b] = split(f, static_cast<BlockId>(b), runs, counter, log);
      changed = true;
    }
    if (f.blocks.size() == original) continue;
    std::vector<BlockId> order;
    order.reserve(f.blocks.size());
    for (std::size_t b = 0; b < original; ++b) {
      order.push_back(static_cast<BlockId>(b));
      order.insert(order.end(), added[b].begin(), added[b].end());
    }
    permute_blocks(f, order);
  }
  return changed;
}

}  // namespace rcxc::ir
