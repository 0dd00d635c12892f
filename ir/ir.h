// The compiler's intermediate representation.
//
// A Program is a list of Functions (tasks and subroutines) and a table of
// variables. Every function is a list of basic blocks; a block is a list of
// instructions and one terminator. Instructions are RCX opcodes (rows of the
// opcode table in rcx/opcodes.h) whose operands are Operands: an RCX
// source/argument pair, an immediate, a program variable or compiler temporary
// that is not yet bound to one of the 32 slots, or a reference to a function.
// Control flow lives only in terminators, so passes can reorder blocks and the
// backend can choose near or far branch forms at the end.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "frontend/diagnostics.h"
#include "rcx/opcodes.h"

namespace rcxc::ir {

using VarId = int;
using BlockId = int;
using FuncId = int;

// One operand. Var/Imm/Src are values an opcode's source/argument pair can
// name (Var becomes source 0 with the variable's slot once slots are chosen);
// Func names a task or subroutine (its index is chosen by the backend).
struct Operand {
  enum class Kind : std::uint8_t { Imm, Var, Src, Func };
  // Eight bytes: every pass reads the instructions of the whole program
  // several times, and on long programs the time goes into fetching them.
  Kind kind = Kind::Imm;
  std::int16_t source = 2;  // RCX source (Imm: 2, Var: 0, Src: the source; types are 0 to 15)
  int value = 0;            // Imm: the constant; Var: VarId; Src: argument; Func: FuncId

  static Operand imm(int v) { return {Kind::Imm, 2, v}; }
  static Operand var(VarId id) { return {Kind::Var, 0, id}; }
  static Operand src(int source, int argument) {
    if (source == 2) return imm(argument);
    return {Kind::Src, static_cast<std::int16_t>(source), argument};
  }
  static Operand func(FuncId id) { return {Kind::Func, 0, id}; }

  bool is_imm() const { return kind == Kind::Imm; }
  bool is_var() const { return kind == Kind::Var; }
  bool is_var(VarId id) const { return kind == Kind::Var && value == id; }
  friend bool operator==(const Operand&, const Operand&) = default;
};

// An instruction's operands: up to three kept inside the instruction (every
// opcode the compiler emits but a few has at most three), more (raw asm
// bytes) on the heap. A program's instructions then sit in their blocks'
// arrays with their operands: the passes, which walk every instruction of
// the program many times, read memory in order, and copying or making an
// instruction allocates nothing. The rare heap part is one pointer, not a
// vector, to keep every instruction small (40 bytes here, 72 with a vector
// and the 12-byte operands before).
class Operands {
 public:
  Operands() = default;
  Operands(std::initializer_list<Operand> list) {
    for (const Operand& o : list) push_back(o);
  }
  Operands(const std::vector<Operand>& list) {  // NOLINT: as a vector converts
    for (const Operand& o : list) push_back(o);
  }
  Operands(const Operands& o) : inline_(o.inline_), size_(o.size_) {
    if (o.spill_) spill_ = std::make_unique<std::vector<Operand>>(*o.spill_);
  }
  // A moved-from list is empty.
  Operands(Operands&& o) noexcept : inline_(o.inline_), size_(std::exchange(o.size_, 0)), spill_(std::move(o.spill_)) {}
  Operands& operator=(const Operands& o) {
    if (this != &o) *this = Operands(o);
    return *this;
  }
  Operands& operator=(Operands&& o) noexcept {
    if (this == &o) return *this;
    inline_ = o.inline_;
    size_ = std::exchange(o.size_, 0);
    spill_ = std::move(o.spill_);
    return *this;
  }
  ~Operands() = default;

  void push_back(const Operand& o) {
    if (size_ < kInline) {
      inline_[size_] = o;
    } else {
      if (size_ == kInline) spill_ = std::make_unique<std::vector<Operand>>(inline_.begin(), inline_.end());
      spill_->push_back(o);
    }
    ++size_;
  }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  Operand* begin() { return size_ <= kInline ? inline_.data() : spill_->data(); }
  Operand* end() { return begin() + size_; }
  const Operand* begin() const { return size_ <= kInline ? inline_.data() : spill_->data(); }
  const Operand* end() const { return begin() + size_; }
  Operand& operator[](std::size_t i) { return begin()[i]; }
  const Operand& operator[](std::size_t i) const { return begin()[i]; }
  const Operand& at(std::size_t i) const {
    if (i >= size_) throw std::out_of_range("Operands::at");
    return begin()[i];
  }
  Operand& at(std::size_t i) {
    if (i >= size_) throw std::out_of_range("Operands::at");
    return begin()[i];
  }
  friend bool operator==(const Operands& a, const Operands& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end());
  }

