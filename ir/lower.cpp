#include "ir/lower.h"

#include <algorithm>
#include <bit>
#include <deque>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "frontend/fold.h"

namespace rcxc::ir {
namespace {

using rcx::Op;

// What a name stands for while lowering: a variable, or (const and
// const-reference parameters) an expression substituted at every use.
struct Binding {
  VarId var = -1;
  const ast::Expr* expr = nullptr;
};

// An enclosing loop or switch: where break and continue go.
struct LoopContext {
  BlockId break_to = 0;
  BlockId continue_to = -1;  // -1: a switch (continue passes through it)
  int repeat = -1;           // index in Function::repeats, for counter loops
};

// One task/sub body or one inline expansion.
struct Frame {
  BlockId return_to = -1;  // -1: leave the task/sub
  std::map<ast::SymbolId, BlockId> labels;
  std::size_t loop_base = 0;
  // The counter loops (Function::repeats indexes) around each label and
  // around each goto, to find the loops a goto leaves or enters.
  std::map<ast::SymbolId, std::vector<int>> repeats_at_label{};
  std::vector<std::pair<ast::SymbolId, std::vector<int>>> gotos{};
};

struct Lowerer {
  Lowerer(const ast::Program& program, Diagnostics& d) : ast(program), diags(d), env(program.symbols.size()) {}

  const ast::Program& ast;
  Diagnostics& diags;
  Program out;
  FuncId fid = 0;
  BlockId cur = 0;
  std::vector<BlockId> entered;  // layout: blocks in the order code enters them
  // What each symbol stands for now, indexed by SymbolId: every inline
  // call binds its parameters and restores them, so a lookup and a rebind
  // are an index, not a tree node allocated and freed per parameter.
  std::vector<std::optional<Binding>> env;
  std::vector<VarId> globals;
  std::map<int, VarId> reserved_vars;  // slot -> the variable standing for it (reserved_var)
  std::vector<LoopContext> loops;
  std::vector<std::vector<BlockId>> switches;
  std::vector<Frame> frames;
  std::vector<ast::SymbolId> expanding;
  // Inline functions' locals declared without a value, per task or sub.
  std::map<std::pair<ast::SymbolId, FuncId>, VarId> inline_locals;
  std::vector<SourceSpan> call_sites;  // where each expansion in `expanding` was called
  SourceSpan span{};  // of the statement being lowered
  // `span` in out.spans, added when an instruction or block first needs
  // it: a statement's instructions share one.
  SourceSpan interned{};
  SpanId interned_id = 0;  // out.spans[0] is the empty span
  // __taskid's value in the body being lowered: nqc's number of the task
  // (main 0, the others from 1 in the order declared), or of the one task
  // that calls the sub; none when no task or several do.
  std::optional<int> task_number;
  bool task_id_reported = false;  // in this sub, so that each says it once

  void set_task_number(std::optional<int> number) {
    task_number = number;
    constants.clear();
  }

  SpanId span_id() {
    if (span != interned) {
      interned = span;
      interned_id = out.add_span(span);
    }
    return interned_id;
  }

  Function& fn() { return out.functions[static_cast<std::size_t>(fid)]; }

  void error(SourceSpan at, std::string message) { report(std::nullopt, at, std::move(message)); }
  void warning(SourceSpan at, WarningKind kind, std::string message) { report(kind, at, std::move(message)); }

  static bool inside(const SourceSpan& inner, const SourceSpan& outer) {
    return inner.begin.file == outer.begin.file && !before(inner.begin, outer.begin) && !before(outer.end, inner.end);
  }

  // Inside inline expansions a problem is reported at the user's own call
  // (the outermost one), with notes down to the line where it arose: a
  // library function's line means little to someone who only called it,
  // and an IDE should mark the line the user wrote.
  // `warning`: which warning it is; none for an error.
  void report(std::optional<WarningKind> warning, SourceSpan at, std::string message) {
    auto say = [&](SourceSpan where) -> Diagnostic& {
      return warning ? diags.warning(where, *warning, std::move(message)) : diags.error(where, std::move(message));
    };
    if (call_sites.empty() || inside(at, call_sites.front())) {
      say(at);
      return;
    }
    Diagnostic& d = say(call_sites.front());
    for (std::size_t i = 1; i < call_sites.size(); ++i)
      d.notes.push_back({call_sites[i], fmt::format("in inline function '{}', which calls it here",
                                                    ast.symbol(expanding[i - 1]).name)});
    d.notes.push_back({at, fmt::format("in inline function '{}'", ast.symbol(expanding.back()).name)});
  }

  // ------------------------------------------------------------ emitting --

  BlockId new_block() {
    BlockId b = add_block(fn());
    fn().blocks[static_cast<std::size_t>(b)].span = span_id();
    return b;
  }
  void enter(BlockId b) {
    cur = b;
    entered.push_back(b);
  }
  // Operands, not a vector: a braced list of up to three operands stays
  // inside the instruction (a vector was an allocation and a free per
  // instruction lowered).
  void emit(Op op, Operands args) {
    fn().blocks[static_cast<std::size_t>(cur)].instrs.push_back(Instr{op, std::move(args), false, span_id()});
  }
  // The statement ending the block owns its branch (listings put its line
  // above it): the block itself may have been opened by an earlier one.
  void terminate(Terminator t) {
    auto& block = fn().blocks[static_cast<std::size_t>(cur)];
    block.term = t;
    if (std::holds_alternative<Branch>(t)) block.span = span_id();
  }
  void jump(BlockId b) { terminate(Jump{b}); }
  // After break/return/goto: what follows is reached only through a label.
  void dead_code() { enter(new_block()); }
  VarId temp() { return out.add_var("", VarKind::Temp); }

  // ----------------------------------------------------------- constants --

  void bind(ast::SymbolId symbol, std::optional<Binding> b) {
    // No expression names a symbol outside the table (ast.symbol() would
    // throw first), so such a binding could never be read.
    if (symbol < env.size()) env[symbol] = b;
    constants.clear();
    reads_memo.clear();
  }

  std::optional<Binding> binding(const ast::Name& n) {
    if (n.symbol == ast::kNoSymbol) return std::nullopt;
    const ast::Symbol& s = ast.symbol(n.symbol);
    if (s.kind == ast::SymbolKind::Global && s.index < globals.size()) return Binding{globals[s.index], nullptr};
    return env[n.symbol];
  }

  // The source node an expression stands for, through substitutions.
  const ast::Source* source_of(const ast::Expr& e) {
    if (const auto* s = ast::as<ast::Source>(e)) return s;
    if (const auto* n = ast::as<ast::Name>(e))
      if (auto b = binding(*n); b && b->expr) return source_of(*b->expr);
    return nullptr;
  }

  // `k ? a : b` with a constant k is just a or b (what else is constant
  // folds through constant()).
  const ast::Expr& chosen(const ast::Expr& e) {
    if (const auto* c = ast::as<ast::Conditional>(e))
      if (auto k = constant(*c->cond)) return chosen(*k != 0 ? *c->then_value : *c->else_value);
    return e;
  }

  // Remembered per node: lowering asks again at every level of a long
  // expression, which would otherwise walk its subtree each time. What a
  // node folds to depends only on the bindings and on __taskid, so `bind`
  // and `set_task_number` forget it all (an inline function's `__taskid + 1`
  // is another number in each task that calls it).
  std::unordered_map<const ast::Expr*, std::optional<int>> constants;
  // Expressions lowering builds itself (`x %= e` as `x % e`), alive as long
  // as the memos that name them.
  std::deque<ast::Expr> synthesized;

