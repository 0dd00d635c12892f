// The NQC grammar (bison, C++ skeleton). Reads preprocessed tokens through
// `Feed` and builds the AST of frontend/ast.h; every node gets the span of
// the tokens it was built from.
%require "3.2"
%language "c++"
%define api.namespace {rcxc::frontend::yy}
%define api.parser.class {Parser}
%define api.value.type variant
%define api.token.constructor
%define api.location.type {rcxc::SourceSpan}
%define parse.error custom
%locations
%param {Feed& feed}

%code requires {
#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "frontend/ast.h"
#include "frontend/diagnostics.h"
#include "frontend/nesting.h"
#include "frontend/parse.h"
#include "frontend/token.h"

namespace rcxc::frontend {
struct Feed;
// Semantic values are owning pointers: bison's stack slot is as large as
// its largest value type and is zeroed and moved on every shift and
// reduction, and an expression built on the heap is adopted by the node
// above it (an ast::Box) without another move.
using ExprPtr = std::unique_ptr<ast::Expr>;
using StmtPtr = std::unique_ptr<ast::Stmt>;
}
}

%code provides {
namespace rcxc::frontend {

// Hands the parser one token at a time and collects what it builds.
struct Feed {
  const std::vector<Token>& tokens;
  Diagnostics& diags;
  ast::Program program;
  std::size_t pos = 0;
  std::string_view last_text;  // spelling of the token just handed out (in `tokens`)
  SourceLoc prev_end;        // end of the token before it
  // asm blocks: mnemonic lines start with an identifier at an item start.
  int asm_stage = 0;         // 0 none, 1 saw 'asm', 2 inside its braces
  bool asm_item_start = false;
  int asm_depth = 0;
  bool asm_byte_list = false;  // the block is a list of bytes (`asm { 0x51, 1 }`), not mnemonic lines
  std::vector<SourceSpan> open_braces;  // each '{' handed out and not yet closed
  // Names declared as arrays (`int a[4]`), refused at the declaration: an
  // index on one of them is that same mistake again, not a new error.
  std::vector<std::string> refused_arrays{};
  // The index of the token after the last one the lexer could not read (a
  // string or character left open, which takes the rest of its line, or a
  // stray character), already reported: a syntax error found right there is
  // that mistake again (`PlaySound("click);` lost its `);` to the string).
  // Likewise the '{' after `task main();`, whose ';' was reported.
  std::size_t after_unreadable = static_cast<std::size_t>(-1);
  // The index of the last number the lexer took that has no value (`3x`),
  // already reported: a syntax error found at it is that mistake again
  // (`int 3x;` also said "expected identifier").
  std::size_t invalid_number = static_cast<std::size_t>(-1);
  // Set when the input nests deeper than the tree may (an expression taller
  // than kMaxNesting, or the parser's stack past what that many levels
  // need): reported once, and the parse ends there, before the tree or the
  // stack grows with the input.
  bool too_deep = false;
  // The largest stack a token was read with and the tallest expression
  // built: together a bound on how deep the tree nests (parse_tokens).
  std::size_t deepest_stack = 0;
  std::uint32_t tallest_expr = 0;
  // C's `int main() { ... }`: set at the head, then the body from its '{'
  // to its '}' (end unset while open). A `return 0;` in it is the same C
  // habit the head's error names, not a second mistake.
  bool int_main_head = false;
  SourceSpan int_main_body{};
  // Where the preprocessor reported an error at a token a macro made (a
  // macro used in its own text, which it leaves unexpanded): a syntax error
  // in the statement holding that token is the same mistake again
  // (`#define X X + 1`, then `int X;` reads `int X + 1;`).
  std::vector<SourceLoc> macro_errors{};
};

// Whether `at` lies in the body of C's `int main()` (Feed::int_main_body).
bool in_int_main_body(const Feed& feed, const SourceLoc& at);

// `stack_size` is the parser's stack as this token is asked for.
yy::Parser::symbol_type next_token(Feed& feed, std::size_t stack_size);

}  // namespace rcxc::frontend

// Expanded inside Parser::parse(), where the stack is in scope: the feed
// stops a parse whose stack grows with the input (x = x = ... = 1).
#define yylex(feed) rcxc::frontend::next_token(feed, yystack_.size())
}

%code {
#define YYLLOC_DEFAULT(Cur, Rhs, N)                 \
  do {                                              \
    if (N) {                                        \
      (Cur).begin = YYRHSLOC(Rhs, 1).begin;         \
      (Cur).end = YYRHSLOC(Rhs, N).end;             \
    } else {                                        \
      (Cur).begin = (Cur).end = YYRHSLOC(Rhs, 0).end; \
    }                                               \
  } while (0)

namespace {
using namespace rcxc;
using namespace rcxc::ast;

// C's `const int K = 5;`: NQC's only constants are macros and numbers.
constexpr const char* kNoConstVariables =
    "NQC has no constant variables: write '#define NAME value' for a named constant ('const' belongs to "
    "function parameters only)";

template <class F>
void each_operand(const ExprNode& n, F f) {
  std::visit([&](const auto& v) {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, Unary>) f(*v.operand);
    if constexpr (std::is_same_v<T, Binary>) { f(*v.lhs); f(*v.rhs); }
    if constexpr (std::is_same_v<T, Assign>) { f(*v.target); f(*v.value); }
    if constexpr (std::is_same_v<T, Conditional>) { f(*v.cond); f(*v.then_value); f(*v.else_value); }
    if constexpr (std::is_same_v<T, Call>) for (const auto& a : v.args) f(a);
    if constexpr (std::is_same_v<T, Source>) { f(*v.type); f(*v.arg); }
    if constexpr (std::is_same_v<T, SourceArg>) f(*v.operand);
    if constexpr (std::is_same_v<T, TypeOf>) f(*v.operand);
  }, n);
}
// A node one level above its tallest operand. A left-associative chain
// (x+x+...) reduces as it goes, so the parser's stack stays small while the
// tree grows: the height is what stops it, at the operand that made it too
// tall, and that tree is dropped at once.
using frontend::ExprPtr;
using frontend::StmtPtr;
ExprPtr mk(frontend::Feed& feed, ExprNode n, const SourceSpan& s) {
  std::uint32_t height = 0;
  SourceSpan last_operand = s;
  each_operand(n, [&](const Expr& e) {
    height = std::max(height, e.parsed_height);
    last_operand = e.span;
  });
  if (height + 1 > static_cast<std::uint32_t>(frontend::kMaxNesting)) {
    if (!feed.too_deep) feed.diags.error(last_operand, frontend::too_deep_message());
    feed.too_deep = true;
    return std::make_unique<Expr>(Expr{IntLit{0}, s, std::nullopt});
  }
  auto e = std::make_unique<Expr>(Expr{std::move(n), s, std::nullopt});
  e->parsed_height = height + 1;
  feed.tallest_expr = std::max(feed.tallest_expr, height + 1);
  return e;
}
StmtPtr mks(StmtNode n, const SourceSpan& s) { return std::make_unique<Stmt>(Stmt{std::move(n), s}); }
ExprBox box(ExprPtr e) { return ExprBox(std::move(e)); }
StmtBox box(StmtPtr s) { return StmtBox(std::move(s)); }
std::vector<Stmt> stmts_of(StmtPtr a, StmtPtr b = nullptr) {
  std::vector<Stmt> out;
  out.push_back(std::move(*a));
  if (b) out.push_back(std::move(*b));
  return out;
}
ExprPtr bin(frontend::Feed& feed, BinaryOp op, ExprPtr a, ExprPtr b, const SourceSpan& s) {
  return mk(feed, Binary{op, box(std::move(a)), box(std::move(b))}, s);
}
ExprPtr asg(frontend::Feed& feed, AssignOp op, ExprPtr a, ExprPtr b, const SourceSpan& s, const SourceSpan& op_span) {
  return mk(feed, Assign{op, box(std::move(a)), box(std::move(b)), op_span}, s);
}
ExprPtr un(frontend::Feed& feed, UnaryOp op, ExprPtr a, const SourceSpan& s) {
  return mk(feed, Unary{op, box(std::move(a))}, s);
}
// nqc's `@E`: the source whose type is E's upper 16 bits and whose argument
// its lower 16 (`@(0x10000 + n)` is Timer(n)). Constants fold in 16 bits, so
// the literals of E's +/- chain are summed here, in full width; what is left
// (n) joins the argument. Names hold 16-bit values, so they never carry a
// type.
void additive_terms(Expr e, bool negate, std::int64_t& literal, std::vector<std::pair<bool, ExprPtr>>& rest) {
  if (auto* lit = std::get_if<IntLit>(&e.node)) {
    literal += negate ? -lit->value : lit->value;
    return;
  }
  if (auto* b = std::get_if<Binary>(&e.node); b && (b->op == BinaryOp::Add || b->op == BinaryOp::Sub)) {
    additive_terms(std::move(*b->lhs), negate, literal, rest);
    additive_terms(std::move(*b->rhs), b->op == BinaryOp::Sub ? !negate : negate, literal, rest);
    return;
  }
  rest.emplace_back(negate, std::make_unique<Expr>(std::move(e)));
}
ExprPtr encoded_source(frontend::Feed& feed, Expr e, const SourceSpan& s) {
  std::int64_t literal = 0;
  std::vector<std::pair<bool, ExprPtr>> rest;
  const SourceSpan whole = e.span;
  additive_terms(std::move(e), false, literal, rest);
  ExprPtr arg = mk(feed, IntLit{literal & 0xffff}, whole);
  for (auto& [negate, term] : rest)
    arg = bin(feed, negate ? BinaryOp::Sub : BinaryOp::Add, std::move(arg), std::move(term), whole);
  return mk(feed, Source{box(mk(feed, IntLit{literal >> 16}, whole)), box(std::move(arg)), 0, 0}, s);
}
// Whether the token just handed out sits in a `for (...)` header: the
// nearest '(' left open before it follows `for`.
bool in_for_header(const frontend::Feed& feed) {
  int depth = 0;
  for (std::size_t i = feed.pos - 1; i-- > 1;) {
    const frontend::Token& t = feed.tokens[i];
    if (t.is("{") || t.is("}")) return false;
    if (t.is(")")) ++depth;
    if (t.is("(") && depth-- == 0) return feed.tokens[i - 1].is_identifier("for");
  }
  return false;
}
// A ',' where C's comma operator would stand: in a statement, or inside
// its parentheses, but not in a case label (`case 1, 2:`) nor in the one
// value of abs(), sign() and the intrinsics, which have a message of
// their own. (Where a list is allowed, the parser took the comma.)
bool comma_operator(const frontend::Feed& feed) {
  static constexpr std::string_view kOneValue[] = {"abs", "sign", "__type", "__sensor", "__source", "__source_arg"};
  int depth = 0;
  bool innermost = true;
  for (std::size_t i = feed.pos - 1; i-- > 0;) {
    const frontend::Token& t = feed.tokens[i];
    if (t.is(";") || t.is("{") || t.is("}")) return !feed.tokens[i + 1].is_identifier("case");
    if (t.is(")")) {
      ++depth;
    } else if (t.is("(") && depth > 0) {
      --depth;
    } else if (t.is("(") && innermost) {
      innermost = false;
      if (i > 0 && feed.tokens[i - 1].kind == frontend::TokenKind::Identifier &&
          std::find(std::begin(kOneValue), std::end(kOneValue), feed.tokens[i - 1].text) != std::end(kOneValue))
        return false;
    }
  }
  return false;
}
// Inside an inline function's parameter list (`void f(` ...) up to the
// token found, which is not its ')'.
bool in_parameter_list(const frontend::Feed& feed) {
  for (std::size_t i = feed.pos - 1; i-- > 0;) {
    const frontend::Token& t = feed.tokens[i];
    if (t.is(")") || t.is(";") || t.is("{") || t.is("}")) return false;
    if (t.is("("))
      return i >= 2 && feed.tokens[i - 1].kind == frontend::TokenKind::Identifier &&
             feed.tokens[i - 2].is_identifier("void");
  }
  return false;
}
// Token `i` is the first of a statement: after ';', a brace, a label's ':',
// an `else`, or the ')' that closes an if/while/for head (any ')' will do:
// a name right after a call's ')' is no statement either way).
bool starts_statement(const frontend::Feed& feed, std::size_t i) {
  if (i == 0) return false;
  const frontend::Token& t = feed.tokens[i - 1];
  return t.is(";") || t.is("{") || t.is("}") || t.is(":") || t.is(")") || t.is_identifier("else");
}
// The '*' just before the one at `star`, with nothing between: `y ** 2`.
bool doubled_star(const frontend::Feed& feed, const SourceSpan& star) {
  for (std::size_t i = std::min(feed.pos, feed.tokens.size()); i-- > 1;) {
    if (!(feed.tokens[i].span.begin == star.begin)) continue;
    return feed.tokens[i - 1].is("*") && !feed.tokens[i].space_before && !feed.tokens[i].line_start;
  }
  return false;
}
// The operator just before the '*' at `star` (`3 + * 4`), if one is: an
// operand left out there, not a dereference.
const frontend::Token* operator_before(const frontend::Feed& feed, const SourceSpan& star) {
  static constexpr std::string_view kOperators[] = {"+", "-", "*", "/", "%", "<<", ">>", "<", ">", "<=",
                                                    ">=", "==", "!=", "&", "^", "|", "&&", "||"};
  for (std::size_t i = std::min(feed.pos, feed.tokens.size()); i-- > 1;) {
    if (!(feed.tokens[i].span.begin == star.begin)) continue;
    const frontend::Token& t = feed.tokens[i - 1];
    bool is_operator = std::any_of(std::begin(kOperators), std::end(kOperators), [&](std::string_view op) {
      return t.is(op);
    });
    return is_operator ? &t : nullptr;
  }
  return nullptr;
}
void note_order(Program& p, SymbolKind kind, std::size_t index) {
  p.order.push_back(TopLevelRef{kind, static_cast<std::uint32_t>(index)});
}
// C's `void f();` before the definition (nqc: syntax error). NQC needs none:
// a name may be used above the line that defines it.
void prototype(frontend::Feed& feed, const SourceSpan& semicolon, const char* what, std::string_view name) {
  // `task main();` with the body after it: the ';' is the mistake, and the
  // '{' that follows is no second one. (The parser may have read the token
  // after the ';' already, so the ';' is looked up by its place.)
  std::size_t at = std::min(feed.pos, feed.tokens.size() - 1);
  while (at > 0 && !(feed.tokens[at].is(";") && feed.tokens[at].span.begin == semicolon.begin)) --at;
  if (at + 1 < feed.tokens.size() && feed.tokens[at + 1].is("{")) {
    // Not read past: the body after it is no part of the task.
    feed.diags.error(semicolon, std::string("the ';' ends the ") + what + " '" + std::string(name) +
                                    "' before its body: leave it out");
    feed.after_unreadable = at + 1;
    return;
  }
  feed.diags.error(semicolon, std::string("NQC has no declarations without a body: define the ") + what + " '" +
                                  std::string(name) + "' here with its body, or leave this line out (a " + what +
                                  " may be used above its definition)")
      .parsed_past = true;
}
}  // namespace
}

