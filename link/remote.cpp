#include "link/remote.h"

#include <fmt/format.h>

#include <charconv>
#include <ctime>
#include <algorithm>
#include <map>
#include <sstream>

#include "rcx/file_read.h"
#include "rcx/opcodes.h"

namespace rcx {
namespace {

using Words = std::vector<std::string>;
using Outcome = std::variant<std::string, RemoteError>;

constexpr int kKey[] = {1, 3, 5, 7, 11};
constexpr int kUnlockKey[] = {76, 69, 71, 79, 174};
constexpr int kDatalogChunk = 50;     // records per upload request
constexpr int kFirmwareBlock = 100;   // bytes per firmware block
constexpr int kFirmwareBlockChecksumError = 3;
// The ROM stores a firmware download from 0x8000 on (seed, Start firmware
// download), in the external RAM that ends at 0xffff.
constexpr std::uint32_t kFirmwareFirst = 0x8000, kFirmwareEnd = 0x10000;

RemoteError usage(std::string message) { return {RemoteFailure::Usage, std::move(message)}; }

std::optional<int> number(const std::string& text, int lo, int hi) {
  int v = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi) return std::nullopt;
  return v;
}

// A request by table row and field values; the reply or a link error.
std::variant<Bytes, RemoteError> call(Link& link, Op op, std::vector<int> values = {}) {
  auto r = transact(link, request_payload(info(op), values));
  if (auto* e = std::get_if<LinkError>(&r)) return RemoteError{RemoteFailure::Link, e->message};
  return std::get<Bytes>(r);
}

// Runs a list of requests whose replies carry nothing; `done` is printed.
Outcome calls(Link& link, std::initializer_list<std::pair<Op, std::vector<int>>> steps, std::string done) {
  for (const auto& [op, values] : steps) {
    auto r = call(link, op, values);
    if (auto* e = std::get_if<RemoteError>(&r)) return *e;
  }
  return done;
}

std::optional<int> parse_source(const std::string& name) {
  for (int s = 0; s < 16; ++s)
    if (source_name(s) == name) return s;
  if (name == "variable") return 0;
  return number(name, 0, 15);
}

std::string datalog_type(int type) {
  if (type == 0xff) return "size";
  if (type <= 0x1f) return fmt::format("var {}", type);
  if (type >= 0x20 && type <= 0x23) return fmt::format("timer {}", type - 0x20);
  if (type >= 0x40 && type <= 0x42) return fmt::format("sensor {}", type - 0x40 + 1);
  if (type == 0x80) return "clock";
  return fmt::format("type 0x{:02x}", type);
}

Outcome datalog(Link& link, const RemoteOptions& options) {
  auto first = call(link, Op::UploadDatalog, {0, 1});
  if (auto* e = std::get_if<RemoteError>(&first)) return *e;
  const Bytes& head = std::get<Bytes>(first);
  if (head.size() < 4) return RemoteError{RemoteFailure::Refused, "the RCX did not return its datalog size"};
  const int size = read_field(FieldType::Short, head.data() + 2);  // entry 0 counts itself
  std::string out = options.csv ? "index,type,value\n" : "";
  if (!options.csv) out += fmt::format("{} entr{}\n", size - 1, size - 1 == 1 ? "y" : "ies");
  for (int at = 1; at < size; at += kDatalogChunk) {
    int count = std::min(kDatalogChunk, size - at);
    auto r = call(link, Op::UploadDatalog, {at, count});
    if (auto* e = std::get_if<RemoteError>(&r)) return *e;
    const Bytes& reply = std::get<Bytes>(r);
    if (reply.size() != 1 + 3 * static_cast<std::size_t>(count))
      return RemoteError{RemoteFailure::Refused, fmt::format("the RCX could not upload entries {}..{}", at,
                                                             at + count - 1)};
    for (int i = 0; i < count; ++i) {
      const std::uint8_t* rec = reply.data() + 1 + 3 * i;
      int value = read_field(FieldType::Short, rec + 1);
      if (options.csv)
        out += fmt::format("{},{},{}\n", at + i, datalog_type(rec[0]), value);
      else
        out += fmt::format("{:4}  {:<10} {}\n", at + i, datalog_type(rec[0]), value);
    }
  }
  return out;
}

Outcome watch(Link& link, const std::string& when) {
  int h = 0, m = 0;
  if (when == "now") {
    std::time_t t = std::time(nullptr);
    std::tm local{};
    localtime_r(&t, &local);
    h = local.tm_hour;
    m = local.tm_min;
  } else {
    auto colon = when.find(':');
    auto hh = colon == std::string::npos ? std::nullopt : number(when.substr(0, colon), 0, 23);
    auto mm = colon == std::string::npos ? std::nullopt : number(when.substr(colon + 1), 0, 59);
    if (!hh || !mm) return usage(fmt::format("watch wants HH:MM or now, not '{}'", when));
    h = *hh;
    m = *mm;
  }
  return calls(link, {{Op::SetTime, {h, m}}}, fmt::format("watch set to {:02}:{:02}\n", h, m));
}

Outcome clear(Link& link) {
  for (int slot = 0; slot < 5; ++slot) {
    auto r = calls(link, {{Op::SetProgramNumber, {slot}}, {Op::DeleteAllTasks, {}}, {Op::DeleteAllSubroutines, {}}},
                   "");
    if (std::holds_alternative<RemoteError>(r)) return r;
  }
  return calls(link, {{Op::SetDatalogSize, {0}}, {Op::SetProgramNumber, {0}}}, "all programs and the datalog cleared\n");
}

// Why the firmware file was not read, with the reason: "cannot read x.srec"
// alone left a misspelt name and a missing permission looking alike.
std::string firmware_file_problem(const std::string& path, FileProblem problem) {
  switch (problem) {
    case FileProblem::Directory: return fmt::format("{}: is a directory, not a firmware file", path);
    case FileProblem::TooLarge: return too_large_message(path, kFirmwareFile);
    case FileProblem::CannotOpen: return fmt::format("cannot read {}: {}", path, cannot_open_reason(path));
    default: return fmt::format("cannot read {}", path);
  }
}

Outcome firmware(Link& link, const std::string& path, const RemoteOptions& options) {
  auto file = read_file(path, kFirmwareFile);
  if (const auto* problem = std::get_if<FileProblem>(&file))
    return RemoteError{RemoteFailure::Input, firmware_file_problem(path, *problem)};
  auto parsed = parse_srec(std::get<std::string>(file));
  if (auto* e = std::get_if<std::string>(&parsed)) return RemoteError{RemoteFailure::Input, path + ": " + *e};
  return download_firmware(link, std::get<Firmware>(parsed), options);
}

}  // namespace

