#include "nxt/transport.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>


#include <algorithm>
#include <array>
#include <charconv>
#include <cctype>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "nxt/usb_library.h"

#ifdef RCXC_HAVE_BLUEZ
#include <bluetooth/bluetooth.h>
#include <bluetooth/rfcomm.h>
#endif

namespace nxt {
namespace {

using Clock = std::chrono::steady_clock;

// Waits are cut into slices this long so the stop descriptor is seen in time
// even where it cannot be polled together with the port (USB).
constexpr Millis kSlice{50};
// No NXT telegram comes near this; a longer prefix means the stream lost its
// framing (line noise, a host that joined mid-telegram).
constexpr std::size_t kMaxFrame = 512;

constexpr std::uint16_t kLegoVendor = 0x0694;
constexpr std::uint16_t kNxtProduct = 0x0002;
constexpr unsigned char kUsbOut = 0x01;
constexpr unsigned char kUsbIn = 0x82;

std::string errno_text() { return std::strerror(errno); }

bool stop_requested(int stop_fd) {
  if (stop_fd < 0) return false;
  pollfd p{stop_fd, POLLIN, 0};
  return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLIN | POLLHUP)) != 0;
}

LinkError interrupted() { return {LinkError::Kind::Interrupted, "interrupted"}; }

Millis remaining(Clock::time_point deadline) {
  auto left = std::chrono::duration_cast<Millis>(deadline - Clock::now());
  return std::max(Millis(0), left);
}

class FramedFdTransport final : public Transport {
 public:
  FramedFdTransport(int fd, std::string name, int stop_fd) : fd_(fd), stop_fd_(stop_fd), name_(std::move(name)) {}
  ~FramedFdTransport() override { ::close(fd_); }
  FramedFdTransport(const FramedFdTransport&) = delete;
  FramedFdTransport& operator=(const FramedFdTransport&) = delete;

  std::optional<LinkError> send(std::span<const std::uint8_t> telegram) override {
    Bytes out = frame(telegram);
    std::size_t done = 0;
    auto deadline = Clock::now() + Millis(2000);
    while (done < out.size()) {
      ssize_t n = ::write(fd_, out.data() + done, out.size() - done);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) {
        if (stop_requested(stop_fd_)) return interrupted();
        if (Clock::now() > deadline) return LinkError{LinkError::Kind::Lost, fmt::format("{} does not take data", name_)};
        pollfd p{fd_, POLLOUT, 0};
        ::poll(&p, 1, static_cast<int>(kSlice.count()));
        continue;
      }
      if (n < 0) return LinkError{LinkError::Kind::Lost, fmt::format("cannot write to {}: {}", name_, errno_text())};
      done += static_cast<std::size_t>(n);
    }
    return std::nullopt;
  }

  std::variant<std::optional<Bytes>, LinkError> receive(Millis timeout) override {
    auto deadline = Clock::now() + timeout;
    while (true) {
      if (auto t = reader_.next()) return t;
      Millis wait = remaining(deadline);
      pollfd fds[2] = {{fd_, POLLIN, 0}, {stop_fd_, POLLIN, 0}};
      int r = ::poll(fds, stop_fd_ >= 0 ? 2 : 1, static_cast<int>(wait.count()));
      if (r < 0 && errno != EINTR)
        return LinkError{LinkError::Kind::Lost, fmt::format("cannot wait for {}: {}", name_, errno_text())};
      if (stop_fd_ >= 0 && (fds[1].revents & (POLLIN | POLLHUP))) return interrupted();
      if (r > 0 && (fds[0].revents & (POLLIN | POLLHUP | POLLERR))) {
        std::uint8_t buf[512];
        ssize_t n = ::read(fd_, buf, sizeof buf);
        if (n > 0) {
          reader_.feed(std::span(buf, static_cast<std::size_t>(n)));
          continue;
        }
        // EIO: the tty hung up (a pty whose brick went away, an rfcomm
        // link that dropped).
        if (n == 0 || (n < 0 && errno == EIO))
          return LinkError{LinkError::Kind::Lost, fmt::format("{} hung up: the link is lost", name_)};
        if (n < 0 && errno != EAGAIN && errno != EINTR)
          return LinkError{LinkError::Kind::Lost, fmt::format("cannot read from {}: {}", name_, errno_text())};
      }
      if (wait.count() == 0) return std::optional<Bytes>{};
    }
  }

  std::string describe() const override { return name_; }
  std::string leftovers() const override { return reader_.leftovers(); }

 private:
  int fd_;
  int stop_fd_;
  std::string name_;
  FrameReader reader_;
};

