// The bison parser: the AST it builds (shapes, precedence, spans) for every
// construct of the language, and syntax error messages with recovery.
#include <gtest/gtest.h>

#include <algorithm>
#include <string_view>

#include "frontend/parse.h"
#include "tests/frontend/frontend_test_util.h"

using namespace rcxc;
using namespace rcxc::ast;
using rcxc::test::run_frontend;

namespace {

// A compact prefix rendering of an expression, to compare shapes.
std::string show(const Expr& e) {
  if (auto* l = as<IntLit>(e)) return std::to_string(l->value);
  if (auto* n = as<Name>(e)) return n->name;
  if (auto* u = as<Unary>(e)) {
    static const char* names[] = {"neg", "not~", "not!", "plus", "++pre", "--pre", "post++", "post--"};
    return std::string("(") + names[static_cast<int>(u->op)] + " " + show(*u->operand) + ")";
  }
  if (auto* b = as<Binary>(e)) {
    static const char* names[] = {"*", "/", "%", "+", "-", "<<", ">>", "<", "<=", ">", ">=", "==", "!=",
                                  "&", "^", "|", "&&", "||"};
    return std::string("(") + names[static_cast<int>(b->op)] + " " + show(*b->lhs) + " " + show(*b->rhs) + ")";
  }
  if (auto* a = as<Assign>(e)) {
    static const char* names[] = {"=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>=", "||=", "+-="};
    return std::string("(") + names[static_cast<int>(a->op)] + " " + show(*a->target) + " " + show(*a->value) + ")";
  }
  if (auto* c = as<Conditional>(e))
    return "(? " + show(*c->cond) + " " + show(*c->then_value) + " " + show(*c->else_value) + ")";
  if (auto* c = as<Call>(e)) {
    std::string s = "(call " + c->callee;
    for (const auto& a : c->args) s += " " + show(a);
    return s + ")";
  }
  if (auto* s = as<Source>(e)) return "(source " + show(*s->type) + " " + show(*s->arg) + ")";
  if (auto* s = as<SourceArg>(e)) return "(source_arg " + show(*s->operand) + ")";
  return "?";
}

// The expression of the first statement of task main, which must be `x = EXPR;`.
std::string parse_expr(const std::string& expr) {
  auto r = run_frontend("int x, y, z;\ntask main()\n{\n  x = " + expr + ";\n}\n", true);
  if (!r.program) return "ERROR: " + r.text();
  const auto& body = std::get<Block>(r.program->tasks[0].body.node);
  const auto& stmt = std::get<ExprStmt>(body.stmts.at(0).node);
  return show(*std::get<Assign>(stmt.expr.node).value);
}

const Block& main_body(const Program& p) {
  for (const auto& t : p.tasks)
    if (t.name == "main") return std::get<Block>(t.body.node);
  throw std::runtime_error("no task main");
}

}  // namespace

TEST(Parser, PrecedenceAndAssociativityFollowC) {
  EXPECT_EQ(parse_expr("1 + 2 * 3"), "(+ 1 (* 2 3))");
  EXPECT_EQ(parse_expr("1 - 2 - 3"), "(- (- 1 2) 3)");
  EXPECT_EQ(parse_expr("y << 1 + 2"), "(<< y (+ 1 2))");
  EXPECT_EQ(parse_expr("y < 1 == z > 2"), "(== (< y 1) (> z 2))");
  EXPECT_EQ(parse_expr("y & 1 ^ 2 | 3"), "(| (^ (& y 1) 2) 3)");
  EXPECT_EQ(parse_expr("y || z && 1 | 2"), "(|| y (&& z (| 1 2)))");
  EXPECT_EQ(parse_expr("y ? 1 : z ? 2 : 3"), "(? y 1 (? z 2 3))");
  EXPECT_EQ(parse_expr("y = z += 2"), "(= y (+= z 2))");
  EXPECT_EQ(parse_expr("-y * ~z % !1"), "(% (* (neg y) (not~ z)) (not! 1))");
  EXPECT_EQ(parse_expr("y++ + ++z - z-- - --y"), "(- (- (+ (post++ y) (++pre z)) (post-- z)) (--pre y))");
  EXPECT_EQ(parse_expr("(1 + 2) * +3"), "(* (+ 1 2) (plus 3))");
  EXPECT_EQ(parse_expr("y % 3 ^ 4 << 1"), "(^ (% y 3) (<< 4 1))");
}

