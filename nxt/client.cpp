#include "nxt/client.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <chrono>
#include <cstring>
#include <thread>

#include <fmt/format.h>

namespace nxt {
namespace {

using Clock = std::chrono::steady_clock;

// File data per Write/Read telegram: a USB Read returns at most 58 data bytes
// (spec/nxt.md), and 58 keeps every Write under the 64-byte packet.
constexpr std::size_t kChunk = 58;
// Sensor valid and I2C ready polls: how often and for how long.
constexpr Millis kPollEvery{5};
constexpr int kPollTries = 200;

CallError from_link(const LinkError& e) {
  return {e.kind == LinkError::Kind::Interrupted ? CallError::Kind::Interrupted : CallError::Kind::Lost, e.message};
}

void log(Client& c, const char* dir, std::span<const std::uint8_t> t) {
  if (!c.on_log) return;
  auto d = decode(t);
  if (auto* ok = std::get_if<Decoded>(&d)) c.on_log(fmt::format("{} {}", dir, describe(*ok)));
  else c.on_log(fmt::format("{} {} (does not parse: {})", dir, hex(t), std::get<TelegramError>(d).message));
}

void wait(Client& c, Millis m) {
  if (c.pause) c.pause(m);
  else std::this_thread::sleep_for(m);
}

// Anything already on the line answers an earlier request: drop it.
std::optional<CallError> drain(Client& c) {
  while (true) {
    auto got = c.transport.receive(Millis(0));
    if (auto* e = std::get_if<LinkError>(&got)) return from_link(*e);
    auto& t = std::get<std::optional<Bytes>>(got);
    if (!t) return std::nullopt;
    ++c.dropped;
    if (c.on_log) c.on_log(fmt::format("dropped a late telegram: {}", hex(*t)));
  }
}

const Command& named(std::string_view name) {
  // Every name used here is in the table (client_test checks each operation).
  return *find_command(name);
}

template <typename T>
T field_or(const Decoded& d, std::string_view name, T fallback) {
  auto v = d.number(name);
  return v ? static_cast<T>(*v) : fallback;
}

}  // namespace

CallError refused(const Decoded& d) {
  return {CallError::Kind::Refused,
          fmt::format("{} refused: 0x{:02x} {}", d.command->name, d.status, status_message(d.status)), d.status};
}

std::variant<Decoded, CallError> call(Client& client, const Command& command, std::span<const Value> values) {
  auto encoded = encode_request(command, values, true);
  if (auto* e = std::get_if<TelegramError>(&encoded)) return CallError{CallError::Kind::Input, e->message};
  const Bytes& request = std::get<Bytes>(encoded);
  if (auto err = drain(client)) return *err;
  log(client, "->", request);
  if (auto err = client.transport.send(request)) return from_link(*err);
  auto deadline = Clock::now() + client.timeout;
  bool first = true;
  // Telegrams that came while waiting but were not this reply: said if the
  // reply never comes, as "no reply" alone hid that the brick did answer.
  std::vector<std::string> others;
  int other_count = 0;
  auto not_ours = [&](const Bytes& t, std::string what) {
    ++client.dropped;
    if (++other_count <= 3) others.push_back(fmt::format("{} ({})", what, hex(t)));
  };
  // The in-process transport answers at once; a real one needs the timeout.
  while (first || Clock::now() < deadline) {
    first = false;
    auto left = std::max(Millis(0), std::chrono::duration_cast<Millis>(deadline - Clock::now()));
    auto got = client.transport.receive(left);
    if (auto* e = std::get_if<LinkError>(&got)) return from_link(*e);
    auto& t = std::get<std::optional<Bytes>>(got);
    if (!t) break;
    log(client, "<-", *t);
    auto decoded = decode_reply(*t);
    if (auto* e = std::get_if<TelegramError>(&decoded)) {
      // A reply to something else that does not parse is still not ours.
      if (t->size() >= 2 && (*t)[0] == kReply && (*t)[1] != command.opcode) {
        not_ours(*t, "a telegram that does not parse");
        continue;
      }
      return CallError{CallError::Kind::BadReply,
                       fmt::format("the reply to {} does not parse: {}", command.name, e->message)};
    }
    auto& d = std::get<Decoded>(decoded);
    if (d.command != &command) {
      // A late reply to an earlier request, or a request sent to us.
      not_ours(*t, d.is_reply ? fmt::format("a reply to {}", d.command->name)
                              : fmt::format("a {} request", d.command->name));
      continue;
    }
    return d;
  }
  std::string message = fmt::format("no reply to {} from {} within {} ms", command.name, client.transport.describe(),
                                    client.timeout.count());
  if (!others.empty())
    message += fmt::format("; what came instead was dropped: {}{}", fmt::join(others, ", "),
                           other_count > static_cast<int>(others.size()) ? ", ..." : "");
  if (auto left = client.transport.leftovers(); !left.empty()) message += "; " + left;
  else if (others.empty()) message += "; " + silence_reasons(client.transport);
  return CallError{CallError::Kind::NoReply, message};
}

std::string silence_reasons(const Transport& link) {
  const std::string asleep =
      "nothing came back: is the brick switched off, or asleep (it switches itself off after the sleep limit set "
      "in its Settings menu)";
  if (link.describe().starts_with("NXT on USB")) return asleep + "?";
  return asleep + ", out of Bluetooth range (about 10 m), or is another program (a terminal, another rcxc) "
                  "reading the port?";
}

std::variant<Decoded, CallError> call_ok(Client& client, std::string_view name, std::span<const Value> values) {
  auto r = call(client, named(name), values);
  if (auto* d = std::get_if<Decoded>(&r); d && d->status != status::kOk) return refused(*d);
  return r;
}

std::optional<CallError> send_only(Client& client, std::string_view name, std::span<const Value> values) {
  auto encoded = encode_request(named(name), values, false);
  if (auto* e = std::get_if<TelegramError>(&encoded)) return CallError{CallError::Kind::Input, e->message};
  log(client, "->", std::get<Bytes>(encoded));
  if (auto err = client.transport.send(std::get<Bytes>(encoded))) return from_link(*err);
  return std::nullopt;
}

std::optional<std::string> check_file_name(const std::string& name) {
  if (name.empty()) return "a file name cannot be empty";
  auto dot = name.rfind('.');
  std::string stem = dot == std::string::npos ? name : name.substr(0, dot);
  std::string ext = dot == std::string::npos ? "" : name.substr(dot + 1);
  if (stem.empty() || stem.size() > 15 || ext.size() > 3)
    return fmt::format("\"{}\" is not an NXT file name: at most 15 characters, a dot and 3 (15.3)", name);
  for (char c : name)
    if (c <= 0x20 || c >= 0x7F || c == '/' || c == '\\' || c == '*')
      return fmt::format("\"{}\" is not an NXT file name: printable characters only, no spaces, slashes or *", name);
  return std::nullopt;
}

std::variant<std::vector<FileEntry>, CallError> list_files(Client& client, const std::string& pattern) {
  std::vector<FileEntry> out;
  std::vector<Value> first{pattern};
  auto r = call(client, named("FindFirst"), first);
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  auto d = std::get<Decoded>(r);
  // No match answers 0x87 "file not found": an empty list, not an error
  // (and FindFirst's handle is closed by then).
  if (d.status != status::kOk) {
    if (d.status != status::kFileNotFound && d.status != status::kNoMoreFiles) return refused(d);
    return out;
  }
  const std::int64_t handle = field_or<int>(d, "handle", 0);
  while (d.status == status::kOk) {
    out.push_back({d.text("name").value_or(""), field_or<std::uint32_t>(d, "size", 0)});
    std::vector<Value> next{handle};
    auto n = call(client, named("FindNext"), next);
    if (auto* e = std::get_if<CallError>(&n)) return *e;
    d = std::get<Decoded>(n);
  }
  // FindNext's handle stays open after its last match (LEGO's loader closes
  // only after a FindFirst error): close it, or every listing costs one of
  // the brick's 16 handles. A firmware that closed it answers 0x88.
  std::vector<Value> close{handle};
  auto c = call(client, named("Close"), close);
  if (auto* e = std::get_if<CallError>(&c)) return *e;
  auto closed = std::get<Decoded>(c).status;
  if (closed != status::kOk && closed != status::kHandleClosed) return refused(std::get<Decoded>(c));
  if (d.status != status::kFileNotFound && d.status != status::kNoMoreFiles) return refused(d);
  return out;
}

std::optional<CallError> upload_file(Client& client, const std::string& name, std::span<const std::uint8_t> data,
                                     const Progress& progress) {
  if (auto bad = check_file_name(name)) return CallError{CallError::Kind::Input, *bad};
  std::vector<Value> open{name, static_cast<std::int64_t>(data.size())};
  auto r = call_ok(client, "OpenWrite", open);
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  std::int64_t handle = *std::get<Decoded>(r).number("handle");
  for (std::size_t at = 0; at < data.size();) {
    std::size_t n = std::min(kChunk, data.size() - at);
    std::vector<Value> write{handle, Bytes(data.begin() + static_cast<std::ptrdiff_t>(at),
                                           data.begin() + static_cast<std::ptrdiff_t>(at + n))};
    auto w = call_ok(client, "Write", write);
    // After an error the firmware has closed the handle itself.
    if (auto* e = std::get_if<CallError>(&w)) return *e;
    auto written = std::get<Decoded>(w).number("count").value_or(0);
    if (written != static_cast<std::int64_t>(n))
      return CallError{CallError::Kind::BadReply, fmt::format("the brick wrote {} of {} bytes", written, n)};
    at += n;
    if (progress) progress(at, data.size());
  }
  std::vector<Value> close{handle};
  auto c = call_ok(client, "Close", close);
  if (auto* e = std::get_if<CallError>(&c)) return *e;
  if (progress && data.empty()) progress(0, 0);
  return std::nullopt;
}

std::variant<Bytes, CallError> download_file(Client& client, const std::string& name, const Progress& progress) {
  if (auto bad = check_file_name(name)) return CallError{CallError::Kind::Input, *bad};
  std::vector<Value> open{name};
  auto r = call_ok(client, "OpenRead", open);
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  const auto& d = std::get<Decoded>(r);
  std::int64_t handle = *d.number("handle");
  std::size_t size = static_cast<std::size_t>(*d.number("size"));
  Bytes out;
  while (out.size() < size) {
    std::int64_t want = static_cast<std::int64_t>(std::min(kChunk, size - out.size()));
    std::vector<Value> read{handle, want};
    auto got = call_ok(client, "Read", read);
    if (auto* e = std::get_if<CallError>(&got)) return *e;
    // The count echoes what was asked and data past the end of the file is
    // zero padding: only the size from OpenRead tells, so never ask past it.
    auto data = std::get<Decoded>(got).bytes("data").value_or(Bytes{});
    if (data.empty() || data.size() > static_cast<std::size_t>(want))
      return CallError{CallError::Kind::BadReply,
                       fmt::format("Read of {} bytes brought {} bytes", want, data.size())};
    out.insert(out.end(), data.begin(), data.end());
    if (progress) progress(out.size(), size);
  }
  std::vector<Value> close{handle};
  auto c = call_ok(client, "Close", close);
  if (auto* e = std::get_if<CallError>(&c)) return *e;
  return out;
}

// LEGO's firmware answers GetFirmwareVersion with protocol 1.124; leJOS's
// LCP.java with protocol 1.2 (docs/nxt.md says what this rests on).
bool is_lego_firmware(const FirmwareVersion& v) { return v.protocol_major == 1 && v.protocol_minor == 124; }

std::variant<FirmwareVersion, CallError> firmware_version(Client& client) {
  auto r = call_ok(client, "GetFirmwareVersion", {});
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  const auto& d = std::get<Decoded>(r);
  return FirmwareVersion{field_or<int>(d, "protocol_major", 0), field_or<int>(d, "protocol_minor", 0),
                         field_or<int>(d, "firmware_major", 0), field_or<int>(d, "firmware_minor", 0)};
}

std::optional<CallError> require_lego_firmware(Client& client, std::string_view what) {
  auto r = firmware_version(client);
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  const auto& v = std::get<FirmwareVersion>(r);
  if (is_lego_firmware(v)) return std::nullopt;
  std::string which = v.protocol_major == 1 && v.protocol_minor == 2 ? " (leJOS NXJ answers so)" : "";
  return CallError{CallError::Kind::Refused,
                   fmt::format("the brick's firmware is not LEGO's: it answers protocol {}.{}, firmware {}.{:02}{}, "
                               "and LEGO's answers protocol 1.124; {} was not sent, as other firmwares give its "
                               "command another meaning (leJOS: 0x20 disconnects, 0x21 defragments the flash)",
                               v.protocol_major, v.protocol_minor, v.firmware_major, v.firmware_minor, which, what)};
}

std::variant<std::uint32_t, CallError> get_property(Client& client, Property property) {
  std::vector<Value> v{static_cast<std::int64_t>(property)};
  auto r = call_ok(client, "GetProperty", v);
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  Bytes value = std::get<Decoded>(r).bytes("value").value_or(Bytes{});
  // One byte for Bluetooth and volume, a u32 for the sleep limit (c_cmd.c).
  std::size_t want = property == Property::SleepMs ? 4 : 1;
  if (value.size() != want)
    return CallError{CallError::Kind::BadReply, fmt::format("GetProperty {} answered {} bytes ({}), not {}",
                                                            static_cast<int>(property), value.size(), hex(value), want)};
  std::uint32_t out = 0;
  for (std::size_t i = 0; i < value.size(); ++i) out |= std::uint32_t{value[i]} << (8 * i);
  return out;
}

std::optional<CallError> set_property(Client& client, Property property, std::uint32_t value) {
  Bytes bytes{static_cast<std::uint8_t>(value)};
  if (property == Property::SleepMs)
    bytes = {static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8),
             static_cast<std::uint8_t>(value >> 16), static_cast<std::uint8_t>(value >> 24)};
  std::vector<Value> v{static_cast<std::int64_t>(property), bytes};
  auto r = call_ok(client, "SetProperty", v);
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  return std::nullopt;
}

