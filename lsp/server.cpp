#include "lsp/server.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <stdexcept>
#include <sstream>
#include <string_view>
#include <thread>
#include <variant>
#include <vector>

#include "format/format.h"
#include "frontend/parse.h"
#include "lsp/jsonrpc.h"
#include "lsp/line_diff.h"
#include "lsp/outline.h"
#include "savefile/savefile.h"
#include "stdlib/stdlib.h"

namespace rcxc::lsp {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// ------------------------------------------------------------ positions --
// LSP counts characters in UTF-16 code units from 0; the compiler counts
// bytes from 1.

std::uint32_t utf16_of_byte_column(std::string_view line, std::uint32_t column) {
  std::size_t bytes = column > 0 ? column - 1 : 0;
  std::uint32_t units = 0;
  for (std::size_t i = 0; i < bytes && i < line.size();) {
    std::size_t n = utf8_length(static_cast<unsigned char>(line[i]));
    units += n == 4 ? 2 : 1;
    i += n;
  }
  if (bytes > line.size()) units += static_cast<std::uint32_t>(bytes - line.size());
  return units;
}

std::uint32_t byte_column_of_utf16(std::string_view line, std::int64_t character) {
  std::size_t i = 0;
  std::int64_t units = 0;
  while (i < line.size() && units < character) {
    std::size_t n = utf8_length(static_cast<unsigned char>(line[i]));
    units += n == 4 ? 2 : 1;
    i += n;
  }
  return static_cast<std::uint32_t>(std::min(i, line.size())) + 1;
}

// The text of 1-based line `line` of `text`.
std::string_view line_of(std::string_view text, std::uint32_t line) {
  std::size_t start = 0;
  for (std::uint32_t l = 1; l < line; ++l) {
    auto nl = text.find('\n', start);
    if (nl == std::string_view::npos) return {};
    start = nl + 1;
  }
  auto end = text.find('\n', start);
  std::string_view s = text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start);
  if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
  return s;
}

json position(std::string_view line_text, std::uint32_t line, std::uint32_t column) {
  if (line == 0) return {{"line", 0}, {"character", 0}};
  return {{"line", line - 1}, {"character", utf16_of_byte_column(line_text, column)}};
}

// A place in one of the index's files, its column through the index's
// table of wide characters (a line read from its start for every place
// made 30,000 diagnostics on one line take 23 s).
json place_json(const Index& index, const Place& p) {
  if (p.line == 0) return {{"line", 0}, {"character", 0}};
  return {{"line", p.line - 1}, {"character", utf16_column(index, p)}};
}

json range_json(const Index& index, const Range& r) { return {{"start", place_json(index, r.begin)}, {"end", place_json(index, r.end)}}; }

// Parameters that are not what LSP says they are (answered Invalid params).
struct BadParams : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A request that is well formed but cannot be done, such as renaming a
// name of the RCX API (answered Request failed, with the reason).
struct Refused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The most bytes one didChange's ranged changes may move: the lines they
// touch, and the table of lines behind them when they add or remove lines
// (a string's worth per line). A thousand added lines in a 20,000-line
// document move 640 MB in all, a fraction of a second; a message that would
// move more is refused (its changes are dropped).
constexpr std::uint64_t kMaxChangeWork = std::uint64_t{4} << 30;

// A line, character or version: a JSON integer. get<std::int64_t>() would
// convert a float too, and 1e300 has no int64 value (undefined behaviour);
// integers past int64 are clamped, which every position check refuses.
std::int64_t integer_field(const json& object, const char* key) {
  const json& v = object.at(key);
  if (v.is_number_unsigned())
    return static_cast<std::int64_t>(std::min<std::uint64_t>(v.get<std::uint64_t>(), INT64_MAX));
  if (!v.is_number_integer()) throw BadParams(std::string("'") + key + "' must be an integer");
  return v.get<std::int64_t>();
}

// Line `line` (from 1) of the document, from the index's line table: the
// index holds the same text. line_of scans from the start, which made
// publishing 20,000 warnings take seconds.
std::string_view doc_line(const Document& doc, std::uint32_t line) { return doc.index.sm.line(doc.index.main_file, line); }

// A client position as a Place in the document (file main_file).
std::optional<Place> place_of(const Document& doc, const json& pos) {
  std::int64_t line = integer_field(pos, "line");
  std::int64_t character = integer_field(pos, "character");
  if (line < 0 || character < 0 || line > 10'000'000) return std::nullopt;
  auto l = static_cast<std::uint32_t>(line + 1);
  return Place{doc.index.main_file, l, byte_column_of_utf16(doc_line(doc, l), character)};
}

// The text after a didChange's changes, each a whole new text or a range
// (in UTF-16 units) replaced. The text is held as lines while they are
// applied, so a change costs the lines it touches, not the whole text:
// with incremental sync a keystroke is one such change, and a rename's
// hundreds of edits one message of them.
std::string apply_changes(const std::string& text, const json& changes) {
  auto split = [](std::string_view t) {
    std::vector<std::string> lines;
    for (std::size_t start = 0;;) {
      std::size_t nl = t.find('\n', start);
      lines.emplace_back(t.substr(start, nl == std::string_view::npos ? std::string_view::npos : nl - start));
      if (nl == std::string_view::npos) return lines;
      start = nl + 1;
    }
  };
  std::vector<std::string> lines = split(text);
  // A place as (line, byte); a line past the end is the end of the text.
  auto locate = [&lines](const json& pos) {
    std::int64_t line = std::max<std::int64_t>(0, integer_field(pos, "line"));
    std::int64_t character = integer_field(pos, "character");
    if (line >= static_cast<std::int64_t>(lines.size())) return std::pair{lines.size() - 1, lines.back().size()};
    std::string_view l = lines[static_cast<std::size_t>(line)];
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    return std::pair{static_cast<std::size_t>(line), std::size_t{byte_column_of_utf16(l, character)} - 1};
  };
  std::uint64_t work = 0;
  for (const auto& change : changes) {
    std::string inserted = change.at("text").get<std::string>();
    if (!change.contains("range")) {
      lines = split(inserted);
      continue;
    }
    auto a = locate(change["range"].at("start"));
    auto b = locate(change["range"].at("end"));
    if (b < a) std::swap(a, b);
    std::string joined = lines[a.first].substr(0, a.second) + inserted + lines[b.first].substr(b.second);
    std::vector<std::string> replacement = split(joined);
    const std::size_t old_n = b.first - a.first + 1, new_n = replacement.size();
    work += joined.size() + (old_n != new_n ? (lines.size() - b.first) * sizeof(std::string) : 0);
    if (work > kMaxChangeWork) throw BadParams("too many ranged changes in one didChange");
    const std::size_t common = std::min(old_n, new_n);
    for (std::size_t i = 0; i < common; ++i) lines[a.first + i] = std::move(replacement[i]);
    auto at = lines.begin() + static_cast<std::ptrdiff_t>(a.first + common);
    if (new_n > old_n)
      lines.insert(at, std::make_move_iterator(replacement.begin() + static_cast<std::ptrdiff_t>(common)),
                   std::make_move_iterator(replacement.end()));
    else if (old_n > new_n)
      lines.erase(at, at + static_cast<std::ptrdiff_t>(old_n - new_n));
  }
  std::string out;
  std::size_t size = lines.size();
  for (const auto& l : lines) size += l.size();
  out.reserve(size);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i > 0) out.push_back('\n');
    out += lines[i];
  }
  return out;
}

// ------------------------------------------------------------------ URIs --

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// ------------------------------------------------------- the stdlib copy --

// Where the copy may go, in order: --stdlib-dir alone when given, else the
// user's cache ($XDG_CACHE_HOME when absolute, as the XDG spec asks: a
// relative one made folders in whatever the editor's working folder was;
// else ~/.cache), then the temporary folder. One folder per library text,
// so an older rcxc's copy is never shown.
std::vector<fs::path> stdlib_folders(const Server& server, std::string_view text) {
  if (!server.stdlib_dir.empty()) return {fs::path(server.stdlib_dir)};
  const std::string leaf = "stdlib-" + std::to_string(std::hash<std::string_view>{}(text) % 1000000007u);
  std::vector<fs::path> out;
  const char* cache = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  if (cache && fs::path(cache).is_absolute()) out.push_back(fs::path(cache) / "rcxc" / leaf);
  if (home && fs::path(home).is_absolute()) out.push_back(fs::path(home) / ".cache" / "rcxc" / leaf);
  std::error_code ec;
  fs::path temp = fs::temp_directory_path(ec);
  if (!ec) out.push_back(temp / "rcxc" / leaf);
  return out;
}

