// Semantic test specifications: expectations written in a program's
// comments (`// @expect global x == 5`, `// @input at 500ms: sensor 1 raw 200`,
// ...), parsed from source text and checked against a finished emulator run.
// The format is documented in docs/testing.md. This file knows nothing of the
// compiler: the caller compiles, runs, and passes what it got.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rcx/image.h"
#include "runtime/vm.h"

namespace rcx::semtest {

enum class Cmp : std::uint8_t { Eq, Ne, Lt, Le, Gt, Ge };

// One event pattern; unset fields match anything.
struct EventPattern {
  EventKind kind = EventKind::Sound;
  std::optional<int> index;     // output / task number
  std::string task_name;        // task events by name (resolved through symbols)
  std::optional<int> value;     // sound, frequency, display, message, datalog value
  std::optional<int> duration;  // tone duration
  std::optional<OutputMode> mode;
  std::optional<Direction> dir;
  std::optional<int> power;
};

struct ExpectStop { StopKind kind; };
struct ExpectGlobal { std::string name; Cmp cmp; int value; };
struct ExpectVar { int index; Cmp cmp; int value; };
struct ExpectOutput { int index; std::optional<OutputMode> mode; std::optional<Direction> dir; std::optional<int> power; };
struct ExpectMessage { Cmp cmp; int value; };
struct ExpectDisplay { Cmp cmp; int value; };
struct ExpectDatalog { std::vector<int> values; };
struct ExpectEvent {
  EventPattern pattern;
  std::optional<Micros> at_us;  // with a window of +-tolerance_us
  Micros tolerance_us = 50'000;
  bool absent = false;          // `@expect no event ...`
};
struct ExpectCount { EventPattern pattern; Cmp cmp; int value; };

using Check = std::variant<ExpectStop, ExpectGlobal, ExpectVar, ExpectOutput, ExpectMessage, ExpectDisplay,
                           ExpectDatalog, ExpectEvent, ExpectCount>;

struct Expectation {
  int line = 0;        // where the directive is written
  std::string text;    // the directive as written, for messages
  Check check;
};

// `@expect-error line N: TEXT` / `@expect-warning ...`: the program must
// (not) compile with a diagnostic whose message contains TEXT.
struct ExpectDiagnostic {
  int line = 0;                   // directive line
  bool error = true;
  std::optional<int> at_line;     // the diagnostic's line, if given
  std::string text;
};

// `@brick FILE`: another brick in the room runs FILE (runtime/room.h).
struct OtherBrick {
  int line = 0;
  std::string file;  // as written (relative to the test file)
};
// A room holds 8 bricks: the test's and 7 others.
inline constexpr std::size_t kMostOtherBricks = 7;

struct Spec {
  std::vector<TimedInput> inputs;
  std::vector<OtherBrick> bricks;
  std::string scenario_file;      // as written (relative to the test file)
  std::optional<Micros> run_for_us;
  std::uint64_t seed = 1;
  bool nqc_differs = false;       // `@nqc-differs: reason`
  // `@options -O0 -DNAME ...`: compiler options, as words; the caller checks
  // them (they are `rcxc compile`'s, which this file does not know).
  std::vector<std::string> options;
  int options_line = 0;
  // The lines of @for, @seed and @scenario (0: none): each may be given once.
  int for_line = 0;
  int seed_line = 0;
  int scenario_line = 0;
  std::vector<Expectation> expectations;
  std::vector<ExpectDiagnostic> diagnostics;
  bool expects_compile_error() const;
  // Whether an expectation is about task events (task-start, task-stop).
  bool expects_task_events() const;
};

// Where the spec's @scenario file is (it is named relative to the folder of
// `test_path`), or "" when it names none.
std::string scenario_path(const Spec& spec, const std::string& test_path);

// Where an @brick file is (relative to the folder of `test_path`).
std::string brick_path(const OtherBrick& brick, const std::string& test_path);

// The spec's @input lines plus the inputs of its @scenario file (a path
// relative to the folder of `test_path`), or the scenario file's error.
std::variant<std::vector<TimedInput>, std::string> all_inputs(const Spec& spec, const std::string& test_path);

struct SpecError {
  int line = 0;
  std::string message;
};

// Parses every `@` directive in `source`. All malformed directives are
// reported (not just the first).
std::variant<Spec, std::vector<SpecError>> parse_spec(std::string_view source);
// The same for the file at `path`. A file that cannot be read is one
// SpecError, line 0, whose message does not name it ("is a directory, not
// a file", "cannot open it: no such file"): the caller does.
std::variant<Spec, std::vector<SpecError>> parse_spec_file(const std::string& path);

// A diagnostic the compiler produced, reduced to what expectations match.
struct CompilerMessage {
  bool error = true;
  int line = 0;
  std::string message;
};

// One failed expectation: the directive's line and a message saying what
// was expected and what happened.
struct Failure {
  int line = 0;
  std::string message;
};

// Checks compile-time expectations against the compiler's messages.
std::vector<Failure> check_diagnostics(const Spec& spec, const std::vector<CompilerMessage>& messages);
// Checks run-time expectations against a machine that has run the image.
std::vector<Failure> check_run(const Spec& spec, const Machine& machine, const Image& image);

}  // namespace rcx::semtest
