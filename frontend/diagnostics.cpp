#include "frontend/diagnostics.h"

#include <algorithm>
#include <array>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rcx/printable_text.h"

namespace rcxc {

std::string with_lone_crs_as_lf(std::string text) {
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n')) text[i] = '\n';
  return text;
}

std::uint32_t SourceManager::add(std::string path, std::string text) {
  // A UTF-8 byte-order mark (Windows editors write one) is not program text;
  // dropping it also keeps columns as editors count them.
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
  // Classic Mac OS editors ended lines with a lone CR.
  File f{std::move(path), with_lone_crs_as_lf(std::move(text)), {0}, {}};
  for (std::size_t i = 0; i < f.text.size(); ++i)
    if (f.text[i] == '\n') f.line_starts.push_back(i + 1);
  files_.push_back(std::move(f));
  return static_cast<std::uint32_t>(files_.size() - 1);
}

std::string_view SourceManager::line(std::uint32_t file, std::uint32_t line) const {
  if (file >= files_.size() || line == 0) return {};
  const File& f = files_[file];
  if (line > f.line_starts.size()) return {};
  std::size_t begin = f.line_starts[line - 1];
  if (begin > f.text.size()) return {};
  std::size_t end = f.text.find('\n', begin);
  if (end == std::string::npos) end = f.text.size();
  std::string_view sv(f.text.data() + begin, end - begin);
  if (!sv.empty() && sv.back() == '\r') sv.remove_suffix(1);
  return sv;
}

std::uint32_t SourceManager::add_expansion(MacroExpansion e) {
  expansions_.push_back(std::move(e));
  return static_cast<std::uint32_t>(expansions_.size());
}

std::vector<Note> SourceManager::empty_expansion_notes(const SourceSpan& span) const {
  std::vector<Note> notes;
  const SourceLoc& b = span.begin;
  // One line at most: an error that spans a whole body would list every
  // empty macro in it (a `#define LOG(x)` called throughout).
  if (!b.valid() || b.expansion != 0 || span.end.expansion != 0 || span.end.file != b.file ||
      span.end.line != b.line)
    return notes;
  for (const MacroExpansion& e : expansions_) {
    const SourceLoc& at = e.site.begin;
    if (e.empty && at.file == b.file && at.expansion == 0 && !before(at, b) && before(at, span.end))
      notes.push_back({e.site, "macro '" + e.macro + "' expands to nothing"});
  }
  return notes;
}

std::vector<Note> SourceManager::expansion_notes(const SourceLoc& loc) const {
  std::vector<Note> notes;
  std::uint32_t id = loc.expansion;
  // Chains are finite (each expansion's site was created before it), but a
  // bound keeps a corrupted table from looping.
  for (std::size_t guard = 0; id != 0 && id <= expansions_.size() && guard < 256; ++guard) {
    const MacroExpansion& e = expansions_[id - 1];
    notes.push_back({e.site, "in expansion of macro '" + e.macro + "'"});
    if (e.site.begin.expansion >= id) break;
    id = e.site.begin.expansion;
  }
  return notes;
}

void SourceManager::mark_library(std::uint32_t file) {
  if (file < files_.size()) files_[file].library = true;
}

void SourceManager::set_include_site(std::uint32_t file, SourceSpan site) {
  if (file < files_.size()) files_[file].included_from = site;
}

std::vector<Note> SourceManager::include_notes(const SourceLoc& loc) const {
  std::vector<Note> notes;
  std::uint32_t file = loc.file;
  // Include nesting is bounded by the preprocessor; the guard is for safety.
  for (std::size_t guard = 0; file < files_.size() && guard < 256; ++guard) {
    const SourceSpan& site = files_[file].included_from;
    if (!site.begin.valid()) break;
    notes.push_back({site, "'" + files_[file].path + "' was included from here"});
    file = site.begin.file;
  }
  return notes;
}

std::string_view severity_name(Severity s) {
  switch (s) {
    case Severity::Note: return "note";
    case Severity::Warning: return "warning";
    case Severity::Error: return "error";
  }
  return "error";
}

Diagnostic& Diagnostics::error(SourceSpan span, std::string message) {
  list_.push_back({Severity::Error, span, std::move(message), {}, false, {}, {}});
  return list_.back();
}

// One place applies the policy: add(), which a trial's warnings pass too.
Diagnostic& Diagnostics::warning(SourceSpan span, WarningKind kind, std::string message) {
  const std::size_t before = list_.size();
  add({Severity::Warning, span, std::move(message), {}, false, {}, kind});
  if (list_.size() == before) {
    discarded_ = {};
    return discarded_;
  }
  return list_.back();
}

void Diagnostics::add(Diagnostic d) {
  if (d.severity == Severity::Warning && d.warning) {
    if (!policy.gives(*d.warning)) return;
    if (policy.as_error_for(*d.warning)) d.severity = Severity::Error;
  }
  list_.push_back(std::move(d));
}

std::size_t Diagnostics::error_count() const {
  return static_cast<std::size_t>(std::count_if(list_.begin(), list_.end(),
                                                [](const Diagnostic& d) { return d.severity == Severity::Error; }));
}

namespace {

std::string file_name(const SourceManager& sm, const SourceLoc& loc) {
  return loc.file < sm.size() ? sm.path(loc.file) : std::string("<unknown>");
}

// The file a message without a position is about: editors' matchers need
// a file name at the start of the line.
std::string unplaced_file(const Diagnostic& d, const SourceManager& sm) {
  if (!d.file.empty()) return d.file;
  if (d.severity == Severity::Note) return "";  // about the run, not a file ("N more errors not shown")
  return sm.size() != 0 ? sm.path(0) : std::string();
}

// ANSI colours as gcc uses them: the place and message bold, the severity
// in its colour, the caret green.
struct Palette {
  bool on = false;
  std::string paint(std::string_view code, std::string_view text) const {
    return on ? fmt::format("\x1b[{}m{}\x1b[0m", code, text) : std::string(text);
  }
  std::string severity(Severity s) const {
    std::string_view code = s == Severity::Error ? "1;31" : s == Severity::Warning ? "1;35" : "1;36";
    return paint(code, fmt::format("{}:", severity_name(s)));
  }
};

void render_one(std::string& out, Severity sev, const SourceSpan& span, const std::string& raw_message,
                const SourceManager& sm, const Palette& palette, const std::string& unplaced = "") {
  // A message may quote the file (#error's text, an #include name): its
  // control bytes are shown as \xNN, as the quoted line shows them as '?'.
  const std::string message = rcx::printable_text(raw_message);
  const SourceLoc& b = span.begin;
  if (!b.valid()) {
    out += fmt::format("{} {} {}\n", palette.paint("1", (unplaced.empty() ? std::string("rcxc") : unplaced) + ":"),
                       palette.severity(sev), palette.paint("1", message));
    return;
  }
  out += fmt::format("{} {} {}\n", palette.paint("1", fmt::format("{}:{}:{}:", file_name(sm, b), b.line, b.column)),
                     palette.severity(sev), palette.paint("1", message));
  std::string_view text = sm.line(b.file, b.line);
  if (text.empty() && b.column <= 1) return;
  std::size_t width = 1;
  if (span.end.file == b.file && span.end.line == b.line && span.end.column > b.column)
    width = span.end.column - b.column;
  QuotedLine quoted = quote_line(text, b.column == 0 ? 0 : b.column - 1, width);
  out += fmt::format("  {}\n  {}", quoted.text, quoted.lead_in);
  out += palette.paint("1;32", "^" + std::string(quoted.width - 1, '~'));
  out += '\n';
}

nlohmann::json location_json(const SourceSpan& span, const SourceManager& sm) {
  nlohmann::json j;
  j["file"] = span.begin.valid() ? file_name(sm, span.begin) : "";
  j["line"] = span.begin.line;
  j["column"] = span.begin.column;
  j["end"] = {{"line", span.end.line}, {"column", span.end.column}};
  return j;
}

// The notes to print: first the macro expansions and #includes that led to
// the main location, then the diagnostic's own notes, each followed by the
// expansions that led to it.
std::vector<Note> all_notes(const Diagnostic& d, const SourceManager& sm) {
  std::vector<Note> notes = sm.expansion_notes(d.span.begin);
  SourceLoc outer = notes.empty() ? d.span.begin : notes.back().span.begin;
  auto included = sm.include_notes(outer);
  notes.insert(notes.end(), included.begin(), included.end());
  for (const auto& n : d.notes) {
    notes.push_back(n);
    auto more = sm.expansion_notes(n.span.begin);
    notes.insert(notes.end(), more.begin(), more.end());
  }
  if (d.severity == Severity::Error) {
    auto empty = sm.empty_expansion_notes(d.span);
    notes.insert(notes.end(), empty.begin(), empty.end());
  }
  return notes;
}

// Where a location stands in the reading order: the #include sites that led
// to it from the outermost file inwards, then the place itself.
std::vector<std::array<std::uint32_t, 3>> reading_key(const SourceLoc& loc, const SourceManager& sm) {
  auto expansions = sm.expansion_notes(loc);
  SourceLoc at = expansions.empty() ? loc : expansions.back().span.begin;
  std::vector<std::array<std::uint32_t, 3>> key;
  for (const Note& site : sm.include_notes(at))
    key.push_back({site.span.begin.file, site.span.begin.line, site.span.begin.column});
  std::reverse(key.begin(), key.end());
  key.push_back({at.file, at.line, at.column});
  return key;
}

// A span that starts in a macro's text and ends in the user's, or the other
// way round (`f(BASE + site)`, the argument from BASE's `20` in the #define
// to `site`), as the user wrote it: each end that lies in an expansion
// moves to the same end of the macro's outermost use, so the caret
// underlines `BASE + site` in the call. Shown at its begin alone, the
// message "must be a constant expression" stood under the #define's `20`,
// a constant (faithfulness round 17). A span within one expansion stays
// in the macro's text, with its "in expansion of" notes.
SourceSpan as_written(const SourceSpan& s, const SourceManager& sm) {
  if (!s.begin.valid() || !s.end.valid() || s.begin.expansion == s.end.expansion) return s;
  auto outermost_use = [&](const SourceLoc& loc) -> std::optional<SourceSpan> {
    auto uses = sm.expansion_notes(loc);
    if (uses.empty()) return std::nullopt;
    return uses.back().span;
  };
  SourceSpan out = s;
  if (auto use = outermost_use(s.begin)) out.begin = use->begin;
  if (auto use = outermost_use(s.end)) out.end = use->end;
  // Both ends now lie in the user's text; in different files (a macro
  // defined in one file and used in another never spans both) keep the
  // span as it was rather than underline across files.
  if (out.begin.file != out.end.file || out.begin.expansion != out.end.expansion) return s;
  return out;
}

}  // namespace

Diagnostic as_reported(const Diagnostic& given, const SourceManager& sm) {
  Diagnostic d = given;
  d.span = as_written(given.span, sm);
  for (auto& n : d.notes) n.span = as_written(n.span, sm);
  const SourceLoc& at = d.span.begin;
  if (!at.valid() || at.expansion == 0 || !sm.is_library(at.file)) return d;
  for (const Note& use : sm.expansion_notes(at)) {
    if (sm.is_library(use.span.begin.file)) continue;
    Diagnostic moved = d;
    moved.span = use.span;
    // The library line, without the expansion chain that leads back here.
    SourceSpan library = d.span;
    library.begin.expansion = library.end.expansion = 0;
    moved.notes.insert(moved.notes.begin(),
                       Note{library, fmt::format("in macro '{}' of the standard library {}",
                                                 sm.expansion(at.expansion).macro, sm.path(at.file))});
    return moved;
  }
  return d;
}

std::vector<const Diagnostic*> in_source_order(const Diagnostics& diags, const SourceManager& sm) {
  struct Keyed {
    const Diagnostic* d;
    std::vector<std::array<std::uint32_t, 3>> key;  // empty: no position
  };
  std::vector<Keyed> keyed;
  for (const auto& d : diags.all())
    keyed.push_back({&d, d.span.begin.valid() ? reading_key(as_reported(d, sm).span.begin, sm) : decltype(Keyed::key){}});
  std::stable_sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    if (a.key.empty() || b.key.empty()) return !a.key.empty() && b.key.empty();
    return a.key < b.key;
  });
  std::vector<const Diagnostic*> ordered;
  for (const auto& k : keyed) ordered.push_back(k.d);
  return ordered;
}

