// Diagnostics that do not trap someone coming from nqc or typing fast: "did
// you mean", the unclosed '{', parameters on a sub, a byte-order mark,
// library errors at the user's line, reading order, a file name on every
// error, colour.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "frontend/other_targets.h"
#include "frontend/spelling.h"
#include "tests/frontend/frontend_test_util.h"
#include "tests/support/process.h"

namespace {

using rcxc::test::run_frontend;
using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

// Each message as "line:column message", in the order given.
std::vector<std::string> placed_messages(const rcxc::Diagnostics& diags) {
  std::vector<std::string> out;
  for (const auto& d : diags.all())
    out.push_back(std::to_string(d.span.begin.line) + ":" + std::to_string(d.span.begin.column) + " " + d.message);
  return out;
}

TEST(Spelling, DistanceCountsEditsAndIgnoresCase) {
  using rcxc::frontend::spelling_distance;
  EXPECT_EQ(spelling_distance("Wiat", "Wait"), 1u);  // two neighbours swapped
  EXPECT_EQ(spelling_distance("onfwd", "OnFwd"), 0u);
  EXPECT_EQ(spelling_distance("Off", "OnFwd"), 3u);
  EXPECT_EQ(spelling_distance("", "abc"), 3u);
}

TEST(Spelling, ClosestNameNeedsOneClearWinner) {
  using rcxc::frontend::closest_name;
  std::vector<std::string> names{"OUT_A", "OUT_B", "OUT_C", "Wait", "SENSOR_TOUCH", "__internal"};
  EXPECT_EQ(closest_name("Wiat", names), "Wait");
  EXPECT_EQ(closest_name("SENSOR_TUOCH", names), "SENSOR_TOUCH");
  EXPECT_EQ(closest_name("OUT_D", names), std::nullopt);  // A, B and C are as near
  EXPECT_EQ(closest_name("xyz", names), std::nullopt);
  EXPECT_EQ(closest_name("__internl", names), std::nullopt);  // the library's helpers are not offered
}

// TOUCH written for SENSOR_TOUCH is too far in edits for closest_name; the
// shortest name that ends in _TOUCH is meant.
TEST(Spelling, ANameWithoutItsPrefixFindsTheShortestThatEndsInIt) {
  using rcxc::frontend::name_with_prefix;
  std::vector<std::string> names{"SENSOR_TOUCH", "SENSOR_TYPE_TOUCH", "OUT_A", "DISPLAY_OUT_A", "SOUND_UP",
                                 "SOUND_FAST_UP", "SOUND_LO_BEEP", "SOUND_HI_BEEP", "__X_FWD", "TOUCHED"};
  EXPECT_EQ(name_with_prefix("TOUCH", names), "SENSOR_TOUCH");
  EXPECT_EQ(name_with_prefix("touch", names), std::nullopt);  // the case is kept
  EXPECT_EQ(name_with_prefix("A", names), std::nullopt);      // too short to guess from
  EXPECT_EQ(name_with_prefix("BEEP", names), std::nullopt);   // LO and HI are as short
  EXPECT_EQ(name_with_prefix("FWD", names), std::nullopt);    // the library's helpers are not offered
  EXPECT_EQ(name_with_prefix("CHED", names), std::nullopt);   // a word's end is not a name's
}

TEST(Spelling, AVeryLongNameGetsNoSuggestion) {
  // The distance costs the product of the lengths: two 20,000-letter names
  // one letter apart took 17 s to compile. No one misspells such a name.
  using rcxc::frontend::closest_name;
  using rcxc::frontend::kMaxSpelledName;
  const std::string stem(kMaxSpelledName - 1, 'a');
  EXPECT_EQ(closest_name(stem + "b", {stem + "c"}), stem + "c");
  EXPECT_EQ(closest_name(stem + "bb", {stem + "bc"}), std::nullopt);
  const std::string huge(20000, 'a');
  EXPECT_EQ(closest_name(huge + "b", {huge + "c", "Wait"}), std::nullopt);
}

TEST(HelpfulDiagnostics, MisspeltApiNameSuggestsTheRightOne) {
  auto r = run_frontend("task main()\n{\n  Wiat(100);\n  OnFwd(OUT_A + SENSOR_TUOCH);\n}\n");
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"3:3: error: 'Wiat' is not declared; did you mean 'Wait'?",
                                                 "4:17: error: 'SENSOR_TUOCH' is not declared; did you mean "
                                                 "'SENSOR_TOUCH'?"}));
}

TEST(HelpfulDiagnostics, MisspeltOwnNamesSuggestTheProgramsNames) {
  auto r = run_frontend(
      "int counter;\nsub bump() { counter++; }\ntask main()\n{\n  int speed;\n  countr = 1;\n  spede = 2;\n  bmup();\n  Wait(speed);\n}\n");
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"6:3: error: 'countr' is not declared; did you mean 'counter'?",
                                                 "7:3: error: 'spede' is not declared; did you mean 'speed'?",
                                                 "8:3: error: 'bmup' is not declared; did you mean 'bump'?"}));
}

TEST(HelpfulDiagnostics, UnclosedBraceAtEndOfFileIsPointedAt) {
  auto r = run_frontend("task main()\n{\n  while (true) {\n    Wait(1);\n}\n");
  ASSERT_EQ(r.diags.all().size(), 1u) << r.text();
  const auto& d = r.diags.all()[0];
  EXPECT_EQ(d.message, "expected '}' before end of file");
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_EQ(d.notes[0].message, "this '{' is not closed");
  EXPECT_EQ(d.notes[0].span.begin.line, 2u);  // the task's: the while's closes on line 5
}

TEST(HelpfulDiagnostics, SubWithParametersSaysSubsTakeNone) {
  auto r = run_frontend("int total;\nsub add(int n)\n{\n  total += n;\n}\ntask main()\n{\n  add(2);\n}\n");
  // One error: the body and the call are judged as the function it could be.
  ASSERT_EQ(r.diags.all().size(), 1u) << r.text();
  EXPECT_EQ(r.diags.all()[0].span.begin.line, 2u);
  EXPECT_NE(r.diags.all()[0].message.find("subroutines take no parameters"), std::string::npos);
  EXPECT_NE(r.diags.all()[0].message.find("'void add(...)'"), std::string::npos);
}

// A C habit: declaring a function above its use. nqc refuses it ("syntax
// error"), and rcxc said "expected '{' before ';'", which did not say that
// NQC needs no such line. The rest of the program is still checked.
TEST(HelpfulDiagnostics, APrototypeSaysNqcNeedsNone) {
  auto r = run_frontend("void turn(int t);\nsub beep();\ntask other();\nint twice(int x);\ntask main()\n{\n"
                        "  turn(3); beep(); start other; undeclared = 1;\n}\nvoid turn(int t) { Wait(t); }\n"
                        "sub beep() { PlaySound(1); }\ntask other() { }\n");
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{
                     "1:17 NQC has no declarations without a body: define the function 'turn' here with its body, "
                     "or leave this line out (a function may be used above its definition)",
                     "2:11 NQC has no declarations without a body: define the sub 'beep' here with its body, or "
                     "leave this line out (a sub may be used above its definition)",
                     "3:13 NQC has no declarations without a body: define the task 'other' here with its body, or "
                     "leave this line out (a task may be used above its definition)",
                     "4:17 NQC has no declarations without a body: define the function 'twice' here with its body, "
                     "or leave this line out (a function may be used above its definition)",
                     "7:33 'undeclared' is not declared"}))
      << r.text();
}

// C's `const int K = 5;` is refused once; its uses where a constant is
// needed (a tone, a case, a `const int` parameter) drew errors of their own
// before, each saying K is no constant, which only repeated the first.
TEST(HelpfulDiagnostics, AConstVariableIsRefusedOnceNotAtEachUse) {
  auto r = run_frontend("const int K = 5;\nvoid f(const int n) { Wait(n); }\nint x;\ntask main()\n{\n"
                        "  const int L = K * 2;\n  PlayTone(K, 10);\n  PlaySound(L - 9);\n  f(L);\n"
                        "  x = Timer(K - 5);\n  switch (x) { case K: x = L; }\n}\n");
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{
                     "1:1 NQC has no constant variables: write '#define NAME value' for a named constant ('const' "
                     "belongs to function parameters only)",
                     "6:3 NQC has no constant variables: write '#define NAME value' for a named constant ('const' "
                     "belongs to function parameters only)"}))
      << r.text();
}

// Three slips that got only "expected ';' before ..." or "expected
// identifier" (nqc: syntax error): a value macro called, two values side by
// side, and a line number (or nothing) after goto.
TEST(HelpfulDiagnostics, ACalledValueTwoValuesAndANumberedGotoSayWhatToWrite) {
  const std::string called = "expected ';' before '(': the name before it is a macro that stands for a value, not a "
                             "function, so it takes no '()': leave them out";
  const std::string side_by_side = "two values stand side by side; write the operator between them (as in '1 + 2')";
  for (const auto& [statement, expected] : std::vector<std::pair<std::string, std::string>>{
           {"x = SENSOR_1();", "4:15 " + called},
           {"x = LIMIT(2);", "4:12 " + called},
           {"x = 1 2;", "4:9 expected an operator or ';' before '2': " + side_by_side},
           {"x = (x) 4;", "4:11 expected an operator or ';' before '4': " + side_by_side},
           {"goto 5;", "4:8 'goto' needs the name of a label, not a number: write 'goto done;' and put 'done:' "
                       "before the statement to go to"},
           {"goto;", "4:7 'goto' needs the name of a label after it: write 'goto done;' and put 'done:' "
                     "before the statement to go to"},
       }) {
    auto r = run_frontend("int x;\n#define LIMIT (3)\ntask main() {\n  " + statement + "\n}\n");
    EXPECT_EQ(placed_messages(r.diags), std::vector<std::string>{expected}) << r.text();
  }
}