%token END 0 "end of file"
// Names are views of the token's spelling in Feed::tokens, which outlives
// the parse: a shift moves no string.
%token <std::string_view> IDENT "identifier" MNEMONIC "asm mnemonic"
%token <std::int64_t> NUMBER "number"
%token STRING "string"
%token TASK "task" SUB "sub" VOID "void" INT "int" CONST "const" IF "if" ELSE "else"
%token WHILE "while" DO "do" UNTIL "until" FOR "for" REPEAT "repeat" SWITCH "switch"
%token CASE "case" DEFAULT "default" BREAK "break" CONTINUE "continue" RETURN "return"
%token GOTO "goto" START "start" STOP "stop" ASM "asm" TRUE "true" FALSE "false" INLINE "inline"
%token SOURCE "__source" SOURCE_ARG "__source_arg" ABS "abs" SIGN "sign" NOLIST "__nolist" SENSOR "__sensor"
%token TASKID "__taskid" TYPE "__type"
%token OROR "||" ANDAND "&&" EQ "==" NE "!=" LE "<=" GE ">=" SHL "<<" SHR ">>" INC "++" DEC "--"
%token ADD_ASSIGN "+=" SUB_ASSIGN "-=" MUL_ASSIGN "*=" DIV_ASSIGN "/=" MOD_ASSIGN "%="
%token AND_ASSIGN "&=" OR_ASSIGN "|=" XOR_ASSIGN "^=" SHL_ASSIGN "<<=" SHR_ASSIGN ">>="
%token ABS_ASSIGN "||=" SIGN_ASSIGN "+-="

%right '=' ADD_ASSIGN SUB_ASSIGN MUL_ASSIGN DIV_ASSIGN MOD_ASSIGN AND_ASSIGN OR_ASSIGN XOR_ASSIGN SHL_ASSIGN SHR_ASSIGN ABS_ASSIGN SIGN_ASSIGN
%right '?' ':'
%left OROR
%left ANDAND
%left '|'
%left '^'
%left '&'
%left EQ NE
%left '<' '>' LE GE
%left SHL SHR
%left '+' '-'
%left '*' '/' '%'
%right UNARY INC DEC
%precedence '['
%precedence LOWER_THAN_ELSE
%precedence ELSE

%type <ExprPtr> expr expr_opt
%type <std::vector<ast::Expr>> args args_opt asm_operands
%type <StmtPtr> stmt block for_init
%type <std::vector<ast::Stmt>> stmts
%type <std::unique_ptr<ast::VarDecl>> declarator
%type <std::vector<ast::VarDecl>> declarators
%type <std::unique_ptr<ast::Param>> param
%type <std::vector<ast::Param>> params params_opt
%type <std::vector<ast::AsmItem>> asm_body asm_bytes asm_lines
%type <std::unique_ptr<ast::AsmByte>> asm_byte
%type <std::unique_ptr<ast::AsmInstr>> asm_line

%start program

%%

program
  : %empty
  | program top
  ;

