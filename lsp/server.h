// The language server: LSP requests and notifications in, responses and
// notifications out. All state is in `Server`; `handle` does no I/O, so the
// protocol is tested by feeding it messages, and `serve` adds the framing.
#pragma once

#include <cstdint>
#include <istream>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "frontend/frontend.h"
#include "lsp/index.h"

namespace rcxc::lsp {

struct Document {
  std::string path;  // the file the URI names (includes are searched next to it)
  std::string text;
  std::int64_t version = 0;
  Index index;
  // The text changed since `index` was built (only with Server::defer_index).
  bool stale = false;
  // Counts the changes (its own and its includes'), so that an index built
  // in the background is kept only if nothing changed meanwhile.
  std::uint64_t generation = 0;
  std::uint64_t index_generation = 0;  // the generation `index` was built from
  std::uint64_t opened = 0;            // the generation of its didOpen
};

struct Server {
  frontend::Options options;  // -I, -D as `rcxc lsp` was started (and initializationOptions.includeDirs)
  WarningPolicy warnings;     // -W options as `rcxc lsp` was started (and initializationOptions.warnings)
  std::string version;        // reported in serverInfo
  // Where go to definition shows the standard library: the compiler embeds
  // it, so a copy is written here when first needed ("" = a cache folder).
  std::string stdlib_dir;
  std::map<std::string, Document> documents;  // by URI
  bool initialized = false;
  bool shutdown = false;  // `shutdown` was received
  bool exited = false;    // `exit` was received: stop reading
  // didOpen, didChange and didSave only take the text and mark the document
  // stale; it is compiled (and its diagnostics published) by the first
  // request about it or by `flush_stale`. `serve` sets it: compiling on every
  // keystroke queued the keystrokes of a large file behind each other. When
  // false (`handle` alone, as tests drive it), every change is compiled at once.
  bool defer_index = false;
  std::uint64_t changes = 0;  // the last Document::generation given
  // -I and -W as `rcxc lsp` was started, before the client's settings
  // (initializationOptions, then workspace/didChangeConfiguration) add theirs.
  std::vector<std::string> started_include_dirs;
  WarningPolicy started_warnings;
};

// Handles one decoded message and returns what to send back, in order.
std::vector<nlohmann::json> handle(Server& server, const nlohmann::json& message);

// The same for a message body as read from the stream: text that is not
// JSON gets a Parse error response (id null).
std::vector<nlohmann::json> handle_text(Server& server, const std::string& body);

// Compiles every stale document and returns their diagnostics to publish.
std::vector<nlohmann::json> flush_stale(Server& server);

// Reads messages from `in` until `exit` or end of input, answering on `out`;
// bad headers are reported on `log` and skipped. Returns the process exit
// code: 0 after shutdown then exit, 1 otherwise (as LSP specifies).
// Messages that have already arrived are read ahead (what `in_avail` says is
// there, up to kMaxBody bytes), so that the documents are compiled once the
// input is quiet, not once per change, and a request cancelled by a
// `$/cancelRequest` already waiting is answered RequestCancelled unrun.
// Those compilations run on a thread of their own, which publishes the
// diagnostics, so that changes and completion are taken meanwhile;
// completion answers from the last compiled text, other requests about a
// changed document compile it first.
int serve(Server& server, std::istream& in, std::ostream& out, std::ostream& log);

// file:// URIs and paths, with percent-encoding.
std::string uri_to_path(const std::string& uri);
std::string path_to_uri(const std::string& path);

}  // namespace rcxc::lsp
