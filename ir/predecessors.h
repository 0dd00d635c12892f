// Every block's predecessors, for the passes that look at the edges into
// each block of a function.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "ir/ir.h"

namespace rcxc::ir {

// All the lists in one array: a vector per block was an allocation per
// block and pass, a third of a million on a 30 000-line program.
class PredecessorLists {
 public:
  // In block order. With `repeated_edges`, a block whose branch goes to
  // the same block both ways is listed twice there; without, once.
  PredecessorLists(const Function& f, bool repeated_edges);
  std::span<const BlockId> operator[](std::size_t b) const {
    return std::span<const BlockId>(from_).subspan(start_[b], start_[b + 1] - start_[b]);
  }

 private:
  std::vector<std::uint32_t> start_;  // block b's are from_[start_[b], start_[b + 1])
  std::vector<BlockId> from_;
};

}  // namespace rcxc::ir