std::variant<std::string, RemoteError> download_firmware(Link& link, const Firmware& fw, const RemoteOptions& options) {
  unsigned sum = 0;
  for (auto b : fw.bytes) sum += b;
  std::vector<int> key(std::begin(kKey), std::end(kKey));
  if (auto r = call(link, Op::DeleteFirmware, key); std::holds_alternative<RemoteError>(r))
    return std::get<RemoteError>(r);
  auto start = call(link, Op::StartFirmwareDownload, {fw.entry, static_cast<int>(sum & 0xffff), 0});
  if (auto* e = std::get_if<RemoteError>(&start)) return *e;
  if (reply_field(info(Op::StartFirmwareDownload), std::get<Bytes>(start), "errorcode") != 0)
    return RemoteError{RemoteFailure::Refused, "the RCX refused to start the firmware download"};
  int sequence = 1;
  int checksum_errors = 0;  // in a row, for the block being sent
  for (std::size_t at = 0; at < fw.bytes.size();) {
    std::size_t n = std::min<std::size_t>(kFirmwareBlock, fw.bytes.size() - at);
    bool last = at + n == fw.bytes.size();
    auto r = transact(link, transfer_payload(last ? 0 : sequence, std::span(fw.bytes).subspan(at, n)));
    if (auto* e = std::get_if<LinkError>(&r)) return RemoteError{RemoteFailure::Link, e->message};
    int code = reply_field(info(Op::TransferData), std::get<Bytes>(r), "errorcode");
    ++sequence;  // also after a block checksum error: the ROM counts it (seed)
    if (code == kFirmwareBlockChecksumError && !last) {
      // A brick that reports every block as garbled would keep us here.
      if (++checksum_errors > link.options.retries)
        return RemoteError{RemoteFailure::Refused,
                           fmt::format("the RCX reported a checksum error for the firmware block at 0x{:04x} {} times "
                                       "in a row; giving up",
                                       kFirmwareFirst + at, checksum_errors)};
      continue;
    }
    checksum_errors = 0;
    if (code != 0)
      return RemoteError{RemoteFailure::Refused, fmt::format("the RCX rejected the firmware (error {})", code)};
    at += n;
    if (options.progress) options.progress(at, fw.bytes.size());
  }
  std::vector<int> unlock(std::begin(kUnlockKey), std::end(kUnlockKey));
  auto r = call(link, Op::UnlockFirmware, unlock);
  if (auto* e = std::get_if<RemoteError>(&r)) return *e;
  const Bytes& reply = std::get<Bytes>(r);
  return fmt::format("firmware downloaded ({} bytes); the RCX says \"{}\"\n", fw.bytes.size(),
                     std::string(reply.begin() + 1, reply.end()));
}

