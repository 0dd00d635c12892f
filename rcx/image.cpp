#include "rcx/image.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <utility>

#include "rcx/file_read.h"

namespace rcx {

const Fragment* Image::find(FragmentType type, int index) const {
  for (const auto& f : fragments)
    if (f.type == type && f.index == index) return &f;
  return nullptr;
}

std::string printable_name(std::string_view name) {
  std::string out;
  for (char ch : name) {
    auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f || c == '\\')
      out += fmt::format("\\x{:02x}", c);
    else
      out += ch;
  }
  return out;
}

std::string Image::name_of(SymbolType type, int index) const {
  for (const auto& s : symbols)
    if (s.type == type && s.index == index) return s.name;
  return {};
}

namespace {

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> b) : bytes_(b) {}
  bool has(std::size_t n) const { return bytes_.size() - pos_ >= n; }
  std::size_t pos() const { return pos_; }
  std::uint8_t u8() { return bytes_[pos_++]; }
  std::uint16_t u16() {
    std::uint16_t v = static_cast<std::uint16_t>(bytes_[pos_] | (bytes_[pos_ + 1] << 8));
    pos_ += 2;
    return v;
  }
  std::span<const std::uint8_t> take(std::size_t n) {
    auto s = bytes_.subspan(pos_, n);
    pos_ += n;
    return s;
  }
  std::size_t remaining() const { return bytes_.size() - pos_; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
};

ImageError fail(std::size_t at, std::string what) { return {fmt::format("offset {}: {}", at, what)}; }

constexpr const char* kSymbolTypeNames[] = {"task", "subroutine", "variable"};

// What is wrong with the name of symbol `number` whose length byte is
// `length` (the name and its NUL), and at which offset from the name's
// first byte, or nullopt when its `length` bytes end in its one NUL. The
// length is one byte, so a name has at most 254 bytes: a writer that puts
// a longer one in gets its length wrong (1000 bytes and the NUL are 1001,
// 233 in a byte), and where the name's NUL really is tells that apart from
// a name cut short or bytes that are no name at all.
std::optional<std::pair<std::size_t, std::string>> name_problem(std::span<const std::uint8_t> from, std::size_t length,
                                                                int number) {
  const std::size_t nul = std::find(from.begin(), from.end(), 0) - from.begin();  // from.size() when none
  const bool found = nul < from.size();
  if (found && nul + 1 == length) return std::nullopt;
  if (found && nul + 1 < length)
    return std::pair{nul, fmt::format("symbol {}: name holds a NUL after {} of the {} bytes its length gives (the "
                                      "length counts the name and the one NUL that ends it)", number, nul, length)};
  if (found && nul > kMaxSymbolName)
    return std::pair{std::size_t{0},
                     fmt::format("symbol {}: name of {} bytes, longer than an image can hold: its length is one byte "
                                 "counting the NUL too, so a name has at most {} bytes (this one's length byte says {})",
                                 number, nul, kMaxSymbolName, length)};
  if (from.size() < length)
    return std::pair{from.size(), fmt::format("symbol {}: name runs past the end of the file", number)};
  if (found)
    return std::pair{length - 1, fmt::format("symbol {}: name of {} bytes runs on past the {} its length byte gives "
                                             "(the length counts the name and its NUL)", number, nul, length - 1)};
  return std::pair{length - 1, fmt::format("symbol {}: name is not NUL-terminated (no NUL in its {} bytes or in the "
                                           "rest of the file)", number, length)};
}

}  // namespace

