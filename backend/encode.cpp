#include "backend/encode.h"

#include <fmt/format.h>

namespace rcxc::backend {
namespace {

// The encoder takes a value in either reading of the field's bits (signed
// or unsigned): whether an operand is in its legal range is the caller's
// check (ir::fits_field); here only the bit width matters.
bool fits(rcx::FieldType t, int v) {
  const int bits = 8 * rcx::field_size(t);
  return v >= -(1 << (bits - 1)) && v < (1 << bits);
}

}  // namespace

std::string encode(const rcx::OpcodeInfo& op, std::span<const int> values, std::vector<std::uint8_t>& out) {
  std::vector<std::uint8_t> bytes{op.code};
  std::size_t next = 0;
  for (const auto& operand : op.operands) {
    if (operand.role == rcx::Role::Data)
      return fmt::format("{}: variable-length operands are not encoded here", op.mnemonic);
    for (int i = 0; i < operand.count; ++i) {
      if (next >= values.size()) return fmt::format("{}: missing operand '{}'", op.mnemonic, operand.name);
      int v = values[next++];
      if (!fits(operand.type, v))
        return fmt::format("{}: operand '{}' value {} does not fit", op.mnemonic, operand.name, v);
      int source = operand.role == rcx::Role::OpSource ? (v & 0x0f) : v;
      if ((operand.role == rcx::Role::Source || operand.role == rcx::Role::OpSource) &&
          !rcx::allows(operand.allowed, source))
        return fmt::format("{}: source {} ({}) is not allowed for operand '{}'", op.mnemonic, source,
                           rcx::source_name(source), operand.name);
      std::size_t at = bytes.size();
      bytes.resize(at + static_cast<std::size_t>(rcx::field_size(operand.type)));
      rcx::write_field(operand.type, v, bytes.data() + at);
    }
  }
  if (next != values.size()) return fmt::format("{}: {} operands given, {} expected", op.mnemonic, values.size(), next);
  out.insert(out.end(), bytes.begin(), bytes.end());
  return {};
}

}  // namespace rcxc::backend
