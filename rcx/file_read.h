// Reading a whole file the user named (an image, a scenario, a firmware
// file, a source, a test). A directory is refused before it is opened: a
// filebuf on a directory throws (EISDIR) on some reads and reads as empty
// on others, and neither tells the user what is wrong. Every read has a
// size cap suited to the kind of file, so /dev/zero, /dev/urandom or an
// endless pipe ends with a message instead of growing until memory runs out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <string_view>
#include <variant>

namespace rcx {

enum class FileProblem : std::uint8_t { Directory, CannotOpen, ReadError, TooLarge };

// What a file is read as, and the most bytes it may have. The caps are far
// above anything real (the RCX has 32 KB of RAM; a whole firmware as
// S-records is about 45 KB) and far below what would hurt the machine.
struct FileKind {
  const char* noun;  // "scenario file": for messages
  std::size_t max_bytes;
};
inline constexpr FileKind kSourceFile{"source file", std::size_t{1} << 20};
inline constexpr FileKind kImageFile{".rcx image", std::size_t{1} << 20};
inline constexpr FileKind kScenarioFile{"scenario file", std::size_t{1} << 20};
inline constexpr FileKind kFirmwareFile{"firmware file", std::size_t{1} << 20};

// The file's bytes, or what kept them from being read. Each caller says it
// in its own words ("P: is a directory, not a scenario file"); a file
// larger than `kind.max_bytes` is TooLarge after reading one byte more.
std::variant<std::string, FileProblem> read_file(const std::string& path, FileKind kind);

// The same for a stream already open (standard input, for a FILE of "-"):
// a pipe that never ends is TooLarge one byte past the cap.
std::variant<std::string, FileProblem> read_stream(std::istream& in, FileKind kind);

// How a file read as text (a source, a scenario, a test) is told from one
// that is not: an RCX image starts with its signature "RCXI"; other binary
// data has a NUL byte in its first 4 KiB, which no text file has.
bool starts_as_image(std::string_view bytes);
bool holds_binary_data(std::string_view bytes);  // an image, or a NUL in the first 4 KiB

// Why `path` could not be opened, in a few words for after "cannot open
// P": "no such file", "permission denied", "a symbolic link to nothing",
// "a loop of symbolic links that never reaches a file". Asked after the
// failure, so a file that changed in between may give a reason of its own.
// Every reader of a user's file says why through this one function.
std::string cannot_open_reason(const std::string& path);

// "P: larger than a source file may be (1 MiB); is it the right file?"
std::string too_large_message(const std::string& path, FileKind kind);
// The same without "P: ", for a caller that names the file itself.
std::string too_large_reason(FileKind kind);

}  // namespace rcx