std::string stdlib_copy(Server& server, const std::string& name) {
  auto text = stdlib::find(name);
  if (!text) return "";
  // A folder that cannot take the copy (XDG_CACHE_HOME=/dev/null, a
  // read-only home) left go to definition answering nothing; the next one
  // is tried.
  for (const fs::path& dir : stdlib_folders(server, *text)) {
    std::error_code ec;
    fs::path file = dir / name;
    // A copy is trusted only when it is the library byte for byte: one cut
    // short or changed is written again. The write goes to a temporary that
    // is then renamed, so a full disk or a crash mid-write leaves no part of
    // a copy for the editor, or the next server, to read.
    std::ifstream existing(file, std::ios::binary);
    std::stringstream ss;
    if (existing) ss << existing.rdbuf();
    if (!existing || ss.str() != *text) {
      fs::create_directories(dir, ec);
      if (savefile::write_file_atomically(file.string(), std::string(*text))) continue;
    }
    return fs::absolute(file, ec).string();
  }
  return "";
}

std::string file_uri(Server& server, const Document& doc, const std::string& uri, std::uint32_t file) {
  if (file == doc.index.main_file) return uri;
  if (on_command_line(doc.index, file)) return "";  // a -D option: no file to show
  const std::string& path = doc.index.sm.path(file);
  if (file < doc.index.is_stdlib.size() && doc.index.is_stdlib[file]) {
    std::string copy = stdlib_copy(server, path);
    return copy.empty() ? "" : path_to_uri(copy);
  }
  std::error_code ec;
  return path_to_uri(fs::absolute(path, ec).string());
}

json location(Server& server, const Document& doc, const std::string& uri, const Range& r) {
  std::string target = file_uri(server, doc, uri, r.begin.file);
  if (target.empty()) return nullptr;
  return {{"uri", target}, {"range", range_json(doc.index, r)}};
}

// ----------------------------------------------------------- diagnostics --

// The standard library file `name` as the index read it, if it did.
std::optional<std::uint32_t> stdlib_file(const Index& index, const std::string& name) {
  for (std::uint32_t f = 0; f < index.sm.size(); ++f)
    if (f < index.is_stdlib.size() && index.is_stdlib[f] && index.sm.path(f) == name) return f;
  return std::nullopt;
}

json diagnostic_json(Server& server, const Document& doc, const std::string& doc_uri, const DocDiagnostic& d) {
  const std::uint32_t main = doc.index.main_file;
  json j = {{"range",
             {{"start", place_json(doc.index, {main, d.line, d.column})},
              {"end", place_json(doc.index, {main, d.end_line, d.end_column})}}},
            {"severity", d.severity == Severity::Error ? 1 : d.severity == Severity::Warning ? 2 : 3},
            {"source", "rcxc"},
            {"message", d.message}};
  if (d.warning) j["code"] = warning_name(*d.warning);
  // Code that does nothing: editors grey it out (DiagnosticTag Unnecessary).
  if (d.warning == WarningKind::UnusedVariable || d.warning == WarningKind::UnreachableCode)
    j["tags"] = json::array({1});
  json related = json::array();
  for (const auto& r : d.related) {
    if (r.path.empty()) continue;
    std::string uri;
    std::string line_text;
    std::error_code ec;
    json range;
    if (fs::path(r.path).is_relative() && stdlib::find(r.path) && !fs::exists(fs::path(doc.path).parent_path() / r.path, ec)) {
      std::string copy = stdlib_copy(server, r.path);
      if (copy.empty()) continue;
      uri = path_to_uri(copy);
      auto file = stdlib_file(doc.index, r.path);
      line_text = std::string(file ? doc.index.sm.line(*file, r.line) : line_of(*stdlib::find(r.path), r.line));
    } else if (r.path == doc.path) {
      // The client's own name for the document: a URI rebuilt from the
      // path differs for untitled: documents and file://localhost/ URIs.
      uri = doc_uri;
      range = {{"start", place_json(doc.index, {main, r.line, r.column})},
               {"end", place_json(doc.index, {main, r.end_line, r.end_column})}};
    } else {
      uri = path_to_uri(fs::absolute(r.path, ec).string());
    }
    if (range.is_null())
      range = {{"start", position(line_text, r.line, r.column)}, {"end", position(line_text, r.end_line, r.end_column)}};
    related.push_back({{"location", {{"uri", uri}, {"range", range}}}, {"message", r.message}});
  }
  if (!related.empty()) j["relatedInformation"] = related;
  return j;
}

json publish(Server& server, const std::string& uri, const Document* doc) {
  json list = json::array();
  if (doc)
    for (const auto& d : doc->index.diagnostics) list.push_back(diagnostic_json(server, *doc, uri, d));
  json params = {{"uri", uri}, {"diagnostics", list}};
  if (doc) params["version"] = doc->version;
  return notification("textDocument/publishDiagnostics", params);
}

// As frontend::Options::unsaved names a file.
std::string normal_path(const std::string& path) {
  std::error_code ec;
  return fs::absolute(path, ec).lexically_normal().string();
}

// What compiling a document reads, copied, so that it can be compiled
// while the server goes on.
struct Snapshot {
  std::string path;
  std::string text;
  frontend::Options options;
  WarningPolicy warnings;
  // An #include of a file open in the editor reads the editor's text, as
  // typed, not the file as last saved.
  std::map<std::string, std::string> unsaved;
  std::uint64_t generation = 0;
  std::int64_t version = 0;
};

Snapshot snapshot_of(const Server& server, const Document& doc) {
  Snapshot s{doc.path, doc.text, server.options, server.warnings, {}, doc.generation, doc.version};
  for (const auto& [uri, other] : server.documents)
    if (&other != &doc) s.unsaved.emplace(normal_path(other.path), other.text);
  return s;
}

Index build(Snapshot& s) {
  s.options.unsaved = &s.unsaved;
  return build_index(s.path, s.text, s.options, s.warnings);
}

void reindex(const Server& server, Document& doc) {
  Snapshot s = snapshot_of(server, doc);
  doc.index = build(s);
  doc.index_generation = doc.generation;
  doc.stale = false;
}

bool includes(const Document& doc, const std::string& path) {
  for (std::uint32_t f = 0; f < doc.index.sm.size(); ++f)
    if (f != doc.index.main_file && normal_path(doc.index.sm.path(f)) == path) return true;
  return false;
}

// The document `d` at `uri` must be compiled again: now, its diagnostics
// added to `out`, or marked for later (defer_index).
void recompile(Server& server, const std::string& uri, Document& d, std::vector<json>& out) {
  d.generation = ++server.changes;
  if (server.defer_index) {
    d.stale = true;
  } else {
    reindex(server, d);
    out.push_back(publish(server, uri, &d));
  }
}

// The text of the document at `path` was set or dropped (`doc` is null when
// it was closed): it is compiled now, or marked for later (defer_index), and
// so is every open document that includes it.
std::vector<json> changed(Server& server, const std::string& uri, Document* doc, const std::string& path) {
  std::vector<json> out;
  auto redo = [&](const std::string& u, Document& d) { recompile(server, u, d, out); };
  if (doc)
    redo(uri, *doc);
  else
    out.push_back(publish(server, uri, nullptr));
  const std::string normal = normal_path(path);
  for (auto& [other_uri, other] : server.documents)
    if (&other != doc && includes(other, normal)) redo(other_uri, other);
  return out;
}

// --------------------------------------------------------------- requests --

int completion_kind(const Definition& d) {
  switch (d.kind) {
    case DefKind::Task: return 23;  // Event: it runs by itself
    case DefKind::Sub:
    case DefKind::Function: return 3;
    case DefKind::Global:
    case DefKind::Local:
    case DefKind::Param: return 6;
    case DefKind::Label: return 18;
    case DefKind::Macro: return d.signature.find(d.name + "(") != std::string::npos ? 3 : 21;
  }
  return 1;
}

int symbol_kind(const Definition& d) {
  switch (d.kind) {
    case DefKind::Task: return 24;  // Event
    case DefKind::Sub: return 6;    // Method
    case DefKind::Function: return 12;
    case DefKind::Macro: return 14;  // Constant
    default: return 13;              // Variable
  }
}