class UsbTransport final : public Transport {
 public:
  UsbTransport(UsbLibrary usb, libusb_context* ctx, libusb_device_handle* handle, std::string name, int stop_fd)
      : usb_(std::move(usb)), ctx_(ctx), handle_(handle), name_(std::move(name)), stop_fd_(stop_fd) {}
  ~UsbTransport() override {
    usb_.release_interface(handle_, 0);
    usb_.close(handle_);
    usb_.exit(ctx_);
  }
  UsbTransport(const UsbTransport&) = delete;
  UsbTransport& operator=(const UsbTransport&) = delete;

  std::optional<LinkError> send(std::span<const std::uint8_t> telegram) override {
    Bytes data(telegram.begin(), telegram.end());
    int done = 0;
    int rc = usb_.bulk_transfer(handle_, kUsbOut, data.data(), static_cast<int>(data.size()), &done, 1000);
    if (rc != 0 || done != static_cast<int>(data.size()))
      return LinkError{LinkError::Kind::Lost, fmt::format("cannot write to {}: {}", name_, usb_.strerror(rc))};
    return std::nullopt;
  }

  std::variant<std::optional<Bytes>, LinkError> receive(Millis timeout) override {
    auto deadline = Clock::now() + timeout;
    do {
      if (stop_requested(stop_fd_)) return interrupted();
      std::uint8_t buf[64];
      int got = 0;
      auto slice = std::clamp(remaining(deadline), Millis(1), kSlice);
      int rc = usb_.bulk_transfer(handle_, kUsbIn, buf, sizeof buf, &got, static_cast<unsigned>(slice.count()));
      if (got > 0) return std::optional<Bytes>(Bytes(buf, buf + got));
      if (rc != 0 && rc != LIBUSB_ERROR_TIMEOUT)
        return LinkError{LinkError::Kind::Lost, fmt::format("cannot read from {}: {}", name_, usb_.strerror(rc))};
    } while (Clock::now() < deadline);
    return std::optional<Bytes>{};
  }

  std::string describe() const override { return name_; }

 private:
  UsbLibrary usb_;
  libusb_context* ctx_;
  libusb_device_handle* handle_;
  std::string name_;
  int stop_fd_;
};

