#include "link/transport.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#ifdef __linux__
#include <sys/sysmacros.h>
#endif
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <thread>

#include <fmt/format.h>

namespace rcx {
namespace {

std::string errno_text() { return std::strerror(errno); }

// A file descriptor transport: serial tower, USB tower, or pty master.
class FdTransport final : public Transport {
 public:
  FdTransport(int fd, bool echo, std::string name) : fd_(fd), echo_(echo), name_(std::move(name)) {}
  ~FdTransport() override {
    if (fd_ >= 0) ::close(fd_);
  }
  FdTransport(const FdTransport&) = delete;
  FdTransport& operator=(const FdTransport&) = delete;

  std::optional<TransportError> write(std::span<const std::uint8_t> bytes) override {
    std::size_t done = 0;
    while (done < bytes.size()) {
      ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) {
        if (errno == EAGAIN) wait_for(POLLOUT, Millis(50));
        continue;
      }
      if (n < 0) return TransportError{fmt::format("cannot write to {}: {}", name_, errno_text())};
      done += static_cast<std::size_t>(n);
    }
    return std::nullopt;
  }

  std::variant<std::vector<std::uint8_t>, TransportError> read(Millis timeout) override {
    std::vector<std::uint8_t> out;
    int ready = wait_for(POLLIN, timeout);
    if (ready < 0) return TransportError{fmt::format("cannot wait for {}: {}", name_, errno_text())};
    if (ready == 0) return out;
    std::uint8_t buf[256];
    ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) return out;
    // A pty master reads EIO while no host has the slave open: no bytes.
    if (n < 0 && errno == EIO) return out;
    if (n < 0) return TransportError{fmt::format("cannot read from {}: {}", name_, errno_text())};
    if (n == 0) return TransportError{fmt::format("{} was closed", name_)};
    out.assign(buf, buf + n);
    return out;
  }

  bool echoes() const override { return echo_; }
  void pause(Millis duration) override { std::this_thread::sleep_for(duration); }
  std::string describe() const override { return name_; }
  int fd() const { return fd_; }

 private:
  // poll() for `events`; returns >0 ready, 0 timeout, <0 error.
  int wait_for(short events, Millis timeout) {
    pollfd p{fd_, events, 0};
    int r;
    do {
      r = ::poll(&p, 1, static_cast<int>(timeout.count()));
    } while (r < 0 && errno == EINTR);
    if (r > 0 && (p.revents & POLLNVAL)) return -1;
    return r;
  }

  int fd_;
  bool echo_;
  std::string name_;
};

// Raw bytes, no line discipline; serial towers run 2400 baud 8O1.
std::optional<TransportError> configure_tty(int fd, const std::string& path, bool serial_settings) {
  termios t{};
  if (::tcgetattr(fd, &t) != 0) return TransportError{fmt::format("{} is not a terminal: {}", path, errno_text())};
  ::cfmakeraw(&t);
  if (serial_settings) {
    ::cfsetispeed(&t, B2400);
    ::cfsetospeed(&t, B2400);
    t.c_cflag &= ~static_cast<tcflag_t>(CSIZE | CSTOPB | CRTSCTS);
    t.c_cflag |= CS8 | PARENB | PARODD | CLOCAL | CREAD;
    t.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  }
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  int rc = ::tcsetattr(fd, TCSANOW, &t);
  if (rc != 0 && serial_settings && errno == EINVAL) {
    // Pseudo-terminals (the virtual brick) refuse parity; they carry bytes
    // as they are, so a pty works without it.
    t.c_cflag &= ~static_cast<tcflag_t>(PARENB | PARODD);
    rc = ::tcsetattr(fd, TCSANOW, &t);
  }
  if (rc != 0) return TransportError{fmt::format("cannot configure {}: {}", path, errno_text())};
  ::tcflush(fd, TCIOFLUSH);
  return std::nullopt;
}

std::string open_advice(const std::string& path) {
  if (errno == ENOENT)
    return fmt::format("{} does not exist (is the tower plugged in? see docs/link.md; name another port with "
                       "--port, -S in nqc mode, or RCX_PORT)",
                       path);
  if (errno == EACCES || errno == EPERM)
    return fmt::format("no permission to open {} (add yourself to the device's group or install the udev rule in "
                       "docs/link.md)",
                       path);
  return fmt::format("cannot open {}: {}", path, errno_text());
}

// Linux gives the USB tower driver (legousbtower) a device of the USB
// major number; a character device that is neither that nor a terminal
// (/dev/null, /dev/zero, a sound card) is no tower: /dev/null read as a
// tower that hung up, /dev/zero as one that never stops talking.
constexpr unsigned kUsbMajor = 180;

