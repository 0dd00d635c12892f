#include "verify/junit.h"

#include <fmt/format.h>

#include <cstdint>
#include <string_view>

namespace rcx::semtest {
namespace {

// The code point of the UTF-8 sequence at text[i], and its length; length
// 0 when the bytes are not one (truncated, overlong, a surrogate).
struct Decoded {
  std::uint32_t code = 0;
  std::size_t length = 0;
};

Decoded decode_utf8(std::string_view text, std::size_t i) {
  auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  unsigned char lead = byte(i);
  if (lead < 0x80) return {lead, 1};
  std::size_t length = (lead >> 5) == 0x6 ? 2 : (lead >> 4) == 0xE ? 3 : (lead >> 3) == 0x1E ? 4 : 0;
  if (length == 0 || i + length > text.size()) return {};
  std::uint32_t code = lead & (0x7F >> length);
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return {};
    code = (code << 6) | (byte(i + k) & 0x3F);
  }
  static constexpr std::uint32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < kSmallest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return {};
  return {code, length};
}

// XML 1.0 allows tab, newline, carriage return and code points from space
// up, less the surrogates and U+FFFE, U+FFFF.
bool xml_char(std::uint32_t c) {
  return c == 0x9 || c == 0xA || c == 0xD || (c >= 0x20 && c <= 0xD7FF) || (c >= 0xE000 && c <= 0xFFFD) ||
         c >= 0x10000;
}

// Text for an attribute or an element: markup escaped, anything XML cannot
// carry shown as U+FFFD (a file name's stray byte must not make the whole
// report unreadable).
std::string escaped(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    Decoded d = decode_utf8(text, i);
    if (d.length == 0 || !xml_char(d.code)) {
      out += "\xEF\xBF\xBD";
      i += d.length == 0 ? 1 : d.length;
      continue;
    }
    switch (d.code) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      case '\n': out += "&#10;"; break;  // kept as a newline inside attributes too
      case '\r': out += "&#13;"; break;
      case '\t': out += "&#9;"; break;
      default: out.append(text.substr(i, d.length));
    }
    i += d.length;
  }
  return out;
}

// "FILE:LINE: message" for a failure that names a line, as `rcxc test`
// prints it.
std::string located(const std::string& file, const Failure& f) {
  return f.line > 0 ? fmt::format("{}:{}: {}", file, f.line, f.message) : fmt::format("{}: {}", file, f.message);
}

}  // namespace

std::string junit_xml(const std::vector<JUnitCase>& cases) {
  std::size_t failures = 0, errors = 0;
  double seconds = 0;
  for (const auto& c : cases) {
    errors += !c.error.empty();
    failures += c.error.empty() && !c.failures.empty();
    seconds += c.seconds;
  }
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += fmt::format("<testsuites name=\"rcxc test\" tests=\"{}\" failures=\"{}\" errors=\"{}\" time=\"{:.3f}\">\n",
                     cases.size(), failures, errors, seconds);
  out += fmt::format("  <testsuite name=\"rcxc test\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"0\" "
                     "time=\"{:.3f}\">\n",
                     cases.size(), failures, errors, seconds);
  for (const auto& c : cases) {
    std::string name = escaped(c.file);
    out += fmt::format("    <testcase name=\"{}\" classname=\"rcxc test\" file=\"{}\" time=\"{:.3f}\"", name, name,
                       c.seconds);
    if (c.error.empty() && c.failures.empty()) {
      out += "/>\n";
      continue;
    }
    out += ">\n";
    if (!c.error.empty()) {
      out += fmt::format("      <error message=\"{}\"/>\n", escaped(c.error));
    } else {
      std::string all;
      for (const auto& f : c.failures) all += located(c.file, f) + "\n";
      out += fmt::format("      <failure message=\"{}\">{}</failure>\n", escaped(c.failures.front().message),
                         escaped(all));
    }
    out += "    </testcase>\n";
  }
  out += "  </testsuite>\n</testsuites>\n";
  return out;
}

}  // namespace rcx::semtest
