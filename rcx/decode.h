// Decoding one instruction of program bytecode through the opcode table:
// the emulator runs what this returns, and the disassembler prints it, so
// both read the same bytes the same way.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "rcx/opcodes.h"

namespace rcx {

// The decoded form of one instruction, cached per byte address.
struct Decoded {
  Op op = Op::Alive;
  std::uint8_t size = 0;          // 0 = not decoded yet
  // Why the bytes there cannot run: 0 fine, else a DecodeError.
  std::uint8_t error = 0;
  std::array<int, 5> v{};         // operand values in table order
  int target = 0;                 // branch target for branch opcodes
};

enum class DecodeError : std::uint8_t { None = 0, NotACommand, Truncated, BadSource };

// Decodes the command at `address` of `code` by walking the opcode table;
// branch targets are resolved with the seed's formulas (they may lie outside
// the code: the machine faults only when such a branch is taken).
Decoded decode_command(std::span<const std::uint8_t> code, int address);
const char* to_string(DecodeError error);

// A request-only opcode (Kind::Request, in either toggle form: Upload
// datalog 0xa4/0xac, Alive, Get value, ...) at `address` of program
// bytecode, where an asm block can put one, decoded with the request's
// operand layout for listings: error NotACommand (the brick runs no such
// instruction; the emulator stops there) or Truncated. nullopt for any
// other byte and for Transfer data, whose size its own bytes give. Not for running: decode_command() is what a task executes.
std::optional<Decoded> decode_request(std::span<const std::uint8_t> code, int address);

// Whether `op` is one of the branch opcodes (its operands hold an offset).
bool is_branch(Op op);

// The first source operand of `v` (operand values in table order) outside
// the sources the opcode allows, or -1.
int disallowed_source(const OpcodeInfo& info, const std::array<int, 5>& v);

}  // namespace rcx
