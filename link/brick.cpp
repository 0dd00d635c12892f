#include "link/brick.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "link/session.h"
#include "rcx/opcodes.h"

namespace rcx {
namespace {

constexpr std::array<int, 5> kVersionsKey = {1, 3, 5, 7, 11};
// "LEGO" and the registered sign, the unlock key of the seed.
constexpr std::array<int, 5> kUnlockKey = {76, 69, 71, 79, 174};
constexpr std::string_view kUnlockText = "Just a bit off the block!";
constexpr std::size_t kLogLimit = 1000;

// Transfer data error codes (seed).
constexpr int kOk = 0, kBlockChecksum = 3, kFirmwareChecksum = 4, kNoDownload = 6;

void note(Brick& b, std::string message) {
  if (b.log.size() < kLogLimit) b.log.push_back(std::move(message));
}

// Field `name` of a request, read through the opcode table.
int field(std::span<const std::uint8_t> request, std::string_view name, int element = 0) {
  return field_value(request_at(request[0])->operands, request, name, element);
}

bool key_is(std::span<const std::uint8_t> request, const std::array<int, 5>& key) {
  for (int i = 0; i < 5; ++i)
    if (field(request, "key", i) != key[static_cast<std::size_t>(i)]) return false;
  return true;
}

// A reply to `request`: the complement opcode, then `fields` written by the
// reply layout of the table (repeated fields take consecutive values).
Bytes reply_with(std::span<const std::uint8_t> request, std::span<const int> fields = {}) {
  Bytes out{reply_code(request[0])};
  append_fields(out, request_at(request[0])->reply, fields);
  return out;
}

Bytes error_reply(std::span<const std::uint8_t> request, int code) {
  std::array<int, 1> v{code};
  return reply_with(request, v);
}

std::optional<Bytes> transfer(Brick& b, std::span<const std::uint8_t> request) {
  BrickProtocol& p = b.protocol;
  const int index = field(request, "index");
  const int length = field(request, "length");
  auto data = std::span(request).subspan(5, static_cast<std::size_t>(length));
  const int checksum = request[5 + static_cast<std::size_t>(length)];
  if (p.target == DownloadTarget::None) return error_reply(request, kNoDownload);
  if (index != 0 && index != p.next_block) {
    note(b, fmt::format("block {} out of order (expected {}): no reply", index, p.next_block));
    return std::nullopt;
  }
  unsigned sum = 0;
  for (auto v : data) sum += v;
  // The block checksum is only checked for non-final blocks (seed).
  if (index != 0 && static_cast<int>(sum & 0xff) != checksum) {
    // The ROM bug: a firmware block with a bad checksum still advances the
    // sequence, so the host must number its retransmission one higher.
    if (p.target == DownloadTarget::Firmware) ++p.next_block;
    return error_reply(request, kBlockChecksum);
  }
  if (p.target == DownloadTarget::Program) {
    b.vm.write_download(data);
  } else {
    p.firmware_sum += sum;
  }
  if (index != 0) {
    ++p.next_block;
    return error_reply(request, kOk);
  }
  // The final block closes the download.
  DownloadTarget finished = p.target;
  p.target = DownloadTarget::None;
  if (finished == DownloadTarget::Program) {
    b.vm.end_download();
    return error_reply(request, kOk);
  }
  p.firmware_ready = static_cast<int>(p.firmware_sum & 0xffff) == (p.firmware_checksum & 0xffff);
  return error_reply(request, p.firmware_ready ? kOk : kFirmwareChecksum);
}

std::optional<Bytes> start_download(Brick& b, std::span<const std::uint8_t> request, bool task) {
  const int index = field(request, task ? "task" : "subroutine");
  const int length = field(request, "length");
  DownloadStatus status = task ? b.vm.begin_task_download(index, length) : b.vm.begin_sub_download(index, length);
  b.protocol.target = status == DownloadStatus::Ok ? DownloadTarget::Program : DownloadTarget::None;
  b.protocol.next_block = 1;
  return error_reply(request, static_cast<int>(status));
}

std::optional<Bytes> upload_datalog(Brick& b, std::span<const std::uint8_t> request) {
  auto entries = b.vm.upload_datalog(field(request, "first"), field(request, "count"));
  Bytes out{reply_code(request[0])};
  // An error (out of range) answers with no records.
  if (static_cast<int>(entries.size()) != field(request, "count")) return out;
  for (const auto& e : entries) {
    out.push_back(e.type);
    std::uint8_t v[2];
    write_field(FieldType::Short, e.value, v);
    out.insert(out.end(), v, v + 2);
  }
  return out;
}

// Without firmware only the ROM answers, and it knows only these requests.
bool rom_handles(Op op) {
  switch (op) {
    case Op::Alive: case Op::GetVersions: case Op::GetBatteryPower: case Op::DeleteFirmware:
    case Op::StartFirmwareDownload: case Op::TransferData: case Op::UnlockFirmware: case Op::PowerOff:
      return true;
    default:
      return false;
  }
}

std::optional<Bytes> execute(Brick& b, std::span<const std::uint8_t> request) {
  const OpcodeInfo& op = *request_at(request[0]);
  if (!b.vm.firmware_present() && !rom_handles(op.op)) {
    note(b, fmt::format("{}: no firmware installed, only the ROM answers", op.name));
    return std::nullopt;
  }
  switch (op.op) {
    case Op::Alive: return reply_with(request);
    case Op::GetVersions: {
      if (!key_is(request, kVersionsKey)) {
        note(b, "Get versions with a wrong key: no reply");
        return std::nullopt;
      }
      auto v = b.vm.versions();
      return reply_with(request, v);
    }
    case Op::GetBatteryPower: {
      std::array<int, 1> mv{b.vm.battery_mv()};
      return reply_with(request, mv);
    }
    case Op::GetMemoryMap: {
      auto map = b.vm.memory_map();
      std::vector<int> v(map.begin(), map.end());
      return reply_with(request, v);
    }
    case Op::StartTaskDownload: return start_download(b, request, true);
    case Op::StartSubroutineDownload: return start_download(b, request, false);
    case Op::TransferData: return transfer(b, request);
    case Op::UploadDatalog: return upload_datalog(b, request);
    case Op::DeleteFirmware:
      if (!key_is(request, kVersionsKey)) return reply_with(request);  // wrong key: nothing happens
      b.vm.set_firmware_present(false);
      // A task or subroutine download the firmware had open goes with it.
      b.vm.end_download();
      b.protocol.target = DownloadTarget::None;
      b.protocol.firmware_ready = false;
      return reply_with(request);
    case Op::StartFirmwareDownload:
      if (b.vm.firmware_present()) {
        note(b, "Start firmware download while firmware is installed: ignored, no reply");
        return std::nullopt;
      }
      b.protocol.target = DownloadTarget::Firmware;
      b.protocol.next_block = 1;
      b.protocol.firmware_checksum = field(request, "checksum");
      b.protocol.firmware_sum = 0;
      b.protocol.firmware_ready = false;
      return error_reply(request, kOk);
    case Op::UnlockFirmware: {
      if (!key_is(request, kUnlockKey)) {
        note(b, "Unlock firmware with a wrong key: no reply");
        return std::nullopt;
      }
      if (b.protocol.firmware_ready) b.vm.set_firmware_present(true);
      b.protocol.firmware_ready = false;
      Bytes out{reply_code(request[0])};
      out.insert(out.end(), kUnlockText.begin(), kUnlockText.end());
      return out;
    }
    case Op::SetMessage:
      b.vm.set_message(field(request, "message"));
      return std::nullopt;
    default: {
      DirectReply r = b.vm.execute_direct(request);
      if (!r.ok) {
        note(b, fmt::format("{}: {}", op.name, r.error));
        return std::nullopt;
      }
      Bytes out{reply_code(request[0])};
      out.insert(out.end(), r.payload.begin(), r.payload.end());
      return out;
    }
  }
}

}  // namespace

Noise make_noise(double probability, std::uint64_t seed) { return Noise{probability, std::mt19937_64(seed)}; }

Bytes apply_noise(Noise& noise, std::span<const std::uint8_t> bytes) {
  if (noise.probability <= 0.0) return Bytes(bytes.begin(), bytes.end());
  Bytes out;
  out.reserve(bytes.size());
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  std::uniform_int_distribution<int> bit(0, 7);
  for (auto byte : bytes) {
    if (chance(noise.rng) >= noise.probability) {
      out.push_back(byte);
    } else if (chance(noise.rng) < 0.5) {
      out.push_back(static_cast<std::uint8_t>(byte ^ (1u << bit(noise.rng))));
    }  // else: lost
  }
  return out;
}

Brick make_brick(Config config) { return Brick{Machine(config), {}, request_decoder(), {}, {}}; }

std::optional<Bytes> answer(Brick& b, std::span<const std::uint8_t> request) {
  ++b.counters.requests;
  if (b.vm.stop().kind == StopKind::PowerOff) return std::nullopt;
  // The same request in the same toggle form again: the host missed our
  // reply. Send it again without executing twice. Not Alive: every session
  // starts with it in the same form, so `rcxc remote alive` twice counted
  // the second session's greeting as a retransmission; answering it again
  // changes nothing, so it is a new request.
  const OpcodeInfo* op = request_at(request[0]);
  if (b.protocol.last_request && std::ranges::equal(*b.protocol.last_request, request) &&
      !(op && op->op == Op::Alive)) {
    ++b.counters.duplicates;
    return b.protocol.last_reply;
  }
  auto reply = execute(b, request);
  if (!reply) {
    ++b.counters.unanswered;
    return std::nullopt;
  }
  b.protocol.last_request = Bytes(request.begin(), request.end());
  b.protocol.last_reply = *reply;
  return reply;
}

Bytes hear(Brick& b, std::span<const std::uint8_t> heard) {
  Bytes out;
  for (auto& event : feed(b.decoder, heard)) {
    if (auto* r = std::get_if<Rejected>(&event)) {
      ++b.counters.rejected;
      note(b, r->reason);
      continue;
    }
    const Bytes& request = std::get<Packet>(event).payload;
    if (b.trace) note(b, "request " + hex(request));
    if (auto reply = answer(b, request)) {
      if (b.trace) note(b, "reply   " + hex(*reply));
      ++b.counters.replies;
      Bytes framed = frame(*reply);
      out.insert(out.end(), framed.begin(), framed.end());
    }
  }
  return out;
}

Bytes broadcasts(Brick& b, std::size_t first) {
  Bytes out;
  const auto& events = b.vm.state().events;
  for (std::size_t i = first; i < events.size(); ++i) {
    if (events[i].kind != EventKind::MessageSent) continue;
    Bytes payload{info(Op::SetMessage).code, static_cast<std::uint8_t>(events[i].value)};
    if (b.trace) note(b, "send    " + hex(payload) + " (the program's Send message)");
    Bytes framed = frame(payload);
    out.insert(out.end(), framed.begin(), framed.end());
  }
  return out;
}

}  // namespace rcx
