// The language server's protocol: framing, the lifecycle, and each request
// on real programs (diagnostics, hover, completion, definition, references,
// symbols, quick fixes), plus robustness against bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <sstream>

#include "lsp/index.h"
#include "lsp/jsonrpc.h"
#include "lsp/server.h"
#include "tests/lsp/session.h"
#include "tests/support/process.h"

namespace rcxc::lsp {
namespace {

using nlohmann::json;

// ---------------------------------------------------------------- framing --

TEST(LspFraming, ReadsMessagesInTurn) {
  std::istringstream in(framed({{"a", 1}}) + "content-length: 7\r\nContent-Type: application/vscode-jsonrpc; charset=utf-8\r\n\r\n{\"b\":2}");
  Frame f = read_frame(in);
  ASSERT_EQ(f.kind, Frame::Kind::Message);
  EXPECT_EQ(json::parse(f.body)["a"], 1);
  f = read_frame(in);
  ASSERT_EQ(f.kind, Frame::Kind::Message);
  EXPECT_EQ(f.body, "{\"b\":2}");
  EXPECT_EQ(read_frame(in).kind, Frame::Kind::End);
}

TEST(LspFraming, BadHeadersAreReportedNotFatal) {
  std::istringstream in("Content-Type: x\r\n\r\nContent-Length: abc\r\n\r\nContent-Length: 99999999999999999999\r\n\r\n" +
                        framed({{"ok", true}}));
  Frame f = read_frame(in);
  EXPECT_EQ(f.kind, Frame::Kind::BadHeader);
  EXPECT_NE(f.error.find("Content-Length"), std::string::npos);
  EXPECT_EQ(read_frame(in).kind, Frame::Kind::BadHeader);
  EXPECT_EQ(read_frame(in).kind, Frame::Kind::BadHeader);
  f = read_frame(in);
  ASSERT_EQ(f.kind, Frame::Kind::Message);
  EXPECT_EQ(json::parse(f.body)["ok"], true);
}

// LSP asks for Content-Length once. Given twice alike it is one length,
// said on stderr; given twice with different values the message is refused
// (which end was meant cannot be known) and the next one is still read,
// whichever of the two was the body's length.
TEST(LspFraming, AContentLengthGivenTwice) {
  const std::string body = R"({"jsonrpc":"2.0","id":10,"method":"initialize","params":{}})";  // 59 bytes
  ASSERT_EQ(body.size(), 59u);
  std::istringstream same("Content-Length: 59\r\ncontent-length:59\r\n\r\n" + body);
  Frame f = read_frame(same);
  ASSERT_EQ(f.kind, Frame::Kind::Message);
  EXPECT_EQ(f.body, body);
  EXPECT_EQ(f.error, "Content-Length given twice, as 59 both times: read as one");
  for (std::string header : {"Content-Length: 59\r\nContent-Length: 70\r\n\r\n",
                                    "Content-Length: 40\r\nContent-Length: 59\r\n\r\n"}) {
    std::istringstream in(header + body + framed({{"next", 1}}));
    f = read_frame(in);
    EXPECT_EQ(f.kind, Frame::Kind::BadHeader) << header;
    EXPECT_NE(f.error.find("Content-Length given twice, as "), std::string::npos) << f.error;
    f = read_frame(in);
    ASSERT_EQ(f.kind, Frame::Kind::Message) << header << f.error;
    EXPECT_EQ(json::parse(f.body), json({{"next", 1}}));
  }
  // Through the server: the refused request is not run (no answer), the
  // one after it is, and stderr says which header was wrong.
  Server server;
  const std::string exit = R"({"jsonrpc":"2.0","method":"exit"})";  // 33 bytes
  std::istringstream in("Content-Length: 59\r\nContent-Length: 12\r\n\r\n" + body + framed(request(2, "initialize")) +
                        framed(request(3, "shutdown")) + "Content-Length: 33\r\nContent-Length: 33\r\n\r\n" + exit);
  std::ostringstream out, log;
  EXPECT_EQ(serve(server, in, out, log), 0);
  EXPECT_EQ(log.str(),
            "rcxc lsp: skipped a message: Content-Length given twice, as 59 and 12: where the message ends is not known\n"
            "rcxc lsp: Content-Length given twice, as 33 both times: read as one\n");
  std::istringstream replies(out.str());
  for (int id : {2, 3}) {
    f = read_frame(replies);
    ASSERT_EQ(f.kind, Frame::Kind::Message);
    EXPECT_EQ(json::parse(f.body)["id"], id);
  }
  EXPECT_EQ(read_frame(replies).kind, Frame::Kind::End);
}

// A client that closed its end of our output: the server stops at the
// first reply it cannot write, instead of reading on with no one to answer.
TEST(LspFraming, AnOutputThatCannotBeWrittenStopsTheServer) {
  Server server;
  std::string input = framed(request(1, "initialize"));
  for (int i = 0; i < 50; ++i) input += framed(request(2 + i, "shutdown"));
  std::istringstream in(input);
  std::ostringstream out, log;
  out.setstate(std::ios::badbit);
  EXPECT_EQ(serve(server, in, out, log), 1);
  EXPECT_EQ(log.str(), "rcxc lsp: cannot write to the client (the standard output is closed); stopping\n");
  EXPECT_FALSE(server.shutdown);  // the requests after the first were never run
}

TEST(LspFraming, ATruncatedBodyEndsTheStream) {
  std::istringstream in("Content-Length: 50\r\n\r\n{\"a\":");
  EXPECT_EQ(read_frame(in).kind, Frame::Kind::End);
}

// A stream cut inside a message lost it without a word (exit 1 and an empty
// stderr); the end of input between messages is still quiet.
TEST(LspFraming, InputThatEndsInsideAMessageIsSaid) {
  auto log_of = [](const std::string& input) {
    Server server;
    std::istringstream in(input);
    std::ostringstream out, log;
    EXPECT_EQ(serve(server, in, out, log), 1);
    return log.str();
  };
  EXPECT_EQ(log_of("Content-Length: 50\r\n\r\n{\"a\":"),
            "rcxc lsp: the input ended inside a message of 50 bytes (its Content-Length)\n");
  EXPECT_EQ(log_of("Content-Length: 70000000\r\n\r\n{}"),
            "rcxc lsp: the input ended inside a message of 70000000 bytes (its Content-Length)\n");
  EXPECT_EQ(log_of("Content-Length: 2\r\n"), "rcxc lsp: the input ended inside a message's header\n");
  EXPECT_EQ(log_of(framed(request(1, "initialize")) + "\r\n"), "");
  EXPECT_EQ(log_of(""), "");
}

TEST(LspFraming, WritesContentLengthInBytes) {
  std::ostringstream out;
  write_message(out, {{"s", "\xc3\xa9"}});
  EXPECT_EQ(out.str(), "Content-Length: 10\r\n\r\n{\"s\":\"\xc3\xa9\"}");
}

// -------------------------------------------------------------- lifecycle --

TEST(LspLifecycle, InitializeAnnouncesTheFeatures) {
  Server server;
  auto out = handle(server, request(1, "initialize", {{"capabilities", json::object()}}));
  ASSERT_EQ(out.size(), 1u);
  const json& caps = out[0]["result"]["capabilities"];
  EXPECT_EQ(caps["textDocumentSync"]["change"], 2);  // incremental: a keystroke is a range, not the whole text
  EXPECT_TRUE(caps["hoverProvider"].get<bool>());
  EXPECT_TRUE(caps["definitionProvider"].get<bool>());
  EXPECT_TRUE(caps["referencesProvider"].get<bool>());
  EXPECT_TRUE(caps["documentSymbolProvider"].get<bool>());
  EXPECT_TRUE(caps.contains("completionProvider"));
  EXPECT_TRUE(caps.contains("codeActionProvider"));
  EXPECT_EQ(out[0]["result"]["serverInfo"]["name"], "rcxc");
}

TEST(LspLifecycle, RequestsBeforeInitializeAreRefused) {
  Server server;
  auto out = handle(server, request(3, "textDocument/hover", {}));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["error"]["code"], kServerNotInitialized);
  EXPECT_EQ(out[0]["id"], 3);
}

TEST(LspLifecycle, BadMessagesGetErrorsAndTheServerGoesOn) {
  Server server;
  handle(server, request(1, "initialize"));
  auto out = handle_text(server, "{not json");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["error"]["code"], kParseError);
  EXPECT_TRUE(out[0]["id"].is_null());
  out = handle_text(server, "[1,2]");
  EXPECT_EQ(out[0]["error"]["code"], kInvalidRequest);
  out = handle(server, request(4, "no/such/method"));
  EXPECT_EQ(out[0]["error"]["code"], kMethodNotFound);
  out = handle(server, request(5, "textDocument/hover", {{"textDocument", 42}}));
  EXPECT_EQ(out[0]["error"]["code"], kInvalidParams);
  out = handle(server, request(6, "textDocument/hover", {{"textDocument", {{"uri", "file:///x.nqc"}}}, {"position", "x"}}));
  EXPECT_EQ(out[0]["id"], 6);  // not open: nothing known, but an answer
  // A malformed notification is dropped without a reply.
  EXPECT_TRUE(handle(server, note("textDocument/didOpen", {{"textDocument", "?"}})).empty());
  EXPECT_TRUE(handle(server, note("textDocument/didChange", json::array())).empty());
  out = handle(server, request(8, "shutdown"));
  EXPECT_TRUE(out[0]["result"].is_null());
  out = handle(server, request(9, "textDocument/hover", {}));
  EXPECT_EQ(out[0]["error"]["code"], kInvalidRequest);
}