std::string hover_text(const Index& index, const Definition& d) {
  std::string text = "```nqc\n" + d.signature + "\n```";
  std::string where = std::string(def_kind_name(d.kind));
  if (in_stdlib(index, d.at.begin.file)) where += " of the RCX API (rcx.nqh)";
  if (on_command_line(index, d.at.begin.file)) where += " defined on the command line";
  text += "\n" + where;
  if (!d.doc.empty()) text += "\n\n" + d.doc;
  return text;
}

struct Request {
  Server& server;
  const json& params;
  std::string uri;
  Document* doc = nullptr;
};

const Definition* definition_at(const Request& r, const Place& at, const Occurrence** occ_out = nullptr) {
  const Occurrence* occ = occurrence_at(r.doc->index, at.file, at.line, at.column);
  if (occ_out) *occ_out = occ;
  return occ ? resolve(r.doc->index, occ->name, occ->at.begin) : nullptr;
}

json hover(Request& r) {
  auto at = place_of(*r.doc, r.params.at("position"));
  if (!at) return nullptr;
  const Occurrence* occ = nullptr;
  const Definition* def = definition_at(r, *at, &occ);
  if (!def) return nullptr;
  return {{"contents", {{"kind", "markdown"}, {"value", hover_text(r.doc->index, *def)}}},
          {"range", range_json(r.doc->index, occ->at)}};
}

json completion(Request& r) {
  auto at = place_of(*r.doc, r.params.at("position"));
  if (!at) return nullptr;
  json items = json::array();
  for (const Definition* d : visible_at(r.doc->index, *at)) {
    if (d->kind == DefKind::Label) continue;
    json item = {{"label", d->name}, {"kind", completion_kind(*d)}, {"detail", d->signature}};
    if (!d->doc.empty()) item["documentation"] = {{"kind", "markdown"}, {"value", d->doc}};
    items.push_back(item);
  }
  for (std::string_view k : frontend::keywords())
    if (!k.starts_with("__")) items.push_back({{"label", k}, {"kind", 14}});
  return {{"isIncomplete", false}, {"items", items}};
}

// ------------------------------------------------------------- includes --

// A file the document #includes, and where: the quoted or bracketed name
// of its directive, or the whole directive when a macro names the file.
struct IncludeLink {
  Range range;
  std::uint32_t file = 0;
};

Range name_in_directive(const Index& index, const SourceSpan& site) {
  Range whole{{index.main_file, site.begin.line, site.begin.column}, {index.main_file, site.end.line, site.end.column}};
  if (site.begin.line != site.end.line) return whole;  // a directive continued with '\\'
  std::string_view line = index.sm.line(index.main_file, site.begin.line);
  std::size_t from = site.begin.column - 1, to = std::min<std::size_t>(site.end.column - 1, line.size());
  std::size_t open = line.find_first_of("\"<", from);
  if (open == std::string_view::npos || open >= to) return whole;
  std::size_t close = line.find(line[open] == '"' ? '"' : '>', open + 1);
  if (close == std::string_view::npos || close >= to) return whole;
  auto column = [](std::size_t byte) { return static_cast<std::uint32_t>(byte + 1); };
  return {{index.main_file, site.begin.line, column(open)}, {index.main_file, site.begin.line, column(close + 1)}};
}

// The files the document itself #includes (not those its includes do).
std::vector<IncludeLink> include_links(const Index& index) {
  std::vector<IncludeLink> out;
  for (std::uint32_t f = 0; f < index.sm.size(); ++f) {
    SourceSpan site = index.sm.include_site(f);
    if (!site.begin.valid() || site.begin.file != index.main_file || site.begin.expansion != 0) continue;
    out.push_back({name_in_directive(index, site), f});
  }
  return out;
}

json document_links(Request& r) {
  json list = json::array();
  for (const IncludeLink& link : include_links(r.doc->index)) {
    std::string target = file_uri(r.server, *r.doc, r.uri, link.file);
    if (!target.empty()) list.push_back({{"range", range_json(r.doc->index, link.range)}, {"target", target}});
  }
  return list;
}

json definition(Request& r) {
  auto at = place_of(*r.doc, r.params.at("position"));
  if (!at) return nullptr;
  // On an #include's file name: the file's first line.
  for (const IncludeLink& link : include_links(r.doc->index)) {
    if (!contains(link.range, *at)) continue;
    std::string target = file_uri(r.server, *r.doc, r.uri, link.file);
    if (target.empty()) return nullptr;
    json top = {{"line", 0}, {"character", 0}};
    return {{"uri", target}, {"range", {{"start", top}, {"end", top}}}};
  }
  const Definition* def = definition_at(r, *at);
  if (!def) return nullptr;
  return location(r.server, *r.doc, r.uri, def->at);
}

json find_references(Request& r) {
  auto at = place_of(*r.doc, r.params.at("position"));
  if (!at) return nullptr;
  const Definition* def = definition_at(r, *at);
  if (!def) return json::array();
  bool with_decl = r.params.contains("context") && r.params["context"].value("includeDeclaration", false);
  json list = json::array();
  for (const Range& range : references(r.doc->index, *def, with_decl)) {
    json loc = location(r.server, *r.doc, r.uri, range);
    if (!loc.is_null()) list.push_back(loc);
  }
  return list;
}

json document_symbols(Request& r) {
  const Index& index = r.doc->index;
  std::vector<const Definition*> defs;
  for (const auto& d : index.defs)
    if (d.at.begin.file == index.main_file && !d.scope) defs.push_back(&d);
  std::stable_sort(defs.begin(), defs.end(), [](const Definition* a, const Definition* b) {
    return std::pair(a->at.begin.line, a->at.begin.column) < std::pair(b->at.begin.line, b->at.begin.column);
  });
  json list = json::array();
  for (const Definition* d : defs)
    list.push_back({{"name", d->name}, {"detail", d->signature}, {"kind", symbol_kind(*d)},
                    {"range", range_json(index, d->extent)}, {"selectionRange", range_json(index, d->at)}});
  return list;
}

// NAME of "'NAME' is not declared...", else "". Read by hand, not by
// std::regex: libstdc++'s matcher recurses once per character, and a
// 300,000-letter name overflowed the stack (SIGSEGV).
std::string undeclared_name(const std::string& message) {
  const std::string_view tail = "' is not declared";
  if (message.empty() || message[0] != '\'') return "";
  auto end = message.find('\'', 1);
  if (end == std::string::npos || message.compare(end, tail.size(), tail) != 0) return "";
  std::string name = message.substr(1, end - 1);
  return is_identifier(name) ? name : "";
}

// NAME of "... did you mean 'NAME'...", else "".
std::string suggested_name(const std::string& message) {
  const std::string_view lead = "did you mean '";
  auto at = message.find(lead);
  if (at == std::string::npos) return "";
  at += lead.size();
  auto end = message.find('\'', at);
  if (end == std::string::npos) return "";
  std::string name = message.substr(at, end - at);
  return is_identifier(name) ? name : "";
}

// "did you mean" quick fixes for the names the compiler does not know.
// TASK of "task 'TASK' is never started...", else "".
std::string unstarted_task(const std::string& message) {
  const std::string_view lead = "task '", tail = "' is never started";
  if (message.rfind(lead, 0) != 0) return "";
  auto end = message.find('\'', lead.size());
  if (end == std::string::npos || message.compare(end, tail.size(), tail) != 0) return "";
  std::string name = message.substr(lead.size(), end - lead.size());
  return is_identifier(name) ? name : "";
}

// "Start 'watch' at the top of main": `start watch;` as main's first
// statement, indented as the line after main's '{' is (two spaces more
// than the brace's line when that line holds no statement).
json start_task_action(Request& r, const DocDiagnostic& d, const std::string& task) {
  const Index& index = r.doc->index;
  const Definition* main = nullptr;
  for (const auto& def : index.defs)
    if (def.kind == DefKind::Task && def.name == "main" && def.at.begin.file == index.main_file) main = &def;
  if (!main) return nullptr;
  auto brace = body_opening(index, *main);
  if (!brace) return nullptr;
  auto indent_of = [](std::string_view line) { return std::string(line.substr(0, line.find_first_not_of(" \t"))); };
  std::string_view next = doc_line(*r.doc, brace->line + 1);
  bool statement_next = !next.empty() && next.find_first_not_of(" \t") != std::string_view::npos &&
                        next[next.find_first_not_of(" \t")] != '}';
  std::string indent = statement_next ? indent_of(next) : indent_of(doc_line(*r.doc, brace->line)) + "  ";
  Place after{brace->file, brace->line, brace->column + 1};
  json edit = {{"range", {{"start", place_json(index, after)}, {"end", place_json(index, after)}}},
               {"newText", "\n" + indent + "start " + task + ";"}};
  return {{"title", "Start '" + task + "' at the top of main"},
          {"kind", "quickfix"},
          {"isPreferred", true},
          {"diagnostics", json::array({diagnostic_json(r.server, *r.doc, r.uri, d)})},
          {"edit", {{"changes", {{r.uri, json::array({edit})}}}}}};
}

