#include "backend/codegen.h"

#include <array>
#include <span>

#include <fmt/format.h>

#include "backend/branch.h"
#include "backend/encode.h"
#include "backend/absorb.h"
#include "backend/outline.h"

namespace rcxc::backend {
namespace {

using ir::Operand;

struct Indices {
  std::vector<int> of;  // per FuncId: task or subroutine index, -1 if dropped
};

std::optional<Indices> number_functions(const ir::Program& p, Diagnostics& diags) {
  Indices idx{std::vector<int>(p.functions.size(), -1)};
  int tasks = 0, subs = 0;
  // main is task 0: the firmware starts task 0 when the program runs.
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t f = 0; f < p.functions.size(); ++f) {
      const auto& fn = p.functions[f];
      if (fn.blocks.empty() || fn.kind != ir::FuncKind::Task || (fn.name == "main") != (pass == 0)) continue;
      idx.of[f] = tasks++;
    }
  for (std::size_t f = 0; f < p.functions.size(); ++f)
    if (!p.functions[f].blocks.empty() && p.functions[f].kind == ir::FuncKind::Sub) idx.of[f] = subs++;
  if (tasks > kMaxTasks) {
    diags.error({}, fmt::format("the program has {} tasks; the RCX runs at most {}", tasks, kMaxTasks));
    return std::nullopt;
  }
  if (subs > kMaxSubroutines) {
    diags.error({}, fmt::format("the program has {} subroutines; the RCX holds at most {}", subs, kMaxSubroutines));
    return std::nullopt;
  }
  return idx;
}

struct Selector {
  const ir::Program& p;
  const std::vector<int>& slots;
  const Indices& indices;
  Diagnostics& diags;
  bool drop_self_copies = false;

  // `set` of a variable from one that got the same slot: once two variables
  // share a slot (the source dies where the copy begins), the copy between
  // them changes nothing.
  bool self_copy(const ir::Instr& in) const {
    return !in.raw && in.op == rcx::Op::SetVariable && in.args.size() == 2 && in.args[0].is_var() &&
           in.args[1].is_var() && resolve(in.args[0]).second >= 0 &&
           resolve(in.args[0]) == resolve(in.args[1]);
  }

  // Source and argument of an operand once slots and indices are known.
  std::pair<int, int> resolve(const Operand& o) const {
    switch (o.kind) {
      case Operand::Kind::Var: return {0, slots[static_cast<std::size_t>(o.value)]};
      case Operand::Kind::Func: return {2, indices.of[static_cast<std::size_t>(o.value)]};
      default: return {o.source, o.value};
    }
  }

  // Table values (every field except branch offsets) of one instruction,
  // in table order: a Source operand fills its own field and its Argument's.
  // Kept in place: this runs for every instruction of the program.
  struct Values {
    std::array<int, kMaxTableOperands> field{};
    std::size_t size = 0;
    std::span<const int> span() const { return {field.data(), size}; }
  };
  Values values(const ir::Instr& in) const {
    const auto& operands = rcx::info(in.op).operands;
    Values v;
    std::size_t next = 0;
    for (std::size_t i = 0; i < operands.size(); ++i) {
      const auto role = operands[i].role;
      if (is_offset(role) || role == rcx::Role::Argument) continue;
      auto [source, argument] = resolve(in.args.at(next++));
      if (role != rcx::Role::Source && role != rcx::Role::OpSource) {
        v.field[i] = argument;
        continue;
      }
      v.field[i] = source;
      for (std::size_t j = 0; j < operands.size(); ++j)
        if (operands[j].role == rcx::Role::Argument && operands[j].pairs_with == static_cast<int>(i))
          v.field[j] = argument;
    }
    // Leave out the offsets: the values only move towards the front.
    for (std::size_t i = 0; i < operands.size(); ++i)
      if (!is_offset(operands[i].role)) v.field[v.size++] = v.field[i];
    return v;
  }
  static bool is_offset(rcx::Role role) { return role == rcx::Role::Offset || role == rcx::Role::Extension; }