  std::optional<int> constant(const ast::Expr& e) {
    if (e.constant) return *e.constant;
    if (auto it = constants.find(&e); it != constants.end()) return it->second;
    if (ast::as<ast::TaskId>(e)) return task_id(e.span);
    auto c = std::visit([&](const auto& node) { return constant_of(node); }, e.node);
    constants.emplace(&e, c);
    return c;
  }
  std::optional<int> constant_of(const ast::IntLit& n) { return wrap16(static_cast<long>(n.value)); }
  std::optional<int> constant_of(const ast::Name& n) {
    auto b = binding(n);
    if (b && b->expr) return constant(*b->expr);
    return std::nullopt;
  }
  std::optional<int> constant_of(const ast::Unary& u) {
    auto x = constant(*u.operand);
    if (!x) return std::nullopt;
    switch (u.op) {
      case ast::UnaryOp::Negate: return wrap16(-static_cast<long>(*x));
      case ast::UnaryOp::BitNot: return wrap16(~static_cast<long>(*x));
      case ast::UnaryOp::LogNot: return *x == 0 ? 1 : 0;
      case ast::UnaryOp::Plus: return *x;
      case ast::UnaryOp::Abs: return *x == -32768 ? 32767 : (*x < 0 ? -*x : *x);
      case ast::UnaryOp::Sign: return (*x > 0) - (*x < 0);
      default: return std::nullopt;
    }
  }
  std::optional<int> constant_of(const ast::Binary& b) {
    auto l = constant(*b.lhs);
    if (b.op == ast::BinaryOp::LogAnd && l && *l == 0) return 0;
    if (b.op == ast::BinaryOp::LogOr && l && *l != 0) return 1;
    auto r = constant(*b.rhs);
    // x || 5 is 1 and x && 0 is 0 whatever x is, when x changes nothing.
    if (b.op == ast::BinaryOp::LogOr && r && *r != 0 && !has_effects(*b.lhs)) return 1;
    if (b.op == ast::BinaryOp::LogAnd && r && *r == 0 && !has_effects(*b.lhs)) return 0;
    if (auto z = absorbed(b, l, r)) return z;
    if (!l || !r) return std::nullopt;
    return binary_constant(b.op, *l, *r);
  }
  // 0 * x, x * 0, 0 & x, x & 0, -1 | x, x | -1, and 0 / x, 0 % x, 0 << x,
  // 0 >> x (whatever x is, 0 by the firmware's rules included: division by
  // zero leaves the dividend), x << 16 and x >> 16 (shifted out, as
  // frontend/fold.cpp folds them) are constant when x only reads: `(2/60) * d`
  // is 0. Reading the random source moves it on, so that is not just a read.
  std::optional<int> absorbed(const ast::Binary& b, std::optional<int> l, std::optional<int> r) {
    using Op = ast::BinaryOp;
    auto is = [](std::optional<int> v, int k) { return v && *v == k; };
    switch (b.op) {
      case Op::Mul:
      case Op::BitAnd:
        if (is(l, 0) && only_reads(*b.rhs)) return 0;
        if (is(r, 0) && only_reads(*b.lhs)) return 0;
        return std::nullopt;
      case Op::BitOr:
        if (is(l, -1) && only_reads(*b.rhs)) return -1;
        if (is(r, -1) && only_reads(*b.lhs)) return -1;
        return std::nullopt;
      case Op::Shl:
      case Op::Shr:
        if (r && *r >= 16 && only_reads(*b.lhs)) return 0;
        [[fallthrough]];
      case Op::Div:
      case Op::Mod:
        if (is(l, 0) && only_reads(*b.rhs)) return 0;
        return std::nullopt;
      default: return std::nullopt;
    }
  }
  bool only_reads(const ast::Expr& e) {
    if (has_effects(e)) return false;
    if (const auto* s = ast::as<ast::Source>(e)) {
      auto type = constant(*s->type);
      return type && *type != static_cast<int>(rcx::Source::Random) && only_reads(*s->arg);
    }
    if (const auto* n = ast::as<ast::Name>(e)) {
      auto b = binding(*n);
      return !b || !b->expr || only_reads(*b->expr);
    }
    if (const auto* u = ast::as<ast::Unary>(e)) return only_reads(*u->operand);
    if (const auto* b = ast::as<ast::Binary>(e)) return only_reads(*b->lhs) && only_reads(*b->rhs);
    if (const auto* c = ast::as<ast::Conditional>(e))
      return only_reads(*c->cond) && only_reads(*c->then_value) && only_reads(*c->else_value);
    return ast::as<ast::IntLit>(e) != nullptr;
  }

  std::optional<int> constant_of(const ast::Conditional& c) {
    auto k = constant(*c.cond);
    if (!k) return std::nullopt;
    return constant(*k ? *c.then_value : *c.else_value);
  }
  // __taskid: the task being lowered, or for a sub the one task that calls
  // it. nqc refuses it in a sub that no task or several tasks call.
  std::optional<int> task_id(SourceSpan at) {
    if (task_number) return *task_number;
    if (!task_id_reported) {
      task_id_reported = true;
      const ast::Sub& s = ast.subs[static_cast<std::size_t>(fid) - ast.tasks.size()];
      std::string callers;
      for (std::size_t i = 0; i < s.calling_tasks.size(); ++i)
        callers += fmt::format("{}'{}'", i == 0 ? "" : i + 1 == s.calling_tasks.size() ? " and " : ", ",
                               ast.symbol(s.calling_tasks[i]).name);
      error(at, s.calling_tasks.empty()
                      ? fmt::format("__taskid in sub '{}' has no value: no task calls the sub", s.name)
                      : fmt::format("__taskid in sub '{}' has no one value: tasks {} call the sub", s.name, callers));
    }
    return 0;
  }
  std::optional<int> constant_of(const ast::TypeOf& t) {
    auto bound = [&](const ast::Name& n) -> const ast::Expr* {
      auto b = binding(n);
      return b ? b->expr : nullptr;
    };
    auto id = task_number ? std::optional<std::int16_t>(static_cast<std::int16_t>(*task_number)) : std::nullopt;
    return frontend::nqc_constant(*t.operand, bound, id).constant ? 2 : 0;
  }
  std::optional<int> constant_of(const ast::SourceArg& s) {
    if (s.or_constant_byte)
      if (auto k = constant(*s.operand)) return *k & 0xff;
    const ast::Source* src = source_of(*s.operand);
    if (!src) return std::nullopt;
    auto type = constant(*src->type);
    if (s.type_required && type && *type != *s.type_required) return std::nullopt;
    return constant(*src->arg);
  }
  template <class T>
  std::optional<int> constant_of(const T&) {
    return std::nullopt;
  }

  // What the brick computes: the frontend's folding, and division by zero
  // leaves the dividend, as the firmware does.
  static std::optional<int> binary_constant(ast::BinaryOp op, int l, int r) {
    auto a = static_cast<std::int16_t>(l), b = static_cast<std::int16_t>(r);
    if ((op == ast::BinaryOp::Div || op == ast::BinaryOp::Mod) && b == 0) return a;
    return frontend::fold_binary(op, a, b);
  }

  // ---------------------------------------------------------- predicates --

  std::optional<VarId> var_of(const ast::Expr& e) {
    if (const auto* n = ast::as<ast::Name>(e)) {
      auto b = binding(*n);
      if (!b) return std::nullopt;
      if (b->expr) return var_of(*b->expr);
      return b->var;
    }
    if (auto slot = variable_slot(e)) return slot_global(*slot);
    return std::nullopt;
  }

  // nqc's `@N` (source type 0) is variable slot N, which nqc lets a program
  // read, assign, step and pass to an `int &` parameter as a variable. N
  // when e is one.
  std::optional<int> variable_slot(const ast::Expr& e) {
    const ast::Source* s = source_of(e);
    if (!s) return std::nullopt;
    auto type = constant(*s->type), arg = constant(*s->arg);
    if (!type || *type != static_cast<int>(rcx::Source::Variable) || !arg) return std::nullopt;
    return *arg;
  }

  // The global in slot N. The globals take the lowest free slots in
  // declaration order, past the reserved ones, used or not (slots.cpp), so
  // this is known before slots are given out.
  std::optional<VarId> slot_global(int slot) {
    std::uint32_t taken = out.reserved_slots;
    for (VarId g : globals) {
      if (taken == 0xffffffffu) break;
      int s = std::countr_one(taken);
      if (s == slot) return g;
      taken |= 1u << s;
    }
    return std::nullopt;
  }

  // A slot `#pragma reserve` keeps that `@N` names as a target: no variable
  // of the program is there, so the instruction names the slot itself.
  std::optional<int> reserved_slot_target(const ast::Expr& e) {
    auto slot = variable_slot(e);
    if (!slot || *slot < 0 || *slot > 31 || slot_global(*slot) || !((out.reserved_slots >> *slot) & 1u))
      return std::nullopt;
    return slot;
  }

  // Why `@N` cannot be written here, when e is such an @N: it holds no
  // global, and where rcxc puts locals and temporaries is its own choice.
  std::optional<std::string> unwritable_slot(const ast::Expr& e) {
    auto slot = variable_slot(e);
    if (!slot) return std::nullopt;
    if (*slot < 0 || *slot > 31)
      return fmt::format("variable slot {} does not exist: the RCX has slots 0 to 31", *slot);
    if ((out.reserved_slots >> *slot) & 1u)
      return fmt::format("variable slot {} is one #pragma reserve keeps: no variable of the program is there, so it "
                         "is assigned by number and cannot stand for one",
                         *slot);
    return fmt::format("variable slot {} holds no global variable: rcxc chooses the slots of locals and temporaries "
                       "itself; name the variable, or keep the slot with #pragma reserve",
                       *slot);
  }

  // The variable standing for a slot `#pragma reserve` keeps, fixed there:
  // a global without a name (no symbol: no variable of the program is
  // there), which the passes treat as any global (never dropped as a dead
  // store, never known constant), so `@11 <<= 2` is one instruction on the
  // slot, as it is on a global, where a raw instruction kept it apart.
  VarId reserved_var(int slot) {
    auto [it, added] = reserved_vars.try_emplace(slot, -1);
    if (added) {
      it->second = out.add_var("", VarKind::Global);
      out.vars[static_cast<std::size_t>(it->second)].slot = slot;
    }
    return it->second;
  }

  // The variable an assignment or a step to `e` writes: the variable e
  // names, or a reserved slot's.
  std::optional<VarId> written_var(const ast::Expr& e) {
    if (auto v = var_of(e)) return v;
    if (auto slot = reserved_slot_target(e)) return reserved_var(*slot);
    return std::nullopt;
  }

  // Whether evaluating `e` reads variable `v` (through substitutions too).
  // Remembered like `constants`, for the same reason.
  std::map<std::pair<const ast::Expr*, VarId>, bool> reads_memo;

  bool reads(const ast::Expr& e, VarId v) {
    if (auto it = reads_memo.find({&e, v}); it != reads_memo.end()) return it->second;
    bool r = reads_uncached(e, v);
    reads_memo.emplace(std::pair{&e, v}, r);
    return r;
  }

