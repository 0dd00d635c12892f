#include "frontend/sema.h"

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "frontend/fold.h"
#include "frontend/other_targets.h"
#include "frontend/parse.h"
#include "frontend/ranges.h"
#include "frontend/spelling.h"
#include "frontend/token.h"

namespace rcxc::frontend {
namespace {

using namespace ast;

// Names the RCX 2 firmware's API gives and the RCX's does not (the names
// `nqc -TRCX2` declares and `nqc -TRCX` does not: events, resource control,
// the user display, serial packets, priorities, 1/100 s timers, counters,
// sound muting, Spybot and remote-control messages). Programs written for it
// fail here with "not declared"; saying why saves the reader a search, and
// keeps a suggestion ('ClearSound': "did you mean 'PlaySound'?") from
// misleading.
bool is_rcx2_api_name(const std::string& name) {
  static const std::set<std::string> names{
      "SetEvent",       "ClearEvent",         "ClearAllEvents", "EventState",     "CalibrateEvent",
      "SetUpperLimit",  "SetLowerLimit",      "SetHysteresis",  "SetClickTime",   "SetClickCounter",
      "SetUserDisplay", "SetPriority",        "SetGlobalOutput", "SetGlobalDirection", "SetMaxPower",
      "EnableOutput",   "DisableOutput",      "SendSerial",     "SetSerialComm",  "SetSerialPacket",
      "SetSerialData",  "SerialData",         "EVENT_MASK",     "DISPLAY_USER",   "ActiveEvents",
      "UpperLimit",     "LowerLimit",         "Hysteresis",     "ClickCounter",   "ClickTime",
      "__event_src",    "CurrentEvents",      "Event",          "FastTimer",      "SetTimer",
      "Counter",        "ClearCounter",       "IncCounter",     "DecCounter",     "MuteSound",
      "UnmuteSound",    "ClearSound",         "SelectProgram",  "BatteryLevel",   "FirmwareVersion",
      "SetMessage",     "SetRandomSeed",      "Indirect",       "SetIndirectVar", "InvertOutput",
      "ObvertOutput",   "GlobalOutputStatus", "DatalogType",    "DatalogValue",   "DatalogByte",
      "Set",            "SerialComm",         "SerialPacket",   "InitRCComm",     "InitSpybotComm",
      "SendRCMessage",  "SendRCMsg",          "SetRCMessage",   "SendSpybotMessage", "SendSpybotMsg",
      "SendSpybotPing", "SendSpybotPingMsg",  "SetSpybotMessage", "SetSpybotPing",
      "SendSpybotCtrlMessage", "SendSpybotCtrlMsg", "SendSpybotCtrlPingMessage",
      "SendSpybotCtrlPingMsg", "SetSpybotCtrlMessage", "SetSpybotCtrlPingMessage",
      "ID_NONE",        "ID_PC",              "ID_BOT_MIN",     "ID_BOT_MAX",     "MSG_BROADCAST",
      "MSG_DIRECT",     "MSG_LINKCAST",       "UART_BOT",       "UART_CTRL",      "UART_PING",
      "UART_RC",        "CMD_SMART_BOMB",     "CMD_FROM_RCX2"};
  static const char* const prefixes[] = {"EVENT_TYPE_", "ACQUIRE_",   "SERIAL_COMM_", "SERIAL_PACKET_",
                                         "SPY_CTRL_",   "RC_CHANNEL_", "RC_CMD_",     "ID_CTRL_",
                                         "CMD_TYPE_",   "CMD_TELL_",  "CMD_GAME_",    "CMD_REACT_TO_",
                                         "CMD_FIRE_"};
  if (names.count(name) > 0) return true;
  for (const char* prefix : prefixes)
    if (name.rfind(prefix, 0) == 0) return true;
  return false;
}

// NXC, the NXT's language, gives OnFwd and OnRev the power as a second
// argument; programs written for it are often tried on the RCX, where the
// power is an output's setting of its own.
std::string nxc_power_hint(const std::string& callee, std::size_t args) {
  if (args != 2 || (callee != "OnFwd" && callee != "OnRev")) return "";
  return " (the RCX sets the power apart: SetPower(outputs, 0 to 7); " + callee + "(outputs, power) is NXC's)";
}

std::string kind_name(SymbolKind k) {
  switch (k) {
    case SymbolKind::Global: return "global variable";
    case SymbolKind::Local: return "local variable";
    case SymbolKind::Param: return "parameter";
    case SymbolKind::Task: return "task";
    case SymbolKind::Sub: return "sub";
    case SymbolKind::Function: return "function";
    case SymbolKind::Label: return "label";
  }
  return "name";
}

bool is_variable(const Symbol& s) {
  return s.kind == SymbolKind::Global || s.kind == SymbolKind::Local || s.kind == SymbolKind::Param;
}

// A variable that may be written: not a `const` parameter.
bool is_writable(const Symbol& s) {
  if (s.kind == SymbolKind::Param)
    return s.param_kind == ParamKind::Value || s.param_kind == ParamKind::Reference;
  return s.kind == SymbolKind::Global || s.kind == SymbolKind::Local;
}

// nqc's `@N` with source type 0: variable slot N, which nqc lets a program
// assign, step and pass to an `int &` parameter. Lowering finds the
// variable in the slot (or refuses a slot that holds none).
bool is_variable_slot(const Expr& e) {
  const auto* s = as<Source>(e);
  return s && s->type->constant && *s->type->constant == static_cast<int>(rcx::Source::Variable) && s->arg->constant;
}

// How an expression's value is used, for call and condition checks.
enum class Use { Value, Discarded, Condition };

class Checker {
 public:
  Checker(Program& p, Diagnostics& d, const std::vector<std::string>& function_macro_names, bool whole)
      : prog_(p), diags_(d), function_macro_names_(function_macro_names), whole_(whole) {}

  void run() {
    declare_top_level();
    for (auto& g : prog_.globals) check_global(g);
    for (std::size_t i = 0; i < prog_.functions.size(); ++i) check_function(prog_.functions[i]);
    for (auto& t : prog_.tasks) check_body(t.symbol, t.body);
    for (auto& s : prog_.subs) check_body(s.symbol, s.body);
    check_limits();
    check_function_recursion();
    check_pragmas();
    record_calling_tasks();
    report_tasks_never_started();
  }

 private:
  Program& prog_;
  Diagnostics& diags_;
  const std::vector<std::string>& function_macro_names_;
  bool whole_;  // false after syntax errors: a task may be missing from the program
  std::unordered_map<std::string, SymbolId> globals_;
  // Global variables named like a task, sub or function declared before
  // them (`int On;`): nqc keeps variables apart from those, so the name is
  // the variable where a value is meant and the callee in a call or start.
  std::unordered_map<std::string, SymbolId> shadowing_variables_;
  std::vector<std::unordered_map<std::string, SymbolId>> scopes_;  // innermost last
  std::unordered_set<SymbolId> started_tasks_;  // named by a `start`
  SymbolId owner_ = kNoSymbol;
  // The first symbol declared in the body being checked: its locals all
  // come after, so the unused-variable report reads only those.
  SymbolId body_symbols_begin_ = 0;
  bool in_function_ = false;
  bool in_case_value_ = false;  // reading a `case` value (see TypeOf)
  bool in_const_argument_ = false;  // reading the argument of a `const int` parameter (see TypeOf)
  const Expr* written_ = nullptr;   // the expression being written, if any (see written_expr)
  // The global whose initial value is being checked (see check_global).
  std::optional<std::uint32_t> initialising_global_;
  std::unordered_map<SymbolId, std::int16_t> refused_constants_;  // see VarDecl::refused_const
  std::unordered_map<std::string, SymbolId> labels_;
  // A name not declared is said once in the program, at its first use in
  // the source; the first use in another body becomes a note of that error.
  struct ReportedUndefined {
    std::size_t diagnostic = 0;  // index in diags_
    SymbolId owner = kNoSymbol;  // the body it was found in
    bool noted = false;          // a use in another body is noted already
  };
  std::map<std::string, ReportedUndefined> reported_undefined_;
  bool in_rcx2_call_ = false;  // checking the arguments of an RCX 2 call (see undefined)
  // The `=` that is a whole condition (`if (SENSOR_1 = 1)`), and whether its
  // target was refused (see condition).
  const Assign* condition_assign_ = nullptr;
  bool condition_assign_refused_ = false;
  bool in_other_target_call_ = false;  // likewise of a Scout, CyberMaster or Spybot call
  int loop_depth_ = 0;
  int breakable_depth_ = 0;
  std::vector<Switch*> switches_;
  std::map<SymbolId, std::set<SymbolId>> function_calls_;  // function -> functions it calls
  std::map<SymbolId, std::set<SymbolId>> callees_;  // task, sub or function -> subs and functions it calls
  RangeMemo range_memo_;

