// Encoding one instruction through the opcode table.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rcx/opcodes.h"

namespace rcxc::backend {

// Appends `op` and its operands to `out`. `values` holds one value per
// operand field in table order (a repeated field takes `count` values).
// Returns an error text when a value does not fit its field or a source is
// not allowed for that operand; nothing is appended then.
std::string encode(const rcx::OpcodeInfo& op, std::span<const int> values, std::vector<std::uint8_t>& out);

}  // namespace rcxc::backend
