// nqc's command line on top of rcxc: `rcxc nqc ARGS...`, or rcxc started
// under the name `nqc`, so IDEs and scripts written for nqc 3.1 (BricxCC's
// `nqc -E"temp.log" -L"temp.lst" -I... -Trcx -O"f.rcx" "temp.nqc"`) run
// unchanged. docs/nqc.md lists what this mode does and does not do.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "frontend/diagnostics.h"

namespace rcxc::cli {

// nqc's exit codes (its negative error numbers as a process status).
inline constexpr int kNqcExitOk = 0;
inline constexpr int kNqcExitCompile = 243;  // compile errors, unreadable input file
inline constexpr int kNqcExitUsage = 244;    // bad command line
inline constexpr int kNqcExitNoReply = 253;  // the RCX did not answer
inline constexpr int kNqcExitLink = 255;     // the port or tower cannot be opened

// True when rcxc was started under the name nqc (argv[0]'s last component).
bool started_as_nqc(const char* argv0);

// Runs one nqc command line (`args` without the program name; NQC_OPTIONS
// and NQC_INCLUDE are read from the environment) and returns the exit code.
int run_nqc_mode(const std::vector<std::string>& args);

// When a rejected rcxc command line holds nqc habits (-Efile, -Lfile,
// -Trcx), what to write instead, one line each. (compile's -O<file> is
// judged by -O's own check.)
std::vector<std::string> nqc_habit_hints(const std::vector<std::string>& args);
// Whether a word the parser did not expect is what it left of an nqc habit
// in `args` (-Etemp.log leaves "-temp.log" once -E is taken as a flag):
// then the habit's hint says it, and the parser's "argument was not
// expected: -temp.log" only misleads.
bool left_of_nqc_habit(const std::string& unexpected, const std::vector<std::string>& args);

// Diagnostics the way nqc prints them: "# Error: MESSAGE", the line BricxCC
// searches (`File "NAME" ; line N`), the source line and carets after "# ",
// a rule, and "# N errors during compilation" at the end.
std::string render_nqc(const Diagnostics& diags, const SourceManager& sm);

}  // namespace rcxc::cli
