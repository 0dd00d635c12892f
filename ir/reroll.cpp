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

int instr_size(const Instr& in) {
  return in.raw ? static_cast<int>(in.args.size()) : rcx::command_size(rcx::info(in.op)).value_or(4);
}

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
  for (std::size_t g = 1; g <= kMaxGroup && s + 3 * g <= ins.size(); ++g) {
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

// Splits block b around the run: b keeps what comes before and sets the
// counter, a new loop block holds one copy of the group, and a new block
// after it holds the rest and b's old terminator.
void apply(Program& p, Function& f, BlockId b, const Run& r, Log& log) {
  VarId counter = p.add_var(fmt::format("__reroll{}", p.vars.size()), VarKind::Temp);
  Block& head = f.blocks[static_cast<std::size_t>(b)];
  SourceSpan span = head.instrs[r.start].span;
  std::vector<Instr> body(head.instrs.begin() + static_cast<long>(r.start),
                          head.instrs.begin() + static_cast<long>(r.start + r.group));
  for (auto [j, k] : r.varying) body[j].args[k] = Operand::var(counter);
  body.push_back(Instr{rcx::Op::AddToVariable, {Operand::var(counter), Operand::imm(r.step)}, false, span});
  std::vector<Instr> rest(head.instrs.begin() + static_cast<long>(r.start + r.group * r.count), head.instrs.end());
  Terminator term = head.term;
  head.instrs.resize(r.start);
  head.instrs.push_back(Instr{rcx::Op::SetVariable, {Operand::var(counter), Operand::imm(r.first)}, false, span});

  BlockId loop = add_block(f);
  BlockId after = add_block(f);
  int end = wrap16(static_cast<long>(r.first) + static_cast<long>(r.count) * r.step);
  f.blocks[static_cast<std::size_t>(b)].term = Jump{loop};
  f.blocks[static_cast<std::size_t>(loop)] = Block{std::move(body), Branch{Cmp::NE, Operand::imm(end), Operand::var(counter), loop, after}, span};
  f.blocks[static_cast<std::size_t>(after)] = Block{std::move(rest), std::move(term), span};
  // A repeat's setup ends with its loopset and its head is the LoopTest:
  // both moved to the block after the run.
  for (auto& rep : f.repeats) {
    if (rep.setup == b) rep.setup = after;
    if (rep.head == b) rep.head = after;
  }
  move_block(f, loop, b + 1);
  move_block(f, after, b + 2);
  log.push_back(fmt::format("{}: {} copies of {} instructions rerolled into a loop (the copies took {} bytes more)", f.name, r.count,
                            r.group, r.saving));
}

}  // namespace

bool reroll_sequences(Program& p, Log& log) {
  bool changed = false;
  for (auto& f : p.functions) {
    // Two tasks may run one subroutine at once, and its counter would be
    // the same variable in both.
    if (f.kind == FuncKind::Sub) continue;
    for (std::size_t b = 0; b < f.blocks.size(); ++b) {
      // main's startup code stays first and straight.
      std::size_t s = b == 0 ? static_cast<std::size_t>(f.startup) : 0;
      for (; s < f.blocks[b].instrs.size(); ++s) {
        auto r = best_run_at(f.blocks[b].instrs, s);
        if (!r) continue;
        apply(p, f, static_cast<BlockId>(b), *r, log);
        changed = true;
        ++b;  // the loop block; the loop continues with the block after it
        break;
      }
    }
  }
  return changed;
}

}  // namespace rcxc::ir
