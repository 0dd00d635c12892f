// The typed syntax tree of an NQC program: what the parser builds, semantic
// analysis annotates (name resolution, constant values, switch cases), and
// IR lowering consumes.
//
// Contract for consumers (lowering):
//  - Every node carries a SourceSpan for diagnostics.
//  - Nodes are plain values: `Box<T>` is a deep-copying owning pointer, so a
//    whole Program (or one inline function body) can be copied freely, e.g.
//    to substitute parameters at an inline call site.
//  - After `frontend::check` (sema.h) succeeded, every `Name` has `symbol`
//    set, every Call/Start/Stop/Goto names its target symbol, every
//    expression that is a compile-time constant has `constant` set (16-bit
//    wrapped), each `Switch` lists its cases, and every `AsmInstr` has `op`.
//  - This header only grows: fields are added, never renamed or removed.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "frontend/diagnostics.h"
#include "rcx/opcodes.h"

namespace rcxc::ast {

// An owning pointer with value semantics: copying a Box copies the pointee.
// Used where the tree recurses (an expression holds expressions).
template <class T>
class Box {
 public:
  Box() : p_(std::make_unique<T>()) {}
  Box(T value) : p_(std::make_unique<T>(std::move(value))) {}  // NOLINT: implicit by design
  // Adopts a node the parser built on the heap; `p` must not be null.
  explicit Box(std::unique_ptr<T> p) : p_(std::move(p)) {}
  Box(const Box& o) : p_(std::make_unique<T>(*o.p_)) {}
  Box(Box&&) noexcept = default;
  Box& operator=(const Box& o) {
    if (this != &o) p_ = std::make_unique<T>(*o.p_);
    return *this;
  }
  Box& operator=(Box&&) noexcept = default;
  ~Box() = default;

  T& operator*() { return *p_; }
  const T& operator*() const { return *p_; }
  T* operator->() { return p_.get(); }
  const T* operator->() const { return p_.get(); }
  T* get() { return p_.get(); }
  const T* get() const { return p_.get(); }

 private:
  std::unique_ptr<T> p_;  // never null except after being moved from
};

// An optional node on the heap, with std::optional's reading interface
// (`if (b)`, `*b`, `b->`): where a std::optional<Expr> would hold a whole
// expression in every node of its kind, this holds a pointer. For's
// condition and step made every statement (a variant as large as its
// largest kind) 368 bytes; a program has a few statements per line.
template <class T>
class OptionalBox {
 public:
  OptionalBox() = default;
  OptionalBox(std::nullopt_t) {}  // NOLINT: implicit, as std::optional's
  OptionalBox(T value) : p_(std::make_unique<T>(std::move(value))) {}  // NOLINT: implicit by design
  // Adopts a node the parser built on the heap; null for none.
  explicit OptionalBox(std::unique_ptr<T> p) : p_(std::move(p)) {}
  OptionalBox(const OptionalBox& o) : p_(o.p_ ? std::make_unique<T>(*o.p_) : nullptr) {}
  OptionalBox(OptionalBox&&) noexcept = default;
  OptionalBox& operator=(const OptionalBox& o) {
    if (this != &o) p_ = o.p_ ? std::make_unique<T>(*o.p_) : nullptr;
    return *this;
  }
  OptionalBox& operator=(OptionalBox&&) noexcept = default;
  ~OptionalBox() = default;

  bool has_value() const { return p_ != nullptr; }
  explicit operator bool() const { return has_value(); }
  void reset() { p_.reset(); }
  T& operator*() { return *p_; }
  const T& operator*() const { return *p_; }
  T* operator->() { return p_.get(); }
  const T* operator->() const { return p_.get(); }

