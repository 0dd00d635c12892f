// Behaviour comparison of two runs (the nqc equivalence check), on
// hand-assembled programs whose timing is known from the seed.
#include "verify/compare.h"

#include <gtest/gtest.h>

using namespace rcx;
using Bytes = std::vector<std::uint8_t>;

namespace {

struct RunResult {
  Image image;
  Machine machine;
};

// Each program: an optional prefix, then "A on; wait W; sound 2".
RunResult run_program(Bytes prefix, int wait_ticks, Micros limit_us = 5'000'000, std::string var_name = "v",
                      Micros instruction_us = kDefaultInstructionCostUs) {
  RunResult r;
  Config config;
  config.instruction_cost_us = instruction_us;
  r.machine = Machine(config);
  Bytes code = prefix;
  for (int b : {0x21, 0x81, 0x43, 0x02, wait_ticks & 0xff, wait_ticks >> 8, 0x51, 0x02})
    code.push_back(static_cast<std::uint8_t>(b));
  r.image.fragments.push_back({FragmentType::Task, 0, code});
  r.image.symbols.push_back({SymbolType::Variable, 0, var_name});
  EXPECT_FALSE(r.machine.load(0, r.image).has_value());
  r.machine.start_program();
  r.machine.run(limit_us);
  return r;
}

const Bytes kSetVar5 = {0x14, 0x00, 0x02, 0x05, 0x00};
const Bytes kSetVar6 = {0x14, 0x00, 0x02, 0x06, 0x00};

RunComparison compare(const RunResult& a, const RunResult& b) {
  return compare_runs({&a.machine, &a.image, "one"}, {&b.machine, &b.image, "two"});
}

}  // namespace

TEST(Compare, IdenticalProgramsAreTheSame) {
  RunResult a = run_program(kSetVar5, 100), b = run_program(kSetVar5, 100);
  auto c = compare(a, b);
  EXPECT_TRUE(c.same);
  EXPECT_TRUE(c.side_by_side.empty());
}

TEST(Compare, ExtraInstructionsWithinToleranceAreTheSame) {
  // One more instruction (2 ms) before the same events: well inside 50 ms.
  RunResult a = run_program(kSetVar5, 100);
  Bytes two = kSetVar5;
  two.insert(two.end(), kSetVar5.begin(), kSetVar5.end());
  RunResult b = run_program(two, 100);
  EXPECT_TRUE(compare(a, b).same);
}

// The events both runs show are paired with their times: one run with an
// instruction more before them acts 2 ms later on each (A on, sound 2).
TEST(Compare, MatchedEventsGiveTheTimingDifference) {
  RunResult a = run_program(kSetVar5, 100);
  Bytes two = kSetVar5;
  two.insert(two.end(), kSetVar5.begin(), kSetVar5.end());
  RunResult b = run_program(two, 100);
  auto c = compare(a, b);
  ASSERT_EQ(c.matched.size(), 2u);
  auto d = timing_difference(c.matched);
  EXPECT_EQ(d.events, 2);
  EXPECT_DOUBLE_EQ(d.mean_sooner_us, 2000.0);
  EXPECT_EQ(d.worst_later_us, 0);
  auto reverse = timing_difference(compare(b, a).matched);
  EXPECT_DOUBLE_EQ(reverse.mean_sooner_us, -2000.0);
  EXPECT_EQ(reverse.worst_later_us, 2000);
}

TEST(Compare, DifferentEventValueIsReportedSideBySide) {
  RunResult a = run_program(kSetVar5, 100);
  RunResult b = run_program(kSetVar5, 100);
  // Same timing, different sound: patch b's sound number and rerun.
  RunResult c;
  c.image = b.image;
  c.image.fragments[0].code.back() = 0x03;
  ASSERT_FALSE(c.machine.load(0, c.image).has_value());
  c.machine.start_program();
  c.machine.run(5'000'000);
  auto r = compare(a, c);
  EXPECT_FALSE(r.same);
  ASSERT_FALSE(r.differences.empty());
  EXPECT_NE(r.differences[0].find("sound 2"), std::string::npos) << r.differences[0];
  EXPECT_NE(r.differences[0].find("sound 3"), std::string::npos) << r.differences[0];
  EXPECT_NE(r.side_by_side.find("| "), std::string::npos);
  EXPECT_NE(r.side_by_side.find('*'), std::string::npos) << r.side_by_side;
}

