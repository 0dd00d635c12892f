// The language server: LSP requests and notifications in, responses and
// notifications out. All state is in `Server`; `handle` does no I/O, so the
// protocol is tested by feeding it messages, and `serve` adds the framing.
#pragma once

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
};

// Handles one decoded message and returns what to send back, in order.
std::vector<nlohmann::json> handle(Server& server, const nlohmann::json& message);

// The same for a message body as read from the stream: text that is not
// JSON gets a Parse error response (id null).
std::vector<nlohmann::json> handle_text(Server& server, const std::string& body);

// Reads messages from `in` until `exit` or end of input, answering on `out`;
// bad headers are reported on `log` and skipped. Returns the process exit
// code: 0 after shutdown then exit, 1 otherwise (as LSP specifies).
int serve(Server& server, std::istream& in, std::ostream& out, std::ostream& log);

// file:// URIs and paths, with percent-encoding.
std::string uri_to_path(const std::string& uri);
std::string path_to_uri(const std::string& path);

}  // namespace rcxc::lsp
