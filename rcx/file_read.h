// Reading a whole file the user named (an image, a scenario, a firmware
// file, a test). A directory is refused before it is opened: a filebuf on
// a directory throws (EISDIR) on some reads and reads as empty on others,
// and neither tells the user what is wrong.
#pragma once

#include <cstdint>
#include <string>
#include <variant>

namespace rcx {

enum class FileProblem : std::uint8_t { Directory, CannotOpen, ReadError };

// The file's bytes, or what kept them from being read. Each caller says it
// in its own words ("P: is a directory, not a scenario file").
std::variant<std::string, FileProblem> read_file(const std::string& path);

}  // namespace rcx