TEST(LspLifecycle, ServeAnswersAndExitsWithTheRightCode) {
  Server server;
  std::istringstream in("garbage\r\n\r\n" + framed(request(1, "initialize")) + framed(request(2, "shutdown")) +
                        framed(note("exit")) + framed(request(3, "initialize")));
  std::ostringstream out, log;
  EXPECT_EQ(serve(server, in, out, log), 0);
  EXPECT_NE(log.str().find("skipped"), std::string::npos);
  std::istringstream replies(out.str());
  EXPECT_EQ(json::parse(read_frame(replies).body)["id"], 1);
  EXPECT_EQ(json::parse(read_frame(replies).body)["id"], 2);
  EXPECT_EQ(read_frame(replies).kind, Frame::Kind::End);  // nothing read after exit

  Server abrupt;
  std::istringstream in2(framed(request(1, "initialize")) + framed(note("exit")));
  EXPECT_EQ(serve(abrupt, in2, out, log), 1);  // exit without shutdown
}

// A message nested a million deep killed the server (SIGSEGV: JSON is freed
// recursively); it is refused unread with a parse error and the server goes on.
TEST(LspLifecycle, AMessageNestedTooDeepIsRefusedAndTheServerGoesOn) {
  EXPECT_EQ(json_nesting(R"({"a":[1,{"b":"[[[["}]})"), 3);
  const std::string deep = std::string(2'000'000, '[') + std::string(2'000'000, ']');
  EXPECT_EQ(json_nesting(deep), 2'000'000);
  Server server;
  std::istringstream in(framed(request(1, "initialize")) + "Content-Length: " + std::to_string(deep.size()) +
                        "\r\n\r\n" + deep + framed(request(2, "shutdown")) + framed(note("exit")));
  std::ostringstream out, log;
  EXPECT_EQ(serve(server, in, out, log), 0);
  std::istringstream replies(out.str());
  EXPECT_EQ(json::parse(read_frame(replies).body)["id"], 1);
  json refused = json::parse(read_frame(replies).body);
  EXPECT_EQ(refused["error"]["code"], kParseError);
  EXPECT_EQ(refused["error"]["message"], "the message nests arrays and objects deeper than 100 levels; it was not read");
  EXPECT_EQ(json::parse(read_frame(replies).body)["id"], 2);
}

TEST(LspLifecycle, UrisRoundTrip) {
  EXPECT_EQ(uri_to_path("file:///home/a%20b/x.nqc"), "/home/a b/x.nqc");
  EXPECT_EQ(path_to_uri("/home/a b/x.nqc"), "file:///home/a%20b/x.nqc");
  EXPECT_EQ(uri_to_path(path_to_uri("/tmp/é#1.nqc")), "/tmp/é#1.nqc");
  EXPECT_EQ(uri_to_path("file:///bad%zz"), "/bad%zz");
}

// ------------------------------------------------------------ diagnostics --

TEST(LspDiagnostics, TheCompilersErrorsWithRanges) {
  Session s("task main()\n{\n  OnFwd(OUT_A);\n  x = 3;\n}\n");
  ASSERT_EQ(s.diagnostics.size(), 1u) << s.diagnostics.dump();
  const json& d = s.diagnostics[0];
  EXPECT_EQ(d["severity"], 1);
  EXPECT_EQ(d["message"], "'x' is not declared");
  EXPECT_EQ(d["range"]["start"], pos(3, 2));
  EXPECT_EQ(d["range"]["end"], pos(3, 3));
}

TEST(LspDiagnostics, ChangesRecompileAndCleanCodeClearsThem) {
  Session s("task main()\n{\n  y = 1;\n}\n");
  ASSERT_EQ(s.diagnostics.size(), 1u);
  auto out = handle(s.server, note("textDocument/didChange",
                                   {{"textDocument", {{"uri", s.uri}, {"version", 2}}},
                                    {"contentChanges", json::array({{{"text", "int y;\ntask main()\n{\n  y = 1;\n}\n"}}})}}));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["params"]["version"], 2);
  EXPECT_TRUE(out[0]["params"]["diagnostics"].empty()) << out[0].dump();
  // An incremental change (a client may send one anyway) is applied too.
  out = handle(s.server, note("textDocument/didChange",
                              {{"textDocument", {{"uri", s.uri}, {"version", 3}}},
                               {"contentChanges", json::array({{{"range", {{"start", pos(3, 2)}, {"end", pos(3, 3)}}},
                                                                {"text", "zz"}}})}}));
  EXPECT_EQ(out[0]["params"]["diagnostics"][0]["message"], "'zz' is not declared");
  out = handle(s.server, note("textDocument/didClose", {{"textDocument", {{"uri", s.uri}}}}));
  EXPECT_TRUE(out[0]["params"]["diagnostics"].empty());
}

TEST(LspDiagnostics, WarningsAndSyntaxErrors) {
  Session s("task main()\n{\n  int unused;\n  Wait(10)\n}\n");
  ASSERT_FALSE(s.diagnostics.empty());
  bool syntax = false;
  for (const auto& d : s.diagnostics) syntax |= d["severity"] == 1 && d["range"]["start"]["line"].get<int>() >= 3;
  EXPECT_TRUE(syntax) << s.diagnostics.dump();
}

TEST(LspDiagnostics, CodeThatDoesNothingIsTaggedUnnecessary) {
  Session s("task helper() { }\ntask main()\n{\n  int spare;\n  return;\n  Wait(10);\n}\n");
  std::vector<std::tuple<int, std::string, json>> seen;
  for (const auto& d : s.diagnostics) seen.emplace_back(d["range"]["start"]["line"], d["message"], d.value("tags", json()));
  std::sort(seen.begin(), seen.end(), [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
  EXPECT_EQ(seen, (std::vector<std::tuple<int, std::string, json>>{
                      {0, "task 'helper' is never started: nothing in the program says 'start helper;'", json()},
                      {3, "unused variable 'spare'", json::array({1})},
                      {5, "unreachable code", json::array({1})}}))
      << s.diagnostics.dump();
}

TEST(LspDiagnostics, EachWarningsCodeIsItsName) {
  Session s("task helper() { }\ntask main()\n{\n  int spare;\n  x = 1;\n}\n");
  std::vector<std::pair<std::string, json>> seen;
  for (const auto& d : s.diagnostics) seen.emplace_back(d["message"], d.value("code", json()));
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, (std::vector<std::pair<std::string, json>>{{"'x' is not declared", json()},
                                                              {"unused variable 'spare'", "unused-variable"}}))
      << s.diagnostics.dump();
  Session w("task helper() { }\ntask main()\n{\n  int spare;\n}\n");
  seen.clear();
  for (const auto& d : w.diagnostics) seen.emplace_back(d["message"], d.value("code", json()));
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, (std::vector<std::pair<std::string, json>>{
                      {"task 'helper' is never started: nothing in the program says 'start helper;'", "unstarted-task"},
                      {"unused variable 'spare'", "unused-variable"}}))
      << w.diagnostics.dump();
}

// The editor shows what rcxc compile says, the passes' and the back end's
// diagnostics too, not only the frontend's.
TEST(LspDiagnostics, TheWholeCompilersDiagnostics) {
  Session sensor("task main()\n{\n  if (SENSOR_2 == 1) Off(OUT_A);\n}\n");
  ASSERT_EQ(sensor.diagnostics.size(), 1u) << sensor.diagnostics.dump();
  EXPECT_EQ(sensor.diagnostics[0]["code"], "unconfigured-sensor");
  EXPECT_EQ(sensor.diagnostics[0]["range"]["start"]["line"], 2);
  std::string globals;
  for (int i = 0; i < 33; ++i) globals += "int g" + std::to_string(i) + ";\n";
  std::string uses;
  for (int i = 0; i < 33; ++i) uses += "  g" + std::to_string(i) + " = Random(" + std::to_string(i + 1) + ");\n";
  Session slots(globals + "task main()\n{\n" + uses + "}\n");
  ASSERT_FALSE(slots.diagnostics.empty());
  EXPECT_EQ(slots.diagnostics[0]["severity"], 1);
  EXPECT_NE(slots.diagnostics[0]["message"].get<std::string>().find("all are taken"), std::string::npos)
      << slots.diagnostics.dump();
}

// initializationOptions.warnings takes -W options; one the server does not
// know is passed over and the rest still apply.
TEST(LspDiagnostics, TheClientChoosesWarningsAsWOptions) {
  test::TempDir dir;
  Server server;
  server.stdlib_dir = dir.path + "/stdlib-copy";
  json init = {{"capabilities", json::object()},
               {"initializationOptions", {{"warnings", json::array({"no-unused-variable", "no-such-thing", 7,
                                                                    "error=unstarted-task"})}}}};
  ASSERT_EQ(handle(server, request(1, "initialize", init)).size(), 1u);
  std::string text = "task helper() { }\ntask main()\n{\n  int spare;\n  return;\n  Wait(10);\n}\n";
  std::string uri = path_to_uri(dir.write("p.nqc", text));
  auto out = handle(server, note("textDocument/didOpen",
                                 {{"textDocument", {{"uri", uri}, {"languageId", "nqc"}, {"version", 1}, {"text", text}}}}));
  ASSERT_EQ(out.size(), 1u);
  std::vector<std::tuple<std::string, int, json>> seen;
  for (const auto& d : out[0]["params"]["diagnostics"]) seen.emplace_back(d["message"], d["severity"], d.value("code", json()));
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, (std::vector<std::tuple<std::string, int, json>>{
                      {"task 'helper' is never started: nothing in the program says 'start helper;'", 1, "unstarted-task"},
                      {"unreachable code", 2, "unreachable-code"}}))
      << out[0].dump();
}

TEST(LspDiagnostics, ColumnsAreUtf16) {
  // "é" is two bytes but one UTF-16 unit; "𝄞" four bytes, two units.
  Session s("task main()\n{\n  /*é𝄞*/ x = 1;\n}\n");
  ASSERT_EQ(s.diagnostics.size(), 1u);
  EXPECT_EQ(s.diagnostics[0]["range"]["start"], pos(2, 10));
}

TEST(LspDiagnostics, AnErrorInAnIncludedFileShowsAtTheInclude) {
  test::TempDir dir;
  dir.write("bad.nqh", "int a;\nint a;\n");
  std::string text = "#include \"bad.nqh\"\ntask main() { a = 1; }\n";
  std::string path = dir.write("p.nqc", text);
  Server server;
  handle(server, request(1, "initialize"));
  auto out = handle(server, note("textDocument/didOpen", {{"textDocument", {{"uri", path_to_uri(path)}, {"text", text}}}}));
  const json& d = out.at(0)["params"]["diagnostics"].at(0);
  EXPECT_EQ(d["range"]["start"]["line"], 0);
  EXPECT_NE(d["message"].get<std::string>().find("bad.nqh:2"), std::string::npos) << d.dump();
  EXPECT_NE(d["relatedInformation"][0]["location"]["uri"].get<std::string>().find("bad.nqh"), std::string::npos);
}

// ---------------------------------------------------------------- hover --

const char* kProgram =
    "// How many times the bumper was hit.\n"   // 0
    "int bumps;\n"                               // 1
    "\n"                                         // 2
    "// Backs off and turns.\n"                  // 3
    "sub back_off()\n"                           // 4
    "{\n"                                        // 5
    "  OnRev(OUT_A + OUT_C);\n"                  // 6
    "  Wait(50);\n"                              // 7
    "}\n"                                        // 8
    "\n"                                         // 9
    "void blink(const int times, int &left)\n"   // 10
    "{\n"                                        // 11
    "  repeat (times) { PlaySound(SOUND_UP); left = left - 1; }\n"  // 12
    "}\n"                                        // 13
    "\n"                                         // 14
    "task main()\n"                              // 15
    "{\n"                                        // 16
    "  int speed = 3;\n"                         // 17
    "  SetSensor(SENSOR_1, SENSOR_TOUCH);\n"     // 18
    "  while (true) {\n"                         // 19
    "    if (SENSOR_1 == 1) { bumps++; back_off(); blink(2, speed); }\n"  // 20
    "    OnFwd(OUT_A);\n"                        // 21
    "  }\n"                                      // 22
    "}\n";                                       // 23

std::string hover_value(const json& result) { return result.is_null() ? "" : result["contents"]["value"].get<std::string>(); }

TEST(LspHover, ApiFunctionsShowSignatureAndDoc) {
  Session s(kProgram);
  EXPECT_TRUE(s.diagnostics.empty()) << s.diagnostics.dump();
  std::string h = hover_value(s.at("textDocument/hover", 7, 3));  // Wait
  EXPECT_NE(h.find("void Wait(const int &ticks)"), std::string::npos) << h;
  EXPECT_NE(h.find("hundredths of a second"), std::string::npos) << h;
  EXPECT_NE(h.find("rcx.nqh"), std::string::npos) << h;
  h = hover_value(s.at("textDocument/hover", 21, 5));  // OnFwd
  EXPECT_NE(h.find("void OnFwd(const int outputs)"), std::string::npos) << h;
}

TEST(LspHover, ApiConstantsShowTheirDefinitionAndGroupComment) {
  Session s(kProgram);
  std::string h = hover_value(s.at("textDocument/hover", 18, 25));  // SENSOR_TOUCH
  EXPECT_NE(h.find("#define SENSOR_TOUCH (SENSOR_TYPE_TOUCH * 256 + SENSOR_MODE_BOOL)"), std::string::npos) << h;
  EXPECT_NE(h.find("configuration for SetSensor"), std::string::npos) << h;
  h = hover_value(s.at("textDocument/hover", 6, 20));  // OUT_C, in a group whose comment is a section rule
  EXPECT_NE(h.find("#define OUT_C 4"), std::string::npos) << h;
  EXPECT_EQ(h.find("----"), std::string::npos) << h;
}

TEST(LspHover, TheProgramsOwnNames) {
  Session s(kProgram);
  std::string h = hover_value(s.at("textDocument/hover", 20, 26));  // bumps
  EXPECT_NE(h.find("int bumps"), std::string::npos) << h;
  EXPECT_NE(h.find("How many times the bumper was hit."), std::string::npos) << h;
  h = hover_value(s.at("textDocument/hover", 20, 37));  // back_off
  EXPECT_NE(h.find("sub back_off()"), std::string::npos) << h;
  EXPECT_NE(h.find("Backs off and turns."), std::string::npos) << h;
  h = hover_value(s.at("textDocument/hover", 20, 49));  // blink
  EXPECT_NE(h.find("void blink(const int times, int &left)"), std::string::npos) << h;
  h = hover_value(s.at("textDocument/hover", 20, 57));  // speed, a local
  EXPECT_NE(h.find("int speed"), std::string::npos) << h;
  EXPECT_NE(h.find("local variable"), std::string::npos) << h;
  h = hover_value(s.at("textDocument/hover", 12, 12));  // times, a parameter
  EXPECT_NE(h.find("const int times"), std::string::npos) << h;
  EXPECT_TRUE(s.at("textDocument/hover", 19, 3).is_null());   // `while`: a keyword
  EXPECT_TRUE(s.at("textDocument/hover", 2, 0).is_null());    // an empty line
  EXPECT_TRUE(s.at("textDocument/hover", 500, 3).is_null());  // past the end
}

// ------------------------------------------------------------ completion --

std::vector<std::string> labels(const json& result) {
  std::vector<std::string> out;
  for (const auto& item : result["items"]) out.push_back(item["label"]);
  return out;
}

bool has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

TEST(LspCompletion, ApiNamesConstantsAndTheProgramsNamesInScope) {
  Session s(kProgram);
  auto in_main = labels(s.at("textDocument/completion", 21, 4));
  for (const char* name : {"OnFwd", "Wait", "SetSensor", "OUT_A", "SENSOR_TOUCH", "SOUND_UP", "Timer", "bumps",
                           "back_off", "blink", "main", "speed", "while", "repeat", "abs", "sign", "goto"})
    EXPECT_TRUE(has(in_main, name)) << name;
  EXPECT_FALSE(has(in_main, "times"));     // blink's parameter is not in scope in main
  EXPECT_FALSE(has(in_main, "__source"));  // compiler internals are not offered
  EXPECT_FALSE(has(in_main, "__sensor"));
  EXPECT_EQ(std::count(in_main.begin(), in_main.end(), "while"), 1);
  auto in_blink = labels(s.at("textDocument/completion", 12, 4));
  EXPECT_TRUE(has(in_blink, "times"));
  EXPECT_FALSE(has(in_blink, "speed"));
  json r = s.at("textDocument/completion", 21, 4);
  for (const auto& item : r["items"])
    if (item["label"] == "Wait") {
      EXPECT_EQ(item["detail"], "void Wait(const int &ticks)");
      EXPECT_EQ(item["kind"], 3);
    }
}

TEST(LspCompletion, WorksWhileTheProgramHasErrors) {
  Session s("int total;\ntask main()\n{\n  int here;\n  to\n}\n");
  EXPECT_FALSE(s.diagnostics.empty());
  auto names = labels(s.at("textDocument/completion", 4, 4));
  EXPECT_TRUE(has(names, "total"));
  EXPECT_TRUE(has(names, "here"));
  EXPECT_TRUE(has(names, "OnFwd"));
}

// ---------------------------------------------------- definition, references --

TEST(LspDefinition, TheProgramsNamesAndTheStandardLibrary) {
  Session s(kProgram);
  json loc = s.at("textDocument/definition", 20, 37);  // back_off
  EXPECT_EQ(loc["uri"], s.uri);
  EXPECT_EQ(loc["range"]["start"], pos(4, 4));
  loc = s.at("textDocument/definition", 20, 57);  // speed
  EXPECT_EQ(loc["range"]["start"], pos(17, 6));
  loc = s.at("textDocument/definition", 7, 3);  // Wait, in the embedded library
  std::string path = uri_to_path(loc["uri"]);
  EXPECT_EQ(path, s.dir.path + "/stdlib-copy/rcx.nqh");
  std::ifstream copy(path);
  std::string line;
  for (int i = 0; i <= loc["range"]["start"]["line"].get<int>(); ++i) std::getline(copy, line);
  EXPECT_NE(line.find("void Wait("), std::string::npos) << line;
}

// The copy of rcx.nqh that go to definition opens is written whole or not
// at all: a write cut short (here by a file size limit, as a full disk
// would) leaves no part of it for the editor, or a later server, to read.
TEST(LspDefinition, TheStdlibCopyIsNeverLeftCutShort) {
  Session s(kProgram);
  const std::string folder = s.dir.path + "/stdlib-copy";
  const std::string copy = folder + "/rcx.nqh";
  const std::string whole = test::read_text_file(RCXC_SOURCE_DIR "/stdlib/rcx.nqh");
  ASSERT_GT(whole.size(), 4096u);
  pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::signal(SIGXFSZ, SIG_IGN);  // a write past the limit then fails with EFBIG
    struct rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    json loc = s.at("textDocument/definition", 7, 3);  // Wait
    ::_exit(loc.is_null() ? 0 : 1);                       // no copy: no place to show
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "a definition was given in a copy that could not be written";
  std::error_code ec;
  EXPECT_FALSE(std::filesystem::exists(copy, ec)) << std::filesystem::file_size(copy, ec) << " bytes left";
  EXPECT_TRUE(std::filesystem::is_empty(folder, ec)) << "a temporary was left behind";
  // Without the limit the copy is written, whole.
  json loc = s.at("textDocument/definition", 7, 3);
  EXPECT_EQ(uri_to_path(loc["uri"]), copy);
  EXPECT_EQ(test::read_text_file(copy), whole);
}

// A copy an earlier server left cut short or changed is not trusted: it is
// written again before a definition is shown in it.
TEST(LspDefinition, ACutOrChangedStdlibCopyIsWrittenAgain) {
  const std::string whole = test::read_text_file(RCXC_SOURCE_DIR "/stdlib/rcx.nqh");
  std::string changed = whole;
  changed[changed.size() / 2] ^= 1;
  for (const std::string& left : {whole.substr(0, whole.size() / 2), changed, std::string()}) {
    Session s(kProgram);
    std::filesystem::create_directories(s.dir.path + "/stdlib-copy");
    s.dir.write("stdlib-copy/rcx.nqh", left);
    json loc = s.at("textDocument/definition", 7, 3);
    EXPECT_EQ(test::read_text_file(uri_to_path(loc["uri"])), whole);
  }
}

TEST(LspDefinition, IntoIncludedFiles) {
  test::TempDir dir;
  dir.write("lib.nqh", "// Turns left.\nvoid turn_left() { OnRev(OUT_A); }\n#define SPEED 5\n");
  std::string text = "#include \"lib.nqh\"\ntask main() { turn_left(); SetPower(OUT_A, SPEED); }\n";
  std::string path = dir.write("p.nqc", text);
  Server server;
  handle(server, request(1, "initialize"));
  std::string uri = path_to_uri(path);
  auto opened = handle(server, note("textDocument/didOpen", {{"textDocument", {{"uri", uri}, {"text", text}}}}));
  EXPECT_TRUE(opened[0]["params"]["diagnostics"].empty()) << opened[0].dump();
  auto ask = [&](const std::string& method, int line, int ch, json extra = json::object()) {
    extra["textDocument"] = {{"uri", uri}};
    extra["position"] = pos(line, ch);
    return handle(server, request(2, method, extra)).at(0)["result"];
  };
  json loc = ask("textDocument/definition", 1, 16);
  EXPECT_EQ(uri_to_path(loc["uri"]), dir.path + "/lib.nqh");
  EXPECT_EQ(loc["range"]["start"], pos(1, 5));
  EXPECT_NE(hover_value(ask("textDocument/hover", 1, 16)).find("Turns left."), std::string::npos);
  loc = ask("textDocument/definition", 1, 45);  // SPEED
  EXPECT_EQ(loc["range"]["start"], pos(2, 8));
  // References of turn_left from its use: the definition in lib.nqh and the call.
  json refs = ask("textDocument/references", 1, 16, {{"context", {{"includeDeclaration", true}}}});
  ASSERT_EQ(refs.size(), 2u) << refs.dump();
}

TEST(LspReferences, EveryUseOfAName) {
  Session s(kProgram);
  json refs = s.ask("textDocument/references", {{"position", pos(1, 5)}, {"context", {{"includeDeclaration", true}}}});
  ASSERT_EQ(refs.size(), 2u) << refs.dump();  // int bumps; and bumps++
  EXPECT_EQ(refs[1]["range"]["start"], pos(20, 25));
  refs = s.ask("textDocument/references", {{"position", pos(1, 5)}, {"context", {{"includeDeclaration", false}}}});
  EXPECT_EQ(refs.size(), 1u);
  // `left` is blink's parameter: three uses in blink, none elsewhere.
  refs = s.ask("textDocument/references", {{"position", pos(12, 41)}, {"context", {{"includeDeclaration", true}}}});
  EXPECT_EQ(refs.size(), 3u) << refs.dump();
}

TEST(LspReferences, ALocalShadowsAGlobalOfTheSameName) {
  Session s("int n;\ntask main()\n{\n  int n;\n  n = 1;\n}\ntask other() { n = 2; }\n");
  json loc = s.at("textDocument/definition", 4, 2);
  EXPECT_EQ(loc["range"]["start"], pos(3, 6));
  loc = s.at("textDocument/definition", 6, 15);
  EXPECT_EQ(loc["range"]["start"], pos(0, 4));
}

// ------------------------------------------------------------- symbols --

TEST(LspSymbols, TasksSubsFunctionsAndGlobals) {
  Session s(kProgram);
  json symbols = s.ask("textDocument/documentSymbol", json::object());
  std::map<std::string, int> kinds;
  for (const auto& sym : symbols) kinds[sym["name"]] = sym["kind"];
  EXPECT_EQ(kinds.size(), 4u) << symbols.dump();  // nothing of the library, no locals
  EXPECT_EQ(kinds["bumps"], 13);
  EXPECT_EQ(kinds["back_off"], 6);
  EXPECT_EQ(kinds["blink"], 12);
  EXPECT_EQ(kinds["main"], 24);
  // In source order; a task's range covers its body, the selection its name.
  EXPECT_EQ(symbols[0]["name"], "bumps");
  EXPECT_EQ(symbols[3]["name"], "main");
  EXPECT_EQ(symbols[3]["selectionRange"]["start"], pos(15, 5));
  EXPECT_EQ(symbols[3]["range"]["start"], pos(15, 5));
  EXPECT_EQ(symbols[3]["range"]["end"], pos(23, 1));
}

// ---------------------------------------------------------- code actions --

TEST(LspCodeAction, DidYouMeanFixesAMisspeltName) {
  Session s("int count;\ntask main()\n{\n  OnFwdd(OUT_A);\n  cuont = 2;\n}\n");
  ASSERT_EQ(s.diagnostics.size(), 2u) << s.diagnostics.dump();
  json actions = s.ask("textDocument/codeAction", {{"range", {{"start", pos(3, 3)}, {"end", pos(3, 3)}}},
                                                   {"context", {{"diagnostics", json::array()}}}});
  ASSERT_FALSE(actions.empty());
  EXPECT_EQ(actions[0]["title"], "Change 'OnFwdd' to 'OnFwd'");
  EXPECT_TRUE(actions[0]["isPreferred"].get<bool>());
  const json& edit = actions[0]["edit"]["changes"][s.uri][0];
  EXPECT_EQ(edit["newText"], "OnFwd");
  EXPECT_EQ(edit["range"]["start"], pos(3, 2));
  EXPECT_EQ(edit["range"]["end"], pos(3, 8));
  actions = s.ask("textDocument/codeAction", {{"range", {{"start", pos(4, 0)}, {"end", pos(4, 12)}}},
                                              {"context", {{"diagnostics", json::array()}}}});
  ASSERT_FALSE(actions.empty());
  EXPECT_EQ(actions[0]["edit"]["changes"][s.uri][0]["newText"], "count");
  // Nothing to fix on a line without an error.
  EXPECT_TRUE(s.ask("textDocument/codeAction", {{"range", {{"start", pos(0, 0)}, {"end", pos(0, 3)}}}}).empty());
}

TEST(LspCodeAction, ATaskNeverStartedIsStartedAtTheTopOfMain) {
  Session s("task watch()\n{\n}\ntask main()\n{\n    Wait(10);\n}\n");
  json actions = s.ask("textDocument/codeAction", {{"range", {{"start", pos(0, 6)}, {"end", pos(0, 6)}}},
                                                   {"context", {{"diagnostics", json::array()}}}});
  ASSERT_EQ(actions.size(), 1u) << actions.dump();
  EXPECT_EQ(actions[0]["title"], "Start 'watch' at the top of main");
  EXPECT_EQ(actions[0]["diagnostics"][0]["message"], "task 'watch' is never started: nothing in the program says 'start watch;'");
  // After main's '{' (line 4, character 1), indented as the Wait below it.
  const json& edit = actions[0]["edit"]["changes"][s.uri][0];
  EXPECT_EQ(edit["range"], range_at(4, 1, 1));
  EXPECT_EQ(edit["newText"], "\n    start watch;");
  // A main whose '{' ends its header line and whose body is empty: two
  // spaces more than the header.
  Session t("task watch() { }\ntask main() {\n}\n");
  actions = t.ask("textDocument/codeAction", {{"range", {{"start", pos(0, 6)}, {"end", pos(0, 6)}}}});
  ASSERT_EQ(actions.size(), 1u) << actions.dump();
  EXPECT_EQ(actions[0]["edit"]["changes"][t.uri][0]["range"], range_at(1, 13, 13));
  EXPECT_EQ(actions[0]["edit"]["changes"][t.uri][0]["newText"], "\n  start watch;");
}

TEST(LspCodeAction, SimilarNamesPreferCaseSlips) {
  EXPECT_EQ(edit_distance("OnFwd", "OnFwd"), 0u);
  EXPECT_EQ(edit_distance("OnFwd", "OnFdw"), 1u);  // a transposition is one edit
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  Index index = build_index("/nonexistent/p.nqc", "int onfwd;\nint OnFud;\ntask main() { }\n", {});
  auto names = similar_names(index, "OnFWD", {index.main_file, 3, 15});
  // Case slips first (the closer one first), then a wrong letter.
  ASSERT_EQ(names.size(), 3u);
  EXPECT_EQ(names[0], "OnFwd");
  EXPECT_EQ(names[1], "onfwd");
  EXPECT_EQ(names[2], "OnFud");
}

// ------------------------------------------------------------ robustness --

// Random edits of a real program and random requests, some well formed and
// some not: every request gets exactly one reply with its id, nothing throws.
TEST(LspRobustness, RandomEditsAndRequestsAlwaysGetOneReply) {
  Session s(kProgram);
  std::mt19937 rng(20);
  auto below = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  const char* methods[] = {"textDocument/hover",         "textDocument/completion",     "textDocument/definition",
                           "textDocument/references",    "textDocument/documentSymbol", "textDocument/codeAction",
                           "textDocument/signatureHelp", "textDocument/prepareRename",  "textDocument/rename",
                           "textDocument/documentHighlight"};
  const char* new_names[] = {"fresh", "main", "while", "2x", "OnFwd", ""};
  const std::string alphabet = "abcXYZ_09 ;{}()#/*\"\n\t=+-<>&|!~'\xc3\xa9\xff";
  std::string text = kProgram;
  for (int round = 0; round < 400; ++round) {
    random_edits(text, rng, alphabet, 8);
    auto change = handle(s.server, note("textDocument/didChange", {{"textDocument", {{"uri", s.uri}, {"version", round}}},
                                                                   {"contentChanges", json::array({{{"text", text}}})}}));
    ASSERT_EQ(change.size(), 1u);
    json params = {{"textDocument", {{"uri", s.uri}}},
                   {"position", pos(below(30) - 2, below(70) - 2)},
                   {"range", {{"start", pos(below(25), below(40))}, {"end", pos(below(25), below(80))}}},
                   {"context", {{"includeDeclaration", below(2) == 0}, {"diagnostics", json::array()}}}};
    if (below(5) == 0) params.erase(params.begin());
    if (below(7) == 0) params["position"] = "nowhere";
    params["newName"] = new_names[below(6)];
    auto out = handle(s.server, request(1000 + round, methods[below(10)], params));
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0]["id"], 1000 + round);
    EXPECT_TRUE(out[0].contains("result") || out[0].contains("error"));
    EXPECT_NE(out[0].value("error", json::object()).value("code", 0), kInternalError) << out[0].dump();
  }
}