  bool reads_uncached(const ast::Expr& e, VarId v) {
    if (const auto* n = ast::as<ast::Name>(e)) {
      auto b = binding(*n);
      return b && (b->expr ? reads(*b->expr, v) : b->var == v);
    }
    if (const auto* u = ast::as<ast::Unary>(e)) return reads(*u->operand, v);
    if (const auto* b = ast::as<ast::Binary>(e)) return reads(*b->lhs, v) || reads(*b->rhs, v);
    if (const auto* a = ast::as<ast::Assign>(e)) return reads(*a->target, v) || reads(*a->value, v);
    if (const auto* c = ast::as<ast::Conditional>(e))
      return reads(*c->cond, v) || reads(*c->then_value, v) || reads(*c->else_value, v);
    if (auto slot = variable_slot(e)) {
      if (slot_global(*slot) == v) return true;
      auto r = reserved_vars.find(*slot);
      return r != reserved_vars.end() && r->second == v && reserved_slot_target(e);
    }
    return false;
  }

  bool has_effects(const ast::Expr& e) {
    if (ast::as<ast::Assign>(e) || ast::as<ast::Call>(e)) return true;
    if (const auto* n = ast::as<ast::Name>(e)) {
      auto b = binding(*n);
      return b && b->expr && has_effects(*b->expr);
    }
    if (const auto* u = ast::as<ast::Unary>(e))
      return u->op == ast::UnaryOp::PreInc || u->op == ast::UnaryOp::PreDec || u->op == ast::UnaryOp::PostInc ||
             u->op == ast::UnaryOp::PostDec || has_effects(*u->operand);
    if (const auto* b = ast::as<ast::Binary>(e)) return has_effects(*b->lhs) || has_effects(*b->rhs);
    if (const auto* c = ast::as<ast::Conditional>(e))
      return has_effects(*c->cond) || has_effects(*c->then_value) || has_effects(*c->else_value);
    return false;
  }

  // --------------------------------------------------------- expressions --

  // An operand holding e's value: an immediate, a variable or an RCX source
  // when e is one, else a temporary computed here.
  Operand value(const ast::Expr& whole) {
    const ast::Expr& e = chosen(whole);
    if (auto c = constant(e)) return Operand::imm(*c);
    if (const auto* n = ast::as<ast::Name>(e)) {
      auto b = binding(*n);
      if (b && b->expr) return value(*b->expr);
      if (b) return Operand::var(b->var);
      error(e.span, fmt::format("'{}' is not a variable here", n->name));
      return Operand::imm(0);
    }
    if (const auto* s = ast::as<ast::Source>(e)) {
      auto type = constant(*s->type), arg = constant(*s->arg);
      if (!type || !arg || *type < 0 || *type > 15) {
        error(e.span, non_constant_source(*s, type));
        return Operand::imm(0);
      }
      // @N where a global is: that global, so the passes see it read.
      if (*type == static_cast<int>(rcx::Source::Variable)) {
        if (auto g = slot_global(*arg)) return Operand::var(*g);
        if (auto r = reserved_slot_target(e)) return Operand::var(reserved_var(*r));
      }
      return Operand::src(*type, *arg);
    }
    VarId t = temp();
    into(t, e);
    return Operand::var(t);
  }

  // A source whose argument comes from a `const int &` parameter (the only
  // way sema lets one through) that is no constant at this call: said in
  // the words of the call written (Timer(t), Random(m), SensorValueRaw(s)),
  // as sema says it of a variable written there.
  static std::string non_constant_source(const ast::Source& s, std::optional<int> type) {
    if (!type || *type < 0 || *type > 15) return "__source needs a constant source type (0..15) and argument";
    const ast::Expr* arg = s.arg.get();
    bool sensor = false;
    if (const auto* sa = ast::as<ast::SourceArg>(*arg)) {
      sensor = sa->or_constant_byte;
      arg = sa->operand.get();
    }
    const auto* n = ast::as<ast::Name>(*arg);
    std::string which = n ? "'" + n->name + "'" : std::string("the argument");
    std::string what = "the argument of __source must be a constant expression";
    if (sensor) {
      what = "the argument must be a sensor (SENSOR_1, SENSOR_2 or SENSOR_3)";
    } else if (*type == static_cast<int>(rcx::Source::Random)) {
      what = "the maximum of Random(n) must be a constant expression";
    } else if (auto range = rcx::source_argument_range(*type); range && !range->noun.empty()) {
      what = fmt::format("the {} number must be a constant expression", range->noun);
    }
    return what + ", and " + which + " is not one at this call";
  }

  // An operand `op` accepts at `slot`, through a temporary if needed.
  Operand operand_for(Op op, std::size_t slot, const ast::Expr& e) {
    Operand v = value(e);
    if (accepts(op, slot, v)) return v;
    VarId t = temp();
    emit(Op::SetVariable, {Operand::var(t), v});
    return Operand::var(t);
  }
  // The second operand of variable arithmetic (variable or immediate).
  Operand arith_value(const ast::Expr& e) { return operand_for(Op::AddToVariable, 1, e); }
  // arith_value, except that ++x and --x step x now and stand for x itself.
  Operand stepped_value(const ast::Expr& e) {
    if (const auto* u = ast::as<ast::Unary>(chosen(e));
        u && (u->op == ast::UnaryOp::PreInc || u->op == ast::UnaryOp::PreDec))
      if (auto v = step(*u, e.span)) return Operand::var(*v);
    return arith_value(e);
  }

  // An operand a test-and-branch can compare (not random or program number,
  // argument within a byte so either position works).
  Operand test_value(const ast::Expr& e) {
    Operand v = value(e);
    bool ok = v.kind != Operand::Kind::Src ||
              (v.source != 4 && v.source != 8 && v.source >= 0 && v.value >= -128 && v.value <= 127);
    if (ok) return v;
    VarId t = temp();
    emit(Op::SetVariable, {Operand::var(t), v});
    return Operand::var(t);
  }

  // test_value, except that ++x and --x step x now and stand for x itself,
  // read by the test: as in nqc's code, `--c <= c++` with c at 5 compares
  // 5 with 4 (c is 4 after `--c`, and `c++` makes it 5 before the test).
  Operand stepped_test_value(const ast::Expr& whole) {
    const ast::Expr& e = chosen(whole);
    if (const auto* n = ast::as<ast::Name>(e))
      if (auto b = binding(*n); b && b->expr) return stepped_test_value(*b->expr);
    if (const auto* u = ast::as<ast::Unary>(e); u && (u->op == ast::UnaryOp::PreInc || u->op == ast::UnaryOp::PreDec))
      if (auto v = step(*u, e.span)) return Operand::var(*v);
    return test_value(e);
  }

  void set(VarId d, Operand v) {
    if (!v.is_var(d)) emit(Op::SetVariable, {Operand::var(d), v});
  }
  void arith(Op op, VarId d, Operand v) { emit(op, {Operand::var(d), v}); }

  static std::optional<Op> direct_op(ast::BinaryOp op) {
    switch (op) {
      case ast::BinaryOp::Add: return Op::AddToVariable;
      case ast::BinaryOp::Sub: return Op::SubtractFromVariable;
      case ast::BinaryOp::Mul: return Op::MultiplyVariable;
      case ast::BinaryOp::Div: return Op::DivideVariable;
      case ast::BinaryOp::BitAnd: return Op::AndVariable;
      case ast::BinaryOp::BitOr: return Op::OrVariable;
      default: return std::nullopt;
    }
  }

  // d = e, for any e (also one that reads d).
  void into(VarId d, const ast::Expr& whole) {
    const ast::Expr& e = chosen(whole);
    if (const auto* n = ast::as<ast::Name>(e)) {
      // A `const int &` parameter stands for its argument: look at that
      // (c = e with e bound to c - 2 is c -= 2).
      auto b = binding(*n);
      if (b && b->expr) return into(d, *b->expr);
    }
    if (!reads(e, d) || constant(e)) return compute(d, e);
    // Below, e reads d: d may only change once what reads it is done.
    if (const auto* b = ast::as<ast::Binary>(e)) {
      // A shift computes its count first, then works on its left side in d.
      if (b->op == ast::BinaryOp::Shl || b->op == ast::BinaryOp::Shr)
        return shift(d, *b, b->op == ast::BinaryOp::Shl);
      auto op = direct_op(b->op);
      if (op && right_first(*b) && !reads(*b->lhs, d)) {
        into(d, *b->rhs);  // x = 5 + x * SENSOR_1  ->  x *= t; x += 5
        arith(*op, d, arith_value(*b->lhs));
        return;
      }
      // The left side may have side effects of its own (x = (x - y++) & 3):
      // into() computes all of it, d included, before the right side runs.
      if (op && !reads(*b->rhs, d)) {
        into(d, *b->lhs);  // x = x + e  ->  x += e; x = (x > 1) - y likewise
        arith(*op, d, stepped_value(*b->rhs));
        return;
      }
    }
    if (auto v = var_of(e); v && *v == d) return;
    if (const auto* u = ast::as<ast::Unary>(e);
        u && (u->op == ast::UnaryOp::PostInc || u->op == ast::UnaryOp::PostDec))
      if (auto v = var_of(*u->operand); v && *v == d) return;  // d = d++: the old value wins, as in nqc's code
    if (const auto* u = ast::as<ast::Unary>(e);
        u && (u->op == ast::UnaryOp::Negate || u->op == ast::UnaryOp::BitNot))
      return unary(d, *u, e);  // x = -x, x = ~(x + 1): in place
    // One instruction reads its source before it writes d: x = abs(x) is
    // `abs x, x`, as nqc writes it (a temporary and a copy cost 5 bytes and
    // an instruction more); so is y = abs(x - y), the operand computed into
    // a temporary first (`set t, x; sub t, y; abs y, t`).
    if (const auto* u = ast::as<ast::Unary>(e); u && (u->op == ast::UnaryOp::Abs || u->op == ast::UnaryOp::Sign))
      return unary(d, *u, e);
    if (const auto* c = ast::as<ast::Conditional>(e)) return conditional(d, *c);
    if (is_truth_valued(e)) {
      // x = (x > 3): each branch sets x once the test is done, which needs
      // no temporary (19 bytes against 22).
      BlockId t = new_block(), f = new_block(), join = new_block();
      cond(e, t, f);
      return one_or_zero(d, t, f, join);
    }
    VarId t = temp();
    compute(t, e);
    set(d, Operand::var(t));
  }