json code_actions(Request& r) {
  const Index& index = r.doc->index;
  auto first = place_of(*r.doc, r.params.at("range").at("start"));
  auto last = place_of(*r.doc, r.params.at("range").at("end"));
  if (!first || !last) return nullptr;
  json actions = json::array();
  for (const auto& d : index.diagnostics) {
    if (d.line == 0) continue;
    // The request's range must touch the diagnostic's.
    if (d.end_line < first->line || (d.end_line == first->line && d.end_column < first->column)) continue;
    if (d.line > last->line || (d.line == last->line && d.column > last->column)) continue;
    if (std::string task = d.warning == WarningKind::UnstartedTask ? unstarted_task(d.message) : "";
        !task.empty()) {
      json action = start_task_action(r, d, task);
      if (!action.is_null()) actions.push_back(std::move(action));
      continue;
    }
    std::string name = undeclared_name(d.message);
    if (name.empty()) continue;
    const Occurrence* occ = nullptr;
    for (const auto& o : index.occurrences)
      if (o.name == name && o.at.begin.file == index.main_file && o.at.begin.line == d.line &&
          o.at.begin.column >= d.column && (o.at.begin.line < d.end_line || o.at.begin.column < d.end_column)) {
        occ = &o;
        break;
      }
    if (!occ) continue;
    std::vector<std::string> names;
    if (std::string meant = suggested_name(d.message); !meant.empty()) names.push_back(meant);
    for (auto& n : similar_names(index, name, occ->at.begin))
      if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    for (std::size_t i = 0; i < names.size(); ++i) {
      json edit = {{"range", range_json(index, occ->at)}, {"newText", names[i]}};
      actions.push_back({{"title", "Change '" + name + "' to '" + names[i] + "'"},
                         {"kind", "quickfix"},
                         {"isPreferred", i == 0},
                         {"diagnostics", json::array({diagnostic_json(r.server, *r.doc, r.uri, d)})},
                         {"edit", {{"changes", {{r.uri, json::array({edit})}}}}}});
    }
  }
  return actions;
}

// ------------------------------------------------------- signature help --

json signature_information(const Definition& def, const ParameterList& list, std::size_t argument) {
  std::string label = def.signature.substr(0, list.close + 1);
  auto units = [&](std::size_t byte) { return utf16_of_byte_column(label, static_cast<std::uint32_t>(byte + 1)); };
  json params = json::array();
  for (const auto& [begin, end] : list.params) params.push_back({{"label", {units(begin), units(end)}}});
  json info = {{"label", label}, {"parameters", params}, {"activeParameter", argument}};
  if (!def.doc.empty()) info["documentation"] = {{"kind", "markdown"}, {"value", def.doc}};
  return info;
}

json signature_help(Request& r) {
  auto at = place_of(*r.doc, r.params.at("position"));
  if (!at) return nullptr;
  auto call = call_at(r.doc->index, *at);
  if (!call) return nullptr;
  const Definition* def = resolve(r.doc->index, call->callee, call->callee_at);
  auto list = def ? parameter_list(*def) : std::nullopt;
  if (!list) return nullptr;
  // An argument past the last parameter stays past it: LSP would read a
  // missing activeParameter as the first one.
  return {{"signatures", json::array({signature_information(*def, *list, call->argument)})},
          {"activeSignature", 0},
          {"activeParameter", call->argument}};
}

// ---------------------------------------------------------- inlay hints --

// The name a parameter's text declares: its last word ("const int &sensor"
// is "sensor"); empty when that is a keyword (a list cut short at "int").
std::string parameter_name(std::string_view text) {
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  std::size_t end = text.size();
  while (end > 0 && !word(text[end - 1])) --end;
  std::size_t begin = end;
  while (begin > 0 && word(text[begin - 1])) --begin;
  std::string name(text.substr(begin, end - begin));
  return is_plain_name(name) ? name : std::string();
}

// Each argument of a call in the range gets its parameter's name before it
// (`PlayTone(frequency: 440, duration: 50)`), the way editors show C's; an
// argument that is a variable of the parameter's own name gets none.
json inlay_hints(Request& r) {
  auto first = place_of(*r.doc, r.params.at("range").at("start"));
  auto last = place_of(*r.doc, r.params.at("range").at("end"));
  json hints = json::array();
  if (!first || !last || r.doc->text.size() > kMaxDocument) return hints;
  const Index& index = r.doc->index;
  for (const CallArguments& call : calls_in(index, index.main_file)) {
    if (call.arguments.empty()) continue;
    const Definition* def = resolve(index, call.callee, call.callee_at);
    // A function's or macro's own declaration lists parameters, not arguments.
    if (!def || (def->at.begin.file == call.callee_at.file && def->at.begin.line == call.callee_at.line &&
                 def->at.begin.column == call.callee_at.column))
      continue;
    auto list = parameter_list(*def);
    if (!list) continue;
    for (const CallArgument& a : call.arguments) {
      if (a.position >= list->params.size() || before(a.at, *first) || !before(a.at, *last)) continue;
      auto [begin, end] = list->params[a.position];
      std::string name = parameter_name(std::string_view(def->signature).substr(begin, end - begin));
      if (name.empty() || name == a.only_name) continue;
      hints.push_back({{"position", place_json(index, a.at)}, {"label", name + ":"}, {"kind", 2}, {"paddingRight", true}});
    }
  }
  return hints;
}

// -------------------------------------------------------- call hierarchy --
// Who calls whom among tasks, subs and functions (`start t;` and `stop t;`
// count as calls of task t). An item carries the document it was found in and its
// name, all a later request needs: top-level names are unique in NQC.

bool callable(const Definition& d) {
  return !d.scope && (d.kind == DefKind::Task || d.kind == DefKind::Sub || d.kind == DefKind::Function);
}

json call_item(Request& r, const Definition& d) {
  json at = location(r.server, *r.doc, r.uri, d.at);
  if (at.is_null()) return nullptr;
  return {{"name", d.name},
          {"kind", symbol_kind(d)},
          {"detail", d.signature},
          {"uri", at["uri"]},
          {"range", range_json(r.doc->index, d.extent)},
          {"selectionRange", at["range"]},
          {"data", {{"document", r.uri}, {"name", d.name}}}};
}

json prepare_call_hierarchy(Request& r) {
  auto at = place_of(*r.doc, r.params.at("position"));
  if (!at) return nullptr;
  const Definition* def = definition_at(r, *at);
  if (!def || !callable(*def)) return nullptr;
  json item = call_item(r, *def);
  return item.is_null() ? json(nullptr) : json::array({item});
}

// The calls of one item in the other's body: the item, and the ranges of
// the names that call, in the order first met.
struct CallsOf {
  const Definition* other = nullptr;
  json ranges = json::array();
};

void add_call(std::vector<CallsOf>& calls, const Definition* other, json range) {
  auto it = std::find_if(calls.begin(), calls.end(), [&](const CallsOf& c) { return c.other == other; });
  if (it == calls.end()) it = calls.insert(calls.end(), CallsOf{other});
  it->ranges.push_back(std::move(range));
}

json call_list(Request& r, const std::vector<CallsOf>& calls, const char* other_key) {
  json list = json::array();
  for (const CallsOf& c : calls) {
    json item = call_item(r, *c.other);
    if (!item.is_null()) list.push_back({{other_key, item}, {"fromRanges", c.ranges}});
  }
  return list;
}

json incoming_calls(Request& r, const Definition& callee) {
  const Index& index = r.doc->index;
  std::vector<CallsOf> calls;
  for (const Range& use : references(index, callee, false))
    for (const Definition& d : index.defs)
      if (callable(d) && contains(d.extent, use.begin)) {
        add_call(calls, &d, range_json(index, use));
        break;
      }
  return call_list(r, calls, "from");
}

