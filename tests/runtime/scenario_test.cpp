// Scenario files: every input kind, and errors that name the line.
#include "runtime/scenario.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace rcx;

namespace {

std::vector<TimedInput> ok(std::string_view text) {
  auto r = parse_scenario(text, "s.toml");
  if (auto* e = std::get_if<ScenarioError>(&r)) ADD_FAILURE() << e->message;
  return std::get_if<std::vector<TimedInput>>(&r) ? std::get<std::vector<TimedInput>>(r) : std::vector<TimedInput>{};
}

std::string error(std::string_view text) {
  auto r = parse_scenario(text, "s.toml");
  auto* e = std::get_if<ScenarioError>(&r);
  return e ? e->message : "(no error)";
}

}  // namespace

TEST(Scenario, AllInputKinds) {
  auto inputs = ok(R"(
[[input]]
at_ms = 1500
message = 7

[[input]]
at_ms = 500
sensor = 2
raw = 300

[[input]]
at_ms = 600
sensor = 3
rotation = -16

[[input]]
at_ms = 700
battery_mv = 7200
)");
  ASSERT_EQ(inputs.size(), 4u);
  // Sorted by time.
  EXPECT_EQ(inputs[0].at_us, 500'000);
  auto* raw = std::get_if<SensorRawInput>(&inputs[0].input);
  ASSERT_TRUE(raw);
  EXPECT_EQ(raw->sensor, 1);  // sensor 2 is index 1
  EXPECT_EQ(raw->raw, 300);
  auto* rot = std::get_if<RotationInput>(&inputs[1].input);
  ASSERT_TRUE(rot);
  EXPECT_EQ(rot->sensor, 2);
  EXPECT_EQ(rot->position, -16);
  EXPECT_EQ(std::get<BatteryInput>(inputs[2].input).millivolts, 7200);
  EXPECT_EQ(std::get<MessageInput>(inputs[3].input).value, 7);
  EXPECT_EQ(inputs[3].at_us, 1'500'000);
}

TEST(Scenario, EmptyFileIsNoInputs) { EXPECT_TRUE(ok("").empty()); }

// A byte-order mark first (Windows editors write one) was refused as "a
// letter that is not ASCII outside a comment" on line 1, which shows none.
TEST(Scenario, AByteOrderMarkFirstIsNoLetter) {
  auto inputs = ok("\xEF\xBB\xBF[[input]]\nat_ms = 5\nmessage = 3\n");
  ASSERT_EQ(inputs.size(), 1u);
  EXPECT_EQ(std::get<MessageInput>(inputs[0].input).value, 3);
  EXPECT_TRUE(ok("\xEF\xBB\xBF").empty());
  // Lines still count from the first: the mark is on line 1.
  EXPECT_EQ(error("\xEF\xBB\xBF[[input]]\nat_ms = 5\nmessage = 300\n"), "s.toml:3: 'message' = 300 is out of range 0..255");
  // Anywhere else it is a letter like any other.
  EXPECT_NE(error("[[input]]\n\xEF\xBB\xBF" "at_ms = 5\nmessage = 3\n").find("s.toml:2: a letter that is not ASCII"),
            std::string::npos);
}

TEST(Scenario, ErrorsNameTheLine) {
  EXPECT_EQ(error("[[input]]\nat_ms = 1\nsensor = 4\nraw = 3\n"), "s.toml:3: 'sensor' = 4 is out of range 1..3");
  EXPECT_EQ(error("[[input]]\nat_ms = 1\nsensor = 1\nraw = 1024\n"), "s.toml:4: 'raw' = 1024 is out of range 0..1023");
  EXPECT_NE(error("[[input]]\nat_ms = 1\nsensr = 1\nraw = 3\n").find("s.toml:3: unknown key 'sensr'"), std::string::npos);
  EXPECT_EQ(error("[[input]]\nat_ms = \"soon\"\nmessage = 1\n"), "s.toml:2: 'at_ms' must be an integer");
  EXPECT_EQ(error("[[input]]\nat_ms = -5\nmessage = 1\n"), "s.toml:2: 'at_ms' = -5 must be 0 or more");
  // The bound is the longest run (it was printed as 9223372036854775, INT64_MAX over 1000).
  EXPECT_EQ(error("[[input]]\nat_ms = 9223372036854775\nmessage = 1\n"),
            "s.toml:2: 'at_ms' = 9223372036854775 is later than the longest run (1099511627776 ms, about 35 years)");
  EXPECT_EQ(error("[[input]]\nat_ms = 1099511627777\nmessage = 1\n"),
            "s.toml:2: 'at_ms' = 1099511627777 is later than the longest run (1099511627776 ms, about 35 years)");
  EXPECT_EQ(ok("[[input]]\nat_ms = 1099511627776\nmessage = 1\n").at(0).at_us, 1099511627776'000);
  EXPECT_EQ(error("[[input]]\nat_ms = 1\nmessage = 256\n"), "s.toml:3: 'message' = 256 is out of range 0..255");
  EXPECT_NE(error("[[input]]\nmessage = 1\n").find("s.toml:1: input without 'at_ms'"), std::string::npos);
  EXPECT_NE(error("[[input]]\nat_ms = 1\n").find("exactly one of"), std::string::npos);
  EXPECT_NE(error("[[input]]\nat_ms = 1\nmessage = 1\nbattery_mv = 9000\n").find("exactly one of"), std::string::npos);
  EXPECT_NE(error("[[input]]\nat_ms = 1\nraw = 100\n").find("'sensor' goes with"), std::string::npos);
  EXPECT_NE(error("[[input]]\nat_ms = 1\nsensor = 1\nmessage = 1\n").find("'sensor' goes with"), std::string::npos);
  EXPECT_NE(error("speed = 3\n").find("s.toml:1: unknown key 'speed'"), std::string::npos);
  EXPECT_NE(error("input = 3\n").find("[[input]]"), std::string::npos);
  EXPECT_EQ(error("[[input]\n").rfind("s.toml:1:", 0), 0u);  // TOML syntax error
}

// A quoted key spelt with an escape ("at\u001b[2J") was quoted raw in
// "unknown key": the escape sequence reached the terminal.
TEST(Scenario, AKeysControlCharactersAreShownNotSent) {
  EXPECT_EQ(error("[[input]]\n\"at\\u001b[2J\" = 5\nmessage = 3\n"),
            "s.toml:2: unknown key 'at\\x1b[2J' (expected at_ms, sensor, raw, rotation, message, battery_mv)");
  EXPECT_EQ(error("\"\\u0007\" = 1\n"), "s.toml:1: unknown key '\\x07' (a scenario is a list of [[input]] tables)");
}

TEST(Scenario, ABinaryFileIsNamedAsSuchNotAsBadUtf8) {
  const std::string expected = "s.toml: holds binary data, not a scenario (a scenario is a TOML file of [[input]] tables)";
  EXPECT_EQ(error(std::string("RCXI\x01\x02", 6)), expected);
  EXPECT_EQ(error(std::string("[[input]]\n\0at_ms = 1\n", 20)), expected);
}

// Found by fuzz_scenario: toml++ 3.3 meets __builtin_unreachable on some
// letters (U+0441 after a value) and an assertion on a header such as "[+"
// (an abort in Debug builds). Both are refused before it parses, with the
// line; letters in comments are still fine.
TEST(Scenario, TextThatTomlPlusPlusCannotTakeIsRefusedFirst) {
  EXPECT_EQ(error("[[input]]\nat_ms = 5\xd1\x81\nmessage = 3\n"),
            "s.toml:2: a letter that is not ASCII outside a comment (a scenario is [[input]] tables of keys and numbers)");
  EXPECT_EQ(error("\xd1\x81/"), "s.toml:1: a letter that is not ASCII outside a comment (a scenario is [[input]] "
                                  "tables of keys and numbers)");
  for (const char* header : {"[+", "[&[", "[//", "[[", "[ [input]]", "[[ \"", "[[]]"}) {
    std::string text = std::string("[[input]]\nat_ms = 1\nmessage = 2\n") + header + "\n";
    if (std::string(header).find('"') != std::string::npos) continue;  // a quote may start a key
    EXPECT_EQ(error(text), "s.toml:4: a table header without a name (a scenario is [[input]] tables of keys and numbers)")
        << header;
  }
  auto in = ok("# Szenario f\xc3\xbcr den Lichtsensor: \xd1\x81\n[[input]]  # \xe2\x80\x94 erster\nat_ms = 5\nmessage = 3\n");
  ASSERT_EQ(in.size(), 1u);
  EXPECT_EQ(in[0].at_us, 5000);
}

// Found by fuzz_scenario in the nineteenth run: a '}' where an array expects
// a value fails toml++ 3.3's assertion in parse_value (an abort in Debug
// builds; in release its own "could not determine value type"). Refused
// first, with its line; braces in strings and comments, and inline tables in
// arrays, are fine.
TEST(Scenario, ABraceWhereAnArrayExpectsAValueIsRefusedFirst) {
  const std::string words = " (a scenario is [[input]] tables of keys and numbers)";
  EXPECT_EQ(error("x = [}"), "s.toml:1: a '}' where an array expects a value" + words);
  EXPECT_EQ(error("[[input]]\nat_ms = 1\nmessage = 2\nx = [1, # c\n\n }\n"),
            "s.toml:6: a '}' where an array expects a value" + words);
  EXPECT_EQ(error("x = [[[[}]]]]\n"), "s.toml:1: a '}' where an array expects a value" + words);
  EXPECT_EQ(error("x = \"\"\"a\nb\\\n\"\"\"\ny = [ }\n"), "s.toml:4: a '}' where an array expects a value" + words);
  // Valid TOML with braces where they may be is not refused by that: it gets
  // the scenario's own word about its keys.
  for (const char* text : {"x = [{}]\n", "x = [\"[}\", ',}']\n", "x = [1] # [}\n", "x = [{a = [1]}, {}]\n",
                           "x = \"\"\"\na [}\"\"\"\n"})
    EXPECT_EQ(error(text), "s.toml:1: unknown key 'x' (a scenario is a list of [[input]] tables)") << text;
}

// The guard against table headers without a name used to look at every
// line, so a line of a multi-line string, or an array's element on a line of
// its own, that began like such a header ("[}", "[ [1]", "[{") was refused as
// one. It sees the headers toml++ sees: at a line's start, outside strings
// and values. Letters past ASCII are still refused in strings, where toml++
// classifies them, and taken in every comment.
TEST(Scenario, OnlyRealTableHeadersAreCheckedForAName) {
  const std::string words = " (a scenario is [[input]] tables of keys and numbers)";
  const std::string unknown_x = "s.toml:1: unknown key 'x' (a scenario is a list of [[input]] tables)";
  for (const char* text : {"x = \"\"\"\n[}\n\"\"\"\n", "x = '''\n[+ a\n  [[\n'''\n", "x = \"\"\"a\\\n[}\"\"\"\n",
                           "x = [\n  [ [1] ],\n  [{a = 1}],\n  [\n    '[}',\n  ],\n]\n", "x = \"a\" # \xd1\x81 \"\n",
                           "x = [ # \xd1\x81\n]\n"})
    EXPECT_EQ(error(text), unknown_x) << text;
  // Headers after a multi-line string or array are still seen, and so are
  // letters past ASCII in any string, a multi-line one's "comment" included.
  EXPECT_EQ(error("x = \"\"\"\n[a\n\"\"\"\n[+\n"), "s.toml:4: a table header without a name" + words);
  EXPECT_EQ(error("x = [\n  1,\n]\n  [[ ]]\n"), "s.toml:4: a table header without a name" + words);
  EXPECT_EQ(error("x = \"\"\"a\"\"\"\"\n[+\n"), "s.toml:2: a table header without a name" + words);  // a"
  EXPECT_EQ(error("x = '''\n# \xd1\x81'''\n"), "s.toml:2: a letter that is not ASCII outside a comment" + words);
  EXPECT_EQ(error("x = 'a\xd1\x81'\n"), "s.toml:1: a letter that is not ASCII outside a comment" + words);
}

// A directory used to read as an empty scenario, so `rcxc run P --scenario
// DIR` ran without inputs and exited 0.
TEST(Scenario, DirectoryIsAnError) {
  auto dir = std::filesystem::temp_directory_path() / "rcxc-scenario-test-dir";
  std::filesystem::create_directories(dir);
  auto r = read_scenario_file(dir.string());
  std::filesystem::remove(dir);
  ASSERT_TRUE(std::holds_alternative<ScenarioError>(r));
  EXPECT_EQ(std::get<ScenarioError>(r).message, dir.string() + ": is a directory, not a scenario file");
}

TEST(Scenario, MissingFile) {
  auto r = read_scenario_file("/nonexistent/dir/s.toml");
  ASSERT_TRUE(std::holds_alternative<ScenarioError>(r));
  EXPECT_NE(std::get<ScenarioError>(r).message.find("cannot open"), std::string::npos);
}
