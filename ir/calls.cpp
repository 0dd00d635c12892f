// Subroutine calls versus the firmware's single return address (see passes.h).
#include <algorithm>
#include <iterator>
#include <map>
#include <fmt/format.h>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

constexpr int kCallSize = 2;  // call opcode + index
// A subroutine with its calls inlined may be this big before the passes
// that shrink it (outlining, rerolling) run: twenty times the RCX's program
// memory. Past that, doubling chains of calls take seconds per link.
constexpr long long kMaxFlattenedBytes = 131072;

std::vector<FuncId> callees(const Function& f) {
  std::vector<FuncId> out;
  for (const auto& b : f.blocks)
    for (const auto& in : b.instrs)
      if (FuncId g = callee_of(in); g >= 0 && std::find(out.begin(), out.end(), g) == out.end()) out.push_back(g);
  return out;
}

// Depth-first search for a call cycle; fills `cycle` with the names on it.
bool find_cycle(const Program& p, FuncId f, std::vector<int>& state, std::vector<FuncId>& stack,
                std::vector<std::string>& cycle) {
  state[static_cast<std::size_t>(f)] = 1;
  stack.push_back(f);
  for (FuncId g : callees(p.functions[static_cast<std::size_t>(f)])) {
    if (state[static_cast<std::size_t>(g)] == 1) {
      auto from = std::find(stack.begin(), stack.end(), g);
      for (auto it = from; it != stack.end(); ++it) cycle.push_back(p.functions[static_cast<std::size_t>(*it)].name);
      cycle.push_back(p.functions[static_cast<std::size_t>(g)].name);
      return true;
    }
    if (state[static_cast<std::size_t>(g)] == 0 && find_cycle(p, g, state, stack, cycle)) return true;
  }
  stack.pop_back();
  state[static_cast<std::size_t>(f)] = 2;
  return false;
}

bool report_recursion(const Program& p, Diagnostics& diags) {
  std::vector<int> state(p.functions.size(), 0);
  for (std::size_t f = 0; f < p.functions.size(); ++f) {
    std::vector<FuncId> stack;
    std::vector<std::string> cycle;
    if (state[f] == 0 && find_cycle(p, static_cast<FuncId>(f), state, stack, cycle)) {
      std::string path;
      for (const auto& name : cycle) path += (path.empty() ? "" : " -> ") + name;
      const Function& first = p.functions[static_cast<std::size_t>(p.find_function(cycle.front()))];
      auto& e = diags.error(first.span, fmt::format("recursive subroutine calls are not possible on the RCX: {}", path));
      // A note at each step's call: a call made inside an inline function
      // carries the place of that function's call (`s -> s` through `void
      // f() { s(); }` points at the `f()` in s), which shows the way.
      for (std::size_t k = 0; k + 1 < cycle.size(); ++k) {
        const Function& caller = p.functions[static_cast<std::size_t>(p.find_function(cycle[k]))];
        FuncId callee = p.find_function(cycle[k + 1]);
        for (const auto& b : caller.blocks) {
          auto call = std::find_if(b.instrs.begin(), b.instrs.end(), [&](const Instr& in) { return callee_of(in) == callee; });
          if (call == b.instrs.end()) continue;
          e.notes.push_back({p.span(call->span), fmt::format("'{}' calls '{}' here", cycle[k], cycle[k + 1])});
          break;
        }
      }
      return true;
    }
  }
  return false;
}