json outgoing_calls(Request& r, const Definition& caller) {
  const Index& index = r.doc->index;
  std::vector<CallsOf> calls;
  for (const auto& [occ, def] : resolve_file(index, caller.extent.begin.file)) {
    const Place& p = occ->at.begin;
    bool own_name = p == caller.at.begin;
    if (def && callable(*def) && contains(caller.extent, p) && !own_name) add_call(calls, def, range_json(index, occ->at));
  }
  return call_list(r, calls, "to");
}

json calls_of_item(Server& server, const std::string& method, const json& params) {
  // A client that drops `data` still sends the item's name and file.
  const json& item = params.at("item");
  const json& data = item.contains("data") ? item["data"] : item;
  Request r{server, params, data.value("document", item.at("uri").get<std::string>())};
  auto it = server.documents.find(r.uri);
  if (it == server.documents.end()) return nullptr;  // closed since
  r.doc = &it->second;
  std::string name = data.at("name").get<std::string>();
  for (const Definition& d : r.doc->index.defs)
    if (d.name == name && callable(d))
      return method == "callHierarchy/incomingCalls" ? incoming_calls(r, d) : outgoing_calls(r, d);
  return nullptr;  // renamed or deleted since
}

// ---------------------------------------------------------------- rename --

// Longer new names are refused: each edit carries the name, and no one
// types a thousand-letter name.
constexpr std::size_t kMaxNewName = 255;

std::string where_defined(const Index& index, const Definition& d) {
  if (in_stdlib(index, d.at.begin.file)) return "in the RCX API (rcx.nqh)";
  if (on_command_line(index, d.at.begin.file)) return "on the command line (" + d.signature + ")";
  std::string file = fs::path(index.sm.path(d.at.begin.file)).filename().string();
  return "at " + (d.at.begin.file == index.main_file ? "" : file + ":") + "line " + std::to_string(d.at.begin.line);
}

// What a rename at the request's position would change: the definition and
// every reference to it, its declaration included.
struct Renamed {
  const Occurrence* occurrence = nullptr;  // nullptr: no name at the position
  const Definition* def = nullptr;
  std::vector<Range> uses;
};

// The rename at `at`, or a refusal saying why the name there cannot be renamed.
Renamed renamable_at(Request& r, const Place& at) {
  Renamed what;
  what.def = definition_at(r, at, &what.occurrence);
  if (!what.occurrence) return what;
  const std::string& name = what.occurrence->name;
  if (!is_plain_name(name)) throw Refused("'" + name + "' is a keyword and cannot be renamed");
  if (!what.def) throw Refused("'" + name + "' is not declared, so there is nothing to rename");
  const Index& index = r.doc->index;
  if (in_stdlib(index, what.def->at.begin.file))
    throw Refused("'" + name + "' is part of the RCX API (rcx.nqh) and cannot be renamed");
  if (on_command_line(index, what.def->at.begin.file))
    throw Refused("'" + name + "' is defined on the command line (" + what.def->signature + ") and cannot be renamed");
  what.uses = references(index, *what.def, true);
  for (const Range& use : what.uses)
    if (in_stdlib(index, use.begin.file)) throw Refused("'" + name + "' is used in the RCX API (rcx.nqh) and cannot be renamed");
  return what;
}

void check_new_name(const Index& index, const Renamed& what, const std::string& name) {
  if (name.size() > kMaxNewName)
    throw Refused("the new name is " + std::to_string(name.size()) + " characters long; at most " +
                  std::to_string(kMaxNewName) + " are accepted");
  if (!is_identifier(name)) throw Refused("'" + name + "' is not a valid name (letters, digits and _, not starting with a digit)");
  if (frontend::is_keyword(name)) throw Refused("'" + name + "' is a keyword");
  if (const Definition* other = rename_clash(index, what.uses, name))
    throw Refused("renaming '" + what.def->name + "' to '" + name + "' would clash with the " +
                  std::string(def_kind_name(other->kind)) + " '" + name + "' " + where_defined(index, *other));
}

json prepare_rename(Request& r) {
  auto at = place_of(*r.doc, r.params.at("position"));
  if (!at) return nullptr;
  Renamed what = renamable_at(r, *at);
  if (!what.def) return nullptr;
  return {{"range", range_json(r.doc->index, what.occurrence->at)}, {"placeholder", what.occurrence->name}};
}

json rename(Request& r) {
  std::string new_name = r.params.at("newName").get<std::string>();
  auto at = place_of(*r.doc, r.params.at("position"));
  Renamed what = at ? renamable_at(r, *at) : Renamed{};
  if (!what.def) throw Refused("there is no name at this position to rename");
  if (new_name == what.def->name) return {{"changes", json::object()}};
  check_new_name(r.doc->index, what, new_name);
  json changes = json::object();
  for (const Range& use : what.uses) {
    std::string target = file_uri(r.server, *r.doc, r.uri, use.begin.file);
    // Only a standard library copy has no URI, and its uses were refused;
    // a rename that left some uses out would change what the program means.
    if (target.empty()) throw Refused("'" + what.def->name + "' is used in a file that has no URI");
    changes[target].push_back({{"range", range_json(r.doc->index, use)}, {"newText", new_name}});
  }
  return {{"changes", changes}};
}

// --------------------------------------------------------- highlighting --

// The highlight kind of a variable's use at `r`: Write where it is
// assigned, Text where it is a whole argument of a call (a function may take
// it by reference and write it), else Read.
int access_kind(const Index& index, const Range& r) {
  switch (access_at(index, r.begin)) {
    case Access::Write: return 3;
    case Access::Argument: return 1;
    case Access::Read: return 2;
  }
  return 2;
}

json document_highlight(Request& r) {
  auto at = place_of(*r.doc, r.params.at("position"));
  if (!at) return nullptr;
  const Definition* def = definition_at(r, *at);
  if (!def) return nullptr;
  const Index& index = r.doc->index;
  bool variable = def->kind == DefKind::Global || def->kind == DefKind::Local || def->kind == DefKind::Param;
  json list = json::array();
  for (const Range& use : references(index, *def, true)) {
    if (use.begin.file != index.main_file) continue;
    bool declaration = use.begin == def->at.begin;
    int kind = !variable ? 1 : declaration ? 3 : access_kind(index, use);  // 1 Text, 3 Write
    list.push_back({{"range", range_json(index, use)}, {"kind", kind}});
  }
  return list;
}

// -------------------------------------------------------------- folding --

json folding_ranges(Request& r) {
  json list = json::array();
  // As large a document as the compiler reads (the protocol allows 64 MiB).
  if (r.doc->text.size() > kMaxDocument) return list;
  for (const Fold& f : folds(r.doc->text)) {
    json range = {{"startLine", f.first - 1}, {"endLine", f.last - 1}};
    if (f.kind == FoldKind::Comment) range["kind"] = "comment";
    if (f.kind == FoldKind::Imports) range["kind"] = "imports";
    list.push_back(range);
  }
  return list;
}

// ------------------------------------------------------ workspace symbols --

// The tasks, subs, functions, globals and macros of every open document
// and of the files they include (an included file that is open itself
// counts as open: its own text, not the one on disk), matching the query.
json workspace_symbols(Server& server, const json& params) {
  const std::string query = params.at("query").get<std::string>();
  std::set<std::string> open;
  for (const auto& [uri, doc] : server.documents) open.insert(fs::path(doc.path).lexically_normal().string());
  struct Found {
    int rank;
    const Definition* def;
    Document* doc;
    const std::string* uri;
  };
  std::vector<Found> found;
  std::set<std::tuple<std::string, std::uint32_t, std::uint32_t>> seen;  // a file included twice counts once
  for (auto& [uri, doc] : server.documents) {
    const Index& index = doc.index;
    for (const auto& d : index.defs) {
      std::uint32_t file = d.at.begin.file;
      if (d.scope || in_stdlib(index, file) || on_command_line(index, file)) continue;
      std::error_code ec;
      std::string path = file == index.main_file ? doc.path : fs::absolute(index.sm.path(file), ec).string();
      path = fs::path(path).lexically_normal().string();
      if (file != index.main_file && open.contains(path)) continue;
      auto rank = symbol_match(d.name, query);
      if (!rank || !seen.insert({path, d.at.begin.line, d.at.begin.column}).second) continue;
      found.push_back({*rank, &d, &doc, &uri});
    }
  }
  std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) {
    return std::tie(a.rank, a.def->name, *a.uri, a.def->at.begin.line) <
           std::tie(b.rank, b.def->name, *b.uri, b.def->at.begin.line);
  });
  json list = json::array();
  for (const Found& f : found) {
    json loc = location(server, *f.doc, *f.uri, f.def->at);
    if (loc.is_null()) continue;
    list.push_back({{"name", f.def->name}, {"kind", symbol_kind(*f.def)}, {"location", loc}});
  }
  return list;
}

