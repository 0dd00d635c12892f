#include "link/brick_server.h"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <chrono>
#include <thread>

#include <fmt/format.h>

namespace rcx {
namespace {

using Clock = std::chrono::steady_clock;

constexpr Micros kByteMicros = static_cast<Micros>(kByteSeconds * 1e6);

// Writes `bytes`, spread out at 2400 baud when pacing.
std::optional<TransportError> emit(Transport& port, std::span<const std::uint8_t> bytes, bool pace) {
  if (!pace) return bytes.empty() ? std::nullopt : port.write(bytes);
  auto next = Clock::now();
  for (auto b : bytes) {
    std::this_thread::sleep_until(next);
    if (auto err = port.write(std::span(&b, 1))) return err;
    next += std::chrono::microseconds(kByteMicros);
  }
  std::this_thread::sleep_until(next);
  return std::nullopt;
}

// Waits for the port or the stop descriptor; true when told to stop.
bool wait_input(int port_fd, int stop_fd, int timeout_ms) {
  pollfd fds[2] = {{port_fd, POLLIN, 0}, {stop_fd, POLLIN, 0}};
  int n = stop_fd >= 0 ? 2 : 1;
  int r = ::poll(fds, static_cast<nfds_t>(n), timeout_ms);
  if (r < 0 && errno == EINTR) return false;
  return n == 2 && (fds[1].revents & (POLLIN | POLLHUP)) != 0;
}

}  // namespace

std::optional<TransportError> serve(Brick& brick, Transport& port, const ServeOptions& options) {
  Noise noise = make_noise(options.noise, options.seed);
  const int fd = transport_fd(port);
  const auto start = Clock::now();
  const Micros vm_start = brick.vm.now_us();
  while (true) {
    // Short polls keep the programs running smoothly in real time.
    if (fd >= 0 && wait_input(fd, options.stop_fd, 5)) return std::nullopt;
    auto got = port.read(Millis(0));
    if (auto* err = std::get_if<TransportError>(&got)) return *err;
    auto& heard = std::get<Bytes>(got);
    auto wall = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start).count();
    brick.vm.run_until(vm_start + wall);
    Bytes sent = broadcasts(brick, 0);
    brick.vm.forget_events();  // nobody reads them here; a brick serving for days must not grow
    if (!sent.empty())
      if (auto err = emit(port, apply_noise(noise, sent), options.pace)) return err;
    if (!heard.empty()) {
      if (options.echo)
        if (auto err = emit(port, heard, options.pace)) return err;
      Bytes reply = hear(brick, apply_noise(noise, heard));
      if (auto err = emit(port, apply_noise(noise, reply), options.pace)) return err;
    }
    // Broadcasts are logged while nobody talks to the brick too.
    if (options.on_log)
      for (const auto& line : brick.log) options.on_log(line);
    brick.log.clear();  // handed on; a brick serving for days must not grow
  }
}

BrickWire::BrickWire(Brick& brick, double noise, std::uint64_t seed, bool echo)
    : brick_(brick), noise_(make_noise(noise, seed)), echo_(echo), events_seen_(brick.vm.state().events.size()) {}

void BrickWire::advance(Micros us) {
  elapsed_us_ += us;
  since_write_us_ += us;
  brick_.vm.run_until(brick_.vm.now_us() + us);
  const std::size_t events = brick_.vm.state().events.size();
  if (events_seen_ > events) events_seen_ = 0;  // the owner forgot them
  Bytes sent = broadcasts(brick_, events_seen_);
  events_seen_ = events;
  Bytes noisy = apply_noise(noise_, sent);
  inbox_.insert(inbox_.end(), noisy.begin(), noisy.end());
}

std::optional<TransportError> BrickWire::write(std::span<const std::uint8_t> bytes) {
  since_write_us_ = 0;
  advance(static_cast<Micros>(bytes.size()) * kByteMicros);
  if (echo_) inbox_.insert(inbox_.end(), bytes.begin(), bytes.end());
  Bytes reply = hear(brick_, apply_noise(noise_, bytes));
  advance(static_cast<Micros>(reply.size()) * kByteMicros);
  Bytes noisy = apply_noise(noise_, reply);
  inbox_.insert(inbox_.end(), noisy.begin(), noisy.end());
  return std::nullopt;
}

std::variant<std::vector<std::uint8_t>, TransportError> BrickWire::read(Millis timeout) {
  if (inbox_.empty()) {
    // The host started its clock when it wrote; the bytes took part of it.
    Micros wait = std::chrono::duration_cast<std::chrono::microseconds>(timeout).count();
    advance(std::max<Micros>(0, wait - since_write_us_));
    return Bytes{};
  }
  Bytes out;
  out.swap(inbox_);
  return out;
}

void BrickWire::pause(Millis duration) {
  advance(std::chrono::duration_cast<std::chrono::microseconds>(duration).count());
}

}  // namespace rcx
