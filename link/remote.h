// Remote actions on a brick over the IR link: `rcxc remote ACTION ...`.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "link/session.h"

namespace rcx {

enum class RemoteFailure : std::uint8_t {
  Usage,    // the action or its arguments are wrong
  Input,    // a file could not be read or parsed
  Link,     // no valid reply after every retry
  Refused,  // the brick answered with an error
};

struct RemoteError {
  RemoteFailure kind;
  std::string message;
};

struct RemoteOptions {
  bool csv = false;  // datalog as CSV
  // Progress of a firmware download (bytes done, total).
  std::function<void(std::size_t, std::size_t)> progress;
};

// The actions `run_remote` knows: name, what follows it, what it does.
struct RemoteAction {
  std::string_view name, arguments, summary;
};
const std::vector<RemoteAction>& remote_actions();

// One line per action, for help texts.
std::string remote_actions_help();

// Runs `words` (the action and its arguments, e.g. {"get", "var", "3"}) and
// returns what to print on stdout.
std::variant<std::string, RemoteError> run_remote(Link& link, const std::vector<std::string>& words,
                                                  const RemoteOptions& options = {});

// What is wrong with `words` that no brick is needed to tell (an unknown
// action, a program number out of range, an unreadable firmware file), so
// a bad command line is reported before the tower is opened; nullopt when
// the action can be tried.
std::optional<RemoteError> check_remote(const std::vector<std::string>& words);

// Firmware as S-records: the bytes from 0x8000, where the ROM stores a
// firmware download, to the highest address given (gaps zero-filled), and
// the entry address (S7/S8/S9 record, else 0x8000). Data or an entry outside
// 0x8000..0xffff, a bad checksum, count or record type is an error naming
// the line.
struct Firmware {
  int start = 0;
  int entry = 0;
  Bytes bytes;
};
std::variant<Firmware, std::string> parse_srec(const std::string& text);

// `remote firmware` once the file is read: deletes the brick's firmware,
// sends `fw` block by block and unlocks it; returns what to print.
std::variant<std::string, RemoteError> download_firmware(Link& link, const Firmware& fw,
                                                         const RemoteOptions& options = {});

}  // namespace rcx
