// Comparing what two runs did, as a robot's owner would see it: outputs,
// sounds and tones, the display, messages sent, the datalog, and (for runs
// that ended by themselves) the final values of global variables by name. Used to check that rcxc's code
// behaves like nqc's for the same program under the same inputs.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rcx/image.h"
#include "runtime/vm.h"

namespace rcx {

// Two events match when they are equal and their times differ by at most
// `absolute_us + relative * t` (t = the later time). The firmware takes a
// fixed time per instruction, so two compilers' code drifts apart in time
// in proportion to how long it has run.
struct TimeTolerance {
  Micros absolute_us = 50'000;
  double relative = 0.02;
  // An output's direction or power that holds for at most this long while
  // the output keeps running is a glitch of command order (`On(OUT_C);
  // OnFwd(OUT_C);` runs C the old way for an instruction), not behaviour.
  Micros glitch_us = 0;
};

struct RunView {
  const Machine* machine = nullptr;
  const Image* image = nullptr;
  std::string label;  // "rcxc", "nqc"
};

// One event both runs show, at its time in each (a's, then b's).
struct MatchedEvent {
  Micros a_us = 0;
  Micros b_us = 0;
};

// The streams compare_runs pairs events in: outputs A, B and C, the sound
// queue (sounds and tones), the display, messages sent, the datalog.
inline constexpr int kEventStreams = 7;
const char* stream_name(int stream);  // "output A", "sounds", ...

// One stream as compare_runs walked it: how many events both runs show in
// the same order, the first of them whose times are further apart than the
// tolerance (its ordinal among them, what it is, its times in a and b), and
// whether the walk stopped at events that differ but for the time.
struct StreamPairing {
  int pairs = 0;
  bool unlike = false;
  std::optional<int> parted_at;
  std::string parted_event;
  MatchedEvent parted_times;
};

struct RunComparison {
  bool same = true;
  std::vector<MatchedEvent> matched;     // the events both runs show, as paired
  std::vector<std::string> differences;  // one line each
  std::string side_by_side;              // both event lists, aligned, when they differ
  std::size_t first_unlike_row = 0;      // its first event row that differs but for the time
  // Every difference is one of time: both runs show the same events in the
  // same order (`in_order` of them), only further apart than the tolerance,
  // as a program shows when it switches an output or plays a sound on every
  // pass of a loop and one code's loop is faster. The most that a acted
  // before b, and after b, on any of those events.
  bool timing_only = false;
  int in_order = 0;
  Micros most_sooner_us = 0;
  Micros most_later_us = 0;
  std::array<StreamPairing, kEventStreams> streams;
};

// `globals`: the program's file-scope variables. Given, only they are
// compared: locals and parameters are the compilers' business (two compilers
// put them in different slots and keep them alive differently), and in each
// image a global is the first variable symbol of its name (both compilers
// number globals before locals, in declaration order; a local that shadows a
// global comes later). Not given, every name both images give once is.
// `side_by_side`: Skip leaves RunComparison::side_by_side empty, for callers
// that only want to know whether runs agree (writing every event of two long
// runs out was most of what a search over many runs spent).
enum class SideBySide : std::uint8_t { Write, Skip };
RunComparison compare_runs(const RunView& a, const RunView& b, TimeTolerance tolerance = {},
                           const std::optional<std::vector<std::string>>& globals = std::nullopt,
                           SideBySide side_by_side = SideBySide::Write);

// The observable events of a run as text lines ("1020ms output A on rev 7",
// "1500ms output A off"): an output's direction and power appear only
// while it is on, and a change nobody could see is no line.
std::vector<std::string> observable_lines(const Machine& machine);

// Where two runs of one image, under inputs that are the same until
// `from_us`, first show something different at or after it: the earlier
// time of the first observable event (as observable_lines lists them) on
// which they disagree, in kind or in time; nullopt when one run's events
// are all the other's. Run once with an input change and once without it,
// this is when the robot first did something the change caused.
std::optional<Micros> parting_time(const Machine& a, const Machine& b, Micros from_us);

// Whether runs that differ in timing only do so because one code runs faster
// than the other, judged from the same two images run again with a much
// shorter instruction time (a tenth or less). A difference of speed is one of
// instruction counts, so it shrinks with the instruction time: the same
// events part later in each stream, or not at all. A difference that does not
// shrink (the same event as far apart, or further, at the shorter time) is
// not one of speed: the runs took other paths to the same events, as when a
// task saw a wrong intermediate value and ended its wait early, or one code
// waits longer. Only the rerun's events are judged (it may be cut short of
// the runs' ends). Undecided when they differ in more than time (speed
// changes what this program does) or do not reach the event that parted.
// Where it can mislead: a program that waits for a timer's tick (or for a
// sound to end) turns a small speed difference into a whole tick; when that
// tick survives the shorter instruction time too, the verdict is NotSpeed.
enum class TimingCause : std::uint8_t { Speed, NotSpeed, Undecided };
struct TimingVerdict {
  TimingCause cause = TimingCause::Undecided;
  std::string why;  // for NotSpeed and Undecided: the event and times that say so
};
TimingVerdict timing_cause(const RunComparison& at_cost, Micros cost_us, const RunComparison& at_shorter_cost,
                           Micros shorter_cost_us);

// How much sooner a's code acted than b's over the matched events: the mean
// and the worst (largest) lateness of a, in microseconds; zeros without
// matched events.
struct TimingDifference {
  int events = 0;
  double mean_sooner_us = 0;  // negative: a acted later on average
  Micros worst_later_us = 0;  // the most a acted after b (0 if never)
};
TimingDifference timing_difference(const std::vector<MatchedEvent>& matched);

}  // namespace rcx
