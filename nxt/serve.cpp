// The virtual NXT on a descriptor (the pty master) with Bluetooth framing,
// on the wall clock.
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include <fmt/format.h>

#include "nxt/transport.h"
#include "nxt/virtual_nxt.h"

namespace nxt {
namespace {

void log_telegram(const ServeOptions& options, const char* dir, std::span<const std::uint8_t> t) {
  if (!options.on_log) return;
  auto d = decode(t);
  if (auto* ok = std::get_if<Decoded>(&d)) options.on_log(fmt::format("{} {}", dir, describe(*ok)));
  else options.on_log(fmt::format("{} {} ({})", dir, hex(t), std::get<TelegramError>(d).message));
}

}  // namespace

std::optional<ServeError> serve(VirtualNxt& nxt, int fd, const ServeOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const Micros base = nxt.now_us;
  nxt.scenario_origin_us.reset();
  FrameReader reader;
  // A host that went away in the middle of a telegram (killed, or a write
  // cut short) left its first bytes here, and the next host's telegrams
  // were read as the rest of it: the brick answered nothing until the
  // bytes added up to the length it had been promised (up to 512). The
  // bytes of one telegram come together, so after a silence an unfinished
  // one is dropped before new bytes are read.
  constexpr auto kStaleTelegram = std::chrono::milliseconds(200);
  auto last_bytes = Clock::now();
  while (true) {
    pollfd fds[2] = {{fd, POLLIN, 0}, {options.stop_fd, POLLIN, 0}};
    // Short polls keep motors and the scenario moving between requests.
    int r = ::poll(fds, options.stop_fd >= 0 ? 2 : 1, 5);
    if (r < 0 && errno != EINTR) return ServeError{fmt::format("cannot wait for the pty: {}", std::strerror(errno))};
    if (options.stop_fd >= 0 && (fds[1].revents & (POLLIN | POLLHUP))) return std::nullopt;
    advance_to(nxt, base + std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start).count());
    if (r <= 0 || !(fds[0].revents & (POLLIN | POLLHUP | POLLERR))) continue;
    std::uint8_t buf[512];
    ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && (errno == EAGAIN || errno == EINTR || errno == EIO)) {
      // EIO: no host has the pty open; wait for one.
      if (errno == EIO) ::poll(nullptr, 0, 5);
      continue;
    }
    if (n <= 0) return ServeError{"the pty was closed"};
    if (!reader.pending.empty() && Clock::now() - last_bytes > kStaleTelegram) {
      if (options.on_log)
        options.on_log(fmt::format("   (dropped {} byte(s) of an unfinished telegram: nothing more came for {} ms)",
                                   reader.pending.size(), kStaleTelegram.count()));
      reader.pending.clear();
    }
    last_bytes = Clock::now();
    reader.feed(std::span(buf, static_cast<std::size_t>(n)));
    while (auto telegram = reader.next()) {
      if (!nxt.scenario_origin_us) {
        nxt.scenario_origin_us = nxt.now_us;
        advance_to(nxt, nxt.now_us);
      }
      log_telegram(options, "->", *telegram);
      auto reply = answer(nxt, *telegram);
      if (!reply) {
        if (options.on_log) options.on_log(nxt.asleep ? "   (asleep: no answer)" : "   (no answer)");
        continue;
      }
      log_telegram(options, "<-", *reply);
      Bytes out = frame(*reply);
      std::size_t done = 0;
      while (done < out.size()) {
        ssize_t w = ::write(fd, out.data() + done, out.size() - done);
        if (w < 0 && (errno == EAGAIN || errno == EINTR)) {
          pollfd p{fd, POLLOUT, 0};
          ::poll(&p, 1, 10);
          continue;
        }
        if (w < 0) return ServeError{fmt::format("cannot write to the pty: {}", std::strerror(errno))};
        done += static_cast<std::size_t>(w);
      }
    }
  }
}

}  // namespace nxt