namespace {

// The firmware has a dozen modules; more means the search never ends.
constexpr std::size_t kMaxModules = 64;
// A USB packet less the reply's 0x02, opcode, status, ID and count: 55 data
// bytes; a WriteIOMap request less type, opcode, ID, offset, count: 54.
constexpr std::size_t kIoMapReadChunk = 55;
constexpr std::size_t kIoMapWriteChunk = 54;

ModuleEntry module_of(const Decoded& d) {
  return {d.text("name").value_or(""), field_or<std::uint32_t>(d, "module_id", 0), field_or<std::uint32_t>(d, "size", 0),
          field_or<std::uint16_t>(d, "iomap_size", 0)};
}

std::optional<CallError> close_module_search(Client& client) {
  std::vector<Value> close{std::int64_t{0}};
  auto c = call(client, named("CloseModuleHandle"), close);
  if (auto* e = std::get_if<CallError>(&c)) return *e;
  return std::nullopt;
}

}  // namespace

std::variant<std::vector<ModuleEntry>, CallError> list_modules(Client& client, const std::string& pattern) {
  std::vector<ModuleEntry> out;
  std::vector<Value> first{pattern};
  auto r = call(client, named("FindFirstModule"), first);
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  if (std::get<Decoded>(r).status == status::kNoMoreHandles) {
    // A search another host left open: end it and ask again.
    if (auto e = close_module_search(client)) return *e;
    r = call(client, named("FindFirstModule"), first);
    if (auto* e = std::get_if<CallError>(&r)) return *e;
  }
  auto d = std::get<Decoded>(r);
  const std::int64_t handle = field_or<int>(d, "handle", 0);
  while (d.status == status::kOk && out.size() < kMaxModules) {
    out.push_back(module_of(d));
    std::vector<Value> next{handle};
    auto n = call(client, named("FindNextModule"), next);
    if (auto* e = std::get_if<CallError>(&n)) return *e;
    d = std::get<Decoded>(n);
  }
  // Running out of modules does not end the loader's one search: end it
  // whatever came, or the next search answers 0x81.
  if (auto e = close_module_search(client)) return *e;
  if (d.status != status::kOk && d.status != status::kModuleNotFound) return refused(d);
  if (d.status == status::kOk)
    return CallError{CallError::Kind::BadReply, fmt::format("the module search did not end after {} modules", kMaxModules)};
  return out;
}

