// Where `rcxc lsp` writes the copy of rcx.nqh that go to definition opens,
// run as an editor runs it, with the environment it is given: a cache that
// cannot take the copy (XDG_CACHE_HOME=/dev/null) left go to definition
// answering null, and a relative XDG_CACHE_HOME made folders in whatever
// folder the editor had been started in.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/process.h"

namespace {

using nlohmann::json;
using rcxc::test::run_process;
using rcxc::test::TempDir;

std::string message(const json& j) {
  std::string body = j.dump();
  return "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

// Go to definition on PlaySound, in a server run with `env`; the URI of the
// answer, or "" when there is none.
std::string definition_uri(const std::vector<std::string>& env, const std::string& cwd) {
  std::string in =
      message({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "initialize"}, {"params", {{"capabilities", json::object()}}}}) +
      message({{"jsonrpc", "2.0"}, {"method", "initialized"}, {"params", json::object()}}) +
      message({{"jsonrpc", "2.0"},
               {"method", "textDocument/didOpen"},
               {"params",
                {{"textDocument",
                  {{"uri", "file:///p.nqc"},
                   {"languageId", "nqc"},
                   {"version", 1},
                   {"text", "task main()\n{\n  PlaySound(SOUND_CLICK);\n}\n"}}}}}}) +
      message({{"jsonrpc", "2.0"},
               {"id", 2},
               {"method", "textDocument/definition"},
               {"params", {{"textDocument", {{"uri", "file:///p.nqc"}}}, {"position", {{"line", 2}, {"character", 4}}}}}}) +
      message({{"jsonrpc", "2.0"}, {"id", 3}, {"method", "shutdown"}}) + message({{"jsonrpc", "2.0"}, {"method", "exit"}});
  std::vector<std::string> args = {"/usr/bin/env", "-C", cwd, "-u", "XDG_CACHE_HOME", "-u", "HOME"};
  args.insert(args.end(), env.begin(), env.end());
  args.insert(args.end(), {RCXC_BINARY, "lsp"});
  auto r = run_process(args, in, 20'000);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // The answer to request 2 among the messages on stdout.
  for (std::size_t at = r.out.find("Content-Length: "); at != std::string::npos;
       at = r.out.find("Content-Length: ", at + 1)) {
    std::size_t body = r.out.find("\r\n\r\n", at) + 4;
    std::size_t length = std::stoul(r.out.substr(at + 16));
    json j = json::parse(r.out.substr(body, length), nullptr, false);
    if (j.is_object() && j.value("id", 0) == 2)
      return j["result"].is_object() ? j["result"].value("uri", "") : "";
  }
  return "";
}

TEST(LspStdlibCopy, ACacheThatCannotTakeTheCopyFallsToTheNext) {
  TempDir home;
  std::string uri = definition_uri({"XDG_CACHE_HOME=/dev/null", "HOME=" + home.path}, home.path);
  EXPECT_EQ(uri.rfind("file://" + home.path + "/.cache/rcxc/stdlib-", 0), 0u) << uri;
  EXPECT_TRUE(uri.ends_with("/rcx.nqh")) << uri;
}

TEST(LspStdlibCopy, ARelativeXdgCacheHomeIsIgnored) {
  TempDir home, cwd;
  std::string uri = definition_uri({"XDG_CACHE_HOME=relative/cache", "HOME=" + home.path}, cwd.path);
  EXPECT_EQ(uri.rfind("file://" + home.path + "/.cache/rcxc/stdlib-", 0), 0u) << uri;
  EXPECT_FALSE(std::filesystem::exists(cwd.path + "/relative")) << "a folder was made in the working folder";
}

}  // namespace
