#include "frontend/diagnostics.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace rcxc;

TEST(Diagnostics, RendersGccStyleWithCaretRange) {
  SourceManager sm;
  auto f = sm.add("prog.nqc", "task main()\n{\n  x = 1;\n}\n");
  Diagnostics diags;
  diags.error({{f, 3, 3}, {f, 3, 4}}, "undefined variable 'x'");
  ASSERT_EQ(diags.error_count(), 1u);
  EXPECT_EQ(render_text(diags.all()[0], sm), "prog.nqc:3:3: error: undefined variable 'x'\n    x = 1;\n    ^\n");
}

TEST(Diagnostics, RangeUnderlinesTheWholeSpanAndNotesFollow) {
  SourceManager sm;
  auto f = sm.add("a.nqc", "int foo;\nint foo;\n");
  Diagnostics diags;
  auto& d = diags.error({{f, 2, 5}, {f, 2, 8}}, "redefinition of 'foo'");
  d.notes.push_back({{{f, 1, 5}, {f, 1, 8}}, "previous definition is here"});
  EXPECT_EQ(render_text(diags.all()[0], sm),
            "a.nqc:2:5: error: redefinition of 'foo'\n  int foo;\n      ^~~\n"
            "a.nqc:1:5: note: previous definition is here\n  int foo;\n      ^~~\n");
}

TEST(Diagnostics, JsonCarriesEveryField) {
  SourceManager sm;
  auto f = sm.add("a.nqc", "x\n");
  Diagnostics diags;
  auto& d = diags.error({{f, 1, 1}, {f, 1, 2}}, "bad");
  d.notes.push_back({{{f, 1, 1}, {f, 1, 2}}, "here"});
  auto j = nlohmann::json::parse(render_json(diags.all()[0], sm));
  EXPECT_EQ(j["file"], "a.nqc");
  EXPECT_EQ(j["line"], 1);
  EXPECT_EQ(j["column"], 1);
  EXPECT_EQ(j["end"]["column"], 2);
  EXPECT_EQ(j["severity"], "error");
  EXPECT_EQ(j["message"], "bad");
  EXPECT_EQ(j["notes"][0]["message"], "here");
}

TEST(Diagnostics, WarningsCanBePromotedOrSilenced) {
  Diagnostics promote;
  promote.policy.all_as_errors = true;
  promote.warning({}, WarningKind::UnusedVariable, "unused variable");
  EXPECT_EQ(promote.error_count(), 1u);

  Diagnostics quiet;
  quiet.policy.none = true;
  quiet.warning({}, WarningKind::UnusedVariable, "unused variable").message = "still discarded";
  EXPECT_TRUE(quiet.all().empty());
}

TEST(Diagnostics, SourceLinesHandleCrLfAndOutOfRange) {
  SourceManager sm;
  auto f = sm.add("w.nqc", "one\r\ntwo");
  EXPECT_EQ(sm.line(f, 1), "one");
  EXPECT_EQ(sm.line(f, 2), "two");
  EXPECT_EQ(sm.line(f, 3), "");
  EXPECT_EQ(sm.line(f, 0), "");
}

TEST(Diagnostics, JsonSurvivesBytesThatAreNotUtf8) {
  SourceManager sm;
  auto f = sm.add("a.nqc", "x\n");
  Diagnostics diags;
  diags.error({{f, 1, 1}, {f, 1, 2}}, std::string("bad \xfd byte"));
  auto j = nlohmann::json::parse(render_json(diags.all()[0], sm));
  EXPECT_EQ(j["message"], "bad \xef\xbf\xbd byte");  // U+FFFD
}