  // ------------------------------------------------------------ symbols --

  SymbolId add_symbol(Symbol s) {
    if (auto why = reserved_by_nqc(s.name))
      diags_.error(s.span, "'" + s.name + "' cannot be a name: nqc reserves it (" + why + ")");
    prog_.symbols.push_back(std::move(s));
    return static_cast<SymbolId>(prog_.symbols.size() - 1);
  }

  void redefinition(const std::string& name, SourceSpan span, SymbolId previous) {
    auto& d = diags_.error(span, "redefinition of '" + name + "'");
    const Symbol& p = prog_.symbols[previous];
    d.notes.push_back({p.span, "previous definition of '" + name + "' (a " + kind_name(p.kind) + ") is here"});
  }

  SymbolId declare_global(SymbolKind kind, const std::string& name, SourceSpan span, std::uint32_t index) {
    SymbolId id = add_symbol({kind, name, span, index, kNoSymbol, ParamKind::Value, false});
    auto [it, fresh] = globals_.emplace(name, id);
    if (fresh) return id;
    bool after_a_callee = kind == SymbolKind::Global && is_callable(prog_.symbols[it->second].kind);
    if (after_a_callee && shadowing_variables_.emplace(name, id).second) return id;
    redefinition(name, span, after_a_callee ? shadowing_variables_[name] : it->second);
    return id;
  }

  // In source order, so a redefinition is reported at the later one.
  void declare_top_level() {
    auto declare = [&](auto& items, const TopLevelRef& ref) {
      auto& item = items.at(ref.index);
      item.symbol = declare_global(ref.kind, item.name, item.span, ref.index);
    };
    for (const TopLevelRef& ref : prog_.order) {
      if (ref.kind == SymbolKind::Global) declare(prog_.globals, ref);
      if (ref.kind == SymbolKind::Task) declare(prog_.tasks, ref);
      if (ref.kind == SymbolKind::Sub) declare(prog_.subs, ref);
      if (ref.kind == SymbolKind::Function) declare(prog_.functions, ref);
    }
  }

  SymbolId declare_local(SymbolKind kind, const std::string& name, SourceSpan span, std::uint32_t index,
                         ParamKind pk = ParamKind::Value) {
    SymbolId id = add_symbol({kind, name, span, index, owner_, pk, false});
    auto [it, fresh] = scopes_.back().emplace(name, id);
    if (!fresh) {
      redefinition(name, span, it->second);
      prog_.symbols[id].used = true;  // one report is enough
    }
    return id;
  }

  std::optional<SymbolId> lookup(const std::string& name) const {
    for (auto s = scopes_.rbegin(); s != scopes_.rend(); ++s)
      if (auto it = s->find(name); it != s->end()) return it->second;
    if (auto it = shadowing_variables_.find(name); it != shadowing_variables_.end()) return it->second;
    if (auto it = globals_.find(name); it != globals_.end()) return it->second;
    return std::nullopt;
  }

  // The callee of `name(...)`. A local or parameter of that name does not hide
  // a sub or function: nqc resolves calls apart from variables, and programs
  // written for it call max(...) inside a function whose parameter is max.
  std::optional<SymbolId> lookup_callee(const std::string& name) const {
    auto id = lookup(name);
    if (id && is_callable(prog_.symbols[*id].kind)) return id;
    if (auto it = globals_.find(name); it != globals_.end() && is_callable(prog_.symbols[it->second].kind))
      return it->second;
    return id;
  }

  static bool is_callable(SymbolKind kind) {
    return kind == SymbolKind::Sub || kind == SymbolKind::Function || kind == SymbolKind::Task;
  }

  // The names a misspelt one could have meant: for a call the subs and
  // functions (the API's too), otherwise the variables in scope; and the
  // macros (OUT_A, SENSOR_TOUCH, ...) either way.
  std::vector<std::string> spelling_candidates(bool callee) const {
    std::vector<std::string> names = prog_.macro_names;
    auto take = [&](const auto& table) {
      for (const auto& [n, id] : table)
        if (is_callable(prog_.symbols[id].kind) == callee) names.push_back(n);
    };
    take(globals_);
    for (const auto& scope : scopes_) take(scope);
    return names;
  }

  void undefined(const std::string& name, SourceSpan span, const std::string& what, bool callee) {
    // The arguments of a call of the RCX 2 firmware's API (SetEvent(1,
    // SENSOR_1, EVENT_TYPE_PRESSED)): the call is the one mistake.
    if (in_rcx2_call_ && is_rcx2_api_name(name)) return;
    if (in_other_target_call_ && other_target_of(name)) return;
    // One report per name keeps a misspelt name from flooding, as nqc says
    // it once; a use in a second body is noted at the error, which stands at
    // the use that comes first in the source (bodies are checked functions
    // first, then tasks, then subs).
    auto seen = reported_undefined_.find(name);
    if (seen == reported_undefined_.end()) {
      reported_undefined_[name] = {diags_.all().size(), owner_, false};
      diags_.add(undefined_diagnostic(name, span, what, callee));
      return;
    }
    if (seen->second.owner == owner_ || seen->second.noted) return;
    seen->second.noted = true;
    const std::string also = "'" + name + "' is also used here (a name not declared is reported once)";
    Diagnostic& first = diags_.at(seen->second.diagnostic);
    if (span.begin.file == first.span.begin.file && before(span.begin, first.span.begin)) {
      Diagnostic earlier = undefined_diagnostic(name, span, what, callee);
      earlier.notes.push_back({first.span, also});
      first = std::move(earlier);
      return;
    }
    first.notes.push_back({span, also});
  }

  Diagnostic undefined_diagnostic(const std::string& name, SourceSpan span, const std::string& what, bool callee) {
    auto error = [&](std::string message) { return Diagnostic{Severity::Error, span, std::move(message), {}, false, {}, {}}; };
    // The other targets' table holds only names -TRCX2 does not declare, so
    // it goes first: the RCX 2 prefixes also match a Spybot's ACQUIRE_LED.
    // The Swan firmware runs on the RCX brick itself, so "for the RCX" would
    // not say what is missing.
    if (auto target = other_target_of(name))
      return error("'" + name + "' is not declared: it is a " + std::string(*target) + (callee ? " function" : " name") +
                   (*target == "Swan firmware" ? " (nqc -TSwan); rcxc compiles for the RCX's standard firmware"
                                               : "; rcxc compiles for the RCX"));
    if (is_rcx2_api_name(name))
      return error("'" + name + "' is not declared (it belongs to the RCX 2 firmware's API; this target is the RCX)");
    // nqc: "wrong number of arguments to 'Random'".
    if (std::find(function_macro_names_.begin(), function_macro_names_.end(), name) != function_macro_names_.end())
      return error("'" + name + "' is not declared: it is a macro that takes arguments, written '" + name + "(...)'");
    // `#undef OUT_A` then `On(OUT_A)`: a near name (DISPLAY_OUT_A) is no help.
    for (const auto& [gone, where] : prog_.undefined_macros) {
      if (gone != name) continue;
      auto d = error("'" + name + "' is not declared: the macro was removed by an #undef");
      d.notes.push_back({where, "'" + name + "' is #undef'd here"});
      return d;
    }
    // `TRUE`, `False`: the constants are keywords, which no list of names holds.
    if (!callee && (spelling_distance(name, "true") == 0 || spelling_distance(name, "false") == 0)) {
      std::string lower = spelling_distance(name, "true") == 0 ? "true" : "false";
      return error("'" + name + "' is not declared; did you mean '" + lower +
                   "'? (NQC's truth values are written in lower case)");
    }
    auto candidates = spelling_candidates(callee);
    auto meant = closest_name(name, candidates);
    if (!meant) meant = name_with_prefix(name, candidates);
    if (meant) return error("'" + name + "' is not declared; did you mean '" + *meant + "'?");
    return error("'" + name + "' is not declared" + what);
  }

  // ------------------------------------------------------ declarations --

