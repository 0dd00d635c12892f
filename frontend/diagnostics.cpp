#include "frontend/diagnostics.h"

#include <algorithm>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace rcxc {

std::uint32_t SourceManager::add(std::string path, std::string text) {
  File f{std::move(path), std::move(text), {0}, {}};
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
  list_.push_back({Severity::Error, span, std::move(message), {}});
  return list_.back();
}

Diagnostic& Diagnostics::warning(SourceSpan span, std::string message) {
  if (suppress_warnings) {
    discarded_ = {};
    return discarded_;
  }
  list_.push_back({warnings_as_errors ? Severity::Error : Severity::Warning, span, std::move(message), {}});
  return list_.back();
}

void Diagnostics::add(Diagnostic d) {
  if (d.severity == Severity::Warning) {
    if (suppress_warnings) return;
    if (warnings_as_errors) d.severity = Severity::Error;
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

void render_one(std::string& out, Severity sev, const SourceSpan& span, const std::string& message,
                const SourceManager& sm) {
  const SourceLoc& b = span.begin;
  if (!b.valid()) {
    out += fmt::format("rcxc: {}: {}\n", severity_name(sev), message);
    return;
  }
  out += fmt::format("{}:{}:{}: {}: {}\n", file_name(sm, b), b.line, b.column, severity_name(sev), message);
  std::string_view text = sm.line(b.file, b.line);
  if (text.empty() && b.column <= 1) return;
  out += fmt::format("  {}\n  ", text);
  // Tabs are kept in the caret line so the caret lines up under the text.
  std::size_t col = b.column == 0 ? 0 : b.column - 1;
  for (std::size_t i = 0; i < col && i < text.size(); ++i) out += text[i] == '\t' ? '\t' : ' ';
  std::size_t width = 1;
  if (span.end.file == b.file && span.end.line == b.line && span.end.column > b.column)
    width = span.end.column - b.column;
  out += '^';
  if (width > 1) out += std::string(width - 1, '~');
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
  return notes;
}

}  // namespace

std::string render_text(const Diagnostic& d, const SourceManager& sm) {
  std::string out;
  render_one(out, d.severity, d.span, d.message, sm);
  for (const auto& n : all_notes(d, sm)) render_one(out, Severity::Note, n.span, n.message, sm);
  return out;
}

std::string render_json(const Diagnostic& d, const SourceManager& sm) {
  nlohmann::json j = location_json(d.span, sm);
  j["severity"] = severity_name(d.severity);
  j["message"] = d.message;
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

std::string render_all(const Diagnostics& diags, const SourceManager& sm, const RenderOptions& options) {
  auto render = [&](const Diagnostic& d) { return options.json ? render_json(d, sm) + "\n" : render_text(d, sm); };
  std::string out;
  std::size_t errors = 0;
  for (const auto& d : diags.all()) {
    if (d.severity == Severity::Error && options.max_errors != 0 && errors == options.max_errors) {
      Diagnostic rest{Severity::Note, {}, fmt::format("{} more errors not shown (--max-errors=0 shows every error)",
                                                       diags.error_count() - errors), {}};
      return out + render(rest);
    }
    if (d.severity == Severity::Error) ++errors;
    out += render(d);
  }
  return out;
}

}  // namespace rcxc