// Three errors with a warning between the second and third: a limit of 2
// prints the warning (it comes before the third error) and then one note
// standing for the third error.
TEST(Diagnostics, ErrorLimitStopsAtTheErrorPastTheLimit) {
  SourceManager sm;
  auto f = sm.add("a.nqc", "a\nb\nc\nd\n");
  Diagnostics diags;
  diags.error({{f, 1, 1}, {f, 1, 2}}, "first");
  diags.error({{f, 2, 1}, {f, 2, 2}}, "second");
  diags.warning({{f, 3, 1}, {f, 3, 2}}, WarningKind::UnusedValue, "a warning");
  diags.error({{f, 4, 1}, {f, 4, 2}}, "third");
  std::string limited = render_all(diags, sm, RenderOptions{false, 2});
  EXPECT_NE(limited.find("second"), std::string::npos);
  EXPECT_NE(limited.find("a warning"), std::string::npos);
  EXPECT_EQ(limited.find("third"), std::string::npos);
  EXPECT_NE(limited.find("rcxc: note: 1 more errors not shown"), std::string::npos) << limited;

  std::string all = render_all(diags, sm, RenderOptions{false, 0});
  EXPECT_NE(all.find("third"), std::string::npos);
  EXPECT_EQ(all.find("not shown"), std::string::npos);
  EXPECT_EQ(render_all(diags, sm, RenderOptions{false, 3}), all);
}

TEST(Diagnostics, ErrorLimitNoteIsJsonToo) {
  SourceManager sm;
  auto f = sm.add("a.nqc", "a\n");
  Diagnostics diags;
  for (int i = 0; i < 5; ++i) diags.error({{f, 1, 1}, {f, 1, 2}}, "bad");
  std::string out = render_all(diags, sm, RenderOptions{true, 1});
  std::vector<nlohmann::json> lines;
  std::size_t start = 0;
  for (std::size_t nl; (nl = out.find('\n', start)) != std::string::npos; start = nl + 1)
    lines.push_back(nlohmann::json::parse(out.substr(start, nl - start)));
  ASSERT_EQ(lines.size(), 2u) << out;
  EXPECT_EQ(lines[0]["severity"], "error");
  EXPECT_EQ(lines[1]["severity"], "note");
  EXPECT_EQ(lines[1]["message"], "4 more errors not shown (--max-errors=0 shows every error)");
}

// A long line is quoted as 160 bytes around the column, so thousands of
// messages on one generated line do not each print the whole line.
TEST(QuotedLine, AShortLineIsQuotedWholeWithItsTabsInTheLeadIn) {
  QuotedLine q = quote_line("\tx = 1;", 1, 1);
  EXPECT_EQ(q.text, "\tx = 1;");
  EXPECT_EQ(q.lead_in, "\t");
  EXPECT_EQ(q.width, 1u);
}

// An ESC or BEL in the source would reach the terminal raw (an OSC
// sequence retitles the window): each shows as '?', one column, so the
// caret stays under the character the message is about.
TEST(QuotedLine, ControlCharactersAreQuotedAsQuestionMarks) {
  QuotedLine q = quote_line("  \x1b]0;pwned\x07 x;\x7f", 12, 1);
  EXPECT_EQ(q.text, "  ?]0;pwned? x;?");
  EXPECT_EQ(q.lead_in, std::string(12, ' '));
}

// The message quoted the file raw where the line under it did not:
// `#error`, `#warning`, an #include name or a #pragma holding ESC [2J
// cleared the terminal of whoever compiled. Control bytes in the message
// show as \xNN (as "stray character '\x1b'" does); JSON escapes its own.
TEST(Diagnostics, ControlBytesInTheMessageAreShownNotSent) {
  SourceManager sm;
  auto f = sm.add("a.nqc", "#error hi \x1b[2J there\n");
  Diagnostics diags;
  diags.error({{f, 1, 1}, {f, 1, 7}}, "#error hi \x1b[2J there\x07\x7f");
  diags.warning({}, WarningKind::WarningDirective, "cannot read 'a\x1b]0;t\x07" "b'");
  std::string text = render_all(diags, sm, {});
  EXPECT_NE(text.find("a.nqc:1:1: error: #error hi \\x1b[2J there\\x07\\x7f\n"), std::string::npos) << text;
  EXPECT_NE(text.find("warning: cannot read 'a\\x1b]0;t\\x07b' [-Wwarning-directive]\n"), std::string::npos) << text;
  EXPECT_EQ(text.find_first_of("\x1b\x07\x7f"), std::string::npos) << text;
}

