// Building IR by hand in tests: a program, its functions and blocks.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "ir/ir.h"

namespace rcxc::ir::test {

inline Operand V(VarId v) { return Operand::var(v); }
inline Operand I(int v) { return Operand::imm(v); }

inline Instr op(rcx::Op o, std::vector<Operand> args) { return Instr{o, std::move(args), false, {}}; }
inline Instr set(VarId v, Operand x) { return op(rcx::Op::SetVariable, {V(v), x}); }
inline Instr add(VarId v, Operand x) { return op(rcx::Op::AddToVariable, {V(v), x}); }
inline Instr sub(VarId v, Operand x) { return op(rcx::Op::SubtractFromVariable, {V(v), x}); }
inline Instr mul(VarId v, Operand x) { return op(rcx::Op::MultiplyVariable, {V(v), x}); }
inline Instr div(VarId v, Operand x) { return op(rcx::Op::DivideVariable, {V(v), x}); }
inline Instr band(VarId v, Operand x) { return op(rcx::Op::AndVariable, {V(v), x}); }
inline Instr bor(VarId v, Operand x) { return op(rcx::Op::OrVariable, {V(v), x}); }
inline Instr wait(Operand x) { return op(rcx::Op::Wait, {x}); }
inline Instr call(FuncId f) { return op(rcx::Op::CallSubroutine, {Operand::func(f)}); }
inline Instr start(FuncId f) { return op(rcx::Op::StartTask, {Operand::func(f)}); }
inline Instr sound(int n) { return op(rcx::Op::PlaySound, {I(n)}); }
// One byte of filler (Clear message).
inline Instr filler() { return op(rcx::Op::ClearMessage, {}); }
inline Instr loopset(Operand n) { return op(rcx::Op::SetLoopCounter, {n}); }
// Motor commands by their encoded byte: direction (0x80 forward | outputs),
// on/off/float (0x80 on, 0x40 off, 0 float | outputs), and power.
inline Instr dir(int code) { return op(rcx::Op::SetMotorDirection, {I(code)}); }
inline Instr out(int code) { return op(rcx::Op::SetMotorOnOff, {I(code)}); }
inline Instr pwr(int outputs, int power) { return op(rcx::Op::SetMotorPower, {I(outputs), I(power)}); }

struct Builder {
  Program p;

  FuncId function(std::string name, FuncKind kind = FuncKind::Task) {
    Function f;
    f.name = std::move(name);
    f.kind = kind;
    p.functions.push_back(std::move(f));
    return static_cast<FuncId>(p.functions.size() - 1);
  }
  Function& fn(FuncId f) { return p.functions[static_cast<std::size_t>(f)]; }
  BlockId block(FuncId f, std::vector<Instr> instrs, Terminator t = Exit{}) {
    BlockId b = add_block(fn(f));
    fn(f).blocks[static_cast<std::size_t>(b)].instrs = std::move(instrs);
    fn(f).blocks[static_cast<std::size_t>(b)].term = t;
    return b;
  }
  Block& at(FuncId f, BlockId b) { return fn(f).blocks[static_cast<std::size_t>(b)]; }
  VarId global(std::string name) { return p.add_var(std::move(name), VarKind::Global); }
  VarId local(std::string name) { return p.add_var(std::move(name), VarKind::Local); }
  VarId temp() { return p.add_var("", VarKind::Temp); }
};

}  // namespace rcxc::ir::test
