// The JUnit XML report of `rcxc test --junit`: well-formed whatever the
// paths and messages hold, with the counts and failures CI services read.
#include <gtest/gtest.h>

#include "verify/junit.h"

using rcx::semtest::JUnitCase;
using rcx::semtest::junit_xml;

namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(JUnit, CountsPassesFailuresAndErrors) {
  std::vector<JUnitCase> cases = {
      {"tests/a.nqc", {}, 0.25, {}},
      {"tests/b.nqc", {{4, "global 'x' is 2, expected 3"}, {0, "the run faulted"}}, 0.5, {}},
      {"no such file or folder: c", {}, 0, "no such file or folder: c"},
  };
  std::string xml = junit_xml(cases);
  EXPECT_EQ(xml.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites ", 0), 0u) << xml;
  EXPECT_NE(xml.find("<testsuite name=\"rcxc test\" tests=\"3\" failures=\"1\" errors=\"1\" skipped=\"0\" time=\"0.750\">"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("<testcase name=\"tests/a.nqc\" classname=\"rcxc test\" file=\"tests/a.nqc\" time=\"0.250\"/>"),
            std::string::npos)
      << xml;
  // Every failure of a test, each at its line, in one <failure>.
  EXPECT_NE(xml.find("<failure message=\"global &apos;x&apos; is 2, expected 3\">tests/b.nqc:4: global &apos;x&apos; "
                     "is 2, expected 3&#10;tests/b.nqc: the run faulted&#10;</failure>"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("<error message=\"no such file or folder: c\"/>"), std::string::npos) << xml;
  EXPECT_EQ(count(xml, "<testcase "), 3u);
  EXPECT_EQ(count(xml, "</testcase>"), 2u);
}

TEST(JUnit, MarkupControlBytesAndBrokenUtf8CannotBreakTheReport) {
  // A file name with markup, a control byte, a stray Latin-1 byte, an
  // overlong encoding of '<' and a surrogate; valid UTF-8 passes through.
  std::string name = "odd<&\"'>\x01\xE9\xC0\xBC\xED\xA0\x80" "caf\xC3\xA9.nqc";
  std::string xml = junit_xml({{name, {{1, "x\ty\r"}}, 0, {}}});
  const std::string expected_name = "odd&lt;&amp;&quot;&apos;&gt;\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD"
                                    "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD" "caf\xC3\xA9.nqc";
  EXPECT_NE(xml.find("name=\"" + expected_name + "\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("message=\"x&#9;y&#13;\""), std::string::npos) << xml;
  for (char c : xml) {
    auto u = static_cast<unsigned char>(c);
    EXPECT_TRUE(u >= 0x20 || c == '\n') << "control byte " << int(u);
  }
}

TEST(JUnit, NoTestsIsAnEmptySuite) {
  std::string xml = junit_xml({});
  EXPECT_NE(xml.find("tests=\"0\" failures=\"0\" errors=\"0\""), std::string::npos) << xml;
  EXPECT_EQ(count(xml, "<testcase"), 0u);
}