std::string warning_option_tag(const Diagnostic& d) {
  if (!d.warning) return "";
  return fmt::format(" [-W{}{}]", d.severity == Severity::Error ? "error=" : "", warning_name(*d.warning));
}

std::string render_text(const Diagnostic& shown, const SourceManager& sm, bool color) {
  const Diagnostic d = as_reported(shown, sm);
  std::string out;
  Palette palette{color};
  render_one(out, d.severity, d.span, d.message + warning_option_tag(d), sm, palette, unplaced_file(d, sm));
  for (const auto& n : all_notes(d, sm)) render_one(out, Severity::Note, n.span, n.message, sm, palette);
  return out;
}

std::string render_json(const Diagnostic& shown, const SourceManager& sm) {
  const Diagnostic d = as_reported(shown, sm);
  nlohmann::json j = location_json(d.span, sm);
  if (!d.span.begin.valid()) j["file"] = unplaced_file(d, sm);
  j["severity"] = severity_name(d.severity);
  j["message"] = d.message;
  if (d.warning) j["code"] = warning_name(*d.warning);
  j["notes"] = nlohmann::json::array();
  for (const auto& n : all_notes(d, sm)) {
    nlohmann::json nj = location_json(n.span, sm);
    nj["message"] = n.message;
    j["notes"].push_back(std::move(nj));
  }
  // Source text need not be UTF-8; bad bytes become U+FFFD instead of
  // making the dump throw.
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

namespace {

constexpr std::size_t kQuotedLineBytes = 160;

bool continues_a_character(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

// The terminal cells a character takes: two for the wide characters of
// East Asian scripts, none for a combining mark or a zero-width one, else
// one (also a byte that is no UTF-8, which the terminal shows as one mark).
std::size_t cells(char32_t u) {
  struct Range {
    char32_t first, last;
  };
  static constexpr Range kWide[] = {
      {0x1100, 0x115F}, {0x2E80, 0x303E}, {0x3041, 0x33FF}, {0x3400, 0x4DBF}, {0x4E00, 0x9FFF},
      {0xA000, 0xA4CF}, {0xAC00, 0xD7A3}, {0xF900, 0xFAFF}, {0xFE30, 0xFE4F}, {0xFF00, 0xFF60},
      {0xFFE0, 0xFFE6}, {0x1F300, 0x1F64F}, {0x1F900, 0x1F9FF}, {0x20000, 0x3FFFD},
  };
  if ((u >= 0x0300 && u <= 0x036F) || (u >= 0x200B && u <= 0x200F) || u == 0xFEFF) return 0;
  for (const Range& r : kWide)
    if (u >= r.first && u <= r.last) return 2;
  return 1;
}

// The cells bytes [from, to) of `line` take, a tab counted as one (the
// caller keeps tabs as they are).
std::size_t cells_of(std::string_view line, std::size_t from, std::size_t to) {
  std::size_t n = 0;
  for (std::size_t i = from; i < to && i < line.size();) {
    Utf8Char ch = decode_utf8(line.substr(i));
    if (ch.length == 0) {
      ++i;
      if (!continues_a_character(line[i - 1])) ++n;
      continue;
    }
    n += cells(ch.code);
    i += ch.length;
  }
  return n;
}

}  // namespace

Utf8Char decode_utf8(std::string_view text) {
  if (text.empty()) return {};
  auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  unsigned char lead = byte(0);
  if (lead < 0x80) return {lead, 1};
  std::size_t length = lead >= 0xC2 && lead <= 0xDF ? 2 : lead >= 0xE0 && lead <= 0xEF ? 3 : lead >= 0xF0 && lead <= 0xF4 ? 4 : 0;
  if (length == 0 || text.size() < length) return {};
  char32_t code = lead & (length == 2 ? 0x1F : length == 3 ? 0x0F : 0x07);
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xC0) != 0x80) return {};
    code = (code << 6) | (byte(i) & 0x3F);
  }
  // Overlong forms, surrogates and past U+10FFFF are no characters.
  if ((length == 3 && code < 0x800) || (length == 4 && (code < 0x10000 || code > 0x10FFFF)) ||
      (code >= 0xD800 && code <= 0xDFFF))
    return {};
  return {code, length};
}

