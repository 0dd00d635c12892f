// The .rcx image: the file `nqc -O` writes and rcxc reads and writes
// (layout in shared/spec/formats.md). A plain value type plus a reader that
// refuses anything it cannot trust and a writer that produces the exact bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace rcx {

enum class FragmentType : std::uint8_t { Task = 0, Subroutine = 1 };
enum class SymbolType : std::uint8_t { Task = 0, Subroutine = 1, Variable = 2 };

inline constexpr int kMaxTasks = 10;
inline constexpr int kMaxSubroutines = 8;
inline constexpr int kMaxVariables = 32;
inline constexpr std::uint16_t kImageVersion = 0x0102;
// A symbol's length is one byte and counts the NUL after the name.
inline constexpr std::size_t kMaxSymbolName = 254;

struct Fragment {
  FragmentType type = FragmentType::Task;
  std::uint8_t index = 0;
  std::vector<std::uint8_t> code;
};

struct Symbol {
  SymbolType type = SymbolType::Task;
  std::uint8_t index = 0;
  std::string name;
};

struct Image {
  std::vector<Fragment> fragments;
  std::vector<Symbol> symbols;
  std::uint8_t target = 0;  // 0 = RCX

  const Fragment* find(FragmentType type, int index) const;
  // The symbol name for a task/sub/variable, or "" when the image has none.
  std::string name_of(SymbolType type, int index) const;
};

// A symbol name from an image as it may go into text output: names are any
// bytes in the file, so control characters (escape sequences, newlines
// that would forge lines of a timeline) and backslashes become \xNN.
std::string printable_name(std::string_view name);

struct ImageError {
  std::string message;  // says what is wrong and at which byte offset
};

std::variant<Image, ImageError> read_image(std::span<const std::uint8_t> bytes);
// A symbol name longer than kMaxSymbolName is written cut to that length.
std::vector<std::uint8_t> write_image(const Image& image);
// Reads and parses an .rcx file; the error names the file.
std::variant<Image, ImageError> read_image_file(const std::string& path);

}  // namespace rcx