// Replaces the calls of `caller` that `chosen(block, index, callee)` picks
// by copies of their callees, in one pass over the function: a block split
// at its calls, each copy laid out right after its call and followed by the
// rest of the block. The same program as replacing them one at a time in
// layout order (blocks, variables and loops numbered alike), but each call
// no longer costs a renumbering of the whole function and a new liveness of
// every subroutine: a task with thousands of calls took the square.
template <class Chosen>
void inline_calls(Program& p, FuncId caller, Chosen&& chosen) {
  struct Site {
    BlockId block;
    std::size_t index;
    FuncId callee;
  };
  std::vector<Site> sites;
  {
    const Function& f = p.functions[static_cast<std::size_t>(caller)];
    for (std::size_t b = 0; b < f.blocks.size(); ++b)
      for (std::size_t i = 0; i < f.blocks[b].instrs.size(); ++i)
        if (FuncId g = callee_of(f.blocks[b].instrs[i]); g >= 0 && g != caller && chosen(static_cast<BlockId>(b), i, g))
          sites.push_back({static_cast<BlockId>(b), i, g});
  }
  if (sites.empty()) return;
  // The callees call nothing by now (flattened first), so what each keeps
  // from one call to the next is the same before and after every copy.
  const CallEffects effects = call_effects(p);
  Function& f = p.functions[static_cast<std::size_t>(caller)];
  std::vector<Block> old = std::move(f.blocks);
  // Where each old block starts in the new order.
  std::vector<BlockId> map(old.size());
  BlockId total = 0;
  for (std::size_t b = 0, s = 0; b < old.size(); ++b) {
    map[b] = total++;
    for (; s < sites.size() && sites[s].block == static_cast<BlockId>(b); ++s)
      total += static_cast<BlockId>(p.functions[static_cast<std::size_t>(sites[s].callee)].blocks.size()) + 1;
  }
  std::vector<Repeat> repeats = std::move(f.repeats);
  for (auto& r : repeats) {
    r.setup = map[static_cast<std::size_t>(r.setup)];
    r.head = map[static_cast<std::size_t>(r.head)];
  }
  f.blocks.clear();
  f.blocks.reserve(static_cast<std::size_t>(total));
  f.repeats.clear();
  std::vector<Repeat> copied_repeats;
  std::size_t s = 0;
  for (std::size_t b = 0; b < old.size(); ++b) {
    Block& from = old[b];
    Terminator term = from.term;
    map_targets(term, map);
    if (s == sites.size() || sites[s].block != static_cast<BlockId>(b)) {
      from.term = term;
      f.blocks.push_back(std::move(from));
      continue;
    }
    BlockId segment = map[b];  // the block holding the instructions before the next call
    std::size_t begin = 0;     // the first instruction of that segment
    for (; s < sites.size() && sites[s].block == static_cast<BlockId>(b); ++s) {
      const Instr& call = from.instrs[sites[s].index];
      const Function& callee = p.functions[static_cast<std::size_t>(sites[s].callee)];
      auto base = static_cast<BlockId>(f.blocks.size()) + 1;
      auto rest = base + static_cast<BlockId>(callee.blocks.size());
      Block head;
      head.instrs.assign(std::make_move_iterator(from.instrs.begin() + static_cast<long>(begin)),
                         std::make_move_iterator(from.instrs.begin() + static_cast<long>(sites[s].index)));
      head.term = Jump{base};
      head.span = from.span;
      f.blocks.push_back(std::move(head));
      // The copy gets its own locals and temporaries: copies in two tasks
      // must not share them, and a call's locals start afresh anyway.
      // Except a local the subroutine reads before writing: the called
      // subroutine keeps it from one call to the next, so every copy keeps
      // that one variable too and inlining does not change what the
      // program computes.
      const VarSet& kept = effects.reads[static_cast<std::size_t>(sites[s].callee)];
      std::map<VarId, VarId> fresh;
      auto own = [&](Operand& a) {
        if (!a.is_var()) return;
        const Var& v = p.vars[static_cast<std::size_t>(a.value)];
        if (v.kind == VarKind::Global || v.slot || kept.has(a.value)) return;
        auto [it, added] = fresh.try_emplace(a.value, 0);
        if (added) it->second = p.add_var(v.name, v.kind, v.span);
        a.value = it->second;
      };
      for (const auto& cb : callee.blocks) {
        Block copy = cb;
        for (auto& in : copy.instrs) {
          if (p.span(in.span).begin.line == 0) in.span = call.span;
          for (auto& a : in.args) own(a);
        }
        if (auto* br = std::get_if<Branch>(&copy.term)) {
          own(br->a);
          own(br->b);
        }
        if (std::holds_alternative<Exit>(copy.term)) {
          copy.term = Jump{rest};
        } else {
          offset_targets(copy.term, base);
        }
        f.blocks.push_back(std::move(copy));
      }
      append_repeats(f, callee.repeats, base);
      for (auto& r : f.repeats) copied_repeats.push_back(r);
      f.repeats.clear();
      // A loop whose setup block is split keeps its loopset, the block's
      // last instruction, in the last part that has instructions.
      if (sites[s].index + 1 < from.instrs.size())
        for (auto& r : repeats)
          if (r.setup == segment) r.setup = rest;
      segment = rest;
      begin = sites[s].index + 1;
    }
    Block tail;
    tail.instrs.assign(std::make_move_iterator(from.instrs.begin() + static_cast<long>(begin)),
                       std::make_move_iterator(from.instrs.end()));
    tail.term = term;
    tail.span = from.span;
    f.blocks.push_back(std::move(tail));
  }
  f.repeats = std::move(repeats);
  f.repeats.insert(f.repeats.end(), copied_repeats.begin(), copied_repeats.end());
}