// `#undef OUT_A` then `On(OUT_A)` suggested DISPLAY_OUT_A, the nearest name
// left; the name was not misspelt but removed, so the note shows where.
TEST(HelpfulDiagnostics, AMacroRemovedByUndefSaysWhere) {
  auto r = run_frontend("#define SPEED 3\n#undef OUT_A\n#undef SPEED\ntask main()\n{\n  On(OUT_A);\n"
                        "  SetPower(OUT_C, SPEED);\n}\n");
  ASSERT_EQ(placed_messages(r.diags), (std::vector<std::string>{
                                          "6:6 'OUT_A' is not declared: the macro was removed by an #undef",
                                          "7:19 'SPEED' is not declared: the macro was removed by an #undef"}))
      << r.text();
  const auto& notes = r.diags.all()[0].notes;
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0].message, "'OUT_A' is #undef'd here");
  EXPECT_EQ(notes[0].span.begin.line, 2u);
  // Defined again after the #undef, it is an ordinary name again.
  auto again = run_frontend("#undef OUT_A\n#define OUT_A 1\n#undef OUT_A\n#define OUT_A 2\ntask main() { On(OUT_A); }\n");
  EXPECT_TRUE(again.diags.all().empty()) << again.text();
}

// `x = Message;` names an API macro that takes arguments; "'Message' is not
// declared" told a beginner that the API has no Message (nqc: "wrong number
// of arguments to 'Message'"). A macro of the program's own is named alike.
TEST(HelpfulDiagnostics, AMacroWithoutItsArgumentsSaysItTakesThem) {
  auto r = run_frontend("#define HALF(x) ((x) / 2)\nint x;\ntask main() { x = Message; x = Random + HALF; }\n");
  std::vector<std::string> got;
  for (const auto& d : r.diags.all()) got.push_back(d.message);
  EXPECT_EQ(got, (std::vector<std::string>{
                     "'Message' is not declared: it is a macro that takes arguments, written 'Message(...)'",
                     "'Random' is not declared: it is a macro that takes arguments, written 'Random(...)'",
                     "'HALF' is not declared: it is a macro that takes arguments, written 'HALF(...)'"}))
      << r.text();
}

// C's `task main(void)` got "expected ')' before 'void'" (nqc: "syntax
// error"), which did not say that a task's parentheses stay empty.
TEST(HelpfulDiagnostics, ATaskOrSubWithParametersSaysItTakesNone) {
  auto r = run_frontend("task main(void)\n{\n  Wait(1);\n}\nsub beep(void) { PlaySound(1); }\n"
                        "task other(int speed) { }\n");
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{
                     "1:11 a task takes no parameters: write 'task main()'",
                     "5:10 a sub takes no parameters: write 'sub beep()'",
                     "6:12 a task takes no parameters: write 'task other()', and share values through global "
                     "variables"}))
      << r.text();
}

// A letter of another script in a name, or a dash, curly quote or
// non-breaking space pasted from a web page, is one error per character,
// and the parse goes on as if the character were not there: no syntax
// error after it. (Each was one error per UTF-8 byte.)
TEST(HelpfulDiagnostics, ANonAsciiCharacterIsOneErrorAndNoCascade) {
  auto name = run_frontend("int gr\xC3\xB6\xC3\x9F" "e;\ntask main() { int \xC3\xB6 = 1; }\n");
  EXPECT_EQ(placed_messages(name.diags),
            (std::vector<std::string>{
                "1:7 '\xC3\xB6' (U+00F6) cannot be part of a name: NQC names are ASCII letters, digits and _",
                "1:9 '\xC3\x9F' (U+00DF) cannot be part of a name: NQC names are ASCII letters, digits and _",
                "2:19 '\xC3\xB6' (U+00F6) cannot be part of a name: NQC names are ASCII letters, digits and _"}));
  auto pasted = run_frontend("task main() {\n  int x = 3 \xE2\x80\x93 1;\n  x\xC2\xA0= 2;\n  PlaySound(\xE2\x80\x9C" "x\xE2\x80\x9D);\n}\n");
  EXPECT_EQ(placed_messages(pasted.diags),
            (std::vector<std::string>{"2:13 '\xE2\x80\x93' (U+2013) is an en dash: use -",
                                      "3:4 a non-breaking space (U+00A0): use an ordinary space",
                                      "4:13 '\xE2\x80\x9C' (U+201C) is a typographic quote: use \"",
                                      "4:17 '\xE2\x80\x9D' (U+201D) is a typographic quote: use \""}));
}

// `#include “rcx.nqh”` (quotes turned curly by a word processor) said
// only that #include expects "FILE" or <FILE>; the quote's own message says
// what to type, once, at the quote.
TEST(HelpfulDiagnostics, ACurlyQuotedIncludeNamesTheQuote) {
  auto r = run_frontend("#include \xE2\x80\x9C" "rcx.nqh\xE2\x80\x9D\ntask main() { }\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{"1:10 '\xE2\x80\x9C' (U+201C) is a typographic quote: use \""}))
      << r.text();
}

// C's comma in a for header got "expected ';' before ','" and a second
// error at the header's ')' (nqc: one "syntax error"). One message now says
// what NQC lacks; the rest of the header and the body get no second error.
TEST(HelpfulDiagnostics, ACommaInAForHeaderSaysNqcHasNoCommaOperator) {
  auto r = run_frontend("int i, j;\ntask main()\n{\n  for (i = 10, j = 0; i > 0; i--) { j++; }\n"
                        "  for (i = 0; i < 3; i++, j++) undeclared = 1;\n}\n");
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{
                     "4:14 NQC has no comma operator: set the other variables before the for loop, or in its body",
                     "5:25 NQC has no comma operator: set the other variables before the for loop, or in its body"}))
      << r.text();
}

// `1--1` is `1--` then `1`, as in C: on a constant the decrement is the
// mistake (nqc: "not a legal target for assignment", gcc: "lvalue required"),
// said where it is; after a variable the value after it is. Both say how
// `--` was read, where they said "expected ';' before '1'".
TEST(HelpfulDiagnostics, ADoubleSignBetweenValuesSaysHowItWasRead) {
  auto r = run_frontend("int x, y;\ntask main()\n{\n  x = 1--1;\n  y = 5++2;\n  x = y--1;\n  y = x++y;\n}\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{
                "4:7 cannot decrement '1': it is a constant, not a variable ('1--1' reads as '1-- 1'; for a minus "
                "sign, put a space: '1 - -1')",
                "5:7 cannot increment '5': it is a constant, not a variable ('5++2' reads as '5++ 2'; for a plus "
                "sign, put a space: '5 + +2')",
                "6:10 expected ';' before '1': '--' here decrements what comes before it (for a minus sign, put a "
                "space: '- -1')",
                "7:10 expected ';' before 'y': '++' here increments what comes before it (for a plus sign, put a "
                "space: '+ +y')"}))
      << r.text();
  // `x--` and then a statement on the next line is a missing ';'.
  auto missing = run_frontend("int x;\ntask main()\n{\n  x--\n  x = 2;\n}\n");
  EXPECT_EQ(placed_messages(missing.diags), (std::vector<std::string>{"4:6 expected ';' before 'x'"})) << missing.text();
}

// C's casts (nqc: syntax error) said "expected an expression before 'int'"
// or, for a type the grammar took as a name, "expected ';' before 'x'".
TEST(HelpfulDiagnostics, ACastSaysNqcHasNone) {
  auto r = run_frontend("int x;\ntask main()\n{\n  x = (int)x + 1;\n  x = 2 * (float) x;\n"
                        "  x = (unsigned int)(x / 2);\n  Wait((const int)3);\n}\n");
  const std::string says = " NQC has no casts: every value is an int already, a 16-bit whole number (-32768 to "
                           "32767), so the cast can go";
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{"4:7" + says, "5:11" + says, "6:7" + says,
                                                                "7:8" + says}))
      << r.text();
  // A parameter without a name is no cast.
  auto unnamed = run_frontend("void f(int) { }\ntask main() { }\n");
  ASSERT_FALSE(unnamed.diags.all().empty());
  EXPECT_EQ(unnamed.diags.all().front().message.find("cast"), std::string::npos) << unnamed.text();
}

// The comma operator outside a for header said "expected ';' before ','"
// (after the statement's first part) or "expected ')' before ','".
TEST(HelpfulDiagnostics, ACommaOperatorAnywhereSaysNqcHasNone) {
  auto r = run_frontend("int x, y;\ntask main()\n{\n  x = 1, y = 2;\n  x = (y = 3, 4);\n  while (x++, y) y--;\n"
                        "  Wait(100), Off(OUT_A);\n}\n");
  const std::string says = " NQC has no comma operator: make each part a statement of its own, ending with ';'";
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{"4:8" + says, "5:13" + says, "6:13" + says,
                                                                "7:12" + says}))
      << r.text();
  // abs() takes one value, and `case 1, 2:` wants two labels: not the comma operator.
  for (const char* body : {"int x, y;\ntask main() { x = abs(x, y); }\n",
                           "int x;\ntask main() { switch (x) { case 1, 2: x = 0; } }\n"}) {
    auto other = run_frontend(body);
    ASSERT_FALSE(other.diags.all().empty());
    EXPECT_EQ(other.diags.all().front().message.find("comma"), std::string::npos) << other.text();
  }
}

