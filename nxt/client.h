// The host side: requests out, their replies back, over any transport.
//
// A reply is taken only if it answers the request just sent (same opcode);
// anything else waiting on the line (a late reply to a request that timed
// out) is drained before sending and dropped if it arrives while waiting.
// The operations below (files, ultrasonic, mailboxes, properties, modules
// and IO maps) are what `rcxc nxt` does, written here so tests drive them
// against the virtual NXT.
#pragma once

#include <functional>
#include <string>
#include <variant>

#include "nxt/telegram.h"
#include "nxt/transport.h"

namespace nxt {

struct CallError {
  enum class Kind : std::uint8_t {
    Input,        // the request could not be built (bad value): exit 2
    NoReply,      // the brick did not answer in time: exit 4
    BadReply,     // what came back does not parse: exit 4
    Refused,      // the brick answered with a non-zero status: exit 1
    Lost,         // the link failed: exit 4
    Interrupted,  // Ctrl-C
  };
  Kind kind;
  std::string message;
  std::uint8_t status = 0;  // Refused only
};

struct Client {
  explicit Client(Transport& link) : transport(link) {}
  Transport& transport;
  Millis timeout{1000};
  std::function<void(const std::string&)> on_log;  // decoded telegrams (-v)
  int dropped = 0;                                  // late or stray replies thrown away
  // Waits between polls (sensor valid, I2C ready); tests advance a virtual
  // clock here instead of sleeping. Empty: sleep.
  std::function<void(Millis)> pause;
};

// Sends the request and waits for its reply. A reply with a non-zero status
// is returned as Decoded (callers decide); use `expect_ok` to make it an error.
std::variant<Decoded, CallError> call(Client& client, const Command& command, std::span<const Value> values);
// The error for a reply whose status is not success: "NAME refused: 0xSS
// what it means".
CallError refused(const Decoded& d);
// call() by command name (from the table), turning a non-zero status into Refused.
std::variant<Decoded, CallError> call_ok(Client& client, std::string_view name, std::span<const Value> values);
// Sends with the no-reply bit (0x80/0x81): for commands whose effect is seen later.
std::optional<CallError> send_only(Client& client, std::string_view name, std::span<const Value> values);

// What "no reply" means when not a byte came back (not when something that
// was no reply came: that is said as it is), for after a "; ": the brick
// switched off or asleep, out of Bluetooth range, or the port read by
// another program. A USB port another program holds does not open, so
// over USB only the first is said.
std::string silence_reasons(const Transport& link);

// Files.
struct FileEntry {
  std::string name;
  std::uint32_t size = 0;
};
// Every file matching the pattern (*.*, x.*, *.ext, x.ext); none is not an error.
std::variant<std::vector<FileEntry>, CallError> list_files(Client& client, const std::string& pattern);
using Progress = std::function<void(std::size_t done, std::size_t total)>;
std::optional<CallError> upload_file(Client& client, const std::string& name, std::span<const std::uint8_t> data,
                                     const Progress& progress = {});
std::variant<Bytes, CallError> download_file(Client& client, const std::string& name, const Progress& progress = {});

// Is `name` a legal NXT file name (15.3, printable, no path)? The message says why not.
std::optional<std::string> check_file_name(const std::string& name);

// Ultrasonic distance in cm on input port 0-3: sets LOWSPEED_9V if needed,
// waits until the port is valid, then reads register 0x42 over I2C.
std::variant<int, CallError> read_ultrasonic(Client& client, int port);

// Which firmware the brick runs, from GetFirmwareVersion. LEGO's firmware
// (and the enhanced NBC/NXC firmware built on it) answers protocol 1.124;
// leJOS NXJ answers protocol 1.2, firmware 1.3 (its LCP.java), and gives
// 0x20 and 0x21 other meanings (disconnect, defragment the flash). The
// direct commands past the seed
// (0x19-0x21) and the IO-map and poll commands mean what the table says
// only on LEGO's.
struct FirmwareVersion {
  int protocol_major = 0, protocol_minor = 0, firmware_major = 0, firmware_minor = 0;
};
bool is_lego_firmware(const FirmwareVersion& v);
std::variant<FirmwareVersion, CallError> firmware_version(Client& client);
// Asks GetFirmwareVersion; a firmware that is not LEGO's is Refused
// (status 0) with a message that names it and `what` was not sent.
std::optional<CallError> require_lego_firmware(Client& client, std::string_view what);

// SetProperty / GetProperty (LEGO's firmware only: require_lego_firmware
// first). Bluetooth is 0 or 1, volume 0-4, the sleep limit in ms (u32).
enum class Property : std::uint8_t { Bluetooth = 0, Volume = 1, SleepMs = 2 };
std::variant<std::uint32_t, CallError> get_property(Client& client, Property property);
std::optional<CallError> set_property(Client& client, Property property, std::uint32_t value);

// The firmware's modules (FindFirstModule / FindNextModule, then
// CloseModuleHandle whatever happened). The loader has one module search;
// one left open by a host that was cut off answers 0x81, so it is closed
// and asked once more. None matching is an empty list.
struct ModuleEntry {
  std::string name;
  std::uint32_t id = 0;
  std::uint32_t size = 0;
  std::uint16_t iomap_size = 0;
};
std::variant<std::vector<ModuleEntry>, CallError> list_modules(Client& client, const std::string& pattern);
// ReadIOMap / WriteIOMap in pieces a USB packet holds (55 and 54 bytes).
std::variant<Bytes, CallError> read_iomap(Client& client, std::uint32_t module_id, std::uint16_t offset,
                                          std::size_t count);
std::optional<CallError> write_iomap(Client& client, std::uint32_t module_id, std::uint16_t offset,
                                     std::span<const std::uint8_t> data);

// A Bluetooth contact or connection slot (BTGetContactName / BTGetConnName).
struct BtEntry {
  int index = 0;
  int device_type = 0;
  std::string name;
};
// Every slot of the contact table (contacts = true) or the connection table
// that holds a name; empty slots are left out.
std::variant<std::vector<BtEntry>, CallError> bluetooth_table(Client& client, bool contacts);

// Mailbox messages: text with its NUL, NXC's int32 LE + NUL, NXT-G's float32 LE + NUL.
Bytes message_text(const std::string& text);
Bytes message_int(std::int32_t value);
Bytes message_float(float value);
// A message as a person reads it: text if it is text, else the number it holds.
std::string show_message(std::span<const std::uint8_t> data);

}  // namespace nxt