  // Whether e is a variable or a constant, which arithmetic takes as it is.
  bool is_plain_operand(const ast::Expr& e) {
    if (constant(e)) return true;
    if (const auto* n = ast::as<ast::Name>(e)) {
      auto b = binding(*n);
      if (b && b->expr) return is_plain_operand(*b->expr);
      return b.has_value();
    }
    return false;
  }

  // Whether e's value is 0 or 1 from a test: a comparison, !, && or ||.
  static bool is_truth_valued(const ast::Expr& e) {
    if (const auto* u = ast::as<ast::Unary>(e)) return u->op == ast::UnaryOp::LogNot;
    if (const auto* b = ast::as<ast::Binary>(e)) {
      switch (b->op) {
        case ast::BinaryOp::Lt: case ast::BinaryOp::Le: case ast::BinaryOp::Gt: case ast::BinaryOp::Ge:
        case ast::BinaryOp::Eq: case ast::BinaryOp::Ne: case ast::BinaryOp::LogAnd: case ast::BinaryOp::LogOr:
          return true;
        default: return false;
      }
    }
    return false;
  }

  // d = e where e does not read d (so d can hold partial results).
  void compute(VarId d, const ast::Expr& whole) {
    const ast::Expr& e = chosen(whole);
    if (auto c = constant(e)) return set(d, Operand::imm(*c));
    if (const auto* n = ast::as<ast::Name>(e)) {
      auto b = binding(*n);
      if (b && b->expr) return into(d, *b->expr);
      return set(d, value(e));
    }
    if (ast::as<ast::Source>(e)) return set(d, value(e));
    if (const auto* u = ast::as<ast::Unary>(e)) return unary(d, *u, e);
    if (const auto* b = ast::as<ast::Binary>(e)) return binary(d, *b, e);
    if (const auto* a = ast::as<ast::Assign>(e)) return set(d, Operand::var(assign(*a, e.span)));
    if (const auto* c = ast::as<ast::Conditional>(e)) return conditional(d, *c);
    if (const auto* sa = ast::as<ast::SourceArg>(e)) {
      error(e.span, sa->or_constant_byte ? "argument must be a sensor (SENSOR_1, SENSOR_2 or SENSOR_3) or a constant"
                                         : "__source_arg needs a source expression such as SENSOR_1");
      return;
    }
    error(e.span, "a call has no value");
  }

  // d = c ? t : e. The test is done before either side sets d, so the
  // test and both sides may read d.
  void conditional(VarId d, const ast::Conditional& c) {
    BlockId t = new_block(), f = new_block(), join = new_block();
    cond(*c.cond, t, f);
    enter(t);
    into(d, *c.then_value);
    jump(join);
    enter(f);
    into(d, *c.else_value);
    jump(join);
    enter(join);
  }

  // After a branch to `one` or `zero`: d = 1 on the first, 0 on the
  // second, both going on at `join`.
  // The side placed after the test falls in and then jumps over the other,
  // so it runs one instruction more. For a truth value that is the zero
  // side, as in nqc's code (the test branches to `one`); `one_falls_in`
  // asks for the other (x >> 15: the sign's test branches on >= 0, as
  // nqc's does). The last test decides when it can only branch one way
  // (a < b of two variables).
  void one_or_zero(VarId d, BlockId one, BlockId zero, BlockId join, bool one_falls_in = false) {
    bool one_first = one_falls_in;
    if (const auto* br = std::get_if<Branch>(&fn().blocks[static_cast<std::size_t>(cur)].term)) {
      auto reaches = [&](BlockId side) {
        return (br->then == side && branches_directly(br->cmp, br->a, br->b)) ||
               (br->otherwise == side && branches_directly(negate(br->cmp), br->a, br->b));
      };
      one_first = one_falls_in ? reaches(zero) : !reaches(one);
    }
    auto side = [&](BlockId b, int value) {
      enter(b);
      set(d, Operand::imm(value));
      jump(join);
    };
    if (one_first) {
      side(one, 1);
      side(zero, 0);
    } else {
      side(zero, 0);
      side(one, 1);
    }
    enter(join);
  }

  // d = 0 or 1: the truth of e, which does not read d. `d = 0` before the
  // tests lets the false outcome fall through to the end without a jump,
  // but when the only test cannot branch on false (x >= y of two
  // variables) it needs a jump all the same: then the test branches to
  // `d = 1` and the false side sets 0 and jumps, the same bytes and one
  // instruction less when true.
  void truth(VarId d, const ast::Expr& e) {
    BlockId t = new_block(), join = new_block();
    BlockId test = cur;
    auto& instrs = fn().blocks[static_cast<std::size_t>(test)].instrs;
    std::size_t zero_at = instrs.size();
    set(d, Operand::imm(0));
    cond(e, t, join);
    const auto* br = std::get_if<Branch>(&fn().blocks[static_cast<std::size_t>(cur)].term);
    bool false_needs_jump = br && cur == test &&
                            ((br->then == t && !branches_directly(negate(br->cmp), br->a, br->b)) ||
                             (br->otherwise == t && !branches_directly(br->cmp, br->a, br->b)));
    if (false_needs_jump) {
      auto& same = fn().blocks[static_cast<std::size_t>(test)].instrs;
      same.erase(same.begin() + static_cast<std::ptrdiff_t>(zero_at));
      Branch b = *br;  // before new_block(), which may move the blocks br points into
      BlockId zero = new_block();
      (b.then == join ? b.then : b.otherwise) = zero;
      terminate(b);
      return one_or_zero(d, t, zero, join);
    }
    enter(t);
    set(d, Operand::imm(1));
    jump(join);
    enter(join);
  }

  void unary(VarId d, const ast::Unary& u, const ast::Expr& e) {
    switch (u.op) {
      case ast::UnaryOp::Plus: return into(d, *u.operand);
      case ast::UnaryOp::Negate:
        into(d, *u.operand);
        return arith(Op::MultiplyVariable, d, Operand::imm(-1));
      case ast::UnaryOp::BitNot: {  // ~x == -1 - x == -x - 1 in two's complement
        if (!reads(*u.operand, d) && is_plain_operand(*u.operand)) {
          set(d, Operand::imm(-1));
          return arith(Op::SubtractFromVariable, d, arith_value(*u.operand));
        }
        into(d, *u.operand);
        arith(Op::MultiplyVariable, d, Operand::imm(-1));
        return arith(Op::SubtractFromVariable, d, Operand::imm(1));
      }
      case ast::UnaryOp::LogNot: return truth(d, e);
      // abs(++x) steps x and reads x itself, as nqc's code does (a copy of x
      // into a temporary first cost 5 bytes and an instruction).
      case ast::UnaryOp::Abs: return arith(Op::AbsoluteValue, d, stepped_value(*u.operand));
      case ast::UnaryOp::Sign: return arith(Op::SignVariable, d, stepped_value(*u.operand));
      case ast::UnaryOp::PreInc:
      case ast::UnaryOp::PreDec:
        if (auto v = step(u, e.span)) set(d, Operand::var(*v));
        return;
      case ast::UnaryOp::PostInc:
      case ast::UnaryOp::PostDec: {
        auto v = written_var(*u.operand);
        if (!v) return error(e.span, unwritable_slot(*u.operand).value_or("++ and -- need a variable"));
        set(d, Operand::var(*v));
        step(u, e.span);
        return;
      }
    }
  }

  // ++x / --x / x++ / x-- as a statement; returns the variable.
  std::optional<VarId> step(const ast::Unary& u, SourceSpan at) {
    bool inc = u.op == ast::UnaryOp::PreInc || u.op == ast::UnaryOp::PostInc;
    Op op = inc ? Op::AddToVariable : Op::SubtractFromVariable;
    auto v = written_var(*u.operand);
    if (!v) {
      error(at, unwritable_slot(*u.operand).value_or("++ and -- need a variable"));
      return std::nullopt;
    }
    arith(op, *v, Operand::imm(1));
    return v;
  }