top
  : INT declarators ';'
      {
        for (auto& v : $2) {
          note_order(feed.program, SymbolKind::Global, feed.program.globals.size());
          feed.program.globals.push_back(std::move(v));
        }
      }
  | TASK IDENT '(' ')' block
      {
        note_order(feed.program, SymbolKind::Task, feed.program.tasks.size());
        feed.program.tasks.push_back(Task{std::string($2), @2, std::move(*$5), kNoSymbol});
      }
  | SUB IDENT '(' ')' block
      {
        note_order(feed.program, SymbolKind::Sub, feed.program.subs.size());
        feed.program.subs.push_back(Sub{std::string($2), @2, std::move(*$5), kNoSymbol, {}});
      }
  | INT IDENT '(' params_opt ')' block
      {
        // C's `int main()`: the program's start, which is a task in NQC;
        // kept as one, so that no "no task main" follows.
        if (std::string_view($2) == "main") {
          feed.diags.error(@1, "the RCX starts a program at a task: write 'task main()' for C's 'int main(...)'")
              .parsed_past = true;
          note_order(feed.program, SymbolKind::Task, feed.program.tasks.size());
          feed.program.tasks.push_back(Task{std::string($2), @2, std::move(*$6), kNoSymbol});
        } else {
          // C's `int f()`: no call in NQC returns a value.
          feed.diags.error(@1, "functions return no value in NQC: write 'void " + std::string($2) +
                               "(...)' and pass a result back in a global variable or an 'int &' parameter")
              .parsed_past = true;
          note_order(feed.program, SymbolKind::Function, feed.program.functions.size());
          feed.program.functions.push_back(Function{std::string($2), @2, std::move($4), std::move(*$6), kNoSymbol});
        }
      }
  | CONST INT declarators ';'
      {
        feed.diags.error(@1, kNoConstVariables).parsed_past = true;
        for (auto& v : $3) {
          v.refused_const = true;
          note_order(feed.program, SymbolKind::Global, feed.program.globals.size());
          feed.program.globals.push_back(std::move(v));
        }
      }
  | SUB IDENT '(' params ')' block
      {
        // The firmware's subroutine call carries no values.
        feed.diags.error(@4, "subroutines take no parameters (the RCX's subroutine call carries no values): "
                             "write 'void " + std::string($2) + "(...)' for a function with parameters, or pass values in "
                             "global variables").parsed_past = true;
        // Checked as that function, so its body and calls are still judged.
        note_order(feed.program, SymbolKind::Function, feed.program.functions.size());
        feed.program.functions.push_back(Function{std::string($2), @2, std::move($4), std::move(*$6), kNoSymbol});
      }
  | VOID IDENT '(' params_opt ')' block
      {
        note_order(feed.program, SymbolKind::Function, feed.program.functions.size());
        feed.program.functions.push_back(Function{std::string($2), @2, std::move($4), std::move(*$6), kNoSymbol});
      }
  | INLINE VOID IDENT '(' params_opt ')' block
      {
        note_order(feed.program, SymbolKind::Function, feed.program.functions.size());
        feed.program.functions.push_back(Function{std::string($3), @3, std::move($5), std::move(*$7), kNoSymbol});
      }
  | NOLIST VOID IDENT '(' params_opt ')' block
      {
        // nqc's `__nolist` keeps a function out of its listings; rcxc's
        // listings show code by address, so it changes nothing here.
        note_order(feed.program, SymbolKind::Function, feed.program.functions.size());
        feed.program.functions.push_back(Function{std::string($3), @3, std::move($5), std::move(*$7), kNoSymbol});
      }
  | TASK IDENT '(' ')' ';'                   { prototype(feed, @5, "task", $2); }
  | SUB IDENT '(' ')' ';'                    { prototype(feed, @5, "sub", $2); }
  | VOID IDENT '(' params_opt ')' ';'        { prototype(feed, @6, "function", $2); }
  | INT IDENT '(' params_opt ')' ';'         { prototype(feed, @6, "function", $2); }
  | ';'
  | error ';'
  | error '}'
  ;

declarators
  : declarator                 { $$.push_back(std::move(*$1)); }
  | declarators ',' declarator { $$ = std::move($1); $$.push_back(std::move(*$3)); }
  ;

declarator
  : IDENT           { $$ = std::make_unique<VarDecl>(VarDecl{std::string($1), @1, std::nullopt, kNoSymbol}); }
  | IDENT '=' expr  { $$ = std::make_unique<VarDecl>(VarDecl{std::string($1), @1, OptionalBox<Expr>(std::move($3)), kNoSymbol}); }
  | IDENT '[' expr ']'
      {
        feed.diags.error(@$, "the RCX has no arrays: '" + std::string($1) + "' must be a plain int");
        feed.refused_arrays.emplace_back($1);
        $$ = std::make_unique<VarDecl>(VarDecl{std::string($1), @1, std::nullopt, kNoSymbol});
      }
  | '*' declarator
      {
        // The RCX firmware reads variables by fixed slot numbers only.
        feed.diags.error(@$, "the RCX has no pointers: '" + $2->name + "' must be a plain int").parsed_past = true;
        $$ = std::move($2);
      }
  ;

params_opt
  : %empty  {}
  | VOID    {}
  | params  { $$ = std::move($1); }
  ;

params
  : param             { $$.push_back(std::move(*$1)); }
  | params ',' param  { $$ = std::move($1); $$.push_back(std::move(*$3)); }
  ;

param
  : INT IDENT              { $$ = std::make_unique<Param>(Param{ParamKind::Value, std::string($2), @2, kNoSymbol}); }
  | CONST INT IDENT        { $$ = std::make_unique<Param>(Param{ParamKind::Const, std::string($3), @3, kNoSymbol}); }
  | INT '&' IDENT          { $$ = std::make_unique<Param>(Param{ParamKind::Reference, std::string($3), @3, kNoSymbol}); }
  | CONST INT '&' IDENT    { $$ = std::make_unique<Param>(Param{ParamKind::ConstReference, std::string($4), @4, kNoSymbol}); }
  | SENSOR IDENT           { $$ = std::make_unique<Param>(Param{ParamKind::ConstReference, std::string($2), @2, kNoSymbol, true}); }
  | INT '*' IDENT
      {
        feed.diags.error(@$, "the RCX has no pointers: write 'int &" + std::string($3) + "' to pass a variable by reference").parsed_past = true;
        $$ = std::make_unique<Param>(Param{ParamKind::Reference, std::string($3), @3, kNoSymbol});
      }
  ;

block
  : '{' stmts '}'        { $$ = mks(Block{std::move($2)}, @$); }
  | '{' stmts error '}'  { $$ = mks(Block{std::move($2)}, @$); }
  ;

stmts
  : %empty      {}
  | stmts stmt  { $$ = std::move($1); $$.push_back(std::move(*$2)); }
  ;

stmt
  : block                 { $$ = std::move($1); }
  | INT declarators ';'   { $$ = mks(DeclStmt{std::move($2)}, @$); }
  | CONST INT declarators ';'
      {
        feed.diags.error(@1, kNoConstVariables).parsed_past = true;
        for (auto& v : $3) v.refused_const = true;
        $$ = mks(DeclStmt{std::move($3)}, @$);
      }
  | expr ';'              { $$ = mks(ExprStmt{std::move(*$1)}, @$); }
  | ';'                   { $$ = mks(Empty{}, @$); }
  | IF '(' expr ')' stmt %prec LOWER_THAN_ELSE
                          { $$ = mks(If{std::move(*$3), box(std::move($5)), std::nullopt}, @$); }
  | IF '(' expr ')' stmt ELSE stmt
                          { $$ = mks(If{std::move(*$3), box(std::move($5)), box(std::move($7))}, @$); }
  // A condition that does not parse (`#define LIMIT 40;` then `if (x >
  // LIMIT)`) resumes at its ')', or at the '{' when the ')' is left out, so
  // the body and its else stay this statement's: the `error ';'` below took
  // the ';', left `) {...} else` to end the block early, and the task's last
  // '}' drew a second error. The bodies are parsed as ever, so a syntax
  // mistake of their own is still said.
  | IF '(' error ')' stmt %prec LOWER_THAN_ELSE
                          { $$ = mks(Block{stmts_of(std::move($5))}, @$); }
  | IF '(' error ')' stmt ELSE stmt
                          { $$ = mks(Block{stmts_of(std::move($5), std::move($7))}, @$); }
  | IF '(' error block %prec LOWER_THAN_ELSE
                          { $$ = mks(Block{stmts_of(std::move($4))}, @$); }
  | IF '(' error block ELSE stmt
                          { $$ = mks(Block{stmts_of(std::move($4), std::move($6))}, @$); }
  | WHILE '(' expr ')' stmt
                          { $$ = mks(While{std::move(*$3), box(std::move($5))}, @$); }
  | DO stmt WHILE '(' expr ')' ';'
                          { $$ = mks(DoWhile{box(std::move($2)), std::move(*$5), false}, @$); }
  | DO stmt UNTIL '(' expr ')' ';'
                          { $$ = mks(DoWhile{box(std::move($2)), std::move(*$5), true}, @$); }
  | UNTIL '(' expr ')' stmt
                          { $$ = mks(Until{std::move(*$3), box(std::move($5))}, @$); }
  | FOR '(' for_init ';' expr_opt ';' expr_opt ')' stmt
      {
        std::optional<StmtBox> init;
        if (!std::holds_alternative<Empty>($3->node)) init = box(std::move($3));
        $$ = mks(For{std::move(init), OptionalBox<Expr>(std::move($5)), OptionalBox<Expr>(std::move($7)), box(std::move($9))}, @$);
      }
  | FOR '(' error ')' stmt { $$ = mks(Empty{}, @$); }
  // `for (...; i++ {`: the ')' left out. Without this the recovery above
  // took the ')' of a call in the body, and the body's '}' ended the task.
  | FOR '(' error block    { $$ = mks(Empty{}, @$); }
  | REPEAT '(' expr ')' stmt
                          { $$ = mks(Repeat{std::move(*$3), box(std::move($5))}, @$); }
  | SWITCH '(' expr ')' stmt
                          { $$ = mks(Switch{std::move(*$3), box(std::move($5)), {}}, @$); }
  | CASE expr ':' stmt    { $$ = mks(Case{std::move(*$2), box(std::move($4)), 0}, @$); }
  | DEFAULT ':' stmt      { $$ = mks(Default{box(std::move($3)), 0}, @$); }
  | BREAK ';'             { $$ = mks(Break{}, @$); }
  | CONTINUE ';'          { $$ = mks(Continue{}, @$); }
  | RETURN ';'            { $$ = mks(Return{}, @$); }
  | RETURN expr ';'
      {
        if (!in_int_main_body(feed, @1.begin))
          feed.diags.error(@2, "'return' takes no value in NQC: tasks, subs and functions return nothing (pass a "
                               "result back in a global variable or an 'int &' parameter)").parsed_past = true;
        $$ = mks(Return{}, @$);
      }
  | GOTO IDENT ';'        { $$ = mks(Goto{std::string($2), kNoSymbol}, @$); }
  | IDENT ':' stmt        { $$ = mks(Labeled{std::string($1), @1, box(std::move($3)), kNoSymbol}, @$); }
  | START IDENT ';'       { $$ = mks(StartTask{std::string($2), kNoSymbol}, @$); }
  | STOP IDENT ';'        { $$ = mks(StopTask{std::string($2), kNoSymbol}, @$); }
  | START IDENT '(' ')' ';'
      {
        feed.diags.error(SourceSpan{@3.begin, @4.end}, "'start' takes the task's name alone: write 'start " + std::string($2) + ";'").parsed_past = true;
        $$ = mks(StartTask{std::string($2), kNoSymbol}, @$);
      }
  | STOP IDENT '(' ')' ';'
      {
        feed.diags.error(SourceSpan{@3.begin, @4.end}, "'stop' takes the task's name alone: write 'stop " + std::string($2) + ";'").parsed_past = true;
        $$ = mks(StopTask{std::string($2), kNoSymbol}, @$);
      }
  | ASM '{' asm_body '}'  { $$ = mks(Asm{std::move($3)}, @$); }
  | error ';'             { $$ = mks(Empty{}, @$); }
  ;

