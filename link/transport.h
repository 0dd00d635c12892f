// Byte transports for the IR link: the serial tower, the USB tower, and a
// pseudo-terminal, all behind one small interface with timeouts.
//
// A transport only moves bytes. Framing and retries live in link_packet.h and
// link_session.h; the virtual brick implements this interface too (in memory,
// in virtual time) so the host side can be tested at full speed.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace rcx {

using Millis = std::chrono::milliseconds;

// 2400 baud, 11 bits a byte (start, 8 data, odd parity, stop): 4.58 ms a byte.
inline constexpr double kByteSeconds = 11.0 / 2400.0;

struct TransportError {
  std::string message;
};

class Transport {
 public:
  virtual ~Transport() = default;
  // Sends every byte or reports why it could not.
  virtual std::optional<TransportError> write(std::span<const std::uint8_t> bytes) = 0;
  // Waits at most `timeout` for bytes and returns those that arrived (empty
  // on timeout).
  virtual std::variant<std::vector<std::uint8_t>, TransportError> read(Millis timeout) = 0;
  // Does the host hear its own bytes back (the serial tower does)?
  virtual bool echoes() const = 0;
  // Waits without reading (backoff between retries). In-memory transports
  // advance their virtual clock instead of sleeping.
  virtual void pause(Millis duration) = 0;
  // How the transport shows up in messages ("serial tower /dev/ttyS0").
  virtual std::string describe() const = 0;
};

// The kinds of device a port name can mean.
enum class PortKind : std::uint8_t {
  Serial,  // a tty: termios 2400 8O1, echo
  Usb,     // the legousbtower character device: no echo
};

struct PortSpec {
  std::string path;
  PortKind kind = PortKind::Serial;
};

inline constexpr const char* kUsbTowerPath = "/dev/usb/legousbtower0";
inline constexpr const char* kSerialTowerPath = "/dev/ttyS0";

// The port to use: `option` (from --port) if given, else `environment` (the
// value of RCX_PORT, if set), else the USB tower. "usb" and "serial" are
// aliases for the default USB tower and first serial port; "usb:PATH" and
// "serial:PATH" force the kind. Otherwise a path that is a tty is a serial
// tower, and any other path is a USB tower.
PortSpec resolve_port(const std::optional<std::string>& option, const std::optional<std::string>& environment);

// Opens a port. The error says what to check (permissions, the device node).
std::variant<std::unique_ptr<Transport>, TransportError> open_port(const PortSpec& spec);
// resolve_port with the RCX_PORT environment variable, then open_port; an
// error about a port RCX_PORT gave starts "RCX_PORT=VALUE: ".
std::variant<std::unique_ptr<Transport>, TransportError> open_user_port(const std::optional<std::string>& option);

// A pseudo-terminal pair for the virtual brick: the brick keeps the master
// (wrapped as a transport without echo), hosts open `slave_path`.
struct Pty {
  std::unique_ptr<Transport> master;
  std::string slave_path;
  int keep_slave_fd = -1;  // held open so the master never sees a hang-up
};
std::variant<Pty, TransportError> open_pty();
void close_pty(Pty& pty);

// The file descriptor behind a transport made by open_port/open_pty, or -1
// (the brick server polls it together with its stop descriptor).
int transport_fd(const Transport& transport);

}  // namespace rcx
