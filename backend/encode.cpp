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
  // Written straight into `out`, grown once; on an error `out` is cut back
  // to what it held.
  const std::size_t start = out.size();
  std::size_t size = 1;
  for (const auto& operand : op.operands)
    size += static_cast<std::size_t>(rcx::field_size(operand.type)) * operand.count;
  out.reserve(start + size);
  out.push_back(op.code);
  auto fail = [&](std::string message) {
    out.resize(start);
    return message;
  };
  std::size_t next = 0;
  for (const auto& operand : op.operands) {
    if (operand.role == rcx::Role::Data)
      return fail(fmt::format("{}: variable-length operands are not encoded here", op.mnemonic));
    for (int i = 0; i < operand.count; ++i) {
      if (next >= values.size()) return fail(fmt::format("{}: missing operand '{}'", op.mnemonic, operand.name));
      int v = values[next++];
      if (!fits(operand.type, v))
        return fail(fmt::format("{}: operand '{}' value {} does not fit", op.mnemonic, operand.name, v));
      int source = operand.role == rcx::Role::OpSource ? (v & 0x0f) : v;
      if ((operand.role == rcx::Role::Source || operand.role == rcx::Role::OpSource) &&
          !rcx::allows(operand.allowed, source))
        return fail(fmt::format("{}: source {} ({}) is not allowed for operand '{}'", op.mnemonic, source,
                                rcx::source_name(source), operand.name));
      std::size_t at = out.size();
      out.resize(at + static_cast<std::size_t>(rcx::field_size(operand.type)));
      rcx::write_field(operand.type, v, out.data() + at);
    }
  }
  if (next != values.size())
    return fail(fmt::format("{}: {} operands given, {} expected", op.mnemonic, values.size(), next));
  return {};
}

}  // namespace rcxc::backend
