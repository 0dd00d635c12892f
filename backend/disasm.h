// The disassembler: turns RCX bytecode back into readable instructions by
// walking the opcode table (rcx/opcodes.h). `format_instruction` is the
// one-instruction formatter the compiler's listing reuses.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "rcx/image.h"

namespace rcxc::backend {

struct Instruction {
  int address = 0;
  int size = 1;          // bytes consumed (at least 1, even for bad bytes)
  std::string text;      // "mnemonic operands", e.g. "chk var[0] <= 10, 37"
  bool valid = true;     // false: not a program opcode, or truncated
};

// Decodes and formats the instruction at `address` of `code` (a task or
// subroutine body; branch targets are printed as absolute addresses).
Instruction format_instruction(std::span<const std::uint8_t> code, int address);

// One listing line: address, text, then the instruction's bytes in hex.
std::string format_line(std::span<const std::uint8_t> code, const Instruction& instruction);

// Every task and subroutine of the image, with names from its symbols.
std::string disassemble(const rcx::Image& image);

}  // namespace rcxc::backend