  // Machine instructions of one instruction.
  bool select(const ir::Instr& in, std::vector<MInstr>& out) const {
    MInstr m;
    m.span = p.span(in.span);
    if (in.raw) {
      m.raw = true;
      for (const auto& a : in.args) m.bytes.push_back(static_cast<std::uint8_t>(resolve(a).second & 0xff));
      out.push_back(std::move(m));
      return true;
    }
    m.op = in.op;
    if (rcx::info(in.op).operands.size() > kMaxTableOperands) {
      diags.error(m.span, fmt::format("cannot encode instruction: {} has more than {} operands", rcx::info(in.op).mnemonic,
                                       kMaxTableOperands));
      return false;
    }
    std::string err = encode(rcx::info(in.op), values(in).span(), m.bytes);
    if (!err.empty()) {
      diags.error(m.span, fmt::format("cannot encode instruction: {}", err));
      return false;
    }
    out.push_back(std::move(m));
    return true;
  }

  // A comparison as test-and-branch fields, or the constant it always has.
  struct Test {
    int opsrc1 = 0, src2 = 0, arg1 = 0, arg2 = 0;
  };
  std::optional<Test> test(ir::Cmp cmp, Operand a, Operand b, bool& constant, bool& always) const {
    constant = false;
    if (b.is_imm()) {
      std::swap(a, b);
      cmp = ir::swap(cmp);
    }
    if (a.is_imm() && b.is_imm()) {
      constant = true;
      always = ir::evaluate(cmp, a.value, b.value);
      return std::nullopt;
    }
    if (cmp == ir::Cmp::LT || cmp == ir::Cmp::GT) {
      if (!a.is_imm()) return std::nullopt;  // only the negated form is direct
      bool at_edge = cmp == ir::Cmp::LT ? a.value == 32767 : a.value == -32768;
      if (at_edge) {
        constant = true;
        always = false;
        return std::nullopt;
      }
      a.value += cmp == ir::Cmp::LT ? 1 : -1;  // c < x  <=>  c+1 <= x
      cmp = cmp == ir::Cmp::LT ? ir::Cmp::LE : ir::Cmp::GE;
    }
    auto [s1, v1] = resolve(a);
    auto [s2, v2] = resolve(b);
    rcx::Compare code = cmp == ir::Cmp::LE   ? rcx::Compare::LessEqual
                        : cmp == ir::Cmp::GE ? rcx::Compare::GreaterEqual
                        : cmp == ir::Cmp::NE ? rcx::Compare::NotEqual
                                             : rcx::Compare::Equal;
    return Test{(static_cast<int>(code) << 6) | s1, s2, v1, v2};
  }

  MInstr branch_if(const Test& t, Target target, SourceSpan span) const {
    MInstr m;
    m.kind = MInstr::Kind::Test;
    m.values = {t.opsrc1, t.src2, t.arg1, t.arg2};
    m.target = target;
    m.span = span;
    return m;
  }

  static MInstr jump(Target target, SourceSpan span) {
    MInstr m;
    m.kind = MInstr::Kind::Jump;
    m.target = target;
    m.span = span;
    return m;
  }

  // Decrement the loop counter; below zero: pop it and branch to `target`.
  static MInstr loop_test(Target target, SourceSpan span) {
    MInstr m = jump(target, span);
    m.kind = MInstr::Kind::Loop;
    return m;
  }

