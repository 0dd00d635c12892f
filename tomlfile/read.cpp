#include "tomlfile/read.h"

#include "tomlfile/longest_run.h"

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
  std::size_t at = row.size() > 1 && row[1] == '[' ? 2 : 1;  // "[[" is one token, "[ [" is not
  at = row.find_first_not_of(" \t", at);
  if (at == std::string_view::npos) return true;
  return !bare_key_character(row[at]) && row[at] != '"' && row[at] != '\'';
}

bool past_ascii(char c) { return static_cast<unsigned char>(c) > 0x7f; }

struct StringEnd {
  std::size_t last = 0;  // the closing quote's last character, or where toml++ gives up on the string
  bool closed = false;
};

// The end of the string that opens at `at` (a quote). Basic strings take
// backslash escapes, literal ones none; a triple quote runs over lines and
// its closing quote may have one or two more quotes before it (`"""a""""`
// holds `a"`). `line` counts the lines the string runs over.
StringEnd string_end(std::string_view text, std::size_t at, int& line) {
  const char quote = text[at];
  const bool triple = text.substr(at, 3) == std::string(3, quote);
  for (std::size_t i = at + (triple ? 3 : 1); i < text.size(); ++i) {
    if (quote == '"' && text[i] == '\\') {
      if (i + 1 < text.size() && text[i + 1] == '\n') {
        if (!triple) return {i, false};  // toml++ says what is wrong
        ++line;  // a line-ending backslash
      }
      ++i;
      continue;
    }
    if (text[i] == '\n') {
      if (!triple) return {i, false};
      ++line;
    }
    if (!triple && text[i] == quote) return {i, true};
    if (triple && text.substr(i, 3) == std::string(3, quote)) {
      std::size_t run = std::min(text.find_first_not_of(quote, i), text.size()) - i;
      return {i + std::min<std::size_t>(run, 5) - 1, true};
    }
  }
  return {text.size(), false};
}

// What in a TOML file of keys and numbers would reach a fault of toml++
// 3.3, which the fuzzer found, refused before the parser sees it:
// - it classifies some letters (U+0441, U+0411) as whitespace or not
//   through __builtin_unreachable (undefined behaviour): any letter past
//   ASCII outside a comment, strings included;
// - it asserts on a table header whose key starts with another character
//   than a letter, digit, '_', '-' or a quote ("[+", "[[/"): an abort in
//   Debug builds. A header is a '[' first on its line outside strings and
//   the brackets of values, where toml++ reads one; a line of a multi-line
//   string or an array's element on a line of its own is none;
// - it assumes no '}' where an array expects a value ("x = [}", "[1, }",
//   with blanks, line ends or comments between: TOML_ASSERT_ASSUME in
//   parse_value). No TOML text has a '}' right after a '[' or a ','
//   outside strings.
// Where the text is not TOML before any of these (a string that does not
// end), toml++ stops there with its own message.
std::optional<TomlTrap> toml_trap(std::string_view text) {
  int line = 1;
  int depth = 0;            // the '[' and '{' of values open here
  bool line_start = true;   // only blanks so far on this line
  bool in_header = false;   // on a table header's line: its brackets are not a value's
  char last = 0;            // the last character outside blanks, comments and strings
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      line_start = true;
      in_header = false;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r') continue;
    if (c == '#') {
      i = std::min(text.find('\n', i), text.size()) - 1;
      continue;
    }
    const bool first_on_line = line_start;
    line_start = false;
    if (past_ascii(c)) return TomlTrap{line, "a letter that is not ASCII outside a comment"};
    if (c == '"' || c == '\'') {
      int string_line = line;
      StringEnd end = string_end(text, i, line);
      std::string_view body = text.substr(i, std::min(end.last, text.size() - 1) - i + 1);
      if (auto bad = std::find_if(body.begin(), body.end(), past_ascii); bad != body.end())
        return TomlTrap{string_line + static_cast<int>(std::count(body.begin(), bad, '\n')),
                        "a letter that is not ASCII outside a comment"};
      if (!end.closed) return std::nullopt;
      i = end.last;
      last = c;
      continue;
    }
    if (c == '[' && depth == 0 && first_on_line) {
      std::string_view header = text.substr(i, std::min(text.find('\n', i), text.size()) - i);
      if (header_with_a_bad_key(header)) return TomlTrap{line, "a table header without a name"};
      in_header = true;
    } else if (!in_header) {  // a header's own brackets open and close no value
      if (c == '}' && (last == '[' || last == ',')) return TomlTrap{line, "a '}' where an array expects a value"};
      if (c == '[' || c == '{') ++depth;
      if ((c == ']' || c == '}') && depth > 0) --depth;
    }
    last = c;
  }
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

std::optional<std::int64_t> at_ms_key(const toml::table& t, std::string_view path) {
  auto at = int_key(t, "at_ms", 0, INT64_MAX, path, true);
  if (at && *at > kLongestRunMs)
    throw TomlError{fmt::format("{}: 'at_ms' = {} is later than the longest run ({} ms, about 35 years)",
                                where(path, *t.get("at_ms")), *at, kLongestRunMs)};
  return at;
}

std::variant<toml::table, TomlError> read_toml(std::string_view text, std::string_view path,
                                               std::string_view what_it_holds) {
  // A byte-order mark, which Windows editors put first, was refused as "a
  // letter that is not ASCII outside a comment" on a line that shows none.
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
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
