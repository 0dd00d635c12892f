// Telegrams built and read from the command table: a request is
// `type, opcode, fields`, a reply `0x02, opcode, status, fields`.
//
// Field values are integers, text or bytes, one per field of the table entry
// and in its order. Decoding checks the length against the layout, so a
// truncated or overlong telegram is an error that says what came back.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "nxt/commands.h"

namespace nxt {

using Bytes = std::vector<std::uint8_t>;
using Value = std::variant<std::int64_t, std::string, Bytes>;

struct TelegramError {
  std::string message;
};

struct Decoded {
  const Command* command = nullptr;
  bool is_reply = false;
  bool reply_wanted = true;  // requests: type byte without the 0x80 bit
  std::uint8_t status = 0;   // replies only
  // One value per field of the layout; empty for an error reply whose body
  // was not sent in full.
  std::vector<Value> fields;

  // The value of the named field (the layout's names), or nullopt.
  std::optional<std::int64_t> number(std::string_view field) const;
  std::optional<std::string> text(std::string_view field) const;
  std::optional<Bytes> bytes(std::string_view field) const;
};

// A request: one value per field of `command.request`, in order. A field
// that counts the Rest data (MessageWrite's size) is recomputed from the
// data, so the two cannot disagree; each value is checked against its type.
std::variant<Bytes, TelegramError> encode_request(const Command& command, std::span<const Value> values,
                                                  bool reply_wanted = true);
// A reply with `status`; with a non-zero status and no values, the body is
// zero-filled to the full layout, as the firmware does.
std::variant<Bytes, TelegramError> encode_reply(const Command& command, std::uint8_t status,
                                                std::span<const Value> values);

std::variant<Decoded, TelegramError> decode_request(std::span<const std::uint8_t> telegram);
std::variant<Decoded, TelegramError> decode_reply(std::span<const std::uint8_t> telegram);
// Either, by the type byte.
std::variant<Decoded, TelegramError> decode(std::span<const std::uint8_t> telegram);

// The fixed length of a layout's fields, and whether it ends in a Rest field.
std::size_t fixed_size(std::span<const Field> layout);
bool has_rest(std::span<const Field> layout);

// "SetOutputState port=0 power=75 mode=MOTORON|BRAKE ..." for logs and -v;
// replies add "-> status" first.
std::string describe(const Decoded& telegram);
// "02 0b 00 ..." for messages about telegrams that do not parse.
std::string hex(std::span<const std::uint8_t> bytes);

// Text fields: the string up to its first NUL.
std::string text_of(std::span<const std::uint8_t> field);

}  // namespace nxt