// LSP counts a lone CR as a line end, as the compiler does (classic Mac OS
// files): diagnostics and ranged changes agree on where line 2 is.
TEST(LspDiagnostics, ALoneCarriageReturnEndsALineForRangesToo) {
  Session s("task main()\r{\r  y = 1;\r}\r");
  ASSERT_EQ(s.diagnostics.size(), 1u) << s.diagnostics.dump();
  EXPECT_EQ(s.diagnostics[0]["range"]["start"], pos(2, 2));
  auto out = handle(s.server, note("textDocument/didChange",
                                   {{"textDocument", {{"uri", s.uri}, {"version", 2}}},
                                    {"contentChanges", json::array({{{"range", {{"start", pos(2, 2)}, {"end", pos(2, 3)}}},
                                                                     {"text", "zz"}}})}}));
  ASSERT_EQ(out.size(), 1u);
  ASSERT_EQ(out[0]["params"]["diagnostics"].size(), 1u) << out[0].dump();
  EXPECT_EQ(out[0]["params"]["diagnostics"][0]["message"], "'zz' is not declared");
  EXPECT_EQ(out[0]["params"]["diagnostics"][0]["range"]["start"], pos(2, 2));
}

// ------------------------------------------------------ hostile clients --
// Each of these was a bug found by fuzz/fuzz_lsp.cpp or the audit of the
// server against a hostile client (docs/fuzzing.md, "The language server").