  // For + * & |, whether to compute the right side first and apply the
  // left, a variable or constant, to it: `300 + Random(300)` is `t =
  // Random(300); t += 300`, where left to right sets 300, draws into a
  // second temporary and adds it (the arithmetic opcodes take only a
  // variable or a constant). Only where the order cannot show: the left
  // side is a constant, or a variable the right side does not change.
  // A right side that tests (`c + (b < c) * 3`) stays second: in a
  // temporary its 0 or 1 and what follows fold into the branches
  // (joinconst.cpp), which they cannot in a global.
  bool right_first(const ast::Binary& b) {
    bool commutes = b.op == ast::BinaryOp::Add || b.op == ast::BinaryOp::Mul || b.op == ast::BinaryOp::BitAnd ||
                    b.op == ast::BinaryOp::BitOr;
    if (!commutes || !is_plain_operand(*b.lhs) || is_plain_operand(*b.rhs) || tests(*b.rhs)) return false;
    return constant(*b.lhs) || !has_effects(*b.rhs);
  }

  // Whether computing e takes a branch: a comparison, !, &&, || or ?:.
  bool tests(const ast::Expr& whole) {
    const ast::Expr& e = chosen(whole);
    if (is_truth_valued(e) || ast::as<ast::Conditional>(e)) return true;
    if (const auto* u = ast::as<ast::Unary>(e)) return tests(*u->operand);
    if (const auto* b = ast::as<ast::Binary>(e)) return tests(*b->lhs) || tests(*b->rhs);
    if (const auto* a = ast::as<ast::Assign>(e)) return tests(*a->value);
    return false;
  }

  void binary(VarId d, const ast::Binary& b, const ast::Expr& e) {
    if (auto op = direct_op(b.op)) {
      if (right_first(b)) {
        compute(d, *b.rhs);
        return arith(*op, d, arith_value(*b.lhs));
      }
      into(d, *b.lhs);
      return arith(*op, d, stepped_value(*b.rhs));
    }
    switch (b.op) {
      case ast::BinaryOp::Mod: {
        // a % b == a - (a / b) * b with the firmware's truncating division.
        // As in nqc's code, a variable on the left is read after the right
        // side is computed, and ++x / --x stand for x itself: with b at 5,
        // --b % b++ is 5 % 4.
        Operand x = stepped_value(*b.lhs);
        Operand y = stepped_value(*b.rhs);
        set(d, x);
        arith(Op::DivideVariable, d, y);
        arith(Op::MultiplyVariable, d, y);
        arith(Op::SubtractFromVariable, d, x);
        return arith(Op::MultiplyVariable, d, Operand::imm(-1));
      }
      case ast::BinaryOp::BitXor: {
        // a ^ b == (a | b) - (a & b)
        Operand x = arith_value(*b.lhs), y = arith_value(*b.rhs);
        VarId t = temp();
        set(d, x);
        arith(Op::OrVariable, d, y);
        set(t, x);
        arith(Op::AndVariable, t, y);
        return arith(Op::SubtractFromVariable, d, Operand::var(t));
      }
      case ast::BinaryOp::Shl: return shift(d, b, true);
      case ast::BinaryOp::Shr: return shift(d, b, false);
      default: return truth(d, e);
    }
  }

  // d >>= n for a constant n in 1..14, shifting in zeros: a negative value
  // loses its sign bit first, which then reappears n places lower.
  void shift_right_const(VarId d, int n) {
    BlockId neg = new_block(), pos = new_block(), join = new_block();
    terminate(Branch{Cmp::LT, Operand::var(d), Operand::imm(0), neg, pos});
    enter(neg);
    arith(Op::AndVariable, d, Operand::imm(0x7fff));
    arith(Op::DivideVariable, d, Operand::imm(1 << n));
    arith(Op::OrVariable, d, Operand::imm(1 << (15 - n)));
    jump(join);
    enter(pos);
    arith(Op::DivideVariable, d, Operand::imm(1 << n));
    jump(join);
    enter(join);
  }

  void shift_const(VarId d, bool left, int n) {
    if (n <= 0) return;
    if (n >= 16) return set(d, Operand::imm(0));
    if (left) return arith(Op::MultiplyVariable, d, Operand::imm(wrap16(1L << n)));
    if (n == 15) {  // only the sign bit survives
      BlockId neg = new_block(), join = new_block();
      BlockId pos = new_block();
      terminate(Branch{Cmp::LT, Operand::var(d), Operand::imm(0), neg, pos});
      return one_or_zero(d, neg, pos, join, true);
    }
    shift_right_const(d, n);
  }

  void shift(VarId d, const ast::Binary& b, bool left) {
    if (auto n = constant(*b.rhs)) {
      into(d, *b.lhs);
      return shift_const(d, left, *n);
    }
    // Shift one place per iteration, count in a temporary.
    VarId count = temp();
    into(count, *b.rhs);
    if (reads(*b.lhs, d)) {
      VarId t = temp();
      into(t, *b.lhs);
      set(d, Operand::var(t));
    } else {
      into(d, *b.lhs);
    }
    BlockId head = new_block(), body = new_block(), done = new_block();
    jump(head);
    enter(head);
    terminate(Branch{Cmp::GT, Operand::var(count), Operand::imm(0), body, done});
    enter(body);
    if (left)
      arith(Op::AddToVariable, d, Operand::var(d));
    else
      shift_right_const(d, 1);
    arith(Op::SubtractFromVariable, count, Operand::imm(1));
    jump(head);
    enter(done);
  }

  // Performs `target op= value`; returns the target variable.
  VarId assign(const ast::Assign& a, SourceSpan at) {
    auto v = written_var(*a.target);
    if (!v) {
      error(at, unwritable_slot(*a.target).value_or("the left side of an assignment must be a variable"));
      return temp();
    }
    auto binary_op = compound_op(a.op);
    switch (a.op) {
      case ast::AssignOp::Assign: into_visible(*v, *a.value); break;
      case ast::AssignOp::Abs: arith(Op::AbsoluteValue, *v, stepped_value(*a.value)); break;
      case ast::AssignOp::Sign: arith(Op::SignVariable, *v, stepped_value(*a.value)); break;
      default:
        if (auto op = direct_op(*binary_op)) {
          arith(*op, *v, stepped_value(*a.value));
        } else {
          // Kept for the whole lowering: the memos are keyed by node
          // address, and a freed node's address comes back for the next.
          const ast::Expr& whole =
              synthesized.emplace_back(ast::Expr{ast::Binary{*binary_op, *a.target, *a.value}, at, std::nullopt});
          into_visible(*v, whole);
        }
    }
    return *v;
  }

  // v = e where another task may watch v: computed in place, v would hold
  // each step for an instruction. nqc's code computes in place too, as a
  // chain from the first operand (`g = (a + b) * c`: a, a + b), which rcxc
  // keeps; the steps it takes otherwise (-x as x then its negation, ~E and
  // -E, a ^ b as a | b first, an operand computed before the first one)
  // nqc's code never shows, so those go through a temporary and v takes
  // only the result. `g = -E` is `g = 0; g -= E`, and `g = ~E` `g = -1;
  // g -= E`, as nqc's (E in a temporary unless a variable or constant).
  void into_visible(VarId v, const ast::Expr& whole) {
    if (ast.tasks.size() < 2 || !shared_between_tasks(out.vars[static_cast<std::size_t>(v)])) return into(v, whole);
    const ast::Expr& e = chosen(whole);
    if (constant(e)) return into(v, e);
    if (const auto* u = ast::as<ast::Unary>(e); u && (u->op == ast::UnaryOp::Negate || u->op == ast::UnaryOp::BitNot)) {
      if (u->op == ast::UnaryOp::Negate && var_of(*u->operand) == v) return into(v, e);  // v *= -1: one step
      if (!reads(*u->operand, v)) {
        Operand x = arith_value(*u->operand);  // a temporary unless a variable or constant
        set(v, Operand::imm(u->op == ast::UnaryOp::Negate ? 0 : -1));
        return arith(Op::SubtractFromVariable, v, x);
      }
    }
    if (!steps_unlike_nqcs(e, v)) return into(v, e);
    VarId t = temp();
    compute(t, e);
    set(v, Operand::var(t));
  }

  // Whether computing e in place holds a value nqc's code would not: see
  // into_visible.
  bool steps_unlike_nqcs(const ast::Expr& whole, VarId v) {
    const ast::Expr& e = chosen(whole);
    if (constant(e)) return false;
    if (const auto* n = ast::as<ast::Name>(e)) {
      auto b = binding(*n);
      return b && b->expr && steps_unlike_nqcs(*b->expr, v);
    }
    if (const auto* u = ast::as<ast::Unary>(e)) {
      if (u->op == ast::UnaryOp::Negate) return true;
      if (u->op == ast::UnaryOp::BitNot) return !is_plain_operand(*u->operand) || reads(*u->operand, v);
      return false;
    }
    if (const auto* c = ast::as<ast::Conditional>(e))
      return steps_unlike_nqcs(*c->then_value, v) || steps_unlike_nqcs(*c->else_value, v);
    if (const auto* b = ast::as<ast::Binary>(e)) {
      if (b->op == ast::BinaryOp::BitXor) return true;
      if (direct_op(b->op) && right_first(*b)) return true;
      if (direct_op(b->op) || b->op == ast::BinaryOp::Shl || b->op == ast::BinaryOp::Shr)
        return steps_unlike_nqcs(*b->lhs, v);
    }
    return false;
  }