 private:
  std::unique_ptr<T> p_;
};

// ---------------------------------------------------------------- symbols --

// Index into Program::symbols. Filled by semantic analysis.
using SymbolId = std::uint32_t;
inline constexpr SymbolId kNoSymbol = std::numeric_limits<SymbolId>::max();

enum class SymbolKind : std::uint8_t {
  Global,    // `int x;` at file scope; index = position in Program::globals
  Local,     // `int x;` in a block; owner = enclosing task/sub/function
  Param,     // inline function parameter; owner = the function; index = position
  Task,      // index = position in Program::tasks
  Sub,       // index = position in Program::subs
  Function,  // inline `void` function; index = position in Program::functions
  Label,     // goto target; owner = enclosing task/sub/function
};

// The four parameter kinds of an inline function.
enum class ParamKind : std::uint8_t {
  Value,          // `int x`: fresh variable initialised from the argument
  Const,          // `const int x`: the argument must be a compile-time constant
  Reference,      // `int &x`: the argument must be a variable (aliased)
  ConstReference  // `const int &x`: the argument expression is substituted
};

struct Symbol {
  SymbolKind kind = SymbolKind::Global;
  std::string name;
  SourceSpan span;                 // the declaring name
  std::uint32_t index = 0;         // see SymbolKind
  SymbolId owner = kNoSymbol;      // Local/Param/Label: the task/sub/function
  ParamKind param_kind = ParamKind::Value;  // Param only
  bool used = false;               // read or referenced anywhere
};

// ------------------------------------------------------------ expressions --

struct Expr;
using ExprBox = Box<Expr>;

// An integer literal, `true`/`false` and character literals included.
// `value` is the literal as written (may exceed 16 bits; sema warns/wraps).
struct IntLit {
  std::int64_t value = 0;
};

// A use of a variable or parameter (or, wrongly, of a task/sub/function).
struct Name {
  std::string name;
  SymbolId symbol = kNoSymbol;
};

enum class UnaryOp : std::uint8_t {
  Negate,   // -x
  BitNot,   // ~x
  LogNot,   // !x
  Plus,     // +x
  PreInc,   // ++x
  PreDec,   // --x
  PostInc,  // x++
  PostDec,  // x--
  Abs,      // abs(x): the firmware's Absolute value (abs(-32768) is 32767)
  Sign,     // sign(x): -1, 0 or 1
};

struct Unary {
  UnaryOp op = UnaryOp::Negate;
  ExprBox operand;
};

enum class BinaryOp : std::uint8_t {
  Mul, Div, Mod, Add, Sub, Shl, Shr,
  Lt, Le, Gt, Ge, Eq, Ne,
  BitAnd, BitXor, BitOr, LogAnd, LogOr,
};

struct Binary {
  BinaryOp op = BinaryOp::Add;
  ExprBox lhs;
  ExprBox rhs;
};

enum class AssignOp : std::uint8_t {
  Assign,  // =
  Add, Sub, Mul, Div, Mod, BitAnd, BitOr, BitXor, Shl, Shr,  // op=
  Abs,     // ||=  target = abs(value)
  Sign,    // +-=  target = sign(value): -1, 0 or 1
};

// `target op= value`. `target` must name a variable (sema checks).
struct Assign {
  AssignOp op = AssignOp::Assign;
  ExprBox target;
  ExprBox value;
  // The operator: where a problem is shown when the target begins inside a
  // macro (SENSOR_1 = 1).
  SourceSpan op_span{};
};

// cond ? then_value : else_value
struct Conditional {
  ExprBox cond;
  ExprBox then_value;
  ExprBox else_value;
};

// `NAME(args)`: a call of a sub (no args) or an inline function. Calls have
// no value; sema rejects a call used as an operand.
struct Call {
  std::string callee;
  SourceSpan callee_span;
  std::vector<Expr> args;
  SymbolId symbol = kNoSymbol;  // Sub or Function
};

// `__source(TYPE, ARG)`: the value of RCX source TYPE with argument ARG (both
// constant expressions), e.g. Timer(n) = __source(1, n). Sema sets the two
// folded numbers; `Name`s are never rewritten into Source nodes.
struct Source {
  ExprBox type;
  ExprBox arg;
  std::int16_t type_value = 0;  // filled by sema
  std::int16_t arg_value = 0;   // filled by sema
};

// `__source_arg(E)`: the argument number of source expression E, as a
// constant. This is how the stdlib gets a sensor's index out of SENSOR_1
// (= __source(9, 0)) for SetSensor(SENSOR_1, ...). When E is (after inline
// substitution) a Source node it folds to that node's argument; anything else
// is an error ("argument must be a sensor"-style, reported by whoever folds).
// Written `__source_arg(E)` or `__source_arg(E, TYPE)`; with TYPE (a
// constant, e.g. 9 for sensors) E must be a source of exactly that type.
struct SourceArg {
  ExprBox operand;
  std::optional<std::int16_t> type_required;
  // nqc's `__sensor(E)`: a constant E gives its low byte (nqc reads
  // __sensor(300) as 44, __sensor(-1) as 255), a sensor its number.
  bool or_constant_byte = false;
};

// nqc's `__taskid`: the number of the task the code is compiled into
// (main is 0, the others count on in the order they are declared), a
// constant once lowering knows the task: for a subroutine, the one task
// that calls it. Sema leaves it unfolded, so a `case` label or a `const
// int` argument refuses it, as nqc does.
struct TaskId {};

// nqc's `__type(E)`: the source type of E's value without computing it, 2
// (constant) when E is a constant expression and 0 (variable) otherwise,
// as nqc gives even for a timer or a sensor. A constant itself; inside an
// inline function it is known once the parameters are substituted.
struct TypeOf {
  ExprBox operand;
};

using ExprNode = std::variant<IntLit, Name, Unary, Binary, Assign, Conditional, Call, Source, SourceArg, TaskId, TypeOf>;

struct Expr {
  ExprNode node;
  SourceSpan span;
  // The folded 16-bit value when the expression is a compile-time constant
  // (set by sema; lowering may rely on it).
  std::optional<std::int16_t> constant;
  // Levels of expression from here down, as the parser built it (a leaf is
  // 1); it stops a tree taller than the nesting limit while it is built.
  std::uint32_t parsed_height = 1;
};

// ------------------------------------------------------------------- asm --

// One item of an nqc-style byte list: a constant byte, or `$expr`, which
// emits the expression's source byte then its 16-bit argument (3 bytes), as
// nqc does (`$x` for a variable gives 0, slot, 0).
struct AsmByte {
  Expr value;
  bool source_pair = false;  // written `$expr`
  SourceSpan span;
  // nqc's `$expr : FLAGS` (its own header writes `$p : 0x01000015`): the
  // source types allowed (bit n for type n; none set means any) in bits
  // 0..23, 0x01000000 for a one-byte argument and 0x02000000 for no type
  // byte. Summed from the literals in full width, as for `@`.
  std::optional<std::int64_t> restriction;
};

// One mnemonic line `MNEMONIC operand, operand, ...;` (project extension).
// MNEMONIC is a row of the opcode table (rcx::by_mnemonic). Operands follow
// the row's operand list, except that a Source operand and its Argument are
// written as ONE expression operand (the compiler maps it onto the pair, or
// through a temporary when that source is not allowed there). Opcodes with
// Offset/Extension/Data operands (branches, loops, transfers) are rejected by
// sema: control flow is written in C.
struct AsmInstr {
  std::string mnemonic;
  SourceSpan mnemonic_span;
  std::vector<Expr> operands;
  std::optional<rcx::Op> op;  // filled by sema from rcx::by_mnemonic
  SourceSpan span;
};

using AsmItem = std::variant<AsmByte, AsmInstr>;

// ------------------------------------------------------------- statements --

struct Stmt;
using StmtBox = Box<Stmt>;

// `int name = init;` (global or local). Locals may have any initialiser;
// globals only constant ones (sema checks).
struct VarDecl {
  std::string name;
  SourceSpan span;  // the name
  OptionalBox<Expr> init;
  SymbolId symbol = kNoSymbol;
  // C's `const int K = 5;`: refused where it is written, but its uses read
  // K's value, so they draw no errors of their own (`PlayTone(K, 10)`).
  bool refused_const = false;
};

struct Block {
  std::vector<Stmt> stmts;
};

struct DeclStmt {
  std::vector<VarDecl> vars;  // `int a, b = 2;` gives two
};

struct ExprStmt {
  Expr expr;
};

struct If {
  Expr cond;
  StmtBox then_branch;
  std::optional<StmtBox> else_branch;
};

struct While {
  Expr cond;
  StmtBox body;
};

struct DoWhile {
  StmtBox body;
  Expr cond;
  bool until = false;  // `do body until (cond);` loops while cond is false
};

// `until (cond) body`: loops while cond is false.
struct Until {
  Expr cond;
  StmtBox body;
};

// `for (init; cond; step) body`. `init` is an ExprStmt or a DeclStmt (the
// latter scoped to the loop, an extension over nqc), or absent.
struct For {
  std::optional<StmtBox> init;
  OptionalBox<Expr> cond;
  OptionalBox<Expr> step;
  StmtBox body;
};

// `repeat (count) body`.
struct Repeat {
  Expr count;
  StmtBox body;
};

// One `case`/`default` of a switch, collected by sema in source order.
struct SwitchCase {
  std::optional<std::int16_t> value;  // nullopt for `default`
  SourceSpan span;
};

// `switch (value) body`. Case labels are statements (`Case`, `Default`)
// inside body, as in C (fall-through, cases inside nested blocks).
struct Switch {
  Expr value;
  StmtBox body;
  std::vector<SwitchCase> cases;  // filled by sema
};

// `case value: stmt`. `index` is this label's position in the innermost
// enclosing Switch::cases (filled by sema).
struct Case {
  Expr value;
  StmtBox body;
  std::uint32_t index = 0;
};

struct Default {
  StmtBox body;
  std::uint32_t index = 0;
};

struct Break {};
struct Continue {};
struct Return {};

struct Goto {
  std::string label;
  SymbolId symbol = kNoSymbol;
};

// `label: stmt`
struct Labeled {
  std::string label;
  SourceSpan label_span;
  StmtBox body;
  SymbolId symbol = kNoSymbol;
};

// `start NAME;` / `stop NAME;`
struct StartTask {
  std::string task;
  SymbolId symbol = kNoSymbol;
};
struct StopTask {
  std::string task;
  SymbolId symbol = kNoSymbol;
};

struct Asm {
  std::vector<AsmItem> items;
};

struct Empty {};

using StmtNode = std::variant<Block, DeclStmt, ExprStmt, If, While, DoWhile, Until, For, Repeat, Switch, Case,
                              Default, Break, Continue, Return, Goto, Labeled, StartTask, StopTask, Asm, Empty>;

struct Stmt {
  StmtNode node;
  SourceSpan span;
};

// --------------------------------------------------------------- program --

struct Param {
  ParamKind kind = ParamKind::Value;
  std::string name;
  SourceSpan span;
  SymbolId symbol = kNoSymbol;
  // nqc's `__sensor NAME`: a `const int &` whose argument must be SENSOR_n.
  bool sensor = false;
};

// `task NAME() body` / `sub NAME() body`. body is always a Block.
struct Task {
  std::string name;
  SourceSpan span;  // the name
  Stmt body;
  SymbolId symbol = kNoSymbol;
};
struct Sub {
  std::string name;
  SourceSpan span;
  Stmt body;
  SymbolId symbol = kNoSymbol;
  // The tasks that call it, directly or through inline functions and other
  // subs, in the order of Program::tasks (filled by sema).
  std::vector<SymbolId> calling_tasks;
};

// `void NAME(params) body`, expanded at each call.
struct Function {
  std::string name;
  SourceSpan span;
  std::vector<Param> params;
  Stmt body;
  SymbolId symbol = kNoSymbol;
};

// `#pragma reserve LO [HI]`: variable slots LO..HI (inclusive) stay free.
struct Reserve {
  int lo = 0;
  int hi = 0;
  SourceSpan span;
};

struct Pragmas {
  // The later of `#pragma noinit` and `#pragma init NAME` holds: at most
  // one of these is set.
  bool noinit = false;                 // `#pragma noinit`: no startup code
  std::optional<std::string> init;     // `#pragma init NAME`: startup calls NAME
  SourceSpan init_span;
  // Without the standard library (-n) nothing defines the `_init` nqc's
  // startup code calls: a program that defines its own gets it called, as
  // with nqc, where the built-in startup would silently replace it.
  bool program_init = false;
  std::vector<Reserve> reserve;
};

// A top-level declaration, by kind and position in its Program vector.
struct TopLevelRef {
  SymbolKind kind = SymbolKind::Global;  // Global, Task, Sub or Function
  std::uint32_t index = 0;
};

struct Program {
  std::vector<VarDecl> globals;
  std::vector<Task> tasks;       // in source order; `main` is wherever it is
  std::vector<Sub> subs;
  std::vector<Function> functions;
  Pragmas pragmas;
  std::vector<Symbol> symbols;   // filled by sema; SymbolId indexes this
  // Every top-level declaration in the order of the (preprocessed) source:
  // stdlib first, then the program. Filled by the parser.
  std::vector<TopLevelRef> order;
  // The macros defined at the end of the program (OUT_A, SENSOR_TOUCH, the
  // program's own), for "did you mean" when a name is not declared.
  std::vector<std::string> macro_names;
  // The macros an #undef removed for good, each with the name in the #undef.
  std::vector<std::pair<std::string, SourceSpan>> undefined_macros;

  const Symbol& symbol(SymbolId id) const { return symbols.at(id); }
};

// Convenience for consumers: `if (auto* b = as<Binary>(e)) ...`.
template <class T>
const T* as(const Expr& e) { return std::get_if<T>(&e.node); }
template <class T>
T* as(Expr& e) { return std::get_if<T>(&e.node); }
template <class T>
const T* as(const Stmt& s) { return std::get_if<T>(&s.node); }
template <class T>
T* as(Stmt& s) { return std::get_if<T>(&s.node); }

}  // namespace rcxc::ast