  // nqc computes the globals' initial values at the start of task main, in
  // the order they are declared, from any expression: a sensor, a timer or
  // a global declared before (`int limit = SENSOR_2 + 5;`, `int b = a * 2;`).
  void check_global(VarDecl& g) {
    if (!g.init) return;
    scopes_.clear();
    initialising_global_ = prog_.symbols[g.symbol].index;
    expr(*g.init, Use::Value);
    initialising_global_.reset();
    note_refused_constant(g);
  }

  // See VarDecl::refused_const.
  void note_refused_constant(const VarDecl& v) {
    if (v.refused_const && v.init && (*v.init).constant) refused_constants_[v.symbol] = *(*v.init).constant;
  }

  void begin_body(SymbolId owner) {
    owner_ = owner;
    body_symbols_begin_ = static_cast<SymbolId>(prog_.symbols.size());
    scopes_.assign(1, {});
    labels_.clear();
    loop_depth_ = breakable_depth_ = 0;
    switches_.clear();
  }

  void check_function(Function& f) {
    begin_body(f.symbol);
    in_function_ = true;
    for (std::uint32_t i = 0; i < f.params.size(); ++i) {
      Param& p = f.params[i];
      p.symbol = declare_local(SymbolKind::Param, p.name, p.span, i, p.kind);
    }
    collect_labels(f.body);
    block_contents(f.body);
    in_function_ = false;
    report_unused();
  }

  void check_body(SymbolId owner, Stmt& body) {
    begin_body(owner);
    collect_labels(body);
    block_contents(body);
    report_unused();
  }

  // A body's block shares the scope of the parameters (like C).
  void block_contents(Stmt& body) {
    if (auto* b = as<Block>(body)) {
      statements(b->stmts, false);
    } else {
      stmt(body);
    }
  }

  // A task no `start` names never runs (only main starts by itself): the
  // forgotten `start t;` is a classroom's commonest multitasking bug, and
  // nqc says nothing of it. Not said beside errors: a `start` the parser
  // lost, or a missing main, would make every task look forgotten.
  void report_tasks_never_started() {
    if (diags_.has_errors()) return;
    for (const auto& t : prog_.tasks) {
      const Symbol& s = prog_.symbols[t.symbol];
      if (s.name != "main" && !started_tasks_.count(t.symbol))
        diags_.warning(s.span, WarningKind::UnstartedTask,
                       "task '" + s.name + "' is never started: nothing in the program says 'start " + s.name + ";'");
    }
  }

  void report_unused() {
    for (SymbolId id = body_symbols_begin_; id < prog_.symbols.size(); ++id) {
      const Symbol& s = prog_.symbols[id];
      if (s.owner == owner_ && s.kind == SymbolKind::Local && !s.used)
        diags_.warning(s.span, WarningKind::UnusedVariable, "unused variable '" + s.name + "'");
    }
  }

  // Labels are visible in the whole body, so gotos may jump forward.
  void collect_labels(Stmt& s) {
    std::function<void(Stmt&)> walk = [&](Stmt& st) {
      std::visit(
          [&](auto& n) {
            using N = std::decay_t<decltype(n)>;
            if constexpr (std::is_same_v<N, Labeled>) {
              SymbolId id = add_symbol({SymbolKind::Label, n.label, n.label_span, 0, owner_, ParamKind::Value, false});
              auto [it, fresh] = labels_.emplace(n.label, id);
              if (!fresh) {
                auto& d = diags_.error(n.label_span, "label '" + n.label + "' is defined twice");
                d.notes.push_back({prog_.symbols[it->second].span, "the first definition is here"});
              }
              n.symbol = it->second;
              walk(*n.body);
            } else if constexpr (std::is_same_v<N, Block>) {
              for (auto& c : n.stmts) walk(c);
            } else if constexpr (std::is_same_v<N, If>) {
              walk(*n.then_branch);
              if (n.else_branch) walk(**n.else_branch);
            } else if constexpr (std::is_same_v<N, While> || std::is_same_v<N, Until> || std::is_same_v<N, DoWhile> ||
                                 std::is_same_v<N, Repeat> || std::is_same_v<N, Switch> || std::is_same_v<N, Case> ||
                                 std::is_same_v<N, Default> || std::is_same_v<N, For>) {
              walk(*n.body);
            }
          },
          st.node);
    };
    walk(s);
  }

  // --------------------------------------------------------- statements --

  static bool ends_flow(const Stmt& s) {
    return as<Break>(s) || as<Continue>(s) || as<Return>(s) || as<Goto>(s);
  }
  static bool is_jump_target(const Stmt& s) { return as<Labeled>(s) || as<Case>(s) || as<Default>(s); }

  // `own_scope`: false for a body, whose block shares the parameters'
  // scope, so `void f(int a) { int a; }` redeclares a (as in C and nqc).
  void statements(std::vector<Stmt>& list, bool own_scope = true) {
    if (own_scope) scopes_.emplace_back();
    bool dead = false;
    bool warned = false;
    for (auto& s : list) {
      if (is_jump_target(s)) dead = false;
      if (dead && !warned && !as<Empty>(s)) {
        diags_.warning(s.span, WarningKind::UnreachableCode, "unreachable code");
        warned = true;
      }
      stmt(s);
      if (ends_flow(s)) dead = true;
    }
    if (own_scope) scopes_.pop_back();
  }

  void condition(Expr& e) {
    const auto* a = as<Assign>(e);
    condition_assign_ = a && a->op == AssignOp::Assign ? a : nullptr;
    condition_assign_refused_ = false;
    expr(e, Use::Condition);
    // `if (SENSOR_1 = 1)`: the error that the sensor cannot be assigned
    // asks for '==' itself, and the warning would say it again.
    if (condition_assign_ && !condition_assign_refused_)
      diags_.warning(at_operator(*a, e.span), WarningKind::AssignInCondition, "assignment used as a condition; did you mean '=='?");
    condition_assign_ = nullptr;
  }

  void loop_body(Stmt& body) {
    ++loop_depth_;
    ++breakable_depth_;
    stmt(body);
    --loop_depth_;
    --breakable_depth_;
  }

  void stmt(Stmt& s) {
    std::visit([&](auto& n) { visit_stmt(n, s); }, s.node);
  }

