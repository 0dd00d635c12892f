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
  promote.warnings_as_errors = true;
  promote.warning({}, "unused variable");
  EXPECT_EQ(promote.error_count(), 1u);

  Diagnostics quiet;
  quiet.suppress_warnings = true;
  quiet.warning({}, "unused variable").message = "still discarded";
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