// Bluetooth addresses and USB serials compare without separators or case
// (the NXT's USB serial number is its Bluetooth address without colons).
std::string plain_address(std::string_view s) {
  std::string out;
  for (char c : s)
    if (c != ':') out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

// An NXT's USB serial number is its Bluetooth address without colons, 12
// hex digits: anything else ("usb:zz", a typo) was looked for among the
// bricks on USB and ended as "no NXT on USB" rather than as the typo it is.
bool valid_usb_serial(std::string_view s) {
  std::string plain = plain_address(s);
  return plain.size() == 12 && std::ranges::all_of(plain, [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; });
}

constexpr const char* kUdevHint =
    "install the udev rule from docs/nxt.md "
    "(SUBSYSTEM==\"usb\", ATTRS{idVendor}==\"0694\", ATTRS{idProduct}==\"0002\", TAG+=\"uaccess\"), "
    "then unplug and replug the brick";

std::variant<std::unique_ptr<Transport>, LinkError> open_usb(const std::string& serial, int stop_fd) {
  auto fail = [](std::string message) { return LinkError{LinkError::Kind::Open, std::move(message)}; };
  auto loaded = load_usb_library();
  if (auto* why = std::get_if<std::string>(&loaded)) return fail(*why);
  UsbLibrary usb = std::get<UsbLibrary>(std::move(loaded));
  libusb_context* ctx = nullptr;
  if (int rc = usb.init(&ctx); rc != 0) return fail(fmt::format("cannot start libusb: {}", usb.strerror(rc)));
  libusb_device** list = nullptr;
  ssize_t count = usb.get_device_list(ctx, &list);
  std::vector<std::string> seen;
  bool denied = false;
  libusb_device_handle* chosen = nullptr;
  std::string chosen_serial;
  for (ssize_t i = 0; i < count && !chosen; ++i) {
    libusb_device_descriptor desc{};
    if (usb.get_device_descriptor(list[i], &desc) != 0) continue;
    if (desc.idVendor != kLegoVendor || desc.idProduct != kNxtProduct) continue;
    libusb_device_handle* h = nullptr;
    int rc = usb.open(list[i], &h);
    if (rc == LIBUSB_ERROR_ACCESS) {
      denied = true;
      continue;
    }
    if (rc != 0) continue;
    unsigned char text[64] = {};
    int n = desc.iSerialNumber ? usb.get_string_descriptor_ascii(h, desc.iSerialNumber, text, sizeof text) : 0;
    std::string this_serial = n > 0 ? std::string(reinterpret_cast<char*>(text), static_cast<std::size_t>(n)) : "";
    seen.push_back(this_serial);
    if (!serial.empty() && plain_address(this_serial) != plain_address(serial)) {
      usb.close(h);
      continue;
    }
    usb.set_auto_detach_kernel_driver(h, 1);
    rc = usb.claim_interface(h, 0);
    if (rc != 0) {
      usb.close(h);
      usb.free_device_list(list, 1);
      usb.exit(ctx);
      if (rc == LIBUSB_ERROR_BUSY) return fail("the NXT on USB is in use by another program");
      if (rc == LIBUSB_ERROR_ACCESS) return fail(fmt::format("no permission to claim the NXT on USB: {}", kUdevHint));
      return fail(fmt::format("cannot claim the NXT on USB: {}", usb.strerror(rc)));
    }
    chosen = h;
    chosen_serial = this_serial;
  }
  usb.free_device_list(list, 1);
  if (chosen)
    return std::unique_ptr<Transport>(std::make_unique<UsbTransport>(
        std::move(usb), ctx, chosen, fmt::format("NXT on USB{}", chosen_serial.empty() ? "" : " " + chosen_serial),
        stop_fd));
  usb.exit(ctx);
  if (denied) return fail(fmt::format("found an NXT on USB but have no permission to open it: {}", kUdevHint));
  if (!serial.empty() && !seen.empty())
    return fail(fmt::format("no NXT with serial {} on USB (found: {})", serial, fmt::join(seen, ", ")));
  return fail("no NXT on USB (vendor 0694, product 0002): is it plugged in and switched on? "
              "Or give the port as bt:ADDR or a tty path");
}

bool valid_bt_address(std::string_view a) {
  if (a.size() != 17) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i % 3 == 2 ? a[i] != ':' : !std::isxdigit(static_cast<unsigned char>(a[i]))) return false;
  }
  return true;
}

