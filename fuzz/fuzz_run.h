// Shared by the fuzz targets: run an image on a fresh machine for a bounded
// stretch of virtual time. The bound is virtual, so a program that loops
// forever costs a fixed number of instructions (time / instruction cost).
#pragma once

#include <optional>
#include <string>

#include "rcx/image.h"
#include "runtime/vm.h"

namespace rcxc::fuzz {

inline constexpr rcx::Micros kRunLimitUs = 2 * 1000 * 1000;

// How the bounded run ended; `refused` holds the loader's reason when the
// machine would not take the image at all.
struct RunOutcome {
  std::optional<std::string> refused;
  rcx::StopInfo stop;
};

inline RunOutcome run_bounded(const rcx::Image& image) {
  rcx::Machine machine;
  if (auto refused = machine.load(0, image)) return {refused, {}};  // too big: that is an answer too
  machine.start_program();
  machine.run(kRunLimitUs);
  return {std::nullopt, machine.stop()};
}

}  // namespace rcxc::fuzz