TEST(QuotedLine, ALongLineShowsAWindowCentredOnTheColumn) {
  std::string line(400, 'a');
  line[200] = 'X';
  QuotedLine q = quote_line(line, 200, 1);
  // Bytes 120..279: 80 before the column.
  EXPECT_EQ(q.text, "..." + line.substr(120, 160) + "...");
  EXPECT_EQ(q.lead_in, std::string(3 + 80, ' '));
  EXPECT_EQ(q.text[q.lead_in.size()], 'X');
}

TEST(QuotedLine, TheWindowStopsAtEitherEndOfTheLine) {
  std::string line(400, 'a');
  QuotedLine start = quote_line(line, 10, 3);
  EXPECT_EQ(start.text, line.substr(0, 160) + "...");
  EXPECT_EQ(start.lead_in, std::string(10, ' '));
  EXPECT_EQ(start.width, 3u);
  QuotedLine end = quote_line(line, 399, 1);  // bytes 240..399
  EXPECT_EQ(end.text, "..." + line.substr(240));
  EXPECT_EQ(end.lead_in, std::string(3 + 159, ' '));
}

TEST(QuotedLine, AWindowIsCutBetweenCharactersAndTheSpanClampedToIt) {
  std::string line;
  for (int i = 0; i < 300; ++i) line += "\xC3\xA9";  // é, two bytes
  // From byte 301 the window would start at 221 and end at 381, both in
  // the middle of an é: it widens to 220..382.
  QuotedLine q = quote_line(line, 301, 1000);
  EXPECT_EQ(q.text, "..." + line.substr(220, 162) + "...");
  // The caret line counts characters: 41 é (bytes 220..300, the last one's
  // first byte at 300) before the column, and 40 after it.
  EXPECT_EQ(q.lead_in, std::string(3 + 41, ' '));
  EXPECT_EQ(q.width, 40u);
}

// Columns count bytes, but the terminal shows characters: behind 'ö' the
// caret was one place right per extra byte, and a span over a two-byte
// character was "^~" under one character. A wide character (CJK) takes
// two places, a tab stays a tab.
TEST(QuotedLine, TheCaretLineCountsCharactersNotBytes) {
  QuotedLine after = quote_line("int gr\xC3\xB6\xC3\x9F" "e;", 8, 2);  // the ß of größe
  EXPECT_EQ(after.lead_in, std::string(7, ' '));
  EXPECT_EQ(after.width, 1u);
  QuotedLine wide = quote_line("\t\xE5\xA4\xA7 = x;", 7, 1);  // 大 = x;
  EXPECT_EQ(wide.lead_in, "\t" + std::string(2 + 3, ' '));
  QuotedLine over = quote_line("a \xE2\x80\x9Cxy\xE2\x80\x9D b", 2, 8);  // “xy”
  EXPECT_EQ(over.lead_in, "  ");
  EXPECT_EQ(over.width, 4u);
}

TEST(Diagnostics, ACaretGoesUnderTheWholeCharacterAfterOthers) {
  SourceManager sm;
  auto f = sm.add("a.nqc", "int gr\xC3\xB6\xC3\x9F" "e;\n");
  Diagnostics diags;
  diags.error({{f, 1, 9}, {f, 1, 11}}, "here");
  EXPECT_EQ(render_text(diags.all()[0], sm), "a.nqc:1:9: error: here\n  int gr\xC3\xB6\xC3\x9F" "e;\n         ^\n");
}

TEST(Utf8, DecodesWellFormedSequencesOnly) {
  EXPECT_EQ(decode_utf8("\xC3\xB6x").code, U'\u00F6');
  EXPECT_EQ(decode_utf8("\xC3\xB6x").length, 2u);
  EXPECT_EQ(decode_utf8("\xE2\x80\x93").code, U'\u2013');
  EXPECT_EQ(decode_utf8("\xF0\x9D\x84\x9E").code, U'\U0001D11E');
  EXPECT_EQ(decode_utf8("a").length, 1u);
  for (std::string_view bad : {"\xB6", "\xC3", "\xC3x", "\xC0\xAF", "\xE0\x80\xAF", "\xED\xA0\x80",
                               "\xF4\x90\x80\x80", "\xFD", "\xE2\x80"})
    EXPECT_EQ(decode_utf8(bad).length, 0u) << bad;
  EXPECT_EQ(decode_utf8("").length, 0u);
}