std::variant<Bytes, CallError> read_iomap(Client& client, std::uint32_t module_id, std::uint16_t offset,
                                          std::size_t count) {
  Bytes out;
  while (out.size() < count) {
    std::size_t want = std::min(kIoMapReadChunk, count - out.size());
    std::vector<Value> v{std::int64_t{module_id}, static_cast<std::int64_t>(offset + out.size()),
                         static_cast<std::int64_t>(want)};
    auto r = call_ok(client, "ReadIOMap", v);
    if (auto* e = std::get_if<CallError>(&r)) return *e;
    const auto& d = std::get<Decoded>(r);
    Bytes data = d.bytes("data").value_or(Bytes{});
    auto got = static_cast<std::size_t>(d.number("count").value_or(0));
    if (got != want || data.size() < want)
      return CallError{CallError::Kind::BadReply,
                       fmt::format("ReadIOMap of {} bytes at {} brought {} ({} data bytes)", want, offset + out.size(),
                                   got, data.size())};
    out.insert(out.end(), data.begin(), data.begin() + static_cast<std::ptrdiff_t>(want));
  }
  return out;
}

std::optional<CallError> write_iomap(Client& client, std::uint32_t module_id, std::uint16_t offset,
                                     std::span<const std::uint8_t> data) {
  for (std::size_t at = 0; at < data.size();) {
    std::size_t n = std::min(kIoMapWriteChunk, data.size() - at);
    std::vector<Value> v{std::int64_t{module_id}, static_cast<std::int64_t>(offset + at), static_cast<std::int64_t>(n),
                         Bytes(data.begin() + static_cast<std::ptrdiff_t>(at),
                               data.begin() + static_cast<std::ptrdiff_t>(at + n))};
    auto r = call_ok(client, "WriteIOMap", v);
    if (auto* e = std::get_if<CallError>(&r)) return *e;
    auto written = std::get<Decoded>(r).number("count").value_or(0);
    if (written != static_cast<std::int64_t>(n))
      return CallError{CallError::Kind::BadReply, fmt::format("WriteIOMap wrote {} of {} bytes", written, n)};
    at += n;
  }
  return std::nullopt;
}

