#include "backend/absorb.h"

#include <algorithm>
#include <optional>

#include <fmt/format.h>

#include "backend/disasm.h"

namespace rcxc::backend {
namespace {

enum class Side { Before, After };

struct Site {
  std::size_t fragment;
  std::size_t call;  // index of the call instruction
};

constexpr std::uint8_t kConstantSource = 2;

bool calls(const MInstr& m, int sub) {
  return !m.raw && m.op == rcx::Op::CallSubroutine && m.bytes.size() == 2 && m.bytes[1] == sub;
}

std::vector<Site> call_sites(const std::vector<Selected>& fragments, int sub) {
  std::vector<Site> sites;
  for (std::size_t f = 0; f < fragments.size(); ++f)
    for (std::size_t i = 0; i < fragments[f].code.size(); ++i)
      if (calls(fragments[f].code[i], sub)) sites.push_back({f, i});
  return sites;
}

// The wait time of a constant wait, if `m` is one.
std::optional<int> constant_wait(const MInstr& m) {
  if (m.raw || m.op != rcx::Op::Wait || m.bytes.size() != 4 || m.bytes[1] != kConstantSource) return std::nullopt;
  return static_cast<std::int16_t>(m.bytes[2] | (m.bytes[3] << 8));
}

void set_wait(MInstr& m, int ticks) {
  m.bytes[2] = static_cast<std::uint8_t>(ticks & 0xff);
  m.bytes[3] = static_cast<std::uint8_t>((ticks >> 8) & 0xff);
}

// The neighbour of each call on `side` that could move, or nothing when
// one cannot: it must be a movable instruction, and no branch may enter
// between it and the call.
std::optional<std::vector<std::size_t>> neighbours(const std::vector<Selected>& fragments,
                                                   const std::vector<Site>& sites, Side side) {
  std::vector<std::size_t> at;
  std::vector<std::optional<Flow>> flows(fragments.size());  // once per fragment: a task may make many calls
  for (const Site& s : sites) {
    const Selected& frag = fragments[s.fragment];
    if (side == Side::Before && s.call == 0) return std::nullopt;
    std::size_t n = side == Side::Before ? s.call - 1 : s.call + 1;
    if (n >= frag.code.size() || !movable_into_subroutine(frag.code[n])) return std::nullopt;
    auto& flow = flows[s.fragment];
    if (!flow) flow = flow_of(frag);
    if (!flow->entered[side == Side::Before ? s.call : n].empty()) return std::nullopt;
    at.push_back(n);
  }
  return at;
}

// The instruction to move: the neighbours' own when all are equal, else
// the shortest constant wait when all are constant waits.
std::optional<MInstr> common_part(const std::vector<const MInstr*>& ns, WaitSplit waits) {
  if (std::all_of(ns.begin(), ns.end(), [&](const MInstr* m) { return m->bytes == ns[0]->bytes; })) return *ns[0];
  if (waits == WaitSplit::Never) return std::nullopt;
  const MInstr* shortest = nullptr;
  for (const MInstr* m : ns) {
    auto w = constant_wait(*m);
    if (!w || *w <= 0) return std::nullopt;
    if (!shortest || *w < *constant_wait(*shortest)) shortest = m;
  }
  return *shortest;
}

// Removes the instructions at `drop` (ascending); a branch to one of them
// goes to the instruction that followed it.
void erase(Selected& frag, const std::vector<std::size_t>& drop) {
  std::vector<MInstr> code;
  std::vector<int> map(frag.code.size() + 1, 0);
  std::size_t next = 0;
  for (std::size_t i = 0; i < frag.code.size(); ++i) {
    map[i] = static_cast<int>(code.size());
    if (next < drop.size() && drop[next] == i) {
      ++next;
      continue;
    }
    code.push_back(std::move(frag.code[i]));
  }
  map[frag.code.size()] = static_cast<int>(code.size());
  install_code(frag, std::move(code), map);
}

// Puts `m` first in the subroutine; its own branches keep their targets.
void prepend(Selected& sub, MInstr m) {
  for (auto& c : sub.code)
    if (c.target.block < 0 && c.target.instr >= 0) ++c.target.instr;
  for (int& b : sub.block_start) ++b;
  sub.code.insert(sub.code.begin(), std::move(m));
}

// Puts `m` last in the subroutine: what branched to the end (the return;
// a block or instruction index at the old end, since only tasks branch to
// kEndOfCode) now runs it first, as the caller did after the call.
void append(Selected& sub, MInstr m) { sub.code.push_back(std::move(m)); }

bool has_early_return(const Selected& sub) {
  return std::any_of(sub.code.begin(), sub.code.end(),
                     [](const MInstr& m) { return m.op == rcx::Op::ReturnFromSubroutine; });
}

// Moves one instruction into `sub` from beside its calls; false when that
// would not save bytes or is not possible.
bool absorb(std::vector<Selected>& fragments, Selected& sub, Side side, WaitSplit waits, std::vector<std::string>& log) {
  auto sites = call_sites(fragments, sub.index);
  if (sites.size() < 2 || (side == Side::After && has_early_return(sub))) return false;
  auto at = neighbours(fragments, sites, side);
  if (!at) return false;
  std::vector<const MInstr*> ns;
  for (std::size_t k = 0; k < sites.size(); ++k) ns.push_back(&fragments[sites[k].fragment].code[(*at)[k]]);
  auto moved = common_part(ns, waits);
  if (!moved) return false;
  auto whole = static_cast<int>(std::count_if(ns.begin(), ns.end(), [&](const MInstr* m) { return m->bytes == moved->bytes; }));
  int size = static_cast<int>(moved->bytes.size());
  int saved = (whole - 1) * size;
  if (saved <= 0) return false;

  std::vector<std::vector<std::size_t>> drop(fragments.size());
  for (std::size_t k = 0; k < sites.size(); ++k) {
    MInstr& m = fragments[sites[k].fragment].code[(*at)[k]];
    if (m.bytes == moved->bytes)
      drop[sites[k].fragment].push_back((*at)[k]);
    else
      set_wait(m, *constant_wait(m) - *constant_wait(*moved));
  }
  for (std::size_t f = 0; f < fragments.size(); ++f)
    if (!drop[f].empty()) erase(fragments[f], drop[f]);
  log.push_back(fmt::format("`{}` {} each call of sub {} moved into it ({} of {} calls had it whole; {} bytes saved)",
                            format_instruction(moved->bytes, 0).text, side == Side::Before ? "before" : "after",
                            sub.name, whole, sites.size(), saved));
  if (side == Side::Before)
    prepend(sub, std::move(*moved));
  else
    append(sub, std::move(*moved));
  return true;
}

}  // namespace

void absorb_call_neighbours(std::vector<Selected>& fragments, std::vector<std::string>& log, WaitSplit waits) {
  for (const auto& f : fragments)
    for (const auto& m : f.code)
      if (m.raw) return;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t s = 0; s < fragments.size(); ++s) {
      if (fragments[s].type != rcx::FragmentType::Subroutine) continue;
      for (Side side : {Side::Before, Side::After})
        while (absorb(fragments, fragments[s], side, waits, log)) changed = true;
    }
  }
}

}  // namespace rcxc::backend