  void visit_stmt(Block& b, Stmt&) { statements(b.stmts); }
  void visit_stmt(DeclStmt& d, Stmt&) {
    // The name is declared before its initial value is read, as in C and
    // nqc: in `int a = a + 1;` a is the new variable, not yet set, even
    // where an outer a exists (lowering warns of the read).
    for (auto& v : d.vars) {
      v.symbol = declare_local(SymbolKind::Local, v.name, v.span, 0);
      if (v.init) expr(*v.init, Use::Value);
      note_refused_constant(v);
    }
  }
  // Whether an error was reported inside `span` (by the preprocessor or the
  // parser, which read past it).
  bool error_within(const SourceSpan& span) const {
    return std::any_of(diags_.all().begin(), diags_.all().end(), [&](const Diagnostic& d) {
      const SourceLoc& at = d.span.begin;
      return d.severity == Severity::Error && at.file == span.begin.file && at.expansion == span.begin.expansion &&
             !before(at, span.begin) && before(at, span.end);
    });
  }
  void visit_stmt(ExprStmt& e, Stmt&) {
    std::size_t errors_before = diags_.error_count();
    expr(e.expr, Use::Discarded);
    // A statement already in error (`f;` for `f();`, or `F(1);` for a macro
    // of two arguments, which the parser read past as `0;`) needs no
    // warning besides.
    if (diags_.error_count() != errors_before || error_within(e.expr.span)) return;
    bool effect = as<Assign>(e.expr) || as<Call>(e.expr);
    if (const auto* u = as<Unary>(e.expr))
      effect = u->op == UnaryOp::PreInc || u->op == UnaryOp::PreDec || u->op == UnaryOp::PostInc ||
               u->op == UnaryOp::PostDec;
    // `x == 1;` for `x = 1;` (clang: "equality comparison result unused").
    const auto* b = as<Binary>(e.expr);
    if (!effect && b && b->op == BinaryOp::Eq && as<Name>(*b->lhs))
      diags_.warning(e.expr.span, WarningKind::UnusedValue, "expression result unused: '==' compares; did you mean '=' to assign?");
    else if (!effect)
      diags_.warning(e.expr.span, WarningKind::UnusedValue, "expression result unused");
  }
  void visit_stmt(If& n, Stmt&) {
    condition(n.cond);
    stmt(*n.then_branch);
    if (n.else_branch) stmt(**n.else_branch);
  }
  void visit_stmt(While& n, Stmt&) {
    condition(n.cond);
    loop_body(*n.body);
  }
  void visit_stmt(DoWhile& n, Stmt&) {
    loop_body(*n.body);
    condition(n.cond);
  }
  void visit_stmt(Until& n, Stmt&) {
    condition(n.cond);
    loop_body(*n.body);
  }
  void visit_stmt(For& n, Stmt&) {
    scopes_.emplace_back();  // a declaration in `for (int i = ...` belongs to the loop
    if (n.init) stmt(**n.init);
    if (n.cond) condition(*n.cond);
    if (n.step) expr(*n.step, Use::Discarded);
    loop_body(*n.body);
    scopes_.pop_back();
  }
  void visit_stmt(Repeat& n, Stmt&) {
    expr(n.count, Use::Value);
    loop_body(*n.body);
  }
  void visit_stmt(Switch& n, Stmt&) {
    expr(n.value, Use::Value);
    switches_.push_back(&n);
    ++breakable_depth_;
    stmt(*n.body);
    --breakable_depth_;
    switches_.pop_back();
  }
  void visit_stmt(Case& n, Stmt& s) {
    in_case_value_ = true;
    expr(n.value, Use::Value);
    in_case_value_ = false;
    if (switches_.empty()) {
      diags_.error(s.span, "'case' outside a switch");
    } else if (!n.value.constant) {
      diags_.error(n.value.span, "a case value must be a constant expression");
    } else {
      add_case(n.value.constant, s.span, n.index);
    }
    stmt(*n.body);
  }
  void visit_stmt(Default& n, Stmt& s) {
    if (switches_.empty())
      diags_.error(s.span, "'default' outside a switch");
    else
      add_case(std::nullopt, s.span, n.index);
    stmt(*n.body);
  }
  void add_case(std::optional<std::int16_t> value, SourceSpan span, std::uint32_t& index) {
    Switch& sw = *switches_.back();
    for (const auto& c : sw.cases) {
      if (c.value != value) continue;
      auto& d = diags_.error(span, value ? "duplicate case value " + std::to_string(*value)
                                         : std::string("more than one 'default' in a switch"));
      d.notes.push_back({c.span, "the previous one is here"});
      return;
    }
    index = static_cast<std::uint32_t>(sw.cases.size());
    sw.cases.push_back({value, span});
  }
  void visit_stmt(Break&, Stmt& s) {
    if (breakable_depth_ == 0) diags_.error(s.span, "'break' outside a loop or switch");
  }
  void visit_stmt(Continue&, Stmt& s) {
    if (loop_depth_ == 0) diags_.error(s.span, "'continue' outside a loop");
  }
  void visit_stmt(Return&, Stmt&) {}
  void visit_stmt(Goto& n, Stmt& s) {
    auto it = labels_.find(n.label);
    if (it == labels_.end()) {
      diags_.error(s.span, "label '" + n.label + "' is not defined in this " +
                               kind_name(prog_.symbols[owner_].kind));
      return;
    }
    n.symbol = it->second;
    prog_.symbols[n.symbol].used = true;
  }
  void visit_stmt(Labeled& n, Stmt&) { stmt(*n.body); }
  void task_ref(const std::string& name, SymbolId& symbol, const Stmt& s, const char* verb) {
    auto id = lookup_callee(name);
    if (!id) {
      diags_.error(s.span, "cannot " + std::string(verb) + " '" + name + "': there is no task of that name");
      return;
    }
    if (prog_.symbols[*id].kind != SymbolKind::Task) {
      diags_.error(s.span, "cannot " + std::string(verb) + " '" + name + "': it is a " +
                               kind_name(prog_.symbols[*id].kind) + ", not a task");
      return;
    }
    symbol = *id;
    prog_.symbols[*id].used = true;
  }
  void visit_stmt(StartTask& n, Stmt& s) {
    task_ref(n.task, n.symbol, s, "start");
    if (n.symbol != kNoSymbol) started_tasks_.insert(n.symbol);
  }
  void visit_stmt(StopTask& n, Stmt& s) { task_ref(n.task, n.symbol, s, "stop"); }
  void visit_stmt(Asm& n, Stmt&) {
    for (auto& item : n.items) std::visit([&](auto& i) { asm_item(i); }, item);
  }
  void visit_stmt(Empty&, Stmt&) {}

  // --------------------------------------------------------------- asm --

  // Inside an inline function a `const` parameter is known only at each
  // call; such operands are checked when lowering substitutes them.
  bool depends_on_const_param(const Expr& e) const {
    if (const auto* n = as<Name>(e)) {
      if (n->symbol == kNoSymbol) return false;
      const Symbol& s = prog_.symbols[n->symbol];
      return s.kind == SymbolKind::Param &&
             (s.param_kind == ParamKind::Const || s.param_kind == ParamKind::ConstReference);
    }
    bool any = false;
    visit_children(e, [&](const Expr& c) { any = any || depends_on_const_param(c); });
    return any;
  }

  // Known only when lowering generates the code: a `const` parameter's
  // argument, or __taskid (the task the code ends up in). Operands that
  // must be constant are checked then.
  bool known_when_lowered(const Expr& e) const {
    if (as<TaskId>(e)) return true;
    if (depends_on_const_param(e)) return true;
    bool any = false;
    visit_children(e, [&](const Expr& c) { any = any || known_when_lowered(c); });
    return any;
  }

  // The first assignment (`x = 5`, `x += 2`) in `e` outside an inner
  // __type (which says so itself), or nullptr.
  static const Expr* assignment_in(const Expr& e) {
    if (as<Assign>(e)) return &e;
    if (as<TypeOf>(e)) return nullptr;
    const Expr* found = nullptr;
    visit_children(e, [&](const Expr& c) { found = found ? found : assignment_in(c); });
    return found;
  }

  template <class F>
  static void visit_children(const Expr& e, F&& f) {
    std::visit(
        [&](const auto& n) {
          using N = std::decay_t<decltype(n)>;
          if constexpr (std::is_same_v<N, Unary>) f(*n.operand);
          if constexpr (std::is_same_v<N, Binary>) {
            f(*n.lhs);
            f(*n.rhs);
          }
          if constexpr (std::is_same_v<N, Assign>) {
            f(*n.target);
            f(*n.value);
          }
          if constexpr (std::is_same_v<N, Conditional>) {
            f(*n.cond);
            f(*n.then_value);
            f(*n.else_value);
          }
          if constexpr (std::is_same_v<N, Call>)
            for (const auto& a : n.args) f(a);
          if constexpr (std::is_same_v<N, Source>) {
            f(*n.type);
            f(*n.arg);
          }
          if constexpr (std::is_same_v<N, SourceArg>) f(*n.operand);
          if constexpr (std::is_same_v<N, TypeOf>) f(*n.operand);
        },
        e.node);
  }

  void asm_item(AsmByte& b) {
    expr(b.value, Use::Value);
    if (b.source_pair) return;
    if (!b.value.constant) {
      if (!known_when_lowered(b.value))
        diags_.error(b.value.span, "an asm byte must be a constant (write $name for a variable)");
      return;
    }
    // nqc keeps the low byte without a word; the byte written is likely not
    // the one meant, so it is a warning, as for other byte operands.
    int v = *b.value.constant;
    if (v < -128 || v > 255)
      diags_.warning(b.value.span, WarningKind::Overflow, "asm byte value " + std::to_string(v) + " does not fit in a byte; its low byte " +
                                       std::to_string(v & 0xff) + " is used, as nqc does");
  }

