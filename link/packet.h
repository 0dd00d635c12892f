// The RCX infrared packet: framing, the 0x08 toggle, reply codes, and a
// streaming decoder that finds packets in a noisy byte stream.
//
// On the wire a message is `55 FF 00`, then each payload byte followed by its
// complement, then the sum of the payload bytes (mod 256) and its complement.
// The decoder never trusts a length it has not checked: the payload length of
// every request and reply comes from the opcode table (rcx/opcodes.h);
// only Transfer data carries a length field, which is bounded before use, and
// the Upload datalog reply's length comes from the request it answers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace rcx {

using Bytes = std::vector<std::uint8_t>;

inline constexpr std::uint8_t kPacketHeader[] = {0x55, 0xFF, 0x00};
// The largest Transfer data block either side accepts. The RCX has about 6 KB
// of program memory; nothing sends blocks this large, so a larger length field
// can only be corruption.
inline constexpr int kMaxTransferBlock = 512;

// Frames a payload (opcode + arguments) for the wire.
Bytes frame(std::span<const std::uint8_t> payload);

// Payload sizes. `request_size` looks at the payload bytes seen so far (the
// opcode, and for Transfer data its length field) and says how long the whole
// payload is, 0 when more bytes are needed to know, or an error.
struct SizeError {
  std::string reason;
};
using SizeResult = std::variant<int, SizeError>;
SizeResult request_size(std::span<const std::uint8_t> prefix);
// The payload size of the reply to `request` (a whole request payload), or an
// error when the request has no reply.
SizeResult reply_size(std::span<const std::uint8_t> request);

// What the decoder is looking for.
enum class Expect : std::uint8_t {
  Requests,  // a brick: any request
  Reply,     // a host: the reply to one request
};

struct Packet {
  Bytes payload;
};
struct Rejected {
  std::string reason;  // why the bytes were not a packet
};
using DecodeEvent = std::variant<Packet, Rejected>;

// A streaming decoder. Feed it bytes as they arrive; it returns packets and
// rejections. After a rejection it looks for a header again from the byte
// after the rejected header, so a packet hidden behind garbage is still found.
struct Decoder {
  Expect expect = Expect::Requests;
  Bytes request;  // Expect::Reply: the request whose reply we wait for
  Bytes buffer;   // bytes received but not yet consumed
};

Decoder request_decoder();
Decoder reply_decoder(std::span<const std::uint8_t> request);

// Appends `bytes` and returns every packet/rejection they complete.
std::vector<DecodeEvent> feed(Decoder& decoder, std::span<const std::uint8_t> bytes);

// Bytes that have arrived but do not yet make a packet (for timeout messages).
inline std::size_t pending(const Decoder& decoder) { return decoder.buffer.size(); }

// The toggle: the two forms of a request opcode differ in bit 0x08. Returns
// `payload` with its opcode set to the form `toggle` selects (false = the
// table's code, true = code ^ 0x08); opcodes without a second form unchanged.
Bytes with_toggle(Bytes payload, bool toggle);

// Fields of a payload by a layout of the opcode table (operands or reply).
// `append_fields` writes `values` in layout order (a repeated field takes
// `count` values, missing values are 0) and stops at a Data field;
// `field_value` reads field `name` (element `element` of a repeated field)
// from a payload whose byte 0 is the opcode, or 0 when it is not there.
struct Operand;
void append_fields(Bytes& out, std::span<const Operand> layout, std::span<const int> values);
int field_value(std::span<const Operand> layout, std::span<const std::uint8_t> payload, std::string_view name,
                int element = 0);

// Does `reply` answer `request` (reply opcode = complement of request opcode)?
bool answers(std::span<const std::uint8_t> reply, std::span<const std::uint8_t> request);

// Hex dump "55 ff 00" for messages and `rcxc remote raw`.
std::string hex(std::span<const std::uint8_t> bytes);
// Parses "12 1a" / "121a" / "0x12,0x1a"; nullopt with `error` set when bad.
std::optional<Bytes> parse_hex(std::string_view text, std::string& error);

}  // namespace rcx
