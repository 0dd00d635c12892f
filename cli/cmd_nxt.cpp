// `rcxc nxt [--port P] ACTION`: one-shot actions on a LEGO NXT over USB or
// Bluetooth, and `rcxc nxt brick --pty`, the virtual NXT. Values are checked
// here, before the port is opened: the brick itself does not range-check
// PlayTone or SetOutputState, and a refused value must leave nothing half-done.
#include <unistd.h>

#include <algorithm>
#include <functional>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/nxt_tether.h"
#include "cli/program_loader.h"
#include "savefile/savefile.h"
#include "nxt/client.h"
#include "nxt/commands.h"
#include "nxt/scenario.h"
#include "nxt/telegram.h"
#include "nxt/transport.h"
#include "nxt/virtual_nxt.h"
#include "rcx/file_read.h"
#include "verify/testspec.h"

namespace rcxc::cli {
namespace {

using nlohmann::json;
using nxt::CallError;
using nxt::Client;
using nxt::Value;

constexpr int kExitInterrupted = 130;  // 128 + SIGINT, as shells report it

struct NxtArgs {
  std::optional<std::string> port;
  bool json = false;
  bool verbose = false;
  int timeout_ms = 1000;
};

// What an action prints: text for people, JSON for scripts.
struct Output {
  std::string text;
  json data = json::object();
};

struct Failure {
  int exit_code;
  std::string message;
};

using Action = std::function<std::variant<Output, Failure>(Client&)>;

// What an action's checks make of its values: the action, a usage message
// (exit 2), or another failure found before the port is opened (a local
// file that cannot be read).
using Made = std::variant<Action, std::string, Failure>;

int exit_code_for(CallError::Kind kind) {
  switch (kind) {
    case CallError::Kind::Input: return kExitUsage;
    case CallError::Kind::Refused: return kExitFailure;
    case CallError::Kind::Interrupted: return kExitInterrupted;
    case CallError::Kind::NoReply:
    case CallError::Kind::BadReply:
    case CallError::Kind::Lost: return kExitNoReply;
  }
  return kExitFailure;
}

Failure failure(const CallError& e) { return {exit_code_for(e.kind), e.message}; }

// Ctrl-C: a signalfd every wait polls (cli/nxt_tether.h).
int stop_descriptor() { return stop_signal_descriptor(); }

int report(const NxtArgs& a, const std::string& action, std::variant<Output, Failure> result) {
  if (auto* f = std::get_if<Failure>(&result)) {
    if (a.json) std::cout << json{{"ok", false}, {"action", action}, {"error", f->message}}.dump() << "\n";
    std::cerr << "rcxc nxt " << action << ": " << f->message << "\n";
    return f->exit_code;
  }
  auto& out = std::get<Output>(result);
  if (a.json) {
    out.data["ok"] = true;
    out.data["action"] = action;
    std::cout << out.data.dump() << "\n";
  } else {
    std::cout << out.text;
  }
  return kExitOk;
}

// Opens the port (--port, else NXT_PORT, else usb) and runs the action.
int with_brick(const NxtArgs& a, const std::string& action, const Action& act) {
  const char* env = std::getenv("NXT_PORT");
  std::optional<std::string> environment;
  if (env && *env) environment = env;
  auto spec = nxt::parse_port(a.port, environment);
  if (auto* e = std::get_if<nxt::LinkError>(&spec)) return report(a, action, Failure{kExitUsage, e->message});
  int stop = stop_descriptor();
  auto opened = nxt::open_port(std::get<nxt::PortSpec>(spec), stop);
  if (auto* e = std::get_if<nxt::LinkError>(&opened)) {
    if (stop >= 0) ::close(stop);
    return report(a, action,
                  Failure{e->kind == nxt::LinkError::Kind::Interrupted ? kExitInterrupted : kExitNoPort, e->message});
  }
  auto transport = std::move(std::get<std::unique_ptr<nxt::Transport>>(opened));
  Client client{*transport};
  client.timeout = std::chrono::milliseconds(a.timeout_ms);
  if (a.verbose) client.on_log = [](const std::string& line) { std::cerr << "nxt: " << line << "\n"; };
  int code = report(a, action, act(client));
  transport.reset();
  if (stop >= 0) ::close(stop);
  return code;
}

// Motor ports are letters (A, B, C, or all); sensor ports numbers 1-4, as
// printed on the brick.
std::optional<int> output_port(const std::string& s) {
  std::string u = s;
  std::transform(u.begin(), u.end(), u.begin(), [](unsigned char c) { return std::toupper(c); });
  if (u == "A" || u == "B" || u == "C") return u[0] - 'A';
  if (u == "ALL") return 0xFF;
  return std::nullopt;
}

std::optional<int> input_port(const std::string& s) {
  if (s.size() == 1 && s[0] >= '1' && s[0] <= '4') return s[0] - '1';
  return std::nullopt;
}

std::string bad_output_port(const std::string& s) {
  return fmt::format("\"{}\" is not a motor port (A, B, C or all)", s);
}
std::string bad_input_port(const std::string& s) { return fmt::format("\"{}\" is not a sensor port (1-4)", s); }

std::vector<Value> values(std::initializer_list<Value> v) { return v; }

std::variant<Output, Failure> simple(Client& c, std::string_view command, std::vector<Value> v, std::string text) {
  auto r = nxt::call_ok(c, command, v);
  if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
  return Output{std::move(text), json::object()};
}

std::string names_of(std::span<const nxt::EnumName> names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + std::string(n.name);
  return s;
}

std::string bt_address(const nxt::Bytes& b) {
  std::string s;
  for (std::size_t i = 0; i < 6 && i < b.size(); ++i) s += fmt::format("{}{:02X}", i ? ":" : "", b[i]);
  return s;
}

std::variant<Output, Failure> info(Client& c) {
  auto fw = nxt::call_ok(c, "GetFirmwareVersion", {});
  if (auto* e = std::get_if<CallError>(&fw)) return failure(*e);
  auto dev = nxt::call_ok(c, "GetDeviceInfo", {});
  if (auto* e = std::get_if<CallError>(&dev)) return failure(*e);
  auto bat = nxt::call_ok(c, "GetBatteryLevel", {});
  if (auto* e = std::get_if<CallError>(&bat)) return failure(*e);
  const auto& f = std::get<nxt::Decoded>(fw);
  const auto& d = std::get<nxt::Decoded>(dev);
  Output o;
  std::string firmware = fmt::format("{}.{:02}", *f.number("firmware_major"), *f.number("firmware_minor"));
  std::string protocol = fmt::format("{}.{}", *f.number("protocol_major"), *f.number("protocol_minor"));
  std::string address = bt_address(*d.bytes("bt_address"));
  auto millivolts = *std::get<nxt::Decoded>(bat).number("millivolts");
  o.data = {{"name", *d.text("name")},      {"bluetooth_address", address},
            {"firmware", firmware},         {"protocol", protocol},
            {"free_flash", *d.number("free_flash")}, {"battery_mv", millivolts}};
  o.text = fmt::format("name       {}\nbluetooth  {}\nfirmware   {} (protocol {})\nfree flash {} bytes\nbattery    {} mV\n",
                       *d.text("name"), address, firmware, protocol, *d.number("free_flash"), millivolts);
  return o;
}

// No file larger than the NXT's whole flash (256 KB) can go onto it; the
// cap also ends /dev/zero or an endless pipe with a message.
constexpr rcx::FileKind kNxtUpload{"file for the NXT", std::size_t{256} << 10};

std::string read_file_bytes(const std::string& path, nxt::Bytes& out) {
  // /dev/null would go up as an empty file named "null", a pipe be read
  // once (or wait for a writer for ever), as other commands refuse them.
  if (auto problem = special_file_problem(path, Takes::Files, "rcxc nxt upload copies a file to the brick, or the standard input with - NAME"))
    return *problem;
  auto read = rcx::read_file(path, kNxtUpload);
  if (auto* problem = std::get_if<rcx::FileProblem>(&read)) {
    switch (*problem) {
      case rcx::FileProblem::Directory: return fmt::format("{}: is a directory, not a file to upload", path);
      case rcx::FileProblem::TooLarge: return rcx::too_large_message(path, kNxtUpload);
      case rcx::FileProblem::CannotOpen: return fmt::format("cannot read {}: {}", path, rcx::cannot_open_reason(path));
      default: return fmt::format("cannot read {}", path);
    }
  }
  const std::string& bytes = std::get<std::string>(read);
  out.assign(bytes.begin(), bytes.end());
  return {};
}

std::string read_stdin_bytes(nxt::Bytes& out) {
  auto read = rcx::read_stream(std::cin, kNxtUpload);
  if (auto* problem = std::get_if<rcx::FileProblem>(&read))
    return *problem == rcx::FileProblem::TooLarge ? rcx::too_large_message("the standard input", kNxtUpload)
                                                  : "cannot read the standard input";
  const std::string& bytes = std::get<std::string>(read);
  out.assign(bytes.begin(), bytes.end());
  return {};
}

nxt::Progress progress_bar(const std::string& what) {
  if (!::isatty(STDERR_FILENO)) return {};
  return [what](std::size_t done, std::size_t total) {
    int width = 30;
    int filled = total ? static_cast<int>(done * static_cast<std::size_t>(width) / total) : width;
    std::cerr << fmt::format("\r{} [{}{}] {}/{} bytes", what, std::string(static_cast<std::size_t>(filled), '#'),
                             std::string(static_cast<std::size_t>(width - filled), ' '), done, total)
              << (done == total ? "\n" : "") << std::flush;
  };
}

// The sleep limit as `keepalive` and `sleep` print it. LEGO's firmware
// keeps whole minutes; a limit that is not one (other firmwares) printed as
// "sleeps after 0 min" for 30 s.
std::string sleep_text(std::uint64_t ms) {
  if (ms == 0) return "never sleeps\n";
  std::string after = ms % 60000 == 0 ? fmt::format("{} min", ms / 60000)
                      : ms % 1000 == 0 ? fmt::format("{} s", ms / 1000)
                                       : fmt::format("{} ms", ms);
  return "sleeps after " + after + "\n";
}

// Words of two-digit hex pairs (0x allowed: `00 0b`, `000b`, `0x0b`) as
// bytes; nullopt with `error` naming the first word that is not.
std::optional<nxt::Bytes> hex_bytes(const std::vector<std::string>& words, std::string_view example,
                                    std::string& error) {
  nxt::Bytes out;
  for (const auto& w : words) {
    std::string s = w.rfind("0x", 0) == 0 || w.rfind("0X", 0) == 0 ? w.substr(2) : w;
    if (s.empty() || s.size() % 2 != 0 || !std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isxdigit(c); })) {
      error = fmt::format("\"{}\" is not hex bytes ({})", w, example);
      return std::nullopt;
    }
    for (std::size_t i = 0; i < s.size(); i += 2)
      out.push_back(static_cast<std::uint8_t>(std::stoi(s.substr(i, 2), nullptr, 16)));
  }
  return out;
}