  void asm_item(AsmInstr& in) {
    for (auto& o : in.operands) expr(o, Use::Value);
    const rcx::OpcodeInfo* info = rcx::by_mnemonic(in.mnemonic);
    if (!info) {
      diags_.error(in.mnemonic_span, "unknown asm mnemonic '" + in.mnemonic + "'");
      return;
    }
    if (!info->is_command()) {
      diags_.error(in.mnemonic_span, "'" + in.mnemonic + "' (" + std::string(info->name) +
                                         ") is a host request, not a program instruction");
      return;
    }
    // The operands as written: Argument fields ride with their Source.
    std::vector<const rcx::Operand*> written;
    for (const auto& o : info->operands) {
      if (o.role == rcx::Role::Argument) continue;
      if (o.role == rcx::Role::Offset || o.role == rcx::Role::Extension || o.role == rcx::Role::Length ||
          o.role == rcx::Role::Data || o.role == rcx::Role::Checksum || o.role == rcx::Role::OpSource ||
          o.count != 1) {
        diags_.error(in.mnemonic_span, "'" + in.mnemonic + "' cannot be written in asm; use C control flow instead");
        return;
      }
      written.push_back(&o);
    }
    if (in.operands.size() != written.size()) {
      diags_.error(in.span, "'" + in.mnemonic + "' takes " + std::to_string(written.size()) + " operand" +
                                (written.size() == 1 ? "" : "s") + ", but " + std::to_string(in.operands.size()) +
                                (in.operands.size() == 1 ? " was" : " were") + " given");
      return;
    }
    in.op = info->op;
    for (std::size_t i = 0; i < written.size(); ++i) asm_operand(in, *written[i], in.operands[i]);
  }

  void asm_operand(const AsmInstr& in, const rcx::Operand& o, const Expr& e) {
    std::string what = "operand '" + std::string(o.name) + "' of '" + in.mnemonic + "'";
    if (o.role == rcx::Role::Source) {  // any value; lowering maps it
      check_range(in, o, e);
      return;
    }
    if (o.role == rcx::Role::Variable) {
      const auto* n = as<Name>(e);
      if (is_variable_slot(e)) return;
      if (!n || n->symbol == kNoSymbol || !is_writable(prog_.symbols[n->symbol]))
        diags_.error(e.span, what + " must be a variable");
      return;
    }
    if (!e.constant) {
      if (!known_when_lowered(e)) diags_.error(e.span, what + " must be a constant");
      return;
    }
    int v = *e.constant;
    bool byte = rcx::field_size(o.type) == 1;
    bool fits = byte ? (v >= -128 && v <= 255) : true;
    if (!fits) {
      diags_.error(e.span, what + " is " + std::to_string(v) + ", which does not fit in a byte");
      return;
    }
    check_range(in, o, e);
  }

  void check_range(const AsmInstr& in, const rcx::Operand& o, const Expr& e) {
    auto range = operand_range(in.mnemonic, o.name);
    if (!range || !e.constant) return;
    int v = *e.constant;
    if (v < range->lo || v > range->hi)
      diags_.warning(e.span, WarningKind::Range,
                     describe_operand(in.mnemonic, o.name, *range) + " is " + std::to_string(v) + outside_range(*range));
  }

  // -------------------------------------------------------- expressions --

  void expr(Expr& e, Use use) {
    std::visit([&](auto& n) { visit_expr(n, e, use); }, e.node);
  }

  // An expression the statement writes (an assignment's target, `++x`'s
  // operand, an `int &` argument): `@32 = 1` is then one error, that slot
  // 32 cannot be written, not a range warning beside it.
  void written_expr(Expr& e) {
    const Expr* outer = written_;
    written_ = &e;
    expr(e, Use::Value);
    written_ = outer;
  }

  void visit_expr(IntLit& n, Expr& e, Use) {
    if (n.value > 0xFFFF || n.value < -0x8000) {
      std::string number = n.value >= kLiteralPastRange ? "" : std::to_string(n.value) + " ";
      diags_.warning(e.span, WarningKind::Overflow, "integer constant " + number + "does not fit in 16 bits; it becomes " +
                                 std::to_string(wrap16(n.value)));
    }
    e.constant = wrap16(n.value);
  }

  void visit_expr(Name& n, Expr& e, Use) {
    auto id = lookup(n.name);
    if (!id) {
      undefined(n.name, e.span, "", false);
      return;
    }
    const Symbol& s = prog_.symbols[*id];
    if (!is_variable(s)) {
      // `f;` or `x = f;`: a call without its parentheses, or a task used as one.
      std::string how;
      if (s.kind == SymbolKind::Function || s.kind == SymbolKind::Sub) how = " (a call is written '" + n.name + "()')";
      if (s.kind == SymbolKind::Task) how = " (a task is run with 'start " + n.name + ";')";
      diags_.error(e.span, "'" + n.name + "' is a " + kind_name(s.kind) + ", not a variable" + how);
      return;
    }
    if (initialising_global_ && s.kind == SymbolKind::Global && s.index > *initialising_global_) {
      // Its own initial value is set after this one (nqc: undefined variable).
      diags_.error(e.span, "'" + n.name + "' is declared after this global, so its initial value is not set yet: "
                                          "initial values are set in the order the globals are declared");
      return;
    }
    n.symbol = *id;
    prog_.symbols[*id].used = true;
    if (auto k = refused_constants_.find(*id); k != refused_constants_.end()) e.constant = k->second;
  }

  void visit_expr(Unary& n, Expr& e, Use) {
    bool steps = n.op == UnaryOp::PreInc || n.op == UnaryOp::PreDec || n.op == UnaryOp::PostInc ||
                 n.op == UnaryOp::PostDec;
    if (steps)
      written_expr(*n.operand);
    else
      expr(*n.operand, Use::Value);
    if (steps) {
      require_writable(*n.operand, n.op == UnaryOp::PreInc || n.op == UnaryOp::PostInc ? "increment" : "decrement",
                       n.operand->span);
      return;
    }
    if (n.operand->constant) e.constant = fold_unary(n.op, *n.operand->constant);
  }

  void visit_expr(Binary& n, Expr& e, Use) {
    expr(*n.lhs, Use::Value);
    expr(*n.rhs, Use::Value);
    const auto& a = n.lhs->constant;
    const auto& b = n.rhs->constant;
    bool divides = n.op == BinaryOp::Div || n.op == BinaryOp::Mod;
    if (a && b) {
      e.constant = fold_binary(n.op, *a, *b);
      if (!e.constant) diags_.error(n.rhs->span, "division by zero in a constant expression");
      if (e.constant) warn_wrapped_operand(n, *e.constant);
      if (e.constant) warn_folded_shift(n, *e.constant);
      return;
    }
    if (a && n.op == BinaryOp::LogAnd && *a == 0) e.constant = 0;
    if (a && n.op == BinaryOp::LogOr && *a != 0) e.constant = 1;
    if (divides && b && *b == 0)
      diags_.warning(n.rhs->span, WarningKind::DivisionByZero, "division by zero (at run time the firmware leaves the value unchanged)");
  }

  // `Wait(65535 + 2)` passes 1, as `Wait(65537)` does, whose literal warns:
  // so does the expression (nqc refuses both for Wait, and wraps both for
  // PlayTone). Only where nothing inside has said so already.
  void warn_wide_argument(const Expr& arg) {
    if (!arg.constant || as<IntLit>(arg)) return;
    auto exact = exact_constant(arg);
    if (!exact || (*exact >= -0x8000 && *exact <= 0xFFFF)) return;
    diags_.warning(arg.span, WarningKind::Overflow,
                   fmt::format("the argument's value {} does not fit in 16 bits; it becomes {}", *exact,
                               *arg.constant));
  }

  // `Wait(60 * 1000 / 10)`: 60000 wraps to -5536 in 16 bits, as the brick
  // would compute it, so the wait is -553, where nqc (32-bit constants) and
  // a C reader expect 6000. + - and * wrap to the same low 16 bits either
  // way; a division, a remainder or a comparison of a wrapped operand does
  // not, so it is said where the operand leaves the 16 bits.
  void warn_wrapped_operand(const Binary& n, std::int16_t folded) {
    bool divides = n.op == BinaryOp::Div || n.op == BinaryOp::Mod;
    bool compares = n.op == BinaryOp::Lt || n.op == BinaryOp::Le || n.op == BinaryOp::Gt || n.op == BinaryOp::Ge ||
                    n.op == BinaryOp::Eq || n.op == BinaryOp::Ne;
    if (!divides && !compares) return;
    auto x = exact_constant(*n.lhs);
    auto y = exact_constant(*n.rhs);
    if (!x || !y) return;
    auto fits = [](std::int64_t v) { return v >= -32768 && v <= 32767; };
    const Expr* wrapped = !fits(*x) ? n.lhs.get() : !fits(*y) ? n.rhs.get() : nullptr;
    // A literal past 65535 has its own warning already; one of 32768 to
    // 65535 has none (`0xFFFF` is a common way to write -1), and `40000 >
    // 30000` is 0 here where nqc gives 1 (faithfulness round 16's in12).
    if (!wrapped) return;
    if (const auto* lit = as<IntLit>(*wrapped); lit && (lit->value > 0xFFFF || lit->value < -0x8000)) return;
    std::int64_t wide = 0;
    switch (n.op) {
      case BinaryOp::Div:
      case BinaryOp::Mod: {
        auto q = exact_divide(n.op, *x, *y);
        if (!q) return;
        wide = *q;
        break;
      }
      case BinaryOp::Lt: wide = *x < *y; break;
      case BinaryOp::Le: wide = *x <= *y; break;
      case BinaryOp::Gt: wide = *x > *y; break;
      case BinaryOp::Ge: wide = *x >= *y; break;
      case BinaryOp::Eq: wide = *x == *y; break;
      default: wide = *x != *y; break;
    }
    if (wrap16(wide) == folded) return;
    std::int64_t exact = wrapped == n.lhs.get() ? *x : *y;
    const char* what = n.op == BinaryOp::Div ? "division" : n.op == BinaryOp::Mod ? "remainder" : "comparison";
    diags_.warning(wrapped->span, WarningKind::Overflow, fmt::format("{} does not fit in 16 bits: it wraps to {}, so the {} gives {} (nqc, "
                                              "which computes constants in 32 bits, gives {})",
                                              exact, wrap16(exact), what, folded, wide));
  }

