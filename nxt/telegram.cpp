#include "nxt/telegram.h"

#include <fmt/format.h>

namespace nxt {
namespace {

std::size_t width_of(const Field& f) {
  switch (f.kind) {
    case FieldKind::U8:
    case FieldKind::S8:
    case FieldKind::Bool: return 1;
    case FieldKind::U16:
    case FieldKind::S16: return 2;
    case FieldKind::U32:
    case FieldKind::S32: return 4;
    case FieldKind::Text:
    case FieldKind::Bytes: return f.width;
    case FieldKind::Rest: return 0;
  }
  return 0;
}

bool is_number(FieldKind k) { return k != FieldKind::Text && k != FieldKind::Bytes && k != FieldKind::Rest; }

std::pair<std::int64_t, std::int64_t> range_of(FieldKind k) {
  switch (k) {
    case FieldKind::U8: return {0, 0xFF};
    case FieldKind::S8: return {-128, 127};
    case FieldKind::Bool: return {0, 0xFF};
    case FieldKind::U16: return {0, 0xFFFF};
    case FieldKind::S16: return {-32768, 32767};
    case FieldKind::U32: return {0, 0xFFFFFFFFLL};
    case FieldKind::S32: return {INT32_MIN, INT32_MAX};
    default: return {0, 0};
  }
}

void put_le(Bytes& out, std::int64_t v, std::size_t width) {
  auto u = static_cast<std::uint64_t>(v);
  for (std::size_t i = 0; i < width; ++i) out.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
}

std::int64_t get_le(std::span<const std::uint8_t> b, FieldKind k) {
  std::uint64_t u = 0;
  for (std::size_t i = 0; i < b.size(); ++i) u |= std::uint64_t{b[i]} << (8 * i);
  switch (k) {
    case FieldKind::S8: return static_cast<std::int8_t>(u);
    case FieldKind::S16: return static_cast<std::int16_t>(u);
    case FieldKind::S32: return static_cast<std::int32_t>(u);
    default: return static_cast<std::int64_t>(u);
  }
}

// Appends the fields of `layout` from `values` to `out`.
std::optional<TelegramError> encode_fields(const Command& c, std::span<const Field> layout,
                                           std::span<const Value> values, Bytes& out) {
  if (values.size() != layout.size())
    return TelegramError{fmt::format("{} takes {} fields, {} given", c.name, layout.size(), values.size())};
  // The length of the Rest field, for fields that count it.
  std::size_t rest_size = 0;
  for (std::size_t i = 0; i < layout.size(); ++i)
    if (layout[i].kind == FieldKind::Rest) {
      if (const auto* b = std::get_if<Bytes>(&values[i])) rest_size = b->size();
      else if (const auto* s = std::get_if<std::string>(&values[i])) rest_size = s->size();
    }
  for (std::size_t i = 0; i < layout.size(); ++i) {
    const Field& f = layout[i];
    const Value& v = values[i];
    if (is_number(f.kind)) {
      const auto* n = std::get_if<std::int64_t>(&v);
      if (!n) return TelegramError{fmt::format("{} {}: a number is needed", c.name, f.name)};
      std::int64_t value = f.counts_rest ? static_cast<std::int64_t>(rest_size) : *n;
      auto [lo, hi] = range_of(f.kind);
      if (value < lo || value > hi)
        return TelegramError{fmt::format("{} {}: {} is out of range {}..{}", c.name, f.name, value, lo, hi)};
      put_le(out, value, width_of(f));
      continue;
    }
    Bytes data;
    if (const auto* s = std::get_if<std::string>(&v)) data.assign(s->begin(), s->end());
    else if (const auto* b = std::get_if<Bytes>(&v)) data = *b;
    else return TelegramError{fmt::format("{} {}: text or bytes are needed", c.name, f.name)};
    if (f.kind == FieldKind::Text) {
      // Room for the terminating NUL, unless the field may come full.
      if (data.size() > f.width || (data.size() == f.width && !f.may_fill))
        return TelegramError{fmt::format("{} {}: \"{}\" is longer than {} characters", c.name, f.name,
                                         std::string(data.begin(), data.end()), f.may_fill ? f.width : f.width - 1)};
      data.resize(f.width, 0);
    } else if (f.kind == FieldKind::Bytes) {
      if (data.size() > f.width)
        return TelegramError{fmt::format("{} {}: {} bytes do not fit in {}", c.name, f.name, data.size(), f.width)};
      data.resize(f.width, 0);
    }
    out.insert(out.end(), data.begin(), data.end());
  }
  return std::nullopt;
}

std::vector<Value> decode_fields(std::span<const Field> layout, std::span<const std::uint8_t> body) {
  std::vector<Value> values;
  std::size_t at = 0;
  for (const Field& f : layout) {
    if (f.kind == FieldKind::Rest) {
      values.emplace_back(Bytes(body.begin() + static_cast<std::ptrdiff_t>(at), body.end()));
      at = body.size();
      continue;
    }
    auto piece = body.subspan(at, width_of(f));
    at += piece.size();
    if (f.kind == FieldKind::Text) values.emplace_back(text_of(piece));
    else if (f.kind == FieldKind::Bytes) values.emplace_back(Bytes(piece.begin(), piece.end()));
    else values.emplace_back(get_le(piece, f.kind));
  }
  return values;
}

std::string group_name(Group g) { return g == Group::Direct ? "direct" : "system"; }

// Checks the body length against the layout.
std::optional<TelegramError> check_length(const Command& c, std::span<const Field> layout, std::size_t got,
                                          std::string_view what, std::span<const std::uint8_t> telegram) {
  std::size_t need = fixed_size(layout);
  bool ok = has_rest(layout) ? got >= need : got == need;
  if (ok) return std::nullopt;
  return TelegramError{fmt::format("{} {} has {} bytes after its header where {}{} are expected: {}", c.name, what,
                                   got, need, has_rest(layout) ? " or more" : "", hex(telegram))};
}

const Field* field_named(const Decoded& d, std::string_view name, std::size_t& index) {
  if (!d.command) return nullptr;
  auto layout = d.is_reply ? d.command->reply : d.command->request;
  if (d.fields.size() != layout.size()) return nullptr;
  for (std::size_t i = 0; i < layout.size(); ++i)
    if (layout[i].name == name) {
      index = i;
      return &layout[i];
    }
  return nullptr;
}

std::string show_number(const Field& f, std::int64_t v) {
  auto named = [&](std::span<const EnumName> names, std::uint8_t value) {
    auto n = enum_name(names, value);
    return n.empty() ? fmt::format("0x{:02x}", value) : std::string(n);
  };
  switch (f.show) {
    case Show::Hex: return fmt::format("0x{:x}", v);
    case Show::SensorType: return named(sensor_types(), static_cast<std::uint8_t>(v));
    case Show::SensorMode: {
      auto mode = named(sensor_modes(), static_cast<std::uint8_t>(v & 0xE0));
      return (v & 0x1F) ? fmt::format("{}+slope{}", mode, v & 0x1F) : mode;
    }
    case Show::OutputMode: return output_mode_names(static_cast<std::uint8_t>(v));
    case Show::Regulation: return named(regulation_modes(), static_cast<std::uint8_t>(v));
    case Show::RunState: return named(run_states(), static_cast<std::uint8_t>(v));
    case Show::Status:
    case Show::Decimal: break;
  }
  return std::to_string(v);
}

// Text from bytes for logs: printable ASCII as is, the rest escaped.
std::string printable(std::span<const std::uint8_t> bytes) {
  std::string s;
  for (auto b : bytes) {
    if (b >= 0x20 && b < 0x7F && b != '"' && b != '\\') s += static_cast<char>(b);
    else s += fmt::format("\\x{:02x}", b);
  }
  return s;
}

}  // namespace

std::size_t fixed_size(std::span<const Field> layout) {
  std::size_t n = 0;
  for (const auto& f : layout) n += width_of(f);
  return n;
}

bool has_rest(std::span<const Field> layout) {
  return !layout.empty() && layout.back().kind == FieldKind::Rest;
}

std::string text_of(std::span<const std::uint8_t> field) {
  std::string s;
  for (auto b : field) {
    if (b == 0) break;
    s += static_cast<char>(b);
  }
  return s;
}

std::string hex(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return "(nothing)";
  std::string s;
  for (auto b : bytes) s += fmt::format("{}{:02x}", s.empty() ? "" : " ", b);
  return s;
}

std::variant<Bytes, TelegramError> encode_request(const Command& command, std::span<const Value> values,
                                                  bool reply_wanted) {
  Bytes out;
  std::uint8_t type = command.group == Group::Direct ? kDirectWithReply : kSystemWithReply;
  out.push_back(reply_wanted ? type : static_cast<std::uint8_t>(type | kNoReplyBit));
  out.push_back(command.opcode);
  if (auto err = encode_fields(command, command.request, values, out)) return *err;
  // Direct commands must fit the brick's 64-byte buffer; system commands
  // (file writes) are bounded by the transport (checked there).
  if (command.group == Group::Direct && out.size() > kMaxTelegram)
    return TelegramError{fmt::format("{} would be {} bytes, more than the {} a direct command may have", command.name,
                                     out.size(), kMaxTelegram)};
  return out;
}

std::variant<Bytes, TelegramError> encode_reply(const Command& command, std::uint8_t status,
                                                std::span<const Value> values) {
  Bytes out{kReply, command.opcode, status};
  if (status != status::kOk && values.empty()) {
    out.resize(out.size() + fixed_size(command.reply), 0);
    return out;
  }
  if (auto err = encode_fields(command, command.reply, values, out)) return *err;
  return out;
}

std::variant<Decoded, TelegramError> decode_request(std::span<const std::uint8_t> telegram) {
  if (telegram.size() < 2)
    return TelegramError{fmt::format("a request needs a type and an opcode; got {}", hex(telegram))};
  std::uint8_t type = telegram[0];
  Group group;
  if ((type & ~kNoReplyBit) == kDirectWithReply) group = Group::Direct;
  else if ((type & ~kNoReplyBit) == kSystemWithReply) group = Group::System;
  else return TelegramError{fmt::format("0x{:02x} is not a request type (0x00, 0x01, 0x80, 0x81): {}", type, hex(telegram))};
  const Command* c = find_command(group, telegram[1]);
  if (!c)
    return TelegramError{fmt::format("0x{:02x} is not a {} command: {}", telegram[1], group_name(group), hex(telegram))};
  auto body = telegram.subspan(2);
  if (auto err = check_length(*c, c->request, body.size(), "request", telegram)) return *err;
  Decoded d;
  d.command = c;
  d.reply_wanted = (type & kNoReplyBit) == 0;
  d.fields = decode_fields(c->request, body);
  return d;
}

std::variant<Decoded, TelegramError> decode_reply(std::span<const std::uint8_t> telegram) {
  if (telegram.size() < 3)
    return TelegramError{fmt::format("a reply needs 0x02, an opcode and a status; got {}", hex(telegram))};
  if (telegram[0] != kReply)
    return TelegramError{fmt::format("0x{:02x} is not the reply type 0x02: {}", telegram[0], hex(telegram))};
  // Opcodes of direct and system commands do not overlap (0x00-0x21 against
  // 0x80-0xA2), so the opcode alone names the command.
  const Command* c = find_command(telegram[1] < 0x80 ? Group::Direct : Group::System, telegram[1]);
  if (!c) return TelegramError{fmt::format("a reply to unknown opcode 0x{:02x}: {}", telegram[1], hex(telegram))};
  Decoded d;
  d.command = c;
  d.is_reply = true;
  d.status = telegram[2];
  auto body = telegram.subspan(3);
  // An error reply may carry only its status (some firmware paths do).
  if (d.status != status::kOk && body.size() < fixed_size(c->reply)) return d;
  if (auto err = check_length(*c, c->reply, body.size(), "reply", telegram)) return *err;
  d.fields = decode_fields(c->reply, body);
  return d;
}

std::variant<Decoded, TelegramError> decode(std::span<const std::uint8_t> telegram) {
  if (!telegram.empty() && telegram[0] == kReply) return decode_reply(telegram);
  return decode_request(telegram);
}

std::optional<std::int64_t> Decoded::number(std::string_view field) const {
  std::size_t i = 0;
  if (!field_named(*this, field, i)) return std::nullopt;
  if (const auto* n = std::get_if<std::int64_t>(&fields[i])) return *n;
  return std::nullopt;
}

std::optional<std::string> Decoded::text(std::string_view field) const {
  std::size_t i = 0;
  if (!field_named(*this, field, i)) return std::nullopt;
  if (const auto* s = std::get_if<std::string>(&fields[i])) return *s;
  return std::nullopt;
}

std::optional<Bytes> Decoded::bytes(std::string_view field) const {
  std::size_t i = 0;
  if (!field_named(*this, field, i)) return std::nullopt;
  if (const auto* b = std::get_if<Bytes>(&fields[i])) return *b;
  return std::nullopt;
}

std::string describe(const Decoded& t) {
  if (!t.command) return "(nothing)";
  std::string s(t.command->name);
  if (t.is_reply) {
    const Status* st = find_status(t.status);
    s += t.status == 0 ? " -> ok" : fmt::format(" -> 0x{:02x} {}", t.status, st ? st->name : "unknown");
  } else if (!t.reply_wanted) {
    s += " (no reply)";
  }
  auto layout = t.is_reply ? t.command->reply : t.command->request;
  for (std::size_t i = 0; i < t.fields.size() && i < layout.size(); ++i) {
    const Field& f = layout[i];
    const Value& v = t.fields[i];
    s += fmt::format(" {}=", f.name);
    if (const auto* n = std::get_if<std::int64_t>(&v)) s += show_number(f, *n);
    else if (const auto* txt = std::get_if<std::string>(&v)) s += fmt::format("\"{}\"", printable({reinterpret_cast<const std::uint8_t*>(txt->data()), txt->size()}));
    else {
      const auto& b = std::get<Bytes>(v);
      // Message data reads as text; other bytes as hex.
      s += f.show == Show::Hex ? fmt::format("[{}]", b.empty() ? "" : hex(b)) : fmt::format("\"{}\"", printable(b));
    }
  }
  return s;
}

}  // namespace nxt
