#include "link/packet.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "rcx/opcodes.h"

namespace rcx {
namespace {

std::uint8_t sum(std::span<const std::uint8_t> bytes) {
  unsigned s = 0;
  for (auto b : bytes) s += b;
  return static_cast<std::uint8_t>(s & 0xff);
}

// The payload size of an operand list (plus the opcode byte) given the bytes
// seen so far: a Length field sizes the Data field after it. 0 = need more.
SizeResult operands_size(std::span<const Operand> operands, std::span<const std::uint8_t> prefix) {
  int offset = 1;
  int data_length = -1;
  for (const auto& o : operands) {
    if (o.role == Role::Data) {
      if (data_length < 0) return SizeError{"a data field without a length"};
      offset += data_length;
      continue;
    }
    int size = field_size(o.type) * o.count;
    if (o.role == Role::Length) {
      if (static_cast<int>(prefix.size()) < offset + size) return 0;
      data_length = read_field(o.type, prefix.data() + offset);
      if (data_length < 0 || data_length > kMaxTransferBlock)
        return SizeError{fmt::format("data length {} is outside 0..{}", data_length, kMaxTransferBlock)};
    }
    offset += size;
  }
  return offset;
}

// Upload datalog answers with `count` dlrecs of 3 bytes (type, value short),
// the count being the request's; on error the reply has no records.
constexpr int kDlrecSize = 3;

}  // namespace

Bytes frame(std::span<const std::uint8_t> payload) {
  Bytes out(std::begin(kPacketHeader), std::end(kPacketHeader));
  out.reserve(3 + 2 * payload.size() + 2);
  for (auto b : payload) {
    out.push_back(b);
    out.push_back(static_cast<std::uint8_t>(~b));
  }
  auto s = sum(payload);
  out.push_back(s);
  out.push_back(static_cast<std::uint8_t>(~s));
  return out;
}

SizeResult request_size(std::span<const std::uint8_t> prefix) {
  if (prefix.empty()) return 0;
  const OpcodeInfo* op = request_at(prefix[0]);
  if (op == nullptr) return SizeError{fmt::format("0x{:02x} is not a request opcode", prefix[0])};
  return operands_size(op->operands, prefix);
}

SizeResult reply_size(std::span<const std::uint8_t> request) {
  if (request.empty()) return SizeError{"empty request"};
  const OpcodeInfo* op = request_at(request[0]);
  if (op == nullptr) return SizeError{fmt::format("0x{:02x} is not a request opcode", request[0])};
  if (!op->replies) return SizeError{fmt::format("{} has no reply", op->name)};
  if (op->op == Op::UploadDatalog) {
    auto full = operands_size(op->operands, request);
    if (auto* n = std::get_if<int>(&full); n == nullptr || static_cast<int>(request.size()) < *n)
      return SizeError{"truncated Upload datalog request"};
    int count = field_value(op->operands, request, "count");
    if (count < 0 || count * kDlrecSize > 2 * kMaxTransferBlock)
      return SizeError{fmt::format("datalog count {} is out of range", count)};
    return 1 + kDlrecSize * count;
  }
  auto n = fixed_size(op->reply);
  if (!n) return SizeError{fmt::format("{} reply has no fixed size", op->name)};
  return 1 + *n;
}

Decoder request_decoder() { return Decoder{Expect::Requests, {}, {}}; }

Decoder reply_decoder(std::span<const std::uint8_t> request) {
  return Decoder{Expect::Reply, Bytes(request.begin(), request.end()), {}};
}

namespace {

// One attempt to read a packet at the start of `buf` (which starts with a
// header). Returns the packet and the bytes it used, a rejection, or nothing
// when more bytes are needed.
struct NeedMore {};
struct Parsed {
  Packet packet;
  std::size_t used;
};
using Attempt = std::variant<NeedMore, Parsed, Rejected>;

// The payload size the decoder expects given the payload bytes seen so far.
SizeResult expected_size(const Decoder& d, std::span<const std::uint8_t> payload) {
  if (d.expect == Expect::Requests) return request_size(payload);
  if (payload.empty()) return 0;
  const std::uint8_t want = reply_code(d.request.empty() ? 0 : d.request[0]);
  if (payload[0] != want) {
    if (payload[0] == reply_code(alternate_form(d.request[0])))
      return SizeError{fmt::format("reply 0x{:02x} answers the previous request, not this one", payload[0])};
    return SizeError{fmt::format("0x{:02x} is not the reply 0x{:02x} we wait for", payload[0], want)};
  }
  return reply_size(d.request);
}

Attempt try_packet(const Decoder& d, std::span<const std::uint8_t> buf) {
  constexpr std::size_t kHeader = std::size(kPacketHeader);
  Bytes payload;
  std::size_t pos = kHeader;
  int size = 0;
  const bool datalog_reply = d.expect == Expect::Reply && !d.request.empty() &&
                             request_at(d.request[0]) == &info(Op::UploadDatalog);
  while (true) {
    if (pos + 2 > buf.size()) return NeedMore{};
    std::uint8_t b = buf[pos], c = buf[pos + 1];
    if (static_cast<std::uint8_t>(b ^ c) != 0xFF)
      return Rejected{fmt::format("byte {} of the packet: 0x{:02x} is not followed by its complement (got 0x{:02x})",
                                  payload.size(), b, c)};
    pos += 2;
    if (size > 0 && static_cast<int>(payload.size()) == size) {
      if (b != sum(payload))
        return Rejected{fmt::format("checksum 0x{:02x} does not match the payload sum 0x{:02x}", b, sum(payload))};
      return Parsed{Packet{std::move(payload)}, pos};
    }
    // An Upload datalog reply with no records (the brick's error answer): the
    // pair after the opcode is the checksum. No dlrec type equals the opcode.
    if (datalog_reply && payload.size() == 1 && b == payload[0]) return Parsed{Packet{std::move(payload)}, pos};
    payload.push_back(b);
    if (size == 0) {
      auto s = expected_size(d, payload);
      if (auto* e = std::get_if<SizeError>(&s)) return Rejected{e->reason};
      size = std::get<int>(s);
    }
  }
}

// Where the next possible header starts in `buf` (a partial header at the end
// counts), or buf.size() when there is none.
std::size_t next_header(std::span<const std::uint8_t> buf, std::size_t from) {
  for (std::size_t i = from; i < buf.size(); ++i) {
    std::size_t n = std::min(buf.size() - i, std::size(kPacketHeader));
    if (std::equal(buf.begin() + static_cast<std::ptrdiff_t>(i), buf.begin() + static_cast<std::ptrdiff_t>(i + n),
                   std::begin(kPacketHeader)))
      return i;
  }
  return buf.size();
}

}  // namespace

std::vector<DecodeEvent> feed(Decoder& d, std::span<const std::uint8_t> bytes) {
  std::vector<DecodeEvent> events;
  d.buffer.insert(d.buffer.end(), bytes.begin(), bytes.end());
  while (!d.buffer.empty()) {
    std::size_t start = next_header(d.buffer, 0);
    if (start > 0) {
      events.push_back(Rejected{fmt::format("skipped {} byte{} that are not a packet header", start,
                                            start == 1 ? "" : "s")});
      d.buffer.erase(d.buffer.begin(), d.buffer.begin() + static_cast<std::ptrdiff_t>(start));
      continue;
    }
    if (d.buffer.size() < std::size(kPacketHeader)) break;
    auto attempt = try_packet(d, d.buffer);
    if (std::holds_alternative<NeedMore>(attempt)) break;
    if (auto* p = std::get_if<Parsed>(&attempt)) {
      d.buffer.erase(d.buffer.begin(), d.buffer.begin() + static_cast<std::ptrdiff_t>(p->used));
      events.push_back(std::move(p->packet));
      continue;
    }
    // Rejected: drop this header's first byte and search again, so a real
    // packet that starts inside the rejected bytes is still found.
    events.push_back(std::move(std::get<Rejected>(attempt)));
    d.buffer.erase(d.buffer.begin());
  }
  return events;
}

Bytes with_toggle(Bytes payload, bool toggle) {
  if (payload.empty()) return payload;
  const OpcodeInfo* op = request_at(payload[0]);
  if (op == nullptr || !op->toggles) return payload;
  payload[0] = toggle ? alternate_form(op->code) : op->code;
  return payload;
}

void append_fields(Bytes& out, std::span<const Operand> layout, std::span<const int> values) {
  std::size_t next = 0;
  for (const auto& o : layout) {
    if (o.role == Role::Data) return;
    for (int i = 0; i < o.count; ++i, ++next) {
      std::size_t at = out.size();
      out.resize(at + static_cast<std::size_t>(field_size(o.type)));
      write_field(o.type, next < values.size() ? values[next] : 0, out.data() + at);
    }
  }
}

int field_value(std::span<const Operand> layout, std::span<const std::uint8_t> payload, std::string_view name,
                int element) {
  std::size_t offset = 1;
  for (const auto& o : layout) {
    std::size_t size = static_cast<std::size_t>(field_size(o.type));
    if (o.name == name) {
      offset += size * static_cast<std::size_t>(element);
      return offset + size <= payload.size() ? read_field(o.type, payload.data() + offset) : 0;
    }
    if (o.role == Role::Data) return 0;
    offset += size * o.count;
  }
  return 0;
}

bool answers(std::span<const std::uint8_t> reply, std::span<const std::uint8_t> request) {
  return !reply.empty() && !request.empty() && reply[0] == reply_code(request[0]);
}

std::string hex(std::span<const std::uint8_t> bytes) {
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i > 0) out += ' ';
    out += fmt::format("{:02x}", bytes[i]);
  }
  return out;
}

std::optional<Bytes> parse_hex(std::string_view text, std::string& error) {
  Bytes out;
  std::string digits;
  auto flush = [&]() -> bool {
    if (digits.empty()) return true;
    if (digits.size() % 2 != 0) {
      error = fmt::format("'{}' has an odd number of hex digits", digits);
      return false;
    }
    for (std::size_t i = 0; i < digits.size(); i += 2)
      out.push_back(static_cast<std::uint8_t>(std::stoi(digits.substr(i, 2), nullptr, 16)));
    digits.clear();
    return true;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '0' && i + 1 < text.size() && (text[i + 1] == 'x' || text[i + 1] == 'X') && digits.empty()) {
      ++i;
      continue;
    }
    if (std::isxdigit(static_cast<unsigned char>(c))) {
      digits += c;
    } else if (c == ' ' || c == ',' || c == ':' || c == '\t') {
      if (!flush()) return std::nullopt;
    } else {
      error = fmt::format("'{}' is not a hex digit", c);
      return std::nullopt;
    }
  }
  if (!flush()) return std::nullopt;
  if (out.empty()) {
    error = "no bytes given";
    return std::nullopt;
  }
  return out;
}

}  // namespace rcx