std::optional<nxt::Bytes> parse_hex_words(const std::vector<std::string>& words, std::string& error) {
  auto parsed = hex_bytes(words, "e.g. 00 0b, or 000b", error);
  if (!parsed) return std::nullopt;
  const nxt::Bytes& out = *parsed;
  if (out.empty()) error = "raw needs the telegram's bytes";
  else if (out.size() < 2) error = "a telegram needs at least its type byte and an opcode (00 0b: GetBatteryLevel)";
  if (out.size() > 256) error = "a telegram this long cannot be framed for the brick";
  // The seed's Maximum Command Length: a direct command is at most 64 bytes
  // with its type byte (the brick's buffer); more would reach it cut.
  else if (!out.empty() && (out[0] & ~nxt::kNoReplyBit) == nxt::kDirectWithReply && out.size() > nxt::kMaxTelegram)
    error = fmt::format("a direct command is at most {} bytes with its type byte; this one is {}", nxt::kMaxTelegram,
                        out.size());
  return error.empty() ? parsed : std::nullopt;
}

// Hex bytes for WriteIOMap.
std::optional<nxt::Bytes> parse_hex_data(const std::vector<std::string>& words, std::string& error) {
  auto parsed = hex_bytes(words, "two digits a byte: 0a 1b, or 0a1b", error);
  if (parsed && parsed->empty()) error = "no bytes to write";
  return error.empty() ? parsed : std::nullopt;
}

// A number as typed: decimal, or hex with 0x. nullopt if it is neither or past `max`.
std::optional<std::uint64_t> parse_number(const std::string& text, std::uint64_t max) {
  bool hex_form = text.rfind("0x", 0) == 0 || text.rfind("0X", 0) == 0;
  std::string digits = hex_form ? text.substr(2) : text;
  if (digits.empty() || digits.size() > 10) return std::nullopt;
  if (!std::all_of(digits.begin(), digits.end(),
                   [&](unsigned char c) { return hex_form ? std::isxdigit(c) != 0 : std::isdigit(c) != 0; }))
    return std::nullopt;
  std::uint64_t v = std::stoull(digits, nullptr, hex_form ? 16 : 10);
  if (v > max) return std::nullopt;
  return v;
}

// MODULE as typed: an ID (0x000C0001 or decimal) or a name (Ui.mod, or Ui).
struct ModuleSpec {
  std::optional<std::uint32_t> id;
  std::string name;
};

std::variant<ModuleSpec, std::string> parse_module(const std::string& text) {
  if (!text.empty() && std::isdigit(static_cast<unsigned char>(text[0]))) {
    auto id = parse_number(text, 0xFFFFFFFFu);
    if (!id) return fmt::format("\"{}\" is not a module: a name (Ui.mod) or an ID (0x000C0001)", text);
    return ModuleSpec{static_cast<std::uint32_t>(*id), ""};
  }
  std::string name = text.find('.') == std::string::npos ? text + ".mod" : text;
  if (nxt::check_file_name(name) || name.find('*') != std::string::npos)
    return fmt::format("\"{}\" is not a module: a name (Ui.mod) or an ID (0x000C0001)", text);
  return ModuleSpec{std::nullopt, name};
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// The module MODULE names, from the brick's own list: an unknown one is a
// bad value (exit 2) that lists what there is.
std::variant<nxt::ModuleEntry, Failure> find_module(Client& c, const ModuleSpec& spec, const std::string& typed) {
  auto r = nxt::list_modules(c, "*.*");
  if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
  const auto& all = std::get<std::vector<nxt::ModuleEntry>>(r);
  std::string names;
  for (const auto& m : all) {
    if (spec.id ? m.id == *spec.id : lower(m.name) == lower(spec.name)) return m;
    names += (names.empty() ? "" : ", ") + m.name;
  }
  return Failure{kExitUsage, fmt::format("no module \"{}\" on the brick (it has {})", typed, names.empty() ? "none" : names)};
}

// "0000  00 0b ...  |..|", 16 bytes a line, offsets as in the IO map.
std::string hex_dump(std::size_t offset, const nxt::Bytes& data) {
  std::string out;
  for (std::size_t at = 0; at < data.size(); at += 16) {
    std::string hexes, chars;
    for (std::size_t i = at; i < at + 16; ++i) {
      if (i < data.size()) {
        hexes += fmt::format("{:02x} ", data[i]);
        chars += data[i] >= 0x20 && data[i] < 0x7F ? static_cast<char>(data[i]) : '.';
      } else {
        hexes += "   ";
      }
    }
    out += fmt::format("{:04x}  {} |{}|\n", offset + at, hexes, chars);
  }
  return out;
}

// The firmware's own commands past the seed, and its IO maps: what they
// mean is LEGO's firmware's (leJOS gives 0x20 and 0x21 other meanings), so
// each action asks GetFirmwareVersion first and sends nothing else to a
// firmware that is not LEGO's (nxt/client.h, require_lego_firmware).
std::optional<Failure> lego_first(Client& c, std::string_view what) {
  if (auto e = nxt::require_lego_firmware(c, what)) return failure(*e);
  return std::nullopt;
}

// volume, sleep and bluetooth: SetProperty when `set` holds a value, then
// GetProperty to show what the brick keeps (LEGO's firmware only, above).
// `read_back` false: the set's answer is the result (Bluetooth switched off
// over Bluetooth leaves no one to ask).
std::variant<Output, Failure> property(Client& c, nxt::Property p, std::optional<std::uint32_t> set,
                                       const std::function<Output(std::uint32_t)>& show, bool read_back = true) {
  if (auto f = lego_first(c, set ? "SetProperty (0x1F)" : "GetProperty (0x20)")) return *f;
  if (set) {
    if (auto e = nxt::set_property(c, p, *set)) return failure(*e);
    if (!read_back) return show(*set);
  }
  auto r = nxt::get_property(c, p);
  if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
  return show(std::get<std::uint32_t>(r));
}

// The table as `rcxc nxt --help` shows it.
std::string table_help() {
  std::string s = "NXT commands (the table behind every action; `raw` sends any of them):\n";
  for (const auto& c : nxt::commands())
    s += fmt::format("  {} 0x{:02X} {:<22} {}\n", c.group == nxt::Group::Direct ? "direct" : "system", c.opcode,
                     c.name, c.summary);
  return s;
}

// The virtual NXT's inputs from an NQC program's own test directives
// (`// @input`, docs/testing.md): what `rcxc run` feeds the emulator, as the
// NXT's inputs 1-3, mailbox 1 and battery see it.
std::variant<std::vector<nxt::ScenarioInput>, std::string> scenario_from_directives(const std::string& path) {
  auto parsed = rcx::semtest::parse_spec_file(path);
  if (auto* errors = std::get_if<std::vector<rcx::semtest::SpecError>>(&parsed)) {
    // Line 0: about the whole file (a folder, a file that cannot be read).
    const auto& first = errors->front();
    return first.line > 0 ? fmt::format("{}:{}: {}", path, first.line, first.message)
                          : fmt::format("{}: {}", path, first.message);
  }
  auto gathered = rcx::semtest::all_inputs(std::get<rcx::semtest::Spec>(parsed), path);
  if (auto* e = std::get_if<std::string>(&gathered)) return *e;
  std::vector<nxt::ScenarioInput> out;
  for (const auto& in : std::get<std::vector<rcx::TimedInput>>(gathered)) {
    nxt::ScenarioInput s;
    s.at_ms = in.at_us / rcx::kMicrosPerMs;
    if (auto* raw = std::get_if<rcx::SensorRawInput>(&in.input)) s.port = raw->sensor, s.raw = raw->raw;
    else if (auto* r = std::get_if<rcx::RotationInput>(&in.input)) s.port = r->sensor, s.rotation = r->position;
    else if (auto* m = std::get_if<rcx::MessageInput>(&in.input)) s.message = m->value, s.queue = kTetherInbox;
    else if (auto* b = std::get_if<rcx::BatteryInput>(&in.input)) s.battery_mv = b->millivolts;
    out.push_back(s);
  }
  return out;
}

// A scenario file: NQC source (named .nqc) for its // @input lines, else TOML.
std::variant<std::vector<nxt::ScenarioInput>, std::string> read_brick_scenario(const std::string& path) {
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower.ends_with(".nqc")) {
    // As `rcxc test` says of it: binary data has no directives to read.
    if (is_nqc_source(path) == false)
      return fmt::format("{}: {}, not an NQC program whose // @input lines to replay", path, non_source_kind(path));
    auto inputs = scenario_from_directives(path);
    if (auto* list = std::get_if<std::vector<nxt::ScenarioInput>>(&inputs); list && list->empty())
      std::cerr << "rcxc nxt brick: " << path << " has no // @input lines: the inputs stay as they are\n";
    return inputs;
  }
  auto parsed = nxt::read_scenario_file(path);
  if (auto* e = std::get_if<nxt::ScenarioError>(&parsed)) return e->message;
  if (std::get<std::vector<nxt::ScenarioInput>>(parsed).empty())
    std::cerr << "rcxc nxt brick: " << path << " holds no [[input]] tables: the inputs stay as they are\n";
  return std::get<std::vector<nxt::ScenarioInput>>(std::move(parsed));
}

