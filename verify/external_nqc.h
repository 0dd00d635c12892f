// Compiling with the reference compiler, nqc, for comparisons: `rcxc test
// --nqc` runs a test's program as nqc compiles it, on the same emulator.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rcx/image.h"
#include "verify/testspec.h"

namespace rcx::semtest {

struct ExternalCompile {
  std::optional<rcx::Image> image;                    // nullopt: did not compile
  std::vector<CompilerMessage> messages;
  std::string failure;                                // nqc could not be run at all
};

// What nqc may use: a macro bomb makes it take gigabytes and never return.
// The memory limit is its address space (RLIMIT_AS), the time both its CPU
// time (RLIMIT_CPU) and the wall-clock time after which it is killed.
struct NqcLimits {
  int seconds = 20;
  int memory_mib = 512;
};

// Runs `nqc -Trcx -O<tmp> ARGS FILE` (`nqc` is a path or a name found on
// PATH; `args` are more options: -I, -D, -U, -n) within `limits`; a run
// that passes them is a failure saying so.
ExternalCompile compile_with_nqc(const std::string& nqc, const std::string& file,
                                 const std::vector<std::string>& args = {}, const NqcLimits& limits = {});

}  // namespace rcx::semtest