std::variant<std::unique_ptr<Transport>, LinkError> open_bluetooth(const std::string& address, int stop_fd) {
#ifdef RCXC_HAVE_BLUEZ
  auto fail = [&](std::string why) { return LinkError{LinkError::Kind::Open, std::move(why)}; };
  int fd = ::socket(AF_BLUETOOTH, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, BTPROTO_RFCOMM);
  if (fd < 0) return fail(fmt::format("cannot make a Bluetooth socket: {} (is BlueZ running?)", errno_text()));
  sockaddr_rc addr{};
  addr.rc_family = AF_BLUETOOTH;
  addr.rc_channel = 1;  // the NXT's serial port profile
  std::array<std::uint8_t, 6> bytes = bluetooth_address_bytes(address);
  std::copy(bytes.begin(), bytes.end(), addr.rc_bdaddr.b);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 && errno != EINPROGRESS) {
    std::string why = errno_text();
    ::close(fd);
    return fail(fmt::format("cannot connect to {}: {}", address, why));
  }
  // Connecting (paging the brick) can take seconds: wait in slices for Ctrl-C.
  auto deadline = Clock::now() + Millis(20000);
  while (true) {
    pollfd fds[2] = {{fd, POLLOUT, 0}, {stop_fd, POLLIN, 0}};
    int r = ::poll(fds, stop_fd >= 0 ? 2 : 1, static_cast<int>(kSlice.count()));
    if (stop_fd >= 0 && r > 0 && (fds[1].revents & POLLIN)) {
      ::close(fd);
      return interrupted();
    }
    if (r > 0 && fds[0].revents) break;
    if (Clock::now() > deadline) {
      ::close(fd);
      return fail(fmt::format("{} does not answer (switched on, paired with PIN 1234, Bluetooth on?)", address));
    }
  }
  int err = 0;
  socklen_t len = sizeof err;
  ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len);
  if (err != 0) {
    ::close(fd);
    return fail(fmt::format("cannot connect to {}: {} (paired with PIN 1234? docs/nxt.md)", address, std::strerror(err)));
  }
  return framed_fd_transport(fd, fmt::format("NXT on Bluetooth {}", address), stop_fd);
#else
  (void)stop_fd;
  return LinkError{LinkError::Kind::Open,
                   fmt::format("this rcxc was built without Bluetooth sockets (libbluetooth-dev); bind {} to "
                               "/dev/rfcomm0 with `rfcomm bind` and use that path",
                               address)};
#endif
}

std::variant<std::unique_ptr<Transport>, LinkError> open_path(const std::string& path, int stop_fd) {
  int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    std::string why;
    if (errno == ENOENT) why = fmt::format("{} does not exist (`rfcomm bind` it first? see docs/nxt.md)", path);
    else if (errno == EACCES || errno == EPERM)
      why = fmt::format("no permission to open {} (join the dialout group)", path);
    else why = fmt::format("cannot open {}: {}", path, errno_text());
    return LinkError{LinkError::Kind::Open, why};
  }
  // Only a tty (rfcomm, a pseudo-terminal, a serial adapter) or a socket
  // carries telegrams: /dev/null or a plain file would read as a hang-up or
  // as garbage frames.
  struct stat st {};
  if (::fstat(fd, &st) == 0 && !S_ISSOCK(st.st_mode) && !::isatty(fd)) {
    ::close(fd);
    return LinkError{LinkError::Kind::Open,
                     fmt::format("{} is not a tty (a /dev/rfcommN bound with `rfcomm bind`, or a pseudo-terminal)", path)};
  }
  termios t{};
  if (::tcgetattr(fd, &t) == 0) {
    // Raw bytes: the length prefix and the telegrams are binary.
    ::cfmakeraw(&t);
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    ::tcsetattr(fd, TCSANOW, &t);
    ::tcflush(fd, TCIFLUSH);
  }
  return framed_fd_transport(fd, fmt::format("NXT on {}", path), stop_fd);
}

}  // namespace

std::array<std::uint8_t, 6> bluetooth_address_bytes(std::string_view address) {
  std::array<std::uint8_t, 6> bytes{};
  for (std::size_t i = 0; i < bytes.size() && i * 3 + 2 <= address.size(); ++i) {
    unsigned value = 0;
    std::from_chars(address.data() + i * 3, address.data() + i * 3 + 2, value, 16);
    bytes[bytes.size() - 1 - i] = static_cast<std::uint8_t>(value);
  }
  return bytes;
}

