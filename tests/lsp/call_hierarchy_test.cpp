// Call hierarchy: which tasks, subs and functions call (or start) which.
// Every expected line and character is counted by hand from the test text
// (LSP counts from 0).
#include <gtest/gtest.h>

#include <tuple>

#include "tests/lsp/session.h"

namespace rcxc::lsp {
namespace {

const char* const kProgram =
    "void beep() { PlayTone(440, 10); }\n"  // 0
    "sub turn()\n"                          // 1
    "{\n"                                   // 2
    "  beep();\n"                           // 3
    "  Wait(20);\n"                         // 4
    "}\n"                                   // 5
    "task patrol()\n"                       // 6
    "{\n"                                   // 7
    "  while (true) { turn(); beep(); turn(); }\n"  // 8
    "}\n"                                   // 9
    "task main()\n"                         // 10
    "{\n"                                   // 11
    "  int turn_count = 0;\n"               // 12
    "  start patrol;\n"                     // 13
    "  beep();\n"                           // 14
    "}\n";                                  // 15

// (name, [(line, character) of each range's start])
using Calls = std::vector<std::pair<std::string, std::vector<std::pair<int, int>>>>;

Calls calls(Session& s, const std::string& method, const json& item, const char* key) {
  auto out = handle(s.server, request(8, method, {{"item", item}}));
  EXPECT_EQ(out.size(), 1u);
  Calls list;
  for (const auto& c : out.at(0)["result"]) {
    std::vector<std::pair<int, int>> at;
    for (const auto& r : c["fromRanges"]) at.emplace_back(r["start"]["line"], r["start"]["character"]);
    list.emplace_back(c[key]["name"], at);
  }
  return list;
}

json prepared(Session& s, int line, int character) {
  json items = s.at("textDocument/prepareCallHierarchy", line, character);
  EXPECT_TRUE(items.is_array() && items.size() == 1u) << items.dump();
  return items.is_array() && !items.empty() ? items[0] : json();
}

TEST(LspCallHierarchy, PreparesTheCallableUnderTheCursorFromAUseOrItsDefinition) {
  Session s(kProgram);
  json item = prepared(s, 8, 18);  // `turn` in patrol's loop
  EXPECT_EQ(item["name"], "turn");
  EXPECT_EQ(item["kind"], 6);  // Method, as document symbols call subs
  EXPECT_EQ(item["uri"], s.uri);
  EXPECT_EQ(item["selectionRange"], range_at(1, 4, 8));
  // The whole sub, from its name (as document symbols give it) to its '}'.
  EXPECT_EQ(item["range"]["start"], pos(1, 4));
  EXPECT_EQ(item["range"]["end"]["line"], 5);
  EXPECT_EQ(prepared(s, 6, 7)["name"], "patrol");
  // A variable, a keyword and the empty space are not callables.
  EXPECT_TRUE(s.at("textDocument/prepareCallHierarchy", 12, 7).is_null());
  EXPECT_TRUE(s.at("textDocument/prepareCallHierarchy", 8, 4).is_null());
  EXPECT_TRUE(s.at("textDocument/prepareCallHierarchy", 15, 0).is_null());
}

TEST(LspCallHierarchy, IncomingCallsGroupTheCallsByCaller) {
  Session s(kProgram);
  EXPECT_EQ(calls(s, "callHierarchy/incomingCalls", prepared(s, 0, 6), "from"),
            (Calls{{"turn", {{3, 2}}}, {"patrol", {{8, 25}}}, {"main", {{14, 2}}}}));
  EXPECT_EQ(calls(s, "callHierarchy/incomingCalls", prepared(s, 1, 5), "from"), (Calls{{"patrol", {{8, 17}, {8, 33}}}}));
  // `start patrol;` is how a task is called.
  EXPECT_EQ(calls(s, "callHierarchy/incomingCalls", prepared(s, 6, 6), "from"), (Calls{{"main", {{13, 8}}}}));
  EXPECT_EQ(calls(s, "callHierarchy/incomingCalls", prepared(s, 10, 6), "from"), Calls{});
}

TEST(LspCallHierarchy, OutgoingCallsIncludeTheApiButNotVariablesOrTheOwnName) {
  Session s(kProgram);
  EXPECT_EQ(calls(s, "callHierarchy/outgoingCalls", prepared(s, 10, 6), "to"),
            (Calls{{"patrol", {{13, 8}}}, {"beep", {{14, 2}}}}));
  EXPECT_EQ(calls(s, "callHierarchy/outgoingCalls", prepared(s, 6, 6), "to"),
            (Calls{{"turn", {{8, 17}, {8, 33}}}, {"beep", {{8, 25}}}}));
  // The API's functions are where rcx.nqh defines them.
  json to = handle(s.server, request(8, "callHierarchy/outgoingCalls", {{"item", prepared(s, 1, 5)}})).at(0)["result"];
  ASSERT_EQ(to.size(), 2u) << to.dump();
  EXPECT_EQ(to[1]["to"]["name"], "Wait");
  EXPECT_NE(to[1]["to"]["uri"].get<std::string>().find("rcx.nqh"), std::string::npos);
  EXPECT_EQ(to[1]["fromRanges"], json::array({range_at(4, 2, 6)}));
}

TEST(LspCallHierarchy, ItemsOfAClosedDocumentOrAGoneNameGetNullAndBadItemsAnError) {
  Session s(kProgram);
  json item = prepared(s, 0, 6);
  // Without `data`, the item's own uri and name serve.
  json bare = item;
  bare.erase("data");
  EXPECT_EQ(calls(s, "callHierarchy/incomingCalls", bare, "from").size(), 3u);
  // The sub renamed since: nothing to answer.
  std::string text = kProgram;
  text.replace(text.find("beep"), 4, "bleep");
  handle(s.server, note("textDocument/didChange", {{"textDocument", {{"uri", s.uri}, {"version", 2}}},
                                                  {"contentChanges", json::array({{{"text", text}}})}}));
  auto out = handle(s.server, request(8, "callHierarchy/outgoingCalls", {{"item", item}}));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0]["result"].is_null()) << out[0].dump();
  handle(s.server, note("textDocument/didClose", {{"textDocument", {{"uri", s.uri}}}}));
  out = handle(s.server, request(8, "callHierarchy/incomingCalls", {{"item", item}}));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0]["result"].is_null()) << out[0].dump();
  out = handle(s.server, request(8, "callHierarchy/incomingCalls", {{"item", {{"name", 3}}}}));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["error"]["code"], -32602) << out[0].dump();
}

}  // namespace
}  // namespace rcxc::lsp
