#include "backend/outline.h"

#include <algorithm>
#include <charconv>
#include <map>

#include <fmt/format.h>

namespace rcxc::backend {

// A loop counter may move into a subroutine: the counters are the task's,
// and a subroutine runs on its caller's, at the depth the call is made, so
// an outlined loop nests exactly as deep as it did in place.
bool movable_into_subroutine(const MInstr& m) {
  if (m.raw || is_branch(m)) return false;
  switch (m.op) {
    case rcx::Op::CallSubroutine:
    case rcx::Op::ReturnFromSubroutine: return false;
    default: return true;
  }
}

int target_index(const Selected& f, const Target& t) {
  if (t.block == kEndOfCode) return static_cast<int>(f.code.size());
  if (t.block >= 0) return f.block_start[static_cast<std::size_t>(t.block)];
  return t.instr;
}

void install_code(Selected& frag, std::vector<MInstr> code, const std::vector<int>& map) {
  for (int& b : frag.block_start) b = map[static_cast<std::size_t>(b)];
  for (auto& m : code)
    if (m.target.block < 0 && m.target.instr >= 0) m.target.instr = map[static_cast<std::size_t>(m.target.instr)];
  frag.code = std::move(code);
}

Flow flow_of(const Selected& f) {
  Flow flow;
  flow.target.assign(f.code.size(), -1);
  flow.entered.resize(f.code.size() + 1);
  for (std::size_t i = 0; i < f.code.size(); ++i) {
    if (!is_branch(f.code[i])) continue;
    int t = target_index(f, f.code[i].target);
    flow.target[i] = t;
    flow.entered[static_cast<std::size_t>(t)].push_back(static_cast<int>(i));
  }
  return flow;
}

namespace {

constexpr std::size_t kMaxSequence = 24;  // instructions looked at from each start (grow() goes on)
constexpr int kCallBytes = 2;
constexpr int kReturnBytes = 1;  // appended by the firmware to every subroutine

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

int size_estimate(const MInstr& m) {
  if (!is_branch(m)) return static_cast<int>(m.bytes.size());
  return rcx::command_size(rcx::info(branch_op(m))).value_or(0);
}

void append_number(std::string& out, int n) {
  char digits[16];
  auto end = std::to_chars(digits, digits + sizeof digits, n).ptr;
  out.append(digits, end);
}

// Every repeated sequence and where it occurs, keyed by what it does.
Candidate best_candidate(const std::vector<Selected>& fragments) {
  // Sorted (a hash map takes fewer instructions but misses the cache on
  // nearly every one of the (start, length) pairs: slower on long code).
  std::map<std::string, Candidate> seen;
  for (std::size_t f = 0; f < fragments.size(); ++f) {
    const Selected& frag = fragments[f];
    if (frag.type != rcx::FragmentType::Task) continue;
    Flow flow = flow_of(frag);
    for (std::size_t i = 0; i < frag.code.size(); ++i) {
      // A sequence [i, end) can be outlined when its branches stay inside
      // it or go just past it (they are copied with it and keyed by
      // distance, so equal keys behave the same wherever they are) and no
      // branch from outside enters it after its first instruction (one
      // entering the first reaches the call instead). `need_end` is how far the sequence must
      // reach for both to hold.
      std::string key;
      int bytes = 0;
      std::size_t need_end = 0;
      for (std::size_t len = 1; len <= kMaxSequence && i + len <= frag.code.size(); ++len) {
        std::size_t k = i + len - 1;
        const MInstr& m = frag.code[k];
        if (!is_branch(m)) {
          if (!movable_into_subroutine(m)) break;
          key.append(m.bytes.begin(), m.bytes.end());
        } else {
          int t = flow.target[k];
          if (t < static_cast<int>(i)) break;
          // A branch just past the sequence (a loop's exit when the loop
          // ends it) becomes a branch to the subroutine's end: its return
          // goes on after the call, where the branch went.
          need_end = std::max(need_end, static_cast<std::size_t>(t));
          // "<kind values,... distance>", written without a format call
          // per (start, length) pair.
          key.push_back('<');
          append_number(key, static_cast<int>(m.kind));
          key.push_back(' ');
          for (std::size_t v = 0; v < m.values.size(); ++v) {
            if (v > 0) key.push_back(',');
            append_number(key, m.values[v]);
          }
          key.push_back(' ');
          append_number(key, t - static_cast<int>(i));
          key.push_back('>');
        }
        key.push_back('\x7f');  // instruction boundary
        bytes += size_estimate(m);
        if (k > i) {
          bool entered_before = false;
          for (int from : flow.entered[k]) {
            entered_before |= from < static_cast<int>(i);
            need_end = std::max(need_end, static_cast<std::size_t>(std::max(from, 0)) + 1);
          }
          if (entered_before) break;
        }
        if (i + len < need_end) continue;
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

// Whether instruction `k` of every place (at `offset` from its start) is
// the same: equal bytes, or branches of one kind and values going equally
// far from the place's start.
bool same_at(const std::vector<Selected>& fragments, const std::vector<Flow>& flows,
             const std::vector<Occurrence>& places, std::size_t offset) {
  const Occurrence& first = places.front();
  const MInstr& a = fragments[first.fragment].code[first.start + offset];
  for (const Occurrence& o : places) {
    const MInstr& b = fragments[o.fragment].code[o.start + offset];
    if (is_branch(a) != is_branch(b)) return false;
    if (!is_branch(a)) {
      if (a.bytes != b.bytes) return false;
      continue;
    }
    int ta = flows[first.fragment].target[first.start + offset] - static_cast<int>(first.start);
    int tb = flows[o.fragment].target[o.start + offset] - static_cast<int>(o.start);
    if (a.kind != b.kind || a.values != b.values || ta != tb) return false;
  }
  return true;
}

// Whether [start, end) of a fragment, already outlinable as [start + 1,
// end) or [start, end - 1), stays so with instruction `added` (start or
// end - 1) in it: movable, or a branch staying inside or going just past
// the end, and the instruction it grew over (the old first one, or the
// one just past the old end) entered only from inside.
bool still_outlinable(const Selected& frag, const Flow& flow, std::size_t start, std::size_t end, std::size_t added) {
  const MInstr& m = frag.code[added];
  if (is_branch(m)) {
    int t = flow.target[added];
    if (t < static_cast<int>(start) || t > static_cast<int>(end)) return false;
  } else if (!movable_into_subroutine(m)) {
    return false;
  }
  std::size_t inner = added == start ? start + 1 : added;  // no longer the first instruction
  if (inner == start || inner >= end) return true;
  return std::all_of(flow.entered[inner].begin(), flow.entered[inner].end(), [&](int from) {
    return from >= static_cast<int>(start) && from < static_cast<int>(end);
  });
}

// Grows the chosen sequence over what all its places share before and
// after it: best_candidate looks at most kMaxSequence instructions from a
// start, but a song or routine written out twice may be longer, and the
// longer it is, the more each copy saves. A place stops growing where it
// would reach the next one.
void grow(const std::vector<Selected>& fragments, Candidate& c) {
  std::vector<Flow> flows(fragments.size());
  for (const Occurrence& o : c.places)
    if (flows[o.fragment].target.empty()) flows[o.fragment] = flow_of(fragments[o.fragment]);
  // Places are in program order: a place may grow up to the next one in
  // the same fragment (after) or the previous one (before).
  auto room_after = [&](std::size_t p) {
    const Occurrence& o = c.places[p];
    std::size_t limit = fragments[o.fragment].code.size();
    if (p + 1 < c.places.size() && c.places[p + 1].fragment == o.fragment) limit = c.places[p + 1].start;
    return o.start + c.length < limit;
  };
  auto room_before = [&](std::size_t p) {
    const Occurrence& o = c.places[p];
    std::size_t limit = p > 0 && c.places[p - 1].fragment == o.fragment ? c.places[p - 1].start + c.length : 0;
    return o.start > limit;
  };
  for (bool grew = true; grew;) {
    grew = false;
    bool forward = true;
    for (std::size_t p = 0; p < c.places.size() && forward; ++p) {
      const Occurrence& o = c.places[p];
      forward = room_after(p) && still_outlinable(fragments[o.fragment], flows[o.fragment], o.start,
                                                  o.start + c.length + 1, o.start + c.length);
    }
    if (forward && same_at(fragments, flows, c.places, c.length)) {
      const Occurrence& o = c.places.front();
      c.bytes += size_estimate(fragments[o.fragment].code[o.start + c.length]);
      ++c.length;
      grew = true;
      continue;
    }
    bool backward = true;
    for (std::size_t p = 0; p < c.places.size() && backward; ++p) {
      const Occurrence& o = c.places[p];
      backward = room_before(p) && still_outlinable(fragments[o.fragment], flows[o.fragment], o.start - 1,
                                                    o.start + c.length, o.start - 1);
    }
    if (!backward) break;
    for (auto& o : c.places) --o.start;
    if (!same_at(fragments, flows, c.places, 0)) {
      for (auto& o : c.places) ++o.start;
      break;
    }
    const Occurrence& o = c.places.front();
    c.bytes += size_estimate(fragments[o.fragment].code[o.start]);
    ++c.length;
    grew = true;
  }
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
  install_code(frag, std::move(code), map);
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
    grow(fragments, c);
    Selected sub;
    sub.type = rcx::FragmentType::Subroutine;
    sub.index = next_index++;
    sub.name = fmt::format("__outlined{}", sub.index);
    const Selected& first = fragments[c.places[0].fragment];
    Flow flow = flow_of(first);
    for (std::size_t k = c.places[0].start; k < c.places[0].start + c.length; ++k) {
      MInstr m = first.code[k];
      if (is_branch(m)) m.target = Target{-1, flow.target[k] - static_cast<int>(c.places[0].start)};
      sub.code.push_back(std::move(m));
    }
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