namespace {

Outcome raw(Link& link, const Words& words) {
  std::string joined;
  for (std::size_t i = 1; i < words.size(); ++i) joined += words[i] + " ";
  std::string error;
  auto bytes = parse_hex(joined, error);
  if (!bytes) return usage("raw: " + error);
  auto size = request_size(*bytes);
  if (auto* e = std::get_if<SizeError>(&size)) return usage("raw: " + e->reason);
  if (std::get<int>(size) != static_cast<int>(bytes->size()))
    return usage(fmt::format("raw: {} (0x{:02x}) is {} byte{} long, not {}", request_at((*bytes)[0])->name, (*bytes)[0],
                             std::get<int>(size), std::get<int>(size) == 1 ? "" : "s", bytes->size()));
  if (!request_at((*bytes)[0])->replies) {
    auto r = send_only(link, *bytes);
    if (auto* e = std::get_if<LinkError>(&r)) return RemoteError{RemoteFailure::Link, e->message};
    return std::string("sent (this request has no reply)\n");
  }
  auto r = transact(link, *bytes);
  if (auto* e = std::get_if<LinkError>(&r)) return RemoteError{RemoteFailure::Link, e->message};
  return hex(std::get<Bytes>(r)) + "\n";
}

Outcome get_value(Link& link, const Words& w) {
  if (w.size() != 3) return usage("get wants SOURCE ARG, e.g. get var 3");
  auto source = parse_source(w[1]);
  auto arg = number(w[2], -128, 255);
  if (!source) return usage(fmt::format("'{}' is not a source (var, timer, sensor, clock, message, ... or 0..15)", w[1]));
  if (!allows(info(Op::GetValue).operands[0].allowed, *source))
    return usage(fmt::format("source {} cannot be read with Get value", source_name(*source)));
  // The source's own range for any bad argument: `get var 99999999999999999999`
  // said "0..255" where `get var 40` says 0..31.
  auto range = source_argument_range(*source);
  if (range && (!arg || *arg < range->lo || *arg > range->hi))
    return usage(fmt::format("{} {}: the argument of {} is {}..{}", w[1], w[2], source_name(*source), range->lo, range->hi));
  if (!arg) return usage(fmt::format("'{}' is not an argument -128..255", w[2]));
  auto r = call(link, Op::GetValue, {*source, *arg});
  if (auto* e = std::get_if<RemoteError>(&r)) return *e;
  return fmt::format("{}\n", reply_field(info(Op::GetValue), std::get<Bytes>(r), "value"));
}

Outcome versions(Link& link) {
  auto r = call(link, Op::GetVersions, std::vector<int>(std::begin(kKey), std::end(kKey)));
  if (auto* e = std::get_if<RemoteError>(&r)) return *e;
  const auto& op = info(Op::GetVersions);
  const Bytes& reply = std::get<Bytes>(r);
  int fw_major = reply_field(op, reply, "firmware", 0), fw_minor = reply_field(op, reply, "firmware", 1);
  return fmt::format("ROM {}.{}, firmware {}\n", reply_field(op, reply, "rom", 0), reply_field(op, reply, "rom", 1),
                     fw_major == 0 && fw_minor == 0 ? std::string("none") : fmt::format("{}.{}", fw_major, fw_minor));
}

// Actions that take one number in a range and send one request.
Outcome one_number(Link& link, const Words& w, Op op, int lo, int hi, int offset, const char* done) {
  if (w.size() != 2) return usage(fmt::format("{} wants one number {}..{}", w[0], lo, hi));
  auto n = number(w[1], lo, hi);
  if (!n) return usage(fmt::format("{}: '{}' is not a number {}..{}", w[0], w[1], lo, hi));
  return calls(link, {{op, {*n - offset}}}, fmt::format(fmt::runtime(done), *n));
}

}  // namespace

