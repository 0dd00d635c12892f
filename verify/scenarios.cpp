#include "verify/scenarios.h"

#include <stdexcept>

namespace rcx {
namespace {

TimedInput at(std::int64_t ms, Input in) { return {ms * kMicrosPerMs, in}; }

}  // namespace

std::vector<NamedScenario> builtin_scenarios() {
  NamedScenario idle{"idle", {}};
  NamedScenario touch{"touch and messages", {}};
  for (int s = 0; s < 3; ++s) {
    for (auto [down, up] : {std::pair{1000, 1500}, {3000, 3300}, {6000, 8000}, {12000, 12400}}) {
      touch.inputs.push_back(at(down, SensorRawInput{s, 100}));
      touch.inputs.push_back(at(up, SensorRawInput{s, 1023}));
    }
  }
  for (auto [ms, value] : {std::pair{2000, 1}, {4000, 2}, {7000, 7}, {10000, 3}})
    touch.inputs.push_back(at(ms, MessageInput{value}));
  NamedScenario light{"light levels and rotation", {}};
  const int levels[] = {800, 500, 300, 700, 450, 900, 350, 600, 750, 400};
  for (int i = 0; i < 10; ++i)
    for (int s = 0; s < 3; ++s) {
      light.inputs.push_back(at(i * 1000, SensorRawInput{s, levels[(i + s) % 10]}));
      light.inputs.push_back(at(i * 1000 + 500, RotationInput{s, (i + 1) * 20 * (s == 1 ? -1 : 1)}));
    }
  return {idle, touch, light};
}

Machine start_scenario(const Image& image, const std::vector<TimedInput>& inputs, Micros instruction_us,
                       std::uint64_t seed) {
  Config config;
  config.seed = seed;
  config.instruction_cost_us = instruction_us;
  Machine m(config);
  if (auto error = m.load(0, image)) throw std::runtime_error(*error);
  for (const auto& in : inputs) m.schedule(in);
  m.start_program();
  return m;
}

Machine run_scenario(const Image& image, const NamedScenario& scenario, Micros instruction_us, std::uint64_t seed,
                     Micros until_us) {
  Machine m = start_scenario(image, scenario.inputs, instruction_us, seed);
  m.run(until_us);
  return m;
}

}  // namespace rcx