 private:
  static constexpr std::size_t kInline = 3;
  std::array<Operand, kInline> inline_{};
  std::uint32_t size_ = 0;
  std::unique_ptr<std::vector<Operand>> spill_;  // all of them once there are more than kInline
};

// Where in the source an instruction or block comes from: an index into
// the Program's `spans`. 0 is no place (an empty span). A SourceSpan is 32
// bytes and an instruction without one 48: the passes walk every
// instruction of the program many times, and on long programs the time
// goes into fetching them, while only diagnostics and listings read where
// one came from (most instructions share their statement's).
using SpanId = std::uint32_t;

// One instruction: an opcode of the table and one Operand per operand of
// the table's layout, where a Source+Argument pair is ONE operand (the
// pair's Argument entry takes no Operand of its own). A raw instruction
// (asm byte lists) holds bytes as Imm operands and variable slots as Var.
// The operands come first, so that the small fields share their last
// eight bytes.
struct Instr {
  Instr() = default;
  Instr(rcx::Op o, Operands a, bool r = false, SpanId s = 0) : args(std::move(a)), span(s), op(o), raw(r) {}

  Operands args;
  SpanId span = 0;
  rcx::Op op = rcx::Op::SetVariable;
  bool raw = false;
};

// Comparisons a branch can test. The firmware has <=, >=, != and ==; the
// strict ones are rewritten by the backend.
enum class Cmp : std::uint8_t { LE, GE, NE, EQ, LT, GT };
Cmp negate(Cmp c);
Cmp swap(Cmp c);  // a c b  <=>  b swap(c) a
// Whether one test-and-branch can branch when `a c b` holds: it compares
// with <=, >=, == or !=, and a strict comparison works only against a
// constant (c < x is c+1 <= x).
bool branches_directly(Cmp c, const Operand& a, const Operand& b);
// The comparison evaluated on 16-bit signed values.
bool evaluate(Cmp c, int a, int b);

struct Jump {
  BlockId target = 0;
};
// if (a cmp b) goto then else goto otherwise.
struct Branch {
  Cmp cmp = Cmp::EQ;
  Operand a, b;
  BlockId then = 0, otherwise = 0;
};
// Head of a `repeat` that uses the firmware loop counter: decrement the
// counter; if it went below zero pop it and go to `exit`, else go to `body`.
struct LoopTest {
  int loop = 0;
  BlockId body = 0, exit = 0;
};
// Draws Random(1) and goes to `zero` or `one`. The backend tosses it on
// the loop counter (loopset random(1), then two loop tests), which only
// branches forward, so both sides must lie after the block.
struct CoinToss {
  BlockId zero = 0, one = 0;
};
// Leaves the function: end of a task, return from a subroutine.
struct Exit {};
using Terminator = std::variant<Jump, Branch, LoopTest, CoinToss, Exit>;

struct Block {
  std::vector<Instr> instrs;
  Terminator term = Exit{};
  SpanId span = 0;
};

// A `repeat` loop in its firmware loop counter form: the block that pushes
// the counter (its last instruction is the loopset) and the LoopTest block.
// `escapes` is set when control can leave the body other than through the
// LoopTest (break, return, goto): the counter would stay pushed, so such
// loops are rewritten to use a variable.
struct Repeat {
  BlockId setup = 0;
  BlockId head = 0;
  bool escapes = false;
  bool counter = true;  // false once rewritten to a variable counter
};

enum class FuncKind : std::uint8_t { Task, Sub };

struct Function {
  std::string name;
  FuncKind kind = FuncKind::Task;
  std::vector<Block> blocks;  // blocks[0] is the entry; order is the layout
  std::vector<Repeat> repeats;
  SourceSpan span{};
  // The first `startup` instructions of the entry block are main's startup
  // code: they run before any other task can have been started.
  int startup = 0;
};

enum class VarKind : std::uint8_t { Global, Local, Temp };

struct Var {
  std::string name;
  VarKind kind = VarKind::Temp;
  std::optional<int> slot;  // fixed slot (e.g. asm wants it), else chosen
  SourceSpan span{};
};