Bytes frame(std::span<const std::uint8_t> telegram) {
  Bytes out;
  out.reserve(telegram.size() + 2);
  out.push_back(static_cast<std::uint8_t>(telegram.size() & 0xFF));
  out.push_back(static_cast<std::uint8_t>(telegram.size() >> 8));
  out.insert(out.end(), telegram.begin(), telegram.end());
  return out;
}

void FrameReader::feed(std::span<const std::uint8_t> bytes) { pending.insert(pending.end(), bytes.begin(), bytes.end()); }

std::optional<Bytes> FrameReader::next() {
  while (pending.size() >= 2) {
    std::size_t length = pending[0] | (std::size_t{pending[1]} << 8);
    if (length == 0) {
      pending.erase(pending.begin(), pending.begin() + 2);
      continue;
    }
    if (length > kMaxFrame) {
      // Lost framing: drop what we have and wait for the next telegram.
      dropped.insert(dropped.end(), pending.begin(), pending.end());
      pending.clear();
      return std::nullopt;
    }
    if (pending.size() < 2 + length) return std::nullopt;
    Bytes t(pending.begin() + 2, pending.begin() + 2 + static_cast<std::ptrdiff_t>(length));
    pending.erase(pending.begin(), pending.begin() + 2 + static_cast<std::ptrdiff_t>(length));
    dropped.clear();
    return t;
  }
  return std::nullopt;
}

std::string FrameReader::leftovers() const {
  // Enough bytes to recognise a reply's start; a flood is not repeated whole.
  auto shown = [](const Bytes& b) {
    constexpr std::size_t kShown = 24;
    std::string s;
    for (std::size_t i = 0; i < b.size() && i < kShown; ++i) s += fmt::format("{}{:02x}", i ? " " : "", b[i]);
    return b.size() > kShown ? s + " ..." : s;
  };
  std::string out;
  if (!dropped.empty()) {
    std::size_t length = dropped.size() >= 2 ? dropped[0] | (std::size_t{dropped[1]} << 8) : 0;
    out = fmt::format("{} bytes came under a length prefix of {}, more than any telegram, and were dropped: {}",
                      dropped.size(), length, shown(dropped));
  }
  if (!pending.empty()) {
    if (!out.empty()) out += "; ";
    if (pending.size() < 2)
      out += fmt::format("1 byte came, half a length prefix: {}", shown(pending));
    else
      out += fmt::format("{} of a {}-byte telegram came: {}", pending.size() - 2,
                         pending[0] | (std::size_t{pending[1]} << 8), shown(pending));
  }
  return out;
}