  static std::optional<ast::BinaryOp> compound_op(ast::AssignOp op) {
    switch (op) {
      case ast::AssignOp::Add: return ast::BinaryOp::Add;
      case ast::AssignOp::Sub: return ast::BinaryOp::Sub;
      case ast::AssignOp::Mul: return ast::BinaryOp::Mul;
      case ast::AssignOp::Div: return ast::BinaryOp::Div;
      case ast::AssignOp::Mod: return ast::BinaryOp::Mod;
      case ast::AssignOp::BitAnd: return ast::BinaryOp::BitAnd;
      case ast::AssignOp::BitOr: return ast::BinaryOp::BitOr;
      case ast::AssignOp::BitXor: return ast::BinaryOp::BitXor;
      case ast::AssignOp::Shl: return ast::BinaryOp::Shl;
      case ast::AssignOp::Shr: return ast::BinaryOp::Shr;
      default: return std::nullopt;
    }
  }

  // Evaluates e for its side effects only.
  void effect(const ast::Expr& e) {
    if (expanding.empty()) span = e.span;
    if (const auto* a = ast::as<ast::Assign>(e)) {
      assign(*a, e.span);
    } else if (const auto* u = ast::as<ast::Unary>(e); u && u->op != ast::UnaryOp::Negate &&
                                                       u->op != ast::UnaryOp::BitNot && u->op != ast::UnaryOp::LogNot &&
                                                       u->op != ast::UnaryOp::Plus && u->op != ast::UnaryOp::Abs &&
                                                       u->op != ast::UnaryOp::Sign) {
      step(*u, e.span);
    } else if (const auto* c = ast::as<ast::Call>(e)) {
      call(*c, e.span);
    } else if (const auto* k = ast::as<ast::Conditional>(e)) {
      BlockId t = new_block(), f = new_block(), join = new_block();
      cond(*k->cond, t, f);
      enter(t);
      effect(*k->then_value);
      jump(join);
      enter(f);
      effect(*k->else_value);
      jump(join);
      enter(join);
    } else if (has_effects(e)) {
      value(e);
    }
  }

  // --------------------------------------------------------- conditions --

  static std::optional<Cmp> comparison(ast::BinaryOp op) {
    switch (op) {
      case ast::BinaryOp::Lt: return Cmp::LT;
      case ast::BinaryOp::Le: return Cmp::LE;
      case ast::BinaryOp::Gt: return Cmp::GT;
      case ast::BinaryOp::Ge: return Cmp::GE;
      case ast::BinaryOp::Eq: return Cmp::EQ;
      case ast::BinaryOp::Ne: return Cmp::NE;
      default: return std::nullopt;
    }
  }

  // Ends the current block with a branch to t when e is true, else to f.
  void cond(const ast::Expr& e, BlockId t, BlockId f) {
    if (auto c = constant(e)) return jump(*c ? t : f);
    if (const auto* n = ast::as<ast::Name>(e))
      if (auto b = binding(*n); b && b->expr) return cond(*b->expr, t, f);
    if (const auto* u = ast::as<ast::Unary>(e); u && u->op == ast::UnaryOp::LogNot) return cond(*u->operand, f, t);
    if (const auto* b = ast::as<ast::Binary>(e)) {
      if (b->op == ast::BinaryOp::LogAnd || b->op == ast::BinaryOp::LogOr) {
        BlockId mid = new_block();
        if (b->op == ast::BinaryOp::LogAnd)
          cond(*b->lhs, mid, f);
        else
          cond(*b->lhs, t, mid);
        enter(mid);
        return cond(*b->rhs, t, f);
      }
      if (auto cmp = comparison(b->op)) {
        Operand x = stepped_test_value(*b->lhs);
        Operand y = stepped_test_value(*b->rhs);
        return terminate(Branch{*cmp, x, y, t, f});
      }
    }
    terminate(Branch{Cmp::NE, stepped_test_value(e), Operand::imm(0), t, f});
  }

  // --------------------------------------------------------------- calls --

  FuncId function_of(ast::SymbolId id) {
    const ast::Symbol& s = ast.symbol(id);
    if (s.kind == ast::SymbolKind::Task) return static_cast<FuncId>(s.index);
    if (s.kind == ast::SymbolKind::Sub) return static_cast<FuncId>(ast.tasks.size() + s.index);
    return -1;
  }

  void call(const ast::Call& c, SourceSpan at) {
    if (c.symbol == ast::kNoSymbol) return error(at, fmt::format("'{}' is not defined", c.callee));
    const ast::Symbol& s = ast.symbol(c.symbol);
    if (s.kind == ast::SymbolKind::Sub) {
      if (!c.args.empty()) return error(at, fmt::format("sub {} takes no arguments", c.callee));
      return emit(Op::CallSubroutine, {Operand::func(function_of(c.symbol))});
    }
    if (s.kind != ast::SymbolKind::Function || s.index >= ast.functions.size())
      return error(at, fmt::format("'{}' cannot be called", c.callee));
    expand(ast.functions[s.index], c, at);
  }

  void expand(const ast::Function& f, const ast::Call& c, SourceSpan at) {
    if (std::find(expanding.begin(), expanding.end(), f.symbol) != expanding.end()) {
      std::string cycle;
      bool on = false;
      for (ast::SymbolId id : expanding) {
        on = on || id == f.symbol;
        if (on) cycle += ast.symbol(id).name + " -> ";
      }
      return error(at, fmt::format("inline function {} calls itself: {}{}", f.name, cycle, f.name));
    }
    if (c.args.size() != f.params.size())
      return error(at, fmt::format("{} takes {} arguments, {} given", f.name, f.params.size(), c.args.size()));
    // Arguments are evaluated in the caller's scope, before any binding.
    std::vector<std::pair<ast::SymbolId, Binding>> bound;
    bound.reserve(f.params.size());
    for (std::size_t i = 0; i < f.params.size(); ++i) {
      const ast::Param& p = f.params[i];
      const ast::Expr& arg = c.args[i];
      switch (p.kind) {
        case ast::ParamKind::Value: {
          VarId v = out.add_var(p.name, VarKind::Local, p.span);
          into(v, arg);
          bound.push_back({p.symbol, Binding{v, nullptr}});
          break;
        }
        case ast::ParamKind::Reference: {
          auto v = var_of(arg);
          if (!v) {
            if (auto why = unwritable_slot(arg))
              error(arg.span, fmt::format("argument for 'int &{}' of '{}': {}", p.name, f.name, *why));
            else
              error(arg.span, fmt::format("argument for 'int &{}' of '{}' must be a variable", p.name, f.name));
            return;
          }
          bound.push_back({p.symbol, Binding{*v, nullptr}});
          break;
        }
        case ast::ParamKind::Const:
          // Sema lets through an argument made of the caller's `const int &`
          // parameters, known only here (nqc: "argument must be a constant"
          // for `g(q)` when q's own argument is a variable). Said of the
          // call written, so `PlaySound(s)` names PlaySound's parameter, not
          // the asm operand the library's body passes it to.
          if (!constant(arg)) {
            const auto* n = ast::as<ast::Name>(arg);
            error(arg.span, fmt::format("argument for 'const int {}' of '{}' must be a constant expression, and {} "
                                        "is not one at this call",
                                        p.name, f.name, n ? "'" + n->name + "'" : std::string("the argument")));
            return;
          }
          bound.push_back({p.symbol, Binding{-1, &arg}});
          break;
        case ast::ParamKind::ConstReference: bound.push_back({p.symbol, Binding{-1, &arg}}); break;
      }
    }
    std::vector<std::pair<ast::SymbolId, std::optional<Binding>>> saved;
    saved.reserve(bound.size());
    for (const auto& [sym, b] : bound) {
      saved.push_back({sym, sym < env.size() ? env[sym] : std::nullopt});
      bind(sym, b);
    }
    expanding.push_back(f.symbol);
    call_sites.push_back(at);
    BlockId done = new_block();
    frames.push_back(Frame{done, {}, loops.size()});
    statement(f.body);
    escape_repeats_crossed_by_gotos(frames.back());
    frames.pop_back();
    expanding.pop_back();
    call_sites.pop_back();
    jump(done);
    enter(done);
    for (const auto& [sym, b] : saved) bind(sym, b);
  }

  // ---------------------------------------------------------- statements --

  // The counter loops of this frame around the statement being lowered.
  std::vector<int> repeats_around() const {
    std::vector<int> out;
    for (std::size_t i = frames.back().loop_base; i < loops.size(); ++i)
      if (loops[i].repeat >= 0) out.push_back(loops[i].repeat);
    return out;
  }

  // A goto leaves the counter loops around it but not around its label, and
  // enters those around the label but not around it: each would leave a
  // counter pushed or pop one never pushed. Called as the frame ends, when
  // every label of it is placed.
  void escape_repeats_crossed_by_gotos(const Frame& frame) {
    for (const auto& [label, around_goto] : frame.gotos) {
      auto it = frame.repeats_at_label.find(label);
      if (it == frame.repeats_at_label.end()) continue;
      const std::vector<int>& around_label = it->second;
      auto escape_unshared = [&](const std::vector<int>& from, const std::vector<int>& other) {
        for (int r : from)
          if (std::find(other.begin(), other.end(), r) == other.end())
            fn().repeats[static_cast<std::size_t>(r)].escapes = true;
      };
      escape_unshared(around_goto, around_label);
      escape_unshared(around_label, around_goto);
    }
  }

  void escape_repeats(std::size_t from) {
    for (std::size_t i = from; i < loops.size(); ++i)
      if (loops[i].repeat >= 0) fn().repeats[static_cast<std::size_t>(loops[i].repeat)].escapes = true;
  }

