// Moving NXT telegrams: USB (libusb-1.0, one telegram per bulk transfer),
// Bluetooth as an RFCOMM socket or a tty (/dev/rfcommN, a pseudo-terminal)
// with the 2-byte little-endian length prefix, and an in-process transport
// for tests. A transport moves whole telegrams; matching replies to requests
// is client.h's job.
//
// Every wait is cut into short polls that also watch a stop descriptor (the
// CLI's signalfd for SIGINT), so Ctrl-C ends any wait within 50 ms.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace nxt {

using Bytes = std::vector<std::uint8_t>;
using Millis = std::chrono::milliseconds;

struct LinkError {
  enum class Kind : std::uint8_t {
    Open,         // the port cannot be opened (exit 3)
    Lost,         // reading or writing failed, the link is gone (exit 4)
    Interrupted,  // the stop descriptor fired (Ctrl-C)
  };
  Kind kind;
  std::string message;
};

class Transport {
 public:
  virtual ~Transport() = default;
  virtual std::optional<LinkError> send(std::span<const std::uint8_t> telegram) = 0;
  // The next whole telegram, nullopt when none came within `timeout`.
  virtual std::variant<std::optional<Bytes>, LinkError> receive(Millis timeout) = 0;
  virtual std::string describe() const = 0;
  // Bytes that came but make no whole telegram (half a frame, a length no
  // telegram has), said for a reply that never came whole; "" if none.
  virtual std::string leftovers() const { return {}; }
};

// Bluetooth framing: `telegram` after its 2-byte little-endian length.
Bytes frame(std::span<const std::uint8_t> telegram);

// Reassembles length-prefixed telegrams from a byte stream that arrives split
// or glued. A zero length is skipped (it carries no telegram).
struct FrameReader {
  Bytes pending;
  // What an impossible length made us throw away since the last whole telegram.
  Bytes dropped;
  void feed(std::span<const std::uint8_t> bytes);
  std::optional<Bytes> next();
  // "4 bytes of a 5-byte telegram: 05 00 02 0b 00 78", or "" when nothing is left over.
  std::string leftovers() const;
};

enum class PortKind : std::uint8_t { Usb, Bluetooth, Path };

struct PortSpec {
  PortKind kind = PortKind::Usb;
  std::string address;  // USB: serial number or empty; Bluetooth: AA:BB:..; Path: the tty
};

// `option` (--port) if given, else `environment` (NXT_PORT), else "usb".
// Syntax: usb, usb:SERIAL, bt:AA:BB:CC:DD:EE:FF, or a path.
std::variant<PortSpec, LinkError> parse_port(const std::optional<std::string>& option,
                                             const std::optional<std::string>& environment);

// Opens a port; `stop_fd` (or -1) interrupts waits when readable.
std::variant<std::unique_ptr<Transport>, LinkError> open_port(const PortSpec& spec, int stop_fd);

// A length-framed transport over a descriptor it owns (tty, pty, socket).
std::unique_ptr<Transport> framed_fd_transport(int fd, std::string name, int stop_fd);

// A Bluetooth address "AA:BB:CC:DD:EE:FF" as BlueZ's sockets take it: the
// bytes last first (FF first). It does BlueZ's str2ba's work so that rcxc
// needs BlueZ's headers but not its library. `address` is one parse_port
// accepted; a shorter one leaves the missing bytes 0.
std::array<std::uint8_t, 6> bluetooth_address_bytes(std::string_view address);

// Is this build able to open RFCOMM sockets (BlueZ headers at build time)?
bool have_bluetooth_sockets();

// A pseudo-terminal for the virtual NXT: it serves on `master_fd`, hosts open
// `slave_path`. The slave is held open so the master never reads a hang-up.
struct PtyPair {
  int master_fd = -1;
  int keep_slave_fd = -1;
  std::string slave_path;
};
std::variant<PtyPair, LinkError> open_pty_pair();
void close_pty_pair(PtyPair& pty);

// In-process transport: each telegram sent is handed to `answer`, whose reply
// (if any) the next receive returns. Tests can hold replies back (`late_by`)
// or put stray telegrams on the line (`inbox`).
class InProcessTransport final : public Transport {
 public:
  using Answer = std::function<std::optional<Bytes>(std::span<const std::uint8_t>)>;
  explicit InProcessTransport(Answer answer) : answer_(std::move(answer)) {}
  std::optional<LinkError> send(std::span<const std::uint8_t> telegram) override;
  std::variant<std::optional<Bytes>, LinkError> receive(Millis timeout) override;
  std::string describe() const override { return "virtual NXT (in process)"; }
  std::deque<Bytes> inbox;
  // Replies are delayed by this many receive calls (a "late" brick).
  int late_by = 0;
  Millis waited{0};  // total timeout spent waiting for nothing

 private:
  Answer answer_;
  std::deque<std::pair<int, Bytes>> delayed_;
};

}  // namespace nxt