QuotedLine quote_line(std::string_view line, std::size_t column0, std::size_t width) {
  std::size_t begin = 0, end = line.size();
  if (line.size() > kQuotedLineBytes) {
    begin = std::min(column0 > kQuotedLineBytes / 2 ? column0 - kQuotedLineBytes / 2 : 0, line.size() - kQuotedLineBytes);
    end = begin + kQuotedLineBytes;
    while (begin > 0 && continues_a_character(line[begin])) --begin;
    while (end < line.size() && continues_a_character(line[end])) ++end;
  }
  std::string_view shown = line.substr(begin, end - begin);
  QuotedLine q;
  // A control character would reach the terminal as itself (ESC starts a
  // sequence that can retitle the window or move the cursor); a '?' in its
  // place keeps the caret under the right column, and the message names it.
  std::string printable(shown);
  for (char& c : printable)
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f) c = '?';
  q.text = fmt::format("{}{}{}", begin > 0 ? "..." : "", printable, end < line.size() ? "..." : "");
  if (begin > 0) q.lead_in = "   ";
  // Columns count bytes, the terminal characters: the caret goes under the
  // character at the column, and as wide as what the span covers, past a
  // line that holds 'ö' or '→'.
  std::size_t col = column0 - std::min(column0, begin);
  for (std::size_t i = 0; i < col && i < shown.size(); ++i) {
    if (shown[i] == '\t') q.lead_in += '\t';
    else q.lead_in += std::string(cells_of(shown, i, i + 1), ' ');
  }
  if (col < shown.size()) q.width = std::max<std::size_t>(1, cells_of(shown, col, col + std::min(width, shown.size() - col)));
  return q;
}

std::string render_all(const Diagnostics& diags, const SourceManager& sm, const RenderOptions& options) {
  auto render = [&](const Diagnostic& d) { return options.json ? render_json(d, sm) + "\n" : render_text(d, sm, options.color); };
  std::string out;
  std::size_t errors = 0;
  for (const Diagnostic* in_order : in_source_order(diags, sm)) {
    const Diagnostic& d = *in_order;
    if (d.severity == Severity::Error && options.max_errors != 0 && errors == options.max_errors) {
      Diagnostic rest{Severity::Note, {}, fmt::format("{} more errors not shown (--max-errors=0 shows every error)",
                                                       diags.error_count() - errors), {}, false, {}, {}};
      return out + render(rest);
    }
    if (d.severity == Severity::Error) ++errors;
    out += render(d);
  }
  return out;
}

}  // namespace rcxc
