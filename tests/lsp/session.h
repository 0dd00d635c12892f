// A language server driven in-process for the tests of tests/lsp/: the
// messages a client sends, and a session with one open document.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "lsp/server.h"
#include "tests/support/process.h"

namespace rcxc::lsp {

using nlohmann::json;

inline std::string framed(const json& j) {
  std::string body = j.dump();
  return "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

inline json request(int id, const std::string& method, json params = json::object()) {
  return {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", params}};
}

inline json note(const std::string& method, json params = json::object()) {
  return {{"jsonrpc", "2.0"}, {"method", method}, {"params", params}};
}

inline json pos(int line, int character) { return {{"line", line}, {"character", character}}; }

// A server with one open document; `diagnostics` is what didOpen published.
struct Session {
  test::TempDir dir;
  Server server;
  std::string uri;
  json diagnostics;

  explicit Session(const std::string& text, const std::string& name = "prog.nqc", frontend::Options options = {}) {
    server.stdlib_dir = dir.path + "/stdlib-copy";
    server.options = std::move(options);
    EXPECT_EQ(handle(server, request(1, "initialize", {{"capabilities", json::object()}})).size(), 1u);
    EXPECT_TRUE(handle(server, note("initialized")).empty());
    std::string path = dir.write(name, text);
    uri = path_to_uri(path);
    auto out = handle(server, note("textDocument/didOpen", {{"textDocument",
                                                             {{"uri", uri}, {"languageId", "nqc"}, {"version", 1}, {"text", text}}}}));
    EXPECT_EQ(out.size(), 1u);
    if (!out.empty()) diagnostics = out[0]["params"]["diagnostics"];
  }

  json ask(const std::string& method, json params) {
    params["textDocument"] = {{"uri", uri}};
    auto out = handle(server, request(7, method, params));
    EXPECT_EQ(out.size(), 1u);
    if (out.empty()) return nullptr;
    EXPECT_FALSE(out[0].contains("error")) << out[0].dump();
    return out[0]["result"];
  }
  json at(const std::string& method, int line, int character) { return ask(method, {{"position", pos(line, character)}}); }
};

inline json range_at(int line, int begin, int end) { return {{"start", pos(line, begin)}, {"end", pos(line, end)}}; }

// The request's error reply (code and message), or null when it succeeded.
inline json error_of(Session& s, const std::string& method, json params) {
  params["textDocument"] = {{"uri", s.uri}};
  auto out = handle(s.server, request(9, method, params));
  EXPECT_EQ(out.size(), 1u);
  return out.empty() || !out[0].contains("error") ? json(nullptr) : out[0]["error"];
}

// One to four random edits of `text`, each at a random place: a cut of up
// to `longest_cut` bytes, or one byte of `alphabet` put in.
inline void random_edits(std::string& text, std::mt19937& rng, const std::string& alphabet, int longest_cut) {
  auto below = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  for (int e = below(4); e >= 0; --e) {
    std::size_t at = text.empty() ? 0 : static_cast<std::size_t>(below(static_cast<int>(text.size())));
    if (below(2) == 0 && !text.empty())
      text.erase(at, static_cast<std::size_t>(1 + below(longest_cut)));
    else
      text.insert(at, 1, alphabet[static_cast<std::size_t>(below(static_cast<int>(alphabet.size())))]);
  }
}

// (line, character, kind) of each highlight of the name at the position.
inline std::vector<std::tuple<int, int, int>> highlights(Session& s, int line, int character) {
  std::vector<std::tuple<int, int, int>> out;
  for (const auto& h : s.at("textDocument/documentHighlight", line, character))
    out.emplace_back(h["range"]["start"]["line"], h["range"]["start"]["character"], h["kind"]);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace rcxc::lsp