// For's condition and step and a declaration's initialiser are held on the
// heap (ast::OptionalBox): a copied tree has its own, and an absent one
// stays absent, as when they were std::optional values.
TEST(Parser, CopiedForAndInitialiserAreTheirOwn) {
  auto r = run_frontend("task main() { int a = 1, b; for (a = 0; a < 3; a++) b = a; for (;;) break; }\n", true);
  ASSERT_TRUE(r.program) << r.text();
  Program copy = *r.program;
  auto& st = const_cast<Block&>(main_body(copy)).stmts;
  auto& decl = std::get<DeclStmt>(st[0].node);
  ASSERT_TRUE(decl.vars[0].init && !decl.vars[1].init);
  std::get<IntLit>(decl.vars[0].init->node).value = 7;
  auto& f = std::get<For>(st[1].node);
  ASSERT_TRUE(f.cond && f.step);
  f.cond->span = {};
  f.step.reset();
  const auto& original = main_body(*r.program).stmts;
  EXPECT_EQ(std::get<IntLit>(std::get<DeclStmt>(original[0].node).vars[0].init->node).value, 1);
  const auto& g = std::get<For>(original[1].node);
  EXPECT_TRUE(g.step);
  EXPECT_EQ(g.cond->span.begin.column, 41u);
  const auto& empty = std::get<For>(st[2].node);
  EXPECT_FALSE(empty.cond || empty.step);
}

// Every keyword is one (the parser finds them by first character): none
// can name a variable, and a name that only starts like one can.
TEST(Parser, EveryKeywordIsReservedAndOnlyIt) {
  const std::vector<std::string_view> all = {
      "task",   "sub",  "void",   "int",      "const", "if",    "else",    "while",   "do",           "until",
      "for",    "repeat", "switch", "case",   "default", "break", "continue", "return", "goto",       "start",
      "stop",   "asm",  "true",   "false",    "inline", "__source", "__source_arg", "abs", "sign", "__nolist",
      "__sensor", "__taskid", "__type"};
  for (std::string_view kw : all) {
    EXPECT_FALSE(run_frontend("int " + std::string(kw) + ";\ntask main() { }\n", true).program) << kw;
    auto r = run_frontend("int " + std::string(kw) + "x;\ntask main() { " + std::string(kw) + "x = 1; }\n", true);
    EXPECT_TRUE(r.program) << kw << ": " << r.text();
    EXPECT_TRUE(frontend::is_keyword(kw)) << kw;
    EXPECT_FALSE(frontend::is_keyword(std::string(kw) + "x")) << kw;
  }
  // The list tools are given is the parser's, no word more or less.
  auto listed = frontend::keywords();
  std::sort(listed.begin(), listed.end());
  auto expected = all;
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(listed, expected);
  EXPECT_FALSE(frontend::is_keyword(""));
  EXPECT_FALSE(frontend::is_keyword("While"));
}

TEST(Parser, AbsAndSignAssignmentsAreOperators) {
  EXPECT_EQ(parse_expr("y ||= -4"), "(||= y (neg 4))");
  EXPECT_EQ(parse_expr("y +-= z"), "(+-= y z)");
  for (const char* op : {"-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>="})
    EXPECT_EQ(parse_expr(std::string("y ") + op + " 2"), std::string("(") + op + " y 2)");
}