  BlockId label_block(ast::SymbolId id) {
    auto& labels = frames.back().labels;
    auto it = labels.find(id);
    if (it != labels.end()) return it->second;
    BlockId b = new_block();
    labels[id] = b;
    return b;
  }

  void statement(const ast::Stmt& s) {
    // Inside an inline expansion the code keeps the call's line, so a
    // listing shows the user's statement rather than the library's.
    if (expanding.empty()) span = s.span;
    std::visit([&](const auto& node) { lower_stmt(node, s); }, s.node);
  }

  void lower_stmt(const ast::Block& b, const ast::Stmt&) {
    for (const auto& s : b.stmts) statement(s);
  }
  void lower_stmt(const ast::DeclStmt& d, const ast::Stmt&) {
    for (const auto& v : d.vars) {
      // nqc gives an inline function's local one variable for all calls in
      // a task (or sub), so a call that reads it before writing it sees the
      // previous call's value; each task has its own, as tasks run at once.
      // A local with an initial value is written first: each expansion may
      // have its own.
      VarId id = -1;
      if (!expanding.empty() && !v.init) {
        auto [it, added] = inline_locals.try_emplace({v.symbol, fid}, -1);
        if (added) it->second = out.add_var(v.name, VarKind::Local, v.span);
        id = it->second;
      } else {
        id = out.add_var(v.name, VarKind::Local, v.span);
      }
      bind(v.symbol, Binding{id, nullptr});
      if (v.init) into(id, *v.init);
    }
  }
  void lower_stmt(const ast::ExprStmt& e, const ast::Stmt&) { effect(e.expr); }
  void lower_stmt(const ast::If& i, const ast::Stmt&) {
    BlockId t = new_block(), f = i.else_branch ? new_block() : -1, join = new_block();
    cond(i.cond, t, i.else_branch ? f : join);
    enter(t);
    statement(*i.then_branch);
    jump(join);
    if (i.else_branch) {
      enter(f);
      statement(**i.else_branch);
      jump(join);
    }
    enter(join);
  }

  // test-first loop: head tests, body, back to head (rotated later).
  void loop(const ast::Expr* c, bool negate_cond, const ast::Stmt& body, const ast::Expr* step_expr) {
    BlockId head = new_block(), start = new_block(), next = step_expr ? new_block() : head, exit = new_block();
    jump(head);
    enter(head);
    if (c == nullptr)
      jump(start);
    else if (negate_cond)
      cond(*c, exit, start);
    else
      cond(*c, start, exit);
    enter(start);
    loops.push_back({exit, next, -1});
    statement(body);
    loops.pop_back();
    jump(next);
    if (step_expr) {
      enter(next);
      effect(*step_expr);
      jump(head);
    }
    enter(exit);
  }
  void lower_stmt(const ast::While& w, const ast::Stmt&) { loop(&w.cond, false, *w.body, nullptr); }
  void lower_stmt(const ast::Until& u, const ast::Stmt&) { loop(&u.cond, true, *u.body, nullptr); }
  void lower_stmt(const ast::For& f, const ast::Stmt&) {
    if (f.init) statement(**f.init);
    loop(f.cond ? &*f.cond : nullptr, false, *f.body, f.step ? &*f.step : nullptr);
  }
  void lower_stmt(const ast::DoWhile& d, const ast::Stmt&) {
    BlockId body = new_block(), test = new_block(), exit = new_block();
    jump(body);
    enter(body);
    loops.push_back({exit, test, -1});
    statement(*d.body);
    loops.pop_back();
    jump(test);
    enter(test);
    if (d.until)
      cond(d.cond, exit, body);
    else
      cond(d.cond, body, exit);
    enter(exit);
  }
  void lower_stmt(const ast::Repeat& r, const ast::Stmt&) {
    BlockId head = new_block(), body = new_block(), exit = new_block();
    auto n = constant(r.count);
    if (n && *n <= 0) {  // runs no time: the body is unreachable
      jump(exit);
      enter(body);
      loops.push_back({exit, exit, -1});
      statement(*r.body);
      loops.pop_back();
      jump(exit);
      enter(exit);
      return;
    }
    Operand count = operand_for(Op::SetLoopCounter, 0, r.count);
    emit(Op::SetLoopCounter, {count});
    auto index = static_cast<int>(fn().repeats.size());
    fn().repeats.push_back(ir::Repeat{cur, head, false, true});
    jump(head);
    enter(head);
    terminate(LoopTest{index, body, exit});
    enter(body);
    loops.push_back({exit, head, index});
    statement(*r.body);
    loops.pop_back();
    jump(head);
    enter(exit);
  }
  void lower_stmt(const ast::Switch& s, const ast::Stmt&) {
    Operand v = test_value(s.value);
    std::vector<BlockId> cases;
    BlockId exit = new_block(), fallback = exit;
    for (const auto& c : s.cases) {
      cases.push_back(new_block());
      if (!c.value) fallback = cases.back();
    }
    for (std::size_t i = 0; i < s.cases.size(); ++i) {
      if (!s.cases[i].value) continue;
      BlockId next = new_block();
      terminate(Branch{Cmp::EQ, v, Operand::imm(*s.cases[i].value), cases[i], next});
      enter(next);
    }
    jump(fallback);
    dead_code();
    switches.push_back(cases);
    loops.push_back({exit, -1, -1});
    statement(*s.body);
    loops.pop_back();
    switches.pop_back();
    jump(exit);
    enter(exit);
  }
  void case_label(std::uint32_t index, const ast::Stmt& body, const ast::Stmt& s) {
    if (switches.empty() || index >= switches.back().size()) return error(s.span, "case label outside a switch");
    BlockId b = switches.back()[index];
    jump(b);
    enter(b);
    statement(body);
  }
  void lower_stmt(const ast::Case& c, const ast::Stmt& s) { case_label(c.index, *c.body, s); }
  void lower_stmt(const ast::Default& d, const ast::Stmt& s) { case_label(d.index, *d.body, s); }
  void lower_stmt(const ast::Break&, const ast::Stmt& s) {
    if (loops.size() <= frames.back().loop_base) return error(s.span, "break outside a loop or switch");
    escape_repeats(loops.size() - 1);
    jump(loops.back().break_to);
    dead_code();
  }
  void lower_stmt(const ast::Continue&, const ast::Stmt& s) {
    for (std::size_t i = loops.size(); i-- > frames.back().loop_base;) {
      if (loops[i].continue_to < 0) continue;
      escape_repeats(i + 1);
      jump(loops[i].continue_to);
      dead_code();
      return;
    }
    error(s.span, "continue outside a loop");
  }
  void lower_stmt(const ast::Return&, const ast::Stmt&) {
    escape_repeats(frames.back().loop_base);
    if (frames.back().return_to >= 0)
      jump(frames.back().return_to);
    else
      terminate(Exit{});
    dead_code();
  }
  void lower_stmt(const ast::Goto& g, const ast::Stmt& s) {
    if (g.symbol == ast::kNoSymbol) return error(s.span, fmt::format("label '{}' is not defined", g.label));
    frames.back().gotos.emplace_back(g.symbol, repeats_around());
    jump(label_block(g.symbol));
    dead_code();
  }
  void lower_stmt(const ast::Labeled& l, const ast::Stmt&) {
    BlockId b = label_block(l.symbol);
    frames.back().repeats_at_label[l.symbol] = repeats_around();
    jump(b);
    enter(b);
    statement(*l.body);
  }
  void task_op(Op op, ast::SymbolId id, const std::string& name, const ast::Stmt& s) {
    FuncId f = id == ast::kNoSymbol ? -1 : function_of(id);
    if (f < 0 || ast.symbol(id).kind != ast::SymbolKind::Task) return error(s.span, fmt::format("'{}' is not a task", name));
    emit(op, {Operand::func(f)});
  }
  void lower_stmt(const ast::StartTask& t, const ast::Stmt& s) { task_op(Op::StartTask, t.symbol, t.task, s); }
  void lower_stmt(const ast::StopTask& t, const ast::Stmt& s) { task_op(Op::StopTask, t.symbol, t.task, s); }
  void lower_stmt(const ast::Empty&, const ast::Stmt&) {}
  void lower_stmt(const ast::Asm& a, const ast::Stmt&) {
    std::vector<Operand> bytes;
    auto flush = [&] {
      if (bytes.empty()) return;
      fn().blocks[static_cast<std::size_t>(cur)].instrs.push_back(Instr{Op::SetVariable, bytes, true, span_id()});
      bytes.clear();
    };
    for (const auto& item : a.items) {
      if (const auto* b = std::get_if<ast::AsmByte>(&item)) {
        asm_byte(*b, bytes);
      } else {
        flush();
        asm_instr(std::get<ast::AsmInstr>(item));
      }
    }
    flush();
  }
  void asm_byte(const ast::AsmByte& b, std::vector<Operand>& bytes) {
    if (!b.source_pair) {
      auto c = constant(b.value);
      if (!c) return error(b.span, "an asm byte must be a constant");
      bytes.push_back(Operand::imm(*c & 0xff));
      return;
    }
    Operand v = value(b.value);
    if (b.restriction) return restricted_asm_byte(b, v, bytes);
    if (v.is_var()) {
      bytes.insert(bytes.end(), {Operand::imm(0), v, Operand::imm(0)});
    } else {
      bytes.insert(bytes.end(), {Operand::imm(v.source), Operand::imm(v.value & 0xff), Operand::imm((v.value >> 8) & 0xff)});
    }
  }
  // nqc's `$expr : FLAGS`, as nqc 3.1 encodes it: a source whose type the
  // low 24 bits do not allow goes through a temporary variable when they
  // allow variables (else it is an error); 0x02000000 leaves out the type
  // byte, 0x01000000 keeps only the low byte of the argument. So the
  // `$sensor : 0x03000200` of nqc's ClearSensor is the sensor's number.
  void restricted_asm_byte(const ast::AsmByte& b, Operand v, std::vector<Operand>& bytes) {
    const std::int64_t flags = *b.restriction;
    const std::int64_t allowed = flags & 0xffffff;
    const bool one_byte = (flags & 0x01000000) != 0, no_type = (flags & 0x02000000) != 0;
    int type = v.is_var() ? 0 : v.source;
    if (allowed != 0 && (type < 0 || type > 23 || ((allowed >> type) & 1) == 0)) {
      if ((allowed & 1) == 0)
        return error(b.value.span, fmt::format("this source (type {}) is not one the restriction {:#x} allows", type,
                                               static_cast<std::uint64_t>(flags)));
      VarId t = temp();
      emit(Op::SetVariable, {Operand::var(t), v});
      v = Operand::var(t);
      type = 0;
    }
    if (!no_type) bytes.push_back(Operand::imm(type));
    if (v.is_var()) {
      bytes.push_back(v);
      if (!one_byte) bytes.push_back(Operand::imm(0));
      return;
    }
    bytes.push_back(Operand::imm(v.value & 0xff));
    if (!one_byte) bytes.push_back(Operand::imm((v.value >> 8) & 0xff));
  }
  void asm_instr(const ast::AsmInstr& in) {
    if (expanding.empty()) span = in.span;
    if (!in.op) return error(in.span, fmt::format("unknown instruction '{}'", in.mnemonic));
    auto slots = operand_slots(*in.op);
    if (slots.size() != in.operands.size())
      return error(in.span, fmt::format("{} takes {} operands, {} given", in.mnemonic, slots.size(), in.operands.size()));
    Operands args;
    for (std::size_t i = 0; i < slots.size(); ++i) {
      const ast::Expr& e = in.operands[i];
      switch (slots[i]->role) {
        case rcx::Role::Variable: {
          auto v = var_of(e);
          if (!v) return error(e.span, fmt::format("operand '{}' of {} must be a variable", slots[i]->name, in.mnemonic));
          args.push_back(Operand::var(*v));
          break;
        }
        case rcx::Role::Source:
        case rcx::Role::OpSource: {
          // A message is one byte: the brick sends the low byte of a
          // variable's value, so a constant outside it is that byte, as in
          // nqc's code, not a temporary holding the whole number.
          if (auto c = constant(e); c && *in.op == Op::SendMessage && (*c < 0 || *c > 255)) {
            warning(e.span, WarningKind::Overflow, fmt::format("a message is one byte: {} is sent as {}", *c, *c & 0xff));
            args.push_back(Operand::imm(*c & 0xff));
            break;
          }
          // A power outside a byte whose low byte is no power either (-1 is
          // 255): the brick ignores the command whichever it reads (sema
          // says so), and the byte takes no temporary, as in nqc's code.
          if (auto c = constant(e); c && *in.op == Op::SetMotorPower && (*c < 0 || *c > 255) && (*c & 0xff) > 7) {
            args.push_back(Operand::imm(*c & 0xff));
            break;
          }
          Operand o = operand_for(*in.op, i, e);
          if (!accepts(*in.op, i, o))
            return error(e.span, fmt::format("operand '{}' of {} cannot take this value", slots[i]->name, in.mnemonic));
          args.push_back(o);
          break;
        }
        default: {
          auto c = constant(e);
          if (!c) return error(e.span, fmt::format("operand '{}' of {} must be a constant", slots[i]->name, in.mnemonic));
          if (!fits_field(slots[i]->type, *c) && rcx::field_size(slots[i]->type) == 1) {
            // As nqc does, a byte field keeps the low byte of the value.
            warning(e.span, WarningKind::Overflow, fmt::format("operand '{}' of {} is {}, which does not fit a byte: using {}",
                                              slots[i]->name, in.mnemonic, *c, *c & 0xff));
            c = *c & 0xff;
          }
          if (!fits_field(slots[i]->type, *c))
            return error(e.span, fmt::format("operand '{}' of {} must fit its field", slots[i]->name, in.mnemonic));
          args.push_back(Operand::imm(*c));
        }
      }
    }
    emit(*in.op, std::move(args));
  }