// `case 1, 2:` said "syntax error at ','".
TEST(HelpfulDiagnostics, ACaseWithTwoValuesSaysEachNeedsALabel) {
  auto r = run_frontend("int x;\ntask main()\n{\n  switch (x) {\n    case 0: case 1, 2: x = 0; break;\n"
                        "    case 3 + 1, 5: x = 1;\n  }\n}\n");
  const std::string says = " a case label takes one value: give each value a label of its own, as in 'case 1: "
                           "case 2:'";
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{"5:19" + says, "6:15" + says})) << r.text();
}

// C and C++ habits in an inline function's parameters (nqc: syntax error)
// said "expected ')' before 'x'", "expected ')' before '='" or "expected
// identifier, '&' or '*' before 'const'".
TEST(HelpfulDiagnostics, ParametersWrittenAsInCSayWhatNqcWants) {
  auto placed_first = [](const char* text) {
    auto r = run_frontend(text);
    return r.diags.all().empty() ? std::string("none") : placed_messages(r.diags).front();
  };
  EXPECT_EQ(placed_first("void f(x) { }\ntask main() { }\n"),
            "1:8 a parameter needs its kind: write 'int x' (or 'int &x', 'const int x', 'const int &x')");
  EXPECT_EQ(placed_first("void f(int a, b) { }\ntask main() { }\n"),
            "1:15 a parameter needs its kind: write 'int b' (or 'int &b', 'const int b', 'const int &b')");
  EXPECT_EQ(placed_first("void f(float x) { }\ntask main() { }\n"),
            "1:8 'float' is not a type in NQC: every parameter is an int (write 'int', 'int &', 'const int' or "
            "'const int &')");
  EXPECT_EQ(placed_first("void f(int x = 3) { }\ntask main() { }\n"),
            "1:14 a parameter has no default value in NQC: every call gives every argument");
  EXPECT_EQ(placed_first("void f(int const &x) { }\ntask main() { }\n"),
            "1:12 'const' goes before 'int' in NQC: write 'const int' (or 'const int &')");
}

// Slips of other languages' habits said "expected ';' before '100'",
// "expected an expression before '>'" (`->` too) and, for `**`, that the RCX has no
// pointers (nqc: "undefined variable 'Wait'", syntax errors).
TEST(HelpfulDiagnostics, OtherLanguagesCallsAndOperatorsSayWhatNqcWrites) {
  auto r = run_frontend("int x, y;\ntask main()\n{\n  Wait 100;\n  if (x) Off 1;\n  if (x <> y) x = 1;\n"
                        "  if (x =< y) x = 2;\n  if (x => y) x = 3;\n  x = y ** 2;\n  x = y->next;\n}\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{
                "4:8 a call needs parentheses around its arguments: write 'Wait(100)'",
                "5:14 a call needs parentheses around its arguments: write 'Off(1)'",
                "6:9 '<>' is not an operator in NQC: 'not equal' is written '!='",
                "7:9 '=<' is not an operator in NQC: 'less than or equal' is written '<='",
                "8:9 '=>' is not an operator in NQC: 'greater than or equal' is written '>='",
                "9:10 NQC has no power operator '**': multiply instead ('y * y' for y squared)",
                "10:8 '->' is not an operator in NQC: the RCX has no structs or pointers, so there is no member to "
                "reach"}))
      << r.text();
  // A macro's value is not shown as if the user had written it.
  auto macro = run_frontend("task main()\n{\n  Off OUT_A;\n}\n");
  ASSERT_EQ(macro.diags.all().size(), 1u) << macro.text();
  EXPECT_EQ(macro.diags.all().front().message, "a call needs parentheses around its arguments: write 'Off(...)'");
  // A name after a name is no call: `itn x;` may be a misspelt type.
  auto typo = run_frontend("task main()\n{\n  itn x;\n}\n");
  ASSERT_FALSE(typo.diags.all().empty());
  EXPECT_EQ(typo.diags.all().front().message.find("parentheses"), std::string::npos) << typo.text();
}

// `x == 1;` as a statement is an assignment mistyped (clang: "equality
// comparison result unused").
TEST(HelpfulDiagnostics, AnUnusedEqualityAsksWhetherAnAssignmentWasMeant) {
  auto r = run_frontend("int x;\ntask main()\n{\n  x == 1;\n  x < 1;\n}\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{"4:3 expression result unused: '==' compares; did you mean '=' to assign?",
                                      "5:3 expression result unused"}))
      << r.text();
}

// A '?' without its ':' said "syntax error at ';'"; a case label without
// its ':' keeps its own message.
TEST(HelpfulDiagnostics, AConditionalWithoutItsColonSaysSo) {
  auto r = run_frontend("int x, y;\ntask main()\n{\n  x = (y > 1) ? 1;\n  Wait(y ? 10);\n}\n");
  const std::string says = "': a '?' needs ':' and the value for when the condition is false ('c ? a : b')";
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{"4:18 expected ':' before ';" + says,
                                                                "5:14 expected ':' before ')" + says}))
      << r.text();
  // A value where the ':' goes said "syntax error at '2'" (the thirteenth
  // faithfulness round).
  auto value = run_frontend("int x, y;\ntask main()\n{\n  x = x ? 1 2;\n  y = x ? y x;\n}\n");
  EXPECT_EQ(placed_messages(value.diags), (std::vector<std::string>{"4:13 expected ':' before '2" + says,
                                                                    "5:13 expected ':' before 'x" + says}))
      << value.text();
  auto label = run_frontend("int x;\ntask main()\n{\n  switch (x) { case 1; x = 2; }\n}\n");
  ASSERT_FALSE(label.diags.all().empty());
  EXPECT_EQ(label.diags.all().front().message.find("'?'"), std::string::npos) << label.text();
}

// `stop;` said "expected identifier before ';'".
TEST(HelpfulDiagnostics, StartOrStopWithoutATaskSaysItNeedsOne) {
  auto stop = run_frontend("task main()\n{\n  stop;\n}\n");
  EXPECT_EQ(placed_messages(stop.diags),
            (std::vector<std::string>{
                "3:7 'stop' needs the name of a task: write 'stop NAME;' (StopAllTasks() stops every task)"}))
      << stop.text();
  auto start = run_frontend("task main()\n{\n  start 3;\n}\n");
  EXPECT_EQ(placed_messages(start.diags),
            (std::vector<std::string>{"3:9 'start' needs the name of a task: write 'start NAME;'"}))
      << start.text();
}

TEST(HelpfulDiagnostics, LabelAtTheEndOfABlockWantsAStatement) {
  // C and nqc both refuse `end: }` and `case 1: }`; "expected an
  // expression" did not say what was missing.
  for (const char* body : {"int x;\ntask main() { goto end; x = 1; end: }\n",
                           "int x;\ntask main() { switch (x) { case 1: } }\n"}) {
    auto r = run_frontend(body);
    ASSERT_EQ(r.diags.all().size(), 1u) << r.text();
    EXPECT_EQ(r.diags.all()[0].message,
              "a label needs a statement after it: at the end of a block, add an empty one (';')");
  }
  auto r = run_frontend("int x, y;\ntask main() { x = y ? 1 : }\n");
  ASSERT_FALSE(r.diags.all().empty());
  EXPECT_EQ(r.diags.all()[0].message.find("label"), std::string::npos) << r.text();
}

TEST(HelpfulDiagnostics, NolistGoesBeforeVoidOnly) {
  for (const char* decl : {"__nolist task t() { }\n", "__nolist int y;\n", "__nolist sub s() { }\n"}) {
    auto r = run_frontend(std::string(decl) + "task main() { }\n");
    ASSERT_EQ(r.diags.all().size(), 1u) << r.text();
    EXPECT_EQ(r.diags.all()[0].message,
              "'__nolist' goes before 'void' only: it keeps an inline function out of nqc's listings");
  }
}

TEST(HelpfulDiagnostics, ByteOrderMarkIsSkipped) {
  auto r = run_frontend("\xEF\xBB\xBFtask main()\n{\n  x = 1;\n}\n");
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"3:3: error: 'x' is not declared"}));
  auto clean = run_frontend("\xEF\xBB\xBF" "task main()\n{\n}\n");
  EXPECT_TRUE(clean.diags.all().empty()) << clean.text();
}

// Classic Mac OS editors ended lines with a lone CR, and nqc reads such a
// file line by line; rcxc saw one long line, so a `#define` swallowed the
// whole program ("no 'task main()'").
TEST(HelpfulDiagnostics, ALoneCarriageReturnEndsALine) {
  auto r = run_frontend("#define SPEED 3\rtask main()\r{\r  SetPower(OUT_A, SPEED);\r  x = 1; // a comment\r}\r");
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"5:3: error: 'x' is not declared"}));
  EXPECT_EQ(r.sm.line(r.diags.all().at(0).span.begin.file, 5), "  x = 1; // a comment");
  auto mixed = run_frontend("task main()\r\n{\r  OnFwd(OUT_A);\n}\r\n");
  EXPECT_TRUE(mixed.diags.all().empty()) << mixed.text();
}

