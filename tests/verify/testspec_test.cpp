// Semantic-test directives: parsing, and checking against real emulator runs
// of hand-assembled bytecode (bytes from the seed's layouts).
#include "verify/testspec.h"

#include <gtest/gtest.h>

using namespace rcx;
using namespace rcx::semtest;
using namespace std::string_literals;

namespace {

Spec parse_ok(std::string_view text) {
  auto r = parse_spec(text);
  if (auto* e = std::get_if<std::vector<SpecError>>(&r)) {
    ADD_FAILURE() << "line " << e->front().line << ": " << e->front().message;
    return {};
  }
  return std::get<Spec>(std::move(r));
}

std::vector<SpecError> parse_bad(std::string_view text) {
  auto r = parse_spec(text);
  if (auto* e = std::get_if<std::vector<SpecError>>(&r)) return *e;
  ADD_FAILURE() << "expected a parse error for: " << text;
  return {};
}

// task 0: var0 = 5; sound 3; tone 440 for 50; wait 100; A on; var1 = 7
Image sample_image() {
  Image img;
  img.fragments.push_back({FragmentType::Task, 0,
                           {0x14, 0x00, 0x02, 0x05, 0x00,   // set var0, 5
                            0x51, 0x03,                     // sound 3
                            0x23, 0xb8, 0x01, 0x32,         // tone 440, 50
                            0x43, 0x02, 0x64, 0x00,         // wait 100 (1 s)
                            0x21, 0x81,                     // A on
                            0x14, 0x01, 0x02, 0x07, 0x00}});// set var1, 7
  img.symbols.push_back({SymbolType::Task, 0, "main"});
  img.symbols.push_back({SymbolType::Variable, 0, "x"});
  return img;
}

Machine run_sample(const Spec& spec) {
  Machine m;
  EXPECT_FALSE(m.load(0, sample_image()).has_value());
  for (const auto& in : spec.inputs) m.schedule(in);
  m.start_program();
  m.run(spec.run_for_us.value_or(10'000'000));
  return m;
}

}  // namespace

