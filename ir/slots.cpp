// Variable slot allocation (see passes.h).
#include <array>
#include <bit>
#include <optional>
#include <fmt/format.h>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {
namespace {

constexpr int kSlots = 32;
using TaskMask = std::uint64_t;

bool live_function(const Function& f) { return !f.blocks.empty(); }

// Which tasks may execute each function: a task runs its own code and the
// subroutines it calls.
std::vector<TaskMask> tasks_running(const Program& p) {
  std::vector<TaskMask> mask(p.functions.size(), 0);
  int task_no = 0;
  for (std::size_t t = 0; t < p.functions.size(); ++t) {
    if (p.functions[t].kind != FuncKind::Task || !live_function(p.functions[t])) continue;
    TaskMask bit = TaskMask{1} << (task_no++ % 64);
    std::vector<FuncId> work{static_cast<FuncId>(t)};
    while (!work.empty()) {
      FuncId f = work.back();
      work.pop_back();
      if (mask[static_cast<std::size_t>(f)] & bit) continue;
      mask[static_cast<std::size_t>(f)] |= bit;
      for (const auto& b : p.functions[static_cast<std::size_t>(f)].blocks)
        for (const auto& in : b.instrs)
          if (FuncId g = callee_of(in); g >= 0) work.push_back(g);
    }
  }
  return mask;
}

struct Graph {
  std::vector<VarSet> edges;
  void add(VarId a, VarId b) {
    if (a == b) return;
    edges[static_cast<std::size_t>(a)].add(b);
    edges[static_cast<std::size_t>(b)].add(a);
  }
};

void add_liveness_edges(const Program& p, const Function& f, const CallEffects& calls, Graph& g) {
  Liveness L = compute_liveness(p, f, calls);
  auto entry = L.live_in[0].members();
  for (VarId a : entry)
    for (VarId b : entry) g.add(a, b);
  VarSet live;  // reused: assigning keeps its room (a copy per block was an allocation per block)
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    const Block& block = f.blocks[b];
    live.items.assign(L.live_out[b].items.begin(), L.live_out[b].items.end());
    for (VarId v : reads_of(block.term))
      if (p.vars[static_cast<std::size_t>(v)].kind != VarKind::Global) live.add(v);
    for (std::size_t k = block.instrs.size(); k-- > 0;) {
      const Instr& in = block.instrs[k];
      const auto& after = live.members();
      for (VarId w : uses_of(in).writes)
        for (VarId l : after) g.add(w, l);
      if (FuncId callee = callee_of(in); callee >= 0)
        for (VarId x : calls.touches[static_cast<std::size_t>(callee)].members())
          for (VarId l : after) g.add(x, l);
      step_back(p, in, calls, live);
    }
  }
}

constexpr std::string_view kNoSlotLeft = "no variable slot left for ";

std::string holder_name(const Var& v) { return v.name.empty() ? std::string("a compiler temporary") : "'" + v.name + "'"; }

// Where a variable is first used: a compiler temporary has no declaration,
// so the error points at the code that needed it, an instruction or the
// test that ends a block (`if (Random(5) > 3)` reads its temporary there).
SourceSpan first_use(const Program& p, VarId v) {
  for (const auto& f : p.functions) {
    if (!live_function(f)) continue;
    for (const auto& b : f.blocks) {
      for (const auto& in : b.instrs)
        if (in.span != 0)
          for (const auto& a : in.args)
            if (a.is_var() && a.value == v) return p.span(in.span);
      if (b.span != 0)
        for (VarId read : reads_of(b.term))
          if (read == v) return p.span(b.span);
    }
  }
  return {};
}

// What holds slot `s` when `failed` found none free: its holders' names and
// where the first named one is declared (else `at`), and the one named
// variable when that is all there is.
struct SlotHolders {
  std::string names;
  SourceSpan where;
  std::optional<std::size_t> lone_named;
};

SlotHolders holders_of(const Program& p, VarId failed, const std::vector<int>& slot, int s, SourceSpan at) {
  SlotHolders h{"", at, std::nullopt};
  if ((p.reserved_slots >> s) & 1u) h.names = "#pragma reserve";
  int count = 0;
  for (std::size_t u = 0; u < slot.size(); ++u) {
    if (slot[u] != s || static_cast<VarId>(u) == failed) continue;
    if (h.names.empty() && p.vars[u].span.begin.valid()) h.where = p.vars[u].span;
    h.names += (h.names.empty() ? "" : ", ") + holder_name(p.vars[u]);
    ++count;
    if (count == 1 && !p.vars[u].name.empty()) h.lone_named = u;
  }
  if (count != 1 || ((p.reserved_slots >> s) & 1u)) h.lone_named.reset();
  if (h.names.empty()) h.names = "a variable live at the same time";
  return h;
}

// One note a slot, except that a run of three or more slots each held by one
// named variable (the globals, most often) is one note at the first of them:
// 33 globals gave 32 notes.
void report_exhaustion(const Program& p, VarId failed, const std::vector<int>& slot, Diagnostics& diags) {
  const Var& v = p.vars[static_cast<std::size_t>(failed)];
  SourceSpan at = v.span.begin.valid() ? v.span : first_use(p, failed);
  auto& d = diags.error(at, fmt::format("{}{}: the RCX has {} and all are taken", kNoSlotLeft, holder_name(v),
                                            kSlots));
  std::vector<SlotHolders> held;
  for (int s = 0; s < kSlots; ++s) held.push_back(holders_of(p, failed, slot, s, at));
  for (int s = 0; s < kSlots;) {
    int end = s;
    while (end < kSlots && held[static_cast<std::size_t>(end)].lone_named) ++end;
    if (end - s >= 3) {
      std::string names;
      for (int k = s; k < end; ++k) names += (k == s ? "" : ", ") + held[static_cast<std::size_t>(k)].names;
      d.notes.push_back({held[static_cast<std::size_t>(s)].where,
                         fmt::format("slots {} to {} are held by {}", s, end - 1, names)});
      s = end;
      continue;
    }
    const SlotHolders& h = held[static_cast<std::size_t>(s)];
    d.notes.push_back({h.where, fmt::format("slot {} is held by {}", s, h.names)});
    ++s;
  }
}