const std::vector<RemoteAction>& remote_actions() {
  static const std::vector<RemoteAction> actions = {
      {"alive", "", "check that the RCX answers"},
      {"versions", "", "ROM and firmware versions"},
      {"battery", "", "battery voltage"},
      {"run", " [N]", "start program N (1..5; default: the current one)"},
      {"stop", "", "stop all tasks"},
      {"program", " N", "select program N (1..5)"},
      {"message", " N", "send IR message N (0..255)"},
      {"get", " SOURCE ARG", "read a value, e.g. get var 3, get sensor 0, get timer 1"},
      {"datalog", " [--csv]", "upload and print the datalog"},
      {"watch", " HH:MM|now", "set the RCX clock"},
      {"sleep", " MIN", "set the power-down delay (0 = never)"},
      {"clear", "", "delete every program and the datalog"},
      {"firmware", " FILE.srec", "download and unlock firmware"},
      {"raw", " HEX...", "send one request and print the reply"},
  };
  return actions;
}

std::string remote_actions_help() {
  std::string text = "actions:\n";
  for (const RemoteAction& a : remote_actions())
    text += fmt::format("  {:<22}{}\n", std::string(a.name) + std::string(a.arguments), a.summary);
  return text;
}

std::variant<std::string, RemoteError> run_remote(Link& link, const Words& w, const RemoteOptions& options) {
  if (w.empty()) return usage("an action is required");
  const std::string& a = w[0];
  auto arity = [&](std::size_t n) { return w.size() == n; };
  if (a == "alive" && arity(1)) return calls(link, {{Op::Alive, {}}}, "the RCX is alive\n");
  if (a == "versions" && arity(1)) return versions(link);
  if (a == "battery" && arity(1)) {
    auto r = call(link, Op::GetBatteryPower);
    if (auto* e = std::get_if<RemoteError>(&r)) return *e;
    int mv = reply_field(info(Op::GetBatteryPower), std::get<Bytes>(r), "millivolts");
    return fmt::format("{} mV\n", mv);
  }
  if (a == "run" && arity(1)) return calls(link, {{Op::StartTask, {0}}}, "program started\n");
  if (a == "run" && arity(2)) {
    auto n = number(w[1], 1, 5);
    if (!n) return usage(fmt::format("run: '{}' is not a program number 1..5", w[1]));
    return calls(link, {{Op::SetProgramNumber, {*n - 1}}, {Op::StartTask, {0}}},
                 fmt::format("program {} started\n", *n));
  }
  if (a == "stop" && arity(1)) return calls(link, {{Op::StopAllTasks, {}}}, "all tasks stopped\n");
  if (a == "program") return one_number(link, w, Op::SetProgramNumber, 1, 5, 1, "program {} selected\n");
  if (a == "sleep") return one_number(link, w, Op::SetPowerDownDelay, 0, 255, 0, "power-down delay set to {} min\n");
  if (a == "message") {
    if (w.size() != 2 || !number(w[1], 0, 255)) return usage("message wants one number 0..255");
    std::vector<int> v{*number(w[1], 0, 255)};
    auto r = send_only(link, request_payload(info(Op::SetMessage), v));
    if (auto* e = std::get_if<LinkError>(&r)) return RemoteError{RemoteFailure::Link, e->message};
    return fmt::format("message {} sent\n", v[0]);
  }
  if (a == "get") return get_value(link, w);
  if (a == "datalog" && arity(1)) return datalog(link, options);
  if (a == "watch" && arity(2)) return watch(link, w[1]);
  if (a == "clear" && arity(1)) return clear(link);
  if (a == "firmware" && arity(2)) return firmware(link, w[1], options);
  if (a == "raw" && w.size() >= 2) return raw(link, w);
  for (const RemoteAction& known : remote_actions())
    if (known.name == a) return usage(fmt::format("usage: {}{}", a, known.arguments));
  return usage(fmt::format("unknown action '{}'\n{}", a, remote_actions_help()));
}

