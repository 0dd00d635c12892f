#include "tomlfile/read.h"

#include <algorithm>
#include <cctype>
#include <optional>
#include <string>

#include <fmt/format.h>

namespace rcxc::toml_read {
namespace {

struct TomlTrap {
  int line = 0;  // from 1
  std::string what;
};

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

// The end of the string that opens at `at` (a quote), or npos: basic strings
// take backslash escapes, literal ones none; a triple quote runs over lines.
std::size_t string_end(std::string_view text, std::size_t at, int& line) {
  const char quote = text[at];
  const bool triple = text.substr(at, 3) == std::string(3, quote);
  for (std::size_t i = at + (triple ? 3 : 1); i < text.size(); ++i) {
    if (quote == '"' && text[i] == '\\') {
      if (i + 1 < text.size() && text[i + 1] == '\n') ++line;  // a line-ending backslash
      ++i;
      continue;
    }
    if (text[i] == '\n') {
      if (!triple) return std::string_view::npos;  // toml++ says what is wrong
      ++line;
    }
    if (triple ? text.substr(i, 3) == std::string(3, quote) : text[i] == quote) return i + (triple ? 2 : 0);
  }
  return std::string_view::npos;
}

// The line of a '}' where an array expects a value ("x = [}", "[1, }", with
// blanks, line ends or comments between): toml++ 3.3 assumes none is there
// (TOML_ASSERT_ASSUME in parse_value: an abort in Debug builds, an
// assumption clang may build on in release), which the fuzzer found. No
// TOML text has a '}' right after a '[' or a ',' outside strings.
std::optional<int> brace_where_a_value_goes(std::string_view text) {
  int line = 1;
  char last = 0;  // the last character outside blanks, comments and strings
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '\n') ++line;
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
    if (c == '#') {
      i = std::min(text.find('\n', i), text.size()) - 1;
      continue;
    }
    if (c == '"' || c == '\'') {
      i = string_end(text, i, line);
      if (i == std::string_view::npos) return std::nullopt;
      last = c;
      continue;
    }
    if (c == '}' && (last == '[' || last == ',')) return line;
    last = c;
  }
  return std::nullopt;
}

// What in a TOML file of keys and numbers would reach a fault of
// toml++ 3.3, which the fuzzer found: it classifies some letters (U+0441,
// U+0411) as whitespace or not through __builtin_unreachable (undefined
// behaviour), and asserts on a table header whose key starts with another
// character than a letter, digit, '_', '-' or a quote ("[+", "[[/"): an
// abort in Debug builds. Such text is refused before the parser sees it,
// as is a '}' where a value goes (above).
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
  if (auto brace = brace_where_a_value_goes(text)) return TomlTrap{*brace, "a '}' where an array expects a value"};
  return std::nullopt;
}

}  // namespace

std::string where(std::string_view path, const toml::node& node) {
  return fmt::format("{}:{}", path, node.source().begin.line);
}

std::string shown_key(std::string_view key) {
  std::string out;
  for (char c : key) {
    auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) out += fmt::format("\\x{:02x}", byte);
    else out += c;
  }
  return out;
}

std::optional<std::int64_t> int_key(const toml::table& t, std::string_view key, std::int64_t lo, std::int64_t hi,
                                    std::string_view path, bool open_above) {
  const toml::node* node = t.get(key);
  if (node == nullptr) return std::nullopt;
  auto v = node->value_exact<std::int64_t>();
  if (!v) throw TomlError{fmt::format("{}: '{}' must be an integer", where(path, *node), key)};
  if (open_above && *v < lo)
    throw TomlError{fmt::format("{}: '{}' = {} must be {} or more", where(path, *node), key, *v, lo)};
  if (*v < lo || *v > hi)
    throw TomlError{fmt::format("{}: '{}' = {} is out of range {}..{}", where(path, *node), key, *v, lo, hi)};
  return v;
}

std::variant<toml::table, TomlError> read_toml(std::string_view text, std::string_view path,
                                               std::string_view what_it_holds) {
  // Binary bytes (an .rxe or .rcx file, random data) would be told as
  // their first byte past ASCII: say what the file is instead. No text
  // file has a NUL, and an image or program has one early.
  if (text.substr(0, 4096).find('\0') != std::string_view::npos)
    return TomlError{fmt::format("{}: holds binary data, not a scenario ({})", path, what_it_holds)};
  if (auto trap = toml_trap(text))
    return TomlError{fmt::format("{}:{}: {} ({})", path, trap->line, trap->what, what_it_holds)};
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    return TomlError{fmt::format("{}:{}: {}", path, e.source().begin.line, e.description())};
  }
}

}  // namespace rcxc::toml_read