// SensorValueRaw(SENSOR_1) is nqc's usual spelling and compiles; a variable
// as the sensor gets one message at the argument, not a second one about
// __source's operands.
TEST(HelpfulDiagnostics, ASensorValueFunctionTakesASensorNameAndSaysOnceWhatIsWrong) {
  auto good = run_frontend("int x;\ntask main()\n{\n  x = SensorValueRaw(SENSOR_1) + SensorType(SENSOR_3);\n}\n");
  EXPECT_TRUE(good.diags.all().empty()) << good.text();
  auto bad = run_frontend("int x;\ntask main()\n{\n  x = SensorValueBool(x);\n}\n");
  EXPECT_EQ(bad.brief(), (std::vector<std::string>{"4:23: error: argument must be a sensor (SENSOR_1, SENSOR_2 or "
                                                   "SENSOR_3)"}));
}

// A source's argument past what the brick has (SensorValue(3) meaning the
// third sensor, Timer(4) the fourth timer) is a warning at the argument.
TEST(HelpfulDiagnostics, ASourceArgumentPastTheBricksRangeIsAWarning) {
  auto r = run_frontend("int x;\ntask main()\n{\n  x = SensorValue(3) + Timer(4) + @(0x30003) + @32 + Message();\n"
                        "  x = __source(14, 2) + SensorValue(2) + Timer(3) + Random(500) + Program();\n}\n");
  EXPECT_EQ(r.brief(),
            (std::vector<std::string>{
                "4:19: warning: sensor 3 does not exist: the RCX has sensors 0 to 2 (SENSOR_1 to SENSOR_3)",
                "4:30: warning: timer 4 does not exist: the RCX has timers 0 to 3",
                "4:36: warning: output 3 does not exist: the RCX has outputs 0 to 2",
                "4:49: warning: variable 32 does not exist: the RCX has variables 0 to 31",
                "5:20: warning: the clock source takes argument 0, not 2"}));
}

TEST(HelpfulDiagnostics, ErrorInALibraryMacroIsShownAtTheUsersLine) {
  auto r = run_frontend("int v;\ntask main()\n{\n  v = Random();\n}\n");
  std::string text = render_all(r.diags, r.sm, {});
  EXPECT_EQ(text.rfind("test.nqc:4:7: error: expected an expression before ')'\n", 0), 0u) << text;
  EXPECT_NE(text.find("rcx.nqh:"), std::string::npos) << text;
  EXPECT_NE(text.find("note: in macro 'Random' of the standard library rcx.nqh"), std::string::npos) << text;
}

TEST(HelpfulDiagnostics, MessagesComeInReadingOrder) {
  rcxc::SourceManager sm;
  auto main_file = sm.add("main.nqc", "#include \"lib.nqh\"\nline 2\nline 3\n");
  auto lib = sm.add("lib.nqh", "lib 1\nlib 2\n");
  sm.set_include_site(lib, {{main_file, 1, 1}, {main_file, 1, 2}});
  rcxc::Diagnostics diags;
  diags.error({{main_file, 3, 1}, {main_file, 3, 2}}, "third");
  diags.error({}, "no place");
  diags.error({{lib, 2, 1}, {lib, 2, 2}}, "second");
  diags.error({{main_file, 2, 1}, {main_file, 2, 2}}, "fourth");
  diags.error({{lib, 1, 1}, {lib, 1, 2}}, "first");
  std::vector<std::string> order;
  for (const auto* d : in_source_order(diags, sm)) order.push_back(d->message);
  // The included file's lines stand where the #include is (line 1).
  EXPECT_EQ(order, (std::vector<std::string>{"first", "second", "fourth", "third", "no place"}));
}

TEST(HelpfulDiagnostics, ErrorsWithoutAPositionNameTheFile) {
  TempDir d;
  std::string nomain = d.write("nomain.nqc", "int x;\n");
  auto r = run_rcxc({"compile", nomain});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind(nomain + ": error: the program has no 'task main()'", 0), 0u) << r.err;
  auto missing = run_rcxc({"compile", d.path + "/missing.nqc"});
  EXPECT_EQ(missing.err.rfind(d.path + "/missing.nqc: error: cannot open '" + d.path + "/missing.nqc': no such file",
                             0),
            0u)
      << missing.err;
}

TEST(HelpfulDiagnostics, ColourOnlyWhenAskedOrOnATerminal) {
  TempDir d;
  std::string bad = d.write("bad.nqc", "task main()\n{\n  x = 1;\n}\n");
  auto plain = run_rcxc({"compile", bad});  // stderr is a pipe: auto means none
  EXPECT_EQ(plain.err.find('\x1b'), std::string::npos) << plain.err;
  auto never = run_rcxc({"compile", "--color=never", bad});
  EXPECT_EQ(never.err.find('\x1b'), std::string::npos) << never.err;
  auto always = run_rcxc({"compile", "--color=always", bad});
  EXPECT_NE(always.err.find("\x1b[1;31merror:\x1b[0m"), std::string::npos) << always.err;
  auto wrong = run_rcxc({"compile", "--color=sometimes", bad});
  EXPECT_EQ(wrong.exit_code, 2);
}

TEST(HelpfulDiagnostics, NqcsOutputOptionGetsAHint) {
  TempDir d;
  std::string ok = d.write("ok.nqc", "task main() { }\n");
  auto r = run_rcxc({"compile", "-Oout.rcx", ok});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the output file is -o out.rcx"), std::string::npos) << r.err;
  EXPECT_EQ(run_rcxc({"compile", "-O1", ok}).exit_code, 0);
}

// `#define PAUSE` left without its value: `Wait(PAUSE)` shows an argument,
// and the error counts none. A note at the macro's use says why.
TEST(HelpfulDiagnostics, AMacroThatExpandsToNothingInsideAnErrorIsNamed) {
  TempDir d;
  std::string src = d.write("empty.nqc", "#define PAUSE\n#define FAST 7\ntask main()\n{\n  Wait(PAUSE);\n  SetPower(OUT_A, FAST);\n}\n");
  auto r = run_rcxc({"compile", src});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("empty.nqc:5:3: error: function 'Wait' takes 1 argument, but 0 were given"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("empty.nqc:5:8: note: macro 'PAUSE' expands to nothing"), std::string::npos) << r.err;
  // Only where an error is: the macro with a value gets no note.
  EXPECT_EQ(r.err.find("'FAST'"), std::string::npos) << r.err;
}

// A macro called with too few or too many arguments was followed by a
// second error on the same line ("expected an expression before ';'"),
// since the call left nothing behind; the call now stands as a 0 the
// parser reads past, so each call is one error, and the program around it
// is still checked (the undeclared name below).
TEST(HelpfulDiagnostics, AMacroCalledWithTheWrongArgumentsIsOneError) {
  auto r = run_frontend("#define F(a, b) ((a) + (b))\n#define DECL(a, b) int a = b;\nDECL(g)\nint x;\ntask main()\n{\n"
                        "  x = F(1);\n  x = F(1, 2, 3);\n  F(4);\n  Wait(F(5) + 1);\n  y = 2;\n}\n");
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{"3:1 macro 'DECL' takes 2 arguments, but 1 was given",
                                                               "7:7 macro 'F' takes 2 arguments, but 1 was given",
                                                               "8:7 macro 'F' takes 2 arguments, but 3 were given",
                                                               "9:3 macro 'F' takes 2 arguments, but 1 was given",
                                                               "10:8 macro 'F' takes 2 arguments, but 1 was given",
                                                               "11:3 'y' is not declared"}))
      << r.text();
}

// A call whose ')' never comes took the rest of the program as its
// arguments; the parser then said "expected an expression before end of
// file" and that the task's '{' was not closed, both about the one ')'.
TEST(HelpfulDiagnostics, AMacroCallLeftOpenIsOneError) {
  auto r = run_frontend("#define F(a) ((a) + 1)\nint x;\ntask main() { x = F(2; }\n");
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"3:19: error: unterminated argument list invoking macro 'F'"}))
      << r.text();
}

// A /* never closed took the rest of the file, and the preprocessor and the
// parser then reported what was missing at its end: the #endif of the #if
// 0 around it, and the task's '}'. The comment is the one error, as with nqc.
TEST(HelpfulDiagnostics, ACommentNeverClosedIsOneError) {
  auto r = run_frontend("int x;\ntask main() {\n#if 0\n  /* never closed\n#endif\n  x = 1;\n}\n");
  EXPECT_EQ(r.brief(), (std::vector<std::string>{"4:3: error: unterminated /* comment"})) << r.text();
  auto plain = run_frontend("int x;\ntask main() {\n  /* never closed\n  x = 1;\n}\n");
  EXPECT_EQ(plain.brief(), (std::vector<std::string>{"3:3: error: unterminated /* comment"})) << plain.text();
}

}  // namespace

// A string left open takes the rest of its line, and with it the `);` the
// call needed: the parse then failed at the next line's '}' and said so, a
// second error for the one mistake (the thirteenth faithfulness round).
// A stray character likewise: the syntax error right after it is the same
// mistake. An error further on is still reported.
TEST(HelpfulDiagnostics, NoSyntaxErrorRightAfterTextTheLexerCouldNotRead) {
  auto open_string = run_frontend("task main()\n{\n  PlaySound(\"click);\n}\n");
  EXPECT_EQ(placed_messages(open_string.diags),
            (std::vector<std::string>{"3:13 missing terminating \" character"}))
      << open_string.text();
  auto stray = run_frontend("int x;\ntask main()\n{\n  x = `;\n  x = 1 2;\n}\n");
  EXPECT_EQ(placed_messages(stray.diags),
            (std::vector<std::string>{"4:7 stray character '`' in program",
                                      "5:9 expected an operator or ';' before '2': two values stand side by side; "
                                      "write the operator between them (as in '1 + 2')"}))
      << stray.text();
}