TEST(Compare, EventTooLateIsADifference) {
  RunResult a = run_program(kSetVar5, 100), b = run_program(kSetVar5, 150);  // sound at ~1 s vs ~1.5 s
  auto r = compare(a, b);
  EXPECT_FALSE(r.same);
  EXPECT_NE(r.differences[0].find("allowed difference"), std::string::npos) << r.differences[0];
}

TEST(Compare, FinalGlobalsComparedWhenBothRunsEnded) {
  RunResult a = run_program(kSetVar5, 10), b = run_program(kSetVar6, 10);
  auto r = compare(a, b);
  EXPECT_FALSE(r.same);
  EXPECT_NE(r.differences[0].find("global 'v' = 5 (one) but 6 (two)"), std::string::npos) << r.differences[0];
}

TEST(Compare, GlobalsOfRunsCutByTheTimeLimitAreNotCompared) {
  // Both still waiting when the run is cut at 0.5 s.
  RunResult a = run_program(kSetVar5, 100, 500'000), b = run_program(kSetVar6, 100, 500'000);
  ASSERT_EQ(a.machine.stop().kind, StopKind::TimeLimit);
  EXPECT_TRUE(compare(a, b).same);
}

TEST(Compare, GlobalsInOnlyOneImageAreIgnored) {
  RunResult a = run_program(kSetVar5, 10, 5'000'000, "v"), b = run_program(kSetVar5, 10, 5'000'000, "param");
  EXPECT_TRUE(compare(a, b).same);
}