json change_note(const std::string& uri, json version, json changes) {
  return note("textDocument/didChange", {{"textDocument", {{"uri", uri}, {"version", version}}}, {"contentChanges", changes}});
}

std::vector<std::string> symbol_names(Session& s) {
  std::vector<std::string> names;
  for (const auto& sym : s.ask("textDocument/documentSymbol", json::object())) names.push_back(sym["name"]);
  return names;
}

TEST(LspHostile, AnIdThatIsNotAStringOrIntegerIsAnsweredWithNull) {
  // JSON-RPC: an Invalid Request whose id cannot be read is answered with
  // null; the object and array were echoed back.
  Server server;
  for (const char* text : {R"({"jsonrpc":"2.0","id":{"a":1}})", R"({"jsonrpc":"2.0","id":[1,2],"method":5})"}) {
    auto out = handle_text(server, text);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0]["error"]["code"], kInvalidRequest);
    EXPECT_TRUE(out[0]["id"].is_null()) << out[0].dump();
  }
  auto out = handle_text(server, R"({"jsonrpc":"2.0","id":"x"})");
  EXPECT_EQ(out.at(0)["id"], "x");  // a usable id is kept
}

TEST(LspHostile, VersionsAreIntegersKeptWhole) {
  Server server;
  handle(server, request(1, "initialize"));
  auto open = [&](json version) {
    return handle(server, note("textDocument/didOpen", {{"textDocument",
                                                         {{"uri", "untitled:a"}, {"version", version}, {"text", "task main() {}\n"}}}}));
  };
  // Read as an int, 2^40 was published as version 0.
  auto out = open(std::int64_t{1} << 40);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["params"]["version"], std::int64_t{1} << 40);
  // 1e300 was converted to an int (undefined; -2147483648 here); a version
  // that is not an integer makes the notification malformed, so it is dropped.
  EXPECT_TRUE(open(1e300).empty());
  EXPECT_TRUE(open("7").empty());
}