std::variant<PortSpec, LinkError> parse_port(const std::optional<std::string>& option,
                                             const std::optional<std::string>& environment) {
  std::string name = option ? *option : environment ? *environment : std::string("usb");
  // A bad NXT_PORT is named as such: nothing on the command line says "usb:zz".
  const std::string from = option ? "" : "NXT_PORT: ";
  if (name.empty())
    return LinkError{LinkError::Kind::Open, from + "the port is empty (usb, usb:SERIAL, bt:ADDR or a path)"};
  // The schemes in any case ("USB", "BT:..."): a path of that name was
  // never meant, and opening it said "USB does not exist".
  auto lower = [](std::string s) {
    for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  if (lower(name) == "usb") return PortSpec{PortKind::Usb, ""};
  if (lower(name.substr(0, 4)) == "usb:") name = "usb:" + name.substr(4);
  if (lower(name.substr(0, 3)) == "bt:") name = "bt:" + name.substr(3);
  // An address without its scheme would be opened as a path that does not
  // exist ("rfcomm bind it first?"): say which scheme it needs.
  if (valid_bt_address(name) || (name.size() == 12 && valid_usb_serial(name))) {
    std::string plain = plain_address(name), colons;
    for (std::size_t i = 0; i < plain.size(); i += 2) colons += (i ? ":" : "") + plain.substr(i, 2);
    return LinkError{LinkError::Kind::Open,
                     fmt::format("{}\"{}\" is a brick's address without its kind: bt:{} for Bluetooth, usb:{} for "
                                 "the brick with that serial number on USB",
                                 from, name, colons, plain)};
  }
  if (name.rfind("usb:", 0) == 0) {
    std::string serial = name.substr(4);
    if (!valid_usb_serial(serial))
      return LinkError{LinkError::Kind::Open,
                       fmt::format("{}\"{}\" is not an NXT's USB serial number: that is its Bluetooth address, 12 "
                                   "hex digits (usb:001653123456; colons and case do not matter)",
                                   from, serial)};
    return PortSpec{PortKind::Usb, serial};
  }
  if (name.rfind("bt:", 0) == 0) {
    std::string address = name.substr(3);
    if (!valid_bt_address(address))
      return LinkError{LinkError::Kind::Open,
                       fmt::format("{}\"{}\" is not a Bluetooth address (bt:AA:BB:CC:DD:EE:FF)", from, address)};
    return PortSpec{PortKind::Bluetooth, address};
  }
  return PortSpec{PortKind::Path, name};
}

std::variant<std::unique_ptr<Transport>, LinkError> open_port(const PortSpec& spec, int stop_fd) {
  switch (spec.kind) {
    case PortKind::Usb: return open_usb(spec.address, stop_fd);
    case PortKind::Bluetooth: return open_bluetooth(spec.address, stop_fd);
    case PortKind::Path: return open_path(spec.address, stop_fd);
  }
  return LinkError{LinkError::Kind::Open, "unknown port kind"};
}

std::unique_ptr<Transport> framed_fd_transport(int fd, std::string name, int stop_fd) {
  return std::make_unique<FramedFdTransport>(fd, std::move(name), stop_fd);
}

bool have_bluetooth_sockets() {
#ifdef RCXC_HAVE_BLUEZ
  return true;
#else
  return false;
#endif
}

std::variant<PtyPair, LinkError> open_pty_pair() {
  auto fail = [](std::string why) { return LinkError{LinkError::Kind::Open, std::move(why)}; };
  int master = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (master < 0) return fail(fmt::format("cannot open a pseudo-terminal: {}", errno_text()));
  char name[128];
  if (::grantpt(master) != 0 || ::unlockpt(master) != 0 || ::ptsname_r(master, name, sizeof name) != 0) {
    std::string why = errno_text();
    ::close(master);
    return fail(fmt::format("cannot set up the pseudo-terminal: {}", why));
  }
  int slave = ::open(name, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  termios t{};
  if (slave < 0 || ::tcgetattr(slave, &t) != 0) {
    std::string why = errno_text();
    if (slave >= 0) ::close(slave);
    ::close(master);
    return fail(fmt::format("cannot open {}: {}", name, why));
  }
  // Raw, so the slave's default echo and line editing do not touch telegrams.
  ::cfmakeraw(&t);
  ::tcsetattr(slave, TCSANOW, &t);
  return PtyPair{master, slave, name};
}

void close_pty_pair(PtyPair& pty) {
  for (int* fd : {&pty.master_fd, &pty.keep_slave_fd}) {
    if (*fd >= 0) ::close(*fd);
    *fd = -1;
  }
}

std::optional<LinkError> InProcessTransport::send(std::span<const std::uint8_t> telegram) {
  if (auto reply = answer_(telegram)) {
    if (late_by > 0) delayed_.emplace_back(late_by, std::move(*reply));
    else inbox.push_back(std::move(*reply));
  }
  return std::nullopt;
}

std::variant<std::optional<Bytes>, LinkError> InProcessTransport::receive(Millis timeout) {
  if (inbox.empty()) {
    for (auto& [calls, bytes] : delayed_) --calls;
    while (!delayed_.empty() && delayed_.front().first <= 0) {
      inbox.push_back(std::move(delayed_.front().second));
      delayed_.pop_front();
    }
    if (inbox.empty()) {
      waited += timeout;
      return std::optional<Bytes>{};
    }
  }
  Bytes t = std::move(inbox.front());
  inbox.pop_front();
  return std::optional<Bytes>(std::move(t));
}

}  // namespace nxt