TEST(Compare, EventJustBeforeTheCutOffIsNotADifference) {
  // The sound comes at ~1 s; cut one run at 1.01 s and the other at 0.99 s.
  RunResult a = run_program(kSetVar5, 100, 1'010'000), b = run_program(kSetVar5, 100, 990'000);
  EXPECT_TRUE(compare(a, b).same);
}

TEST(Compare, WhatARunShowsAfterTheOtherEndedIsADifference) {
  // One run switches A on and stops everything; the other goes on to its
  // sound at ~1 s. Only a run cut by the time limit may lack later events.
  RunResult a = run_program({0x21, 0x81, 0x50}, 100), b = run_program({}, 100);
  ASSERT_EQ(a.machine.stop().kind, StopKind::Ended);
  ASSERT_EQ(b.machine.stop().kind, StopKind::Ended);
  auto r = compare(a, b);
  EXPECT_FALSE(r.same);
  ASSERT_FALSE(r.differences.empty());
  EXPECT_NE(r.differences[0].find("only two has"), std::string::npos) << r.differences[0];
  EXPECT_NE(r.differences[0].find("sound 2"), std::string::npos) << r.differences[0];
}

TEST(Compare, DirectionChangesWhileAnOutputIsOffAreNotADifference) {
  // One run reverses A and sets it forward again while A floats; a robot
  // shows nothing of that, and A then runs forward in both.
  RunResult a = run_program({0xe1, 0x01, 0xe1, 0x81}, 100);
  RunResult b = run_program({0xe1, 0x81, 0xe1, 0x81}, 100);
  auto c = compare(a, b);
  EXPECT_TRUE(c.same) << c.side_by_side;
  for (const auto& line : observable_lines(a.machine)) EXPECT_EQ(line.find("rev"), std::string::npos) << line;
}

TEST(Compare, ADirectionPulseWhileRunningIsADifference) {
  // A runs and is reversed for one instruction in one run only.
  RunResult a = run_program({0x21, 0x81, 0xe1, 0x01, 0xe1, 0x81}, 100);
  Bytes filler = {0x21, 0x81};
  for (const Bytes* part : {&kSetVar5, &kSetVar5}) filler.insert(filler.end(), part->begin(), part->end());
  RunResult b = run_program(filler, 100);
  auto c = compare(a, b);
  EXPECT_FALSE(c.same);
  ASSERT_FALSE(c.differences.empty());
  EXPECT_NE(c.differences[0].find("output A on rev 7"), std::string::npos) << c.differences[0];
}

namespace {
RunComparison compare_with_glitches(const RunResult& a, const RunResult& b) {
  TimeTolerance tol;
  tol.glitch_us = 5 * 2'000;  // five instructions at the default 2 ms
  return compare_runs({&a.machine, &a.image, "one"}, {&b.machine, &b.image, "two"}, tol);
}
// n instructions nothing observes: B set forward while it floats.
Bytes fillers(int n) {
  Bytes out;
  for (int i = 0; i < n; ++i) out.insert(out.end(), {0xe1, 0x82});
  return out;
}
}  // namespace

TEST(Compare, ARunningOutputsBriefOldDirectionIsAGlitchOfCommandOrder) {
  // A reversed while floating, switched on (running reversed for one
  // instruction), then set forward: nqc's order for On(OUT_A); OnFwd(OUT_A).
  RunResult a = run_program({0xe1, 0x01, 0x21, 0x81, 0xe1, 0x81}, 100);
  RunResult b = run_program(fillers(3), 100);
  EXPECT_FALSE(compare(a, b).same);
  auto c = compare_with_glitches(a, b);
  EXPECT_TRUE(c.same) << c.side_by_side << (c.differences.empty() ? "" : c.differences[0]);
}

TEST(Compare, AnOnOffPulseIsNeverAGlitch) {
  RunResult a = run_program({0x21, 0x81, 0x21, 0x41}, 100);
  RunResult b = run_program(fillers(2), 100);
  EXPECT_FALSE(compare_with_glitches(a, b).same);
}

TEST(Compare, ANameGivenToSeveralVariablesIsNotCompared) {
  // nqc names a local like the global it shadows: which "v" is the
  // global cannot be told, so neither is compared; "w" still is.
  RunResult a = run_program(kSetVar5, 100), b = run_program(kSetVar6, 100);
  for (RunResult* r : {&a, &b}) r->image.symbols.push_back({SymbolType::Variable, 1, "v"});
  EXPECT_TRUE(compare(a, b).same);
  RunResult c = run_program(kSetVar5, 100, 5'000'000, "w"), d = run_program(kSetVar6, 100, 5'000'000, "w");
  EXPECT_FALSE(compare(c, d).same);
}

TEST(Compare, GivenTheGlobalsOnlyTheyAreCompared) {
  // "v" differs (5 vs 6); told the program's only global is "g", the
  // comparison leaves "v" (a local) alone.
  RunResult a = run_program(kSetVar5, 10), b = run_program(kSetVar6, 10);
  auto cmp = [&](std::vector<std::string> globals) {
    return compare_runs({&a.machine, &a.image, "one"}, {&b.machine, &b.image, "two"}, {}, globals);
  };
  EXPECT_TRUE(cmp({"g"}).same);
  EXPECT_FALSE(cmp({"v"}).same);
}

TEST(Compare, AGlobalIsTheFirstVariableOfItsName) {
  // Both images name slot 0 "v" (the global, 5 in both) and slot 1 "v" too
  // (a local that shadows it: 0 in one, 9 in the other). The global is
  // compared and agrees; the local is not.
  Bytes set_local_9 = {0x14, 0x01, 0x02, 0x09, 0x00};
  Bytes prefix = kSetVar5;
  prefix.insert(prefix.end(), set_local_9.begin(), set_local_9.end());
  RunResult a = run_program(kSetVar5, 10), b = run_program(prefix, 10);
  for (RunResult* r : {&a, &b}) r->image.symbols.push_back({SymbolType::Variable, 1, "v"});
  EXPECT_TRUE(compare_runs({&a.machine, &a.image, "one"}, {&b.machine, &b.image, "two"}, {},
                           std::vector<std::string>{"v"})
                  .same);
  RunResult c = run_program(kSetVar6, 10);
  c.image.symbols.push_back({SymbolType::Variable, 1, "v"});
  EXPECT_FALSE(compare_runs({&a.machine, &a.image, "one"}, {&c.machine, &c.image, "two"}, {},
                            std::vector<std::string>{"v"})
                   .same);
}

namespace {

// A on, then forever: `extra` (instructions that show nothing), flip A's
// direction, jump back. Every pass shows a switch, so a longer pass shows
// the same switches later and later.
RunResult run_flipping(Bytes extra, Micros limit_us, Micros instruction_us = kDefaultInstructionCostUs) {
  RunResult r;
  Config config;
  config.instruction_cost_us = instruction_us;
  r.machine = Machine(config);
  Bytes code = {0x21, 0x81};  // out A on
  code.insert(code.end(), extra.begin(), extra.end());
  code.insert(code.end(), {0xe1, 0x41});  // dir A flip
  auto back = static_cast<std::uint8_t>(0x80 | (code.size() + 1 - 2));
  code.insert(code.end(), {0x27, back});  // jmp to the first instruction after `out`
  r.image.fragments.push_back({FragmentType::Task, 0, code});
  EXPECT_FALSE(r.machine.load(0, r.image).has_value());
  r.machine.start_program();
  r.machine.run(limit_us);
  return r;
}

}  // namespace

TEST(Compare, SameEventsDriftingApartDifferInTimingOnly) {
  RunResult fast = run_flipping(kSetVar5, 1'000'000);
  Bytes two = kSetVar5;
  two.insert(two.end(), kSetVar6.begin(), kSetVar6.end());
  RunResult slow = run_flipping(two, 1'000'000);
  auto c = compare(fast, slow);
  EXPECT_FALSE(c.same);
  EXPECT_TRUE(c.timing_only) << (c.differences.empty() ? "" : c.differences[0]);
  ASSERT_EQ(c.differences.size(), 1u);
  EXPECT_NE(c.differences[0].find("allowed difference"), std::string::npos) << c.differences[0];
  // The fast run's pass is 3 instructions, the slow one's 4 (6 and 8 ms):
  // the slow run's 125th switch, at 1 s, is the fast run's at 0.75 s.
  EXPECT_GT(c.in_order, 100);
  EXPECT_GT(c.most_sooner_us, 200'000);
  EXPECT_EQ(c.most_later_us, 0);
  EXPECT_EQ(c.first_unlike_row, static_cast<std::size_t>(c.in_order)) << "every row both show is alike but for its time";
}

TEST(Compare, ADifferentEventAfterTheDriftIsMoreThanTiming) {
  RunResult fast = run_flipping(kSetVar5, 1'000'000);
  Bytes two = kSetVar5;
  two.insert(two.end(), {0x51, 0x02});  // a sound on every pass, beside the switch
  RunResult slow = run_flipping(two, 1'000'000);
  auto c = compare(fast, slow);
  EXPECT_FALSE(c.same);
  EXPECT_FALSE(c.timing_only);
}

// Whether a difference in timing only is one of speed: run again at a tenth
// of the instruction time, the drifting switches part ten times later (a
// difference of instruction counts shrinks with the instruction time) ...
TEST(TimingCause, ADriftThatShrinksWithTheInstructionTimeIsSpeed) {
  Bytes two = kSetVar5;
  two.insert(two.end(), kSetVar6.begin(), kSetVar6.end());
  auto at = [&](Micros instruction_us) {
    RunResult fast = run_flipping(kSetVar5, 1'000'000, instruction_us);
    RunResult slow = run_flipping(two, 1'000'000, instruction_us);
    return compare(fast, slow);
  };
  RunComparison slow = at(2'000), shorter = at(200);
  ASSERT_TRUE(slow.timing_only);
  const StreamPairing& a = slow.streams[0];
  ASSERT_TRUE(a.parted_at.has_value());
  EXPECT_EQ(a.parted_event.rfind("output A on ", 0), 0u) << a.parted_event;
  ASSERT_TRUE(shorter.streams[0].parted_at.has_value());
  EXPECT_GT(*shorter.streams[0].parted_at, 5 * *a.parted_at);
  auto verdict = timing_cause(slow, 2'000, shorter, 200);
  EXPECT_EQ(verdict.cause, TimingCause::Speed) << verdict.why;
}

// ... while one code waiting 100 ms longer before the same sound (the same
// events, in the same order: "timing only" as compare_runs sees it) is as
// far apart at any instruction time: not a difference of speed.
TEST(TimingCause, ADifferenceThatDoesNotShrinkIsNotSpeed) {
  auto at = [](Micros instruction_us) {
    RunResult sooner = run_program(kSetVar5, 100, 5'000'000, "v", instruction_us);
    RunResult later = run_program(kSetVar5, 110, 5'000'000, "v", instruction_us);
    return compare(sooner, later);
  };
  RunComparison slow = at(2'000), shorter = at(200);
  ASSERT_TRUE(slow.timing_only) << (slow.differences.empty() ? "" : slow.differences[0]);
  EXPECT_EQ(slow.streams[3].parted_at, 0);
  EXPECT_EQ(slow.streams[0].pairs, 1);
  EXPECT_FALSE(slow.streams[0].parted_at.has_value()) << "A switches on at once in both";
  auto verdict = timing_cause(slow, 2'000, shorter, 200);
  EXPECT_EQ(verdict.cause, TimingCause::NotSpeed);
  EXPECT_EQ(verdict.why, "sounds: the 1st event both show (sound 2) is 100.0 ms apart at 2000 us an instruction and "
                         "100.0 ms apart at 200 us an instruction");
}

// Where the shorter instruction time changes what the program shows, or the
// rerun never reaches the event that parted, nothing is decided.
TEST(TimingCause, ARerunThatDiffersInMoreThanTimeOrStopsShortDecidesNothing) {
  RunResult sooner = run_program(kSetVar5, 100), later = run_program(kSetVar5, 110);
  RunComparison slow = compare(sooner, later);
  ASSERT_TRUE(slow.timing_only);
  RunResult other_sound = run_program({0x51, 0x03}, 100);
  RunComparison more = compare(sooner, other_sound);
  ASSERT_FALSE(more.same || more.timing_only);
  EXPECT_EQ(timing_cause(slow, 2'000, more, 200).cause, TimingCause::Undecided);
  // Cut at 0.5 s, before either sound: no sound is paired at all.
  RunResult cut_a = run_program(kSetVar5, 100, 500'000), cut_b = run_program(kSetVar5, 110, 500'000);
  RunComparison cut = compare(cut_a, cut_b);
  ASSERT_TRUE(cut.same);
  auto verdict = timing_cause(slow, 2'000, cut, 2'000);
  EXPECT_EQ(verdict.cause, TimingCause::Undecided);
  EXPECT_EQ(verdict.why, "sounds: at 2000 us an instruction the runs show only 0 event(s) in the same order, not the "
                         "1st that parted");
}

// A run whose event log filled was cut off there, as one at its time limit
// is: what the other run shows after that point, its values and its stop
// are no difference. Both switch A on and off every pass (on, off, jmp).
TEST(Compare, ARunCutByItsEventLogIsComparedUpToTheCut) {
  auto toggling = [](std::size_t event_limit) {
    RunResult r;
    r.image.fragments.push_back({FragmentType::Task, 0, {0x21, 0x81, 0x21, 0x41, 0x27, 0x85}});
    Config config;
    config.event_limit = event_limit;
    r.machine = Machine(config);
    EXPECT_FALSE(r.machine.load(0, r.image).has_value());
    r.machine.start_program();
    r.machine.run(1'000'000);
    return r;
  };
  RunResult cut = toggling(40), whole = toggling(kDefaultEventLimit);
  ASSERT_EQ(cut.machine.stop().kind, StopKind::EventLimit);
  ASSERT_EQ(whole.machine.stop().kind, StopKind::TimeLimit);
  auto c = compare(cut, whole);
  EXPECT_TRUE(c.same) << (c.differences.empty() ? "" : c.differences[0]);
  EXPECT_TRUE(compare(whole, cut).same);
  EXPECT_GT(c.in_order, 30);
  // Cut at the same point, a real difference before it still shows.
  RunResult other = toggling(40);
  other.image.fragments[0].code[1] = 0x82;  // B on, not A
  other.machine = Machine(Config{.event_limit = 40});
  ASSERT_FALSE(other.machine.load(0, other.image).has_value());
  other.machine.start_program();
  other.machine.run(1'000'000);
  EXPECT_FALSE(compare(cut, other).same);
}

namespace {

Micros sound_time(const Machine& m) {
  for (const auto& e : m.state().events)
    if (e.kind == EventKind::Sound) return e.t_us;
  ADD_FAILURE() << "no sound";
  return -1;
}

}  // namespace

TEST(PartingTime, RunsThatShowTheSameNeverPart) {
  RunResult a = run_program(kSetVar5, 100), b = run_program(kSetVar6, 100);
  EXPECT_EQ(parting_time(a.machine, b.machine, 0), std::nullopt);
}

// "A on" at the same time in both; the sound 1 s or 1.2 s later: they part
// at the earlier sound, whichever run is given first.
TEST(PartingTime, RunsPartAtTheEarlierOfTheFirstEventsThatDiffer) {
  RunResult a = run_program(kSetVar5, 100), b = run_program(kSetVar5, 120);
  Micros a_sound = sound_time(a.machine), b_sound = sound_time(b.machine);
  ASSERT_LT(a_sound, b_sound);
  EXPECT_EQ(parting_time(a.machine, b.machine, 0), a_sound);
  EXPECT_EQ(parting_time(b.machine, a.machine, 0), a_sound);
}

// A run cut off before its sound shows one event fewer: the runs part at
// the other's sound.
TEST(PartingTime, AnEventOnlyOneRunShowsIsWhereTheyPart) {
  RunResult a = run_program(kSetVar5, 100), cut = run_program(kSetVar5, 100, 500'000);
  EXPECT_EQ(parting_time(a.machine, cut.machine, 0), sound_time(a.machine));
  EXPECT_EQ(parting_time(cut.machine, a.machine, 0), sound_time(a.machine));
}

// The inputs were the same until `from_us`, so a difference the caller
// asks about from later on is placed there.
TEST(PartingTime, NoPartingIsEarlierThanTheInputsDiffer) {
  RunResult a = run_program(kSetVar5, 100), b = run_program(kSetVar5, 120);
  EXPECT_EQ(parting_time(a.machine, b.machine, 5'000'000), 5'000'000);
}