std::optional<TransportError> not_a_tower_device(int fd, const struct stat& st, const PortSpec& spec) {
#ifdef __linux__
  if (!S_ISCHR(st.st_mode) || ::isatty(fd) != 0 || major(st.st_rdev) == kUsbMajor) return std::nullopt;
  return TransportError{fmt::format("{} is not a tower: a character device (major {}, minor {}) that is neither a "
                                    "serial port nor the USB tower's driver (legousbtower, major {})",
                                    spec.path, major(st.st_rdev), minor(st.st_rdev), kUsbMajor)};
#else
  (void)fd, (void)st, (void)spec;
  return std::nullopt;
#endif
}

}  // namespace

PortSpec resolve_port(const std::optional<std::string>& option, const std::optional<std::string>& environment) {
  std::string name = option ? *option : environment ? *environment : std::string("usb");
  if (name == "usb") return {kUsbTowerPath, PortKind::Usb};
  if (name == "serial") return {kSerialTowerPath, PortKind::Serial};
  if (name.rfind("usb:", 0) == 0) return {name.substr(4), PortKind::Usb};
  if (name.rfind("serial:", 0) == 0) return {name.substr(7), PortKind::Serial};
  // A character device that is not a terminal is the USB tower driver.
  int fd = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY);
  if (fd >= 0) {
    bool tty = ::isatty(fd) != 0;
    ::close(fd);
    return {name, tty ? PortKind::Serial : PortKind::Usb};
  }
  return {name, name.find("usb") != std::string::npos && name.find("tty") == std::string::npos ? PortKind::Usb
                                                                                              : PortKind::Serial};
}

std::variant<std::unique_ptr<Transport>, TransportError> open_port(const PortSpec& spec) {
  if (spec.path.empty()) return TransportError{"the port is empty (usb, serial, usb:PATH, serial:PATH or a path)"};
  int fd = ::open(spec.path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) return TransportError{open_advice(spec.path)};
  // A tower is a character device (USB driver, serial port, pty) or a
  // socket; anything else, a regular file above all, would get IR packets
  // written into it.
  struct stat st{};
  if (::fstat(fd, &st) != 0 || !(S_ISCHR(st.st_mode) || S_ISSOCK(st.st_mode))) {
    ::close(fd);
    return TransportError{fmt::format("{} is {}, not a tower (a character device, socket or pseudo-terminal)",
                                      spec.path, S_ISREG(st.st_mode) ? "a regular file" : S_ISDIR(st.st_mode) ? "a directory"
                                                                     : S_ISFIFO(st.st_mode) ? "a FIFO" : "not a device")};
  }
  if (auto err = not_a_tower_device(fd, st, spec)) {
    ::close(fd);
    return *err;
  }
  if (spec.kind == PortKind::Serial) {
    if (auto err = configure_tty(fd, spec.path, true)) {
      ::close(fd);
      return *err;
    }
    return std::unique_ptr<Transport>(
        std::make_unique<FdTransport>(fd, true, fmt::format("serial tower {}", spec.path)));
  }
  return std::unique_ptr<Transport>(std::make_unique<FdTransport>(fd, false, fmt::format("USB tower {}", spec.path)));
}

std::variant<std::unique_ptr<Transport>, TransportError> open_user_port(const std::optional<std::string>& option) {
  const char* env = std::getenv("RCX_PORT");
  std::optional<std::string> environment;
  if (env != nullptr && *env != '\0') environment = env;
  auto opened = open_port(resolve_port(option, environment));
  // A port from RCX_PORT is named as such: "zz does not exist" after
  // `rcxc remote alive` named nothing the user had typed.
  if (auto* e = std::get_if<TransportError>(&opened); e && !option && environment)
    e->message = fmt::format("RCX_PORT={}: {}", *environment, e->message);
  return opened;
}

std::variant<Pty, TransportError> open_pty() {
  int master = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (master < 0) return TransportError{fmt::format("cannot open a pseudo-terminal: {}", errno_text())};
  char name[128];
  if (::grantpt(master) != 0 || ::unlockpt(master) != 0 || ::ptsname_r(master, name, sizeof name) != 0) {
    std::string why = errno_text();
    ::close(master);
    return TransportError{fmt::format("cannot set up the pseudo-terminal: {}", why)};
  }
  // Hold the slave open ourselves, raw: otherwise the master reads EIO while no
  // host is connected, and the slave's default echo would bounce our replies.
  int slave = ::open(name, O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (slave < 0) {
    std::string why = errno_text();
    ::close(master);
    return TransportError{fmt::format("cannot open {}: {}", name, why)};
  }
  if (auto err = configure_tty(slave, name, false)) {
    ::close(slave);
    ::close(master);
    return *err;
  }
  Pty pty;
  pty.master = std::make_unique<FdTransport>(master, false, fmt::format("pty {}", name));
  pty.slave_path = name;
  pty.keep_slave_fd = slave;
  return pty;
}

void close_pty(Pty& pty) {
  pty.master.reset();
  if (pty.keep_slave_fd >= 0) ::close(pty.keep_slave_fd);
  pty.keep_slave_fd = -1;
}

int transport_fd(const Transport& transport) {
  auto* fdt = dynamic_cast<const FdTransport*>(&transport);
  return fdt ? fdt->fd() : -1;
}

}  // namespace rcx