TEST(TestSpec, ParsesDirectivesInComments) {
  Spec s = parse_ok(
      "// @for 2.5s\n"
      "int x; // @seed 42\n"
      "// @input at 500ms: sensor 1 raw 200\n"
      "// @input at 100: sensor 2 pressed\n"
      "  //   @input at 1s: message 9\n"
      "// @expect global x == 5\n"
      "// @expect output A: on fwd 7\n"
      "// @expect event at 1000ms+-10ms: tone 440 50\n"
      "// @expect no event: sound 1\n"
      "// @expect count sound == 1\n"
      "// not a directive: x @ y\n");
  EXPECT_EQ(s.run_for_us, 2'500'000);
  EXPECT_EQ(s.seed, 42u);
  ASSERT_EQ(s.inputs.size(), 3u);
  EXPECT_EQ(s.inputs[0].at_us, 100'000);  // sorted by time
  EXPECT_EQ(std::get<SensorRawInput>(s.inputs[0].input).sensor, 1);
  EXPECT_EQ(std::get<SensorRawInput>(s.inputs[1].input).raw, 200);
  EXPECT_EQ(std::get<MessageInput>(s.inputs[2].input).value, 9);
  ASSERT_EQ(s.expectations.size(), 5u);
  EXPECT_EQ(s.expectations[0].line, 6);
  auto& ev = std::get<ExpectEvent>(s.expectations[2].check);
  EXPECT_EQ(ev.at_us, 1'000'000);
  EXPECT_EQ(ev.tolerance_us, 10'000);
  EXPECT_EQ(ev.pattern.value, 440);
  EXPECT_EQ(ev.pattern.duration, 50);
  EXPECT_TRUE(std::get<ExpectEvent>(s.expectations[3].check).absent);
}

TEST(TestSpec, ParsesExpectedDiagnostics) {
  Spec s = parse_ok("// @expect-error line 12: undefined variable 'y'\n// @expect-warning: unused variable\n");
  ASSERT_EQ(s.diagnostics.size(), 2u);
  EXPECT_TRUE(s.diagnostics[0].error);
  EXPECT_EQ(s.diagnostics[0].at_line, 12);
  EXPECT_EQ(s.diagnostics[0].text, "undefined variable 'y'");
  EXPECT_FALSE(s.diagnostics[1].error);
  EXPECT_EQ(s.diagnostics[1].at_line, std::nullopt);
  EXPECT_EQ(s.diagnostics[1].text, "unused variable");
  EXPECT_TRUE(s.expects_compile_error());
}

TEST(TestSpec, ReportsEveryMalformedDirectiveWithItsLine) {
  auto errors = parse_bad(
      "// @expect global x = 5\n"
      "// @input at 5parsecs: message 1\n"
      "// @input at 1s: sensor 4 raw 10\n"
      "// @expect event: honk\n"
      "// @frobnicate\n"
      "// @expect output D: on\n"
      "// @input at 1s: message 300\n");
  ASSERT_EQ(errors.size(), 7u);
  EXPECT_EQ(errors[0].line, 1);
  EXPECT_NE(errors[0].message.find("comparison"), std::string::npos);
  EXPECT_NE(errors[1].message.find("like 500ms"), std::string::npos);
  EXPECT_NE(errors[2].message.find("out of range 1..3"), std::string::npos);
  EXPECT_NE(errors[3].message.find("unknown event 'honk'"), std::string::npos);
  EXPECT_NE(errors[4].message.find("unknown directive '@frobnicate'"), std::string::npos);
  EXPECT_NE(errors[5].message.find("A, B or C"), std::string::npos);
  EXPECT_NE(errors[6].message.find("0..255"), std::string::npos);
}

// Found by fuzz_scenario: `@expect` as the last bytes of a file (no space,
// colon or newline after the word) threw std::out_of_range from substr.
TEST(TestSpec, BareExpectAtEndOfFileIsAnErrorNotACrash) {
  for (std::string_view text : {"// @expect", "// @expect\n", "// @expect:"}) {
    auto errors = parse_bad(text);
    ASSERT_EQ(errors.size(), 1u) << text;
    EXPECT_EQ(errors[0].line, 1) << text;
    EXPECT_FALSE(errors[0].message.empty()) << text;
  }
}

TEST(TestSpec, PassingRunHasNoFailures) {
  Spec s = parse_ok(
      "// @expect stop ended\n"
      "// @expect global x == 5\n"
      "// @expect var 1 >= 7\n"
      "// @expect output A: on fwd 7\n"
      "// @expect event: sound 3\n"
      "// @expect event at 1s: output A on\n"
      "// @expect count tone 440 == 1\n"
      "// @expect no event: sound 1\n"
      "// @expect event: task-stop main\n");
  Machine m = run_sample(s);
  auto failures = check_run(s, m, sample_image());
  for (const auto& f : failures) ADD_FAILURE() << f.line << ": " << f.message;
}

TEST(TestSpec, FailingExpectationsSayWhatHappened) {
  Spec s = parse_ok(
      "// @expect global x == 6\n"
      "// @expect output A: off\n"
      "// @expect event at 200ms+-10ms: output A on\n"
      "// @expect global nope == 1\n"
      "// @expect stop time_limit\n"
      "// @expect datalog: 1 2\n");
  Machine m = run_sample(s);
  auto failures = check_run(s, m, sample_image());
  ASSERT_EQ(failures.size(), 6u);
  EXPECT_EQ(failures[0].line, 1);
  EXPECT_NE(failures[0].message.find("got x = 5"), std::string::npos) << failures[0].message;
  EXPECT_NE(failures[1].message.find("output A is on fwd 7"), std::string::npos) << failures[1].message;
  EXPECT_NE(failures[2].message.find("output A on fwd 7"), std::string::npos) << failures[2].message;
  EXPECT_NE(failures[3].message.find("no global variable 'nope'"), std::string::npos);
  EXPECT_NE(failures[4].message.find("'ended'"), std::string::npos) << failures[4].message;
  EXPECT_NE(failures[5].message.find("[]"), std::string::npos) << failures[5].message;
}

TEST(TestSpec, UnexpectedFaultFailsTheTest) {
  Image img;
  img.fragments.push_back({FragmentType::Task, 0, {0x27, 0x70}});  // jmp far outside the code
  Machine m;
  ASSERT_FALSE(m.load(0, img).has_value());
  m.start_program();
  m.run(1'000'000);
  ASSERT_EQ(m.stop().kind, StopKind::Fault);
  Spec quiet = parse_ok("");
  EXPECT_EQ(check_run(quiet, m, img).size(), 1u);
  Spec expects = parse_ok("// @expect stop fault\n");
  EXPECT_TRUE(check_run(expects, m, img).empty());
}

TEST(TestSpec, DiagnosticsMatchByLineAndText) {
  Spec s = parse_ok("// @expect-error line 3: undefined variable\n");
  EXPECT_TRUE(check_diagnostics(s, {{true, 3, "undefined variable 'q'"}}).empty());
  auto wrong_line = check_diagnostics(s, {{true, 4, "undefined variable 'q'"}});
  ASSERT_EQ(wrong_line.size(), 1u);
  EXPECT_NE(wrong_line[0].message.find("line 4: error: undefined variable 'q'"), std::string::npos);
  Spec none = parse_ok("");
  EXPECT_EQ(check_diagnostics(none, {{true, 2, "syntax error"}}).size(), 1u);
  EXPECT_TRUE(check_diagnostics(none, {{false, 2, "unused variable 'z'"}}).empty());
}

// A bad directive's message quoted its text raw: an escape sequence in a
// test file (ESC [2J clears the screen) reached the terminal of whoever ran
// `rcxc test`, and a NUL its output. Control bytes are shown as \xNN, in
// what the compiler was expected to say too.
TEST(TestSpec, MessagesShowControlBytesOfTheFileEscaped) {
  auto errors = parse_bad("// @for 1\x1b[2J0ms\n// @bogus\x1b[31m\n// @input at 5\0ms: message 3\n"s);
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_NE(errors[0].message.find("found '1\\x1b[2J0ms'"), std::string::npos) << errors[0].message;
  EXPECT_NE(errors[1].message.find("'@bogus\\x1b[31m'"), std::string::npos) << errors[1].message;
  EXPECT_NE(errors[2].message.find("found '5\\x00ms'"), std::string::npos) << errors[2].message;
  for (const auto& e : errors)
    EXPECT_EQ(e.message.find_first_of("\x1b\0"s), std::string::npos) << e.message;
  Spec s = parse_ok("// @expect-error no \x1b]0;title\x07 here\n");
  auto failures = check_diagnostics(s, {});
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_NE(failures[0].message.find("'no \\x1b]0;title\\x07 here'"), std::string::npos) << failures[0].message;
  // The compiler's own messages quote the file too (#error's text), and a
  // backslash stays itself.
  auto unexpected = check_diagnostics(parse_ok(""), {{true, 1, "#error a\\b \x1b[2J"}});
  ASSERT_EQ(unexpected.size(), 1u);
  EXPECT_EQ(unexpected[0].message, "unexpected compile error: #error a\\b \\x1b[2J");
  auto listed = check_diagnostics(s, {{true, 1, "#error \x1b[2J"}});
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_NE(listed[0].message.find("line 1: error: #error \\x1b[2J"), std::string::npos) << listed[0].message;
}

// `@for 1s` then `@for 2s` ran 2 s without a word (so did @seed and
// @scenario), where a second @options was refused.
TEST(TestSpec, ADirectiveOfOneValueIsGivenOnce) {
  for (std::string word : {"for 1s", "seed 3", "scenario a.toml", "options -O0"}) {
    auto errors = parse_bad("// @" + word + "\n// x\n// @" + word + "\n");
    ASSERT_EQ(errors.size(), 1u) << word;
    EXPECT_EQ(errors[0].line, 3) << word;
    std::string name = word.substr(0, word.find(' '));
    EXPECT_EQ(errors[0].message, "a second @" + name + " (the first is on line 1)") << word;
  }
  Spec s = parse_ok("// @for 1s\n// @seed 3\n// @scenario a.toml\n// @options -O0\n");
  EXPECT_EQ(s.seed, 3u);
}

// A seed is 0 or more: the range said for one too large was -2^31..2^31-1.
// An expected diagnostic's line counts from 1: `line 0` could never be met.
TEST(TestSpec, RangesSaidAreTheRangesTaken) {
  auto big = parse_bad("// @seed 99999999999\n");
  ASSERT_EQ(big.size(), 1u);
  EXPECT_EQ(big[0].message, "seed 99999999999 is out of range 0..2147483647");
  auto negative = parse_bad("// @seed -1\n");
  ASSERT_EQ(negative.size(), 1u);
  EXPECT_EQ(negative[0].message, "seed -1 is out of range 0..2147483647");
  for (std::string at : {"0", "-1"}) {
    auto line = parse_bad("// @expect-error line " + at + ": x\n");
    ASSERT_EQ(line.size(), 1u) << at;
    EXPECT_EQ(line[0].message, "line number " + at + " is out of range 1..2147483647");
  }
  EXPECT_EQ(parse_ok("// @expect-error line 1: x\n").diagnostics.at(0).at_line, 1);
}

TEST(TestSpec, NanAndInfinityAreNotTimes) {
  // "nan" passed every range check (NaN compares false) and was rounded.
  for (const char* value : {"nan", "NaN", "inf", "infinity", "-inf", "nanms", "infs"}) {
    auto errors = parse_bad(std::string("// @for ") + value + "\n");
    ASSERT_EQ(errors.size(), 1u) << value;
    EXPECT_NE(errors[0].message.find(std::string("found '") + value + "', which is not a finite number"),
              std::string::npos)
        << errors[0].message;
    auto at = parse_bad(std::string("// @input at ") + value + ": message 1\n");
    ASSERT_EQ(at.size(), 1u) << value;
    EXPECT_NE(at[0].message.find("not a finite number"), std::string::npos) << at[0].message;
  }
}

// "--5" and "-0x-5" read as 5: the sign was taken twice.
TEST(TestSpec, ANumberHasOneSignAtMost) {
  for (const char* value : {"--5", "-0x-5", "0x-5"}) {
    auto errors = parse_bad(std::string("// @input at 1ms: message ") + value + "\n");
    ASSERT_EQ(errors.size(), 1u) << value;
    EXPECT_NE(errors[0].message.find(std::string("found '") + value + "'"), std::string::npos) << errors[0].message;
  }
}

// A time past 10^7 of its unit was refused as no time at all ("expected run
// length (like 500ms or 2s), found '3000000000ms'"), so `@for 10001s` was
// taken and `@for 10000001ms`, a shorter run, was not. Times now reach as
// far as `rcxc run --for` (2^40 ms) in any unit, and a refusal says why.
TEST(TestSpec, ATimeIsRefusedForWhatItIsAndOnlyPastTheLongestRun) {
  Spec s = parse_ok("// @for 3000000000ms\n// @input at 2147483648ms: message 1\n"
                    "// @expect event at 1099511627776ms+-1099511627s: send 1\n");
  ASSERT_TRUE(s.run_for_us);
  EXPECT_EQ(*s.run_for_us, std::int64_t{3'000'000'000'000});
  ASSERT_EQ(s.inputs.size(), 1u);
  EXPECT_EQ(s.inputs[0].at_us, std::int64_t{2'147'483'648'000});
  for (const char* value : {"1099511627777ms", "1099511628s", "1e30s", "1e400", "99999999999999999999999999s"}) {
    auto errors = parse_bad(std::string("// @for ") + value + "\n");
    ASSERT_EQ(errors.size(), 1u) << value;
    EXPECT_NE(errors[0].message.find(std::string("found '") + value +
                                     "', which is later than the longest run (1099511627776 ms, about 35 years)"),
              std::string::npos)
        << errors[0].message;
  }
  auto negative = parse_bad("// @input at -5s: message 1\n");
  ASSERT_EQ(negative.size(), 1u);
  EXPECT_NE(negative[0].message.find("found '-5s', which is negative"), std::string::npos) << negative[0].message;
}

// A number too large for an int read as no number: "expected variable (a
// number), found '99999999999'".
TEST(TestSpec, ANumberTooLargeIsOutOfRangeNotNoNumber) {
  auto errors = parse_bad("// @expect var 99999999999 == 1\n// @expect count sound >= 99999999999999999999\n"
                          "// @input at 1ms: message 0x100000000\n// @expect global x == abc\n"
                          "// @expect event: send 99999999999\n");
  ASSERT_EQ(errors.size(), 5u);
  EXPECT_NE(errors[0].message.find("variable 99999999999 is out of range 0..31"), std::string::npos)
      << errors[0].message;
  EXPECT_NE(errors[1].message.find("count 99999999999999999999 is out of range -2147483648..2147483647"),
            std::string::npos)
      << errors[1].message;
  EXPECT_NE(errors[2].message.find("message 0x100000000 is out of range 0..255"), std::string::npos)
      << errors[2].message;
  EXPECT_NE(errors[3].message.find("expected value (a number), found 'abc'"), std::string::npos) << errors[3].message;
  EXPECT_NE(errors[4].message.find("message 99999999999 is out of range 0..255"), std::string::npos)
      << errors[4].message;
}

// `@for 0ms` ran nothing and passed what held at the start; `rcxc run --for
// 0` is refused, and so is this.
TEST(TestSpec, ARunOfNoTimeIsAnError) {
  for (const char* value : {"0", "0ms", "0s", "0.0001ms"}) {
    auto errors = parse_bad(std::string("// @for ") + value + "\n");
    ASSERT_EQ(errors.size(), 1u) << value;
    EXPECT_NE(errors[0].message.find("the run length must be more than 0 ms"), std::string::npos) << errors[0].message;
  }
}

TEST(TestSpec, ARunCutShortByItsEventLogFailsTheTest) {
  Image img;
  // out A on, out A off, jmp back to the start: two events a pass.
  img.fragments.push_back({FragmentType::Task, 0, {0x21, 0x81, 0x21, 0x41, 0x27, 0x85}});
  Config config;
  config.event_limit = 10;
  Machine m(config);
  ASSERT_FALSE(m.load(0, img).has_value());
  m.start_program();
  m.run(1'000'000);
  ASSERT_EQ(m.stop().kind, StopKind::EventLimit);
  auto failures = check_run(parse_ok(""), m, img);
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_NE(failures[0].message.find("it recorded 10 events, the most a run keeps; ask for less time with @for"),
            std::string::npos)
      << failures[0].message;
}

// `@brick FILE` puts another brick in the room (runtime/room.h): one per
// line, up to seven, each with a file name; `receive V` is an event.
TEST(TestSpec, OtherBricksAreNamedOnePerLine) {
  Spec s = parse_ok("// @brick slave.nqc\n// @brick: sub/other.rcx\n// @expect event: receive 5\n");
  ASSERT_EQ(s.bricks.size(), 2u);
  EXPECT_EQ(s.bricks[0].line, 1);
  EXPECT_EQ(s.bricks[0].file, "slave.nqc");
  EXPECT_EQ(s.bricks[1].file, "sub/other.rcx");
  EXPECT_EQ(brick_path(s.bricks[1], "tests/rooms/t.nqc"), "tests/rooms/sub/other.rcx");
  auto none = parse_bad("// @brick\n");
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].message, "expected the file of the other brick's program, e.g. @brick slave.nqc");
  std::string eight;
  for (int i = 0; i < 8; ++i) eight += "// @brick b" + std::to_string(i) + ".nqc\n";
  auto crowded = parse_bad(eight);
  ASSERT_EQ(crowded.size(), 1u);
  EXPECT_EQ(crowded[0].line, 8);
  EXPECT_EQ(crowded[0].message, "an @brick more than 7: a room holds 8 bricks, this test's and 7 others");
  EXPECT_EQ(parse_bad("// @brick a.nqc b.nqc\n").size(), 1u);
}

TEST(TestSpec, AReceivedMessageIsAnEvent) {
  Spec s = parse_ok("// @expect event at 50ms: receive 7\n// @expect no event: receive 8\n");
  Machine m;
  EXPECT_FALSE(m.load(0, sample_image()).has_value());
  m.schedule({40'000, MessageInput{7}});
  m.start_program();
  m.run(2'000'000);
  EXPECT_TRUE(check_run(s, m, sample_image()).empty());
  Spec wrong = parse_ok("// @expect event: receive 8\n");
  auto failures = check_run(wrong, m, sample_image());
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_NE(failures[0].message.find("40ms receive 7"), std::string::npos) << failures[0].message;
}