TEST(Parser, SourceIntrinsicsAndTrueFalse) {
  EXPECT_EQ(parse_expr("__source(1, 2) + true - false"), "(- (+ (source 1 2) 1) 0)");
  EXPECT_EQ(parse_expr("__source_arg(__source(9, 1), 9)"), "(source_arg (source 9 1))");
}

TEST(Parser, EveryStatementKind) {
  auto r = run_frontend(
      "int g = 4;\n"
      "sub s() { g = 1; }\n"
      "task other() { }\n"
      "task main()\n{\n"
      "  int a = 1, b;\n"
      "  { b = 2; }\n"
      "  if (a) b = 1; else b = 2;\n"
      "  while (a < 3) a++;\n"
      "  do { a--; } while (a > 0);\n"
      "  do a++; until (a == 3);\n"
      "  until (a == 0) a--;\n"
      "  for (a = 0; a < 3; a++) continue;\n"
      "  for (int i = 0; ; ) break;\n"
      "  repeat (3) b++;\n"
      "  switch (a) { case 1: b = 1; break; default: b = 0; }\n"
      "  goto done;\n"
      "  done: start other;\n"
      "  stop other;\n"
      "  s();\n"
      "  asm { 0x51, 3, $a };\n"
      "  return;\n"
      "}\n",
      true);
  ASSERT_TRUE(r.program) << r.text();
  const auto& st = main_body(*r.program).stmts;
  ASSERT_EQ(st.size(), 18u);
  EXPECT_EQ(std::get<DeclStmt>(st[0].node).vars.size(), 2u);
  EXPECT_TRUE(as<Block>(st[1]));
  EXPECT_TRUE(std::get<If>(st[2].node).else_branch.has_value());
  EXPECT_TRUE(as<While>(st[3]));
  EXPECT_FALSE(std::get<DoWhile>(st[4].node).until);
  EXPECT_TRUE(std::get<DoWhile>(st[5].node).until);
  EXPECT_TRUE(as<Until>(st[6]));
  const auto& f1 = std::get<For>(st[7].node);
  EXPECT_TRUE(f1.init && f1.cond && f1.step);
  const auto& f2 = std::get<For>(st[8].node);
  EXPECT_TRUE(f2.init && as<DeclStmt>(**f2.init));
  EXPECT_FALSE(f2.cond || f2.step);
  EXPECT_TRUE(as<Repeat>(st[9]));
  const auto& sw = std::get<Switch>(st[10].node);
  ASSERT_EQ(sw.cases.size(), 2u);
  EXPECT_EQ(sw.cases[0].value, std::optional<std::int16_t>(1));
  EXPECT_FALSE(sw.cases[1].value.has_value());
  EXPECT_EQ(std::get<Goto>(st[11].node).label, "done");
  const auto& lab = std::get<Labeled>(st[12].node);
  EXPECT_EQ(lab.label, "done");
  EXPECT_TRUE(as<StartTask>(*lab.body));
  EXPECT_EQ(std::get<Goto>(st[11].node).symbol, lab.symbol);
  EXPECT_TRUE(as<StopTask>(st[13]));
  EXPECT_TRUE(as<Call>(std::get<ExprStmt>(st[14].node).expr));
  const auto& a = std::get<Asm>(st[15].node);
  ASSERT_EQ(a.items.size(), 3u);
  EXPECT_TRUE(std::get<AsmByte>(a.items[2]).source_pair);
  EXPECT_TRUE(as<Empty>(st[16]));  // the ';' after asm { }
  EXPECT_TRUE(as<Return>(st[17]));
}