// -------------------------------------------------------- semantic tokens --

// The legend: a token's type is an index into the first list, its
// modifiers a bit set over the second.
const std::vector<std::string> kTokenTypes = {"function", "parameter", "variable", "macro", "label"};
const std::vector<std::string> kTokenModifiers = {"declaration", "defaultLibrary", "globalScope", "functionScope",
                                                  "task"};

std::pair<std::uint32_t, std::uint32_t> token_type(const Index& index, const Definition& d, const Occurrence& o) {
  enum : std::uint32_t { function, parameter, variable, macro, label };
  enum : std::uint32_t { declaration = 1, library = 2, global_scope = 4, function_scope = 8, task = 16 };
  std::uint32_t type = function, mods = 0;
  switch (d.kind) {
    case DefKind::Task: mods = task; break;
    case DefKind::Sub:
    case DefKind::Function: break;
    case DefKind::Global: type = variable, mods = global_scope; break;
    case DefKind::Local: type = variable, mods = function_scope; break;
    case DefKind::Param: type = parameter; break;
    case DefKind::Label: type = label; break;
    case DefKind::Macro: type = macro; break;
  }
  if (in_stdlib(index, d.at.begin.file)) mods |= library;
  if (o.at.begin == d.at.begin) mods |= declaration;
  return {type, mods};
}

// The name after a directive's '#' (`#define`, `#include`) is no name of the program.
bool directive_word(std::string_view line, std::uint32_t column) {
  std::string_view before = line.substr(0, std::min<std::size_t>(line.size(), column - 1));
  auto b = before.find_first_not_of(" \t");
  return b != std::string_view::npos && before[b] == '#' && before.find_first_not_of(" \t", b + 1) == std::string_view::npos;
}

json semantic_tokens(Request& r) {
  const Index& index = r.doc->index;
  std::vector<std::uint32_t> data;
  std::uint32_t last_line = 1, last_start = 0;
  for (const auto& [occ, def] : resolve_file(index, index.main_file)) {
    const Place& b = occ->at.begin;
    if (!def || occ->at.end.line != b.line) continue;
    if (directive_word(doc_line(*r.doc, b.line), b.column)) continue;
    std::uint32_t start = utf16_column(index, b);
    std::uint32_t length = utf16_column(index, occ->at.end) - start;
    auto [type, mods] = token_type(index, *def, *occ);
    data.insert(data.end(), {b.line - last_line, b.line == last_line ? start - last_start : start, length, type, mods});
    last_line = b.line;
    last_start = start;
  }
  return {{"data", data}};
}

// ----------------------------------------------------------- formatting --

// The document formatted (docs/format.md) as one edit of the whole text, or
// no edit when it already is; a text the formatter refuses (a lexical
// error) is an error with its message. The editor's tab size is the indent.
// The document as the formatter lays it out, with the editor's tab size
// (1 to 8) as the indent; a text the formatter refuses is an error with its
// message.
std::string formatted_text(Request& r) {
  format::Style style;
  const json& options = r.params.contains("options") ? r.params["options"] : json::object();
  if (options.is_object() && options.contains("tabSize"))
    style.indent = static_cast<int>(std::clamp<std::int64_t>(integer_field(options, "tabSize"), format::kMinIndent,
                                                             format::kMaxIndent));
  auto formatted = format::format_source(r.doc->text, style);
  if (auto* refusal = std::get_if<format::Refusal>(&formatted)) throw Refused(refusal->message);
  return std::move(std::get<std::string>(formatted));
}

// Where line `line` (from 0) of `lines` starts, as an LSP position; past the
// last line, the end of the text.
json line_start(const std::vector<std::string_view>& lines, std::size_t line) {
  if (line < lines.size()) return {{"line", line}, {"character", 0}};
  if (lines.empty()) return {{"line", 0}, {"character", 0}};
  std::string_view last = lines.back();
  if (last.back() == '\n' || last.back() == '\r') return {{"line", lines.size()}, {"character", 0}};
  return {{"line", lines.size() - 1}, {"character", utf16_of_byte_column(last, static_cast<std::uint32_t>(last.size() + 1))}};
}

json formatting(Request& r) {
  const std::string& text = r.doc->text;
  std::string out = formatted_text(r);
  if (out == text) return json::array();
  json range = {{"start", {{"line", 0}, {"character", 0}}}, {"end", line_start(split_lines(text), SIZE_MAX)}};
  return json::array({{{"range", range}, {"newText", std::move(out)}}});
}

// "Format Selection": the lines of the whole document's formatting that
// change a line the range touches. A line laid out again is an edit of its
// own; where the formatter splits or joins lines, the whole run of changed
// lines is one edit, taken whole when it crosses the range's edge.
json range_formatting(Request& r) {
  const json& range = r.params.at("range");
  std::int64_t first = integer_field(range.at("start"), "line");
  std::int64_t last = integer_field(range.at("end"), "line");
  if (first < 0 || last < first) throw BadParams("the range must not end before it starts");
  // A selection of whole lines ends at the start of the line after them.
  if (last > first && integer_field(range.at("end"), "character") == 0) --last;
  const std::string& text = r.doc->text;
  std::string out = formatted_text(r);
  std::vector<std::string_view> old_lines = split_lines(text), new_lines = split_lines(out);
  json edits = json::array();
  auto add = [&](const Hunk& h) {
    auto begin = static_cast<std::int64_t>(h.old_begin), end = static_cast<std::int64_t>(h.old_end);
    bool touches = begin == end ? first <= begin && begin <= last + 1 : begin <= last && end > first;
    if (!touches) return;
    std::string new_text;
    for (std::size_t i = h.new_begin; i < h.new_end; ++i) new_text += new_lines[i];
    edits.push_back({{"range", {{"start", line_start(old_lines, h.old_begin)}, {"end", line_start(old_lines, h.old_end)}}},
                     {"newText", std::move(new_text)}});
  };
  for (const Hunk& h : line_hunks(old_lines, new_lines)) {
    // As many lines as before (indents, spaces): each line is its own edit,
    // so the lines beside the selection keep their layout.
    if (h.old_end - h.old_begin != h.new_end - h.new_begin) {
      add(h);
      continue;
    }
    for (std::size_t i = 0; i < h.old_end - h.old_begin; ++i)
      if (old_lines[h.old_begin + i] != new_lines[h.new_begin + i])
        add({h.old_begin + i, h.old_begin + i + 1, h.new_begin + i, h.new_begin + i + 1});
  }
  return edits;
}

// The client's settings, `{"includeDirs": [...], "warnings": [...]}`, on
// top of the command line's: what an earlier setting added is replaced.
void apply_settings(Server& server, const json& settings) {
  server.options.include_dirs = server.started_include_dirs;
  server.warnings = server.started_warnings;
  if (!settings.is_object()) return;
  if (settings.contains("includeDirs") && settings["includeDirs"].is_array())
    for (const auto& d : settings["includeDirs"])
      if (d.is_string()) server.options.include_dirs.push_back(d.get<std::string>());
  // As -W options: "no-unused-variable", "error=range". One it does not
  // know is left out: the editor's settings should not stop the server.
  if (settings.contains("warnings") && settings["warnings"].is_array())
    for (const auto& w : settings["warnings"])
      if (w.is_string()) {
        WarningPolicy tried = server.warnings;
        if (!apply_warning_option(tried, w.get<std::string>())) server.warnings = tried;
      }
}

