#include "ir/ir.h"
#include "ir/predecessors.h"

#include <algorithm>

#include <fmt/format.h>

namespace rcxc::ir {

Cmp negate(Cmp c) {
  switch (c) {
    case Cmp::LE: return Cmp::GT;
    case Cmp::GE: return Cmp::LT;
    case Cmp::NE: return Cmp::EQ;
    case Cmp::EQ: return Cmp::NE;
    case Cmp::LT: return Cmp::GE;
    case Cmp::GT: return Cmp::LE;
  }
  return c;
}

bool branches_directly(Cmp c, const Operand& a, const Operand& b) {
  return !((c == Cmp::LT || c == Cmp::GT) && !a.is_imm() && !b.is_imm());
}

Cmp swap(Cmp c) {
  switch (c) {
    case Cmp::LE: return Cmp::GE;
    case Cmp::GE: return Cmp::LE;
    case Cmp::LT: return Cmp::GT;
    case Cmp::GT: return Cmp::LT;
    case Cmp::NE:
    case Cmp::EQ: return c;
  }
  return c;
}

bool evaluate(Cmp c, int a, int b) {
  auto x = static_cast<std::int16_t>(a);
  auto y = static_cast<std::int16_t>(b);
  switch (c) {
    case Cmp::LE: return x <= y;
    case Cmp::GE: return x >= y;
    case Cmp::NE: return x != y;
    case Cmp::EQ: return x == y;
    case Cmp::LT: return x < y;
    case Cmp::GT: return x > y;
  }
  return false;
}

std::optional<int> arithmetic(rcx::Op op, int dest, int src) {
  long d = static_cast<std::int16_t>(dest), s = static_cast<std::int16_t>(src);
  switch (op) {
    case rcx::Op::SetVariable: return wrap16(s);
    case rcx::Op::AddToVariable: return wrap16(d + s);
    case rcx::Op::SubtractFromVariable: return wrap16(d - s);
    case rcx::Op::MultiplyVariable: return wrap16(d * s);
    // Division by zero leaves the variable unchanged (seed); C rounding.
    case rcx::Op::DivideVariable: return s == 0 ? wrap16(d) : wrap16(d / s);
    case rcx::Op::AndVariable: return wrap16(d & s);
    case rcx::Op::OrVariable: return wrap16(d | s);
    case rcx::Op::AbsoluteValue: return s == -32768 ? 32767 : wrap16(s < 0 ? -s : s);
    case rcx::Op::SignVariable: return s > 0 ? 1 : (s < 0 ? -1 : 0);
    default: return std::nullopt;
  }
}

bool leaves_unchanged(rcx::Op op, int k) {
  switch (op) {
    case rcx::Op::AddToVariable:
    case rcx::Op::SubtractFromVariable:
    case rcx::Op::OrVariable: return k == 0;
    case rcx::Op::MultiplyVariable: return k == 1;
    case rcx::Op::AndVariable: return k == -1;
    case rcx::Op::DivideVariable: return k == 0 || k == 1;
    default: return false;
  }
}

SpanId Program::add_span(const SourceSpan& span) {
  spans.push_back(span);
  return static_cast<SpanId>(spans.size() - 1);
}

VarId Program::add_var(std::string name, VarKind kind, SourceSpan span) {
  vars.push_back(Var{std::move(name), kind, std::nullopt, span});
  return static_cast<VarId>(vars.size() - 1);
}

FuncId Program::find_function(const std::string& name) const {
  for (std::size_t i = 0; i < functions.size(); ++i)
    if (functions[i].name == name) return static_cast<FuncId>(i);
  return -1;
}

BlockId add_block(Function& f) {
  f.blocks.emplace_back();
  return static_cast<BlockId>(f.blocks.size() - 1);
}

std::vector<int> predecessor_counts(const Function& f) {
  std::vector<int> preds(f.blocks.size(), 0);
  for (const auto& b : f.blocks)
    for (BlockId s : successors(b.term)) ++preds[static_cast<std::size_t>(s)];
  return preds;
}

PredecessorLists::PredecessorLists(const Function& f, bool repeated_edges) : start_(f.blocks.size() + 1, 0) {
  // Twice over the edges: counting, then filling; `last` drops an edge
  // that repeats the one just listed for the same block.
  std::vector<BlockId> last(f.blocks.size(), -1);
  auto each_edge = [&](auto&& edge) {
    std::fill(last.begin(), last.end(), -1);
    for (std::size_t b = 0; b < f.blocks.size(); ++b)
      for (BlockId s : successors(f.blocks[b].term)) {
        auto to = static_cast<std::size_t>(s);
        if (!repeated_edges && last[to] == static_cast<BlockId>(b)) continue;
        last[to] = static_cast<BlockId>(b);
        edge(to, static_cast<BlockId>(b));
      }
  };
  each_edge([&](std::size_t to, BlockId) { ++start_[to + 1]; });
  for (std::size_t b = 0; b < f.blocks.size(); ++b) start_[b + 1] += start_[b];
  from_.resize(start_.back());
  std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
  each_edge([&](std::size_t to, BlockId from) { from_[next[to]++] = from; });
}

std::vector<int> reverse_postorder_index(const Function& f) {
  std::size_t n = f.blocks.size();
  std::vector<int> index(n, -1);
  if (n == 0) return index;
  // Iterative depth-first search: (block, how many of its successors
  // have been visited).
  std::vector<bool> seen(n, false);
  std::vector<std::pair<BlockId, std::size_t>> stack;
  std::vector<BlockId> postorder;
  postorder.reserve(n);
  seen[0] = true;
  stack.emplace_back(0, 0);
  while (!stack.empty()) {
    auto& [b, visited] = stack.back();
    Successors left = successors(f.blocks[static_cast<std::size_t>(b)].term);
    if (visited == left.size()) {
      postorder.push_back(b);
      stack.pop_back();
      continue;
    }
    BlockId next = left[visited++];
    if (seen[static_cast<std::size_t>(next)]) continue;
    seen[static_cast<std::size_t>(next)] = true;
    stack.emplace_back(next, 0);
  }
  for (std::size_t i = 0; i < postorder.size(); ++i)
    index[static_cast<std::size_t>(postorder[i])] = static_cast<int>(postorder.size() - 1 - i);
  return index;
}

namespace {
// Calls fix(b) on every block reference of a terminator.
template <class Fix>
void each_target(Terminator& t, Fix&& fix) {
  if (auto* j = std::get_if<Jump>(&t)) fix(j->target);
  if (auto* b = std::get_if<Branch>(&t)) {
    fix(b->then);
    fix(b->otherwise);
  }
  if (auto* l = std::get_if<LoopTest>(&t)) {
    fix(l->body);
    fix(l->exit);
  }
  if (auto* c = std::get_if<CoinToss>(&t)) {
    fix(c->zero);
    fix(c->one);
  }
}
}  // namespace

void offset_targets(Terminator& t, BlockId delta) {
  each_target(t, [&](BlockId& b) { b += delta; });
}

void append_repeats(Function& to, const std::vector<Repeat>& from, BlockId base) {
  for (auto r : from) {
    r.setup += base;
    r.head += base;
    to.repeats.push_back(r);
  }
}

void map_targets(Terminator& t, const std::vector<BlockId>& map) {
  each_target(t, [&](BlockId& b) { b = map[static_cast<std::size_t>(b)]; });
}

void retarget(Terminator& t, BlockId from, BlockId to) {
  each_target(t, [&](BlockId& b) {
    if (b == from) b = to;
  });
}

namespace {
// Applies `map` (old id -> new id, -1 = gone) to every block reference.
void renumber(Function& f, const std::vector<BlockId>& map) {
  auto fix = [&](BlockId& b) { b = map[static_cast<std::size_t>(b)]; };
  for (auto& b : f.blocks) each_target(b.term, fix);
  std::vector<Repeat> kept;
  for (auto r : f.repeats) {
    fix(r.setup);
    fix(r.head);
    if (r.setup >= 0 && r.head >= 0) kept.push_back(r);
  }
  f.repeats = std::move(kept);
}
}  // namespace

namespace {
bool is_task_op(const Instr& in) {
  return !in.raw && (in.op == rcx::Op::StartTask || in.op == rcx::Op::StopTask) && !in.args.empty();
}
}  // namespace

FuncId task_named(const Instr& in) {
  return is_task_op(in) && in.args[0].kind == Operand::Kind::Func ? in.args[0].value : -1;
}

bool starts_or_stops_unnamed_task(const Instr& in) { return in.raw || (is_task_op(in) && task_named(in) < 0); }

std::vector<bool> started_functions(const Program& p) {
  std::vector<bool> started(p.functions.size(), false);
  for (const auto& fn : p.functions)
    for (const auto& b : fn.blocks)
      for (const auto& in : b.instrs)
        if (in.op == rcx::Op::StartTask)
          if (FuncId t = task_named(in); t >= 0 && static_cast<std::size_t>(t) < started.size())
            started[static_cast<std::size_t>(t)] = true;
  return started;
}

bool same_instr(const Instr& a, const Instr& b) { return a.op == b.op && a.raw == b.raw && a.args == b.args; }

bool reads_random(const Operand& o) {
  return o.kind == Operand::Kind::Src && o.source == static_cast<int>(rcx::Source::Random);
}

bool is_repeat_block(const Function& f, BlockId b) {
  for (const auto& r : f.repeats)
    if (r.head == b || r.setup == b) return true;
  return false;
}

std::vector<bool> repeat_blocks(const Function& f) {
  std::vector<bool> in(f.blocks.size(), false);
  for (const auto& r : f.repeats)
    for (BlockId b : {r.head, r.setup})
      if (b >= 0 && static_cast<std::size_t>(b) < in.size()) in[static_cast<std::size_t>(b)] = true;
  return in;
}

void permute_blocks(Function& f, const std::vector<BlockId>& order) {
  std::vector<BlockId> map(order.size());
  std::vector<Block> blocks(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    map[static_cast<std::size_t>(order[i])] = static_cast<BlockId>(i);
    blocks[i] = std::move(f.blocks[static_cast<std::size_t>(order[i])]);
  }
  f.blocks = std::move(blocks);
  renumber(f, map);
}

void move_block(Function& f, BlockId from, BlockId to) {
  if (from == to) return;
  std::vector<BlockId> order(f.blocks.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<BlockId>(i);
  order.erase(order.begin() + from);
  order.insert(order.begin() + to, from);
  permute_blocks(f, order);
}

void remove_blocks(Function& f, const std::vector<bool>& keep) {
  std::vector<BlockId> map(f.blocks.size(), -1);
  std::vector<Block> blocks;
  for (std::size_t i = 0; i < f.blocks.size(); ++i)
    if (keep[i]) {
      map[i] = static_cast<BlockId>(blocks.size());
      blocks.push_back(std::move(f.blocks[i]));
    }
  f.blocks = std::move(blocks);
  renumber(f, map);
}

OperandSlots operand_slots(rcx::Op op) {
  OperandSlots slots;
  for (const auto& operand : rcx::info(op).operands)
    if (operand.role != rcx::Role::Argument && operand.role != rcx::Role::Offset &&
        operand.role != rcx::Role::Extension)
      slots.push_back(&operand);
  return slots;
}

bool fits_field(rcx::FieldType t, int v) {
  switch (t) {
    case rcx::FieldType::Byte: return v >= -128 && v <= 127;
    case rcx::FieldType::UByte: return v >= 0 && v <= 255;
    case rcx::FieldType::Short:
    case rcx::FieldType::ShortBE: return v >= -32768 && v <= 32767;
    case rcx::FieldType::UShort:
    case rcx::FieldType::UShortBE: return v >= 0 && v <= 65535;
  }
  return false;
}

namespace {
const rcx::Operand* argument_of(const rcx::OpcodeInfo& info, const rcx::Operand* source) {
  auto index = static_cast<std::int8_t>(source - info.operands.data());
  for (const auto& operand : info.operands)
    if (operand.role == rcx::Role::Argument && operand.pairs_with == index) return &operand;
  return nullptr;
}
}  // namespace

bool accepts(rcx::Op op, std::size_t slot, const Operand& o) {
  auto slots = operand_slots(op);
  if (slot >= slots.size()) return false;
  const rcx::Operand& operand = *slots[slot];
  switch (operand.role) {
    case rcx::Role::Variable: return o.is_var();
    case rcx::Role::Source:
    case rcx::Role::OpSource: {
      if (o.kind == Operand::Kind::Func) return false;
      if (!rcx::allows(operand.allowed, o.source)) return false;
      // Variables get a slot 0..31, which fits every argument field.
      if (o.is_var()) return true;
      const auto* arg = argument_of(rcx::info(op), &operand);
      return arg == nullptr || fits_field(arg->type, o.value);
    }
    default:
      if (o.kind == Operand::Kind::Func) return true;
      return o.is_imm() && fits_field(operand.type, o.value);
  }
}

bool computes_into_variable(rcx::Op op) {
  switch (op) {
    case rcx::Op::SetVariable:
    case rcx::Op::AddToVariable:
    case rcx::Op::SubtractFromVariable:
    case rcx::Op::MultiplyVariable:
    case rcx::Op::DivideVariable:
    case rcx::Op::AndVariable:
    case rcx::Op::OrVariable:
    case rcx::Op::AbsoluteValue:
    case rcx::Op::SignVariable: return true;
    default: return false;
  }
}

bool is_motor_command(const Instr& in) {
  return !in.raw && (in.op == rcx::Op::SetMotorDirection || in.op == rcx::Op::SetMotorOnOff ||
                     in.op == rcx::Op::SetMotorPower);
}

bool is_quick_command(const Instr& in) {
  return !in.raw && (is_motor_command(in) || in.op == rcx::Op::PlaySound || in.op == rcx::Op::PlayTone ||
                     computes_into_variable(in.op));
}

bool runs_several_tasks(const Program& p) {
  auto tasks = std::count_if(p.functions.begin(), p.functions.end(),
                             [](const Function& f) { return f.kind == FuncKind::Task && !f.blocks.empty(); });
  return tasks > 1;
}

bool seen_by_other_tasks(const Instr& in, const std::vector<Var>& vars) {
  if (is_motor_command(in)) return true;
  if (in.raw || !computes_into_variable(in.op)) return false;
  const Operand& dest = in.args.at(0);
  return dest.is_var() && shared_between_tasks(vars.at(static_cast<std::size_t>(dest.value)));
}

bool shared_between_tasks(const Var& v) { return v.kind == VarKind::Global; }

int instr_size(const Instr& in) {
  return in.raw ? static_cast<int>(in.args.size()) : rcx::command_size(rcx::info(in.op)).value_or(4);
}

namespace {
bool overwrites_destination(rcx::Op op) {
  return op == rcx::Op::SetVariable || op == rcx::Op::AbsoluteValue || op == rcx::Op::SignVariable;
}

// Which of an opcode's operand slots (operand_slots) it writes: what
// uses_of needs of the opcode table. The passes ask uses_of about every
// instruction many times, and walking the table's operand list each time,
// skipping the Argument halves and offsets, was most of its work. A
// constant worked out once from the opcode table.
struct SlotWrites {
  std::uint8_t count = 0;
  std::array<bool, kMaxOperandSlots> writes{};  // the slot is a Variable: written
};

const SlotWrites& slot_writes(rcx::Op op) {
  static const auto table = [] {
    std::array<SlotWrites, rcx::kOpcodeCount> t{};
    for (std::size_t i = 0; i < rcx::kOpcodeCount; ++i)
      for (const rcx::Operand* o : operand_slots(static_cast<rcx::Op>(i)))
        t[i].writes[t[i].count++] = o->role == rcx::Role::Variable;
    return t;
  }();
  return table[static_cast<std::size_t>(op)];
}

}  // namespace

VarUse uses_of(const Instr& in) {
  VarUse u;
  if (in.raw) {
    // Raw bytes may read or write a named variable in any way: treat every
    // mention as a read so nothing around it is removed or reordered.
    for (const auto& a : in.args)
      if (a.is_var()) u.reads.push_back(a.value);
    return u;
  }
  const SlotWrites& slots = slot_writes(in.op);
  const std::size_t n = std::min<std::size_t>(slots.count, in.args.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Operand& a = in.args[i];
    if (!a.is_var()) continue;
    if (slots.writes[i]) {
      u.writes.push_back(a.value);
      // set, abs and sgn compute from their source alone; the other
      // arithmetic instructions combine it with the old value.
      if (!overwrites_destination(in.op)) u.reads.push_back(a.value);
    } else {
      u.reads.push_back(a.value);
    }
  }
  return u;
}

InlineList<VarId, 2> reads_of(const Terminator& t) {
  InlineList<VarId, 2> r;
  if (const auto* b = std::get_if<Branch>(&t)) {
    if (b->a.is_var()) r.push_back(b->a.value);
    if (b->b.is_var()) r.push_back(b->b.value);
  }
  return r;
}

namespace {

std::string operand_text(const Program& p, const Operand& o) {
  switch (o.kind) {
    case Operand::Kind::Imm: return std::to_string(o.value);
    case Operand::Kind::Var:
      return (o.value >= 0 && static_cast<std::size_t>(o.value) < p.vars.size() && !p.vars[o.value].name.empty())
                 ? fmt::format("%{}", p.vars[o.value].name)
                 : fmt::format("%t{}", o.value);
    case Operand::Kind::Src: return fmt::format("{}({})", rcx::source_name(o.source), o.value);
    case Operand::Kind::Func:
      return (o.value >= 0 && static_cast<std::size_t>(o.value) < p.functions.size())
                 ? fmt::format("@{}", p.functions[o.value].name)
                 : fmt::format("@f{}", o.value);
  }
  return "?";
}

constexpr std::string_view kCmpText[] = {"<=", ">=", "!=", "==", "<", ">"};

std::string term_text(const Program& p, const Terminator& t) {
  if (const auto* j = std::get_if<Jump>(&t)) return fmt::format("jump b{}", j->target);
  if (const auto* b = std::get_if<Branch>(&t))
    return fmt::format("if {} {} {} then b{} else b{}", operand_text(p, b->a), kCmpText[static_cast<int>(b->cmp)],
                       operand_text(p, b->b), b->then, b->otherwise);
  if (const auto* l = std::get_if<LoopTest>(&t)) return fmt::format("loop{} b{} exit b{}", l->loop, l->body, l->exit);
  if (const auto* c = std::get_if<CoinToss>(&t)) return fmt::format("coin 0: b{} 1: b{}", c->zero, c->one);
  return "exit";
}

}  // namespace

std::string to_string(const Program& p, const Function& f) {
  std::string out = fmt::format("{} {}\n", f.kind == FuncKind::Task ? "task" : "sub", f.name);
  for (std::size_t b = 0; b < f.blocks.size(); ++b) {
    out += fmt::format("b{}:\n", b);
    for (const auto& in : f.blocks[b].instrs) {
      out += fmt::format("  {}", in.raw ? std::string_view("raw") : rcx::info(in.op).mnemonic);
      for (std::size_t i = 0; i < in.args.size(); ++i)
        out += fmt::format("{}{}", i ? ", " : " ", operand_text(p, in.args[i]));
      out += "\n";
    }
    out += "  " + term_text(p, f.blocks[b].term) + "\n";
  }
  return out;
}

std::string to_string(const Program& p) {
  std::string out;
  for (const auto& f : p.functions) out += to_string(p, f);
  return out;
}

}  // namespace rcxc::ir