// Where a statement goes the parser said "expected an expression": before
// a '}' that ends a body a `repeat (3)` still needed, before an `else` an
// extra ';' parted from its `if`, before a `task` a missing '}' let into a
// body (the thirteenth faithfulness round).
TEST(HelpfulDiagnostics, WhereAStatementGoesTheMessageSaysSo) {
  auto body = run_frontend("task main()\n{\n  repeat (3)\n}\n");
  EXPECT_EQ(placed_messages(body.diags), (std::vector<std::string>{"4:1 expected a statement before '}'"}))
      << body.text();
  auto dangling = run_frontend("int x;\ntask main()\n{\n  if (x) x = 1;;\n  else x = 2;\n}\n");
  EXPECT_EQ(placed_messages(dangling.diags),
            (std::vector<std::string>{"5:3 'else' without an 'if' before it: a statement stands between them (an "
                                      "extra ';' is an empty statement, and two statements after an 'if' need "
                                      "braces)"}))
      << dangling.text();
  auto nested = run_frontend("task main()\n{\n  On(OUT_A);\n\nsub s() { }\n");
  ASSERT_FALSE(nested.diags.all().empty());
  EXPECT_EQ(placed_messages(nested.diags).front(),
            "5:1 'sub' cannot stand inside a task, sub or function: is a '}' missing before it?")
      << nested.text();
}

// An if's '}' left out before its else, in the else's column (a long
// program's missing brace, faithfulness round 17): the message said a
// statement stood between the if and the else, and the reader looked for
// a ';'. An else that sits elsewhere keeps that message.
TEST(HelpfulDiagnostics, AnElseInsideItsIfsOpenBracesAsksForTheMissingBrace) {
  auto missing = run_frontend("int x;\ntask main()\n{\n  if (x > 6)\n  {\n    x = 1;\n\n  else\n  {\n    x = 2;\n  }\n}\n");
  ASSERT_FALSE(missing.diags.all().empty()) << missing.text();
  EXPECT_EQ(placed_messages(missing.diags)[0], "8:3 'else' inside the braces of the 'if' on line 4: is a '}' missing "
                                               "before it?")
      << missing.text();
  ASSERT_EQ(missing.diags.all()[0].notes.size(), 1u) << missing.text();
  EXPECT_EQ(missing.diags.all()[0].notes[0].span.begin.line, 4u) << missing.text();
  EXPECT_EQ(missing.diags.all()[0].notes[0].span.begin.column, 3u) << missing.text();
  // Not in the if's column: not said to be the if's.
  auto elsewhere = run_frontend("int x;\ntask main()\n{\n  if (x > 6) {\n    x = 1;\n    else x = 2;\n  }\n}\n");
  ASSERT_FALSE(elsewhere.diags.all().empty()) << elsewhere.text();
  EXPECT_EQ(placed_messages(elsewhere.diags)[0].substr(0, 47), "6:5 'else' without an 'if' before it: a stateme")
      << elsewhere.text();
}

// A keyword as a new name said "expected identifier or '*' before 'repeat'"
// (the '*' of a pointer declarator the RCX refuses anyway; the thirteenth
// faithfulness round).
TEST(HelpfulDiagnostics, AKeywordAsANewNameSaysItIsAKeyword) {
  auto placed_first = [](const char* text) {
    auto r = run_frontend(text);
    return r.diags.all().empty() ? std::string("none") : placed_messages(r.diags).front();
  };
  const std::string says = " is a keyword of NQC and cannot be a name: choose another";
  EXPECT_EQ(placed_first("int repeat;\ntask main() { }\n"), "1:5 'repeat'" + says);
  EXPECT_EQ(placed_first("int a, for;\ntask main() { }\n"), "1:8 'for'" + says);
  EXPECT_EQ(placed_first("task while() { }\ntask main() { }\n"), "1:6 'while'" + says);
  EXPECT_EQ(placed_first("void f(int &case) { }\ntask main() { }\n"), "1:13 'case'" + says);
}

// One error for each of two mistakes that gave two (the thirteenth
// faithfulness round): a '}' left out before `task main()` also said the
// program has no task main (the parser had set main aside); `task main();`
// with its body after it also said "expected a declaration before '{'".
TEST(HelpfulDiagnostics, AMainTheParserSetAsideOrASemicolonBeforeABodyIsOneError) {
  auto open_body = run_frontend("task helper()\n{\n  On(OUT_A);\n\ntask main()\n{\n  start helper;\n}\n");
  EXPECT_EQ(placed_messages(open_body.diags),
            (std::vector<std::string>{"5:1 'task' cannot stand inside a task, sub or function: is a '}' missing "
                                      "before it?"}))
      << open_body.text();
  auto semicolon = run_frontend("task main();\n{\n  On(OUT_A);\n}\n");
  EXPECT_EQ(placed_messages(semicolon.diags),
            (std::vector<std::string>{"1:12 the ';' ends the task 'main' before its body: leave it out"}))
      << semicolon.text();
  auto function = run_frontend("void f();\n{\n}\ntask main() { f(); }\n");
  EXPECT_EQ(placed_messages(function.diags),
            (std::vector<std::string>{"1:9 the ';' ends the function 'f' before its body: leave it out"}))
      << function.text();
  // Without a body after it, the ';' keeps its message, and the program is
  // whole: a missing main is still said.
  auto alone = run_frontend("task t();\ntask t() { }\n");
  EXPECT_EQ(placed_messages(alone.diags).size(), 2u) << alone.text();
}

// A case label without its ':' said "syntax error at 'x'" (the thirteenth
// faithfulness round); before a ';' it said "expected ':'" alone.
TEST(HelpfulDiagnostics, ACaseLabelWithoutItsColonSaysSo) {
  auto r = run_frontend("int x;\ntask main()\n{\n  switch (x) {\n    case 1 x = 2; break;\n  }\n}\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{"5:12 expected ':' before 'x': a case label ends with ':' ('case 1: ...')"}))
      << r.text();
  auto semicolon = run_frontend("int x;\ntask main()\n{\n  switch (x) { case 1; x = 2; }\n}\n");
  EXPECT_EQ(placed_messages(semicolon.diags),
            (std::vector<std::string>{"4:22 expected ':' before ';': a case label ends with ':' ('case 1: ...')"}))
      << semicolon.text();
}

// A head without its '{' said "expected ';' or '{'" at the head's end (the
// thirteenth faithfulness round): a ';' there is no declaration NQC has.
TEST(HelpfulDiagnostics, AHeadWithoutItsBraceAsksForTheBrace) {
  auto task = run_frontend("task main()\n  On(OUT_A);\n}\n");
  EXPECT_EQ(placed_messages(task.diags),
            (std::vector<std::string>{"2:3 expected '{' before 'On': the body goes between braces after the head"}))
      << task.text();
  auto function = run_frontend("void f(int x)\n  x++;\n}\ntask main() { }\n");
  EXPECT_EQ(placed_messages(function.diags),
            (std::vector<std::string>{"2:3 expected '{' before 'x': the body goes between braces after the head"}))
      << function.text();
}

// Four mistakes left from the thirteenth faithfulness round, each said once
// and for what it is (the fourteenth round).
// A call of the RCX 2 firmware's API with an RCX 2 constant among its
// arguments said two errors for the one line: the call is the mistake.
TEST(HelpfulDiagnostics, AnRcx2CallIsOneErrorWithItsRcx2Arguments) {
  auto r = run_frontend("task main()\n{\n  SetEvent(1, SENSOR_1, EVENT_TYPE_PRESSED);\n}\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{"3:3 'SetEvent' is not declared (it belongs to the RCX 2 firmware's API; this "
                                      "target is the RCX)"}))
      << r.text();
  // Apart from such a call, an RCX 2 name is still said; so is a name
  // misspelt among the call's arguments.
  auto apart = run_frontend("int x;\ntask main()\n{\n  SetEvent(1, SENSR_1, 2);\n  x = EVENT_TYPE_PRESSED;\n}\n");
  auto said = placed_messages(apart.diags);
  auto has = [&](const std::string& start) {
    return std::any_of(said.begin(), said.end(), [&](const std::string& m) { return m.rfind(start, 0) == 0; });
  };
  EXPECT_EQ(said.size(), 3u) << apart.text();
  EXPECT_TRUE(has("4:3 'SetEvent' is not declared (it belongs to the RCX 2")) << apart.text();
  EXPECT_TRUE(has("4:15 'SENSR_1' is not declared; did you mean 'SENSOR_1'?")) << apart.text();
  EXPECT_TRUE(has("5:7 'EVENT_TYPE_PRESSED' is not declared (it belongs to the RCX 2")) << apart.text();
}

