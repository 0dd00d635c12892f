// JSON-RPC 2.0 over a byte stream with LSP's framing: a header block
// (`Content-Length: N`, optionally `Content-Type`), an empty line, then N
// bytes of JSON.
#pragma once

#include <cstdint>
#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace rcxc::lsp {

// Error codes of JSON-RPC and LSP.
inline constexpr int kParseError = -32700;
inline constexpr int kInvalidRequest = -32600;
inline constexpr int kMethodNotFound = -32601;
inline constexpr int kInvalidParams = -32602;
inline constexpr int kInternalError = -32603;
inline constexpr int kServerNotInitialized = -32002;
inline constexpr int kRequestCancelled = -32800;
inline constexpr int kRequestFailed = -32803;  // a good request the server declines (LSP 3.17)

// The largest message body accepted; a longer one is read past unparsed.
inline constexpr std::size_t kMaxBody = 64u << 20;
// A Content-Length above this is not believed (nothing is skipped for it):
// 10^18 bytes is no message.
inline constexpr std::uint64_t kMaxSkip = 1'000'000'000'000'000'000u;

// Messages nested deeper than this are refused unparsed: nlohmann's JSON
// is copied, printed and freed recursively, a call a level, so a message of
// a million brackets overflowed the stack (rcxc debug and rcxc lsp both
// died of SIGSEGV). No LSP or DAP message comes near it.
inline constexpr int kMostNesting = 100;
// How deeply `text` nests arrays and objects (brackets in strings do not
// count).
int json_nesting(std::string_view text);

struct Frame {
  enum class Kind { Message, BadHeader, End } kind = Kind::End;
  std::string body;   // Message: the JSON text
  // BadHeader: what was wrong; End: why, when the input ended inside a
  // message; Message: what was odd in its header but could be read past.
  std::string error;
};

// Reads the next frame. A header block without a usable Content-Length, or
// with two that differ, is reported (and skipped) as BadHeader; End at end
// of input (with an error when it ended inside a message: that message is
// lost).
Frame read_frame(std::istream& in);

// Writes one message with its header and flushes.
void write_message(std::ostream& out, const nlohmann::json& message);

nlohmann::json response(const nlohmann::json& id, nlohmann::json result);
nlohmann::json error_response(const nlohmann::json& id, int code, const std::string& message);
nlohmann::json notification(const std::string& method, nlohmann::json params);

}  // namespace rcxc::lsp