std::variant<std::vector<BtEntry>, CallError> bluetooth_table(Client& client, bool contacts) {
  auto count = call_ok(client, contacts ? "BTGetContactCount" : "BTGetConnCount", {});
  if (auto* e = std::get_if<CallError>(&count)) return *e;
  auto slots = std::get<Decoded>(count).number("count").value_or(0);
  std::vector<BtEntry> out;
  for (std::int64_t i = 0; i < slots; ++i) {
    std::vector<Value> v{i};
    auto r = call_ok(client, contacts ? "BTGetContactName" : "BTGetConnName", v);
    if (auto* e = std::get_if<CallError>(&r)) return *e;
    const auto& d = std::get<Decoded>(r);
    std::string name = d.text("name").value_or("");
    if (!name.empty()) out.push_back({static_cast<int>(i), field_or<int>(d, "device_type", 0), name});
  }
  return out;
}

std::variant<int, CallError> read_ultrasonic(Client& client, int port) {
  const std::int64_t p = port;
  std::vector<Value> get{p};
  auto state = call_ok(client, "GetInputValues", get);
  if (auto* e = std::get_if<CallError>(&state)) return *e;
  if (std::get<Decoded>(state).number("type") != kLowSpeed9V) {
    std::vector<Value> mode{p, std::int64_t{kLowSpeed9V}, std::int64_t{0}};
    auto m = call_ok(client, "SetInputMode", mode);
    if (auto* e = std::get_if<CallError>(&m)) return *e;
  }
  // I2C commands fail with 0xE0 until the port reads valid.
  for (int i = 0;; ++i) {
    auto v = call_ok(client, "GetInputValues", get);
    if (auto* e = std::get_if<CallError>(&v)) return *e;
    if (std::get<Decoded>(v).number("valid").value_or(0) != 0) break;
    if (i == kPollTries) return CallError{CallError::Kind::NoReply, fmt::format("input port {} never became valid", port + 1)};
    wait(client, kPollEvery);
  }
  // Device address 0x02, register 0x42: the first distance in cm.
  std::vector<Value> write{p, std::int64_t{2}, std::int64_t{1}, Bytes{0x02, 0x42}};
  auto w = call_ok(client, "LSWrite", write);
  if (auto* e = std::get_if<CallError>(&w)) return *e;
  for (int i = 0;; ++i) {
    auto s = call(client, named("LSGetStatus"), get);
    if (auto* e = std::get_if<CallError>(&s)) return *e;
    const auto& d = std::get<Decoded>(s);
    if (d.status == status::kOk && d.number("bytes_ready").value_or(0) >= 1) break;
    if (d.status == status::kBusError) {
      CallError e = refused(d);
      e.message += fmt::format(": no I2C device answered at address 0x02 (is the ultrasonic sensor on input port {}?)",
                               port + 1);
      return e;
    }
    if (d.status != status::kOk && d.status != status::kPending) return refused(d);
    if (i == kPollTries) return CallError{CallError::Kind::NoReply, "the ultrasonic sensor never answered"};
    wait(client, kPollEvery);
  }
  auto r = call_ok(client, "LSRead", get);
  if (auto* e = std::get_if<CallError>(&r)) return *e;
  const auto& d = std::get<Decoded>(r);
  auto data = d.bytes("rx_data").value_or(Bytes{});
  if (d.number("bytes_read").value_or(0) < 1 || data.empty())
    return CallError{CallError::Kind::BadReply, "LSRead brought no byte"};
  return static_cast<int>(data[0]);
}