// Inlines every call in `f` (callees first), so the subroutine calls nothing.
void flatten(Program& p, FuncId f, std::vector<bool>& done, Log& log) {
  if (done[static_cast<std::size_t>(f)]) return;
  done[static_cast<std::size_t>(f)] = true;
  for (FuncId g : callees(p.functions[static_cast<std::size_t>(f)])) flatten(p, g, done, log);
  for (const auto& b : p.functions[static_cast<std::size_t>(f)].blocks)
    for (const auto& in : b.instrs)
      if (FuncId g = callee_of(in); g >= 0)
        log.push_back(fmt::format("sub {} inlined into sub {} (a subroutine cannot call another on the RCX)",
                                  p.functions[static_cast<std::size_t>(g)].name, p.functions[static_cast<std::size_t>(f)].name));
  inline_calls(p, f, [](BlockId, std::size_t, FuncId) { return true; });
}

void inline_everywhere(Program& p, FuncId g) {
  for (std::size_t f = 0; f < p.functions.size(); ++f)
    inline_calls(p, static_cast<FuncId>(f), [&](BlockId, std::size_t, FuncId callee) { return callee == g; });
  p.functions[static_cast<std::size_t>(g)].blocks.clear();
  p.functions[static_cast<std::size_t>(g)].repeats.clear();
}

// The calls each function receives and whether they come from more than
// one caller, for every function in one walk of the program. The choices
// below asked the program once per subroutine, and chose the next
// subroutine to inline by asking again for every one: 400 subroutines took
// 2 s, 1 000 took 41. After flattening no subroutine calls another, so
// inlining one (its body holds no call) changes no other's counts.
struct CallCounts {
  std::vector<int> calls;
  std::vector<FuncId> caller;  // the one caller; -1 none, -2 several
};

CallCounts count_calls(const Program& p) {
  CallCounts c{std::vector<int>(p.functions.size(), 0), std::vector<FuncId>(p.functions.size(), -1)};
  for (std::size_t f = 0; f < p.functions.size(); ++f)
    for (const auto& b : p.functions[f].blocks)
      for (const auto& in : b.instrs)
        if (FuncId g = callee_of(in); g >= 0) {
          auto at = static_cast<std::size_t>(g);
          ++c.calls[at];
          if (c.caller[at] == -1) c.caller[at] = static_cast<FuncId>(f);
          else if (c.caller[at] != static_cast<FuncId>(f)) c.caller[at] = -2;
        }
  return c;
}

// Bytes inlining `g` at every call site adds (negative: saves), `n` being
// its calls.
int inline_growth(const Program& p, FuncId g, int n) {
  int s = estimate_size(p.functions[static_cast<std::size_t>(g)]);
  return n * s - (s + kCallSize * n);
}

std::vector<FuncId> live_subs(const Program& p) {
  std::vector<FuncId> subs;
  for (std::size_t f = 0; f < p.functions.size(); ++f)
    if (p.functions[f].kind == FuncKind::Sub && !p.functions[f].blocks.empty()) subs.push_back(static_cast<FuncId>(f));
  return subs;
}

// Whether `f` uses locals or temporaries (`footprint`: what it touches),
// or will: a repeat left by a jump counts in a variable.
bool has_own_variables(const Program& p, FuncId f, const VarSet& footprint) {
  for (const auto& r : p.functions[static_cast<std::size_t>(f)].repeats)
    if (r.escapes) return true;
  const auto& vars = footprint.members();
  return std::any_of(vars.begin(), vars.end(),
                     [&](VarId v) { return p.vars[static_cast<std::size_t>(v)].kind != VarKind::Global; });
}


}  // namespace

int estimate_size(const Function& f) {
  int size = 0;
  for (const auto& b : f.blocks) {
    for (const auto& in : b.instrs) size += instr_size(in);
    if (std::holds_alternative<Branch>(b.term)) size += 7;
    if (std::holds_alternative<Jump>(b.term) || std::holds_alternative<LoopTest>(b.term)) size += 2;
    if (std::holds_alternative<CoinToss>(b.term)) size += 7;
  }
  return size;
}

void inline_call(Program& p, FuncId caller, BlockId block, std::size_t index) {
  inline_calls(p, caller, [&](BlockId b, std::size_t i, FuncId) { return b == block && i == index; });
}

