// Back-and-forth loops as one half and a direction flip (see passes.h).
#include <fmt/format.h>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

constexpr int kForward = 0x80, kFlip = 0x40, kOutputs = 7;

bool is_direction(const Instr& in) { return !in.raw && in.op == rcx::Op::SetMotorDirection; }

// Whether `in` may change the direction of an output in `outputs`.
bool turns(const Instr& in, int outputs) {
  if (in.raw) return true;
  if (!is_direction(in)) return false;
  return !in.args.at(0).is_imm() || (in.args[0].value & outputs) != 0;
}

// The outputs whose direction the two instructions set one way and the other
// (dir S, fwd against dir S, rev), or 0.
int opposite_directions(const Instr& a, const Instr& b) {
  if (!is_direction(a) || !is_direction(b) || !a.args.at(0).is_imm() || !b.args.at(0).is_imm()) return 0;
  int x = a.args[0].value, y = b.args[0].value;
  if ((x & kFlip) || (y & kFlip) || (x & kOutputs) != (y & kOutputs) || (x & kForward) == (y & kForward)) return 0;
  return x & kOutputs;
}

// Whether anything but task `f` may turn an output of `outputs`: another
// task or a subroutine (main's startup code aside, which runs before any
// other task unless something restarts main).
bool turned_elsewhere(const Program& p, FuncId f, int outputs) {
  bool turned = false;
  const std::vector<bool> started = started_functions(p);
  for (std::size_t g = 0; g < p.functions.size(); ++g)
    if (static_cast<FuncId>(g) != f)
      each_instr_beside_other_tasks(p.functions[g], started[g],
                                    [&](const Instr& in) { turned = turned || turns(in, outputs); });
  return turned;
}

// Block b loops on itself through H1 H2, two halves alike but for one
// direction command: P (dir S, d) Q  P (dir S, !d) Q. Returns the index of
// that command in H1, or -1.
int halves_differing_in_direction(const Block& block, int& outputs) {
  std::size_t n = block.instrs.size();
  if (n < 4 || n % 2 != 0) return -1;
  std::size_t half = n / 2;
  int at = -1;
  for (std::size_t i = 0; i < half; ++i) {
    const Instr& a = block.instrs[i];
    const Instr& b = block.instrs[half + i];
    if (same_instr(a, b)) continue;
    if (at >= 0) return -1;
    outputs = opposite_directions(a, b);
    if (outputs == 0) return -1;
    at = static_cast<int>(i);
  }
  if (at < 0) return -1;
  // Nothing else in the loop may turn those outputs, nor call a subroutine
  // that might.
  for (std::size_t i = 0; i < half; ++i) {
    const Instr& in = block.instrs[i];
    if (static_cast<int>(i) != at && (turns(in, outputs) || callee_of(in) >= 0)) return -1;
  }
  return at;
}

}  // namespace

void halve_back_and_forth_loops(Program& p, Log& log) {
  for (std::size_t fi = 0; fi < p.functions.size(); ++fi) {
    Function& f = p.functions[fi];
    if (f.kind != FuncKind::Task) continue;
    for (std::size_t bi = 0; bi < f.blocks.size(); ++bi) {
      auto b = static_cast<BlockId>(bi);
      const auto* j = std::get_if<Jump>(&f.blocks[bi].term);
      int outputs = 0;
      if (j == nullptr || j->target != b || is_repeat_block(f, b)) continue;
      int at = halves_differing_in_direction(f.blocks[bi], outputs);
      if (at < 0 || turned_elsewhere(p, static_cast<FuncId>(fi), outputs)) continue;
      // b keeps P (dir S, d) and enters the new loop Q P (dir S, flip):
      // P d Q P !d Q P d ... as before.
      std::vector<Instr> body = std::move(f.blocks[bi].instrs);
      std::size_t half = body.size() / 2, k = static_cast<std::size_t>(at);
      Instr flip = body[k];
      flip.args[0].value = kFlip | outputs;
      std::vector<Instr> entry(body.begin(), body.begin() + static_cast<std::ptrdiff_t>(k) + 1);
      std::vector<Instr> loop(body.begin() + static_cast<std::ptrdiff_t>(k) + 1,
                              body.begin() + static_cast<std::ptrdiff_t>(half));
      loop.insert(loop.end(), body.begin(), body.begin() + static_cast<std::ptrdiff_t>(k));
      loop.push_back(flip);
      BlockId l = add_block(f);
      f.blocks[static_cast<std::size_t>(l)].instrs = std::move(loop);
      f.blocks[static_cast<std::size_t>(l)].term = Jump{l};
      f.blocks[static_cast<std::size_t>(l)].span = f.blocks[bi].span;
      f.blocks[bi].instrs = std::move(entry);
      f.blocks[bi].term = Jump{l};
      move_block(f, l, b + 1);
      log.push_back(fmt::format("{}: a loop going one way then back is one half and a direction flip", f.name));
    }
  }
}

}  // namespace rcxc::ir
