#include "rcx/image.h"

#include <fmt/format.h>

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
    if (type > 2) return fail(at, fmt::format("symbol {}: unknown type {}", i + 1, type));
    s.type = static_cast<SymbolType>(type);
    s.index = r.u8();
    std::uint8_t length = r.u8();
    r.u8();  // reserved
    if (length == 0) return fail(at + 2, fmt::format("symbol {}: empty name", i + 1));
    if (!r.has(length)) return fail(r.pos(), fmt::format("symbol {}: name runs past the end of the file", i + 1));
    auto name = r.take(length);
    if (name[length - 1] != 0) return fail(r.pos() - 1, fmt::format("symbol {}: name is not NUL-terminated", i + 1));
    s.name.assign(name.begin(), name.end() - 1);
    int limit = s.type == SymbolType::Task ? kMaxTasks : s.type == SymbolType::Subroutine ? kMaxSubroutines : kMaxVariables;
    if (s.index >= limit) return fail(at + 1, fmt::format("symbol '{}': index {} out of range", s.name, s.index));
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
    u8(static_cast<int>(s.type));
    u8(s.index);
    u8(static_cast<int>(s.name.size() + 1));
    u8(0);
    for (char c : s.name) u8(c);
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