TEST(LspHostile, PositionsThatAreNotIntegersAreInvalidParams) {
  Session s("int a;\ntask main() { a = 1; }\n");
  for (json line : {json(1e300), json(-1e300), json(1.5), json("1"), json(nullptr)}) {
    auto out = handle(s.server, request(5, "textDocument/hover", {{"textDocument", {{"uri", s.uri}}},
                                                                   {"position", {{"line", line}, {"character", 4}}}}));
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0]["error"]["code"], kInvalidParams) << line.dump() << " " << out[0].dump();
  }
  // Integers out of any document's range are positions nowhere, not errors.
  for (json line : {json(std::uint64_t{18446744073709551615u}), json(std::int64_t{1} << 40), json(-1)})
    EXPECT_TRUE(s.ask("textDocument/hover", {{"position", {{"line", line}, {"character", line}}}}).is_null()) << line.dump();
  EXPECT_FALSE(s.at("textDocument/hover", 1, 15).is_null());
}

TEST(LspHostile, ABadDidChangeLeavesTheDocumentAsItWas) {
  Session s("int a;\ntask main() { a = 1; }\n");
  // A bad version, or a later change that is malformed, used to leave the
  // text changed but the index of the old text (and no diagnostics).
  EXPECT_TRUE(handle(s.server, change_note(s.uri, "two", json::array({{{"text", "int bbbbb;\ntask main() {}\n"}}}))).empty());
  EXPECT_TRUE(handle(s.server, change_note(s.uri, 2, json::array({{{"text", "int ccccc;\ntask main() {}\n"}}, 42}))).empty());
  // An empty edit shows what text the server holds: it is indexed afresh.
  auto out = handle(s.server, change_note(s.uri, 3, json::array({{{"range", {{"start", pos(0, 0)}, {"end", pos(0, 0)}}}, {"text", ""}}})));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["params"]["version"], 3);
  EXPECT_EQ(symbol_names(s), (std::vector<std::string>{"a", "main"}));
  // A null version (older clients) keeps the version and applies the text.
  out = handle(s.server, change_note(s.uri, nullptr, json::array({{{"text", "int d;\ntask main() { d = 1; }\n"}}})));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["params"]["version"], 3);
  EXPECT_EQ(symbol_names(s), (std::vector<std::string>{"d", "main"}));
}

TEST(LspHostile, AVeryLongUndeclaredNameIsAnsweredQuickly) {
  // Two 300,000-letter names one letter apart: the compiler's "did you
  // mean" took minutes over them (an edit distance costs the product of
  // the lengths), and the quick fix's std::regex overflowed the stack
  // matching the name in the message (SIGSEGV).
  const std::string a(300000, 'A');
  const std::string b = std::string(299999, 'A') + "B";
  Session s("int " + a + ";\ntask main()\n{\n  " + b + " = 1;\n}\n");
  ASSERT_EQ(s.diagnostics.size(), 1u);
  EXPECT_EQ(s.diagnostics[0]["message"], "'" + b + "' is not declared");
  json actions = s.ask("textDocument/codeAction", {{"range", {{"start", pos(3, 0)}, {"end", pos(3, 9)}}}});
  EXPECT_TRUE(actions.is_array() && actions.empty()) << actions.dump().substr(0, 200);
  // A short slip is still offered its fix.
  Session short_name("int counter;\ntask main() { countr = 1; }\n");
  json fixes = short_name.ask("textDocument/codeAction", {{"range", {{"start", pos(1, 0)}, {"end", pos(1, 30)}}}});
  ASSERT_FALSE(fixes.empty());
  EXPECT_EQ(fixes[0]["title"], "Change 'countr' to 'counter'");
}