json initialize_result(Server& server, const json& params) {
  server.started_include_dirs = server.options.include_dirs;
  server.started_warnings = server.warnings;
  if (params.is_object() && params.contains("initializationOptions"))
    apply_settings(server, params["initializationOptions"]);
  json capabilities = {
      {"textDocumentSync", {{"openClose", true}, {"change", 2}, {"save", {{"includeText", false}}}}},
      {"hoverProvider", true},
      {"completionProvider", {{"resolveProvider", false}}},
      {"definitionProvider", true},
      {"referencesProvider", true},
      {"documentSymbolProvider", true},
      {"codeActionProvider", {{"codeActionKinds", json::array({"quickfix"})}}},
      {"signatureHelpProvider", {{"triggerCharacters", json::array({"(", ","})}}},
      {"renameProvider", {{"prepareProvider", true}}},
      {"documentHighlightProvider", true},
      {"foldingRangeProvider", true},
      {"documentLinkProvider", {{"resolveProvider", false}}},
      {"workspaceSymbolProvider", true},
      {"semanticTokensProvider", {{"legend", {{"tokenTypes", kTokenTypes}, {"tokenModifiers", kTokenModifiers}}}, {"full", true}}},
      {"documentFormattingProvider", true},
      {"documentRangeFormattingProvider", true},
      {"inlayHintProvider", true},
      {"callHierarchyProvider", true},
  };
  return {{"capabilities", capabilities}, {"serverInfo", {{"name", "rcxc"}, {"version", server.version}}}};
}

std::string text_document_uri(const json& params) { return params.at("textDocument").at("uri").get<std::string>(); }

std::vector<json> notify(Server& server, const std::string& method, const json& params) {
  if (method == "exit") {
    server.exited = true;
    return {};
  }
  if (!server.initialized) return {};
  if (method == "textDocument/didOpen") {
    const json& td = params.at("textDocument");
    std::string uri = td.at("uri").get<std::string>();
    std::string text = td.at("text").get<std::string>();
    // Read before the document is touched: a bad version drops the message.
    std::int64_t version = td.contains("version") ? integer_field(td, "version") : 0;
    Document& doc = server.documents[uri];
    doc.path = uri_to_path(uri);
    // LSP counts a lone CR as a line end, as the compiler does: the copy
    // keeps LF there, so the position arithmetic looks for '\n' alone.
    doc.text = with_lone_crs_as_lf(std::move(text));
    doc.version = version;
    doc.opened = server.changes + 1;  // what `changed` gives it: older compilations are not its own
    return changed(server, uri, &doc, doc.path);
  }
  if (method == "textDocument/didChange") {
    std::string uri = text_document_uri(params);
    auto it = server.documents.find(uri);
    if (it == server.documents.end()) return {};
    Document& doc = it->second;
    // Every change is applied to a copy and kept only if the whole message
    // is good: a bad version or a later malformed change used to leave the
    // text changed but the index (and diagnostics) of the old text.
    std::string updated = apply_changes(doc.text, params.at("contentChanges"));
    const json& td = params.at("textDocument");
    std::int64_t version = td.contains("version") && !td["version"].is_null() ? integer_field(td, "version") : doc.version;
    doc.text = with_lone_crs_as_lf(std::move(updated));
    doc.version = version;
    return changed(server, uri, &doc, doc.path);
  }
  if (method == "textDocument/didSave") {
    std::string uri = text_document_uri(params);
    auto it = server.documents.find(uri);
    if (it == server.documents.end()) return {};
    return changed(server, uri, &it->second, it->second.path);  // an included file may have changed
  }
  if (method == "textDocument/didClose") {
    std::string uri = text_document_uri(params);
    auto it = server.documents.find(uri);
    if (it == server.documents.end()) return {publish(server, uri, nullptr)};
    std::string path = it->second.path;
    server.documents.erase(it);
    return changed(server, uri, nullptr, path);  // who includes it reads the saved file again
  }
  if (method == "workspace/didChangeConfiguration") {
    // Settings under "rcxc" (VS Code's and Neovim's way: the section named
    // after the server), with initializationOptions' names; other settings
    // change nothing. Every open document is compiled again with them.
    if (!params.is_object() || !params.contains("settings") || !params["settings"].is_object() ||
        !params["settings"].contains("rcxc"))
      return {};
    apply_settings(server, params["settings"]["rcxc"]);
    std::vector<json> out;
    for (auto& [uri, doc] : server.documents) recompile(server, uri, doc, out);
    return out;
  }
  return {};  // initialized, $/cancelRequest, ...: nothing to do
}

struct UnknownMethod {};

json answer(Server& server, const std::string& method, const json& params) {
  using Handler = json (*)(Request&);
  static const std::map<std::string, Handler> handlers = {
      {"textDocument/hover", hover},
      {"textDocument/completion", completion},
      {"textDocument/definition", definition},
      {"textDocument/references", find_references},
      {"textDocument/documentSymbol", document_symbols},
      {"textDocument/codeAction", code_actions},
      {"textDocument/signatureHelp", signature_help},
      {"textDocument/prepareRename", prepare_rename},
      {"textDocument/rename", rename},
      {"textDocument/documentHighlight", document_highlight},
      {"textDocument/foldingRange", folding_ranges},
      {"textDocument/documentLink", document_links},
      {"textDocument/semanticTokens/full", semantic_tokens},
      {"textDocument/formatting", formatting},
      {"textDocument/rangeFormatting", range_formatting},
      {"textDocument/inlayHint", inlay_hints},
      {"textDocument/prepareCallHierarchy", prepare_call_hierarchy},
  };
  if (method == "workspace/symbol") return workspace_symbols(server, params);
  if (method == "callHierarchy/incomingCalls" || method == "callHierarchy/outgoingCalls")
    return calls_of_item(server, method, params);
  auto h = handlers.find(method);
  if (h == handlers.end()) throw UnknownMethod{};
  Request r{server, params, text_document_uri(params)};
  auto it = server.documents.find(r.uri);
  if (it == server.documents.end()) return nullptr;  // not open: nothing known about it
  r.doc = &it->second;
  return h->second(r);
}

}  // namespace

std::vector<json> handle(Server& server, const json& message) {
  if (!message.is_object() || !message.contains("method") || !message["method"].is_string()) {
    if (message.is_object() && message.contains("id") && !message.contains("method") &&
        (message.contains("result") || message.contains("error")))
      return {};  // a reply to a request of ours (we send none): ignored
    // JSON-RPC: an id that is not a string or an integer is answered with null.
    json id = nullptr;
    if (message.is_object() && message.contains("id") && (message["id"].is_string() || message["id"].is_number_integer()))
      id = message["id"];
    return {error_response(id, kInvalidRequest, "not a JSON-RPC request or notification")};
  }
  const std::string method = message["method"].get<std::string>();
  const json params = message.contains("params") ? message["params"] : json::object();
  if (!message.contains("id")) {
    try {
      return notify(server, method, params);
    } catch (const std::exception&) {
      return {};  // a malformed notification cannot be answered; it is dropped
    }
  }
  const json& id = message["id"];
  if (!id.is_string() && !id.is_number_integer()) return {error_response(nullptr, kInvalidRequest, "bad request id")};
  if (method == "initialize") {
    if (server.initialized) return {error_response(id, kInvalidRequest, "initialize was already received")};
    server.initialized = true;
    return {response(id, initialize_result(server, params))};
  }
  if (!server.initialized) return {error_response(id, kServerNotInitialized, "initialize first")};
  if (server.shutdown) return {error_response(id, kInvalidRequest, "the server is shutting down")};
  if (method == "shutdown") {
    // The last text of every document has its diagnostics, however soon
    // the client leaves after changing it.
    std::vector<json> out = flush_stale(server);
    server.shutdown = true;
    out.push_back(response(id, nullptr));
    return out;
  }
  // The documents the request reads are compiled first, their diagnostics
  // sent before the answer: a request about one document reads it alone;
  // others (workspace symbols, call hierarchy items) may read any.
  std::vector<json> out;
  if (params.is_object() && params.contains("textDocument") && params["textDocument"].is_object() &&
      params["textDocument"].contains("uri") && params["textDocument"]["uri"].is_string()) {
    const std::string uri = params["textDocument"]["uri"].get<std::string>();
    auto it = server.documents.find(uri);
    // Completion, asked at every keystroke, answers from the text last
    // compiled (the names of a moment ago, the API and keywords): compiling
    // a large file first held it up by a compilation each time.
    bool stale_will_do = server.defer_index && method == "textDocument/completion" && it != server.documents.end() &&
                         it->second.index.sm.size() > 0;
    if (it != server.documents.end() && it->second.stale && !stale_will_do) {
      reindex(server, it->second);
      out.push_back(publish(server, uri, &it->second));
    }
  } else {
    out = flush_stale(server);
  }
  try {
    out.push_back(response(id, answer(server, method, params)));
    return out;
  } catch (const UnknownMethod&) {
    out.push_back(error_response(id, kMethodNotFound, "unknown method '" + method + "'"));
  } catch (const nlohmann::json::exception& e) {
    out.push_back(error_response(id, kInvalidParams, std::string("bad parameters for ") + method + ": " + e.what()));
  } catch (const BadParams& e) {
    out.push_back(error_response(id, kInvalidParams, std::string("bad parameters for ") + method + ": " + e.what()));
  } catch (const Refused& e) {
    out.push_back(error_response(id, kRequestFailed, e.what()));
  } catch (const std::exception& e) {
    out.push_back(error_response(id, kInternalError, e.what()));
  }
  return out;
}

