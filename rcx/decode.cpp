#include "rcx/decode.h"

namespace rcx {
namespace {

// The seed's target formulas. `at` is the address of the offset field.
int branch_target(Op op, int at, const std::array<int, 5>& v, int offset_index) {
  int off = v[static_cast<std::size_t>(offset_index)];
  switch (op) {
    case Op::BranchAlwaysNear:
      return (off & 0x80) ? at - off + 128 : at + off;
    case Op::BranchAlwaysFar: {
      int ext = v[static_cast<std::size_t>(offset_index) + 1];
      return (off & 0x80) ? at - off - 128 * ext + 128 : at + off + 128 * ext;
    }
    default:  // test-and-branch (signed) and loop decrement (unsigned): field value as read
      return at + off;
  }
}

}  // namespace

bool is_branch(Op op) {
  switch (op) {
    case Op::BranchAlwaysNear: case Op::BranchAlwaysFar: case Op::TestAndBranchNear:
    case Op::TestAndBranchFar: case Op::DecrementLoopCounterNear: case Op::DecrementLoopCounterFar:
      return true;
    default:
      return false;
  }
}

// Fixed-size opcodes with sources have count-1 fields.
int disallowed_source(const OpcodeInfo& info, const std::array<int, 5>& v) {
  for (std::size_t i = 0; i < info.operands.size() && i < v.size(); ++i) {
    const Operand& o = info.operands[i];
    int source = o.role == Role::OpSource ? (v[i] & 0x0f) : v[i];
    if ((o.role == Role::Source || o.role == Role::OpSource) && !allows(o.allowed, source)) return source;
  }
  return -1;
}

namespace {

// The opcode `info` at `address` of `code` with its operands, as the table
// lays them out; `d` holds the opcode byte's decoding so far (size 1).
Decoded with_operands(const OpcodeInfo& info, std::span<const std::uint8_t> code, int address, Decoded d) {
  d.op = info.op;
  int size = command_size(info).value_or(1);  // every command has a fixed size
  if (address + size > static_cast<int>(code.size())) {
    d.error = static_cast<std::uint8_t>(DecodeError::Truncated);
    return d;
  }
  d.size = static_cast<std::uint8_t>(size);
  int at = address + 1;
  std::size_t n = 0;
  int offset_index = -1, offset_at = 0;
  for (const auto& operand : info.operands) {
    for (int i = 0; i < operand.count && n < d.v.size(); ++i) {
      if (operand.role == Role::Offset) offset_index = static_cast<int>(n), offset_at = at;
      d.v[n++] = read_field(operand.type, code.data() + at);
      at += field_size(operand.type);
    }
  }
  if (d.error == 0 && disallowed_source(info, d.v) >= 0) d.error = static_cast<std::uint8_t>(DecodeError::BadSource);
  if (offset_index >= 0) d.target = branch_target(d.op, offset_at, d.v, offset_index);
  return d;
}

}  // namespace

Decoded decode_command(std::span<const std::uint8_t> code, int address) {
  Decoded d;
  d.size = 1;
  if (address < 0 || address >= static_cast<int>(code.size())) {
    d.error = static_cast<std::uint8_t>(DecodeError::Truncated);
    return d;
  }
  const OpcodeInfo* info = command_at(code[static_cast<std::size_t>(address)]);
  if (info == nullptr) {
    d.error = static_cast<std::uint8_t>(DecodeError::NotACommand);
    return d;
  }
  return with_operands(*info, code, address, d);
}

std::optional<Decoded> decode_request(std::span<const std::uint8_t> code, int address) {
  if (address < 0 || address >= static_cast<int>(code.size())) return std::nullopt;
  const OpcodeInfo* info = request_at(code[static_cast<std::size_t>(address)]);
  // Transfer data's size depends on its length field: not listed.
  if (info == nullptr || info->is_command() || !command_size(*info)) return std::nullopt;
  Decoded d;
  d.size = 1;
  d.error = static_cast<std::uint8_t>(DecodeError::NotACommand);
  d = with_operands(*info, code, address, d);
  return d;
}

const char* to_string(DecodeError error) {
  switch (error) {
    case DecodeError::None: return "ok";
    case DecodeError::NotACommand: return "not a program opcode";
    case DecodeError::Truncated: return "instruction runs past the end of the code";
    case DecodeError::BadSource: return "source not allowed for this opcode";
  }
  return "?";
}

}  // namespace rcx