// A subroutine's locals and temporaries have one slot whichever task runs
// it: two tasks running it at once overwrite each other's values.
void warn_shared_sub_variables(const Program& p, const std::vector<TaskMask>& running, const CallEffects& calls,
                               Diagnostics& diags) {
  std::vector<std::string> task_names;
  for (const auto& f : p.functions)
    if (f.kind == FuncKind::Task && live_function(f)) task_names.push_back(f.name);
  for (std::size_t f = 0; f < p.functions.size(); ++f) {
    const Function& fn = p.functions[f];
    if (fn.kind != FuncKind::Sub || !live_function(fn) || std::popcount(running[f]) < 2) continue;
    if (calls.touches[f].members().empty()) continue;  // only globals
    std::string tasks;
    for (std::size_t t = 0; t < task_names.size() && t < 64; ++t)
      if ((running[f] >> t) & 1) tasks += (tasks.empty() ? "'" : ", '") + task_names[t] + "'";
    diags.warning(fn.span, WarningKind::SharedSubroutine, fmt::format("subroutine '{}' is run by tasks {} and keeps a local or temporary value in "
                                       "one variable slot for all of them: tasks running it at the same time "
                                       "overwrite each other's value",
                                       fn.name, tasks));
  }
}

}  // namespace

std::vector<int> allocate_slots(const Program& p, Diagnostics& diags) {
  std::size_t nv = p.vars.size();
  auto calls = call_effects(p);
  auto running = tasks_running(p);
  std::vector<bool> used(nv, false);
  std::vector<TaskMask> var_tasks(nv, 0);
  for (std::size_t f = 0; f < p.functions.size(); ++f) {
    if (!live_function(p.functions[f])) continue;
    for (const auto& b : p.functions[f].blocks) {
      auto note = [&](VarId v) {
        used[static_cast<std::size_t>(v)] = true;
        var_tasks[static_cast<std::size_t>(v)] |= running[f];
      };
      for (const auto& in : b.instrs)
        for (const auto& a : in.args)
          if (a.is_var()) note(a.value);
      for (VarId v : reads_of(b.term)) note(v);
    }
  }
  warn_shared_sub_variables(p, running, calls, diags);
  Graph g{std::vector<VarSet>(nv)};
  for (const auto& f : p.functions)
    if (live_function(f)) add_liveness_edges(p, f, calls, g);

  std::vector<int> slot(nv, -1);
  std::uint32_t global_slots = p.reserved_slots;
  // The tasks whose variables each slot holds: variables that two tasks
  // may touch at once never share a slot.
  std::array<TaskMask, kSlots> slot_tasks{};
  auto assign = [&](VarId v, bool global) {
    std::uint32_t taken = global_slots;
    TaskMask mine = var_tasks[static_cast<std::size_t>(v)];
    if (!global) {
      for (VarId n : g.edges[static_cast<std::size_t>(v)].members())
        if (slot[static_cast<std::size_t>(n)] >= 0) taken |= 1u << slot[static_cast<std::size_t>(n)];
      // A slot serves one task's variables, or one variable that several
      // tasks use (a subroutine's temporary) alone.
      for (int s = 0; s < kSlots; ++s) {
        TaskMask holders = slot_tasks[static_cast<std::size_t>(s)];
        if (holders != 0 && (holders != mine || std::popcount(mine) > 1)) taken |= 1u << s;
      }
    }
    if (global)
      for (std::size_t u = 0; u < nv; ++u)
        if (slot[u] >= 0) taken |= 1u << slot[u];
    const auto& fixed = p.vars[static_cast<std::size_t>(v)].slot;
    if (fixed) {
      slot[static_cast<std::size_t>(v)] = *fixed;
    } else {
      if (taken == 0xffffffffu) return false;
      slot[static_cast<std::size_t>(v)] = std::countr_one(taken);
    }
    if (global) global_slots |= 1u << slot[static_cast<std::size_t>(v)];
    slot_tasks[static_cast<std::size_t>(slot[static_cast<std::size_t>(v)])] |= mine;
    return true;
  };
  // Fixed slots first, then globals, then the rest. Every file-scope
  // global gets the slot nqc gives it, used or not: the lowest free one in
  // declaration order. The PC reads globals by number, raw asm names them
  // by number and a brick's five programs share the 32 slots, so leaving an
  // unused global out would move every later one.
  for (int pass = 0; pass < 3; ++pass)
    for (std::size_t v = 0; v < nv; ++v) {
      const Var& var = p.vars[v];
      bool global = var.kind == VarKind::Global;
      if (!used[v] && !global) continue;
      int want = var.slot ? 0 : (global ? 1 : 2);
      if (want != pass) continue;
      if (!assign(static_cast<VarId>(v), global || var.slot.has_value())) {
        report_exhaustion(p, static_cast<VarId>(v), slot, diags);
        return {};
      }
    }
  return slot;
}

bool reports_no_slot_left(const Diagnostic& d) {
  return d.severity == Severity::Error && d.message.starts_with(kNoSlotLeft);
}

}  // namespace rcxc::ir
