#include "backend/branch.h"

#include <fmt/format.h>

#include "backend/encode.h"

namespace rcxc::backend {

rcx::Op branch_op(const MInstr& m) {
  switch (m.kind) {
    case MInstr::Kind::Jump: return m.far ? rcx::Op::BranchAlwaysFar : rcx::Op::BranchAlwaysNear;
    case MInstr::Kind::Test: return m.far ? rcx::Op::TestAndBranchFar : rcx::Op::TestAndBranchNear;
    case MInstr::Kind::Loop: return m.far ? rcx::Op::DecrementLoopCounterFar : rcx::Op::DecrementLoopCounterNear;
    case MInstr::Kind::Fixed: break;
  }
  return m.op;
}

int offset_origin(rcx::Op op) {
  int at = 1;  // the opcode byte
  for (const auto& operand : rcx::info(op).operands) {
    if (operand.role == rcx::Role::Offset) return at;
    at += rcx::field_size(operand.type) * operand.count;
  }
  return at;
}

// Reach of each branch form, from the seed's target address formulas:
// branch always: bit 7 of the offset byte selects backward, the far form
// adds 128 x extension; test-and-branch: signed offset; loop counter:
// unsigned offset, forward only.
bool reaches(rcx::Op op, int origin, int target) {
  int rel = target - origin;
  switch (op) {
    case rcx::Op::BranchAlwaysNear: return rel >= -127 && rel <= 127;
    case rcx::Op::BranchAlwaysFar: return rel >= -(127 + 128 * 255) && rel <= 127 + 128 * 255;
    case rcx::Op::TestAndBranchNear: return rel >= -128 && rel <= 127;
    case rcx::Op::TestAndBranchFar: return rel >= -32768 && rel <= 32767;
    case rcx::Op::DecrementLoopCounterNear: return rel >= 0 && rel <= 255;
    case rcx::Op::DecrementLoopCounterFar: return rel >= 0 && rel <= 65535;
    default: return false;
  }
}

std::vector<int> offset_fields(rcx::Op op, int origin, int target) {
  int rel = target - origin;
  switch (op) {
    case rcx::Op::BranchAlwaysNear: return {rel >= 0 ? rel : 128 - rel};
    case rcx::Op::BranchAlwaysFar:
      if (rel >= 0) return {rel % 128, rel / 128};
      return {128 + (-rel) % 128, (-rel) / 128};
    default: return {rel};
  }
}

namespace {

int size_of(const MInstr& m) {
  if (m.kind == MInstr::Kind::Fixed) return static_cast<int>(m.bytes.size());
  return rcx::command_size(rcx::info(branch_op(m))).value_or(0);
}

int target_address(const MInstr& m, const std::vector<int>& address, const std::vector<int>& block_start, int end) {
  if (m.target.block == kEndOfCode) return end;
  std::size_t i = m.target.block >= 0 ? static_cast<std::size_t>(block_start[static_cast<std::size_t>(m.target.block)])
                                      : static_cast<std::size_t>(m.target.instr);
  return i < address.size() ? address[i] : end;
}

}  // namespace

std::string assemble(std::vector<MInstr>& code, const std::vector<int>& block_start, std::vector<std::uint8_t>& bytes,
                     std::vector<Emitted>& listing) {
  std::vector<int> address(code.size(), 0);
  int end = 0;
  // Branches only ever grow, so this reaches a fixed point.
  for (bool changed = true; changed;) {
    changed = false;
    end = 0;
    for (std::size_t i = 0; i < code.size(); ++i) {
      address[i] = end;
      end += size_of(code[i]);
    }
    for (std::size_t i = 0; i < code.size(); ++i) {
      MInstr& m = code[i];
      if (m.kind == MInstr::Kind::Fixed || m.far) continue;
      rcx::Op op = branch_op(m);
      if (!reaches(op, address[i] + offset_origin(op), target_address(m, address, block_start, end))) {
        m.far = true;
        changed = true;
      }
    }
  }
  bytes.reserve(bytes.size() + static_cast<std::size_t>(end));
  listing.reserve(listing.size() + code.size());
  std::vector<int> values;  // a branch's fields, reused
  for (std::size_t i = 0; i < code.size(); ++i) {
    MInstr& m = code[i];
    if (m.kind != MInstr::Kind::Fixed) {
      rcx::Op op = branch_op(m);
      int origin = address[i] + offset_origin(op);
      int target = target_address(m, address, block_start, end);
      if (!reaches(op, origin, target))
        return fmt::format("a branch at byte {} cannot reach byte {} ({})", address[i], target,
                           m.kind == MInstr::Kind::Loop ? "loop counters only branch forward" : "too far");
      values.assign(m.values.begin(), m.values.end());
      for (int v : offset_fields(op, origin, target)) values.push_back(v);
      m.bytes.clear();
      std::string err = encode(rcx::info(op), values, m.bytes);
      if (!err.empty()) return err;
    }
    bytes.insert(bytes.end(), m.bytes.begin(), m.bytes.end());
    // Moved, not copied: an allocation per instruction of the program.
    listing.push_back({address[i], std::move(m.bytes), m.span});
  }
  return {};
}

}  // namespace rcxc::backend