for_init
  : %empty                { $$ = mks(Empty{}, @$); }
  | expr                  { $$ = mks(ExprStmt{std::move(*$1)}, @$); }
  | INT declarators       { $$ = mks(DeclStmt{std::move($2)}, @$); }
  ;

expr_opt
  : %empty  {}
  | expr    { $$ = std::move($1); }
  ;

asm_body
  : %empty         {}
  | asm_bytes      { $$ = std::move($1); }
  | asm_bytes ','  { $$ = std::move($1); }
  | asm_lines      { $$ = std::move($1); }
  ;

asm_bytes
  : asm_byte                { $$.push_back(std::move(*$1)); }
  | asm_bytes ',' asm_byte  { $$ = std::move($1); $$.push_back(std::move(*$3)); }
  ;

asm_byte
  : expr      { $$ = std::make_unique<AsmByte>(AsmByte{std::move(*$1), false, @$, std::nullopt}); }
  | '$' expr  { $$ = std::make_unique<AsmByte>(AsmByte{std::move(*$2), true, @$, std::nullopt}); }
  | '$' expr ':' expr {
      std::int64_t literal = 0;
      std::vector<std::pair<bool, ExprPtr>> rest;
      additive_terms(std::move(*$4), false, literal, rest);
      if (!rest.empty())
        feed.diags.error(@4, "the restriction after ':' in an asm byte list must be a number");
      $$ = std::make_unique<AsmByte>(AsmByte{std::move(*$2), true, @$, literal});
    }
  ;

asm_lines
  : asm_line            { $$.push_back(std::move(*$1)); }
  | asm_lines asm_line  { $$ = std::move($1); $$.push_back(std::move(*$2)); }
  ;

asm_line
  : MNEMONIC ';'               { $$ = std::make_unique<AsmInstr>(AsmInstr{std::string($1), @1, {}, std::nullopt, @$}); }
  | MNEMONIC asm_operands ';'  { $$ = std::make_unique<AsmInstr>(AsmInstr{std::string($1), @1, std::move($2), std::nullopt, @$}); }
  ;

asm_operands
  : expr                   { $$.push_back(std::move(*$1)); }
  | asm_operands ',' expr  { $$ = std::move($1); $$.push_back(std::move(*$3)); }
  ;

expr
  : NUMBER                  { $$ = mk(feed, IntLit{$1}, @$); }
  | TRUE                    { $$ = mk(feed, IntLit{1}, @$); }
  | FALSE                   { $$ = mk(feed, IntLit{0}, @$); }
  | IDENT                   { $$ = mk(feed, Name{std::string($1), kNoSymbol}, @$); }
  | IDENT '(' args_opt ')'  { $$ = mk(feed, Call{std::string($1), @1, std::move($3), kNoSymbol}, @$); }
  | SOURCE '(' expr ',' expr ')'
                            { $$ = mk(feed, Source{box(std::move($3)), box(std::move($5)), 0, 0}, @$); }
  | SOURCE_ARG '(' expr ')' { $$ = mk(feed, SourceArg{box(std::move($3)), std::nullopt, false}, @$); }
  | SOURCE_ARG '(' expr ',' expr ')'
      {
        // The required type must be a literal-like constant; sema folds it.
        std::optional<std::int16_t> type;
        if (const auto* lit = std::get_if<IntLit>(&$5->node)) type = static_cast<std::int16_t>(lit->value);
        else feed.diags.error(@5, "the type in __source_arg(E, TYPE) must be a number");
        $$ = mk(feed, SourceArg{box(std::move($3)), type, false}, @$);
      }
  | '(' expr ')'            { $$ = std::move($2); $$->span = @$; }
  | TASKID                  { $$ = mk(feed, TaskId{}, @$); }
  | TYPE '(' expr ')'       { $$ = mk(feed, TypeOf{box(std::move($3))}, @$); }
  | ABS '(' expr ')'        { $$ = un(feed, UnaryOp::Abs, std::move($3), @$); }
  | SIGN '(' expr ')'       { $$ = un(feed, UnaryOp::Sign, std::move($3), @$); }
  | '@' expr %prec UNARY    { $$ = encoded_source(feed, std::move(*$2), @$); }
  | SENSOR '(' expr ')'
      {
        // nqc's __sensor(E): a constant's low byte (a sensor number), or
        // the number of the sensor E reads (SENSOR_2 gives 1); anything
        // else is an error.
        $$ = mk(feed, SourceArg{box(std::move($3)), static_cast<std::int16_t>(9), true}, @$);
      }
  | expr '[' expr ']'
      {
        const auto* n = ast::as<ast::Name>(*$1);
        bool refused = n && std::find(feed.refused_arrays.begin(), feed.refused_arrays.end(), n->name) !=
                                feed.refused_arrays.end();
        if (!refused) feed.diags.error(@$, "the RCX has no arrays, so nothing can be indexed");
        $$ = std::move($1);
      }
  | '*' expr %prec UNARY
      {
        // `y ** 2` reads as `y * (*2)`: a power, as Python and Basic write it.
        // After another operator (`3 + * 4`) an operand was left out.
        std::string message = "the RCX has no pointers, so nothing can be dereferenced";
        if (doubled_star(feed, @1))
          message = "NQC has no power operator '**': multiply instead ('y * y' for y squared)";
        else if (const auto* op = operator_before(feed, @1))
          message = "expected an expression after '" + std::string(op->text) + "' before '*': two operators stand "
                    "side by side";
        feed.diags.error(@$, message).parsed_past = true;
        $$ = std::move($2);
      }
  | '&' expr %prec UNARY
      {
        feed.diags.error(@$, "the RCX has no pointers, so no address can be taken").parsed_past = true;
        $$ = std::move($2);
      }
  | '-' expr %prec UNARY    { $$ = un(feed, UnaryOp::Negate, std::move($2), @$); }
  | '+' expr %prec UNARY    { $$ = un(feed, UnaryOp::Plus, std::move($2), @$); }
  | '~' expr %prec UNARY    { $$ = un(feed, UnaryOp::BitNot, std::move($2), @$); }
  | '!' expr %prec UNARY    { $$ = un(feed, UnaryOp::LogNot, std::move($2), @$); }
  | INC expr %prec UNARY    { $$ = un(feed, UnaryOp::PreInc, std::move($2), @$); }
  | DEC expr %prec UNARY    { $$ = un(feed, UnaryOp::PreDec, std::move($2), @$); }
  | expr INC                { $$ = un(feed, UnaryOp::PostInc, std::move($1), @$); }
  | expr DEC                { $$ = un(feed, UnaryOp::PostDec, std::move($1), @$); }
  | expr '*' expr           { $$ = bin(feed, BinaryOp::Mul, std::move($1), std::move($3), @$); }
  | expr '/' expr           { $$ = bin(feed, BinaryOp::Div, std::move($1), std::move($3), @$); }
  | expr '%' expr           { $$ = bin(feed, BinaryOp::Mod, std::move($1), std::move($3), @$); }
  | expr '+' expr           { $$ = bin(feed, BinaryOp::Add, std::move($1), std::move($3), @$); }
  | expr '-' expr           { $$ = bin(feed, BinaryOp::Sub, std::move($1), std::move($3), @$); }
  | expr SHL expr           { $$ = bin(feed, BinaryOp::Shl, std::move($1), std::move($3), @$); }
  | expr SHR expr           { $$ = bin(feed, BinaryOp::Shr, std::move($1), std::move($3), @$); }
  | expr '<' expr           { $$ = bin(feed, BinaryOp::Lt, std::move($1), std::move($3), @$); }
  | expr LE expr            { $$ = bin(feed, BinaryOp::Le, std::move($1), std::move($3), @$); }
  | expr '>' expr           { $$ = bin(feed, BinaryOp::Gt, std::move($1), std::move($3), @$); }
  | expr GE expr            { $$ = bin(feed, BinaryOp::Ge, std::move($1), std::move($3), @$); }
  | expr EQ expr            { $$ = bin(feed, BinaryOp::Eq, std::move($1), std::move($3), @$); }
  | expr NE expr            { $$ = bin(feed, BinaryOp::Ne, std::move($1), std::move($3), @$); }
  | expr '&' expr           { $$ = bin(feed, BinaryOp::BitAnd, std::move($1), std::move($3), @$); }
  | expr '^' expr           { $$ = bin(feed, BinaryOp::BitXor, std::move($1), std::move($3), @$); }
  | expr '|' expr           { $$ = bin(feed, BinaryOp::BitOr, std::move($1), std::move($3), @$); }
  | expr ANDAND expr        { $$ = bin(feed, BinaryOp::LogAnd, std::move($1), std::move($3), @$); }
  | expr OROR expr          { $$ = bin(feed, BinaryOp::LogOr, std::move($1), std::move($3), @$); }
  | expr '?' expr ':' expr  { $$ = mk(feed, Conditional{box(std::move($1)), box(std::move($3)), box(std::move($5))}, @$); }
  | expr '=' expr           { $$ = asg(feed, AssignOp::Assign, std::move($1), std::move($3), @$, @2); }
  | expr ADD_ASSIGN expr    { $$ = asg(feed, AssignOp::Add, std::move($1), std::move($3), @$, @2); }
  | expr SUB_ASSIGN expr    { $$ = asg(feed, AssignOp::Sub, std::move($1), std::move($3), @$, @2); }
  | expr MUL_ASSIGN expr    { $$ = asg(feed, AssignOp::Mul, std::move($1), std::move($3), @$, @2); }
  | expr DIV_ASSIGN expr    { $$ = asg(feed, AssignOp::Div, std::move($1), std::move($3), @$, @2); }
  | expr MOD_ASSIGN expr    { $$ = asg(feed, AssignOp::Mod, std::move($1), std::move($3), @$, @2); }
  | expr AND_ASSIGN expr    { $$ = asg(feed, AssignOp::BitAnd, std::move($1), std::move($3), @$, @2); }
  | expr OR_ASSIGN expr     { $$ = asg(feed, AssignOp::BitOr, std::move($1), std::move($3), @$, @2); }
  | expr XOR_ASSIGN expr    { $$ = asg(feed, AssignOp::BitXor, std::move($1), std::move($3), @$, @2); }
  | expr SHL_ASSIGN expr    { $$ = asg(feed, AssignOp::Shl, std::move($1), std::move($3), @$, @2); }
  | expr SHR_ASSIGN expr    { $$ = asg(feed, AssignOp::Shr, std::move($1), std::move($3), @$, @2); }
  | expr ABS_ASSIGN expr    { $$ = asg(feed, AssignOp::Abs, std::move($1), std::move($3), @$, @2); }
  | expr SIGN_ASSIGN expr   { $$ = asg(feed, AssignOp::Sign, std::move($1), std::move($3), @$, @2); }
  ;