  // Control transfer at the end of block `b` given the layout.
  void select_terminator(const ir::Function& f, ir::BlockId b, std::vector<MInstr>& out) const {
    const ir::Block& block = f.blocks[static_cast<std::size_t>(b)];
    ir::BlockId next = b + 1;
    bool last = next == static_cast<ir::BlockId>(f.blocks.size());
    SourceSpan span = p.span(block.span);
    auto to = [](ir::BlockId t) { return Target{t, -1}; };
    auto jump_unless_next = [&](ir::BlockId t) {
      if (t != next) out.push_back(jump(to(t), span));
    };
    auto ret = [&] {
      MInstr m;
      m.op = rcx::Op::ReturnFromSubroutine;
      m.bytes = {rcx::info(rcx::Op::ReturnFromSubroutine).code};
      m.span = span;
      out.push_back(std::move(m));
    };
    if (const auto* j = std::get_if<ir::Jump>(&block.term)) {
      // In a subroutine, a jump to a block that only returns is a return:
      // one byte instead of two.
      const ir::Block& target = f.blocks[static_cast<std::size_t>(j->target)];
      if (f.kind == ir::FuncKind::Sub && j->target != next && target.instrs.empty() &&
          std::holds_alternative<ir::Exit>(target.term))
        ret();
      else
        jump_unless_next(j->target);
    } else if (std::holds_alternative<ir::Exit>(block.term)) {
      if (f.kind == ir::FuncKind::Sub) {
        if (!last) ret();
      } else if (!last) {
        out.push_back(jump(Target{kEndOfCode, -1}, span));  // a task ends where its code ends
      }
    } else if (const auto* l = std::get_if<ir::LoopTest>(&block.term)) {
      if (l->exit > b) {
        out.push_back(loop_test(to(l->exit), span));
        jump_unless_next(l->body);
      } else {
        // The counter only branches forward: step over a jump to the body
        // onto a jump back to the exit.
        out.push_back(loop_test(Target{-1, static_cast<int>(out.size()) + 2}, span));
        out.push_back(jump(to(l->body), span));
        out.push_back(jump(to(l->exit), span));
      }
    } else if (const auto* br = std::get_if<ir::Branch>(&block.term)) {
      select_branch(*br, next, span, out);
    } else if (const auto* c = std::get_if<ir::CoinToss>(&block.term)) {
      select_coin_toss(*c, b, block.span, out);
    }
  }

  // loopset random(1); the first loop test pops a 0 and goes to `zero`,
  // the second pops what a 1 has become (-1) and goes to `one`. A side
  // behind them (the counter branches forward only) gets a jump after.
  void select_coin_toss(const ir::CoinToss& c, ir::BlockId b, ir::SpanId span_id, std::vector<MInstr>& out) const {
    select(ir::Instr{rcx::Op::SetLoopCounter, {ir::Operand::src(static_cast<int>(rcx::Source::Random), 1)}, false, span_id},
           out);
    SourceSpan span = p.span(span_id);
    std::size_t first = out.size();
    int behind = 0;
    for (ir::BlockId side : {c.zero, c.one})
      out.push_back(loop_test(side > b ? Target{side, -1} : Target{-1, static_cast<int>(first) + 2 + behind++}, span));
    for (ir::BlockId side : {c.zero, c.one})
      if (side <= b) out.push_back(jump(Target{side, -1}, span));
  }

  void select_branch(const ir::Branch& br, ir::BlockId next, SourceSpan span, std::vector<MInstr>& out) const {
    bool constant = false, always = false;
    auto direct = test(br.cmp, br.a, br.b, constant, always);
    if (constant) {
      ir::BlockId t = always ? br.then : br.otherwise;
      if (t != next) out.push_back(jump(Target{t, -1}, span));
      return;
    }
    bool c2 = false, a2 = false;
    auto negated = test(ir::negate(br.cmp), br.a, br.b, c2, a2);
    if (direct && (br.otherwise == next || !negated || br.then != next)) {
      out.push_back(branch_if(*direct, Target{br.then, -1}, span));
      if (br.otherwise != next) out.push_back(jump(Target{br.otherwise, -1}, span));
    } else {
      out.push_back(branch_if(*negated, Target{br.otherwise, -1}, span));
      if (br.then != next) out.push_back(jump(Target{br.then, -1}, span));
    }
  }

  std::optional<std::vector<MInstr>> select_function(const ir::Function& f, std::vector<int>& block_start) const {
    std::vector<MInstr> out;
    block_start.assign(f.blocks.size(), 0);
    for (std::size_t b = 0; b < f.blocks.size(); ++b) {
      block_start[b] = static_cast<int>(out.size());
      for (const auto& in : f.blocks[b].instrs)
        if (!(drop_self_copies && self_copy(in)) && !select(in, out)) return std::nullopt;
      select_terminator(f, static_cast<ir::BlockId>(b), out);
    }
    return out;
  }
};

void add_symbols(const ir::Program& p, const std::vector<int>& slots, const Indices& idx, rcx::Image& image) {
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t f = 0; f < p.functions.size(); ++f) {
      const auto& fn = p.functions[f];
      bool task = fn.kind == ir::FuncKind::Task;
      if (idx.of[f] < 0 || task != (pass == 0)) continue;
      image.symbols.push_back({task ? rcx::SymbolType::Task : rcx::SymbolType::Subroutine,
                               static_cast<std::uint8_t>(idx.of[f]), fn.name});
    }
  std::vector<bool> named(32, false);
  for (std::size_t v = 0; v < p.vars.size(); ++v) {
    int s = slots.size() > v ? slots[v] : -1;
    if (s < 0 || s >= 32 || named[static_cast<std::size_t>(s)] || p.vars[v].name.empty() ||
        p.vars[v].kind == ir::VarKind::Temp)
      continue;
    named[static_cast<std::size_t>(s)] = true;
    image.symbols.push_back({rcx::SymbolType::Variable, static_cast<std::uint8_t>(s), p.vars[v].name});
  }
}

}  // namespace

