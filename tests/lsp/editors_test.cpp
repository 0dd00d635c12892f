// The editor files under editors/: the JSON of the VS Code extension parses
// and declares the server's own semantic token modifiers, its grammar's
// patterns compile, every API name of stdlib/rcx.nqh is in the
// vim, VS Code and Emacs highlighting, the problem matchers read rcxc's real
// messages, and the vim files load in headless Neovim, where :make fills the
// quickfix list through the errorformat.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "lsp/server.h"
#include "tests/support/process.h"

namespace rcxc::test {
namespace {

using nlohmann::json;

const std::string kEditors = RCXC_SOURCE_DIR "/editors/";

json read_json(const std::string& path) {
  std::string text = read_text_file(path);
  EXPECT_FALSE(text.empty()) << path;
  json j = json::parse(text, nullptr, false);
  EXPECT_FALSE(j.is_discarded()) << path << " is not valid JSON";
  return j;
}

// Every name of the API: inline functions and macros of rcx.nqh.
std::vector<std::string> api_names() {
  std::string nqh = read_text_file(RCXC_SOURCE_DIR "/stdlib/rcx.nqh");
  std::vector<std::string> names;
  std::regex def(R"(^(?:void|#define) ([A-Za-z_][A-Za-z0-9_]*))", std::regex::multiline);
  for (std::sregex_iterator it(nqh.begin(), nqh.end(), def), end; it != end; ++it) names.push_back((*it)[1]);
  return names;
}

bool has_word(const std::string& text, const std::string& word) {
  return std::regex_search(text, std::regex("(^|[^A-Za-z0-9_])" + word + "($|[^A-Za-z0-9_])"));
}

TEST(Editors, VsCodeFilesAreValidJson) {
  json package = read_json(kEditors + "vscode/package.json");
  EXPECT_EQ(package["contributes"]["languages"][0]["id"], "nqc");
  EXPECT_EQ(package["contributes"]["grammars"][0]["path"], "./syntaxes/nqc.tmLanguage.json");
  read_json(kEditors + "vscode/language-configuration.json");
  json tasks = read_json(kEditors + "vscode/tasks.json");
  std::set<std::string> commands;
  for (const auto& t : tasks["tasks"]) commands.insert(t["args"][0].get<std::string>());
  EXPECT_EQ(commands, (std::set<std::string>{"compile", "run", "test", "download"}));
}

// Patterns are Oniguruma; the ones used here are also valid ECMAScript, which
// std::regex checks.
void check_patterns(const json& node, int& count) {
  if (node.is_object()) {
    for (const char* key : {"match", "begin", "end"})
      if (node.contains(key)) {
        ++count;
        EXPECT_NO_THROW(std::regex(node[key].get<std::string>())) << node[key];
      }
    for (const auto& [k, v] : node.items()) check_patterns(v, count);
  } else if (node.is_array()) {
    for (const auto& v : node) check_patterns(v, count);
  }
}

// VS Code styles only the semantic token modifiers it knows: the LSP's own
// and those an extension declares. Every other one `rcxc lsp` announces is
// declared by the extension.
TEST(Editors, VsCodeDeclaresTheServersOwnTokenModifiers) {
  lsp::Server server;
  json legend = lsp::handle(server, {{"jsonrpc", "2.0"}, {"id", 1}, {"method", "initialize"}, {"params", json::object()}})
                    .at(0)["result"]["capabilities"]["semanticTokensProvider"]["legend"];
  const std::set<std::string> standard = {"declaration", "definition",   "readonly",     "static",
                                          "deprecated",  "abstract",     "async",        "modification",
                                          "documentation", "defaultLibrary"};
  std::set<std::string> declared;
  json package = read_json(kEditors + "vscode/package.json");
  for (const auto& m : package["contributes"]["semanticTokenModifiers"]) declared.insert(m["id"].get<std::string>());
  ASSERT_FALSE(legend["tokenModifiers"].empty());
  for (const auto& m : legend["tokenModifiers"]) {
    std::string name = m.get<std::string>();
    EXPECT_TRUE(standard.contains(name) || declared.contains(name)) << name;
  }
}

TEST(Editors, TextMateGrammarParsesAndItsPatternsCompile) {
  json grammar = read_json(kEditors + "vscode/syntaxes/nqc.tmLanguage.json");
  EXPECT_EQ(grammar["scopeName"], "source.nqc");
  int count = 0;
  check_patterns(grammar, count);
  EXPECT_GT(count, 15);
  // Every #include of the repository is defined.
  std::string text = grammar.dump();
  std::regex include("\"#([a-z]+)\"");
  for (std::sregex_iterator it(text.begin(), text.end(), include), end; it != end; ++it)
    EXPECT_TRUE(grammar["repository"].contains((*it)[1].str())) << (*it)[1];
}

TEST(Editors, EveryApiNameIsHighlightedEverywhere) {
  auto names = api_names();
  ASSERT_GT(names.size(), 80u);
  std::string vim = read_text_file(kEditors + "vim/syntax/nqc.vim");
  std::string grammar = read_text_file(kEditors + "vscode/syntaxes/nqc.tmLanguage.json");
  std::string emacs = read_text_file(kEditors + "emacs/nqc-mode.el");
  for (const auto& n : names) {
    if (n.rfind("__", 0) == 0) continue;
    EXPECT_TRUE(has_word(vim, n)) << n << " missing from editors/vim/syntax/nqc.vim";
    EXPECT_TRUE(has_word(grammar, n)) << n << " missing from editors/vscode/syntaxes/nqc.tmLanguage.json";
    EXPECT_TRUE(has_word(emacs, "\"" + n + "\"") || has_word(emacs, n)) << n << " missing from editors/emacs/nqc-mode.el";
  }
}

TEST(Editors, ProblemMatchersReadRcxcsMessages) {
  TempDir dir;
  std::string file = dir.write("bad.nqc", "task main()\n{\n  OnFwd(OUT_A);\n  speed = 3;\n}\n");
  auto r = run_rcxc({"compile", file, "-o", "/dev/null"});
  ASSERT_EQ(r.exit_code, 1);
  std::string first = r.err.substr(0, r.err.find('\n'));
  json package = read_json(kEditors + "vscode/package.json");
  const json& matcher = package["contributes"]["problemMatchers"][0];
  std::smatch m;
  std::regex re(matcher["pattern"]["regexp"].get<std::string>());
  ASSERT_TRUE(std::regex_match(first, m, re)) << first;
  EXPECT_EQ(m[matcher["pattern"]["file"].get<int>()], file);
  EXPECT_EQ(m[matcher["pattern"]["line"].get<int>()], "4");
  EXPECT_EQ(m[matcher["pattern"]["column"].get<int>()], "3");
  EXPECT_EQ(m[matcher["pattern"]["severity"].get<int>()], "error");
}

std::string find_program(const std::string& name) {
  auto r = run_process({"/bin/sh", "-c", "command -v " + name});
  return r.exit_code == 0 ? r.out.substr(0, r.out.find('\n')) : "";
}

TEST(Editors, VimFilesLoadInHeadlessNeovimAndMakeFindsTheError) {
  std::string nvim = find_program("nvim");
  if (nvim.empty()) GTEST_SKIP() << "nvim is not installed (apt-get install neovim)";
  TempDir dir;
  std::string file = dir.write("bad.nqc", "task main()\n{\n  OnFwd(OUT_A);\n  speed = 3;\n}\n");
  std::string out = dir.path + "/result.json";
  auto r = run_process({nvim, "--headless", "-n", "-i", "NONE", "-u", "NONE", "--cmd",
                        "set rtp^=" + kEditors + "vim", "--cmd", "let g:nqc_file = '" + file + "'", "--cmd",
                        "let g:rcxc = '" RCXC_BINARY "'", "--cmd", "let g:api_line = 3", "--cmd",
                        "let g:api_col = 3", "--cmd", "let g:out = '" + out + "'", "-c", "filetype plugin on",
                        "-c", "syntax on", "-c", "source " RCXC_SOURCE_DIR "/tests/lsp/nvim_editor.vim"},
                       "", 60000);
  ASSERT_FALSE(r.timed_out);
  json result = json::parse(read_text_file(out), nullptr, false);
  ASSERT_FALSE(result.is_discarded()) << r.out << r.err;
  ASSERT_FALSE(result.contains("exception")) << result["exception"];
  EXPECT_EQ(result["filetype"], "nqc");
  EXPECT_EQ(result["syntax"], "nqc");
  EXPECT_EQ(result["errmsg"], "");
  EXPECT_EQ(result["commentstring"], "// %s");
  EXPECT_NE(result["makeprg"].get<std::string>().find("rcxc compile"), std::string::npos);
  EXPECT_EQ(result["api_group"], "nqcApiFunction");  // OnFwd
  ASSERT_EQ(result["qf"].size(), 1u) << result.dump();
  const json& e = result["qf"][0];
  EXPECT_EQ(e["valid"], 1);
  EXPECT_EQ(e["lnum"], 4);
  EXPECT_EQ(e["col"], 3);
  EXPECT_EQ(e["type"], "e");  // %t keeps the letter as matched; vim reads e as an error
  EXPECT_EQ(e["text"], "'speed' is not declared");
  EXPECT_EQ(e["file"], file);
}

// The VS Code extension under node with the two modules it needs stubbed:
// `${workspaceFolder}` in rcxc.includeDirs (as docs/editors.md shows it)
// and a relative folder reach the server as folders of the workspace, and
// a changed rcxc setting restarts the server with the new folders. Both
// were passed as written (`-I ${workspaceFolder}/include`), a folder that
// does not exist, and a change waited for the next window. Launch
// configurations of type "rcxc" start `rcxc debug` (rcxc.path's executable).
TEST(Editors, VsCodeExtensionResolvesIncludeDirsAndRestartsOnChange) {
  std::string node = find_program("node");
  if (node.empty()) GTEST_SKIP() << "node is not installed";
  TempDir dir;
  std::filesystem::create_directories(dir.path + "/node_modules/vscode");
  std::filesystem::create_directories(dir.path + "/node_modules/vscode-languageclient");
  dir.write("node_modules/vscode/index.js", R"(
let dirs = ['${workspaceFolder}/include', 'lib', '/abs/inc'];
let handler;
module.exports = {
  workspace: {
    workspaceFolders: [{ uri: { fsPath: '/proj/robot' } }],
    getConfiguration: () => ({ get: (key, fallback) => (key === 'includeDirs' ? dirs : fallback) }),
    onDidChangeConfiguration: (h) => { handler = h; return { dispose() {} }; },
  },
  setDirs: (d) => { dirs = d; },
  fire: (section) => handler({ affectsConfiguration: (s) => s === section }),
  debug: { registerDebugAdapterDescriptorFactory: (type, f) => { module.exports.adapters[type] = f; return { dispose() {} }; } },
  DebugAdapterExecutable: class { constructor(command, args) { this.command = command; this.args = args; } },
  adapters: {},
};
)");
  dir.write("node_modules/vscode-languageclient/node.js", R"(
const log = [];
class LanguageClient {
  constructor(id, name, server) { this.args = server.args; log.push({ started: server.args }); }
  start() { return Promise.resolve(); }
  stop() { log.push({ stopped: this.args }); return Promise.resolve(); }
}
module.exports = { LanguageClient, TransportKind: { stdio: 0 }, log };
)");
  dir.write("run.js", R"(
const vscode = require('vscode');
const { log } = require('vscode-languageclient/node');
const ext = require(process.argv[2]);
(async () => {
  await ext.activate({ subscriptions: [] });
  await vscode.fire('editor.fontSize');
  vscode.setDirs(['${workspaceFolder}/other']);
  await vscode.fire('rcxc.includeDirs');
  const adapter = vscode.adapters.rcxc.createDebugAdapterDescriptor({});
  log.push({ debug: [adapter.command].concat(adapter.args) });
  console.log(JSON.stringify(log));
})();
)");
  auto r = run_process({"/bin/sh", "-c",
                        "cd '" + dir.path + "' && NODE_PATH='" + dir.path + "/node_modules' '" + node + "' run.js '" +
                            kEditors + "vscode/extension.js'"},
                       "", 30000);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  json log = json::parse(r.out, nullptr, false);
  ASSERT_FALSE(log.is_discarded()) << r.out << r.err;
  EXPECT_EQ(log, json::parse(R"([
    {"started": ["lsp", "-I", "/proj/robot/include", "-I", "/proj/robot/lib", "-I", "/abs/inc"]},
    {"stopped": ["lsp", "-I", "/proj/robot/include", "-I", "/proj/robot/lib", "-I", "/abs/inc"]},
    {"started": ["lsp", "-I", "/proj/robot/other"]},
    {"debug": ["rcxc", "debug"]}])"));
}

}  // namespace
}  // namespace rcxc::test
