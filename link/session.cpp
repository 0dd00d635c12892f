#include "link/session.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "rcx/opcodes.h"

namespace rcx {
namespace {

void reject(Link& link, const std::string& reason) {
  ++link.stats.rejected;
  if (link.on_rejected) link.on_rejected(reason);
}

// Throws away whatever is waiting on the line (late replies, noise).
void drain(Link& link) {
  for (int i = 0; i < 64; ++i) {
    auto got = link.port->read(Millis(0));
    auto* bytes = std::get_if<Bytes>(&got);
    if (bytes == nullptr || bytes->empty()) return;
  }
}

struct Attempt {
  std::optional<Bytes> reply;
  std::optional<TransportError> fatal;
  bool heard = false;      // some bytes besides the echo arrived
  bool echo_missing = false;
};

// One transmission of `framed` and the wait for the reply.
Attempt attempt_once(Link& link, const Bytes& request, const Bytes& framed, Millis timeout) {
  Attempt result;
  drain(link);
  if (auto err = link.port->write(framed)) {
    result.fatal = *err;
    return result;
  }
  ++link.stats.attempts;
  link.stats.bytes_sent += framed.size();
  std::size_t echo_left = link.port->echoes() ? framed.size() : 0;
  Decoder decoder = reply_decoder(request);
  const bool expects_reply = request_at(request[0]) != nullptr && request_at(request[0])->replies;
  if (!expects_reply && echo_left == 0) return result;
  // One deadline for the whole reply: a line that trickles bytes must not
  // stretch the wait forever.
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    auto left = std::chrono::duration_cast<Millis>(deadline - std::chrono::steady_clock::now());
    auto got = link.port->read(std::max(left, Millis(0)));
    if (auto* err = std::get_if<TransportError>(&got)) {
      result.fatal = *err;
      return result;
    }
    auto& bytes = std::get<Bytes>(got);
    if (bytes.empty()) break;  // timed out
    std::size_t skip = std::min(echo_left, bytes.size());
    echo_left -= skip;
    if (skip == bytes.size()) {
      if (echo_left == 0 && !expects_reply) return result;
      if (std::chrono::steady_clock::now() >= deadline) break;
      continue;
    }
    result.heard = true;
    for (auto& event : feed(decoder, std::span(bytes).subspan(skip))) {
      if (auto* p = std::get_if<Packet>(&event)) {
        result.reply = std::move(p->payload);
        return result;
      }
      reject(link, std::get<Rejected>(event).reason);
    }
    // A port that never stops delivering (/dev/zero, a broken driver) is
    // never silent long enough to time out: the deadline ends it too.
    if (std::chrono::steady_clock::now() >= deadline) break;
  }
  result.echo_missing = echo_left > 0;
  if (pending(decoder) > 0) reject(link, fmt::format("{} bytes of an incomplete reply", pending(decoder)));
  return result;
}

Millis line_time(const Link& link, std::size_t bytes) {
  return Millis(static_cast<long>(std::ceil(static_cast<double>(bytes) * link.options.byte_seconds * 1000.0)));
}

std::string request_name(const Bytes& request) {
  const OpcodeInfo* op = request_at(request[0]);
  return op ? std::string(op->name) : fmt::format("request 0x{:02x}", request[0]);
}

}  // namespace

Link make_link(Transport& port, LinkOptions options) {
  Link link;
  link.port = &port;
  link.options = options;
  return link;
}

// Sends Alive once per session before anything else (see Link::greeted).
std::optional<LinkError> greet(Link& link, const Bytes& request) {
  if (link.greeted) return std::nullopt;
  link.greeted = true;
  if (request_at(request[0]) == &info(Op::Alive)) return std::nullopt;
  auto r = transact(link, Bytes{info(Op::Alive).code});
  if (auto* e = std::get_if<LinkError>(&r)) return *e;
  return std::nullopt;
}

std::variant<Bytes, LinkError> transact(Link& link, Bytes request) {
  if (request.empty()) return LinkError{"empty request", false};
  if (auto e = greet(link, request)) return *e;
  request = with_toggle(std::move(request), link.toggle);
  link.toggle = !link.toggle;
  ++link.stats.requests;
  const Bytes framed = frame(request);
  auto reply_len = reply_size(request);
  if (auto* e = std::get_if<SizeError>(&reply_len)) return LinkError{e->reason, false};
  std::size_t reply_wire = 3 + 2 * static_cast<std::size_t>(std::get<int>(reply_len)) + 2;
  Millis timeout = line_time(link, (link.port->echoes() ? framed.size() : 0) + reply_wire) + link.options.reply_grace;

  Millis backoff = link.options.backoff;
  bool heard = false, echoed = false;
  for (int attempt = 0; attempt <= link.options.retries; ++attempt) {
    if (attempt > 0) {
      link.port->pause(backoff);
      backoff = std::min(backoff * 2, link.options.max_backoff);
    }
    Attempt a = attempt_once(link, request, framed, timeout);
    if (a.fatal) return LinkError{a.fatal->message, false};
    if (a.reply) return std::move(*a.reply);
    heard = heard || a.heard;
    echoed = echoed || !a.echo_missing;
  }
  int tries = link.options.retries + 1;
  const std::string after = tries == 1 ? "after 1 try" : fmt::format("after {} tries", tries);  // --retries 0
  if (!echoed)
    return LinkError{fmt::format("{} sent nothing back, not even the echo of our bytes (is the tower connected?)",
                                 link.port->describe()),
                     true};
  if (heard)
    return LinkError{fmt::format("no valid reply to {} {} (the replies were garbled; move the RCX "
                                 "closer to the tower)",
                                 request_name(request), after),
                     false};
  return LinkError{fmt::format("no reply to {} {} (is the RCX on and facing the tower?)", request_name(request),
                               after),
                   true};
}

std::variant<std::monostate, LinkError> send_only(Link& link, Bytes request) {
  if (request.empty()) return LinkError{"empty request", false};
  if (auto e = greet(link, request)) return *e;
  ++link.stats.requests;
  const Bytes framed = frame(request);
  Attempt a = attempt_once(link, request, framed, line_time(link, framed.size()) + link.options.reply_grace);
  if (a.fatal) return LinkError{a.fatal->message, false};
  return std::monostate{};
}

Bytes request_payload(const OpcodeInfo& op, std::span<const int> values) {
  Bytes out{op.code};
  append_fields(out, op.operands, values);
  return out;
}

Bytes transfer_payload(int index, std::span<const std::uint8_t> data) {
  const OpcodeInfo& op = info(Op::TransferData);
  Bytes out{op.code};
  unsigned checksum = 0;
  for (auto b : data) checksum += b;
  for (const auto& o : op.operands) {
    std::size_t at = out.size();
    switch (o.role) {
      case Role::Data: out.insert(out.end(), data.begin(), data.end()); continue;
      case Role::Checksum: out.push_back(static_cast<std::uint8_t>(checksum & 0xff)); continue;
      case Role::Length:
        out.resize(at + static_cast<std::size_t>(field_size(o.type)));
        write_field(o.type, static_cast<int>(data.size()), out.data() + at);
        continue;
      default:
        out.resize(at + static_cast<std::size_t>(field_size(o.type)));
        write_field(o.type, index, out.data() + at);
    }
  }
  return out;
}

int reply_field(const OpcodeInfo& op, std::span<const std::uint8_t> reply, std::string_view name, int element) {
  return field_value(op.reply, reply, name, element);
}

}  // namespace rcx