struct Program {
  std::vector<Function> functions;
  std::vector<Var> vars;
  std::uint32_t reserved_slots = 0;  // bit n: #pragma reserve keeps slot n free
  // What each SpanId stands for; spans[0] is the empty span.
  std::vector<SourceSpan> spans{SourceSpan{}};

  VarId add_var(std::string name, VarKind kind, SourceSpan span = {});
  FuncId find_function(const std::string& name) const;  // -1 if absent
  // A new SpanId for `span`.
  SpanId add_span(const SourceSpan& span);
  const SourceSpan& span(SpanId id) const { return spans[id]; }
};

// Up to N values kept inline: the few ids a terminator or an opcode has
// (a block's successors, the variables a branch reads), which the passes ask
// for per block and per instruction, so they allocate nothing.
template <class T, std::size_t N>
class InlineList {
 public:
  void push_back(T v) {
    if (size_ == N) throw std::length_error("InlineList: more than its capacity");
    items_[size_++] = v;
  }
  const T* begin() const { return items_.data(); }
  const T* end() const { return items_.data() + size_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const T& operator[](std::size_t i) const { return items_[i]; }

 private:
  std::array<T, N> items_{};
  std::size_t size_ = 0;
};

// Reading and writing a function's blocks.
BlockId add_block(Function& f);
using Successors = InlineList<BlockId, 2>;
// Inline: the passes ask for the successors of every block many times.
inline Successors successors(const Terminator& t) {
  Successors s;
  if (const auto* j = std::get_if<Jump>(&t)) {
    s.push_back(j->target);
  } else if (const auto* b = std::get_if<Branch>(&t)) {
    s.push_back(b->then);
    s.push_back(b->otherwise);
  } else if (const auto* l = std::get_if<LoopTest>(&t)) {
    s.push_back(l->body);
    s.push_back(l->exit);
  } else if (const auto* c = std::get_if<CoinToss>(&t)) {
    s.push_back(c->zero);
    s.push_back(c->one);
  }
  return s;
}
// Edges into each block (a branch whose two sides are one block counts twice).
std::vector<int> predecessor_counts(const Function& f);
// For each block its index in reverse postorder from the entry (every
// block before its successors, loops aside); -1 for blocks no path reaches.
// Forward data-flow visiting blocks in this order meets each join once
// per round instead of once per path.
std::vector<int> reverse_postorder_index(const Function& f);
// Adds `delta` to every block `t` refers to.
void offset_targets(Terminator& t, BlockId delta);
// Appends `from`'s repeat loops to `to`, whose copies of their blocks
// start at block `base`.
void append_repeats(Function& to, const std::vector<Repeat>& from, BlockId base);
// Rewrites every reference to block `from` in `t` to `to`.
void retarget(Terminator& t, BlockId from, BlockId to);
// Rewrites every block `t` refers to through `map` (old id -> new id).
void map_targets(Terminator& t, const std::vector<BlockId>& map);

// The operands of an opcode as the IR sees them: the table's operands
// minus the Argument half of each Source/Argument pair and minus branch
// offsets, which the backend fills in.
// At most kMaxOperandSlots (a unit test checks every opcode of the table).
inline constexpr std::size_t kMaxOperandSlots = 8;
using OperandSlots = InlineList<const rcx::Operand*, kMaxOperandSlots>;
OperandSlots operand_slots(rcx::Op op);
// Whether `o` can be operand `slot` of `op` as is: its source is allowed
// there and an immediate fits the argument field. When not, the value must
// go through a temporary variable first.
bool accepts(rcx::Op op, std::size_t slot, const Operand& o);
// Whether a 16-bit value fits a table field.
bool fits_field(rcx::FieldType t, int v);

// 16-bit wrap-around.
constexpr int wrap16(long v) { return static_cast<std::int16_t>(static_cast<std::uint16_t>(v & 0xffff)); }
// The firmware's variable arithmetic (set/add/sub/mul/div/and/or/abs/sgn)
// on constants: `dest` is the variable's old value, `src` the operand.
// std::nullopt for opcodes that are not variable arithmetic.
std::optional<int> arithmetic(rcx::Op op, int dest, int src);
// Whether `x op= k` leaves every x as it was: + - | of 0, * of 1, & of
// -1, and / of 1 or 0 (the firmware leaves a variable divided by zero
// unchanged).
bool leaves_unchanged(rcx::Op op, int k);

// The task a start or stop instruction names, or -1: another instruction,
// raw asm, or a task given by its number in asm (`asm { start 2; }`), which
// the compiler cannot follow (task numbers are chosen by the backend).
FuncId task_named(const Instr& in);
// Whether `in` may start or stop a task without naming it: raw asm bytes,
// or a start or stop by number.
bool starts_or_stops_unnamed_task(const Instr& in);
// For each function, whether some instruction starts it as a task (for
// main: restarts it, so its startup code can run while other tasks run),
// all found in one walk of the program.
std::vector<bool> started_functions(const Program& p);

// Visits the instructions of `fn` that can act while other tasks run: all
// but main's startup code, unless something restarts main (`started`:
// started_functions' entry for fn).
template <class Visit>
void each_instr_beside_other_tasks(const Function& fn, bool started, Visit&& visit) {
  int skip = started ? 0 : fn.startup;
  for (std::size_t b = 0; b < fn.blocks.size(); ++b)
    for (std::size_t i = 0; i < fn.blocks[b].instrs.size(); ++i)
      if (!(b == 0 && static_cast<int>(i) < skip)) visit(fn.blocks[b].instrs[i]);
}

// Whether block b is the setup or the head of one of f's counter loops,
// which passes must not merge, thread through or move code across.
bool is_repeat_block(const Function& f, BlockId b);
// The same for every block at once (a pass asking per block would take
// blocks x loops).
std::vector<bool> repeat_blocks(const Function& f);

// Reorders the blocks: `order` lists every old BlockId once, in the new
// layout order (order[0] must be the entry, 0).
void permute_blocks(Function& f, const std::vector<BlockId>& order);
// Moves block `from` so that it becomes layout position `to` (0 = entry is
// not allowed to move), renumbering every reference.
void move_block(Function& f, BlockId from, BlockId to);
// Deletes the blocks for which keep[b] is false (none may be referenced by
// a kept block) and renumbers the rest in order.
void remove_blocks(Function& f, const std::vector<bool>& keep);

// Bytes an instruction takes in the image (raw asm: its byte count).
int instr_size(const Instr& in);

// Whether two instructions are the same: opcode, operands and rawness
// (source spans aside).
bool same_instr(const Instr& a, const Instr& b);
// Whether the operand reads the random source (each read draws a number).
bool reads_random(const Operand& o);

// The opcodes that compute into a variable and do nothing else: set,
// arithmetic, logic, absolute value and sign.
bool computes_into_variable(rcx::Op op);
// Whether `in` sets outputs' direction, on/off mode or power (raw asm
// bytes are not counted).
bool is_motor_command(const Instr& in);
// Whether `in` is a motor command, a sound or arithmetic into a variable:
// an instruction's time that changes nothing but outputs, the speaker or
// a variable, which hoist.cpp may move before a test and a coin toss may
// then find between its draw and its test.
bool is_quick_command(const Instr& in);
// Whether the program has more than one task with code: one task's
// commands may then be seen, and answered, by another between two of its
// instructions.
bool runs_several_tasks(const Program& p);
// Whether another task can read or write `v` between any two instructions
// of a task: a global (a `#pragma reserve` slot written by number is one
// too). Locals and temporaries belong to their task.
bool shared_between_tasks(const Var& v);
// Whether another task can see `in` happen: a motor command (through an
// output's state) or an assignment to a variable shared between tasks.
bool seen_by_other_tasks(const Instr& in, const std::vector<Var>& vars);

// Variables an instruction reads and writes (Var operands only).
// The variables of one instruction: a few, kept inline, so the passes that
// ask about every instruction of every block allocate nothing (raw asm with
// more operands spills to the heap).
class VarList {
 public:
  void push_back(VarId v) {
    if (size_ < kInline) {
      inline_[size_] = v;
    } else {
      if (size_ == kInline) spill_.assign(inline_.begin(), inline_.end());
      spill_.push_back(v);
    }
    ++size_;
  }
  const VarId* begin() const { return size_ <= kInline ? inline_.data() : spill_.data(); }
  const VarId* end() const { return begin() + size_; }
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  VarId front() const { return *begin(); }

 private:
  static constexpr std::size_t kInline = 4;
  std::array<VarId, kInline> inline_{};
  std::vector<VarId> spill_;
  std::size_t size_ = 0;
};

struct VarUse {
  VarList reads;
  VarList writes;  // a write that fully replaces the old value
};
VarUse uses_of(const Instr& in);
InlineList<VarId, 2> reads_of(const Terminator& t);

// Human-readable dump (tests and -v).
std::string to_string(const Program& p);
std::string to_string(const Program& p, const Function& f);

}  // namespace rcxc::ir