args_opt
  : %empty  {}
  | args    { $$ = std::move($1); }
  ;

args
  : expr           { $$.push_back(std::move(*$1)); }
  | args ',' expr  { $$ = std::move($1); $$.push_back(std::move(*$3)); }
  ;

%%

namespace rcxc::frontend {

void yy::Parser::error(const location_type& loc, const std::string& msg) {
  if (!feed.too_deep) feed.diags.error(loc, msg);
}

namespace {

std::string lower_case(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

// A keyword written with capitals where the parse failed: `Task main()` (the
// token found), `Int x` (the one before it), `While (x < 3) x++` (the one
// before the parenthesis the token found follows); each only where a
// statement or declaration starts, so that `y = Stop x` names no keyword.
const Token* miscased_keyword(const Feed& feed, bool between_declarations) {
  static constexpr std::string_view kKeywords[] = {"task", "sub", "void", "int", "const", "if", "else", "while",
                                                   "do", "until", "for", "repeat", "switch", "case", "default",
                                                   "break", "continue", "return", "goto", "start", "stop", "asm"};
  // Before a parenthesis only the keywords with a parenthesised head count:
  // `Stop()` there is more likely a sub of the program's own.
  static constexpr std::string_view kHeadKeywords[] = {"if", "while", "for", "repeat", "switch", "until"};
  auto miscased = [&](std::size_t i, bool before_parenthesis = false) -> const Token* {
    const Token& t = feed.tokens[i];
    if (t.kind != TokenKind::Identifier) return nullptr;
    std::string lower = lower_case(t.text);
    bool keyword = lower != t.text && (before_parenthesis ? std::find(std::begin(kHeadKeywords), std::end(kHeadKeywords), lower) != std::end(kHeadKeywords)
                                                          : std::find(std::begin(kKeywords), std::end(kKeywords), lower) != std::end(kKeywords));
    bool starts = i == 0 || feed.tokens[i - 1].is(";") || feed.tokens[i - 1].is("{") || feed.tokens[i - 1].is("}") ||
                  feed.tokens[i - 1].is(":") || feed.tokens[i - 1].is(")");
    return keyword && starts ? &t : nullptr;
  };
  if (feed.pos < 1) return nullptr;
  std::size_t found = feed.pos - 1;
  // In a body a name is always welcome where a statement starts, so the
  // token found is a keyword only between declarations.
  if (between_declarations) return miscased(found);
  if (found < 1) return nullptr;
  if (const Token* t = miscased(found - 1)) return t;
  if (!feed.tokens[found - 1].is(")")) return nullptr;
  int depth = 0;
  for (std::size_t i = found - 1; i > 0; --i) {
    if (feed.tokens[i].is(")")) ++depth;
    if (feed.tokens[i].is("(") && --depth == 0) return miscased(i - 1, true);
  }
  return nullptr;
}

// Whether no '(' is open before the ')' at `close` in its statement: back to
// the ';' or brace at the statement's level (a for head's ';' is inside
// its parentheses).
bool unmatched_close(const Feed& feed, std::size_t close) {
  int depth = 0;
  for (std::size_t i = close; i-- > 0;) {
    const Token& t = feed.tokens[i];
    if (t.is(")")) ++depth;
    if (t.is("(") && --depth < 0) return false;
    if (depth == 0 && (t.is(";") || t.is("{") || t.is("}"))) return true;
  }
  return true;
}

// The `if` whose '{' is still open where an `else` stands at `pos`, in
// the same column as that `if` (or nullptr): `if (c) { a; else { b; }`,
// its '}' left out, reads as an else inside the if's own braces. A long
// program's missing '}' shows there (faithfulness round 17), and the
// message for an else after a ';' would send the reader to look for one.
const Token* if_left_open_before_else(const Feed& feed, std::size_t pos) {
  if (pos >= feed.tokens.size() || !feed.tokens[pos].line_start) return nullptr;
  int depth = 0;
  for (std::size_t i = pos; i-- > 0;) {
    const Token& t = feed.tokens[i];
    if (t.is("}")) ++depth;
    if (!t.is("{") || depth-- > 0) continue;
    // The innermost open '{': the body of an `if (...)`?
    if (i == 0 || !feed.tokens[i - 1].is(")")) return nullptr;
    int parens = 0;
    for (std::size_t j = i; j-- > 0;) {
      if (feed.tokens[j].is(")")) ++parens;
      if (feed.tokens[j].is("(") && --parens == 0) {
        if (j == 0 || !feed.tokens[j - 1].is_identifier("if")) return nullptr;
        const Token& word = feed.tokens[j - 1];
        bool same_column = word.span.begin.file == feed.tokens[pos].span.begin.file &&
                           word.span.begin.expansion == 0 && feed.tokens[pos].span.begin.expansion == 0 &&
                           word.span.begin.column == feed.tokens[pos].span.begin.column;
        return same_column ? &word : nullptr;
      }
    }
    return nullptr;
  }
  return nullptr;
}

// Other languages' `elsif (c)`, `elseif (c)`, `elif (c)` ending at the
// ')' at `close` and starting a statement: the parse fails after it (it
// reads as a call with no ';'), and what was meant is `else if (c)`.
const Token* else_if_word_before(const Feed& feed, std::size_t close) {
  if (close >= feed.tokens.size() || !feed.tokens[close].is(")")) return nullptr;
  int depth = 0;
  for (std::size_t i = close + 1; i-- > 0;) {
    if (feed.tokens[i].is(")")) ++depth;
    if (feed.tokens[i].is("(") && --depth == 0) {
      if (i == 0) return nullptr;
      const Token& word = feed.tokens[i - 1];
      bool is = word.is_identifier("elsif") || word.is_identifier("elseif") || word.is_identifier("elif");
      bool starts = i < 2 || feed.tokens[i - 2].is(";") || feed.tokens[i - 2].is("}") || feed.tokens[i - 2].is("{") ||
                    feed.tokens[i - 2].is(")");
      return is && starts ? &word : nullptr;
    }
  }
  return nullptr;
}

// Whether a new name follows `t` in a declaration.
bool declares_next(const Token& t) {
  return t.is_identifier("int") || t.is_identifier("void") || t.is_identifier("sub") || t.is_identifier("task") ||
         t.is(",") || t.is("&");
}

}  // namespace

// `#define BACK OnRev(OUT_A); Wait(20)` then `if (c) BACK; else ...`: the
// macro's own ';' ended the if's statement, so its second statement and the
// user's ';' stand before the `else`; with `#define TURN { ... }` the ';'
// written after TURN is that statement. The error is at the `else`, where
// the macro is not to be seen: a note points into it (faithfulness round
// 16's pp07, pp08). `feed.pos - 1` is the `else`.
static std::optional<Note> macro_that_ended_the_if(const Feed& feed) {
  if (feed.pos < 3 || !feed.tokens[feed.pos - 2].is(";") || feed.tokens[feed.pos - 2].span.begin.expansion != 0)
    return std::nullopt;
  const Token& last = feed.tokens[feed.pos - 3];
  if (last.span.begin.expansion == 0) return std::nullopt;
  if (last.is("}"))
    return Note{last.span, "the macro's text is a block, so the ';' written after it is a statement of its "
                           "own: leave that ';' out, or define the macro as 'do { ... } while (false)'"};
  int depth = 0;
  for (std::size_t j = feed.pos - 3; j > 0 && feed.tokens[j].span.begin.expansion != 0; --j) {
    const Token& t = feed.tokens[j];
    if (t.is(")") || t.is("}")) ++depth;
    if (t.is("(") || t.is("{")) --depth;
    if (depth == 0 && t.is(";"))
      return Note{t.span, "this ';' in the macro's text ends the 'if' statement, and what follows it does "
                          "not belong to the 'if': put braces around the macro's text, or define it as "
                          "'do { ... } while (false)'"};
  }
  return std::nullopt;
}

// gcc-like messages: "expected ';' before 'x'", naming what the grammar
// wanted when that is short, or the most useful single expectation.
void yy::Parser::report_syntax_error(const context& ctx) const {
  // The parse was cut where it nested too deeply; that is the error.
  if (feed.too_deep) return;
  std::size_t found_at = ctx.token() == symbol_kind::S_YYEOF ? feed.pos : feed.pos - 1;
  if (feed.pos > 0 && (found_at == feed.after_unreadable || found_at == feed.invalid_number)) return;
  if (!feed.macro_errors.empty() && found_at < feed.tokens.size()) {
    // The statement around the token found, a few dozen tokens each way at most.
    auto ends = [&](const Token& t) { return t.is(";") || t.is("{") || t.is("}"); };
    auto reported = [&](const Token& t) {
      return std::find(feed.macro_errors.begin(), feed.macro_errors.end(), t.span.begin) != feed.macro_errors.end();
    };
    constexpr std::size_t kReach = 64;
    bool same_mistake = reported(feed.tokens[found_at]);
    for (std::size_t i = found_at; !same_mistake && i-- > 0 && found_at - i <= kReach && !ends(feed.tokens[i]);)
      same_mistake = reported(feed.tokens[i]);
    for (std::size_t i = found_at + 1; !same_mistake && i < feed.tokens.size() && i - found_at <= kReach &&
                                       !ends(feed.tokens[i]) && feed.tokens[i].kind != TokenKind::End;
         ++i)
      same_mistake = reported(feed.tokens[i]);
    if (same_mistake) return;
  }
  std::string found = ctx.token() == symbol_kind::S_YYEOF ? "end of file" : "'" + std::string(feed.last_text) + "'";
  // `Wa\` at the end of a line and `it(10);` on the next: C splices the
  // lines before it reads words and gets `Wait`; rcxc, like nqc, reads the
  // backslash-newline as a space, so the parse fails at the second half.
  if (found_at > 0 && found_at < feed.tokens.size() && feed.tokens[found_at].splits_word) {
    std::string first(feed.tokens[found_at - 1].text), second(feed.tokens[found_at].text);
    feed.diags.error(ctx.location(), "a backslash at the end of the line splits '" + first + second + "' in two: '" +
                                         first + "' and '" + second + "' are two words, because a backslash joins "
                                         "lines, not words (C would join them); write '" + first + second +
                                         "' on one line");
    return;
  }
  symbol_kind_type expected[64];
  int n = ctx.expected_tokens(expected, 64);
  auto expects = [&](symbol_kind_type k) { return std::find(expected, expected + n, k) != expected + n; };
  auto expects_punct = [&](std::string_view p) {
    return std::any_of(expected, expected + n, [&](symbol_kind_type k) { return symbol_name(k) == p; });
  };
  auto shown = [&](symbol_kind_type k) {
    std::string name = symbol_name(k);
    // Punctuation arrives as 'x' or "xx"; show both as 'x'.
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = "'" + name.substr(1, name.size() - 2) + "'";
    return name;
  };
  // C's other types (`float x`, `unsigned int x`): said at the type rather
  // than "expected ';' before 'x'". Between declarations the type is the
  // token found; in a body, the token before the name found.
  static constexpr std::string_view kCTypes[] = {"float", "double", "char", "short", "long", "unsigned", "signed",
                                                 "bool", "boolean", "byte", "string", "uint8_t", "int16_t"};
  // Only where a declaration can start: `y = byte x` is about a variable.
  auto c_type = [&](std::size_t back) -> const Token* {
    if (feed.pos < back) return nullptr;
    std::size_t i = feed.pos - back;
    const Token& t = feed.tokens[i];
    bool is = t.kind == TokenKind::Identifier &&
              std::find(std::begin(kCTypes), std::end(kCTypes), t.text) != std::end(kCTypes);
    bool starts = i == 0 || feed.tokens[i - 1].is(";") || feed.tokens[i - 1].is("{") ||
                  feed.tokens[i - 1].is("}") || feed.tokens[i - 1].is(")") || feed.tokens[i - 1].is(":") ||
                  feed.tokens[i - 1].is("(");
    return is && starts ? &t : nullptr;
  };
  // A C cast, `(int)x` or `(float)x`: the parse fails at the type after the
  // '(' (a keyword there is no expression) or, for a name the grammar took
  // as a value, at what follows the ')'. nqc: syntax error.
  auto type_word = [&](const Token& t) {
    return t.is_identifier("int") || t.is_identifier("const") ||
           (t.kind == TokenKind::Identifier &&
            std::find(std::begin(kCTypes), std::end(kCTypes), t.text) != std::end(kCTypes));
  };
  auto cast_at = [&](std::size_t open) -> std::optional<SourceSpan> {
    if (!feed.tokens[open].is("(")) return std::nullopt;
    std::size_t i = open + 1;
    while (i < feed.tokens.size() && type_word(feed.tokens[i])) ++i;
    if (i == open + 1 || i >= feed.tokens.size() || !feed.tokens[i].is(")")) return std::nullopt;
    return SourceSpan{feed.tokens[open].span.begin, feed.tokens[i].span.end};
  };
  // The cast's '(' is before the type words that end at `last`.
  auto cast_ending = [&](std::size_t last) -> std::optional<SourceSpan> {
    std::size_t open = last;
    while (open > 0 && type_word(feed.tokens[open])) --open;
    return cast_at(open);
  };
  std::optional<SourceSpan> cast;
  if (feed.pos >= 2 && type_word(feed.tokens[feed.pos - 1])) cast = cast_ending(feed.pos - 1);
  if (!cast && feed.pos >= 4 && feed.tokens[feed.pos - 2].is(")") && type_word(feed.tokens[feed.pos - 3]))
    cast = cast_ending(feed.pos - 3);
  if (cast) {
    feed.diags.error(*cast, "NQC has no casts: every value is an int already, a 16-bit whole number (-32768 to "
                            "32767), so the cast can go");
    return;
  }
  // `void f(int v[])` or `int a[];`: an array without a size, which the
  // declarator's own rule (`int a[4]`) does not take (nqc: syntax error).
  bool bracket_found = feed.last_text == "[" && feed.pos >= 2;
  bool empty_brackets = feed.last_text == "]" && feed.pos >= 3 && feed.tokens[feed.pos - 2].is("[");
  if (bracket_found || empty_brackets) {
    std::size_t at = feed.pos - (bracket_found ? 2 : 3);
    const Token& name = feed.tokens[at];
    const Token* before = at > 0 ? &feed.tokens[at - 1] : nullptr;
    bool declared = before && (before->is_identifier("int") || before->is("&") || before->is(","));
    if (name.kind == TokenKind::Identifier && declared) {
      feed.diags.error(ctx.location(), "the RCX has no arrays: '" + std::string(name.text) + "' must be a plain int");
      return;
    }
  }
  // `int repeat;`, `task while()`: a keyword where a new name goes (the
  // lexer gives keywords as identifiers; the parser took this one as a
  // keyword). Said as such, rather than "expected identifier or '*'".
  if (feed.pos >= 2 && expects(symbol_kind::S_IDENT) && ctx.token() != symbol_kind::S_IDENT &&
      feed.tokens[feed.pos - 1].kind == TokenKind::Identifier && declares_next(feed.tokens[feed.pos - 2]) &&
      feed.last_text != "const" && feed.last_text != "int" && feed.last_text != "void") {
    feed.diags.error(ctx.location(), "'" + std::string(feed.last_text) + "' is a keyword of NQC and cannot be a "
                                     "name: choose another");
    return;
  }
  // `int &flag = 1;` in a body or at the top: a reference where only a
  // parameter may be one. Said as such, rather than "expected identifier or '*'".
  if (feed.pos >= 2 && expects(symbol_kind::S_IDENT) && feed.tokens[feed.pos - 1].is("&") &&
      feed.tokens[feed.pos - 2].is_identifier("int")) {
    feed.diags.error(ctx.location(),
                     "a '&' reference can only be a parameter (void f(int &x)): a variable is a plain int");
    return;
  }
  const Token* type = nullptr;
  if (ctx.token() == symbol_kind::S_IDENT && expects(symbol_kind::S_TASK)) type = c_type(1);
  if (!type && (ctx.token() == symbol_kind::S_IDENT || ctx.token() == symbol_kind::S_INT)) type = c_type(2);
  if (type) {
    feed.diags.error(type->span, "'" + std::string(type->text) +
                                     "' is not a type in NQC: every variable is an int, a 16-bit whole number "
                                     "(-32768 to 32767)");
    return;
  }
  if (const Token* k = miscased_keyword(feed, expects(symbol_kind::S_TASK))) {
    feed.diags.error(k->span, "'" + std::string(k->text) + "' is not a keyword: NQC's keywords are lower case (did you mean '" +
                                  lower_case(k->text) + "'?)");
    return;
  }
  // `int OUT_A = 3;` or `void Random(int n)`: a name that is a macro was
  // expanded where a new name is declared. The note names the macro.
  auto declares = [&](const Token& t) {
    return t.is_identifier("int") || t.is_identifier("void") || t.is_identifier("sub") || t.is_identifier("task") ||
           t.is(",") || t.is("&");
  };
  if (feed.pos >= 2 && expects(symbol_kind::S_IDENT) && !expects(symbol_kind::S_NUMBER) &&
      feed.tokens[feed.pos - 1].span.begin.expansion != 0 && declares(feed.tokens[feed.pos - 2])) {
    feed.diags.error(ctx.location(), "expected a new name, but a macro stands here and expands to '" +
                                         std::string(feed.last_text) + "': a macro's name cannot be declared again");
    return;
  }
  // `end: }` and `case 1: }`: C and nqc want a statement after a label.
  auto ends_a_label = [&](std::size_t colon) {
    std::size_t first = colon;
    while (first > 0 && !feed.tokens[first - 1].is(";") && !feed.tokens[first - 1].is("{") &&
           !feed.tokens[first - 1].is("}") && !feed.tokens[first - 1].is(":"))
      --first;
    const Token& t = feed.tokens[first];
    return t.is_identifier("case") || t.is_identifier("default") ||
           (first + 1 == colon && t.kind == TokenKind::Identifier);
  };
  if (feed.pos >= 2 && feed.tokens[feed.pos - 1].is("}") && feed.tokens[feed.pos - 2].is(":") &&
      ends_a_label(feed.pos - 2)) {
    feed.diags.error(ctx.location(), "a label needs a statement after it: at the end of a block, add an empty "
                                     "one (';')");
    return;
  }
  // `task main(void)`, C's habit, or `task t(int x)`: syntax errors in nqc
  // too. (`sub s(int x)` has a rule of its own, which names functions.)
  if (feed.pos >= 4 && feed.tokens[feed.pos - 2].is("(") && !feed.tokens[feed.pos - 1].is(")") &&
      (feed.tokens[feed.pos - 4].is_identifier("task") || feed.tokens[feed.pos - 4].is_identifier("sub"))) {
    std::string kind(feed.tokens[feed.pos - 4].text), name(feed.tokens[feed.pos - 3].text);
    bool c_void = feed.tokens[feed.pos - 1].is_identifier("void");
    feed.diags.error(ctx.location(), "a " + kind + " takes no parameters: write '" + kind + " " + name + "()'" +
                                         (c_void ? "" : ", and share values through global variables"));
    return;
  }
  // `for (i = 0, j = 0; ...)`: C's comma operator, which NQC lacks (nqc:
  // syntax error). Said in a for loop's header, where C programs use it.
  if (feed.last_text == "," && in_for_header(feed)) {
    feed.diags.error(ctx.location(), "NQC has no comma operator: set the other variables before the for loop, or "
                                     "in its body");
    return;
  }
  // C and C++ habits in an inline function's parameters (nqc: syntax error).
  if (feed.pos >= 2 && in_parameter_list(feed)) {
    const Token& found_token = feed.tokens[feed.pos - 1];
    const Token& prev = feed.tokens[feed.pos - 2];
    std::string message;
    bool c_type_name = std::find(std::begin(kCTypes), std::end(kCTypes), found_token.text) != std::end(kCTypes);
    if (found_token.kind == TokenKind::Identifier && c_type_name)
      message = "'" + std::string(found_token.text) + "' is not a type in NQC: every parameter is an int (write "
                "'int', 'int &', 'const int' or 'const int &')";
    else if (found_token.kind == TokenKind::Identifier && (prev.is("(") || prev.is(",")))
      message = "a parameter needs its kind: write 'int " + std::string(found_token.text) + "' (or 'int &" +
                std::string(found_token.text) + "', 'const int " + std::string(found_token.text) + "', 'const int &" +
                std::string(found_token.text) + "')";
    else if (found_token.is("="))
      message = "a parameter has no default value in NQC: every call gives every argument";
    else if (found_token.is_identifier("const") && prev.is_identifier("int"))
      message = "'const' goes before 'int' in NQC: write 'const int' (or 'const int &')";
    if (!message.empty()) {
      feed.diags.error(ctx.location(), message);
      return;
    }
  }
  // `Wait 100;` or `Off OUT_A;`: a call written without its parentheses
  // (nqc: "undefined variable 'Wait'"). Only before a number, where no name
  // could be a misspelt type (`itn x;`).
  static constexpr std::string_view kStatementKeywords[] = {"start", "stop", "goto", "return", "case", "int",
                                                             "const", "else", "do", "asm", "void", "inline"};
  auto keyword = [&](const Token& t) {
    return std::find(std::begin(kStatementKeywords), std::end(kStatementKeywords), t.text) !=
           std::end(kStatementKeywords);
  };
  if (feed.pos >= 3 && ctx.token() == symbol_kind::S_NUMBER &&
      feed.tokens[feed.pos - 2].kind == TokenKind::Identifier && !keyword(feed.tokens[feed.pos - 2]) &&
      starts_statement(feed, feed.pos - 2)) {
    const Token& callee = feed.tokens[feed.pos - 2];
    const Token& value = feed.tokens[feed.pos - 1];
    // `__res 3 { ... }` is nqc's resource block of the Spybot, no call.
    if (const char* why = reserved_by_nqc(callee.text)) {
      feed.diags.error(callee.span, "'" + std::string(callee.text) + "' is reserved by nqc (" + why +
                                        "); the RCX has no use for it");
      return;
    }
    std::string argument = value.span.begin.expansion != 0 ? "..." : std::string(value.text);
    // `repeat 3 { ... }`, `while 1 ...`: a statement's head, no call.
    if (callee.is_identifier("repeat") || callee.is_identifier("while") || callee.is_identifier("if") ||
        callee.is_identifier("until") || callee.is_identifier("switch")) {
      std::string what = callee.is_identifier("repeat") ? "its count" : callee.is_identifier("switch") ? "its value"
                                                                                                      : "its condition";
      feed.diags.error(ctx.location(), "'" + std::string(callee.text) + "' needs " + what + " in parentheses: write '" +
                                           std::string(callee.text) + " (" + argument + ")'");
      return;
    }
    feed.diags.error(ctx.location(), "a call needs parentheses around its arguments: write '" +
                                         std::string(callee.text) + "(" + argument + ")'");
    return;
  }
  // Comparisons as Basic and Pascal write them: `<>`, `=<`, `=>`; and C's
  // `p->field` (read as `p - > field`).
  if (feed.pos >= 3 && (feed.last_text == ">" || feed.last_text == "<")) {
    const Token& first = feed.tokens[feed.pos - 2];
    const Token& second = feed.tokens[feed.pos - 1];
    bool adjacent = !second.space_before && !second.line_start;
    std::string written = std::string(first.text) + std::string(second.text), meant;
    if (written == "<>") meant = "'not equal' is written '!='";
    if (written == "=<") meant = "'less than or equal' is written '<='";
    if (written == "=>") meant = "'greater than or equal' is written '>='";
    if (written == "->") meant = "the RCX has no structs or pointers, so there is no member to reach";
    if (adjacent && !meant.empty()) {
      feed.diags.error({first.span.begin, second.span.end}, "'" + written + "' is not an operator in NQC: " + meant);
      return;
    }
  }
  // `x = c ? 1;` or `x = c ? 1 2;`: the '?' without its ':' (nqc: syntax
  // error).
  if (expects_punct("':'") && ctx.token() != symbol_kind::S_YYEOF && feed.pos >= 2) {
    bool question = false;
    std::size_t i = feed.pos - 1;
    while (i > 0 && !feed.tokens[i - 1].is(";") && !feed.tokens[i - 1].is("{") && !feed.tokens[i - 1].is("}")) {
      --i;
      question = question || feed.tokens[i].is("?");
    }
    if (question && !feed.tokens[i].is_identifier("case")) {
      feed.diags.error(ctx.location(), "expected ':' before '" + std::string(feed.last_text) +
                                           "': a '?' needs ':' and the value for when the condition is false "
                                           "('c ? a : b')");
      return;
    }
    // `case 1 x = 2;`: the label's ':' left out (said "syntax error at 'x'").
    if (!question && feed.tokens[i].is_identifier("case") && ctx.token() != symbol_kind::S_YYEOF &&
        feed.last_text != ",") {  // `case 1, 2:` has a message of its own below
      feed.diags.error(ctx.location(), "expected ':' before '" + std::string(feed.last_text) +
                                           "': a case label ends with ':' ('case 1: ...')");
      return;
    }
  }
  // `stop;` and `start;` without a task (nqc: syntax error).
  if (feed.pos >= 2 && (feed.tokens[feed.pos - 2].is_identifier("stop") ||
                        feed.tokens[feed.pos - 2].is_identifier("start")) &&
      !expects(symbol_kind::S_TASK) && ctx.token() != symbol_kind::S_IDENT) {
    std::string verb(feed.tokens[feed.pos - 2].text);
    feed.diags.error(ctx.location(), "'" + verb + "' needs the name of a task: write '" + verb + " NAME;'" +
                                         (verb == "stop" ? " (StopAllTasks() stops every task)" : ""));
    return;
  }
  // `case 1, 2:`, as Pascal and Basic write it (C and nqc: syntax error).
  if (feed.last_text == "," && feed.pos >= 2) {
    std::size_t i = feed.pos - 1;
    while (i > 0 && !feed.tokens[i - 1].is(":") && !feed.tokens[i - 1].is(";") && !feed.tokens[i - 1].is("{") &&
           !feed.tokens[i - 1].is("}"))
      --i;
    if (feed.tokens[i].is_identifier("case")) {
      feed.diags.error(ctx.location(), "a case label takes one value: give each value a label of its own, as in "
                                       "'case 1: case 2:'");
      return;
    }
  }
  // `x = 1, y = 2;` or `x = (y = 3, 4);`: C's comma operator elsewhere
  // (nqc: syntax error).
  if (feed.last_text == "," && (expects_punct("';'") || expects_punct("')'")) && comma_operator(feed)) {
    feed.diags.error(ctx.location(), "NQC has no comma operator: make each part a statement of its own, ending "
                                     "with ';'");
    return;
  }
  // `x = 1--1`: the lexer reads `--` as one token, as C does, so this is
  // `1--` followed by `1`. On a constant the decrement is the mistake (nqc:
  // "not a legal target for assignment"; gcc: "lvalue required"); after a
  // variable the value that follows is. Either way say how `--` was read.
  // Only where the value follows the sign directly: `x--` with a name on
  // the next line is a missing ';'.
  if (feed.pos >= 3 && (feed.tokens[feed.pos - 2].is("--") || feed.tokens[feed.pos - 2].is("++")) &&
      (ctx.token() == symbol_kind::S_NUMBER || ctx.token() == symbol_kind::S_IDENT) &&
      !feed.tokens[feed.pos - 1].space_before && !feed.tokens[feed.pos - 1].line_start) {
    const Token& op = feed.tokens[feed.pos - 2];
    const Token& before = feed.tokens[feed.pos - 3];
    std::string ops(op.text), sign(1, op.text[0]), value(feed.last_text);
    std::string verb = sign == "-" ? "decrement" : "increment";
    std::string spaced = std::string(sign == "-" ? "for a minus sign" : "for a plus sign") + ", put a space: '";
    if (before.kind == TokenKind::Number || before.kind == TokenKind::Char) {
      std::string b(before.text);
      feed.diags.error({before.span.begin, op.span.end},
                       "cannot " + verb + " '" + b + "': it is a constant, not a variable ('" + b + ops + value +
                           "' reads as '" + b + ops + " " + value + "'; " + spaced + b + " " + sign + " " + sign +
                           value + "')");
    } else {
      feed.diags.error(ctx.location(), "expected ';' before '" + value + "': '" + ops + "' here " + verb +
                                           "s what comes before it (" + spaced + sign + " " + sign + value + "')");
    }
    return;
  }
  // `__nolist task t()`: nqc takes it before an inline function only.
  if (feed.pos >= 2 && feed.tokens[feed.pos - 2].is_identifier("__nolist") && !expects(symbol_kind::S_TASK)) {
    feed.diags.error(ctx.location(), "'__nolist' goes before 'void' only: it keeps an inline function out of "
                                     "nqc's listings");
    return;
  }
  // `goto 5;`: BASIC's line numbers; `goto;`: the label left out (nqc:
  // syntax error, and rcxc said "expected identifier").
  if (feed.pos >= 2 && feed.tokens[feed.pos - 2].is_identifier("goto")) {
    std::string what = ctx.token() == symbol_kind::S_NUMBER ? ", not a number" : " after it";
    feed.diags.error(ctx.location(), "'goto' needs the name of a label" + what + ": write 'goto done;' and put "
                                     "'done:' before the statement to go to");
    return;
  }
  // `x = SENSOR_1();`: a macro that stands for a value, called (nqc: syntax
  // error). The value came out of the macro; the '(' is the user's own.
  if (feed.pos >= 2 && feed.last_text == "(" && feed.tokens[feed.pos - 1].span.begin.expansion == 0 &&
      feed.tokens[feed.pos - 2].span.begin.expansion != 0 &&
      (feed.tokens[feed.pos - 2].is(")") || feed.tokens[feed.pos - 2].kind == TokenKind::Number)) {
    feed.diags.error(ctx.location(), "expected ';' before '(': the name before it is a macro that stands for a "
                                     "value, not a function, so it takes no '()': leave them out");
    return;
  }
  // `asm { 0x51 0x01 }`: a byte list's ',' left out (said "expected '}'").
  bool value_found = ctx.token() == symbol_kind::S_NUMBER || ctx.token() == symbol_kind::S_IDENT;
  if (feed.pos >= 2 && value_found && feed.asm_stage == 2 && feed.asm_depth == 1 && feed.asm_byte_list) {
    const Token& before = feed.tokens[feed.pos - 2];
    if (before.kind == TokenKind::Number || before.kind == TokenKind::Char ||
        before.kind == TokenKind::Identifier || before.is(")")) {
      feed.diags.error(ctx.location(), "expected ',' before '" + std::string(feed.last_text) +
                                           "': the bytes of an asm block are separated by commas (asm { 0x51, 0x01 })");
      return;
    }
  }
  // `#define LIMIT 40;` then `if (x > LIMIT)`: the ';' ending the macro's
  // text is found where the parser wants a ')' or an operator.
  if (ctx.token() != symbol_kind::S_YYEOF && feed.last_text == ";" && !expects_punct("';'")) {
    const SourceLoc& at = feed.tokens[feed.pos - 1].span.begin;
    const SourceLoc& next = feed.tokens[feed.pos].span.begin;
    if (at.expansion != 0 && next.expansion != at.expansion && n >= 1) {
      std::string want = expects_punct("')'") ? "')'" : "an operator";
      if (n <= 3) {
        want.clear();
        for (int i = 0; i < n; ++i) want += (i == 0 ? "" : i + 1 == n ? " or " : ", ") + shown(expected[i]);
      }
      feed.diags.error(ctx.location(), "expected " + want + " before ';': the ';' ends a macro's text (a #define "
                                        "needs no ';' at its end)");
      return;
    }
  }
  // `elsif (x == 1) ...`: the parse fails just after the ')'.
  if (feed.pos >= 2) {
    if (const Token* word = else_if_word_before(feed, feed.pos - 2)) {
      feed.diags.error(word->span, "'" + std::string(word->text) + "' is not NQC: write 'else if (...)'");
      return;
    }
  }
  // `x = 1 2;`: two values side by side on one line, an operator left out.
  if (feed.pos >= 2 && (ctx.token() == symbol_kind::S_NUMBER || ctx.token() == symbol_kind::S_IDENT) &&
      expects_punct("';'") && !feed.tokens[feed.pos - 1].line_start &&
      (feed.tokens[feed.pos - 2].kind == TokenKind::Number || feed.tokens[feed.pos - 2].is(")"))) {
    feed.diags.error(ctx.location(), "expected an operator or ';' before '" + std::string(feed.last_text) +
                                         "': two values stand side by side; write the operator between them (as "
                                         "in '1 + 2')");
    return;
  }
  // `if (x > 1)) x = 0;`: a ')' with no '(' open before it in its statement
  // (said "expected a statement before ')'").
  if (ctx.token() != symbol_kind::S_YYEOF && feed.last_text == ")" && unmatched_close(feed, feed.pos - 1)) {
    feed.diags.error(ctx.location(), "unmatched ')': no '(' before it is open; leave it out");
    return;
  }
  // Where a statement goes: `else` after an `if` a ';' ended, or `task`
  // and `sub` inside a body (a '}' left out above, most often).
  bool statement_wanted = expects(symbol_kind::S_IF) && expects(symbol_kind::S_NUMBER);
  if (statement_wanted && ctx.token() == symbol_kind::S_ELSE) {
    if (const Token* open_if = if_left_open_before_else(feed, feed.pos - 1)) {
      auto& d = feed.diags.error(ctx.location(), "'else' inside the braces of the 'if' on line " +
                                                     std::to_string(open_if->span.begin.line) +
                                                     ": is a '}' missing before it?");
      d.notes.push_back({open_if->span, "this 'if' has a '{' that is not closed before the 'else'"});
      return;
    }
    auto& d = feed.diags.error(ctx.location(), "'else' without an 'if' before it: a statement stands between them "
                                               "(an extra ';' is an empty statement, and two statements after an 'if' "
                                               "need braces)");
    if (auto note = macro_that_ended_the_if(feed)) d.notes.push_back(*note);
    return;
  }
  // `task = 1;`: the keyword as a variable, with no name after it.
  bool named_next = feed.pos < feed.tokens.size() && feed.tokens[feed.pos].kind == TokenKind::Identifier;
  if (statement_wanted && (ctx.token() == symbol_kind::S_TASK || ctx.token() == symbol_kind::S_SUB) && !named_next) {
    feed.diags.error(ctx.location(), "'" + std::string(feed.last_text) + "' is a keyword of NQC and cannot be a "
                                     "name: choose another");
    return;
  }
  if (statement_wanted && (ctx.token() == symbol_kind::S_TASK || ctx.token() == symbol_kind::S_SUB)) {
    feed.diags.error(ctx.location(), "'" + std::string(feed.last_text) + "' cannot stand inside a task, sub or "
                                     "function: is a '}' missing before it?");
    return;
  }
  // `task main()` with its '{' left out: said "expected ';' or '{'", and
  // the ';' would only lead to "no declarations without a body".
  if (feed.pos >= 2 && expects_punct("'{'") && expects_punct("';'") && n == 2 && feed.tokens[feed.pos - 2].is(")") &&
      ctx.token() != symbol_kind::S_YYEOF) {
    feed.diags.error(ctx.location(), "expected '{' before '" + std::string(feed.last_text) +
                                         "': the body goes between braces after the head");
    return;
  }
  std::string want;
  SourceSpan where = ctx.location();
  if (n >= 1 && n <= 3) {
    for (int i = 0; i < n; ++i) want += (i == 0 ? "" : i + 1 == n ? " or " : ", ") + shown(expected[i]);
  } else if (ctx.token() == symbol_kind::S_YYEOF && expects_punct("'}'")) {
    want = "'}'";
  } else if (statement_wanted && !expects(symbol_kind::S_TASK)) {
    want = "a statement";
  } else if (expects(symbol_kind::S_NUMBER) && expects(symbol_kind::S_IDENT) && !expects(symbol_kind::S_TASK)) {
    want = "an expression";
  } else if (expects(symbol_kind::S_TASK)) {
    // Between declarations: a stray '}' or a misspelt keyword, not a
    // missing ';' after the declaration before it.
    want = "a declaration (task, sub, int or an inline function)";
  } else if (expects_punct("';'")) {
    want = "';'";
  } else if (expects_punct("')'")) {
    want = "')'";
  }
  // A string as a call's first argument (`PlayFileEx("cash.rso", ...)`):
  // the parser has already settled on an empty argument list there and
  // asks only for ')', but what was meant is a value.
  bool string_found = ctx.token() == symbol_kind::S_STRING;
  if (string_found && want == "')'" && feed.pos >= 2 && feed.tokens[feed.pos - 2].is("("))
    want = "an expression";
  // A missing ';' is shown just after the statement it should end, unless
  // that statement is in another file (the end of the library, when the
  // first line of a program is wrong): then at what was found.
  if (want.rfind("';'", 0) == 0 && feed.prev_end.valid() && feed.prev_end.file == where.begin.file)
    where = {feed.prev_end, feed.prev_end};
  std::string message = want.empty() ? "syntax error at " + found : "expected " + want + " before " + found;
  // Text where a value goes: a program for another brick (the NXT's
  // TextOut) or a C habit. No rule takes a string, so wherever one is
  // found, say why it cannot be there.
  if (string_found)
    message += ": the RCX has no strings, only numbers (its display shows a number)";
  auto& d = feed.diags.error(where, message);
  // At the end of the file the mistake is far above: show the '{' left open.
  if (ctx.token() == symbol_kind::S_YYEOF && !feed.open_braces.empty())
    d.notes.push_back({feed.open_braces.back(), "this '{' is not closed"});
}

}  // namespace rcxc::frontend