Bytes message_text(const std::string& text) {
  Bytes b(text.begin(), text.end());
  b.push_back(0);
  return b;
}

Bytes message_int(std::int32_t value) {
  auto u = static_cast<std::uint32_t>(value);
  return {static_cast<std::uint8_t>(u), static_cast<std::uint8_t>(u >> 8), static_cast<std::uint8_t>(u >> 16),
          static_cast<std::uint8_t>(u >> 24), 0};
}

Bytes message_float(float value) {
  auto u = std::bit_cast<std::uint32_t>(value);
  return {static_cast<std::uint8_t>(u), static_cast<std::uint8_t>(u >> 8), static_cast<std::uint8_t>(u >> 16),
          static_cast<std::uint8_t>(u >> 24), 0};
}

std::string show_message(std::span<const std::uint8_t> data) {
  std::size_t end = data.size();
  if (end > 0 && data[end - 1] == 0) --end;
  bool text = std::all_of(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(end),
                          [](std::uint8_t b) { return b >= 0x20 && b < 0x7F; });
  if (text) return std::string(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(end));
  if (end == 4) {
    std::uint32_t u = data[0] | (data[1] << 8) | (data[2] << 16) | (std::uint32_t{data[3]} << 24);
    // NXC sends int32, NXT-G float32: the bytes do not say which. Show the
    // float reading only when it is a plausible number.
    float f = std::bit_cast<float>(u);
    float size = std::fabs(f);
    if (std::isnormal(f) && size >= 1e-6f && size <= 1e9f)
      return fmt::format("{} (int32) / {} (float32)", static_cast<std::int32_t>(u), f);
    return fmt::format("{} (int32)", static_cast<std::int32_t>(u));
  }
  return hex(data);
}

}  // namespace nxt