  // `-8 >> 1` folds to 32764, as the brick shifts zeros in and as nqc's own
  // code for `x >> 1` does; nqc folds constants as 32-bit signed numbers and
  // gives -4 (docs/compiler.md). Said where the two differ, as a wrapped
  // operand of a division is (faithfulness round 16's in11).
  void warn_folded_shift(const Binary& n, std::int16_t folded) {
    if (n.op != BinaryOp::Shr) return;
    auto x = exact_constant(*n.lhs);
    auto y = exact_constant(*n.rhs);
    if (!x || !y || *y < 0 || *y > 31 || *x < -(std::int64_t{1} << 31) || *x >= (std::int64_t{1} << 31)) return;
    std::int64_t wide = static_cast<std::int64_t>(static_cast<std::int32_t>(*x) >> *y);
    if (wrap16(wide) == folded) return;
    diags_.warning(n.lhs->span, WarningKind::Overflow,
                   fmt::format("{} >> {} gives {}: the brick shifts zeros in, as nqc's code for a variable does (nqc, "
                               "which computes constants in 32 bits, gives {})",
                               *x, *y, folded, wrap16(wide)));
  }

  void visit_expr(Assign& n, Expr&, Use) {
    // The value is checked first, but an undeclared target is the name's
    // first use in reading order (`a = a + 1`): said there.
    if (const auto* t = as<Name>(*n.target); t && !lookup(t->name)) undefined(t->name, n.target->span, "", false);
    expr(*n.value, Use::Value);
    written_expr(*n.target);
    bool whole_condition = &n == condition_assign_;
    if (!require_writable(*n.target, "assign to", at_operator(n, n.target->span),
                          whole_condition ? "; did you mean '=='?" : "") &&
        whole_condition)
      condition_assign_refused_ = true;
    if ((n.op == AssignOp::Div || n.op == AssignOp::Mod) && n.value->constant && *n.value->constant == 0)
      diags_.warning(n.value->span, WarningKind::DivisionByZero, "division by zero (at run time the firmware leaves the value unchanged)");
  }

  // `preferred` unless it begins inside a macro's body (SENSOR_1 = 1: the
  // user's text would only be a note), then the operator, when that is
  // the user's own text.
  static SourceSpan at_operator(const Assign& a, const SourceSpan& preferred) {
    bool in_macro = preferred.begin.expansion != 0;
    return in_macro && a.op_span.begin.valid() && a.op_span.begin.expansion == 0 ? a.op_span : preferred;
  }

  // `where`: where to show that the target is no variable; `hint` ends the
  // message. False when the target was refused here.
  bool require_writable(const Expr& target, const std::string& verb, const SourceSpan& where,
                        const std::string& hint = "") {
    if (is_variable_slot(target)) return true;
    const auto* n = as<Name>(target);
    if (!n) {
      diags_.error(where, "cannot " + verb + " this expression: it is not a variable" + source_noun(target) + hint);
      return false;
    }
    if (n->symbol == kNoSymbol) return true;  // already reported
    const Symbol& s = prog_.symbols[n->symbol];
    if (is_writable(s)) return true;
    diags_.error(target.span, "cannot " + verb + " '" + s.name + "': it is a constant parameter" + hint);
    return false;
  }

  // What a source other than a variable reads, said after "it is not a
  // variable": Timer(0) = 3 is a timer's value, which no instruction sets.
  static std::string source_noun(const Expr& e) {
    const auto* s = as<Source>(e);
    if (!s || !s->type->constant) return "";
    std::string what;
    switch (static_cast<rcx::Source>(*s->type->constant)) {
      case rcx::Source::Random: what = "a random number"; break;
      case rcx::Source::Program: what = "the program number"; break;
      case rcx::Source::Clock: what = "the clock"; break;
      case rcx::Source::Message: what = "the message buffer"; break;
      default: {
        auto range = rcx::source_argument_range(*s->type->constant);
        if (!range || range->noun.empty()) return "";
        what = std::string(range->noun == "output" ? "an " : "a ") + std::string(range->noun);
      }
    }
    return " but the value of " + what + ", which a program can read and not assign";
  }

  void visit_expr(Conditional& n, Expr& e, Use) {
    expr(*n.cond, Use::Value);
    expr(*n.then_value, Use::Value);
    expr(*n.else_value, Use::Value);
    if (n.cond->constant) {
      const auto& chosen = *n.cond->constant ? n.then_value->constant : n.else_value->constant;
      e.constant = chosen;
    }
  }

  void visit_expr(Call& n, Expr& e, Use use) {
    std::size_t errors_before = diags_.error_count();
    auto id = lookup_callee(n.callee);
    const Function* callee = id && prog_.symbols[*id].kind == SymbolKind::Function
                                 ? &prog_.functions[prog_.symbols[*id].index]
                                 : nullptr;
    bool outer_rcx2_call = in_rcx2_call_;
    bool outer_other_target_call = in_other_target_call_;
    in_rcx2_call_ = in_rcx2_call_ || (!id && is_rcx2_api_name(n.callee));
    in_other_target_call_ = in_other_target_call_ || (!id && other_target_of(n.callee));
    for (std::size_t i = 0; i < n.args.size(); ++i) {
      in_const_argument_ = callee && i < callee->params.size() && callee->params[i].kind == ParamKind::Const;
      std::size_t said_before = diags_.all().size();
      if (callee && i < callee->params.size() && callee->params[i].kind == ParamKind::Reference)
        written_expr(n.args[i]);
      else
        expr(n.args[i], Use::Value);
      in_const_argument_ = false;
      if (diags_.all().size() == said_before) warn_wide_argument(n.args[i]);
    }
    in_rcx2_call_ = outer_rcx2_call;
    in_other_target_call_ = outer_other_target_call;
    bool args_ok = diags_.error_count() == errors_before;
    if (!id) {
      undefined(n.callee, n.callee_span, " (no sub or function of that name)", true);
      return;
    }
    const Symbol& s = prog_.symbols[*id];
    if (s.kind == SymbolKind::Task) {
      diags_.error(e.span, "'" + n.callee + "' is a task: use 'start " + n.callee + ";' to run it");
      return;
    }
    if (s.kind != SymbolKind::Sub && s.kind != SymbolKind::Function) {
      diags_.error(n.callee_span, "'" + n.callee + "' is a " + kind_name(s.kind) + ", not a sub or function");
      return;
    }
    n.symbol = *id;
    prog_.symbols[*id].used = true;
    if (owner_ != kNoSymbol) callees_[owner_].insert(*id);
    if (use != Use::Discarded)
      diags_.error(e.span, "'" + n.callee + "' does not return a value; call it as a statement");
    if (s.kind == SymbolKind::Sub) {
      if (!n.args.empty()) diags_.error(e.span, "sub '" + n.callee + "' takes no arguments");
      return;
    }
    const Function& f = prog_.functions[s.index];
    if (in_function_) function_calls_[owner_].insert(*id);
    if (n.args.size() != f.params.size()) {
      auto& d = diags_.error(e.span, "function '" + n.callee + "' takes " + std::to_string(f.params.size()) +
                                         " argument" + (f.params.size() == 1 ? "" : "s") + ", but " +
                                         std::to_string(n.args.size()) + (n.args.size() == 1 ? " was" : " were") +
                                         " given" + nxc_power_hint(n.callee, n.args.size()));
      d.notes.push_back({f.span, "'" + n.callee + "' is defined here"});
      return;
    }
    if (!args_ok) return;  // an argument that failed already has its error
    for (std::size_t i = 0; i < f.params.size(); ++i) check_argument(f, f.params[i], n.args[i]);
    // From tasks and subs only: by then every function body is resolved.
    if (!in_function_) check_call_ranges(prog_, f, n.args, e.span, diags_, range_memo_);
  }