int serve_brick(bool on_pty, const std::string& scenario_path, const std::string& program, bool verbose) {
  if (!on_pty) {
    std::cerr << "rcxc nxt brick: only --pty is supported (the virtual NXT serves on a pseudo-terminal)\n";
    return kExitUsage;
  }
  std::vector<nxt::ScenarioInput> scenario;
  if (!scenario_path.empty()) {
    auto read = read_brick_scenario(scenario_path);
    if (auto* e = std::get_if<std::string>(&read)) {
      std::cerr << "rcxc nxt brick: " << *e << "\n";
      return kExitFailure;
    }
    scenario = std::get<std::vector<nxt::ScenarioInput>>(std::move(read));
  }
  nxt::VirtualNxt brick = nxt::make_virtual_nxt(std::move(scenario));
  if (!program.empty()) {
    if (auto bad = nxt::start_program(brick, program)) {
      std::cerr << "rcxc nxt brick: --program: " << *bad << "\n";
      return kExitUsage;
    }
  }
  auto opened = nxt::open_pty_pair();
  if (auto* e = std::get_if<nxt::LinkError>(&opened)) {
    std::cerr << "rcxc nxt brick: " << e->message << "\n";
    return kExitFailure;
  }
  auto& pty = std::get<nxt::PtyPair>(opened);
  int stop = stop_descriptor();
  if (stop < 0) {
    std::cerr << "rcxc nxt brick: cannot watch for signals\n";
    nxt::close_pty_pair(pty);
    return kExitFailure;
  }
  std::cout << pty.slave_path << std::endl;
  std::cerr << "rcxc nxt brick: a virtual NXT on " << pty.slave_path << " (Bluetooth framing); Ctrl-C stops\n";
  nxt::ServeOptions options;
  options.stop_fd = stop;
  if (verbose) options.on_log = [](const std::string& line) { std::cerr << "nxt: " << line << "\n"; };
  auto err = nxt::serve(brick, pty.master_fd, options);
  ::close(stop);
  nxt::close_pty_pair(pty);
  std::cerr << "rcxc nxt brick: " << brick.counters.requests << " telegrams, " << brick.counters.replies
            << " replies\n";
  if (err) {
    std::cerr << "rcxc nxt brick: " << err->message << "\n";
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

void print_nxt_usage_error_json(const CLI::App& app, const std::vector<std::string>& words, const std::string& error) {
  if (words.empty() || words[0] != "nxt") return;
  // The flag as typed, read from the words: the parse stopped at the
  // error, so --json after it was never parsed. Words after `--` are values.
  auto end = std::find(words.begin(), words.end(), "--");
  if (std::find(words.begin() + 1, end, "--json") == end) return;
  // The action as report() names it ("tone", "mailbox write"), as far as
  // the parser got; "" when it got to none.
  std::string action;
  const CLI::App* at = nullptr;
  for (const CLI::App* sub : app.get_subcommands())
    if (sub->get_name() == "nxt") at = sub;
  while (at) {
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : at->get_subcommands()) next = sub;
    if (next) action += (action.empty() ? "" : " ") + next->get_name();
    at = next;
  }
  std::cout << json{{"ok", false}, {"action", action}, {"error", error}}.dump() << "\n";
}

void register_nxt(CLI::App& app, int& exit_code) {
  auto* nxt_cmd = app.add_subcommand("nxt", "Act on a LEGO NXT over USB or Bluetooth, or serve a virtual NXT");
  auto a = std::make_shared<NxtArgs>();
  nxt_cmd->add_option("--port", a->port, "usb, usb:SERIAL, bt:AA:BB:CC:DD:EE:FF or a tty path (default: NXT_PORT, else usb)")->check(not_empty());
  nxt_cmd->add_flag("--json", a->json, "Print JSON for scripts");
  nxt_cmd->add_flag("-v,--verbose", a->verbose, "Log every telegram decoded on stderr");
  nxt_cmd->add_option("--timeout", a->timeout_ms, "Milliseconds to wait for a reply (default 1000)")
      ->check(in_range(1, 60000, "ms"));
  nxt_cmd->require_subcommand(1);
  nxt_cmd->fallthrough();
  const std::string exit_codes =
      "Exit codes: 0 done; 1 the brick refused or a file is bad; 2 bad command line or value;\n"
      "3 the port could not be opened; 4 the brick did not answer or answered nonsense; 130 Ctrl-C.";
  nxt_cmd->footer(table_help() + exit_codes);

  // Registers an action whose callback checks its values, then runs `make()`
  // (which returns the action, or a usage message) against the brick.
  // Actions show the exit codes, not the whole table (CLI11 would inherit it).
  auto add = [nxt_cmd, exit_codes](const std::string& name, const std::string& help) {
    auto* sub = nxt_cmd->add_subcommand(name, help);
    sub->footer(exit_codes);
    return sub;
  };
  auto run = [&exit_code, a](CLI::App* sub, std::function<Made()> make) {
    std::string name = sub->get_name();
    if (sub->get_parent() && sub->get_parent()->get_name() != "nxt") name = sub->get_parent()->get_name() + " " + name;
    sub->callback([&exit_code, a, make, name] {
      auto made = make();
      if (auto* usage = std::get_if<std::string>(&made)) {
        exit_code = report(*a, name, Failure{kExitUsage, *usage});
        return;
      }
      if (auto* bad = std::get_if<Failure>(&made)) {
        exit_code = report(*a, name, *bad);
        return;
      }
      exit_code = with_brick(*a, name, std::get<Action>(made));
    });
  };

  // An action on one sensor port: its PORT argument (1-4) is checked, then
  // `make` gets the port index 0-3.
  auto run_on_input = [&run](CLI::App* sub, std::function<Made(int)> make) {
    auto port = std::make_shared<std::string>();
    sub->add_option("PORT", *port, "1-4")->required();
    run(sub, [port, make]() -> Made {
      auto p = input_port(*port);
      if (!p) return bad_input_port(*port);
      return make(*p);
    });
  };

  run(add("info", "Name, Bluetooth address, firmware, free flash, battery"), [] { return Action(info); });

  run(add("battery", "Battery voltage"), [] {
    return Action([](Client& c) -> std::variant<Output, Failure> {
      auto r = nxt::call_ok(c, "GetBatteryLevel", {});
      if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
      auto mv = *std::get<nxt::Decoded>(r).number("millivolts");
      return Output{fmt::format("{} mV\n", mv), {{"battery_mv", mv}}};
    });
  });

  {
    auto* cmd = add("tone", "Play a tone: HZ (200-14000) for MS milliseconds");
    auto hz = std::make_shared<int>(0), ms = std::make_shared<int>(0);
    cmd->add_option("HZ", *hz, "Frequency, 200-14000 Hz")->required()->check(in_range(200, 14000));
    cmd->add_option("MS", *ms, "Duration, 1-65535 ms")->required()->check(in_range(1, 65535));
    run(cmd, [hz, ms]() -> Made {
      return Action([h = *hz, m = *ms](Client& c) {
        return simple(c, "PlayTone", values({std::int64_t{h}, std::int64_t{m}}), "");
      });
    });
  }

  {
    auto* cmd = add("motor", "Drive a motor: PORT (A, B, C, all) at POWER (-100..100)");
    auto port = std::make_shared<std::string>();
    auto power = std::make_shared<int>(0);
    auto limit = std::make_shared<long long>(0);
    auto brake = std::make_shared<bool>(false), coast = std::make_shared<bool>(false),
         regulated = std::make_shared<bool>(false);
    cmd->add_option("PORT", *port, "A, B, C or all")->required();
    cmd->add_option("POWER", *power, "-100..100 (0 stops)")->required()->allow_extra_args(false)->check(in_range(-100, 100));
    // The checks see the text as typed: past 2^63 the number would be read
    // as 2^63 - 1, and a message quoting that would not be what was typed.
    cmd->add_option("--limit", *limit, "Stop after this many degrees (0: run on)")
        ->check(in_range(0, 0xFFFFFFFFLL));
    auto* b = cmd->add_flag("--brake", *brake, "Brake when stopping (hold the position)");
    auto* f = cmd->add_flag("--coast", *coast, "Let the motor float when stopping (default)");
    b->excludes(f);
    cmd->add_flag("--regulated", *regulated, "Speed regulation (keeps speed under load)");
    run(cmd, [=]() -> Made {
      auto p = output_port(*port);
      if (!p) return bad_output_port(*port);
      std::uint8_t mode = 0;
      std::uint8_t run_state = nxt::kRunStateIdle;
      // Power 0 with --brake holds the motor; without it the motor floats.
      if (*power != 0 || *brake) {
        mode = nxt::kMotorOn | (*brake ? nxt::kBrake : 0) | (*regulated ? nxt::kRegulated : 0);
        run_state = nxt::kRunStateRunning;
      }
      std::vector<Value> v{std::int64_t{*p}, std::int64_t{*power}, std::int64_t{mode},
                           std::int64_t{*regulated ? 1 : 0}, std::int64_t{0}, std::int64_t{run_state},
                           static_cast<std::int64_t>(*limit)};
      return Action([v](Client& c) { return simple(c, "SetOutputState", v, ""); });
    });
  }

  {
    auto* cmd = add("motor-state", "A motor's power, mode and tacho counts");
    auto port = std::make_shared<std::string>();
    cmd->add_option("PORT", *port, "A, B or C")->required();
    run(cmd, [port]() -> Made {
      auto p = output_port(*port);
      if (!p || *p == 0xFF) return fmt::format("\"{}\" is not a motor port (A, B or C)", *port);
      return Action([p = *p](Client& c) -> std::variant<Output, Failure> {
        auto r = nxt::call_ok(c, "GetOutputState", values({std::int64_t{p}}));
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        const auto& d = std::get<nxt::Decoded>(r);
        Output o;
        for (const char* f : {"power", "mode", "regulation", "turn_ratio", "run_state", "tacho_limit", "tacho_count",
                              "block_tacho_count", "rotation_count"})
          o.data[f] = *d.number(f);
        o.data["port"] = std::string(1, static_cast<char>('A' + p));
        auto named = [&](std::span<const nxt::EnumName> names, const char* field) {
          auto v = static_cast<std::uint8_t>(*d.number(field));
          auto n = nxt::enum_name(names, v);
          return n.empty() ? fmt::format("0x{:02x}", v) : std::string(n);
        };
        o.text = fmt::format(
            "port {}: power {} mode {} regulation {} turn ratio {} run state {}\n"
            "        tacho count {} (block {}, rotation {}), limit {}\n",
            static_cast<char>('A' + p), *d.number("power"),
            nxt::output_mode_names(static_cast<std::uint8_t>(*d.number("mode"))),
            named(nxt::regulation_modes(), "regulation"), *d.number("turn_ratio"), named(nxt::run_states(), "run_state"),
            *d.number("tacho_count"), *d.number("block_tacho_count"), *d.number("rotation_count"),
            *d.number("tacho_limit"));
        return o;
      });
    });
  }

  {
    // ResetMotorPosition (a seed command). The internal tacho count is
    // UpdateResetCount's (0x21), which other firmwares use for other things
    // (spec/nxt.md): that is tacho-reset, which checks the firmware first.
    auto* cmd = add("motor-reset", "Zero a motor's block and rotation counts (ResetMotorPosition; tacho-reset: the tacho count)");
    auto port = std::make_shared<std::string>();
    auto block = std::make_shared<bool>(false), rotation = std::make_shared<bool>(false);
    cmd->add_option("PORT", *port, "A, B or C")->required();
    auto* b = cmd->add_flag("--block", *block, "Only the block count (since the last movement)");
    auto* r = cmd->add_flag("--rotation", *rotation, "Only the rotation count (since the last reset)");
    b->excludes(r);
    run(cmd, [=]() -> Made {
      auto p = output_port(*port);
      if (!p || *p == 0xFF) return fmt::format("\"{}\" is not a motor port (A, B or C)", *port);
      return Action([p = *p, only_block = *block, only_rotation = *rotation](Client& c) -> std::variant<Output, Failure> {
        // relative = 1 zeroes the block count, 0 the rotation count.
        for (std::int64_t relative : {1, 0}) {
          if ((relative == 1 && only_rotation) || (relative == 0 && only_block)) continue;
          auto r = nxt::call_ok(c, "ResetMotorPosition", values({std::int64_t{p}, relative}));
          if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        }
        return Output{"", {{"port", std::string(1, static_cast<char>('A' + p))}}};
      });
    });
  }

  {
    auto* cmd = add("sensor", "Set a sensor port's TYPE and MODE (names from the NXT protocol)");
    auto type = std::make_shared<std::string>(), mode = std::make_shared<std::string>("RAWMODE");
    run_on_input(cmd, [=](int p) -> Made {
      auto t = nxt::sensor_type_named(*type);
      if (!t) return fmt::format("\"{}\" is not a sensor type ({})", *type, names_of(nxt::sensor_types()));
      auto m = nxt::sensor_mode_named(*mode);
      if (!m) return fmt::format("\"{}\" is not a sensor mode ({})", *mode, names_of(nxt::sensor_modes()));
      return Action([v = values({std::int64_t{p}, std::int64_t{*t}, std::int64_t{*m}})](Client& c) {
        return simple(c, "SetInputMode", v, "");
      });
    });
    cmd->add_option("TYPE", *type, names_of(nxt::sensor_types()))->required();
    cmd->add_option("MODE", *mode,
                    names_of(nxt::sensor_modes()) + " (default RAWMODE; the word MODE may be left off: BOOLEAN)");
  }

  {
    run_on_input(add("read", "Read a sensor port (valid, raw, normalized, scaled)"), [](int p) {
      return Action([p](Client& c) -> std::variant<Output, Failure> {
        auto r = nxt::call_ok(c, "GetInputValues", values({std::int64_t{p}}));
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        const auto& d = std::get<nxt::Decoded>(r);
        auto type = nxt::enum_name(nxt::sensor_types(), static_cast<std::uint8_t>(*d.number("type")));
        auto mode = nxt::enum_name(nxt::sensor_modes(), static_cast<std::uint8_t>(*d.number("mode") & 0xE0));
        Output o;
        o.data = {{"port", p + 1},         {"valid", *d.number("valid") != 0}, {"type", type},
                  {"mode", mode},          {"raw", *d.number("raw")},          {"normalized", *d.number("normalized")},
                  {"scaled", *d.number("scaled")}};
        // The temperature modes' scaled value is in tenths of a degree.
        auto scaled = *d.number("scaled");
        std::string unit;
        if (mode == "CELSIUSMODE") unit = fmt::format(" ({:.1f} °C)", static_cast<double>(scaled) / 10);
        // The firmware computes Fahrenheit in unsigned arithmetic: 0..70 °C
        // reads 32.0..158.0 °F, and below 0 °C the sum wraps (docs/nxt.md).
        if (mode == "FAHRENHEITMODE")
          unit = scaled >= 320 && scaled <= 1580 ? fmt::format(" ({:.1f} °F)", static_cast<double>(scaled) / 10)
                                                 : " (not °F: below 0 °C the firmware's Fahrenheit wraps)";
        o.text = fmt::format("port {}: {} {} {} raw {} normalized {} scaled {}{}\n", p + 1, type, mode,
                             *d.number("valid") ? "valid" : "not valid yet", *d.number("raw"),
                             *d.number("normalized"), scaled, unit);
        return o;
      });
    });
  }

  {
    run_on_input(add("ultrasonic", "Distance from an ultrasonic sensor (I2C), in cm"), [](int p) {
      return Action([p](Client& c) -> std::variant<Output, Failure> {
        auto r = nxt::read_ultrasonic(c, p);
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        int cm = std::get<int>(r);
        // 255 means no echo: nothing in range.
        return Output{cm == 255 ? "nothing in range\n" : fmt::format("{} cm\n", cm),
                      {{"port", p + 1}, {"distance_cm", cm}}};
      });
    });
  }

  {
    auto* mailbox = add("mailbox", "Write or read a mailbox (1-10) of the running program");
    mailbox->require_subcommand(1);
    auto box = std::make_shared<int>(0);
    auto text = std::make_shared<std::optional<std::string>>();
    auto as_int = std::make_shared<std::optional<long long>>();
    auto as_float = std::make_shared<std::optional<double>>();
    auto* w = mailbox->add_subcommand("write", "Put TEXT, --int N (NXC) or --float X (NXT-G) in mailbox BOX");
    w->add_option("BOX", *box, "1-10")->required()->check(in_range(1, 10));
    w->add_option("TEXT", *text, "Text, at most 58 characters");
    w->add_option("--int", *as_int, "A 32-bit integer, as NXC sends numbers")
        ->check(in_range(INT32_MIN, INT32_MAX));
    w->add_option("--float", *as_float, "A 32-bit float, as NXT-G sends numbers")
        ->check(number_in(-3.4028234663852886e38, 3.4028234663852886e38, "a float's range, about -3.4e38..3.4e38"));
    run(w, [=]() -> Made {
      int given = (text->has_value() ? 1 : 0) + (as_int->has_value() ? 1 : 0) + (as_float->has_value() ? 1 : 0);
      if (given != 1) return std::string("give exactly one of TEXT, --int N, --float X");
      nxt::Bytes message;
      if (*text) {
        if ((*text)->size() > nxt::kMaxMessage - 1)
          return fmt::format("the message is {} bytes; at most {} fit (59 with the NUL)", (*text)->size(),
                             nxt::kMaxMessage - 1);
        if ((*text)->find('\0') != std::string::npos) return std::string("the text cannot contain a NUL");
        message = nxt::message_text(**text);
      } else if (*as_int) {
        message = nxt::message_int(static_cast<std::int32_t>(**as_int));
      } else {
        message = nxt::message_float(static_cast<float>(**as_float));
      }
      std::vector<Value> v{std::int64_t{*box - 1}, std::int64_t{0}, message};
      return Action([v](Client& c) { return simple(c, "MessageWrite", v, ""); });
    });
    auto rbox = std::make_shared<int>(0);
    auto keep = std::make_shared<bool>(false);
    auto* r = mailbox->add_subcommand("read", "Take the oldest message from mailbox BOX (1-10, or 11-20: outboxes)");
    r->add_option("BOX", *rbox, "1-20")->required()->check(in_range(1, 20));
    r->add_flag("--keep", *keep, "Leave the message in the mailbox");
    run(r, [=]() -> Made {
      std::int64_t q = *rbox - 1;
      return Action([q, k = *keep](Client& c) -> std::variant<Output, Failure> {
        auto res = nxt::call(c, *nxt::find_command("MessageRead"), values({q, q % 10, std::int64_t{k ? 0 : 1}}));
        if (auto* e = std::get_if<CallError>(&res)) return failure(*e);
        const auto& d = std::get<nxt::Decoded>(res);
        if (d.status == nxt::status::kQueueEmpty)
          return Output{"(empty)\n", {{"mailbox", q + 1}, {"message", nullptr}}};
        if (d.status != nxt::status::kOk)
          return failure(nxt::refused(d));
        auto data = *d.bytes("data");
        auto size = static_cast<std::size_t>(*d.number("size"));
        if (size > data.size()) return Failure{kExitNoReply, fmt::format("MessageRead says {} bytes in a 59-byte field", size)};
        data.resize(size);
        std::string shown = nxt::show_message(data);
        return Output{shown + "\n", {{"mailbox", q + 1}, {"message", shown}, {"bytes", nxt::hex(data)}}};
      });
    });
  }

  auto name_arg = [&](const std::string& sub, const std::string& help, std::string_view command,
                      bool loop = false) {
    auto* cmd = add(sub, help);
    auto name = std::make_shared<std::string>();
    cmd->add_option("NAME", *name, "A file on the brick (15.3)")->required();
    auto looping = std::make_shared<bool>(false);
    if (loop) cmd->add_flag("--loop", *looping, "Repeat until stopped");
    run(cmd, [=]() -> Made {
      if (auto bad = nxt::check_file_name(*name)) return *bad;
      // The brick answers 0x00 to StartProgram of any file that exists and
      // then fails to run one that is no program: refuse it here, where the
      // user can still be told.
      if (command == "StartProgram") {
        std::string ext = name->substr(name->rfind('.') == std::string::npos ? name->size() : name->rfind('.') + 1);
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
        if (ext != "rxe" && ext != "rtm")
          return fmt::format("\"{}\" is not a program (.rxe, or .rtm for Try Me): the brick would accept it and run "
                             "nothing",
                             *name);
      }
      // PlaySoundFile has its loop flag before the name.
      std::vector<Value> v;
      if (loop) v.emplace_back(std::int64_t{*looping ? 1 : 0});
      v.emplace_back(*name);
      return Action([v, command, name](Client& c) -> std::variant<Output, Failure> {
        auto r = nxt::call_ok(c, command, v);
        auto* e = std::get_if<CallError>(&r);
        if (!e) return Output{"", json::object()};
        Failure f = failure(*e);
        // StartProgram and PlaySoundFile answer 0xC0 for a missing file (the
        // seed's 0xBD is never sent): say what it means here.
        if (e->kind == CallError::Kind::Refused && e->status == nxt::status::kOutOfRange && command != "Delete")
          f.message += fmt::format(" (no file \"{}\" on the brick)", *name);
        return f;
      });
    });
  };
  name_arg("start", "Start the program NAME (.rxe)", "StartProgram");
  name_arg("play", "Play the sound file NAME (.rso); with --loop until stop-sound", "PlaySoundFile", true);
  name_arg("rm", "Delete the file NAME", "Delete");

  run(add("stop", "Stop the running program"), [] {
    return Action([](Client& c) { return simple(c, "StopProgram", {}, ""); });
  });

  // `play --loop` repeats until stopped: this is what stops it (and a tone).
  run(add("stop-sound", "Stop the sound playing (a tone, or a file played with --loop)"), [] {
    return Action([](Client& c) { return simple(c, "StopSoundPlayback", {}, ""); });
  });

  run(add("current", "The running program's name"), [] {
    return Action([](Client& c) -> std::variant<Output, Failure> {
      auto r = nxt::call(c, *nxt::find_command("GetCurrentProgramName"), {});
      if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
      const auto& d = std::get<nxt::Decoded>(r);
      if (d.status == nxt::status::kNoProgram) return Output{"(no program running)\n", {{"program", nullptr}}};
      if (d.status != nxt::status::kOk)
        return failure(nxt::refused(d));
      return Output{*d.text("name") + "\n", {{"program", *d.text("name")}}};
    });
  });

  {
    auto* cmd = add("rename", "Rename the brick: NAME, 1-15 characters (Bluetooth and its screen show it)");
    auto name = std::make_shared<std::string>();
    cmd->add_option("NAME", *name, "The new name, 1-15 printable ASCII characters")->required();
    run(cmd, [name]() -> Made {
      // SetBrickName's field is 16 bytes with the NUL, and GetDeviceInfo
      // gives back 15: a longer name would come back cut.
      if (name->empty() || name->size() > 15)
        return fmt::format("\"{}\" is {} characters; a brick's name is 1-15", *name, name->size());
      if (!std::all_of(name->begin(), name->end(), [](unsigned char c) { return c >= 0x20 && c < 0x7F; }))
        return fmt::format("\"{}\" is not a brick name: printable ASCII characters only", *name);
      return Action([n = *name](Client& c) -> std::variant<Output, Failure> {
        auto r = nxt::call_ok(c, "SetBrickName", values({n}));
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        // At start-up the firmware takes the name back from its Bluetooth
        // module and keeps 8 characters (c_comm.c, SIZE_OF_BRICK_NAME).
        if (n.size() > 8)
          std::cerr << fmt::format("rcxc nxt rename: note: after the brick is switched off and on it keeps the first "
                                   "8 characters (\"{}\"); docs/nxt.md\n",
                                   n.substr(0, 8));
        return Output{"", {{"name", n}}};
      });
    });
  }

  run(add("keepalive", "Reset the sleep timer; prints the sleep limit"), [] {
    return Action([](Client& c) -> std::variant<Output, Failure> {
      auto r = nxt::call_ok(c, "KeepAlive", {});
      if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
      auto ms = *std::get<nxt::Decoded>(r).number("sleep_limit_ms");
      return Output{sleep_text(ms), {{"sleep_limit_ms", ms}}};
    });
  });

  {
    auto* cmd = add("volume", "The brick's volume 0-4, as its Settings menu shows it; LEVEL sets it");
    auto level = std::make_shared<std::string>();
    cmd->add_option("LEVEL", *level, "0 (mute) to 4");
    run(cmd, [=]() -> Made {
      std::optional<std::uint32_t> set;
      if (!level->empty()) {
        if (level->size() != 1 || (*level)[0] < '0' || (*level)[0] > '4')
          return fmt::format("\"{}\" is not a volume: 0 (mute) to 4, as the brick's Settings menu has it", *level);
        set = static_cast<std::uint32_t>((*level)[0] - '0');
      }
      return Action([=](Client& c) {
        return property(c, nxt::Property::Volume, set,
                        [](std::uint32_t v) { return Output{fmt::format("volume {}\n", v), {{"volume", v}}}; });
      });
    });
  }

  {
    auto* cmd = add("sleep", "The brick's sleep limit; MINUTES (1-255) or off sets it");
    auto limit = std::make_shared<std::string>();
    cmd->add_option("MINUTES", *limit, "1-255, or off (never sleep)");
    run(cmd, [=]() -> Made {
      std::optional<std::uint32_t> set_ms;
      if (!limit->empty()) {
        std::string l = lower(*limit);
        // The firmware keeps whole minutes in one byte (IOMAPUI SleepTimeout).
        if (l == "off" || l == "never" || l == "0") set_ms = 0;
        else if (auto m = parse_number(*limit, 255); m && *m > 0 && limit->rfind("0x", 0) != 0)
          set_ms = static_cast<std::uint32_t>(*m * 60'000);
        else
          return fmt::format("\"{}\" is not a sleep limit: 1-255 minutes, or off", *limit);
      }
      return Action([=](Client& c) {
        return property(c, nxt::Property::SleepMs, set_ms,
                        [](std::uint32_t ms) { return Output{sleep_text(ms), {{"sleep_limit_ms", ms}}}; });
      });
    });
  }

  {
    auto* cmd = add("bluetooth", "Whether the brick's Bluetooth is on; on or off switches it (off over Bluetooth ends the link)");
    auto state = std::make_shared<std::string>();
    cmd->add_option("STATE", *state, "on or off");
    run(cmd, [=]() -> Made {
      std::optional<std::uint32_t> set;
      if (!state->empty()) {
        std::string l = lower(*state);
        if (l == "on") set = 1;
        else if (l == "off") set = 0;
        else return fmt::format("\"{}\" is not a Bluetooth state: on or off", *state);
      }
      return Action([=](Client& c) {
        auto show = [](std::uint32_t state) {
          bool on = state != 0;
          return Output{on ? "bluetooth on\n" : "bluetooth off\n", {{"bluetooth", on}}};
        };
        // Over Bluetooth the radio is gone once it answered `off`: asking
        // again would only time out and call a switch that worked a failure.
        return property(c, nxt::Property::Bluetooth, set, show, /*read_back=*/set != 0u);
      });
    });
  }

  {
    auto* cmd = add("tacho-reset", "Zero a motor's internal tacho count (UpdateResetCount; motor-reset zeroes the others)");
    auto port = std::make_shared<std::string>();
    cmd->add_option("PORT", *port, "A, B, C or all")->required();
    run(cmd, [=]() -> Made {
      auto p = output_port(*port);
      if (!p) return bad_output_port(*port);
      return Action([p = *p](Client& c) -> std::variant<Output, Failure> {
        if (auto f = lego_first(c, "UpdateResetCount (0x21)")) return *f;
        for (int i = 0; i < 3; ++i) {
          if (p != 0xFF && p != i) continue;
          auto r = nxt::call_ok(c, "UpdateResetCount", values({std::int64_t{i}}));
          if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        }
        return Output{"", {{"port", p == 0xFF ? std::string("all") : std::string(1, static_cast<char>('A' + p))}}};
      });
    });
  }

  {
    auto* cmd = add("datalog", "Read the datalog buffer (DatalogRead); --keep leaves it there");
    auto keep = std::make_shared<bool>(false);
    cmd->add_flag("--keep", *keep, "Leave what was read in the buffer");
    run(cmd, [=]() -> Made {
      return Action([k = *keep](Client& c) -> std::variant<Output, Failure> {
        if (auto f = lego_first(c, "DatalogRead (0x19)")) return *f;
        auto r = nxt::call_ok(c, "DatalogRead", values({std::int64_t{k ? 0 : 1}}));
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        const auto& d = std::get<nxt::Decoded>(r);
        auto data = d.bytes("data").value_or(nxt::Bytes{});
        auto size = static_cast<std::size_t>(d.number("size").value_or(0));
        if (size > data.size())
          return Failure{kExitNoReply, fmt::format("DatalogRead says {} bytes in a {}-byte field", size, data.size())};
        data.resize(size);
        return Output{size == 0 ? "(empty)\n" : nxt::hex(data) + "\n", {{"size", size}, {"bytes", nxt::hex(data)}}};
      });
    });
  }

  auto bt_table = [&](const std::string& action, const std::string& help, bool contacts) {
    run(add(action, help), [=]() -> Made {
      return Action([contacts](Client& c) -> std::variant<Output, Failure> {
        if (auto f = lego_first(c, contacts ? "BTGetContactCount (0x1B)" : "BTGetConnCount (0x1D)")) return *f;
        auto r = nxt::bluetooth_table(c, contacts);
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        Output o;
        o.data[contacts ? "contacts" : "connections"] = json::array();
        for (const auto& b : std::get<std::vector<nxt::BtEntry>>(r)) {
          o.text += fmt::format("{:>2}  {}  (device type {})\n", b.index, b.name, b.device_type);
          o.data[contacts ? "contacts" : "connections"].push_back(
              {{"slot", b.index}, {"name", b.name}, {"device_type", b.device_type}});
        }
        if (o.text.empty()) o.text = "(none)\n";
        return o;
      });
    });
  };
  bt_table("contacts", "The brick's Bluetooth contacts (devices it has paired with)", true);
  bt_table("connections", "The brick's Bluetooth connections (slot 0: its master, 1-3: slaves)", false);

  {
    auto* cmd = add("modules", "The firmware's modules: name, ID, size, IO map size (PATTERN: *.*, Ui.*, ...)");
    auto pattern = std::make_shared<std::string>("*.*");
    cmd->add_option("PATTERN", *pattern, "default *.*");
    run(cmd, [pattern]() -> Made {
      std::string p = *pattern;
      auto dot = p.rfind('.');
      std::string stem = dot == std::string::npos ? p : p.substr(0, dot);
      std::string ext = dot == std::string::npos ? "" : p.substr(dot + 1);
      bool ok = dot != std::string::npos && (stem == "*" || !nxt::check_file_name(stem + ".x")) &&
                (ext == "*" || (!ext.empty() && !nxt::check_file_name("x." + ext)));
      if (!ok) return fmt::format("\"{}\" is not a pattern the brick takes (*.*, name.*, *.ext, name.ext)", p);
      return Action([=](Client& c) -> std::variant<Output, Failure> {
        if (auto f = lego_first(c, "FindFirstModule (0x90)")) return *f;
        auto r = nxt::list_modules(c, p);
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        Output o;
        o.data["modules"] = json::array();
        for (const auto& m : std::get<std::vector<nxt::ModuleEntry>>(r)) {
          o.text += fmt::format("{:<15} 0x{:08X} {:>7} {:>6}\n", m.name, m.id, m.size, m.iomap_size);
          o.data["modules"].push_back({{"name", m.name}, {"id", fmt::format("0x{:08X}", m.id)}, {"size", m.size},
                                       {"iomap_size", m.iomap_size}});
        }
        if (!o.text.empty()) o.text = fmt::format("{:<15} {:<10} {:>7} {:>6}\n", "module", "id", "size", "IO map") + o.text;
        return o;
      });
    });
  }

  {
    auto* iomap = add("iomap", "Read or write a firmware module's IO map (its variables)");
    iomap->require_subcommand(1);
    auto module = std::make_shared<std::string>(), offset = std::make_shared<std::string>(),
         count = std::make_shared<std::string>();
    auto* r = iomap->add_subcommand("read", "Show COUNT bytes of MODULE's IO map from OFFSET, as a hex dump");
    r->add_option("MODULE", *module, "A name (Ui.mod) or an ID (0x000C0001)")->required();
    r->add_option("OFFSET", *offset, "Bytes from the map's start, decimal or 0x hex")->required();
    r->add_option("COUNT", *count, "How many bytes, 1-65535")->required();
    run(r, [=]() -> Made {
      auto spec = parse_module(*module);
      if (auto* e = std::get_if<std::string>(&spec)) return *e;
      auto off = parse_number(*offset, 0xFFFF);
      if (!off) return fmt::format("\"{}\" is not an offset (0-65535)", *offset);
      auto n = parse_number(*count, 0xFFFF);
      if (!n || *n == 0) return fmt::format("\"{}\" is not a count (1-65535)", *count);
      return Action([m = std::get<ModuleSpec>(spec), typed = *module, at = *off, how_many = *n](Client& c)
                        -> std::variant<Output, Failure> {
        const std::uint64_t off = at, n = how_many;
        if (auto f = lego_first(c, "ReadIOMap (0x94)")) return *f;
        auto found = find_module(c, m, typed);
        if (auto* f = std::get_if<Failure>(&found)) return *f;
        const auto& mod = std::get<nxt::ModuleEntry>(found);
        if (off + n > mod.iomap_size)
          return Failure{kExitUsage, fmt::format("{} bytes from offset {} go past {}'s IO map ({} bytes)", n, off,
                                                 mod.name, mod.iomap_size)};
        auto got = nxt::read_iomap(c, mod.id, static_cast<std::uint16_t>(off), n);
        if (auto* e = std::get_if<CallError>(&got)) return failure(*e);
        const auto& data = std::get<nxt::Bytes>(got);
        return Output{hex_dump(off, data), {{"module", mod.name}, {"id", fmt::format("0x{:08X}", mod.id)},
                                            {"offset", off}, {"count", n}, {"bytes", nxt::hex(data)}}};
      });
    });
    auto wmodule = std::make_shared<std::string>(), woffset = std::make_shared<std::string>();
    auto words = std::make_shared<std::vector<std::string>>();
    auto* w = iomap->add_subcommand("write", "Write HEXBYTES into MODULE's IO map at OFFSET");
    w->add_option("MODULE", *wmodule, "A name (Ui.mod) or an ID (0x000C0001)")->required();
    w->add_option("OFFSET", *woffset, "Bytes from the map's start, decimal or 0x hex")->required();
    w->add_option("HEXBYTES", *words, "The bytes: 0a 1b, or 0a1b")->required();
    run(w, [=]() -> Made {
      auto spec = parse_module(*wmodule);
      if (auto* e = std::get_if<std::string>(&spec)) return *e;
      auto off = parse_number(*woffset, 0xFFFF);
      if (!off) return fmt::format("\"{}\" is not an offset (0-65535)", *woffset);
      std::string err;
      auto data = parse_hex_data(*words, err);
      if (!data) return err;
      return Action([m = std::get<ModuleSpec>(spec), typed = *wmodule, off = *off, bytes = *data](Client& c)
                        -> std::variant<Output, Failure> {
        if (auto f = lego_first(c, "WriteIOMap (0x95)")) return *f;
        auto found = find_module(c, m, typed);
        if (auto* f = std::get_if<Failure>(&found)) return *f;
        const auto& mod = std::get<nxt::ModuleEntry>(found);
        // IOCtrl's one word switches the brick off (0x5A00) or erases its
        // firmware into SAMBA mode (0xA55A): never from here.
        if (lower(mod.name) == "ioctrl.mod")
          return Failure{kExitUsage, "IOCtrl.mod's word switches the brick off or boots it into firmware-update "
                                     "mode (erasing the firmware): rcxc does not write it (raw can)"};
        if (off + bytes.size() > mod.iomap_size)
          return Failure{kExitUsage, fmt::format("{} bytes at offset {} go past {}'s IO map ({} bytes)", bytes.size(),
                                                 off, mod.name, mod.iomap_size)};
        if (auto e = nxt::write_iomap(c, mod.id, static_cast<std::uint16_t>(off), bytes)) return failure(*e);
        return Output{"", {{"module", mod.name}, {"id", fmt::format("0x{:08X}", mod.id)}, {"offset", off},
                           {"count", bytes.size()}}};
      });
    });
  }

  {
    auto* cmd = add("poll", "Read what a program on the brick left for the host in a poll buffer");
    auto high_speed = std::make_shared<bool>(false);
    cmd->add_flag("--high-speed", *high_speed, "The high-speed port's buffer (default: the USB poll buffer)");
    run(cmd, [=]() -> Made {
      return Action([buffer = std::int64_t{*high_speed ? 1 : 0}](Client& c) -> std::variant<Output, Failure> {
        if (auto f = lego_first(c, "PollCommandLength (0xA1)")) return *f;
        auto len = nxt::call_ok(c, "PollCommandLength", values({buffer}));
        if (auto* e = std::get_if<CallError>(&len)) return failure(*e);
        // At most a USB packet's 59 bytes come in one PollCommand (c_comm.c).
        auto waiting = std::min<std::int64_t>(std::get<nxt::Decoded>(len).number("count").value_or(0), 59);
        nxt::Bytes data;
        if (waiting > 0) {
          auto r = nxt::call_ok(c, "PollCommand", values({buffer, waiting}));
          if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
          const auto& d = std::get<nxt::Decoded>(r);
          data = d.bytes("data").value_or(nxt::Bytes{});
          data.resize(std::min(data.size(), static_cast<std::size_t>(d.number("count").value_or(0))));
        }
        return Output{data.empty() ? "(empty)\n" : nxt::hex(data) + "\n",
                      {{"buffer", buffer == 0 ? "usb" : "high-speed"}, {"bytes", nxt::hex(data)}}};
      });
    });
  }

  {
    auto* cmd = add("erase-all", "Delete every file on the brick (DeleteUserFlash); needs --yes");
    auto yes = std::make_shared<bool>(false);
    cmd->add_flag("--yes", *yes, "Mean it: programs, sounds and data all go");
    run(cmd, [=]() -> Made {
      if (!*yes)
        return std::string("erase-all deletes every file on the brick (programs, sounds, data) and cannot be undone: "
                           "add --yes to mean it");
      return Action([](Client& c) -> std::variant<Output, Failure> {
        // The brick answers when the flash is erased, about 3 s later.
        c.timeout = std::max(c.timeout, nxt::Millis(6000));
        auto r = nxt::call_ok(c, "DeleteUserFlash", {});
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        return Output{"", json::object()};
      });
    });
  }

  {
    auto* cmd = add("ls", "List files (PATTERN: *.*, name.*, *.ext, name.ext)");
    auto pattern = std::make_shared<std::string>("*.*");
    cmd->add_option("PATTERN", *pattern, "default *.*");
    run(cmd, [pattern]() -> Made {
      std::string p = *pattern;
      auto dot = p.rfind('.');
      std::string stem = dot == std::string::npos ? p : p.substr(0, dot);
      std::string ext = dot == std::string::npos ? "" : p.substr(dot + 1);
      bool ok = dot != std::string::npos && (stem == "*" || !nxt::check_file_name(stem + ".x")) &&
                (ext == "*" || (!ext.empty() && !nxt::check_file_name("x." + ext)));
      if (!ok) return fmt::format("\"{}\" is not a pattern the brick takes (*.*, name.*, *.ext, name.ext)", p);
      return Action([p](Client& c) -> std::variant<Output, Failure> {
        auto r = nxt::list_files(c, p);
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        Output o;
        o.data["files"] = json::array();
        for (const auto& f : std::get<std::vector<nxt::FileEntry>>(r)) {
          o.text += fmt::format("{:>8}  {}\n", f.size, f.name);
          o.data["files"].push_back({{"name", f.name}, {"size", f.size}});
        }
        return o;
      });
    });
  }

  {
    auto* cmd = add("upload", "Copy the local FILE to the brick (as NAME)");
    auto file = std::make_shared<std::string>(), name = std::make_shared<std::string>();
    auto replace = std::make_shared<bool>(false);
    cmd->add_option("FILE", *file, "A local file, or - for the standard input (then NAME is needed)")->required();
    cmd->add_option("NAME", *name, "Its name on the brick (default: FILE's name)");
    cmd->add_flag("--replace", *replace,
                  "Delete a file of that name on the brick first (the brick refuses to write over one)");
    run(cmd, [=]() -> Made {
      // "-" is the standard input, as download's FILE - is the standard
      // output: it was looked for as a file named "-". A pipe has no name
      // to give the file on the brick.
      const bool from_stdin = *file == "-";
      if (from_stdin && name->empty())
        return std::string("FILE - (the standard input) has no name to give the file on the brick: "
                           "add it, rcxc nxt upload - NAME");
      std::string target = name->empty() ? std::filesystem::path(*file).filename().string() : *name;
      if (auto bad = nxt::check_file_name(target)) return *bad;
      if (from_stdin && ::isatty(STDIN_FILENO))
        return std::string("the standard input is a terminal: give a FILE, or send the file through a pipe "
                           "(rcxc nxt upload - NAME < FILE)");
      auto data = std::make_shared<nxt::Bytes>();
      if (std::string err = from_stdin ? read_stdin_bytes(*data) : read_file_bytes(*file, *data); !err.empty())
        return Failure{kExitFailure, err};
      return Action([=](Client& c) -> std::variant<Output, Failure> {
        if (*replace) {
          // Not there is as good as deleted; anything else (0x8B: the file
          // is open) stops the upload.
          auto r = nxt::call(c, *nxt::find_command("Delete"), values({target}));
          if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
          const auto& d = std::get<nxt::Decoded>(r);
          if (d.status != nxt::status::kOk && d.status != nxt::status::kFileNotFound) return failure(nxt::refused(d));
        }
        if (auto e = nxt::upload_file(c, target, *data, progress_bar("upload " + target))) {
          Failure f = failure(*e);
          // OpenWrite never writes over a file (0x8F): say how to.
          if (e->kind == CallError::Kind::Refused && e->status == nxt::status::kFileExists)
            f.message += fmt::format(" (\"{}\" is on the brick: upload --replace, or rcxc nxt rm {} first)", target, target);
          return f;
        }
        return Output{fmt::format("{} bytes to {}\n", data->size(), target), {{"name", target}, {"size", data->size()}}};
      });
    });
  }

  {
    auto* cmd = add("download", "Copy NAME from the brick to a local FILE");
    auto name = std::make_shared<std::string>(), file = std::make_shared<std::string>();
    cmd->add_option("NAME", *name, "A file on the brick")->required();
    cmd->add_option("FILE", *file,
                    "Where to write it: a file, a folder to write NAME in, or - for the standard output "
                    "(default: NAME)");
    run(cmd, [=]() -> Made {
      if (auto bad = nxt::check_file_name(*name)) return *bad;
      // "-" is the standard output, as for rcxc compile -o: it wrote a file named "-".
      if (*file == "-") {
        if (a->json) return std::string("--json and FILE - do not go together: the file's bytes would mix with the JSON");
        if (::isatty(STDOUT_FILENO))
          return std::string("the standard output is a terminal: give a FILE, or send it to a pipe or a file");
        return Action([=](Client& c) -> std::variant<Output, Failure> {
          auto r = nxt::download_file(c, *name, progress_bar("download " + *name));
          if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
          const auto& data = std::get<nxt::Bytes>(r);
          std::cout.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
          std::cout.flush();
          if (!std::cout) return Failure{kExitFailure, "cannot write the standard output"};
          return Output{"", json::object()};
        });
      }
      std::string target = file->empty() ? *name : *file;
      std::error_code ec;
      if (std::filesystem::is_directory(target, ec) || target.ends_with('/'))
        target = (std::filesystem::path(target) / *name).string();
      // Said before the port is opened: a transfer takes seconds over
      // Bluetooth, and only then did a missing folder show.
      if (auto unwritable = savefile::check_writable(target))
        return Failure{kExitFailure, fmt::format("cannot write {}: {}", target, *unwritable)};
      return Action([=](Client& c) -> std::variant<Output, Failure> {
        auto r = nxt::download_file(c, *name, progress_bar("download " + *name));
        if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
        const auto& data = std::get<nxt::Bytes>(r);
        // Written only once the whole file is here, through a temporary: a
        // failed write leaves what was at `target` before.
        if (auto unwritten = savefile::write_file_atomically(target, std::string(data.begin(), data.end())))
          return Failure{kExitFailure, fmt::format("cannot write {}: {}", target, *unwritten)};
        return Output{fmt::format("{} bytes to {}\n", data.size(), target), {{"file", target}, {"size", data.size()}}};
      });
    });
  }

  {
    auto* cmd = add("raw", "Send a telegram given as hex bytes (00 0b: GetBatteryLevel) and show the reply");
    auto words = std::make_shared<std::vector<std::string>>();
    cmd->add_option("HEX", *words, "The telegram without the Bluetooth length")->required();
    run(cmd, [words]() -> Made {
      std::string err;
      auto bytes = parse_hex_words(*words, err);
      if (!bytes) return err;
      return Action([t = *bytes](Client& c) -> std::variant<Output, Failure> {
        if (auto e = c.transport.send(t)) return Failure{kExitNoReply, e->message};
        if (c.on_log) c.on_log("-> " + nxt::hex(t));
        if (t[0] & nxt::kNoReplyBit) {
          bool known = t[0] == (nxt::kDirectWithReply | nxt::kNoReplyBit) || t[0] == (nxt::kSystemWithReply | nxt::kNoReplyBit);
          std::string said = known ? "(sent, no reply asked)\n"
                                   : fmt::format("(sent; 0x{:02x} is not a request type: the firmware ignores it)\n", t[0]);
          return Output{said, {{"sent", nxt::hex(t)}}};
        }
        auto got = c.transport.receive(c.timeout);
        if (auto* e = std::get_if<nxt::LinkError>(&got))
          return Failure{e->kind == nxt::LinkError::Kind::Interrupted ? kExitInterrupted : kExitNoReply, e->message};
        auto& reply = std::get<std::optional<nxt::Bytes>>(got);
        if (!reply) {
          std::uint8_t type = t[0];
          std::string why;
          if (type == nxt::kReply)
            why = ": 0x02 is a reply, which the firmware takes (a MessageRead reply goes into a mailbox) but never answers";
          else if (type != nxt::kDirectWithReply && type != nxt::kSystemWithReply)
            why = fmt::format(": 0x{:02x} is not a request type (0x00, 0x01; 0x80, 0x81 without reply), and the "
                              "firmware answers nothing to a type it does not know",
                              type);
          else if (auto left = c.transport.leftovers(); !left.empty())
            why = "; " + left;
          else
            why = "; " + nxt::silence_reasons(c.transport);
          return Failure{kExitNoReply, fmt::format("no reply within {} ms{}", c.timeout.count(), why)};
        }
        auto d = nxt::decode_reply(*reply);
        std::string what = std::holds_alternative<nxt::Decoded>(d) ? nxt::describe(std::get<nxt::Decoded>(d))
                                                                   : std::get<nxt::TelegramError>(d).message;
        Output o{fmt::format("{}\n{}\n", nxt::hex(*reply), what),
                 {{"sent", nxt::hex(t)}, {"reply", nxt::hex(*reply)}, {"decoded", what}}};
        // "ok" says a reply came; whether the brick did it is its status
        // (null when the reply does not parse), so a script need not read
        // `decoded`'s words.
        o.data["status"] = reply->size() >= 3 && (*reply)[0] == nxt::kReply ? json((*reply)[2]) : json(nullptr);
        return o;
      });
    });
  }

  {
    auto* cmd = add("bench", "Round-trip latency of GetBatteryLevel: p50, p99");
    auto count = std::make_shared<int>(200);
    cmd->add_option("--count", *count, "Round trips (default 200)")->check(in_range(1, 100000));
    run(cmd, [count]() -> Made {
      return Action([n = *count](Client& c) -> std::variant<Output, Failure> {
        std::vector<double> us;
        for (int i = 0; i < n; ++i) {
          auto t0 = std::chrono::steady_clock::now();
          auto r = nxt::call_ok(c, "GetBatteryLevel", {});
          if (auto* e = std::get_if<CallError>(&r)) return failure(*e);
          us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
        }
        std::sort(us.begin(), us.end());
        auto at = [&](double q) { return us[std::min(us.size() - 1, static_cast<std::size_t>(q * static_cast<double>(us.size())))]; };
        Output o;
        o.data = {{"count", n}, {"p50_us", at(0.50)}, {"p99_us", at(0.99)}, {"max_us", us.back()}};
        o.text = fmt::format("{} round trips: p50 {:.0f} us, p99 {:.0f} us, max {:.0f} us\n", n, at(0.50), at(0.99), us.back());
        return o;
      });
    });
  }

  {
    auto* cmd = add("brick", "Serve a virtual NXT on a pseudo-terminal (its path is the first line printed)");
    auto pty = std::make_shared<bool>(false);
    auto scenario = std::make_shared<std::string>(), program = std::make_shared<std::string>();
    cmd->add_flag("--pty", *pty, "Serve on a new pseudo-terminal");
    cmd->add_option("--scenario", *scenario,
                    "Inputs over time: TOML (docs/nxt.md), or a .nqc program whose // @input lines to replay; "
                    "times count from the first telegram")
        ->check(not_empty());
    cmd->add_option("--program", *program,
                    "Start with program NAME.rxe running (made empty if absent), as if started on the brick: "
                    "mailboxes need one")
        ->check(not_empty());
    cmd->callback([&exit_code, a, pty, scenario, program] {
      exit_code = serve_brick(*pty, *scenario, *program, a->verbose);
    });
  }
}

}  // namespace rcxc::cli
