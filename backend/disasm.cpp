#include "backend/disasm.h"

#include <fmt/format.h>

#include "rcx/opcodes.h"
#include "rcx/decode.h"

namespace rcxc::backend {
namespace {

// A source/argument pair as a program would read it.
std::string operand_text(int source, int argument) {
  switch (source) {
    case 0: return fmt::format("var[{}]", argument);
    case 2: return fmt::format("{}", argument);
    case 4: return fmt::format("random({})", argument);
    case 8: return "program";
    case 14: return "clock";
    case 15: return "message";
    default: return fmt::format("{}[{}]", rcx::source_name(source), argument);
  }
}

constexpr const char* kCompare[4] = {"<=", ">=", "!=", "=="};

// Output bits 0x01/0x02/0x04 as letters, e.g. 0x05 -> "AC".
std::string motors(int mask) {
  std::string m;
  for (int i = 0; i < 3; ++i)
    if (mask & (1 << i)) m += static_cast<char>('A' + i);
  return m.empty() ? "-" : m;
}

// The motor opcodes pack outputs and an action in one code byte (seed:
// Set motor on/off, Set motor direction).
std::string motor_code(rcx::Op op, int code) {
  bool hi = code & 0x80, lo = code & 0x40;
  const char* action = op == rcx::Op::SetMotorOnOff ? (hi ? "on" : lo ? "off" : "float")
                                                    : (lo ? "flip" : hi ? "fwd" : "rev");
  return motors(code) + ", " + action;
}

}  // namespace

Instruction format_instruction(std::span<const std::uint8_t> code, int address) {
  Instruction out;
  out.address = address;
  const std::uint8_t byte = code[static_cast<std::size_t>(address)];
  rcx::Decoded d = rcx::decode_command(code, address);
  // A request (an asm block's Upload datalog, say) is named with its
  // operands, as nqc -L does, and marked as nothing the brick runs.
  bool is_request = false;
  if (d.error == static_cast<std::uint8_t>(rcx::DecodeError::NotACommand)) {
    auto request = rcx::decode_request(code, address);
    if (!request) {
      out.valid = false;
      out.text = fmt::format("??? 0x{:02x}", byte);
      return out;
    }
    d = *request;
    is_request = true;
  }
  const std::string_view note = is_request ? "  ; a request, not a program opcode" : "";
  const rcx::OpcodeInfo* info = &rcx::info(d.op);
  if (d.error == static_cast<std::uint8_t>(rcx::DecodeError::Truncated)) {
    out.valid = false;
    out.size = static_cast<int>(code.size()) - address;
    out.text = fmt::format("{} (truncated){}", info->mnemonic, note);
    return out;
  }
  out.valid = !is_request;
  out.size = d.size;
  if (info->op == rcx::Op::SetMotorOnOff || info->op == rcx::Op::SetMotorDirection) {
    out.text = fmt::format("{} {}", info->mnemonic, motor_code(info->op, d.v[0]));
    return out;
  }
  std::vector<std::string> parts;
  const auto& ops = info->operands;
  std::string compare_op;
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const rcx::Operand& o = ops[i];
    int value = d.v[i];
    switch (o.role) {
      case rcx::Role::Argument:
      case rcx::Role::Extension:
        break;  // printed with their source / offset
      case rcx::Role::Variable:
        parts.push_back(fmt::format("var[{}]", value));
        break;
      case rcx::Role::Source:
      case rcx::Role::OpSource: {
        int source = o.role == rcx::Role::OpSource ? (value & 0x0f) : value;
        int argument = 0;
        for (std::size_t j = 0; j < ops.size(); ++j)
          if (ops[j].role == rcx::Role::Argument && ops[j].pairs_with == static_cast<int>(i)) argument = d.v[j];
        parts.push_back(operand_text(source, argument));
        if (o.role == rcx::Role::OpSource) compare_op = kCompare[(value >> 6) & 3];
        break;
      }
      case rcx::Role::Offset:
        parts.push_back(fmt::format("{}", d.target));
        break;
      default:
        if (info->op == rcx::Op::SetMotorPower && i == 0) {
          parts.push_back(motors(value));
        } else if (o.count > 1) {  // a key: only ever the sole operand, so values start at i
          std::string key;
          for (std::size_t k = i; k < i + o.count && k < d.v.size(); ++k) key += fmt::format("{}{}", key.empty() ? "" : " ", d.v[k]);
          parts.push_back("{" + key + "}");
        } else {
          parts.push_back(fmt::format("{}", value));
        }
        break;
    }
  }
  // Test-and-branch reads as "a <op> b, target".
  if (!compare_op.empty() && parts.size() == 3) parts = {parts[0] + " " + compare_op + " " + parts[1], parts[2]};
  out.text = std::string(info->mnemonic);
  for (std::size_t i = 0; i < parts.size(); ++i) out.text += (i == 0 ? " " : ", ") + parts[i];
  if (d.error == static_cast<std::uint8_t>(rcx::DecodeError::BadSource)) out.text += "  ; source not allowed";
  out.text += note;
  return out;
}

std::string format_line(std::span<const std::uint8_t> code, const Instruction& instruction) {
  std::string bytes;
  for (int i = 0; i < instruction.size; ++i)
    bytes += fmt::format("{}{:02x}", i ? " " : "", code[static_cast<std::size_t>(instruction.address + i)]);
  return fmt::format("{:04d}  {:<36} {}", instruction.address, instruction.text, bytes);
}

std::string disassemble(const rcx::Image& image) {
  std::string out;
  for (auto kind : {rcx::FragmentType::Task, rcx::FragmentType::Subroutine}) {
    bool task = kind == rcx::FragmentType::Task;
    for (int index = 0; index < (task ? rcx::kMaxTasks : rcx::kMaxSubroutines); ++index) {
      const rcx::Fragment* f = image.find(kind, index);
      if (f == nullptr) continue;
      std::string name =
          rcx::printable_name(image.name_of(task ? rcx::SymbolType::Task : rcx::SymbolType::Subroutine, index));
      out += fmt::format("{} {}{}{} ({} bytes)\n", task ? "task" : "sub", index, name.empty() ? "" : " ", name,
                         f->code.size());
      for (int at = 0; at < static_cast<int>(f->code.size());) {
        Instruction ins = format_instruction(f->code, at);
        out += format_line(f->code, ins) + "\n";
        at += ins.size;
      }
      out += "\n";
    }
  }
  return out;
}

}  // namespace rcxc::backend