  // ------------------------------------------------------------ functions --

  void startup() {
    // nqc sets the globals' initial values first and then runs the startup
    // code, so a `#pragma init` function may read them (`int speed = 3;`
    // and `SetPower(OUT_A, speed)` in it). The default startup code reads
    // no variable and stays first in the task, where the passes expect
    // main's first `startup` instructions.
    bool init_call = !ast.pragmas.noinit && ast.pragmas.init;
    if (init_call) initialise_globals();
    default_startup();
    if (!init_call) initialise_globals();
  }

  void initialise_globals() {
    for (std::size_t g = 0; g < ast.globals.size(); ++g)
      if (ast.globals[g].init) into(globals[g], *ast.globals[g].init);
  }

  void default_startup() {
    const auto& pragmas = ast.pragmas;
    if (pragmas.noinit) return;
    if (pragmas.init) {
      ast::Call c{*pragmas.init, pragmas.init_span, {}, ast::kNoSymbol};
      for (ast::SymbolId i = 0; i < ast.symbols.size(); ++i)
        if (ast.symbols[i].name == *pragmas.init &&
            (ast.symbols[i].kind == ast::SymbolKind::Function || ast.symbols[i].kind == ast::SymbolKind::Sub))
          c.symbol = i;
      return call(c, pragmas.init_span);
    }
    // As nqc -Trcx: all outputs full power (7) and forward.
    emit(Op::SetMotorPower, {Operand::imm(0x07), Operand::imm(7)});
    emit(Op::SetMotorDirection, {Operand::imm(0x87)});
    fn().startup = 2;
  }

  void body(FuncId f, const ast::Stmt& stmt, bool is_main) {
    fid = f;
    entered.clear();
    span = stmt.span;
    enter(new_block());
    frames.push_back(Frame{-1, {}, loops.size()});
    if (is_main) startup();
    statement(stmt);
    escape_repeats_crossed_by_gotos(frames.back());
    frames.pop_back();
    // Lay blocks out in the order code entered them; blocks never entered
    // hold no code and go last.
    std::vector<BlockId> order;
    std::vector<bool> placed(fn().blocks.size(), false);
    for (BlockId b : entered)
      if (!placed[static_cast<std::size_t>(b)]) {
        placed[static_cast<std::size_t>(b)] = true;
        order.push_back(b);
      }
    for (std::size_t b = 0; b < placed.size(); ++b)
      if (!placed[b]) order.push_back(static_cast<BlockId>(b));
    permute_blocks(fn(), order);
  }

  // Main is task 0 (the firmware starts it) and the others follow in the
  // order they are declared, as nqc and the code generator number them.
  int nqc_task_number(ast::SymbolId task) const {
    std::uint32_t index = ast.symbol(task).index;
    if (ast.tasks[index].name == "main") return 0;
    int before = 1;
    for (std::uint32_t i = 0; i < index; ++i) before += ast.tasks[i].name != "main";
    return before;
  }

  std::optional<Program> run() {
    for (const auto& r : ast.pragmas.reserve) {
      if (r.lo < 0 || r.hi > 31 || r.lo > r.hi) {
        error(r.span, fmt::format("#pragma reserve {} {}: slots are 0..31", r.lo, r.hi));
        continue;
      }
      for (int s = r.lo; s <= r.hi; ++s) out.reserved_slots |= 1u << s;
    }
    for (const auto& g : ast.globals) globals.push_back(out.add_var(g.name, VarKind::Global, g.span));
    for (const auto& t : ast.tasks) out.functions.push_back(Function{t.name, FuncKind::Task, {}, {}, t.span, 0});
    for (const auto& s : ast.subs) out.functions.push_back(Function{s.name, FuncKind::Sub, {}, {}, s.span, 0});
    bool has_main = false;
    for (std::size_t i = 0; i < ast.tasks.size(); ++i) {
      bool is_main = ast.tasks[i].name == "main";
      has_main |= is_main;
      set_task_number(nqc_task_number(ast.tasks[i].symbol));
      body(static_cast<FuncId>(i), ast.tasks[i].body, is_main);
    }
    for (std::size_t i = 0; i < ast.subs.size(); ++i) {
      const auto& callers = ast.subs[i].calling_tasks;
      set_task_number(callers.size() == 1 ? std::optional<int>(nqc_task_number(callers[0])) : std::nullopt);
      task_id_reported = false;
      body(static_cast<FuncId>(ast.tasks.size() + i), ast.subs[i].body, false);
    }
    if (!has_main) error({}, "the program has no task main (the RCX starts task main)");
    if (diags.has_errors()) return std::nullopt;
    return std::move(out);
  }
};

}  // namespace

std::optional<Program> lower(const ast::Program& program, Diagnostics& diags) {
  Lowerer l(program, diags);
  return l.run();
}

}  // namespace rcxc::ir