  // The source type a `const int &` parameter must carry because the body
  // takes __source_arg(param, TYPE) of it, directly or by passing it on to
  // another function's such parameter. Lets `SetSensor(Timer(1), ...)` be
  // reported at the call. nullopt when there is no such requirement.
  std::optional<std::int16_t> required_source_type(const Function& f, SymbolId param, int depth = 0) {
    if (depth > 32) return std::nullopt;
    std::optional<std::int16_t> found;
    std::function<void(const Expr&)> scan_expr = [&](const Expr& e) {
      if (found) return;
      if (const auto* sa = as<SourceArg>(e); sa && !sa->or_constant_byte) {
        const auto* n = as<Name>(*sa->operand);
        if (n && n->symbol == param && sa->type_required) found = sa->type_required;
      }
      if (const auto* c = as<Call>(e); c && c->symbol != kNoSymbol &&
                                        prog_.symbols[c->symbol].kind == SymbolKind::Function) {
        const Function& g = prog_.functions[prog_.symbols[c->symbol].index];
        for (std::size_t i = 0; i < c->args.size() && i < g.params.size() && !found; ++i) {
          const auto* n = as<Name>(c->args[i]);
          if (n && n->symbol == param && &g != &f)
            found = g.params[i].sensor ? std::optional<std::int16_t>(static_cast<std::int16_t>(rcx::Source::SensorValue))
                                       : required_source_type(g, g.params[i].symbol, depth + 1);
        }
      }
      visit_children(e, scan_expr);
    };
    std::function<void(const Stmt&)> scan = [&](const Stmt& st) {
      std::visit(
          [&](const auto& n) {
            using N = std::decay_t<decltype(n)>;
            if constexpr (std::is_same_v<N, Block>) {
              for (const auto& c : n.stmts) scan(c);
            } else if constexpr (std::is_same_v<N, ExprStmt>) {
              scan_expr(n.expr);
            } else if constexpr (std::is_same_v<N, Asm>) {
              for (const auto& item : n.items) {
                if (const auto* in = std::get_if<AsmInstr>(&item))
                  for (const auto& o : in->operands) scan_expr(o);
              }
            } else if constexpr (std::is_same_v<N, If>) {
              scan(*n.then_branch);
              if (n.else_branch) scan(**n.else_branch);
            }
          },
          st.node);
    };
    scan(f.body);
    return found;
  }

  void check_argument(const Function& f, const Param& p, const Expr& arg) {
    // Only a name (a parameter standing for its argument) or a source can
    // turn out to be a source at a call: `__sensor(n)` or `n + 1` never is.
    bool may_become_source = as<Name>(arg) || as<Source>(arg);
    if (p.kind == ParamKind::ConstReference && (!depends_on_const_param(arg) || !may_become_source)) {
      if (auto type = p.sensor ? std::optional<std::int16_t>(static_cast<std::int16_t>(rcx::Source::SensorValue))
                               : required_source_type(f, p.symbol)) {
        const auto* src = as<Source>(arg);
        if (!src || src->type_value != *type) {
          std::string what = *type == static_cast<int>(rcx::Source::SensorValue)
                                 ? std::string("a sensor (SENSOR_1, SENSOR_2 or SENSOR_3)")
                                 : "a " + std::string(rcx::source_name(*type)) + " source";
          auto& d = diags_.error(arg.span, "argument for '" + p.name + "' of '" + f.name + "' must be " + what);
          d.notes.push_back({p.span, "parameter declared here"});
        }
      }
    }
    if (p.kind == ParamKind::Reference) {
      const auto* n = as<Name>(arg);
      // A `const int &` parameter passed on stands for its caller's
      // argument, which lowering checks at each call (nqc takes `f(b)` for
      // `g(x)` and refuses it for `g(3)`).
      if (n && n->symbol != kNoSymbol && prog_.symbols[n->symbol].kind == SymbolKind::Param &&
          prog_.symbols[n->symbol].param_kind == ParamKind::ConstReference)
        return;
      if (is_variable_slot(arg)) return;
      if (!n || (n->symbol != kNoSymbol && !is_writable(prog_.symbols[n->symbol]))) {
        // `f(Timer(0))`: which value of the brick it is, as `Timer(0) = 3`
        // says (faithfulness round 16's rf12; nqc: "argument must be a
        // variable").
        std::string noun = source_noun(arg);
        if (!noun.empty()) noun = "; this is" + noun.substr(std::string_view(" but").size());
        auto& d = diags_.error(arg.span, "argument for 'int &" + p.name + "' of '" + f.name + "' must be a variable" +
                                             noun);
        d.notes.push_back({p.span, "parameter declared here"});
      }
    } else if (p.kind == ParamKind::Const) {
      if (!arg.constant && !depends_on_const_param(arg)) {
        auto& d = diags_.error(arg.span, "argument for 'const int " + p.name + "' of '" + f.name +
                                             "' must be a constant expression");
        d.notes.push_back({p.span, "parameter declared here"});
      }
    }
  }

  // The RCX takes a source's argument from the instruction itself: say so
  // in the words of the call written (Random(n), Timer(i)).
  static std::string non_constant_source_message(const Source& n) {
    std::string why = " must be a constant expression: the RCX takes it from the instruction, so a variable cannot ";
    if (n.type->constant && !n.arg->constant) {
      int type = *n.type->constant;
      if (type == static_cast<int>(rcx::Source::Random)) return "the maximum of Random(n)" + why + "set it";
      if (auto range = rcx::source_argument_range(type); range && !range->noun.empty())
        return fmt::format("the {} number{}choose the {}", range->noun, why, range->noun);
    }
    return "both operands of __source(TYPE, ARG) must be constant expressions";
  }

  void visit_expr(Source& n, Expr& e, Use) {
    std::size_t errors_before = diags_.error_count();
    expr(*n.type, Use::Value);
    expr(*n.arg, Use::Value);
    if (!n.type->constant || !n.arg->constant) {
      // An operand already said what is wrong with it (SensorValueRaw(x):
      // "argument must be a sensor"); a second message would only repeat it.
      if (!known_when_lowered(e) && diags_.error_count() == errors_before)
        diags_.error(e.span, non_constant_source_message(n));
      return;
    }
    int type = *n.type->constant;
    if (type < 0 || type > 15) {
      diags_.error(n.type->span, "source type " + std::to_string(type) + " does not exist (types are 0 to 15)");
      return;
    }
    // nqc emits the CyberMaster sources for -Trcx too, so a program using them
    // compiles; the RCX has nothing behind them (docs/emulator.md, "Sources").
    if (type >= 5 && type <= 7)
      diags_.warning(n.type->span, WarningKind::Source, "source type " + std::to_string(type) +
                                       " is a CyberMaster source; on the RCX it reads 0");
    n.type_value = static_cast<std::int16_t>(type);
    n.arg_value = *n.arg->constant;
    // SensorValueRaw(3) for the third sensor (whose number is 2) or Timer(4)
    // for the fourth timer read what the brick has there, which is not that.
    // `SensorValue(3)` is __source(9, __sensor(3)): the number written is
    // where the user's text is, the __sensor in the library's macro.
    const Expr* arg = n.arg.get();
    if (const auto* sa = as<SourceArg>(*arg); sa && sa->or_constant_byte) arg = sa->operand.get();
    if (auto range = rcx::source_argument_range(type); range && (n.arg_value < range->lo || n.arg_value > range->hi)) {
      if (&e == written_ && type == static_cast<int>(rcx::Source::Variable))
        diags_.error(e.span, fmt::format("variable slot {} does not exist: the RCX has slots {} to {}", n.arg_value,
                                         range->lo, range->hi));
      else if (range->lo == range->hi)
        diags_.warning(arg->span, WarningKind::Source, fmt::format("the {} source takes argument {}, not {}", rcx::source_name(type),
                                              range->lo, n.arg_value));
      else
        diags_.warning(arg->span, WarningKind::Range, fmt::format("{} {} does not exist: the RCX has {}s {} to {}{}", range->noun,
                                              n.arg_value, range->noun, range->lo, range->hi,
                                              range->noun == "sensor" ? " (SENSOR_1 to SENSOR_3)" : ""));
    }
    if (type == static_cast<int>(rcx::Source::Immediate)) e.constant = n.arg_value;
  }

