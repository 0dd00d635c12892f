#include "rcx/file_read.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
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

std::string too_large_message(const std::string& path, FileKind kind) {
  std::size_t cap = kind.max_bytes;
  std::string size = cap % (1u << 20) == 0 ? fmt::format("{} MiB", cap >> 20)
                     : cap % 1024 == 0     ? fmt::format("{} KiB", cap >> 10)
                                           : fmt::format("{} bytes", cap);
  return fmt::format("{}: larger than a {} may be ({}); is it the right file?", path, kind.noun, size);
}

bool starts_as_image(std::string_view bytes) { return bytes.substr(0, 4) == "RCXI"; }

bool holds_binary_data(std::string_view bytes) {
  return starts_as_image(bytes) || bytes.substr(0, 4096).find('\0') != std::string_view::npos;
}

namespace {

bool bare_key_character(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
}

// "[" or "[[" and blanks at the start of `row`, then a character no key
// starts with.
bool header_with_a_bad_key(std::string_view row) {
  std::size_t at = row.find_first_not_of(" \t");
  if (at == std::string_view::npos || row[at] != '[') return false;
  at += at + 1 < row.size() && row[at + 1] == '[' ? 2 : 1;  // "[[" is one token, "[ [" is not
  at = row.find_first_not_of(" \t", at);
  if (at == std::string_view::npos) return true;
  return !bare_key_character(row[at]) && row[at] != '"' && row[at] != '\'';
}

}  // namespace

std::optional<TomlTrap> toml_trap(std::string_view text) {
  int line = 1;
  for (std::size_t at = 0; at <= text.size(); ++line) {
    std::size_t end = std::min(text.find('\n', at), text.size());
    std::string_view row = text.substr(at, end - at);
    std::size_t hash = row.find('#');
    bool quoted = row.substr(0, hash).find_first_of("\"'") != std::string_view::npos;
    std::string_view code = quoted ? row : row.substr(0, hash);
    if (std::any_of(code.begin(), code.end(), [](char c) { return static_cast<unsigned char>(c) > 0x7f; }))
      return TomlTrap{line, "a letter that is not ASCII outside a comment"};
    if (header_with_a_bad_key(code)) return TomlTrap{line, "a table header without a name"};
    at = end + 1;
  }
  return std::nullopt;
}

}  // namespace rcx