// `x = 3 + * 4;` said "the RCX has no pointers": a '*' right after an
// operator is an operand left out, as nqc's syntax error there says.
TEST(HelpfulDiagnostics, AStarRightAfterAnOperatorIsAMissingOperand) {
  auto r = run_frontend("int x;\ntask main()\n{\n  x = 3 + * 4;\n}\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{"4:11 expected an expression after '+' before '*': two operators stand side "
                                      "by side"}))
      << r.text();
  auto shifted = run_frontend("int x;\ntask main()\n{\n  x = x << * 2;\n}\n");
  EXPECT_EQ(placed_messages(shifted.diags),
            (std::vector<std::string>{"4:12 expected an expression after '<<' before '*': two operators stand "
                                      "side by side"}))
      << shifted.text();
  // Where a value starts, the '*' is still a dereference.
  auto deref = run_frontend("int x, p;\ntask main()\n{\n  x = *p;\n}\n");
  EXPECT_EQ(placed_messages(deref.diags),
            (std::vector<std::string>{"4:7 the RCX has no pointers, so nothing can be dereferenced"}))
      << deref.text();
}

// `a = a + 1;` with `a` never declared said so at the second `a` (the
// value is checked before the target): once, at the first use, as C does.
TEST(HelpfulDiagnostics, AnUndeclaredNameIsSaidOnceAtItsFirstUse) {
  auto r = run_frontend("task main()\n{\n  a = a + 1;\n  a++;\n  b += a + c;\n}\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{"3:3 'a' is not declared", "5:3 'b' is not declared",
                                      "5:12 'c' is not declared"}))
      << r.text();
}

// `if (x > 1)) x = 0;` said "expected a statement before ')'": the ')' is
// one too many.
TEST(HelpfulDiagnostics, AParenthesisClosedTwiceIsUnmatched) {
  auto r = run_frontend("int x;\ntask main()\n{\n  if (x > 1)) x = 0;\n  x = 2;\n}\n");
  EXPECT_EQ(placed_messages(r.diags),
            (std::vector<std::string>{"4:13 unmatched ')': no '(' before it is open; leave it out"}))
      << r.text();
  auto value = run_frontend("int x;\ntask main()\n{\n  x = (x + 1));\n}\n");
  EXPECT_EQ(placed_messages(value.diags),
            (std::vector<std::string>{"4:14 unmatched ')': no '(' before it is open; leave it out"}))
      << value.text();
  auto loop = run_frontend("int i;\ntask main()\n{\n  for (i = 0; i < 3; i++)) Wait(1);\n}\n");
  EXPECT_EQ(placed_messages(loop.diags),
            (std::vector<std::string>{"4:26 unmatched ')': no '(' before it is open; leave it out"}))
      << loop.text();
  // A ')' that closes an open '(' too early is another mistake.
  auto early = run_frontend("int x;\ntask main()\n{\n  Wait(x +);\n}\n");
  ASSERT_EQ(placed_messages(early.diags).size(), 1u) << early.text();
  EXPECT_EQ(placed_messages(early.diags)[0].find("unmatched"), std::string::npos) << early.text();
}

// Three mistakes of the fourteenth faithfulness round that were said twice
// or as another: `int 3x;` also said "expected identifier or '*'" at the
// number already refused; `int main()` said both "write 'void main(...)'"
// and "write 'task main()'"; `task = 1;` asked whether a '}' was missing.
TEST(HelpfulDiagnostics, ANumberANameCannotBeAndCsMainAndAKeywordAsAVariableAreOneErrorEach) {
  auto number = run_frontend("int 3x;\ntask main()\n{\n}\n");
  EXPECT_EQ(placed_messages(number.diags), (std::vector<std::string>{"1:5 invalid number '3x'"})) << number.text();
  auto c_main = run_frontend("int main()\n{\n  On(OUT_A);\n}\n");
  EXPECT_EQ(placed_messages(c_main.diags),
            (std::vector<std::string>{"1:1 the RCX starts a program at a task: write 'task main()' for C's 'int "
                                      "main(...)'"}))
      << c_main.text();
  auto keyword = run_frontend("task main()\n{\n  task = 1;\n}\n");
  EXPECT_EQ(placed_messages(keyword.diags),
            (std::vector<std::string>{"3:3 'task' is a keyword of NQC and cannot be a name: choose another"}))
      << keyword.text();
  // A task head inside a body is still a '}' left out.
  auto nested = run_frontend("task main()\n{\n  On(OUT_A);\ntask t()\n{\n}\n");
  ASSERT_FALSE(nested.diags.all().empty());
  EXPECT_EQ(placed_messages(nested.diags).front(),
            "4:1 'task' cannot stand inside a task, sub or function: is a '}' missing before it?");
}

// `repeat 3 { ... }` said "a call needs parentheses around its arguments:
// write 'repeat(3)'": a statement's head is no call (the fourteenth
// faithfulness round).
TEST(HelpfulDiagnostics, AStatementHeadWithoutParenthesesIsNoCall) {
  auto repeat = run_frontend("int x;\ntask main()\n{\n  repeat 3 { x++; }\n}\n");
  EXPECT_EQ(placed_messages(repeat.diags),
            (std::vector<std::string>{"4:10 'repeat' needs its count in parentheses: write 'repeat (3)'"}))
      << repeat.text();
  auto loop = run_frontend("int x;\ntask main()\n{\n  while 1 { x++; }\n}\n");
  EXPECT_EQ(placed_messages(loop.diags),
            (std::vector<std::string>{"4:9 'while' needs its condition in parentheses: write 'while (1)'"}))
      << loop.text();
  auto call = run_frontend("task main()\n{\n  Wait 100;\n}\n");
  EXPECT_EQ(placed_messages(call.diags),
            (std::vector<std::string>{"3:8 a call needs parentheses around its arguments: write 'Wait(100)'"}))
      << call.text();
}

// `int &flag = 1;` in a body (a program from elsewhere that used pointers,
// rewritten with '&') said "expected identifier or '*' before '&'": the '*'
// of a pointer the RCX refuses, and nothing about references being for
// parameters only.
TEST(HelpfulDiagnostics, AReferenceVariableOutsideAParameterListSaysReferencesAreParameters) {
  auto placed_first = [](const char* text) {
    auto r = run_frontend(text);
    return r.diags.all().empty() ? std::string("none") : placed_messages(r.diags).front();
  };
  const std::string says = " a '&' reference can only be a parameter (void f(int &x)): a variable is a plain int";
  EXPECT_EQ(placed_first("task main()\n{\n  int &flag = 1;\n}\n"), "3:7" + says);
  EXPECT_EQ(placed_first("int &g;\ntask main() { }\n"), "1:5" + says);
  EXPECT_EQ(placed_first("void f(int &x) { x = 1; }\ntask main() { int y; f(y); }\n"), "none");
}

// C's `int main()` with `return 0;` at its end (faithfulness round 15): the
// return's value is part of the same C habit, and said "'return' takes no
// value" a second time. Elsewhere the return's own error stays.
TEST(HelpfulDiagnostics, CsMainReturningAValueIsOneError) {
  auto c_main = run_frontend("int main()\n{\n  On(OUT_A);\n  if (1) return 1;\n  return 0;\n}\n");
  EXPECT_EQ(placed_messages(c_main.diags),
            (std::vector<std::string>{"1:1 the RCX starts a program at a task: write 'task main()' for C's 'int "
                                      "main(...)'"}))
      << c_main.text();
  auto after = run_frontend("int main()\n{\n  return 0;\n}\nvoid f() { return 2; }\n");
  ASSERT_EQ(after.diags.all().size(), 2u) << after.text();
  EXPECT_EQ(placed_messages(after.diags)[1].substr(0, 32), "5:19 'return' takes no value in ") << after.text();
  auto task = run_frontend("task main()\n{\n  return 0;\n}\n");
  ASSERT_EQ(task.diags.all().size(), 1u) << task.text();
  EXPECT_EQ(placed_messages(task.diags)[0].substr(0, 32), "3:10 'return' takes no value in ") << task.text();
}

// A name not declared in two bodies was said once per body (faithfulness
// round 14's dx40): nqc says it once. One error at the first use in the
// source, with the first use in another body as a note; the bodies are
// checked in another order than the source's (tasks before subs), and the
// error still stands at the sub's use when the sub comes first.
TEST(HelpfulDiagnostics, ANameNotDeclaredInSeveralBodiesIsOneErrorWithANote) {
  auto tasks = run_frontend("task left()\n{\n  speed = 3;\n}\ntask main()\n{\n  speed = 5;\n  start left;\n}\n");
  ASSERT_EQ(tasks.diags.all().size(), 1u) << tasks.text();
  EXPECT_EQ(placed_messages(tasks.diags)[0], "3:3 'speed' is not declared") << tasks.text();
  ASSERT_EQ(tasks.diags.all()[0].notes.size(), 1u) << tasks.text();
  EXPECT_EQ(tasks.diags.all()[0].notes[0].span.begin.line, 7u) << tasks.text();
  EXPECT_EQ(tasks.diags.all()[0].notes[0].message, "'speed' is also used here (a name not declared is reported once)");
  auto sub_first = run_frontend("sub s()\n{\n  count = 0;\n}\ntask main()\n{\n  s();\n  count++;\n  count++;\n}\n");
  ASSERT_EQ(sub_first.diags.all().size(), 1u) << sub_first.text();
  EXPECT_EQ(placed_messages(sub_first.diags)[0], "3:3 'count' is not declared") << sub_first.text();
  ASSERT_EQ(sub_first.diags.all()[0].notes.size(), 1u) << sub_first.text();
  EXPECT_EQ(sub_first.diags.all()[0].notes[0].span.begin.line, 8u) << sub_first.text();
}