TEST(LspHostile, ADocumentLargerThanASourceFileIsNotCompiled) {
  // rcxc compile refuses a source past 1 MiB; the server compiled any size
  // the framing allows (64 MiB), 6 s and 470 MB per change at 1 MiB.
  std::string text;
  while (text.size() <= kMaxDocument) text += "// a comment line to fill the document with\n";
  text += "task main() { x = 1; }\n";
  Session s(text);
  ASSERT_EQ(s.diagnostics.size(), 1u) << s.diagnostics.dump().substr(0, 300);
  EXPECT_NE(s.diagnostics[0]["message"].get<std::string>().find("larger than a source file may be (1 MiB)"), std::string::npos);
  EXPECT_EQ(s.diagnostics[0]["range"]["start"], pos(0, 0));
  EXPECT_TRUE(symbol_names(s).empty());
  // Cut below the cap, it is compiled again.
  auto out = handle(s.server, change_note(s.uri, 2, json::array({{{"text", "task main() { x = 1; }\n"}}})));
  EXPECT_EQ(out.at(0)["params"]["diagnostics"].at(0)["message"], "'x' is not declared");
}

TEST(LspHostile, ManyDiagnosticsArePublishedInLinearTime) {
  // 40,000 unused locals: each warning's line was found by scanning the
  // text from its start, 30 s of work; the compile itself takes a fraction
  // of a second.
  std::string text = "task main()\n{\n";
  for (int i = 0; i < 40000; ++i) text += "  int v" + std::to_string(i) + ";\n";
  text += "}\n";
  std::unique_ptr<Session> session;
  double seconds = test::cpu_seconds_for([&] { session = std::make_unique<Session>(text); });
  Session& s = *session;
  ASSERT_EQ(s.diagnostics.size(), 40000u);
  EXPECT_EQ(s.diagnostics[39999]["range"]["start"], pos(40001, 6));
  // Measured 3 s after the fix and 55 s before on a loaded 2-core machine.
  EXPECT_LT(seconds, test::built_with_asan() ? 40.0 : 15.0);
}

TEST(LspHostile, ManyRangedChangesInOneMessageAreCheapOrRefused) {
  // 20,000 ranged changes on a 100,000-line document: each found its line
  // from the text's start and moved the rest, two minutes in all; they
  // were then refused. Applied to the text held as lines, each costs its
  // line: they are applied, at once.
  std::string text;
  for (int i = 0; i < 100000; ++i) text += "// line\n";
  text += "task main() {}\n";
  Session s(text);
  json one = {{"range", {{"start", pos(99999, 0)}, {"end", pos(99999, 0)}}}, {"text", "x"}};
  json changes = json::array();
  for (int i = 0; i < 20000; ++i) changes.push_back(one);
  double seconds = test::cpu_seconds_for([&] { EXPECT_EQ(handle(s.server, change_note(s.uri, 2, changes)).size(), 1u); });
  EXPECT_LT(seconds, test::built_with_asan() ? 40.0 : 15.0);
  EXPECT_EQ(s.server.documents.at(s.uri).text.substr(99999 * 8, 20008), std::string(20000, 'x') + "// line\n");
  // 20,000 new lines at the top each move the 100,000 lines below: refused
  // (dropped whole) past 4 GiB of moving.
  json newline = {{"range", {{"start", pos(0, 0)}, {"end", pos(0, 0)}}}, {"text", "\n"}};
  changes = json::array();
  for (int i = 0; i < 20000; ++i) changes.push_back(newline);
  const std::string before = s.server.documents.at(s.uri).text;
  seconds = test::cpu_seconds_for([&] { EXPECT_TRUE(handle(s.server, change_note(s.uri, 3, changes)).empty()); });
  EXPECT_LT(seconds, test::built_with_asan() ? 40.0 : 15.0);
  EXPECT_EQ(s.server.documents.at(s.uri).text, before);
  // A few are still applied.
  auto out = handle(s.server, change_note(s.uri, 4, json::array({newline, newline})));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(s.server.documents.at(s.uri).text, "\n\n" + before);
}

TEST(LspHostile, ANoteInTheDocumentNamesItByTheClientsUri) {
  // The URI was rebuilt from the path: "untitled:Untitled-1" became a
  // file: URI under the server's working folder.
  Server server;
  handle(server, request(1, "initialize"));
  auto out = handle(server, note("textDocument/didOpen", {{"textDocument",
                                                           {{"uri", "untitled:Untitled-1"}, {"version", 1}, {"text", "task main()\n{\n"}}}}));
  const json& d = out.at(0)["params"]["diagnostics"].at(0);
  ASSERT_TRUE(d.contains("relatedInformation")) << d.dump();
  EXPECT_EQ(d["relatedInformation"][0]["location"]["uri"], "untitled:Untitled-1");
  EXPECT_EQ(d["relatedInformation"][0]["location"]["range"]["start"], pos(1, 0));
}

TEST(LspHostile, AnOversizedMessageIsSkippedAndTheNextOneRead) {
  // kMaxBody is not held, but its bytes are read past: the body's text was
  // taken for headers, and the messages after it were lost.
  const std::size_t size = kMaxBody + 1;
  std::istringstream in("Content-Length: " + std::to_string(size) + "\r\n\r\n" + std::string(size, 'x') +
                        framed({{"ok", true}}));
  Frame f = read_frame(in);
  EXPECT_EQ(f.kind, Frame::Kind::BadHeader);
  EXPECT_NE(f.error.find("skipped"), std::string::npos) << f.error;
  f = read_frame(in);
  ASSERT_EQ(f.kind, Frame::Kind::Message);
  EXPECT_EQ(json::parse(f.body)["ok"], true);
  // A body shorter than its length ends the input, as a truncated one does.
  std::istringstream short_body("Content-Length: " + std::to_string(size) + "\r\n\r\nxyz");
  EXPECT_EQ(read_frame(short_body).kind, Frame::Kind::End);
}

// ------------------------------------------------------- the real binary --

TEST(LspProcess, RcxcLspSpeaksOverStdio) {
  test::TempDir dir;
  std::string path = dir.write("p.nqc", "task main() { Wait(1) }\n");
  std::string input = framed(request(1, "initialize", {{"processId", nullptr}, {"capabilities", json::object()}})) +
                      framed(note("initialized")) +
                      framed(note("textDocument/didOpen", {{"textDocument",
                                                            {{"uri", path_to_uri(path)}, {"languageId", "nqc"},
                                                             {"version", 1}, {"text", "task main() { Wait(1) }\n"}}}})) +
                      "Bad-Header\r\n\r\n" + framed(request(2, "shutdown")) + framed(note("exit"));
  auto r = test::run_rcxc({"lsp", "--stdio"}, input, 20000);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::istringstream out(r.out);
  std::vector<json> messages;
  for (Frame f = read_frame(out); f.kind == Frame::Kind::Message; f = read_frame(out)) messages.push_back(json::parse(f.body));
  ASSERT_EQ(messages.size(), 3u) << r.out;
  EXPECT_EQ(messages[0]["id"], 1);
  EXPECT_EQ(messages[1]["method"], "textDocument/publishDiagnostics");
  EXPECT_FALSE(messages[1]["params"]["diagnostics"].empty());
  EXPECT_EQ(messages[2]["id"], 2);
  EXPECT_NE(r.err.find("skipped"), std::string::npos);
}

TEST(LspProcess, EndOfInputWithoutExitIsExitCodeOne) {
  auto r = test::run_rcxc({"lsp"}, framed(request(1, "initialize")), 20000);
  EXPECT_EQ(r.exit_code, 1);
  auto r2 = test::run_rcxc({"lsp"}, std::string("\x00\xff garbage", 10), 20000);
  EXPECT_EQ(r2.exit_code, 1);
  EXPECT_FALSE(r2.timed_out);
}

// ------------------------------------------------------- signature help --

const char* kCalls =
    "#define SCALE(x, y) ((x) * (y))\n"                   // 0
    "// Blinks the light.\n"                              // 1
    "void blink(const int times, int &left, int pause)\n"  // 2
    "{\n"                                                 // 3
    "  left = times;\n"                                   // 4
    "}\n"                                                 // 5
    "task main()\n"                                       // 6
    "{\n"                                                 // 7
    "  int n;\n"                                          // 8
    "  blink(SCALE(1, 2), n, (3 + 4));\n"                 // 9
    "  blink(',', /* , ( */ n, 5);\n"                     // 10
    "  SetPower(OUT_A, 7);\n"                             // 11
    "}\n";                                                // 12

// The one signature's label and active parameter, and the active
// parameter's text (the label cut at its offsets).
struct Shown {
  std::string label;
  int active = -1;
  std::string parameter;
};

