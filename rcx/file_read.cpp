#include "rcx/file_read.h"

#include <fmt/format.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace rcx {

std::variant<std::string, FileProblem> read_file(const std::string& path, FileKind kind) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return FileProblem::Directory;
  std::ifstream in(path, std::ios::binary);
  if (!in) return FileProblem::CannotOpen;
  return read_stream(in, kind);
}

std::variant<std::string, FileProblem> read_stream(std::istream& in, FileKind kind) {
  std::string bytes;
  char chunk[65536];
  while (in) {
    in.read(chunk, sizeof chunk);
    bytes.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (bytes.size() > kind.max_bytes) return FileProblem::TooLarge;
  }
  if (in.bad()) return FileProblem::ReadError;
  return bytes;
}

std::string cannot_open_reason(const std::string& path) {
  if (path.empty()) return "no file name";
  // Asked of lstat() and stat() themselves: std::filesystem::exists() is
  // false alike for a missing name, a link to nothing (ENOENT) and links
  // that lead to each other (ELOOP), and each needs other words.
  constexpr const char* kLoop = "a loop of symbolic links that never reaches a file";
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ELOOP) return kLoop;  // in a folder on the way to it
    if (errno == ENOENT) return "no such file";
  } else if (::stat(path.c_str(), &st) != 0) {
    if (errno == ELOOP) return kLoop;
    if (errno == ENOENT) return "a symbolic link to nothing";
  }
  if (::access(path.c_str(), R_OK) != 0) {
    if (errno == EACCES) return "permission denied";
    std::string why = std::strerror(errno);
    if (!why.empty()) why[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(why[0])));
    return why;
  }
  return "it could not be read";
}

std::string too_large_reason(FileKind kind) {
  std::size_t cap = kind.max_bytes;
  std::string size = cap % (1u << 20) == 0 ? fmt::format("{} MiB", cap >> 20)
                     : cap % 1024 == 0     ? fmt::format("{} KiB", cap >> 10)
                                           : fmt::format("{} bytes", cap);
  return fmt::format("larger than a {} may be ({}); is it the right file?", kind.noun, size);
}

std::string too_large_message(const std::string& path, FileKind kind) {
  return fmt::format("{}: {}", path, too_large_reason(kind));
}

bool starts_as_image(std::string_view bytes) { return bytes.substr(0, 4) == "RCXI"; }

bool holds_binary_data(std::string_view bytes) {
  return starts_as_image(bytes) || bytes.substr(0, 4096).find('\0') != std::string_view::npos;
}

}  // namespace rcx
