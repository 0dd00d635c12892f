// Putting the virtual brick on a line.
//
// `serve` runs it on a real transport (the pty master): it echoes what the
// host sends as a serial tower would, answers at 2400 baud (or at full speed),
// and runs the loaded programs in real time. `BrickWire` connects a host
// directly to a brick in memory, in virtual time, so tests and benchmarks run
// the whole protocol, noise included, without sleeping.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "link/brick.h"
#include "link/transport.h"

namespace rcx {

struct ServeOptions {
  bool echo = true;              // hosts hear their own bytes (serial tower)
  bool pace = true;              // emit bytes at 2400 baud, not at once
  double noise = 0.0;            // per-byte loss/corruption probability
  std::uint64_t seed = 1;        // noise random source
  int stop_fd = -1;              // serving ends when this becomes readable
  std::function<void(const std::string&)> on_log;  // protocol notes (verbose)
};

// Serves until `stop_fd` is readable or the transport fails.
std::optional<TransportError> serve(Brick& brick, Transport& port, const ServeOptions& options);

// A host-side transport wired to `brick` in memory. Time is virtual: a read
// that finds nothing advances the machine by its timeout; bytes advance it by
// their 2400-baud wire time, so `elapsed()` is what the exchange would take on
// a real link.
class BrickWire final : public Transport {
 public:
  BrickWire(Brick& brick, double noise, std::uint64_t seed, bool echo = false);
  std::optional<TransportError> write(std::span<const std::uint8_t> bytes) override;
  std::variant<std::vector<std::uint8_t>, TransportError> read(Millis timeout) override;
  bool echoes() const override { return echo_; }
  void pause(Millis duration) override;
  std::string describe() const override { return "virtual brick (in memory)"; }
  Micros elapsed() const { return elapsed_us_; }

 private:
  void advance(Micros us);
  Brick& brick_;
  Noise noise_;
  bool echo_;
  Bytes inbox_;
  Micros elapsed_us_ = 0;
  Micros since_write_us_ = 0;  // line time since the last write (a read timeout counts from the write)
  std::size_t events_seen_ = 0;  // the machine's events already looked at for broadcasts
};

}  // namespace rcx