namespace {

// A port that refuses everything: running an action over it gets as far as
// the first request, which is past every check of the words.
class NoPort : public Transport {
 public:
  std::optional<TransportError> write(std::span<const std::uint8_t>) override { return TransportError{"no port"}; }
  std::variant<std::vector<std::uint8_t>, TransportError> read(Millis) override { return TransportError{"no port"}; }
  bool echoes() const override { return false; }
  void pause(Millis) override {}
  std::string describe() const override { return "no port"; }
};

}  // namespace

std::optional<RemoteError> check_remote(const std::vector<std::string>& words) {
  NoPort port;
  LinkOptions options;
  options.retries = 0;
  Link link = make_link(port, options);
  auto result = run_remote(link, words);
  if (auto* e = std::get_if<RemoteError>(&result); e && e->kind != RemoteFailure::Link) return *e;
  return std::nullopt;
}

std::variant<Firmware, std::string> parse_srec(const std::string& text) {
  // Every address is checked against the RAM the ROM loads firmware into
  // before anything is stored, in 64-bit arithmetic: an S3 record carries a
  // 32-bit address, and a file may put its bytes anywhere.
  std::vector<std::uint8_t> image(kFirmwareEnd - kFirmwareFirst, 0);
  std::uint32_t end = 0;  // one past the highest byte stored, from kFirmwareFirst; 0 = none
  std::optional<std::uint32_t> entry;
  std::istringstream lines(text);
  std::string line;
  int line_no = 0;
  while (std::getline(lines, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line.size() < 4 || line[0] != 'S') return fmt::format("line {}: not an S-record", line_no);
    std::string error;
    auto rec = parse_hex(std::string_view(line).substr(2), error);
    if (!rec || rec->size() < 3) return fmt::format("line {}: {}", line_no, rec ? "too short" : error);
    const Bytes& r = *rec;
    if (r[0] + 1u != r.size()) return fmt::format("line {}: the count does not match the record length", line_no);
    unsigned sum = 0;
    for (std::size_t i = 0; i + 1 < r.size(); ++i) sum += r[i];
    if (static_cast<std::uint8_t>(~sum) != r.back()) return fmt::format("line {}: bad record checksum", line_no);
    char type = line[1];
    if (type == '0' || type == '5' || type == '6') continue;
    std::size_t addr_len = (type == '1' || type == '9') ? 2 : (type == '2' || type == '8') ? 3 : (type == '3' || type == '7') ? 4 : 0;
    if (addr_len == 0) return fmt::format("line {}: unknown record type S{}", line_no, type);
    if (r.size() < addr_len + 2) return fmt::format("line {}: too short for its address", line_no);
    std::uint64_t addr = 0;
    for (std::size_t i = 0; i < addr_len; ++i) addr = (addr << 8) | r[1 + i];
    if (type >= '7') {
      if (addr < kFirmwareFirst || addr >= kFirmwareEnd)
        return fmt::format("line {}: entry address 0x{:x} is outside the firmware's RAM 0x{:x}..0x{:x}", line_no, addr,
                           kFirmwareFirst, kFirmwareEnd - 1);
      entry = static_cast<std::uint32_t>(addr);
      continue;
    }
    const std::size_t n = r.size() - addr_len - 2;
    if (n == 0) continue;
    if (addr < kFirmwareFirst || addr + n > kFirmwareEnd)
      return fmt::format("line {}: data at 0x{:x}..0x{:x} is outside the firmware's RAM 0x{:x}..0x{:x}", line_no, addr,
                         addr + n - 1, kFirmwareFirst, kFirmwareEnd - 1);
    std::copy_n(r.begin() + static_cast<std::ptrdiff_t>(1 + addr_len), n,
                image.begin() + static_cast<std::ptrdiff_t>(addr - kFirmwareFirst));
    end = std::max(end, static_cast<std::uint32_t>(addr + n - kFirmwareFirst));
  }
  if (end == 0) return std::string("no data records");
  image.resize(end);
  Firmware fw;
  fw.start = kFirmwareFirst;
  fw.entry = static_cast<int>(entry.value_or(kFirmwareFirst));
  fw.bytes = std::move(image);
  return fw;
}

}  // namespace rcx
