#include "backend/outline.h"

#include <algorithm>
#include <map>

#include <fmt/format.h>

namespace rcxc::backend {
namespace {

constexpr std::size_t kMaxSequence = 24;  // instructions per outlined sequence
constexpr int kCallBytes = 2;
constexpr int kReturnBytes = 1;  // appended by the firmware to every subroutine

bool outlinable(const MInstr& m) {
  if (m.kind != MInstr::Kind::Fixed || m.raw) return false;
  switch (m.op) {
    case rcx::Op::CallSubroutine:
    case rcx::Op::ReturnFromSubroutine:
    case rcx::Op::SetLoopCounter: return false;
    default: return true;
  }
}

struct Occurrence {
  std::size_t fragment;
  std::size_t start;
};

struct Candidate {
  std::vector<Occurrence> places;  // non-overlapping
  std::size_t length = 0;          // instructions
  int bytes = 0;
  int saving() const {
    auto n = static_cast<int>(places.size());
    return n * bytes - (kCallBytes * n + bytes + kReturnBytes);
  }
};

std::vector<bool> block_starts(const Selected& f) {
  std::vector<bool> starts(f.code.size() + 1, false);
  for (int b : f.block_start)
    if (b >= 0 && static_cast<std::size_t>(b) < starts.size()) starts[static_cast<std::size_t>(b)] = true;
  return starts;
}

// Every repeated sequence and where it occurs, keyed by its bytes.
Candidate best_candidate(const std::vector<Selected>& fragments) {
  std::map<std::string, Candidate> seen;
  for (std::size_t f = 0; f < fragments.size(); ++f) {
    const Selected& frag = fragments[f];
    if (frag.type != rcx::FragmentType::Task) continue;
    auto starts = block_starts(frag);
    for (std::size_t i = 0; i < frag.code.size(); ++i) {
      std::string key;
      int bytes = 0;
      for (std::size_t len = 1; len <= kMaxSequence && i + len <= frag.code.size(); ++len) {
        const MInstr& m = frag.code[i + len - 1];
        if (!outlinable(m) || (len > 1 && starts[i + len - 1])) break;
        key.append(m.bytes.begin(), m.bytes.end());
        key.push_back('\x7f');  // instruction boundary
        bytes += static_cast<int>(m.bytes.size());
        Candidate& c = seen[key];
        c.length = len;
        c.bytes = bytes;
        bool overlaps = !c.places.empty() && c.places.back().fragment == f && c.places.back().start + len > i;
        if (!overlaps) c.places.push_back({f, i});
      }
    }
  }
  Candidate best;
  for (auto& [key, c] : seen)
    if (c.places.size() > 1 && (c.saving() > best.saving() || (c.saving() == best.saving() && c.length > best.length)))
      best = c;
  return best;
}

// Replaces the sequences of `length` instructions at `starts` (ascending,
// not overlapping) by calls of subroutine `sub`, in one pass.
void replace(Selected& frag, const std::vector<std::size_t>& starts, std::size_t length, int sub) {
  std::vector<MInstr> code;
  std::vector<int> map(frag.code.size() + 1, 0);  // old index -> new index
  std::size_t next = 0;
  for (std::size_t i = 0; i < frag.code.size();) {
    map[i] = static_cast<int>(code.size());
    if (next < starts.size() && starts[next] == i) {
      MInstr call;
      call.op = rcx::Op::CallSubroutine;
      call.bytes = {rcx::info(rcx::Op::CallSubroutine).code, static_cast<std::uint8_t>(sub)};
      call.span = frag.code[i].span;
      for (std::size_t k = 1; k < length; ++k) map[i + k] = static_cast<int>(code.size());
      code.push_back(std::move(call));
      i += length;
      ++next;
    } else {
      code.push_back(std::move(frag.code[i++]));
    }
  }
  map[frag.code.size()] = static_cast<int>(code.size());
  for (int& b : frag.block_start) b = map[static_cast<std::size_t>(b)];
  for (auto& m : code)
    if (m.target.block < 0 && m.target.instr >= 0) m.target.instr = map[static_cast<std::size_t>(m.target.instr)];
  frag.code = std::move(code);
}

}  // namespace

void outline(std::vector<Selected>& fragments, std::vector<std::string>& log) {
  auto subs = static_cast<int>(std::count_if(fragments.begin(), fragments.end(),
                                             [](const Selected& s) { return s.type == rcx::FragmentType::Subroutine; }));
  int next_index = 0;
  for (const auto& s : fragments)
    if (s.type == rcx::FragmentType::Subroutine) next_index = std::max(next_index, s.index + 1);
  while (subs < kMaxSubroutines) {
    Candidate c = best_candidate(fragments);
    if (c.places.size() < 2 || c.saving() <= 0) break;
    Selected sub;
    sub.type = rcx::FragmentType::Subroutine;
    sub.index = next_index++;
    sub.name = fmt::format("__outlined{}", sub.index);
    const Selected& first = fragments[c.places[0].fragment];
    sub.code.assign(first.code.begin() + static_cast<long>(c.places[0].start),
                    first.code.begin() + static_cast<long>(c.places[0].start + c.length));
    sub.block_start = {0};
    log.push_back(fmt::format("{} copies of a {}-byte sequence outlined into sub {} ({} bytes saved)", c.places.size(),
                              c.bytes, sub.index, c.saving()));
    std::map<std::size_t, std::vector<std::size_t>> by_fragment;
    for (const auto& o : c.places) by_fragment[o.fragment].push_back(o.start);
    for (auto& [f, starts] : by_fragment) {
      std::sort(starts.begin(), starts.end());
      replace(fragments[f], starts, c.length, sub.index);
    }
    fragments.push_back(std::move(sub));
    ++subs;
  }
}

}  // namespace rcxc::backend
