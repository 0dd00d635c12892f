// What a program exchanges with the world, found in its bytecode: which
// sensors it reads (value, raw or boolean sources), which sensor types it
// sets, and whether it reads or sends messages. A host that mirrors the brick
// on other hardware (`rcxc run --nxt`) polls only what is read. Every
// instruction of every fragment counts, reached or not.
#pragma once

#include <array>
#include <cstdint>

#include "rcx/image.h"

namespace rcx {

struct ProgramIo {
  std::array<bool, 3> sensors_read{};  // sensor 1..3 (index 0..2)
  // Per sensor, bit t set when a SetSensorType gives it type t (0..7).
  std::array<std::uint8_t, 3> sensor_types{};
  bool message_read = false;
  bool message_sent = false;
  // False when some bytes did not decode as instructions: what follows them
  // is unknown, so a caller should assume every sensor may be read.
  bool complete = true;
};

ProgramIo program_io(const Image& image);

}  // namespace rcx