// The Scout's, CyberMaster's and Spybot's names said only "not declared"
// (faithfulness round 14's ap29-ap35), or offered an RCX name ('SetScoutMode':
// "did you mean 'SensorMode'?"); the RCX 2 names already said which firmware
// has them. The other target's names among such a call's arguments are that
// one mistake.
TEST(HelpfulDiagnostics, AnotherTargetsNameSaysWhichTargetHasIt) {
  EXPECT_TRUE(rcxc::frontend::other_target_lists_are_sorted());
  auto scout = run_frontend("task main()\n{\n  SetScoutMode(SCOUT_MODE_STANDALONE);\n  SendVLL(3);\n}\n");
  EXPECT_EQ(placed_messages(scout.diags),
            (std::vector<std::string>{
                "3:3 'SetScoutMode' is not declared: it is a Scout function; rcxc compiles for the RCX",
                "4:3 'SendVLL' is not declared: it is a Scout and Spybot function; rcxc compiles for the RCX"}))
      << scout.text();
  auto cm = run_frontend("int c;\ntask main()\n{\n  OnFwd(OUT_L);\n  c = TachoCount(OUT_L);\n}\n");
  EXPECT_EQ(placed_messages(cm.diags),
            (std::vector<std::string>{
                "4:9 'OUT_L' is not declared: it is a CyberMaster name; rcxc compiles for the RCX",
                "5:7 'TachoCount' is not declared: it is a CyberMaster function; rcxc compiles for the RCX"}))
      << cm.text();
  auto spy = run_frontend("task main()\n{\n  PlaySound(SOUND_OUCH);\n}\n");
  EXPECT_EQ(placed_messages(spy.diags),
            (std::vector<std::string>{
                "3:13 'SOUND_OUCH' is not declared: it is a Spybot name; rcxc compiles for the RCX"}))
      << spy.text();
  // The RCX 2 prefix ACQUIRE_ took the Spybot's ACQUIRE_LED for an RCX 2
  // name; the RCX 2's own resources still say RCX 2.
  auto led = run_frontend("int r;\ntask main()\n{\n  r = ACQUIRE_LED;\n  r = ACQUIRE_OUT_A;\n}\n");
  EXPECT_EQ(placed_messages(led.diags),
            (std::vector<std::string>{
                "4:7 'ACQUIRE_LED' is not declared: it is a Spybot name; rcxc compiles for the RCX",
                "5:7 'ACQUIRE_OUT_A' is not declared (it belongs to the RCX 2 firmware's API; this target is the RCX)"}))
      << led.text();
  // A name no target has still gets its suggestion.
  auto typo = run_frontend("task main()\n{\n  PlaySound(SOUND_CLIK);\n}\n");
  EXPECT_EQ(placed_messages(typo.diags),
            (std::vector<std::string>{"3:13 'SOUND_CLIK' is not declared; did you mean 'SOUND_CLICK'?"}))
      << typo.text();
}

// The Swan firmware's names (nqc -TSwan: MessageParam, SetMotorPowerSigned,
// MTR_A, OUT_D, ...) said only "not declared" (left from faithfulness round
// 15). The Swan runs on the RCX brick, so the message names the firmware;
// the Swan names among a Swan call's arguments are that one mistake, and a
// Swan name the RCX 2 prefix EVENT_TYPE_ would match is still the Swan's.
TEST(HelpfulDiagnostics, ASwanFirmwareNameSaysItIsTheSwans) {
  const std::string tail = " (nqc -TSwan); rcxc compiles for the RCX's standard firmware";
  auto swan = run_frontend(
      "int p;\ntask main()\n{\n  p = MessageParam();\n  SetMotorPowerSigned(MTR_A, p);\n  On(OUT_D);\n"
      "  p = EVENT_TYPE_RESET;\n}\n");
  EXPECT_EQ(placed_messages(swan.diags),
            (std::vector<std::string>{"4:7 'MessageParam' is not declared: it is a Swan firmware function" + tail,
                                      "5:3 'SetMotorPowerSigned' is not declared: it is a Swan firmware function" + tail,
                                      "6:6 'OUT_D' is not declared: it is a Swan firmware name" + tail,
                                      "7:7 'EVENT_TYPE_RESET' is not declared: it is a Swan firmware name" + tail}))
      << swan.text();
}

// `asm { 0x51 0x01 }` said "expected '}' before '0x01'" (faithfulness round
// 14's dx26): the ',' between the bytes is what is missing. Mnemonic lines,
// which have no commas between them, keep their own message.
TEST(HelpfulDiagnostics, AnAsmByteListWithoutACommaAsksForTheComma) {
  const std::string says = " expected ',' before '0x01': the bytes of an asm block are separated by commas "
                           "(asm { 0x51, 0x01 })";
  auto two = run_frontend("task main()\n{\n  asm { 0x51 0x01 };\n}\n");
  EXPECT_EQ(placed_messages(two.diags), (std::vector<std::string>{"3:14" + says})) << two.text();
  auto later = run_frontend("task main()\n{\n  asm { 0x13, 0x07 0x01, 0x07 };\n}\n");
  EXPECT_EQ(placed_messages(later.diags), (std::vector<std::string>{"3:20" + says})) << later.text();
  auto fine = run_frontend("task main()\n{\n  asm { 0x51, 0x01 };\n}\n");
  EXPECT_TRUE(fine.diags.all().empty()) << fine.text();
  auto lines = run_frontend("task main()\n{\n  asm { pwr ABC, 7 dir ABC, fwd };\n}\n");
  ASSERT_FALSE(lines.diags.all().empty());
  EXPECT_EQ(placed_messages(lines.diags)[0].find("the bytes of an asm block"), std::string::npos) << lines.text();
}

// `if (SENSOR_1 = 1)`, the student's '=' for '==' (faithfulness round 15's
// rs02, dg09): the error said the sensor cannot be assigned, and only a
// warning after it asked for '=='. The error asks itself, once.
TEST(HelpfulDiagnostics, AnAssignmentToASensorAsAConditionAsksForDoubleEquals) {
  auto sensor = run_frontend("task main()\n{\n  until (SENSOR_1 = 1);\n  if (Timer(0) = 5) Off(OUT_A);\n}\n");
  ASSERT_EQ(sensor.diags.all().size(), 2u) << sensor.text();
  for (const auto& d : sensor.diags.all()) {
    EXPECT_EQ(d.severity, rcxc::Severity::Error) << sensor.text();
    EXPECT_NE(d.message.find("which a program can read and not assign; did you mean '=='?"), std::string::npos)
        << sensor.text();
  }
  // A variable assigned in a condition is still only a warning.
  auto variable = run_frontend("int x;\ntask main()\n{\n  if (x = 1) Off(OUT_A);\n}\n");
  ASSERT_EQ(variable.diags.all().size(), 1u) << variable.text();
  EXPECT_EQ(variable.diags.all()[0].message, "assignment used as a condition; did you mean '=='?");
  // An assignment that is not the whole condition gets no hint.
  auto inner = run_frontend("task main()\n{\n  SENSOR_1 = 1;\n}\n");
  ASSERT_EQ(inner.diags.all().size(), 1u) << inner.text();
  EXPECT_EQ(inner.diags.all()[0].message.find("did you mean"), std::string::npos) << inner.text();
}

// Other languages' `elsif`/`elseif`/`elif` (faithfulness round 15's rs39,
// dg08) said "expected an operator or ';' before 'OnRev': two values stand
// side by side"; what was meant is `else if`.
TEST(HelpfulDiagnostics, ElsifAsksForElseIf) {
  for (std::string word : {"elsif", "elseif", "elif"}) {
    auto r = run_frontend("int x;\ntask main()\n{\n  if (x == 0) On(OUT_A);\n  " + word +
                          " (x == 1) { Off(OUT_A); }\n  else Off(OUT_C);\n}\n");
    ASSERT_FALSE(r.diags.all().empty()) << word;
    EXPECT_EQ(placed_messages(r.diags)[0], "5:3 '" + word + "' is not NQC: write 'else if (...)'") << r.text();
  }
  auto same_line = run_frontend("int x;\ntask main()\n{\n  if (x == 0) On(OUT_A); elsif (x == 1) Off(OUT_A);\n}\n");
  ASSERT_FALSE(same_line.diags.all().empty());
  EXPECT_EQ(placed_messages(same_line.diags)[0], "4:26 'elsif' is not NQC: write 'else if (...)'") << same_line.text();
}

// `#define THRESHOLD 40;` used in a condition or an argument (faithfulness
// round 15's rs04, dg07) said "expected ')' before ';'" with the macro as a
// note: why a ';' stood there was left to the reader.
TEST(HelpfulDiagnostics, AMacroEndingInASemicolonSaysSo) {
  auto arg = run_frontend("#define SPEED 5;\ntask main()\n{\n  SetPower(OUT_A, SPEED);\n}\n");
  ASSERT_FALSE(arg.diags.all().empty());
  EXPECT_EQ(arg.diags.all()[0].message,
            "expected ')' before ';': the ';' ends a macro's text (a #define needs no ';' at its end)")
      << arg.text();
  auto condition = run_frontend("#define LIMIT 40;\ntask main()\n{\n  if (SENSOR_2 > LIMIT) Off(OUT_A);\n}\n");
  ASSERT_FALSE(condition.diags.all().empty());
  EXPECT_EQ(condition.diags.all()[0].message,
            "expected ')' before ';': the ';' ends a macro's text (a #define needs no ';' at its end)")
      << condition.text();
  // A ';' of the user's own where a ')' is missing keeps the plain message.
  auto own = run_frontend("task main()\n{\n  OnFwd(OUT_A;\n}\n");
  ASSERT_FALSE(own.diags.all().empty());
  EXPECT_EQ(own.diags.all()[0].message, "expected ')' before ';'") << own.text();
}

