// textDocument/formatting: one edit replacing the whole document, none when
// it is already formatted, an error with the formatter's message when the
// text cannot be formatted. textDocument/rangeFormatting: edits of the
// selected lines only.
#include <gtest/gtest.h>

#include <optional>

#include "lsp/jsonrpc.h"
#include "lsp/server.h"

namespace rcxc::lsp {
namespace {

using nlohmann::json;

json message(const std::string& method, json params, std::optional<int> id = std::nullopt) {
  json m = {{"jsonrpc", "2.0"}, {"method", method}, {"params", std::move(params)}};
  if (id) m["id"] = *id;
  return m;
}

const std::string kUri = "file:///tmp/formatting-test.nqc";

// A server that says it has `capability` and has `text` open as kUri.
void open_document(Server& server, const std::string& text, const char* capability) {
  auto init = handle(server, message("initialize", {{"capabilities", json::object()}}, 1));
  EXPECT_EQ(init.at(0)["result"]["capabilities"][capability], true);
  handle(server, message("initialized", json::object()));
  handle(server, message("textDocument/didOpen",
                         {{"textDocument", {{"uri", kUri}, {"languageId", "nqc"}, {"version", 1}, {"text", text}}}}));
}

// The reply to textDocument/formatting of `text` (opened as a document).
json format_reply(const std::string& text, json options = {{"tabSize", 2}, {"insertSpaces", true}}) {
  Server server;
  open_document(server, text, "documentFormattingProvider");
  auto out = handle(server, message("textDocument/formatting", {{"textDocument", {{"uri", kUri}}}, {"options", options}}, 2));
  EXPECT_EQ(out.size(), 1u);
  return out.empty() ? json() : out[0];
}

TEST(LspFormatting, OneEditReplacesTheWholeDocument) {
  json reply = format_reply("task main() {\nWait(1);\n}\n// \xc3\xa9t\xc3\xa9 \xf0\x9f\x98\x80");
  ASSERT_TRUE(reply.contains("result")) << reply.dump();
  const json& edits = reply["result"];
  ASSERT_EQ(edits.size(), 1u);
  EXPECT_EQ(edits[0]["newText"], "task main()\n{\n  Wait(1);\n}\n// \xc3\xa9t\xc3\xa9 \xf0\x9f\x98\x80\n");
  // The end of the text: line 3, after "// été 😀": 9 UTF-16 units (the emoji takes 2).
  EXPECT_EQ(edits[0]["range"], json::parse(R"({"start":{"line":0,"character":0},"end":{"line":3,"character":9}})"));
}

TEST(LspFormatting, TheEditReachesTheEndOfATextWithLoneCarriageReturns) {
  // Four lines as LSP counts them (a lone CR ends a line); the last, "}",
  // ends at character 1 of line 3. Counting LFs alone put the end on line 0.
  json reply = format_reply("task main()\r{\rWait(1);\r}");
  ASSERT_TRUE(reply.contains("result")) << reply.dump();
  ASSERT_EQ(reply["result"].size(), 1u);
  EXPECT_EQ(reply["result"][0]["range"], json::parse(R"({"start":{"line":0,"character":0},"end":{"line":3,"character":1}})"));
}

TEST(LspFormatting, TheEditorsTabSizeIsTheIndent) {
  json reply = format_reply("task main()\n{\nWait(1);\n}\n", {{"tabSize", 4}, {"insertSpaces", true}});
  EXPECT_EQ(reply["result"][0]["newText"], "task main()\n{\n    Wait(1);\n}\n");
}

TEST(LspFormatting, AFormattedDocumentGetsNoEdit) {
  json reply = format_reply("task main()\n{\n  Wait(1);\n}\n");
  EXPECT_EQ(reply["result"], json::array());
}

TEST(LspFormatting, ARefusalIsAnErrorWithItsMessage) {
  json reply = format_reply("task main()\n{\n  /* never closed\n}\n");
  ASSERT_TRUE(reply.contains("error")) << reply.dump();
  EXPECT_EQ(reply["error"]["code"], kRequestFailed);
  EXPECT_EQ(reply["error"]["message"], "cannot format: line 3, column 3: unterminated /* comment");
}

TEST(LspFormatting, BadOptionsAreInvalidParams) {
  json reply = format_reply("task main() {}\n", {{"tabSize", "four"}});
  EXPECT_EQ(reply["error"]["code"], kInvalidParams);
}

// The reply to textDocument/rangeFormatting of lines [first, last] (to the
// start of the line after `last`).
json range_format_reply(const std::string& text, int first, int last) {
  Server server;
  open_document(server, text, "documentRangeFormattingProvider");
  json range = {{"start", {{"line", first}, {"character", 0}}}, {"end", {{"line", last + 1}, {"character", 0}}}};
  auto out = handle(server, message("textDocument/rangeFormatting",
                                    {{"textDocument", {{"uri", kUri}}}, {"range", range}, {"options", {{"tabSize", 2}}}}, 2));
  EXPECT_EQ(out.size(), 1u);
  return out.empty() ? json() : out[0];
}

json edit(int line0, int char0, int line1, int char1, const std::string& text) {
  return {{"range", {{"start", {{"line", line0}, {"character", char0}}}, {"end", {{"line", line1}, {"character", char1}}}}},
          {"newText", text}};
}

const char* const kTwoTasks =
    "task main()\n"       // 0
    "{\n"                 // 1
    "start   other;\n"    // 2
    "Wait(1);\n"          // 3
    "}\n"                 // 4
    "task other()\n"      // 5
    "{\n"                 // 6
    "Off(OUT_A);\n"       // 7
    "}";                  // 8

TEST(LspRangeFormatting, OnlyTheSelectedLinesChange) {
  // Line 3 alone: its indent, nothing of line 2 or of the other task.
  EXPECT_EQ(range_format_reply(kTwoTasks, 3, 3)["result"], json::array({edit(3, 0, 4, 0, "  Wait(1);\n")}));
  // Lines 2 and 3: an edit each.
  EXPECT_EQ(range_format_reply(kTwoTasks, 1, 4)["result"],
            json::array({edit(2, 0, 3, 0, "  start other;\n"), edit(3, 0, 4, 0, "  Wait(1);\n")}));
  // The last line gets the newline the formatter ends a file with: its
  // edit reaches the end of the text.
  EXPECT_EQ(range_format_reply(kTwoTasks, 7, 8)["result"],
            json::array({edit(7, 0, 8, 0, "  Off(OUT_A);\n"), edit(8, 0, 8, 1, "}\n")}));
  // A selection of formatted lines only needs nothing.
  EXPECT_EQ(range_format_reply(kTwoTasks, 0, 1)["result"], json::array());
}

TEST(LspRangeFormatting, ALineTheFormatterSplitsIsReplacedWhole) {
  // "task main() { Wait(1); }" becomes four lines; the lines after it stay.
  EXPECT_EQ(range_format_reply("task main() { Wait(1); }\ntask b()\n{\nOff(OUT_A);\n}\n", 0, 0)["result"],
            json::array({edit(0, 0, 1, 0, "task main()\n{\n  Wait(1);\n}\n")}));
}

TEST(LspRangeFormatting, RefusalsAndBadRangesAreErrors) {
  json reply = range_format_reply("task main()\n{\n  /* never closed\n}\n", 0, 0);
  EXPECT_EQ(reply["error"]["code"], kRequestFailed);
  reply = range_format_reply(kTwoTasks, 3, 1);
  EXPECT_EQ(reply["error"]["code"], kInvalidParams);
}

}  // namespace
}  // namespace rcxc::lsp