Shown signature_at(Session& s, int line, int character) {
  json help = s.at("textDocument/signatureHelp", line, character);
  if (help.is_null()) return {};
  EXPECT_EQ(help["signatures"].size(), 1u) << help.dump();
  const json& sig = help["signatures"][0];
  Shown shown{sig["label"], help["activeParameter"], ""};
  EXPECT_EQ(sig["activeParameter"], help["activeParameter"]);
  if (shown.active >= 0 && shown.active < static_cast<int>(sig["parameters"].size())) {
    const json& offsets = sig["parameters"][shown.active]["label"];
    int b = offsets[0], e = offsets[1];
    shown.parameter = shown.label.substr(b, e - b);
  }
  return shown;
}

TEST(LspSignatureHelp, TheCalledFunctionsSignatureAndTheArgumentAtTheCursor) {
  Session s(kCalls);
  Shown shown = signature_at(s, 9, 8);  // blink(|
  EXPECT_EQ(shown.label, "void blink(const int times, int &left, int pause)");
  EXPECT_EQ(shown.active, 0);
  EXPECT_EQ(shown.parameter, "const int times");
  shown = signature_at(s, 9, 20);  // after SCALE(1, 2),
  EXPECT_EQ(shown.parameter, "int &left");
  shown = signature_at(s, 9, 25);  // in (3 + 4): a parenthesis that only groups
  EXPECT_EQ(shown.active, 2);
  EXPECT_EQ(shown.parameter, "int pause");
  json help = s.at("textDocument/signatureHelp", 9, 8);
  EXPECT_EQ(help["signatures"][0]["documentation"]["value"], "Blinks the light.");
}

TEST(LspSignatureHelp, TheInnermostCallAndMacrosWithParameters) {
  Session s(kCalls);
  Shown shown = signature_at(s, 9, 14);  // SCALE(|
  EXPECT_EQ(shown.label, "#define SCALE(x, y)");
  EXPECT_EQ(shown.parameter, "x");
  shown = signature_at(s, 9, 17);  // SCALE(1, |
  EXPECT_EQ(shown.active, 1);
  EXPECT_EQ(shown.parameter, "y");
}

TEST(LspSignatureHelp, MacroNamesAndSubs) {
  // A macro named like a part of "#define", a sub (no parameters), and a
  // macro whose body starts with '(' (no parameter list: no signature).
  Session s("#define def(a) (a)\n#define ONE (1)\nsub go() { }\ntask main()\n{\n  def(1);\n  go();\n  ONE(;\n}\n");
  Shown shown = signature_at(s, 5, 6);
  EXPECT_EQ(shown.label, "#define def(a)");
  EXPECT_EQ(shown.parameter, "a");
  json help = s.at("textDocument/signatureHelp", 6, 5);
  EXPECT_EQ(help["signatures"][0]["label"], "sub go()");
  EXPECT_TRUE(help["signatures"][0]["parameters"].empty());
  EXPECT_TRUE(s.at("textDocument/signatureHelp", 7, 6).is_null());
}

TEST(LspSignatureHelp, ApiFunctions) {
  Session s(kCalls);
  Shown shown = signature_at(s, 11, 18);  // SetPower(OUT_A, |
  EXPECT_EQ(shown.label, "void SetPower(const int outputs, const int &power)");
  EXPECT_EQ(shown.active, 1);
  EXPECT_EQ(shown.parameter, "const int &power");
}

TEST(LspSignatureHelp, CommasInCharactersAndCommentsAreNoSeparators) {
  Session s(kCalls);
  EXPECT_EQ(signature_at(s, 10, 9).active, 0);   // inside ','
  EXPECT_EQ(signature_at(s, 10, 19).active, 1);  // inside /* , ( */
  EXPECT_EQ(signature_at(s, 10, 26).active, 2);  // before 5
}

TEST(LspSignatureHelp, NothingOutsideACall) {
  Session s(kCalls);
  EXPECT_TRUE(s.at("textDocument/signatureHelp", 9, 7).is_null());   // blink|(
  EXPECT_TRUE(s.at("textDocument/signatureHelp", 9, 33).is_null());  // after the ;
  EXPECT_TRUE(s.at("textDocument/signatureHelp", 8, 5).is_null());   // int n
  Session keyword("task main()\n{\n  int n;\n  if (n == 1, \n}\n");
  EXPECT_TRUE(keyword.at("textDocument/signatureHelp", 3, 14).is_null());
  // A call left open at the end of the document: only up to the end.
  Session open_call("task main()\n{\n  Wait(");
  EXPECT_EQ(signature_at(open_call, 2, 7).label, "void Wait(const int &ticks)");
  EXPECT_TRUE(open_call.at("textDocument/signatureHelp", 3, 0).is_null());
  EXPECT_TRUE(open_call.at("textDocument/signatureHelp", 99999, 0).is_null());
}

// ---------------------------------------------------------------- rename --

const char* kNames =
    "int count;\n"                                 // 0
    "#define LIMIT 10\n"                           // 1
    "void bump(int &c)\n"                          // 2
    "{\n"                                          // 3
    "  c += 1;\n"                                  // 4
    "}\n"                                          // 5
    "task main()\n"                                // 6
    "{\n"                                          // 7
    "  int speed;\n"                               // 8
    "  count = 0;\n"                               // 9
    "  speed = LIMIT;\n"                           // 10
    "  bump(count);\n"                             // 11
    "  OnFwd(OUT_A);\n"                            // 12
    "}\n"                                          // 13
    "task other() { int count; count = 2; }\n";    // 14

// The ranges a rename of the name at (line, character) to `name` edits in
// the session's document, in order.
std::vector<json> renamed(Session& s, int line, int character, const std::string& name) {
  json edit = s.ask("textDocument/rename", {{"position", pos(line, character)}, {"newName", name}});
  std::vector<json> ranges;
  for (const auto& e : edit["changes"][s.uri]) {
    EXPECT_EQ(e["newText"], name);
    ranges.push_back(e["range"]);
  }
  std::sort(ranges.begin(), ranges.end(), [](const json& a, const json& b) {
    return std::pair(a["start"]["line"].get<int>(), a["start"]["character"].get<int>()) <
           std::pair(b["start"]["line"].get<int>(), b["start"]["character"].get<int>());
  });
  return ranges;
}

TEST(LspRename, AGlobalEverywhereButWhereALocalShadowsIt) {
  Session s(kNames);
  EXPECT_EQ(renamed(s, 9, 2, "hits"), (std::vector<json>{range_at(0, 4, 9), range_at(9, 2, 7), range_at(11, 7, 12)}));
  EXPECT_EQ(renamed(s, 14, 26, "n"), (std::vector<json>{range_at(14, 19, 24), range_at(14, 26, 31)}));
}

TEST(LspRename, ParametersMacrosAndFunctions) {
  Session s(kNames);
  EXPECT_EQ(renamed(s, 4, 2, "amount"), (std::vector<json>{range_at(2, 15, 16), range_at(4, 2, 3)}));
  EXPECT_EQ(renamed(s, 10, 10, "MAXIMUM"), (std::vector<json>{range_at(1, 8, 13), range_at(10, 10, 15)}));
  EXPECT_EQ(renamed(s, 11, 3, "add_one"), (std::vector<json>{range_at(2, 5, 9), range_at(11, 2, 6)}));
  // Renaming to the same name changes nothing.
  json same = s.ask("textDocument/rename", {{"position", pos(9, 2)}, {"newName", "count"}});
  EXPECT_TRUE(same["changes"].empty()) << same.dump();
}

TEST(LspRename, RenameAgreesWithReferences) {
  Session s(kNames);
  for (auto [line, character] : {std::pair{9, 2}, {14, 26}, {4, 2}, {10, 10}, {11, 3}, {8, 6}}) {
    json refs = s.ask("textDocument/references",
                      {{"position", pos(line, character)}, {"context", {{"includeDeclaration", true}}}});
    EXPECT_EQ(renamed(s, line, character, "fresh").size(), refs.size()) << line << ":" << character;
  }
}

TEST(LspRename, PrepareRenameGivesTheNamesRange) {
  Session s(kNames);
  json prep = s.at("textDocument/prepareRename", 9, 4);
  EXPECT_EQ(prep["range"], range_at(9, 2, 7));
  EXPECT_EQ(prep["placeholder"], "count");
  EXPECT_TRUE(s.at("textDocument/prepareRename", 3, 0).is_null());  // on "{"
}

TEST(LspRename, TheApiAndKeywordsAreRefused) {
  Session s(kNames);
  for (auto [line, character, why] : {std::tuple{12, 3, "'OnFwd' is part of the RCX API (rcx.nqh) and cannot be renamed"},
                                      {12, 8, "'OUT_A' is part of the RCX API (rcx.nqh) and cannot be renamed"},
                                      {6, 1, "'task' is a keyword and cannot be renamed"}}) {
    for (const char* method : {"textDocument/prepareRename", "textDocument/rename"}) {
      json e = error_of(s, method, {{"position", pos(line, character)}, {"newName", "x"}});
      ASSERT_FALSE(e.is_null()) << method << " " << line;
      EXPECT_EQ(e["code"], kRequestFailed);
      EXPECT_EQ(e["message"], why);
    }
  }
  json e = error_of(s, "textDocument/rename", {{"position", pos(3, 0)}, {"newName", "x"}});
  EXPECT_EQ(e["message"], "there is no name at this position to rename");
}

