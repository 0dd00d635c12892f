// What the editor says about the RCX API: hover and completion show the
// comment above each function and #define of stdlib/rcx.nqh (above a run of
// #defines for a group of constants). Every name must have one, so a name
// added to the library without saying what it means fails here.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "lsp/index.h"
#include "lsp/jsonrpc.h"
#include "lsp/server.h"
#include "stdlib/stdlib.h"
#include "tests/lsp/session.h"
#include "tests/support/process.h"

namespace rcxc::lsp {
namespace {

using nlohmann::json;

// Hover and completion through `rcxc lsp` itself, over its standard input
// and output, as an editor sees them.
TEST(LspApiDocs, HoverInARealSessionSaysWhatTheApiMeans) {
  const std::string text =
      "task main()\n"                            // 0
      "{\n"                                      // 1
      "  SetSensor(SENSOR_1, SENSOR_TOUCH);\n"   // 2
      "  OnFwd(OUT_A);\n"                        // 3
      "  Wait(100);\n"                           // 4
      "  while (Timer(0) < 10);\n"               // 5
      "}\n";                                     // 6
  test::TempDir dir;
  std::string uri = path_to_uri(dir.write("p.nqc", text));
  auto at = [&](int id, const std::string& method, int line, int character) {
    return framed(request(id, method, {{"textDocument", {{"uri", uri}}}, {"position", pos(line, character)}}));
  };
  std::string input =
      framed(request(1, "initialize", {{"processId", nullptr}, {"capabilities", json::object()}})) +
      framed(note("initialized")) +
      framed(note("textDocument/didOpen",
                  {{"textDocument", {{"uri", uri}, {"languageId", "nqc"}, {"version", 1}, {"text", text}}}})) +
      at(2, "textDocument/hover", 3, 3) +    // OnFwd
      at(3, "textDocument/hover", 4, 3) +    // Wait
      at(4, "textDocument/hover", 3, 9) +    // OUT_A
      at(5, "textDocument/hover", 2, 25) +   // SENSOR_TOUCH
      at(6, "textDocument/hover", 5, 10) +   // Timer
      at(7, "textDocument/completion", 4, 2) + framed(request(8, "shutdown")) + framed(note("exit"));
  auto r = test::run_rcxc({"lsp"}, input, 20000);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream out(r.out);
  std::map<int, json> replies;
  for (Frame f = read_frame(out); f.kind == Frame::Kind::Message; f = read_frame(out)) {
    json m = json::parse(f.body);
    if (m.contains("id")) replies[m["id"].get<int>()] = m["result"];
  }
  auto hover = [&](int id) {
    const json& h = replies[id];
    return h.is_null() ? std::string() : h["contents"]["value"].get<std::string>();
  };
  std::string h = hover(2);
  EXPECT_NE(h.find("void OnFwd(const int outputs)"), std::string::npos) << h;
  EXPECT_NE(h.find("forward and turns them on"), std::string::npos) << h;
  h = hover(3);
  EXPECT_NE(h.find("void Wait(const int &ticks)"), std::string::npos) << h;
  EXPECT_NE(h.find("hundredths of a second"), std::string::npos) << h;
  h = hover(4);
  EXPECT_NE(h.find("#define OUT_A 1"), std::string::npos) << h;
  EXPECT_NE(h.find("outputs (motor ports) A, B and C"), std::string::npos) << h;
  h = hover(5);
  EXPECT_NE(h.find("#define SENSOR_TOUCH"), std::string::npos) << h;
  EXPECT_NE(h.find("pressed"), std::string::npos) << h;
  EXPECT_NE(h.find("released"), std::string::npos) << h;
  h = hover(6);
  EXPECT_NE(h.find("tenths of a second on the brick"), std::string::npos) << h;
  bool wait_documented = false;
  for (const auto& item : replies[7]["items"])
    if (item["label"] == "Wait")
      wait_documented = item["documentation"]["value"].get<std::string>().find("hundredths of a second") != std::string::npos;
  EXPECT_TRUE(wait_documented) << replies[7].dump();
}

// The names the library defines, read from its text: a line that starts
// `void NAME` or `#define NAME`.
std::set<std::string> library_names() {
  std::string nqh(stdlib::find("rcx.nqh").value_or(""));
  std::set<std::string> names;
  std::regex def(R"(^(?:void|#define) ([A-Za-z_][A-Za-z0-9_]*))", std::regex::multiline);
  for (std::sregex_iterator it(nqh.begin(), nqh.end(), def), end; it != end; ++it) names.insert((*it)[1]);
  return names;
}

TEST(LspApiDocs, EveryFunctionMacroAndConstantOfTheLibraryHasHoverText) {
  Index index = build_index("/nonexistent/empty.nqc", "task main() {}\n", {});
  std::map<std::string, const Definition*> api;
  for (const Definition& d : index.defs)
    if ((d.kind == DefKind::Function || d.kind == DefKind::Macro) && in_stdlib(index, d.at.begin.file))
      api[d.name] = &d;
  // The index knows every name the text defines, so none escapes the check.
  std::set<std::string> indexed;
  for (const auto& [name, d] : api) indexed.insert(name);
  EXPECT_EQ(indexed, library_names());
  EXPECT_GT(api.size(), 100u);
  for (const auto& [name, d] : api) {
    EXPECT_FALSE(d->doc.empty()) << name << " in rcx.nqh has no comment above it (nothing to show on hover)";
    EXPECT_EQ(d->doc.find("---"), std::string::npos) << name << ": " << d->doc;
  }
  // A note for the library's readers, set apart by an empty line, is not
  // shown: SetOutput's hover says what it does, not how nqc adds bytes.
  ASSERT_TRUE(api.count("SetOutput"));
  EXPECT_EQ(api["SetOutput"]->doc.find("nqc's code picks"), std::string::npos) << api["SetOutput"]->doc;
  EXPECT_NE(api["SetOutput"]->doc.find("OUT_FLOAT"), std::string::npos) << api["SetOutput"]->doc;
}

}  // namespace
}  // namespace rcxc::lsp