// `#define THRESHOLD 40;` in `if (SENSOR_1 > THRESHOLD) { ... }` inside a
// loop (left from faithfulness round 15): the first error was right, but the
// recovery took the ';' as a statement of the enclosing block, the ')' and
// the if's body after it ended that block early, and the task's last '}'
// drew "expected a declaration". A condition that does not parse now
// resumes at its ')', or at the '{' where the ')' is left out, and the body
// and its else stay the if's. A syntax mistake inside the body is still said.
TEST(HelpfulDiagnostics, AConditionThatDoesNotParseIsOneError) {
  const std::string ends = "expected ')' before ';': the ';' ends a macro's text (a #define needs no ';' at its end)";
  // The shape that drew the second error: no else, in a loop's block.
  auto looped = run_frontend(
      "#define THRESHOLD 40;\ntask main()\n{\n  SetSensor(SENSOR_1, SENSOR_LIGHT);\n  while (true) {\n"
      "    if (SENSOR_1 > THRESHOLD) {\n      OnFwd(OUT_A);\n    }\n  }\n}\ntask other()\n{\n  Off(OUT_A);\n}\n");
  ASSERT_EQ(looped.diags.all().size(), 1u) << looped.text();
  EXPECT_EQ(looped.diags.all()[0].message, ends) << looped.text();
  // With an else, and without braces, it was one error already; so it stays.
  auto braced = run_frontend(
      "#define THRESHOLD 40;\ntask main()\n{\n  SetSensor(SENSOR_1, SENSOR_LIGHT);\n  while (true)\n  {\n"
      "    if (SENSOR_1 > THRESHOLD)\n    {\n      OnFwd(OUT_A);\n    }\n    else\n    {\n      Off(OUT_A);\n"
      "    }\n  }\n}\n");
  ASSERT_EQ(braced.diags.all().size(), 1u) << braced.text();
  EXPECT_EQ(braced.diags.all()[0].message, ends) << braced.text();
  auto unbraced =
      run_frontend("#define LIMIT 40;\ntask main()\n{\n  if (SENSOR_2 > LIMIT) Off(OUT_A); else On(OUT_A);\n  Wait(5);\n}\n");
  ASSERT_EQ(unbraced.diags.all().size(), 1u) << unbraced.text();
  EXPECT_EQ(unbraced.diags.all()[0].message, ends) << unbraced.text();
  // The ')' left out: the body's '{' ends the condition, not a ')' in it.
  auto open = run_frontend("int x;\ntask main()\n{\n  if (x > 3 {\n    OnFwd(OUT_A);\n  }\n  x = 1;\n}\n");
  ASSERT_EQ(open.diags.all().size(), 1u) << open.text();
  EXPECT_EQ(placed_messages(open.diags)[0], "4:13 expected ')' before '{'") << open.text();
  // A mistake of the body's own is still said.
  auto body = run_frontend("#define LIMIT 40;\nint x;\ntask main()\n{\n  if (SENSOR_2 > LIMIT) { x = 1 2; }\n}\n");
  ASSERT_EQ(body.diags.all().size(), 2u) << body.text();
  EXPECT_EQ(placed_messages(body.diags)[1].substr(0, 36), "5:33 expected an operator or ';' bef") << body.text();
}

// A macro that is two statements (`#define BACKUP OnRev(OUT_A); Wait(20)`)
// or a block (`#define TURN { ... }`) before an else (faithfulness round 16's
// pp07, pp08): the error at the else said a statement stood between, and the
// macro, the cause, was nowhere in it. A note now points into the macro.
TEST(HelpfulDiagnostics, AMacroThatEndsTheIfBeforeItsElseIsNamed) {
  auto two = run_frontend("#define BACKUP OnRev(OUT_A); Wait(20)\ntask main()\n{\n  if (SENSOR_1 == 1)\n"
                          "    BACKUP;\n  else\n    Off(OUT_A);\n}\n");
  ASSERT_EQ(two.diags.all().size(), 1u) << two.text();
  EXPECT_EQ(placed_messages(two.diags)[0].substr(0, 47), "6:3 'else' without an 'if' before it: a stateme") << two.text();
  ASSERT_FALSE(two.diags.all()[0].notes.empty()) << two.text();
  EXPECT_EQ(two.diags.all()[0].notes[0].message.substr(0, 45), "this ';' in the macro's text ends the 'if' st")
      << two.text();
  auto block = run_frontend("#define TURN { OnRev(OUT_A); Wait(10); }\ntask main()\n{\n  if (SENSOR_1 == 1)\n"
                            "    TURN;\n  else\n    Off(OUT_A);\n}\n");
  ASSERT_EQ(block.diags.all().size(), 1u) << block.text();
  ASSERT_FALSE(block.diags.all()[0].notes.empty()) << block.text();
  EXPECT_EQ(block.diags.all()[0].notes[0].message.substr(0, 42), "the macro's text is a block, so the ';' wr")
      << block.text();
  // The user's own two statements, or an extra ';', have no macro to name.
  auto own = run_frontend("task main()\n{\n  if (SENSOR_1 == 1)\n    OnRev(OUT_A); Wait(20);\n  else\n    Off(OUT_A);\n}\n");
  ASSERT_EQ(own.diags.all().size(), 1u) << own.text();
  EXPECT_TRUE(own.diags.all()[0].notes.empty()) << own.text();
}

// An `int &` argument that is a value of the brick (`f(Timer(0))`) said only
// "must be a variable" (faithfulness round 16's rf12; nqc: "argument must
// be a variable"); it now says which value it is, as `Timer(0) = 3` does.
TEST(HelpfulDiagnostics, AReferenceGivenAValueOfTheBrickSaysWhichValue) {
  auto r = run_frontend("void f(int &a) { a = 1; }\ntask main()\n{\n  f(Timer(0));\n  f(SENSOR_2);\n  f(3);\n}\n");
  ASSERT_EQ(r.diags.all().size(), 3u) << r.text();
  EXPECT_EQ(r.diags.all()[0].message, "argument for 'int &a' of 'f' must be a variable; this is the value of a timer, "
                                      "which a program can read and not assign")
      << r.text();
  EXPECT_EQ(r.diags.all()[1].message, "argument for 'int &a' of 'f' must be a variable; this is the value of a "
                                      "sensor, which a program can read and not assign")
      << r.text();
  EXPECT_EQ(r.diags.all()[2].message, "argument for 'int &a' of 'f' must be a variable") << r.text();
}

// `Wa\` at the end of a line and `it(10);` on the next: C splices the lines
// first and reads `Wait(10);`; rcxc, like nqc, reads a backslash-newline as
// a space, and said only "expected ';' before 'it'".
TEST(HelpfulDiagnostics, ABackslashSplittingAWordSaysLinesAreJoinedNotWords) {
  const std::string said =
      "a backslash at the end of the line splits 'Wait' in two: 'Wa' and 'it' are two words, because a backslash "
      "joins lines, not words (C would join them); write 'Wait' on one line";
  auto r = run_frontend("task main()\n{\n  Wa\\\nit(10);\n}\n");
  EXPECT_EQ(placed_messages(r.diags), (std::vector<std::string>{"4:1 " + said})) << r.text();
  // The same inside a #define, where a backslash is most often written.
  auto in_macro = run_frontend("#define PAUSE Wa\\\nit(10)\ntask main()\n{\n  PAUSE;\n}\n");
  ASSERT_EQ(in_macro.diags.all().size(), 1u) << in_macro.text();
  EXPECT_EQ(in_macro.diags.all()[0].message, said);
  // A backslash between words that a space parts anyway is no split, and
  // one that joins the lines of a #define between tokens still does.
  EXPECT_TRUE(run_frontend("#define PAUSE Wait( \\\n10)\ntask main()\n{\n  PAUSE;\n  Wait \\\n(10);\n}\n")
                  .diags.all().empty());
  auto spaced = run_frontend("int a;\ntask main()\n{\n  int b \\\nc;\n}\n");
  ASSERT_FALSE(spaced.diags.all().empty());
  EXPECT_EQ(spaced.diags.all()[0].message.find("backslash"), std::string::npos) << spaced.text();
}

// `#define X X + 1` then `int X;`: the inner X is left as it is and the
// parser read `int X + 1;`, so a second error ("expected ';' or ',' before
// '+'") followed the one about the macro, at the same place. (`1 + X`
// gave "expected a new name, but a macro stands here" instead.)
TEST(HelpfulDiagnostics, AMacroUsedInItsOwnTextIsTheOneError) {
  const std::string recursive = "macro 'X' is defined in terms of itself (recursive macros never end)";
  for (const std::string body : {"X + 1", "1 + X", "(X)"}) {
    auto r = run_frontend("#define X " + body + "\nint X;\ntask main()\n{\n}\n");
    ASSERT_EQ(r.diags.all().size(), 1u) << body << "\n" << r.text();
    EXPECT_EQ(r.diags.all()[0].message, recursive) << body;
  }
  // A syntax error in another statement is still reported.
  auto other = run_frontend("#define X X + 1\nint X;\ntask main()\n{\n  int y z;\n}\n");
  ASSERT_EQ(other.diags.all().size(), 2u) << other.text();
  EXPECT_EQ(other.diags.all()[0].message, recursive);
  EXPECT_EQ(other.diags.all()[1].span.begin.line, 5u) << other.text();
}