TEST(LspRename, BadOrClashingNewNamesAreRefused) {
  Session s(kNames);
  auto refusal = [&](int line, int character, const std::string& name) {
    json e = error_of(s, "textDocument/rename", {{"position", pos(line, character)}, {"newName", name}});
    EXPECT_FALSE(e.is_null()) << name;
    if (e.is_null()) return std::string();
    EXPECT_EQ(e["code"], kRequestFailed);
    return e["message"].get<std::string>();
  };
  EXPECT_EQ(refusal(9, 2, "2x"), "'2x' is not a valid name (letters, digits and _, not starting with a digit)");
  EXPECT_EQ(refusal(9, 2, "a-b"), "'a-b' is not a valid name (letters, digits and _, not starting with a digit)");
  EXPECT_EQ(refusal(9, 2, ""), "'' is not a valid name (letters, digits and _, not starting with a digit)");
  EXPECT_EQ(refusal(9, 2, "while"), "'while' is a keyword");
  EXPECT_EQ(refusal(9, 2, "abs"), "'abs' is a keyword");  // NQC's own, not C's
  // main uses the global count where its local speed is in scope.
  EXPECT_EQ(refusal(9, 2, "speed"), "renaming 'count' to 'speed' would clash with the local variable 'speed' at line 9");
  EXPECT_EQ(refusal(8, 6, "count"), "renaming 'speed' to 'count' would clash with the global variable 'count' at line 1");
  EXPECT_EQ(refusal(9, 2, "LIMIT"), "renaming 'count' to 'LIMIT' would clash with the macro 'LIMIT' at line 2");
  EXPECT_EQ(refusal(9, 2, "OnFwd"), "renaming 'count' to 'OnFwd' would clash with the function 'OnFwd' in the RCX API (rcx.nqh)");
  EXPECT_EQ(refusal(11, 3, "main"), "renaming 'bump' to 'main' would clash with the task 'main' at line 7");
  // The local count of task other clashes with nothing outside it.
  EXPECT_EQ(renamed(s, 14, 26, "speed").size(), 2u);
}

TEST(LspRename, UsesInAnIncludedFileAreRenamedThere) {
  test::TempDir dir;
  std::string lib = dir.write("lib.nqh", "int shared;\nvoid reset() { shared = 0; }\n");
  std::string text = "#include \"lib.nqh\"\ntask main() { shared = 1; reset(); }\n";
  std::string path = dir.write("p.nqc", text);
  Server server;
  handle(server, request(1, "initialize"));
  std::string uri = path_to_uri(path);
  handle(server, note("textDocument/didOpen", {{"textDocument", {{"uri", uri}, {"text", text}}}}));
  json params = {{"textDocument", {{"uri", uri}}}, {"position", pos(1, 15)}, {"newName", "total"}};
  json changes = handle(server, request(2, "textDocument/rename", params)).at(0)["result"]["changes"];
  ASSERT_EQ(changes.size(), 2u) << changes.dump();
  EXPECT_EQ(changes[uri], json::array({{{"range", range_at(1, 14, 20)}, {"newText", "total"}}}));
  json in_lib = changes[path_to_uri(lib)];
  ASSERT_EQ(in_lib.size(), 2u) << changes.dump();
  EXPECT_EQ(in_lib[0]["range"], range_at(0, 4, 10));
  EXPECT_EQ(in_lib[1]["range"], range_at(1, 15, 21));
}

// -------------------------------------------------------- highlighting --

TEST(LspDocumentHighlight, EveryUseInTheDocumentWithReadAndWrite) {
  Session s(kNames);
  using H = std::vector<std::tuple<int, int, int>>;
  const int text = 1, read = 2, write = 3;
  // bump(count) may write count (bump takes it by reference): Text.
  EXPECT_EQ(highlights(s, 11, 8), (H{{0, 4, write}, {9, 2, write}, {11, 7, text}}));
  EXPECT_EQ(highlights(s, 4, 2), (H{{2, 15, write}, {4, 2, write}}));
  EXPECT_EQ(highlights(s, 10, 11), (H{{1, 8, text}, {10, 10, text}}));  // a macro
  EXPECT_EQ(highlights(s, 12, 3), (H{{12, 2, text}}));                  // OnFwd: only the use is here
  EXPECT_TRUE(s.at("textDocument/documentHighlight", 3, 0).is_null());
  Session reads("int a;\nint b;\ntask main() { b = a + 1; if (a) b++; ++a; }\n");
  EXPECT_EQ(highlights(reads, 0, 4), (H{{0, 4, write}, {2, 18, read}, {2, 29, read}, {2, 39, write}}));
}

// ----------------------------------------- the new requests, hostile --

TEST(LspHostile, TheNewRequestsAnswerBadPositionsAndParamsProperly) {
  Session s(kNames);
  for (const char* method : {"textDocument/signatureHelp", "textDocument/prepareRename", "textDocument/documentHighlight"}) {
    EXPECT_TRUE(s.at(method, 999999, 0).is_null()) << method;
    EXPECT_TRUE(s.at(method, 0, 999999).is_null()) << method;
    EXPECT_TRUE(s.at(method, -1, 0).is_null()) << method;
    json e = error_of(s, method, json::object());  // no position
    ASSERT_FALSE(e.is_null()) << method;
    EXPECT_EQ(e["code"], kInvalidParams);
    e = error_of(s, method, {{"position", {{"line", 1.5}, {"character", 0}}}});
    EXPECT_EQ(e["code"], kInvalidParams);
  }
  json e = error_of(s, "textDocument/rename", {{"position", pos(999999, 0)}, {"newName", "x"}});
  EXPECT_EQ(e["code"], kRequestFailed);
  e = error_of(s, "textDocument/rename", {{"position", pos(9, 2)}});  // no newName
  EXPECT_EQ(e["code"], kInvalidParams);
  e = error_of(s, "textDocument/rename", {{"position", pos(9, 2)}, {"newName", 42}});
  EXPECT_EQ(e["code"], kInvalidParams);
  double seconds = test::cpu_seconds_for([&] {
    e = error_of(s, "textDocument/rename", {{"position", pos(9, 2)}, {"newName", std::string(1000000, 'a')}});
  });
  EXPECT_EQ(e["message"], "the new name is 1000000 characters long; at most 255 are accepted");
  EXPECT_LT(seconds, 2.0);
  // A document never opened: nothing is known about it.
  for (const char* method : {"textDocument/signatureHelp", "textDocument/prepareRename", "textDocument/rename",
                             "textDocument/documentHighlight"}) {
    auto out = handle(s.server, request(3, method, {{"textDocument", {{"uri", "file:///nowhere.nqc"}}},
                                                    {"position", pos(0, 0)}, {"newName", "x"}}));
    ASSERT_EQ(out.size(), 1u);
    EXPECT_TRUE(out[0]["result"].is_null()) << out[0].dump();
  }
}

TEST(LspHostile, AHugeNameInTheDocumentIsRenamedAndHighlightedQuickly) {
  const std::string big(300000, 'v');
  Session s("int " + big + ";\ntask main() { " + big + " = 1; }\n");
  double seconds = test::cpu_seconds_for([&] {
    EXPECT_EQ(highlights(s, 1, 20).size(), 2u);
    EXPECT_EQ(renamed(s, 1, 20, "v").size(), 2u);
    EXPECT_EQ(error_of(s, "textDocument/rename", {{"position", pos(0, 4)}, {"newName", "main"}})["code"],
              kRequestFailed);
  });
  EXPECT_LT(seconds, 5.0);
}

TEST(LspHostile, TheNewRequestsStayFastOnALargeDocument) {
  // 10,000 lines: 2,000 globals each used in its own function, and one
  // global used on every line of a task. Measured (Release, loaded 2-core
  // machine): signatureHelp 2 ms (it lexes the document), documentHighlight
  // 0.06 s, rename 0.13 s, references 0.07 s; before references looked up
  // the name's definitions once, 0.3 s, 1.1 s and 0.34 s.
  std::string text = "int hits;\n";
  for (int i = 0; i < 2000; ++i) text += "int g" + std::to_string(i) + ";\n";
  for (int i = 0; i < 2000; ++i) text += "void f" + std::to_string(i) + "(int a, int b) { g" + std::to_string(i) + " = a + b; }\n";
  text += "task main()\n{\n";
  for (int i = 0; i < 5990; ++i) text += "  hits = f" + std::to_string(i % 2000) + "(hits, 1) + 0;\n";
  text += "  SetPower(OUT_A, \n}\n";
  Session s(text);
  const int last = 4003 + 5990;  // the SetPower line
  auto timed = [](const std::function<void()>& f) { return test::cpu_seconds_for(f); };
  double help = timed([&] { EXPECT_EQ(signature_at(s, last, 18).active, 1); });
  double highlight = timed([&] { EXPECT_EQ(highlights(s, 0, 4).size(), 1u + 2 * 5990); });
  double rename = timed([&] { EXPECT_EQ(renamed(s, 0, 4, "bumps").size(), 1u + 2 * 5990); });
  double refs = timed([&] {
    s.ask("textDocument/references", {{"position", pos(0, 4)}, {"context", {{"includeDeclaration", true}}}});
  });
  std::cerr << "10,000 lines: signatureHelp " << help << " s, documentHighlight " << highlight << " s, rename "
            << rename << " s, references " << refs << " s\n";
  const double limit = test::built_with_asan() ? 30.0 : 5.0;
  EXPECT_LT(help, limit);
  EXPECT_LT(highlight, limit);
  EXPECT_LT(rename, limit);
}

}  // namespace
}  // namespace rcxc::lsp
