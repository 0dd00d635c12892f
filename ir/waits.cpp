// Consecutive constant waits as one (see passes.h).
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

std::optional<int> constant_wait(const Instr& in) {
  if (in.raw || in.op != rcx::Op::Wait || in.args.size() != 1 || !in.args[0].is_imm() || in.args[0].value < 0)
    return std::nullopt;
  return in.args[0].value;
}

}  // namespace

void merge_consecutive_waits(Function& f) {
  for (auto& b : f.blocks) {
    auto& code = b.instrs;
    std::vector<Instr> out;
    out.reserve(code.size());
    for (auto& in : code) {
      auto w = constant_wait(in);
      if (w && !out.empty()) {
        if (auto before = constant_wait(out.back())) {
          Operand sum = Operand::imm(*before + *w);
          if (accepts(rcx::Op::Wait, 0, sum)) {
            out.back().args[0] = sum;
            continue;
          }
        }
      }
      out.push_back(std::move(in));
    }
    code = std::move(out);
  }
}

}  // namespace rcxc::ir