namespace {

// Estimated bytes of each function once every call in it is inlined
// (flatten), memoised per function and worked out callees first: a chain of
// subroutines each calling the previous twice doubles at every link, so
// this is where such a chain is stopped, before the doubling is done. Sizes
// saturate just above `limit`. Needs an acyclic call graph.
std::vector<long long> flattened_sizes(const Program& p, long long limit) {
  std::vector<long long> size(p.functions.size(), -1);
  std::vector<FuncId> stack;
  for (std::size_t root = 0; root < p.functions.size(); ++root) {
    stack.push_back(static_cast<FuncId>(root));
    while (!stack.empty()) {
      FuncId f = stack.back();
      const Function& fn = p.functions[static_cast<std::size_t>(f)];
      if (size[static_cast<std::size_t>(f)] >= 0) {
        stack.pop_back();
        continue;
      }
      bool ready = true;
      for (FuncId g : callees(fn))
        if (size[static_cast<std::size_t>(g)] < 0) {
          stack.push_back(g);
          ready = false;
        }
      if (!ready) continue;
      long long total = estimate_size(fn);
      for (const auto& b : fn.blocks)
        for (const auto& in : b.instrs)
          if (FuncId g = callee_of(in); g >= 0) total = std::min(limit + 1, total + size[static_cast<std::size_t>(g)]);
      size[static_cast<std::size_t>(f)] = total;
      stack.pop_back();
    }
  }
  return size;
}

// Reports a subroutine too big once the subroutines it calls are inlined.
bool report_explosion(const Program& p, Diagnostics& diags) {
  auto sizes = flattened_sizes(p, kMaxFlattenedBytes);
  for (FuncId s : live_subs(p)) {
    const Function& fn = p.functions[static_cast<std::size_t>(s)];
    if (sizes[static_cast<std::size_t>(s)] <= kMaxFlattenedBytes || callees(fn).empty()) continue;
    diags.error(fn.span, fmt::format("sub {} would grow past {} bytes once the subroutines it calls are inlined into "
                                     "it (the RCX cannot call a subroutine from a subroutine, and its calls nest "
                                     "too often)",
                                     fn.name, kMaxFlattenedBytes));
    return true;
  }
  return false;
}

}  // namespace

void drop_uncalled_subs(Program& p, Log& log) {
  CallCounts counts = count_calls(p);
  for (FuncId s : live_subs(p))
    if (counts.calls[static_cast<std::size_t>(s)] == 0) {
      log.push_back(fmt::format("sub {} is not called: dropped", p.functions[static_cast<std::size_t>(s)].name));
      p.functions[static_cast<std::size_t>(s)].blocks.clear();
    }
}

bool resolve_calls(Program& p, OptLevel level, Diagnostics& diags, Log& log) {
  if (report_recursion(p, diags)) return false;
  if (report_explosion(p, diags)) return false;
  std::vector<bool> done(p.functions.size(), false);
  for (FuncId s : live_subs(p)) flatten(p, s, done, log);
  drop_uncalled_subs(p, log);
  CallCounts counts = count_calls(p);
  auto calls = [&](FuncId s) { return counts.calls[static_cast<std::size_t>(s)]; };
  // A subroutine run by several tasks keeps its locals and temporaries in
  // one slot for all of them; inlined, every task has its own.
  // After flattening no subroutine calls another, so inlining one into the
  // tasks leaves the others' footprints as they are.
  auto footprints = function_footprints(p);
  // (Calls from more than one caller: after flattening only tasks call.)
  for (FuncId s : live_subs(p))
    if (counts.caller[static_cast<std::size_t>(s)] == -2 &&
        has_own_variables(p, s, footprints[static_cast<std::size_t>(s)])) {
      log.push_back(fmt::format("sub {} inlined at its calls (run by several tasks, which would share its "
                                "temporaries; {:+} bytes)",
                                p.functions[static_cast<std::size_t>(s)].name, inline_growth(p, s, calls(s))));
      inline_everywhere(p, s);
    }
  // The cheapest first, the first of equals by number, as choosing the
  // cheapest again after each inlining would (the others' growths stay).
  std::vector<std::pair<int, FuncId>> by_growth;
  for (FuncId s : live_subs(p)) by_growth.emplace_back(inline_growth(p, s, calls(s)), s);
  std::sort(by_growth.begin(), by_growth.end());
  for (std::size_t k = 0; k + 8 < by_growth.size(); ++k) {
    auto [growth, cheapest] = by_growth[k];
    log.push_back(fmt::format("sub {} inlined at its calls (more than 8 subroutines; {:+} bytes)",
                              p.functions[static_cast<std::size_t>(cheapest)].name, growth));
    inline_everywhere(p, cheapest);
  }
  if (shrinks_without_slowing(level))
    for (FuncId s : live_subs(p))
      if (int growth = inline_growth(p, s, calls(s)); growth <= 0) {
        log.push_back(fmt::format("sub {} inlined at its calls ({:+} bytes)", p.functions[static_cast<std::size_t>(s)].name, growth));
        inline_everywhere(p, s);
      }
  return true;
}

}  // namespace rcxc::ir