TEST(Parser, FunctionsWithTheFourParameterKinds) {
  auto r = run_frontend(
      "void f(int a, const int b, int &c, const int &d) { c = a + b + d; }\n"
      "inline void g(void) { }\n"
      "task main() { int v; f(1, 2, v, v + 1); g(); }\n",
      true);
  ASSERT_TRUE(r.program) << r.text();
  ASSERT_EQ(r.program->functions.size(), 2u);
  const auto& p = r.program->functions[0].params;
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p[0].kind, ParamKind::Value);
  EXPECT_EQ(p[1].kind, ParamKind::Const);
  EXPECT_EQ(p[2].kind, ParamKind::Reference);
  EXPECT_EQ(p[3].kind, ParamKind::ConstReference);
  EXPECT_EQ(p[3].name, "d");
  EXPECT_TRUE(r.program->functions[1].params.empty());
}

TEST(Parser, MnemonicAsmLines) {
  auto r = run_frontend("int v;\ntask main() { asm { pwr 1, v; wait 100; out 0x81; msgclr; } }\n", true);
  ASSERT_TRUE(r.program) << r.text();
  const auto& a = std::get<Asm>(main_body(*r.program).stmts.at(0).node);
  ASSERT_EQ(a.items.size(), 4u);
  const auto& pwr = std::get<AsmInstr>(a.items[0]);
  EXPECT_EQ(pwr.mnemonic, "pwr");
  ASSERT_EQ(pwr.operands.size(), 2u);
  EXPECT_EQ(pwr.op, rcx::Op::SetMotorPower);
  EXPECT_EQ(std::get<AsmInstr>(a.items[3]).mnemonic, "msgclr");
  EXPECT_TRUE(std::get<AsmInstr>(a.items[3]).operands.empty());
}

TEST(Parser, SpansCoverTheWholeConstruct) {
  auto r = run_frontend("int x;\ntask main()\n{\n  x = 1 +  2;\n}\n", true);
  ASSERT_TRUE(r.program);
  const auto& s = main_body(*r.program).stmts[0];
  EXPECT_EQ(s.span.begin.line, 4u);
  EXPECT_EQ(s.span.begin.column, 3u);
  EXPECT_EQ(s.span.end.column, 14u);  // after the ';'
  const auto& value = *std::get<Assign>(std::get<ExprStmt>(s.node).expr.node).value;
  EXPECT_EQ(value.span.begin.column, 7u);
  EXPECT_EQ(value.span.end.column, 13u);
  EXPECT_EQ(value.constant, std::optional<std::int16_t>(3));
  EXPECT_EQ(r.program->tasks[0].span.begin.column, 6u);  // the name
}

TEST(Parser, DanglingElseBindsToTheNearestIf) {
  auto r = run_frontend("int x;\ntask main() { if (x) if (x > 1) x = 1; else x = 2; }\n", true);
  ASSERT_TRUE(r.program);
  const auto& outer = std::get<If>(main_body(*r.program).stmts[0].node);
  EXPECT_FALSE(outer.else_branch.has_value());
  EXPECT_TRUE(std::get<If>(outer.then_branch->node).else_branch.has_value());
}

TEST(Parser, SyntaxErrorsAreReportedAndParsingRecovers) {
  auto r = run_frontend(
      "task main()\n{\n  int x\n  x = 3;\n  if (x > ) x = 1;\n  while (x { }\n}\n"
      "task foo() { x = 1 }\n"
      "sub bar() { x = = 2; }\n",
      true);
  EXPECT_FALSE(r.program);
  EXPECT_EQ(r.brief(), (std::vector<std::string>{
                           "3:8: error: expected ';' or ',' before 'x'",
                           "5:11: error: expected an expression before ')'",
                           "6:12: error: expected ')' before '{'",
                           "8:19: error: expected ';' before '}'",
                           "9:17: error: expected an expression before '='",
                       }));
}

TEST(Parser, AWrongFirstLineIsReportedInTheProgramNotTheLibrary) {
  // The token before `foo` is the library's last `}`: the error still
  // belongs to line 1 of the program.
  auto r = run_frontend("foo bar\ntask main() {}\n");
  ASSERT_FALSE(r.diags.all().empty());
  EXPECT_EQ(r.brief().front(), "1:1: error: expected a declaration (task, sub, int or an inline function) before 'foo'");
  EXPECT_EQ(r.sm.path(r.diags.all().front().span.begin.file), "test.nqc");
}

