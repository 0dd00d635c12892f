// The longest run rcxc makes, in virtual milliseconds: the bound of
// `rcxc run --for` and `rcxc compare --for`, of the times a test's
// directives name (`@for`, `@expect ... at`) and of a scenario's `at_ms`.
// 2^40 ms is about 35 years, and its time in µs (the emulator's clock) fits
// 64 bits with room to spare. It lives here, in the lowest folder the TOML
// readers, verify/ and cli/ all may include (cmake/Layers.cmake), so the
// three bounds are one.
#pragma once

#include <cstdint>

namespace rcxc {

inline constexpr std::int64_t kLongestRunMs = std::int64_t{1} << 40;

}  // namespace rcxc
