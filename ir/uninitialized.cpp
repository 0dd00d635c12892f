// Locals read before they are written (see passes.h).
#include <fmt/format.h>

#include "ir/liveness.h"
#include "ir/passes.h"

namespace rcxc::ir {

void warn_reads_before_writes(const Program& p, Diagnostics& diags, LivenessCache* cache) {
  auto calls = call_effects(p);
  Liveness fresh;
  std::vector<bool> reported(p.vars.size(), false);
  for (const auto& f : p.functions) {
    if (f.blocks.empty()) continue;
    // Kept for the first round of the clean-up passes when given a cache.
    const Liveness& live = cache ? cache->of(p, f, calls) : (fresh = compute_liveness(p, f, calls));
    VarSet suspects;
    for (VarId v : live.live_in[0].members())
      if (p.vars[static_cast<std::size_t>(v)].kind == VarKind::Local && !reported[static_cast<std::size_t>(v)])
        suspects.add(v);
    if (suspects.members().empty()) continue;
    // Forward: the suspects no write has reached yet, at each block's start.
    std::vector<VarSet> unwritten(f.blocks.size());
    std::vector<bool> seen(f.blocks.size(), false);
    unwritten[0] = suspects;
    seen[0] = true;
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t b = 0; b < f.blocks.size(); ++b) {
        if (!seen[b]) continue;
        VarSet out = unwritten[b];
        for (const auto& in : f.blocks[b].instrs)
          for (VarId w : uses_of(in).writes) out.remove(w);
        for (BlockId s : successors(f.blocks[b].term)) {
          auto k = static_cast<std::size_t>(s);
          changed |= unwritten[k].merge(out) || !seen[k];
          seen[k] = true;
        }
      }
    }
    // Reported at the first read in layout order. A call that reads a
    // subroutine's local is not the read: the subroutine's own code is.
    // An inline function's code carries the span of its call, so the note
    // at the declaration shows which function's local it is.
    auto report = [&](VarId v, SourceSpan at) {
      if (reported[static_cast<std::size_t>(v)]) return;
      reported[static_cast<std::size_t>(v)] = true;
      const Var& var = p.vars[static_cast<std::size_t>(v)];
      auto& d = diags.warning(at, WarningKind::Uninitialized, fmt::format("'{}' is read before it is written: it holds what it held when the code "
                                              "last ran (one variable serves every call of a subroutine or inline "
                                              "function), and at first whatever its slot held",
                                              var.name));
      if (var.span.begin.valid()) d.notes.push_back({var.span, fmt::format("'{}' is declared here", var.name)});
    };
    for (std::size_t b = 0; b < f.blocks.size(); ++b) {
      if (!seen[b]) continue;
      VarSet pending = unwritten[b];
      for (const auto& in : f.blocks[b].instrs) {
        auto use = uses_of(in);
        if (callee_of(in) < 0)
          for (VarId r : use.reads)
            if (pending.has(r)) report(r, p.span(in.span).begin.valid() ? p.span(in.span) : p.span(f.blocks[b].span));
        for (VarId w : use.writes) pending.remove(w);
      }
      for (VarId r : reads_of(f.blocks[b].term))
        if (pending.has(r)) report(r, p.span(f.blocks[b].span));
    }
  }
}

}  // namespace rcxc::ir
