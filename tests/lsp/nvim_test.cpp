// `rcxc lsp` under a real LSP client: headless Neovim opens a program,
// attaches the server and asks for diagnostics, hover, completion,
// definition, signature help and inlay hints, lists a sub's callers with
// vim.lsp.buf.incoming_calls, formats one line with vim.lsp.buf.range_formatting, searches workspace symbols with
// vim.lsp.buf.workspace_symbol, and renames a sub with vim.lsp.buf.rename
// (tests/lsp/nvim_client.lua). Skipped when nvim is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/support/process.h"

namespace rcxc::test {
namespace {

using nlohmann::json;

std::string find_nvim() {
  auto r = run_process({"/bin/sh", "-c", "command -v nvim"});
  std::string path = r.out.substr(0, r.out.find('\n'));
  return r.exit_code == 0 ? path : "";
}

json run_nvim_client(const TempDir& dir, const std::string& nvim, json config,
                     const std::string& script = RCXC_SOURCE_DIR "/tests/lsp/nvim_client.lua") {
  config["rcxc"] = RCXC_BINARY;
  config["stdlib_dir"] = dir.path + "/stdlib";
  config["out"] = dir.path + "/result.json";
  std::string config_path = dir.write("config.json", config.dump());
  auto r = run_process({nvim, "--headless", "-n", "-i", "NONE", "-u", "NONE", "--cmd",
                        "let g:rcxc_config = '" + config_path + "'", "-c",
                        "luafile " + script},
                       "", 90000);
  EXPECT_FALSE(r.timed_out) << r.err;
  json result = json::parse(read_text_file(dir.path + "/result.json"), nullptr, false);
  EXPECT_FALSE(result.is_discarded()) << "no result from nvim: " << r.out << r.err;
  return result;
}

TEST(NvimClient, DiagnosticsHoverCompletionDefinitionSignatureSymbolsAndRename) {
  std::string nvim = find_nvim();
  if (nvim.empty()) GTEST_SKIP() << "nvim is not installed (apt-get install neovim)";
  TempDir dir;
  std::string file = dir.write("bumper.nqc",
                               "int hits;\n"                 // 0
                               "sub back_off()\n"            // 1
                               "{\n"                         // 2
                               "  OnRev(OUT_A);\n"           // 3
                               "  Wait(50);\n"               // 4
                               "}\n"                         // 5
                               "task main()\n"               // 6
                               "{\n"                         // 7
                               "  back_off();\n"             // 8
                               "  hitz = 1;\n"               // 9
                               "  \n"                        // 10
                               "}\n");                       // 11
  json result = run_nvim_client(dir, nvim,
                                {{"file", file},
                                 {"hover", {4, 3}},        // Wait
                                 {"completion", {10, 2}},  // the empty line in main
                                 {"definition", {8, 4}},   // back_off
                                 {"signature", {4, 7}},    // Wait(|
                                 {"rename", {8, 4}},       // back_off
                                 {"rename_to", "retreat"},
                                 {"symbol_query", "BACK"},
                                 {"callers", {1, 4}},      // back_off's definition
                                 {"untidy", 3},            // OnRev and Wait
                                 {"jump", {3, 4}}});       // OnRev, into the library
  ASSERT_FALSE(result.is_discarded());
  ASSERT_FALSE(result.contains("error")) << result["error"];
  EXPECT_TRUE(result["attached"].get<bool>());

  ASSERT_EQ(result["diagnostics"].size(), 1u) << result.dump();
  const json& d = result["diagnostics"][0];
  EXPECT_EQ(d["message"], "'hitz' is not declared; did you mean 'hits'?");
  EXPECT_EQ(d["lnum"], 9);
  EXPECT_EQ(d["col"], 2);
  EXPECT_EQ(d["end_col"], 6);
  EXPECT_EQ(d["severity"], 1);  // vim.diagnostic.severity.ERROR

  std::string hover = result["hover"].get<std::string>();
  EXPECT_NE(hover.find("void Wait(const int &ticks)"), std::string::npos) << hover;
  EXPECT_NE(hover.find("hundredths of a second"), std::string::npos) << hover;

  std::vector<std::string> labels = result["completion"];
  for (const char* name : {"OnFwd", "OUT_A", "SENSOR_1", "hits", "back_off", "main"})
    EXPECT_NE(std::find(labels.begin(), labels.end(), name), labels.end()) << name;

  EXPECT_EQ(result["definition"]["uri"], "file://" + file);
  EXPECT_EQ(result["definition"]["line"], 1);
  EXPECT_EQ(result["definition"]["character"], 4);

  EXPECT_EQ(result["signature"], "void Wait(const int &ticks)");

  // OnRev(OUT_A) on line 3 and Wait(50) on line 4, each argument's start.
  EXPECT_EQ(result["hints"], json::parse(R"([{"line": 3, "character": 8, "label": "outputs:"},
                                             {"line": 4, "character": 7, "label": "ticks:"}])"));

  // vim.lsp.buf.workspace_symbol: the client lists 'back_off' (line 1,
  // character 4 as LSP counts, 1-based in the quickfix list), nothing of rcx.nqh.
  ASSERT_EQ(result["symbols"].size(), 1u) << result["symbols"].dump();
  EXPECT_EQ(result["symbols"][0]["lnum"], 2);
  EXPECT_EQ(result["symbols"][0]["col"], 5);
  EXPECT_EQ(result["symbols"][0]["text"], "[Method] back_off");

  // vim.lsp.buf.incoming_calls(): main calls back_off on line 8 (9 in the
  // quickfix list), column 3.
  ASSERT_EQ(result["callers"].size(), 1u) << result["callers"].dump();
  EXPECT_EQ(result["callers"][0]["lnum"], 9);
  EXPECT_EQ(result["callers"][0]["col"], 3);
  EXPECT_EQ(result["callers"][0]["text"], "main");

  ASSERT_EQ(result["renamed"].size(), 12u) << result["renamed"].dump();
  EXPECT_EQ(result["renamed"][1], "sub retreat()");
  EXPECT_EQ(result["renamed"][8], "  retreat();");
  EXPECT_EQ(result["renamed"][0], "int hits;");

  // vim.lsp.buf.range_formatting() of the Wait line: OnRev's stays untidy.
  EXPECT_EQ(result["range_formatted"], json::array({"OnRev( OUT_A );", "  Wait(50);"}));

  EXPECT_EQ(result["jump"]["file"], dir.path + "/stdlib/rcx.nqh");
  EXPECT_NE(result["jump"]["text"].get<std::string>().find("void OnRev("), std::string::npos) << result["jump"];
}

// A header edited in one buffer and not saved, the program including it in
// another (tests/lsp/nvim_header.lua): the program knows the name typed
// into the header, and go to definition jumps to the typed line in the
// header's own, still modified, buffer. The server read the header from
// disk: the name was "not declared" and the jump went nowhere. Then a line
// of wide characters is typed in insert mode, sent as incremental changes.
TEST(NvimClient, AnUnsavedHeaderInAnotherBufferIsReadAsTyped) {
  std::string nvim = find_nvim();
  if (nvim.empty()) GTEST_SKIP() << "nvim is not installed (apt-get install neovim)";
  TempDir dir;
  std::string header = dir.write("parts.nqh", "int speed;\n");
  dir.write("main.nqc",
            "#include \"parts.nqh\"\n"              // 0
            "// Grüße 😀: a comment of wide letters\n"  // 1
            "task main()\n"                         // 2
            "{\n"                                   // 3
            "  turn = 2; /* 😀 */ bogus = 1;\n"      // 4
            "  speed = 3;\n"                        // 5
            "}\n");
  json result = run_nvim_client(dir, nvim,
                                {{"dir", dir.path},
                                 {"typed", {"int speed;", "// how long a turn lasts", "int turn;"}},
                                 {"keys", "A // ö😀 x<CR>zap = 1; /* 😀 */ zip = 2;<Esc>"}},
                                RCXC_SOURCE_DIR "/tests/lsp/nvim_header.lua");
  ASSERT_FALSE(result.is_discarded());
  ASSERT_FALSE(result.contains("error")) << result["error"];
  EXPECT_TRUE(result["attached"].get<bool>());
  EXPECT_TRUE(result["header_modified"].get<bool>());
  // Only 'bogus', at byte column 23 as Neovim counts: the server said 21
  // in UTF-16 units (the emoji is two of them and four bytes).
  ASSERT_EQ(result["diagnostics"].size(), 1u) << result["diagnostics"].dump();
  EXPECT_EQ(result["diagnostics"][0]["message"], "'bogus' is not declared");
  EXPECT_EQ(result["diagnostics"][0]["lnum"], 4);
  EXPECT_EQ(result["diagnostics"][0]["col"], 23);
  EXPECT_EQ(result["jump"]["file"], header);
  EXPECT_EQ(result["jump"]["line"], 2);
  EXPECT_EQ(result["jump"]["text"], "int turn;");
  EXPECT_TRUE(result["jump"]["same_buffer"].get<bool>());

  // After typing, the server's text is the buffer's: the names typed are
  // found where Neovim shows them (Neovim indents the new line as the one
  // above; byte columns: zip after the emoji at 22).
  ASSERT_EQ(result["typed"][5], "  speed = 3; // ö😀 x") << result["typed"].dump();
  ASSERT_EQ(result["typed"][6], "  zap = 1; /* 😀 */ zip = 2;");
  EXPECT_EQ(result["after_typing"], json::parse(R"([
    {"lnum": 4, "col": 23, "message": "'bogus' is not declared"},
    {"lnum": 6, "col": 2, "message": "'zap' is not declared"},
    {"lnum": 6, "col": 22, "message": "'zip' is not declared"}])"));
}

}  // namespace
}  // namespace rcxc::test
