// The inputs `rcxc compare` runs both compilers' code under when no
// scenario file is given, shared with the speed benchmark (bench/) so its
// figures come from the runs the comparison judges.
#pragma once

#include <string>
#include <vector>

#include "rcx/image.h"
#include "runtime/vm.h"

namespace rcx {

struct NamedScenario {
  std::string name;
  std::vector<TimedInput> inputs;
};

// Inputs most programs react to: bumpers pressed and released, IR messages,
// light levels across the thresholds programs use, wheels turning.
std::vector<NamedScenario> builtin_scenarios();

// Runs `image` (program slot 0) from the start under `scenario` until it
// ends or `until_us`, at `instruction_us` per instruction. Throws
// std::runtime_error when the image does not load.
Machine run_scenario(const Image& image, const NamedScenario& scenario, Micros instruction_us, std::uint64_t seed,
                     Micros until_us);
// The same machine before it runs: loaded, `inputs` scheduled, program
// started. Running it (Machine::run) is run_scenario.
Machine start_scenario(const Image& image, const std::vector<TimedInput>& inputs, Micros instruction_us,
                       std::uint64_t seed);

}  // namespace rcx