  void visit_expr(SourceArg& n, Expr& e, Use) {
    expr(*n.operand, Use::Value);
    if (n.or_constant_byte && n.operand->constant) {
      e.constant = static_cast<std::int16_t>(*n.operand->constant & 0xff);
      return;
    }
    if (known_when_lowered(*n.operand)) return;  // known at each call
    const auto* src = as<Source>(*n.operand);
    if (!src) {
      diags_.error(n.operand->span, n.type_required == static_cast<int>(rcx::Source::SensorValue)
                                        ? std::string("argument must be a sensor (SENSOR_1, SENSOR_2 or SENSOR_3)")
                                        : std::string("__source_arg needs a source expression such as Timer(0)"));
      return;
    }
    if (n.type_required && src->type_value != *n.type_required) {
      diags_.error(n.operand->span, "argument must be a " + std::string(rcx::source_name(*n.type_required)) +
                                        " source, not a " + std::string(rcx::source_name(src->type_value)));
      return;
    }
    e.constant = src->arg_value;
  }

  // Lowering gives it the task's number; in a `case` or as a `const int`
  // argument it is refused, as nqc refuses it, since it is not constant
  // where the program is read.
  void visit_expr(TaskId&, Expr&, Use) {}

  // __type(E) does not compute E: only whether nqc would count it as a
  // constant matters. Through a `const` parameter that is known at each call,
  // except in a case value, which nqc reads with the function, before any
  // call: there a parameter is a variable and __taskid not yet a constant
  // (`case __type(n):` is `case 0:` whatever the argument). nqc works out a
  // `const int` argument when it reads the call, before it knows the task,
  // so there too __taskid is not a constant (`k(__type(__taskid))` passes 0).
  void visit_expr(TypeOf& n, Expr& e, Use) {
    expr(*n.operand, Use::Value);
    // nqc has no assignment expressions, so it refuses one here ("syntax
    // error"); rcxc has them, and here one would silently never happen.
    // (`x++` nqc takes, and computes no more than rcxc does.)
    if (const Expr* a = assignment_in(*n.operand))
      diags_.error(a->span, "an assignment inside __type is never made: __type does not compute its operand");
    if (!in_case_value_ && depends_on_const_param(*n.operand)) return;
    bool constant = nqc_constant(*n.operand, [](const Name&) -> const Expr* { return nullptr; }, std::nullopt,
                                 !in_case_value_ && !in_const_argument_)
                        .constant;
    e.constant = static_cast<std::int16_t>(constant ? 2 : 0);
  }

  // ------------------------------------------------------------ program --

  // C's `void main()`, a sub of that name, or `task Main()`: said where it
  // is, rather than of the program as a whole.
  void missing_main() {
    const std::string why = ": the RCX starts a program at task main, so write 'task main()'";
    for (const auto& f : prog_.functions)
      if (f.name == "main") return void(diags_.error(f.span, "'main' is an inline function here" + why));
    for (const auto& sub : prog_.subs)
      if (sub.name == "main") return void(diags_.error(sub.span, "'main' is a sub here" + why));
    for (const auto& t : prog_.tasks)
      if (spelling_distance(t.name, "main") == 0)
        return void(diags_.error(t.span, "the program has no 'task main()', and names tell capitals apart: '" +
                                             t.name + "' is another task" + why));
    diags_.error({}, "the program has no 'task main()': the RCX starts a program at task main");
  }

  void check_limits() {
    bool has_main = false;
    for (const auto& t : prog_.tasks) has_main = has_main || t.name == "main";
    if (!has_main && whole_) missing_main();
    if (prog_.tasks.size() > static_cast<std::size_t>(kMaxTasks)) {
      auto& d = diags_.error(prog_.tasks[kMaxTasks].span,
                             "too many tasks: " + std::to_string(prog_.tasks.size()) + " (the RCX runs at most " +
                                 std::to_string(kMaxTasks) + ")");
      d.notes.push_back({prog_.tasks[0].span, "the first task is here"});
    }
  }

  void check_function_recursion() {
    // Inline functions are expanded at each call, so a cycle never ends.
    std::map<SymbolId, int> state;  // 1 = on the path, 2 = done
    std::vector<SymbolId> path;
    std::function<void(SymbolId)> dfs = [&](SymbolId f) {
      state[f] = 1;
      path.push_back(f);
      for (SymbolId g : function_calls_[f]) {
        if (state[g] == 1) {
          std::string chain;
          auto start = std::find(path.begin(), path.end(), g);
          for (auto it = start; it != path.end(); ++it) chain += prog_.symbols[*it].name + " -> ";
          chain += prog_.symbols[g].name;
          diags_.error(prog_.symbols[g].span, "inline functions call each other in a cycle: " + chain +
                                                  " (they are expanded at each call, so this never ends)");
        } else if (state[g] == 0) {
          dfs(g);
        }
      }
      path.pop_back();
      state[f] = 2;
    };
    for (const auto& [f, calls] : function_calls_)
      if (state[f] == 0) dfs(f);
  }

  // Under -n (Pragmas::program_init) the program's own `_init`, a sub or
  // an inline function, is what the startup code calls, as `#pragma init
  // _init` would; with neither, the built-in startup stays (nqc refuses).
  // Whether it was adopted.
  bool adopt_program_init() {
    Pragmas& p = prog_.pragmas;
    if (!p.program_init || p.noinit || p.init) return false;
    auto it = globals_.find("_init");
    if (it == globals_.end()) return false;
    const Symbol& f = prog_.symbols[it->second];
    if (f.kind != SymbolKind::Sub && f.kind != SymbolKind::Function) return false;
    p.init = f.name;
    p.init_span = f.span;
    return true;
  }

  // Which tasks run each sub, directly or through inline functions and
  // other subs: __taskid in a sub is the number of the one task that does.
  // Task main also runs what `#pragma init` names.
  void record_calling_tasks() {
    for (const auto& t : prog_.tasks) {
      std::set<SymbolId> seen;
      std::vector<SymbolId> todo{t.symbol};
      if (t.name == "main" && prog_.pragmas.init)
        if (auto it = globals_.find(*prog_.pragmas.init); it != globals_.end()) todo.push_back(it->second);
      while (!todo.empty()) {
        SymbolId f = todo.back();
        todo.pop_back();
        if (!seen.insert(f).second) continue;
        const Symbol& s = prog_.symbols[f];
        if (s.kind == SymbolKind::Sub) prog_.subs[s.index].calling_tasks.push_back(t.symbol);
        for (SymbolId g : callees_[f]) todo.push_back(g);
      }
    }
  }

  void check_pragmas() {
    bool own_init = adopt_program_init();
    if (!prog_.pragmas.init) return;
    auto it = globals_.find(*prog_.pragmas.init);
    if (it == globals_.end() || (prog_.symbols[it->second].kind != SymbolKind::Sub &&
                                 prog_.symbols[it->second].kind != SymbolKind::Function)) {
      diags_.error(prog_.pragmas.init_span,
                   "#pragma init names '" + *prog_.pragmas.init + "', which is not a sub or function");
      return;
    }
    prog_.symbols[it->second].used = true;
    const Symbol& f = prog_.symbols[it->second];
    if (f.kind != SymbolKind::Function) return;
    std::size_t n = prog_.functions[f.index].params.size();
    if (n == 0) return;
    std::string arguments = fmt::format("{} argument{}", n, n == 1 ? "" : "s");
    diags_.error(prog_.pragmas.init_span,
                 own_init ? "'_init' takes " + arguments +
                                ": without the standard library (-n) the startup code calls the program's own "
                                "'_init', with none"
                          : "#pragma init names '" + f.name + "', which takes " + arguments +
                                ": the startup code calls it with none");
  }
};

}  // namespace

void check(Program& program, Diagnostics& diags, const std::vector<std::string>& function_macro_names, bool whole) {
  program.symbols.clear();
  Checker(program, diags, function_macro_names, whole).run();
}

}  // namespace rcxc::frontend
