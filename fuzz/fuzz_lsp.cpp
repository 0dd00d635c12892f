// Bytes as what a language client sends `rcxc lsp`: `lsp::serve` reads them
// from a string stream, as it reads standard input, and every frame it
// writes back must be a JSON-RPC message (a response with exactly one of
// result and error, or a notification with a method and params), with
// every range in it well formed (non-negative, start not after end).
//
// First byte: mode. Bit 0 clear: the rest is the raw byte stream (headers,
// bodies, garbage). Bit 0 set: the rest is JSON bodies separated by 0x1e
// (a byte JSON text cannot hold unescaped), each framed with its exact
// Content-Length, so mutations of a seed reach the requests instead of
// breaking the framing; then each request (an id that is a string or an
// integer) read before `exit` must get exactly one response with its id,
// in order. Bit 1 starts the server as `rcxc lsp -n` (no rcx.nqh: faster,
// and another path through the front end).
//
// The copy of rcx.nqh that go to definition writes goes to a temporary
// folder (XDG_CACHE_HOME points there too); includes are read from wherever
// a fuzzed URI points, as the server would, but nothing else is written.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "lsp/jsonrpc.h"
#include "lsp/server.h"

namespace {

using nlohmann::json;

std::string g_stdlib_dir;

[[noreturn]] void fail(const std::string& why, const std::string& what) {
  std::fprintf(stderr, "fuzz_lsp: %s\n%.4000s\n", why.c_str(), what.c_str());
  std::abort();
}

bool is_position(const json& p) {
  return p.is_object() && p.contains("line") && p.contains("character") && p["line"].is_number_unsigned() &&
         p["character"].is_number_unsigned();
}

// Every object with "start" and "end" positions anywhere in a reply.
void check_ranges(const json& j, const std::string& whole) {
  if (j.is_object()) {
    if (j.contains("start") && j.contains("end") && j.size() == 2) {
      if (!is_position(j["start"]) || !is_position(j["end"])) fail("a range with a bad position", whole);
      auto key = [](const json& p) { return std::pair(p["line"].get<std::uint64_t>(), p["character"].get<std::uint64_t>()); };
      if (key(j["end"]) < key(j["start"])) fail("a range that ends before it starts", whole);
    }
    for (const auto& [k, v] : j.items()) check_ranges(v, whole);
  } else if (j.is_array()) {
    for (const auto& v : j) check_ranges(v, whole);
  }
}

// The server's output as messages; aborts on anything that is not JSON-RPC.
std::vector<json> replies_of(const std::string& out) {
  std::vector<json> replies;
  std::istringstream in(out);
  while (true) {
    rcxc::lsp::Frame f = rcxc::lsp::read_frame(in);
    if (f.kind == rcxc::lsp::Frame::Kind::End) break;
    if (f.kind != rcxc::lsp::Frame::Kind::Message) fail("a reply with a bad header: " + f.error, out);
    json j = json::parse(f.body, nullptr, false);
    if (j.is_discarded() || !j.is_object()) fail("a reply that is not a JSON object", f.body);
    if (j.value("jsonrpc", "") != "2.0") fail("a reply without jsonrpc 2.0", f.body);
    bool has_id = j.contains("id");
    bool has_result = j.contains("result"), has_error = j.contains("error");
    if (has_id) {
      if (j.contains("method") || has_result == has_error) fail("a response without exactly one of result, error", f.body);
      if (!j["id"].is_null() && !j["id"].is_string() && !j["id"].is_number_integer()) fail("a bad response id", f.body);
      if (has_error && (!j["error"].is_object() || !j["error"].contains("code") || !j["error"]["code"].is_number_integer() ||
                        !j["error"].contains("message") || !j["error"]["message"].is_string()))
        fail("a malformed error", f.body);
    } else if (!j.contains("method") || !j["method"].is_string() || !j.contains("params") || has_result || has_error) {
      fail("neither a response nor a notification", f.body);
    }
    check_ranges(j, f.body);
    replies.push_back(std::move(j));
  }
  return replies;
}

std::string framed(const std::string& body) {
  return "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  char dir[] = "/tmp/fuzz_lsp.XXXXXX";
  if (!mkdtemp(dir)) std::abort();
  g_stdlib_dir = dir;
  setenv("XDG_CACHE_HOME", dir, 1);
  // Fork mode starts a process per job: each would leave a folder behind.
  std::atexit([] {
    std::error_code ec;
    std::filesystem::remove_all(g_stdlib_dir, ec);
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t mode = data[0];
  const std::string rest(reinterpret_cast<const char*>(data + 1), size - 1);

  rcxc::lsp::Server server;
  server.stdlib_dir = g_stdlib_dir;
  server.version = "fuzz";
  server.options.no_stdlib = (mode & 2) != 0;

  std::string stream;
  // Structured mode: the ids of the requests read before `exit`, which must
  // be answered in this order.
  std::vector<json> expected_ids;
  const bool structured = (mode & 1) != 0;
  if (!structured) {
    stream = rest;
  } else {
    bool exited = false;
    std::size_t start = 0;
    while (start <= rest.size()) {
      std::size_t end = rest.find('\x1e', start);
      if (end == std::string::npos) end = rest.size();
      std::string body = rest.substr(start, end - start);
      start = end + 1;
      stream += framed(body);
      if (exited) continue;
      json j = json::parse(body, nullptr, false);
      if (j.is_discarded()) {
        expected_ids.push_back(nullptr);  // Parse error
      } else if (j.is_object() && j.contains("method") && j["method"].is_string()) {
        if (!j.contains("id")) {
          exited = j["method"] == "exit";
        } else {
          const json& id = j["id"];
          expected_ids.push_back(id.is_string() || id.is_number_integer() ? id : json(nullptr));
        }
      } else if (!(j.is_object() && j.contains("id") && !j.contains("method") &&
                   (j.contains("result") || j.contains("error")))) {
        // Invalid Request, answered with the id when there is one.
        bool usable = j.is_object() && j.contains("id") && (j["id"].is_string() || j["id"].is_number_integer());
        expected_ids.push_back(usable ? j["id"] : json(nullptr));
      }
    }
  }

  std::istringstream in(stream);
  std::ostringstream out, log;
  int code = rcxc::lsp::serve(server, in, out, log);
  if (code != 0 && code != 1) fail("exit code " + std::to_string(code), stream);
  if ((code == 0) != (server.shutdown && server.exited)) fail("exit code against the lifecycle", stream);

  std::vector<json> replies = replies_of(out.str());
  if (structured) {
    std::vector<json> ids;
    for (const auto& r : replies)
      if (r.contains("id")) ids.push_back(r["id"]);
    if (ids != expected_ids) fail("responses " + json(ids).dump() + " for requests " + json(expected_ids).dump(), stream);
  }
  return 0;
}