std::optional<Output> generate(const ir::Program& p, const std::vector<int>& slots, Diagnostics& diags,
                               const GenerateOptions& options, std::vector<std::string>* log) {
  auto idx = number_functions(p, diags);
  if (!idx) return std::nullopt;
  Selector sel{p, slots, *idx, diags, options.drop_self_copies};
  std::vector<Selected> selected;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t f = 0; f < p.functions.size(); ++f) {
      const auto& fn = p.functions[f];
      bool task = fn.kind == ir::FuncKind::Task;
      if (idx->of[f] < 0 || task != (pass == 0)) continue;
      Selected s;
      auto code = sel.select_function(fn, s.block_start);
      if (!code) return std::nullopt;
      s.function = static_cast<int>(f);
      s.type = task ? rcx::FragmentType::Task : rcx::FragmentType::Subroutine;
      s.index = idx->of[f];
      s.name = fn.name;
      s.code = std::move(*code);
      selected.push_back(std::move(s));
    }
  std::vector<std::string> discarded;
  if (options.outline) {
    // The user's subroutines take what their calls share first (outlining
    // it instead would save less), then new subroutines do.
    absorb_call_neighbours(selected, log ? *log : discarded, WaitSplit::Allowed);
    outline(selected, log ? *log : discarded);
    absorb_call_neighbours(selected, log ? *log : discarded, WaitSplit::Allowed);
  } else if (options.absorb) {
    absorb_call_neighbours(selected, log ? *log : discarded, WaitSplit::Never);
  }
  Output out;
  int memory = 0;
  for (auto& s : selected) {
    bool task = s.type == rcx::FragmentType::Task;
    SourceSpan span = s.function >= 0 ? p.functions[static_cast<std::size_t>(s.function)].span : SourceSpan{};
    FragmentCode frag;
    frag.function = s.function;
    frag.type = s.type;
    frag.index = s.index;
    frag.name = s.name;
    std::string err = assemble(s.code, s.block_start, frag.code, frag.instrs);
    if (!err.empty()) {
      diags.error(span, fmt::format("{} {}: {}", task ? "task" : "sub", s.name, err));
      return std::nullopt;
    }
    if (static_cast<int>(frag.code.size()) > kMaxFragmentBytes) {
      diags.error(span, fmt::format("{} {} is {} bytes long; a task or subroutine can be at most {} bytes",
                                    task ? "task" : "sub", s.name, frag.code.size(), kMaxFragmentBytes));
      return std::nullopt;
    }
    out.code_bytes += static_cast<int>(frag.code.size());
    memory += static_cast<int>(frag.code.size()) + (task ? 0 : 1);  // the firmware appends a return to subs
    out.image.fragments.push_back({frag.type, static_cast<std::uint8_t>(frag.index), frag.code});
    out.fragments.push_back(std::move(frag));
  }
  if (memory > kProgramMemoryBytes) {
    diags.error({}, fmt::format("the program needs {} bytes of program memory; the RCX has {}", memory,
                                kProgramMemoryBytes));
    return std::nullopt;
  }
  add_symbols(p, slots, *idx, out.image);
  for (const auto& s : selected)
    if (s.function < 0)
      out.image.symbols.push_back({rcx::SymbolType::Subroutine, static_cast<std::uint8_t>(s.index), s.name});
  std::vector<bool> used(32, false);
  for (int s : slots)
    if (s >= 0 && s < 32) used[static_cast<std::size_t>(s)] = true;
  for (bool u : used) out.slots_used += u ? 1 : 0;
  return out;
}

}  // namespace rcxc::backend