std::variant<Image, ImageError> read_image(std::span<const std::uint8_t> bytes) {
  Reader r(bytes);
  if (!r.has(12)) return fail(0, fmt::format("file too short for an RCX image header ({} bytes, need 12)", bytes.size()));
  auto sig = r.take(4);
  if (sig[0] != 'R' || sig[1] != 'C' || sig[2] != 'X' || sig[3] != 'I')
    return fail(0, "not an RCX image (signature is not \"RCXI\")");
  std::uint16_t version = r.u16();
  if (version != kImageVersion) return fail(4, fmt::format("unknown image version 0x{:04x} (expected 0x0102)", version));
  std::uint16_t fragment_count = r.u16();
  std::uint16_t symbol_count = r.u16();
  Image image;
  image.target = r.u8();
  if (image.target != 0) return fail(10, fmt::format("target type {} is not the RCX (0)", image.target));
  r.u8();  // reserved

  for (int i = 0; i < fragment_count; ++i) {
    std::size_t at = r.pos();
    if (!r.has(4)) return fail(at, fmt::format("fragment {} of {}: header runs past the end of the file", i + 1, fragment_count));
    Fragment f;
    std::uint8_t type = r.u8();
    if (type > 1) return fail(at, fmt::format("fragment {}: unknown type {} (0 = task, 1 = subroutine)", i + 1, type));
    f.type = static_cast<FragmentType>(type);
    f.index = r.u8();
    int limit = f.type == FragmentType::Task ? kMaxTasks : kMaxSubroutines;
    if (f.index >= limit)
      return fail(at + 1, fmt::format("{} index {} out of range 0..{}",
                                      f.type == FragmentType::Task ? "task" : "subroutine", f.index, limit - 1));
    if (image.find(f.type, f.index))
      return fail(at, fmt::format("duplicate {} {}", f.type == FragmentType::Task ? "task" : "subroutine", f.index));
    std::uint16_t length = r.u16();
    std::size_t padded = (length + 3u) & ~3u;
    if (!r.has(length))
      return fail(r.pos(), fmt::format("fragment {}: {} code bytes run past the end of the file", i + 1, length));
    auto code = r.take(length);
    f.code.assign(code.begin(), code.end());
    // nqc pads code to a multiple of 4; tolerate a missing pad only at the very end.
    std::size_t pad = padded - length;
    if (r.remaining() < pad) {
      if (i + 1 != fragment_count || symbol_count != 0)
        return fail(r.pos(), fmt::format("fragment {}: padding runs past the end of the file", i + 1));
      pad = r.remaining();
    }
    r.take(pad);
    image.fragments.push_back(std::move(f));
  }

  for (int i = 0; i < symbol_count; ++i) {
    std::size_t at = r.pos();
    if (!r.has(4)) return fail(at, fmt::format("symbol {} of {}: header runs past the end of the file", i + 1, symbol_count));
    Symbol s;
    std::uint8_t type = r.u8();
    if (type > 2)
      return fail(at, fmt::format("symbol {}: unknown type {} (0 = task, 1 = subroutine, 2 = variable)", i + 1, type));
    s.type = static_cast<SymbolType>(type);
    s.index = r.u8();
    std::uint8_t length = r.u8();
    r.u8();  // reserved
    if (length == 0)
      return fail(at + 2, fmt::format("symbol {}: name length 0, which leaves no room for the NUL that ends a name "
                                      "(the length counts it)", i + 1));
    std::size_t name_at = r.pos();
    if (auto why = name_problem(bytes.subspan(name_at), length, i + 1)) return fail(why->first + name_at, why->second);
    auto name = r.take(length);
    s.name.assign(name.begin(), name.end() - 1);
    int limit = s.type == SymbolType::Task ? kMaxTasks : s.type == SymbolType::Subroutine ? kMaxSubroutines : kMaxVariables;
    if (s.index >= limit)
      return fail(at + 1, fmt::format("symbol '{}': {} index {} out of range 0..{}", printable_name(s.name),
                                      kSymbolTypeNames[type], s.index, limit - 1));
    image.symbols.push_back(std::move(s));
  }
  if (r.remaining() != 0) return fail(r.pos(), fmt::format("{} unexpected bytes after the last symbol", r.remaining()));
  return image;
}

std::vector<std::uint8_t> write_image(const Image& image) {
  std::vector<std::uint8_t> out;
  out.reserve(64);
  auto u8 = [&](int v) { out.push_back(static_cast<std::uint8_t>(v)); };
  auto u16 = [&](int v) { u8(v & 0xff); u8((v >> 8) & 0xff); };
  for (char c : {'R', 'C', 'X', 'I'}) u8(c);
  u16(kImageVersion);
  u16(static_cast<int>(image.fragments.size()));
  u16(static_cast<int>(image.symbols.size()));
  u8(image.target);
  u8(0);
  for (const auto& f : image.fragments) {
    u8(static_cast<int>(f.type));
    u8(f.index);
    u16(static_cast<int>(f.code.size()));
    for (std::uint8_t b : f.code) u8(b);
    while (out.size() % 4 != 0) u8(0);
  }
  for (const auto& s : image.symbols) {
    // A name is cut to what its length byte can count: nqc writes a longer
    // one with its length taken mod 256 (301 bytes with the NUL as 45), an
    // image no reader can follow past it. The names only label listings.
    std::string_view name = std::string_view(s.name).substr(0, kMaxSymbolName);
    u8(static_cast<int>(s.type));
    u8(s.index);
    u8(static_cast<int>(name.size() + 1));
    u8(0);
    for (char c : name) u8(c);
    u8(0);
  }
  return out;
}

std::variant<Image, ImageError> read_image_file(const std::string& path) {
  auto file = read_file(path, kImageFile);
  if (const auto* problem = std::get_if<FileProblem>(&file)) {
    switch (*problem) {
      case FileProblem::Directory: return ImageError{fmt::format("{}: is a directory, not an .rcx image", path)};
      case FileProblem::CannotOpen: return ImageError{fmt::format("{}: cannot open file: {}", path, cannot_open_reason(path))};
      case FileProblem::ReadError: return ImageError{fmt::format("{}: read error", path)};
      case FileProblem::TooLarge: return ImageError{too_large_message(path, kImageFile)};
    }
  }
  const std::string& text = std::get<std::string>(file);
  std::vector<std::uint8_t> bytes(text.begin(), text.end());
  auto result = read_image(bytes);
  if (auto* e = std::get_if<ImageError>(&result)) e->message = fmt::format("{}: {}", path, e->message);
  return result;
}

}  // namespace rcx
