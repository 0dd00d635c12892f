// The host side: requests out, their replies back, over any transport.
//
// A reply is taken only if it answers the request just sent (same opcode);
// anything else waiting on the line (a late reply to a request that timed
// out) is drained before sending and dropped if it arrives while waiting.
// The operations below (files, ultrasonic, mailboxes) are what `rcxc nxt`
// does, written here so tests drive them against the virtual NXT.
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

// Mailbox messages: text with its NUL, NXC's int32 LE + NUL, NXT-G's float32 LE + NUL.
Bytes message_text(const std::string& text);
Bytes message_int(std::int32_t value);
Bytes message_float(float value);
// A message as a person reads it: text if it is text, else the number it holds.
std::string show_message(std::span<const std::uint8_t> data);

}  // namespace nxt