TEST(Parser, SemanticErrorsElsewhereAreReportedWithSyntaxErrors) {
  // The syntax error is in main; the undeclared name in other is still
  // found; nothing is said about main's body beyond its syntax error.
  auto r = run_frontend("task other()\n{\n  y = 2;\n}\ntask main()\n{\n  z = (1 + ;\n  start other;\n}\n", true);
  EXPECT_FALSE(r.program);
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"7:12: error: expected an expression before ';'",
                                                 "3:3: error: 'y' is not declared"}));
}

TEST(Parser, AStrayBraceBetweenDeclarationsIsReportedWhereItIs) {
  // Not "expected ';'" after main's own closing brace: nothing is missing
  // there.
  auto r = run_frontend("task main() {\n  while (true) {\n    Wait(1);\n  }\n}\n}\n");
  EXPECT_EQ(r.brief(), (std::vector<std::string>{
                           "6:1: error: expected a declaration (task, sub, int or an inline function) before '}'"}));
}

TEST(Parser, ABrokenDeclarationStopsTheChecks) {
  // `int x y;` may have meant anything: checking on would only report
  // uses of x and y as undeclared.
  auto r = run_frontend("int x y;\ntask main()\n{\n  x = y;\n}\n", true);
  EXPECT_FALSE(r.program);
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"1:6: error: expected ';' or ',' before 'y'"}));
}

TEST(Parser, MissingBraceAtEndOfFile) {
  auto r = run_frontend("task main() {\n  int x;\n", true);
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"3:1: error: expected '}' before end of file"}));
}

TEST(Parser, ArraysAreRejectedClearly) {
  auto r = run_frontend("int v[3];\nint w;\ntask main() { w[1] = 2; }\n", true);
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"1:5: error: the RCX has no arrays: 'v' must be a plain int",
                                                 "3:15: error: the RCX has no arrays, so nothing can be indexed"}));
}

// `int v[]` as a parameter said "expected ')' before '['", and `int a[];`
// "expected an expression before ']'" (the thirteenth faithfulness round).
TEST(Parser, AnArrayWithoutASizeIsRefusedAsAnArray) {
  auto r = run_frontend("int a, b[];\nvoid f(int v[]) { }\ntask main()\n{\n  int c[];\n  a = a[];\n}\n", true);
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"1:10: error: the RCX has no arrays: 'b' must be a plain int",
                                                 "2:13: error: the RCX has no arrays: 'v' must be a plain int",
                                                 "5:9: error: the RCX has no arrays: 'c' must be a plain int",
                                                 "6:9: error: expected an expression before ']'"}));
}

TEST(Parser, AnArrayIsOneErrorAtItsDeclarationNotOneAtEachUse) {
  // The thirteenth faithfulness round: `int a[4]` and three uses gave five
  // errors for one mistake (nqc gives one, at the declaration).
  auto r = run_frontend("int a[4];\ntask main()\n{\n  int t[2];\n  a[0] = 1;\n  a[3] = a[0] + t[1];\n"
                        "  SendMessage(a[3]);\n}\n",
                        true);
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"1:5: error: the RCX has no arrays: 'a' must be a plain int",
                                                 "4:7: error: the RCX has no arrays: 't' must be a plain int"}));
}

// `for (...; i++ {` with a call in the body: the recovery took the call's
// ')' for the head's, and the body's '}' then ended the task, so the task's
// own '}' was a second error (the thirteenth faithfulness round).
TEST(Parser, AForHeadMissingItsParenthesisBeforeTheBodyIsOneError) {
  auto r = run_frontend("int i;\ntask main()\n{\n  for (i = 0; i < 3; i++ {\n    Wait(1);\n  }\n  Off(OUT_A);\n}\n", true);
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"4:26: error: expected ')' before '{'"}));
}