std::vector<json> flush_stale(Server& server) {
  std::vector<json> out;
  for (auto& [uri, doc] : server.documents)
    if (doc.stale) {
      reindex(server, doc);
      out.push_back(publish(server, uri, &doc));
    }
  return out;
}

std::vector<json> handle_text(Server& server, const std::string& body) {
  if (json_nesting(body) > kMostNesting)
    return {error_response(nullptr, kParseError,
                           "the message nests arrays and objects deeper than " + std::to_string(kMostNesting) +
                               " levels; it was not read")};
  json message = json::parse(body, nullptr, false);
  if (message.is_discarded()) return {error_response(nullptr, kParseError, "the message is not valid JSON")};
  return handle(server, message);
}

namespace {

// A message read ahead: its frame and, for a message, its JSON (discarded
// when it is not JSON).
struct Queued {
  Frame frame;
  json message;
};

// The id a `$/cancelRequest` names, or null.
json cancelled_id(const json& message) {
  if (!message.is_object() || !message.contains("method") || message["method"] != "$/cancelRequest" ||
      message.contains("id") || !message.contains("params") || !message["params"].is_object() ||
      !message["params"].contains("id"))
    return nullptr;
  const json& id = message["params"]["id"];
  return id.is_string() || id.is_number_integer() ? id : json(nullptr);
}

}  // namespace

int serve(Server& server, std::istream& in, std::ostream& out, std::ostream& log) {
  server.defer_index = true;
  // The compiler thread and this one share the server and `out` under `m`;
  // the compiler builds from a snapshot without it. Reading from a stream
  // tied to `out` (std::cin is tied to std::cout) flushes `out` first,
  // outside the lock: the compiler's message was written twice. Every
  // message is flushed when written, so nothing needs the tie.
  std::ostream* tied = in.tie(nullptr);
  std::mutex m;
  std::condition_variable quiet;  // the input is quiet (or we stop): compile what is stale
  bool compile_now = false, stopping = false, write_failed = false;
  auto send = [&](const std::vector<json>& replies) {
    for (const auto& reply : replies) write_message(out, reply);
    if (!out) write_failed = true;
    return !write_failed;
  };
  std::thread compiler([&] {
    std::unique_lock lock(m);
    for (;;) {
      quiet.wait(lock, [&] { return stopping || compile_now; });
      if (stopping) return;
      auto it = std::find_if(server.documents.begin(), server.documents.end(),
                             [](const auto& entry) { return entry.second.stale; });
      if (it == server.documents.end()) {
        compile_now = false;
        continue;
      }
      const std::string uri = it->first;
      Snapshot snapshot = snapshot_of(server, it->second);
      lock.unlock();
      Index index = build(snapshot);
      lock.lock();
      // Kept if the document is still open and nothing newer was compiled
      // meanwhile (a request compiles what it needs itself), even when the
      // text has changed since: while the user types on, the diagnostics of
      // a moment ago, with their version, are better than none. The
      // document stays stale then, and is compiled again.
      it = server.documents.find(uri);
      if (it != server.documents.end() && snapshot.generation > it->second.index_generation &&
          snapshot.generation >= it->second.opened) {
        Document& doc = it->second;
        std::swap(doc.index, index);
        doc.index_generation = snapshot.generation;
        doc.stale = doc.generation != snapshot.generation;
        json published = publish(server, uri, &doc);
        published["params"]["version"] = snapshot.version;
        if (!write_failed) send({published});
      }
      // The index let go of (the old one, or this one unused) is freed
      // without the lock: a 20,000-line program's takes a while.
      lock.unlock();
      { Index retired = std::move(index); }
      lock.lock();
    }
  });
  std::unique_lock lock(m);
  std::deque<Queued> queue;
  std::size_t queued_bytes = 0;
  auto arrived = [&in] { return in.rdbuf()->in_avail() > 0; };
  auto read_one = [&] {
    Queued q{read_frame(in), nullptr};
    // Too deep a message stays unparsed (discarded): handle_text says why.
    if (q.frame.kind == Frame::Kind::Message && json_nesting(q.frame.body) <= kMostNesting)
      q.message = json::parse(q.frame.body, nullptr, false);
    else if (q.frame.kind == Frame::Kind::Message)
      q.message = json::value_t::discarded;
    queued_bytes += q.frame.body.size();
    queue.push_back(std::move(q));
  };
  int code = -1;
  while (!server.exited && code < 0) {
    // Reading may wait for the client: the compiler may publish meanwhile.
    lock.unlock();
    if (queue.empty()) read_one();
    while (queue.back().frame.kind != Frame::Kind::End && queued_bytes < kMaxBody && arrived()) read_one();
    lock.lock();
    Queued q = std::move(queue.front());
    queue.pop_front();
    queued_bytes -= q.frame.body.size();
    const Frame& frame = q.frame;
    if (frame.kind == Frame::Kind::End) {
      if (!frame.error.empty()) log << "rcxc lsp: " << frame.error << "\n";
      break;
    }
    if (frame.kind == Frame::Kind::BadHeader) {
      log << "rcxc lsp: skipped a message: " << frame.error << "\n";
      continue;
    }
    if (!frame.error.empty()) log << "rcxc lsp: " << frame.error << "\n";
    std::vector<json> replies;
    // A request the client has already cancelled is not run (it may be the
    // one that would compile a large document).
    const json& msg = q.message;
    bool cancelled = false;
    if (server.initialized && !server.shutdown && msg.is_object() && msg.contains("method") && msg.contains("id") &&
        (msg["id"].is_string() || msg["id"].is_number_integer()) && msg["method"] != "shutdown")
      for (const auto& later : queue)
        if (cancelled_id(later.message) == msg["id"]) cancelled = true;
    if (cancelled)
      replies.push_back(error_response(msg["id"], kRequestCancelled, "cancelled by the client"));
    else
      replies = msg.is_discarded() ? handle_text(server, frame.body) : handle(server, msg);
    // The client closed our output (rcxc ignores SIGPIPE, so the write
    // failed instead of killing us): nothing said from here would arrive.
    if (!send(replies)) code = 1;
    // Nothing more waiting: the changes so far are compiled now, once.
    if (!server.exited && queue.empty() && !arrived()) {
      compile_now = true;
      quiet.notify_one();
    }
  }
  stopping = true;
  quiet.notify_one();
  lock.unlock();
  compiler.join();
  in.tie(tied);
  if (write_failed) {
    log << "rcxc lsp: cannot write to the client (the standard output is closed); stopping\n";
    return 1;
  }
  return code >= 0 ? code : server.shutdown && server.exited ? 0 : 1;
}

std::string uri_to_path(const std::string& uri) {
  std::string rest;
  if (uri.rfind("file://localhost/", 0) == 0)
    rest = uri.substr(16);
  else if (uri.rfind("file://", 0) == 0)
    rest = uri.substr(7);
  else
    return uri;  // untitled: and other schemes name no file
  std::string path;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    int hi, lo;
    if (rest[i] == '%' && i + 2 < rest.size() && (hi = hex_value(rest[i + 1])) >= 0 && (lo = hex_value(rest[i + 2])) >= 0) {
      path.push_back(static_cast<char>(hi * 16 + lo));
      i += 2;
    } else {
      path.push_back(rest[i]);
    }
  }
  return path;
}

std::string path_to_uri(const std::string& path) {
  static const char* hex = "0123456789ABCDEF";
  std::string uri = "file://";
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      uri.push_back(static_cast<char>(c));
    } else {
      uri.push_back('%');
      uri.push_back(hex[c >> 4]);
      uri.push_back(hex[c & 15]);
    }
  }
  return uri;
}

}  // namespace rcxc::lsp
