// `rcxc debug` end to end: a real adapter process driven by a scripted
// client (client.h), as an editor drives it.
#include <gtest/gtest.h>

#include "tests/dap/client.h"
#include "tests/support/process.h"

namespace rcxc::dap::test {
namespace {

// Line numbers matter below: each is said beside its line.
constexpr const char* kProgram =
    "int count;\n"            // 1
    "int seen;\n"             // 2
    "\n"                      // 3
    "sub bump() {\n"          // 4
    "  count += 10;\n"        // 5
    "  count += 1;\n"         // 6
    "}\n"                     // 7
    "\n"                      // 8
    "task main() {\n"         // 9
    "  int k = 2;\n"          // 10
    "  count = 5;\n"          // 11
    "  start other;\n"        // 12
    "  bump();\n"             // 13
    "  k = count + 1;\n"      // 14
    "  Wait(100);\n"          // 15
    "  seen = SENSOR_1;\n"    // 16
    "  count = k;\n"          // 17
    "}\n"                     // 18
    "\n"                      // 19
    "task other() {\n"        // 20
    "  while (true) {\n"      // 21
    "    Wait(50);\n"         // 22
    "  }\n"                   // 23
    "}\n";                    // 24

struct Fixture : ::testing::Test {
  rcxc::test::TempDir dir;
  std::string program = dir.write("prog.nqc", kProgram);
  json launch(json extra = json::object()) {
    json args = {{"program", program}};
    for (auto& [k, v] : extra.items()) args[k] = v;
    return args;
  }
};

using Debug = Fixture;

TEST_F(Debug, BreakpointStopsAtItsLineWithTheVariablesThen) {
  Client c;
  json placed = c.start(launch(), program, {14});
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_TRUE(placed[0]["verified"]);
  EXPECT_EQ(placed[0]["line"], 14);
  json stop = c.event("stopped");
  EXPECT_EQ(stop["body"]["reason"], "breakpoint");
  EXPECT_EQ(stop["body"]["threadId"], 1);
  EXPECT_EQ(stop["body"]["hitBreakpointIds"], json::array({placed[0]["id"]}));
  EXPECT_EQ(c.line(1), 14);
  auto globals = c.variables(c.scope(1, "Globals"));
  EXPECT_EQ(globals["count"], "16");  // 5, then bump's 10 and 1
  EXPECT_EQ(globals["seen"], "0");
  auto locals = c.variables(c.scope(1, "Locals"));
  EXPECT_EQ(locals["k"], "2");  // line 14 has not run
  json value = c.body("evaluate", {{"expression", "count"}, {"context", "hover"}});
  EXPECT_EQ(value["result"], "16");
  EXPECT_FALSE(c.ask("evaluate", {{"expression", "nothing"}}).value("success", true));
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, ABreakpointOnALineWithoutCodeMovesToTheNextLineWithCode) {
  Client c;
  json placed = c.start(launch(), program, {3, 8, 30});
  ASSERT_EQ(placed.size(), 3u);
  EXPECT_TRUE(placed[0]["verified"]);
  EXPECT_EQ(placed[0]["line"], 5);   // line 4 is the sub's header: no code
  EXPECT_TRUE(placed[1]["verified"]);
  EXPECT_EQ(placed[1]["line"], 9);   // main's start-up code is at its header
  EXPECT_FALSE(placed[2]["verified"]);
  EXPECT_NE(placed[2].value("message", "").find("no code at line 30"), std::string::npos) << placed[2];
  EXPECT_EQ(c.event("stopped")["body"]["reason"], "breakpoint");
  EXPECT_EQ(c.line(1), 9);
  c.body("continue", {{"threadId", 1}});
  EXPECT_EQ(c.event("stopped")["body"]["reason"], "breakpoint");
  EXPECT_EQ(c.frames(1), (std::vector<std::pair<std::string, int>>{{"bump", 5}, {"main", 13}}));
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, NextStepInAndStepOutGoByLines) {
  Client c;
  c.start(launch(), program, {11});
  EXPECT_EQ(c.event("stopped")["body"]["reason"], "breakpoint");
  EXPECT_EQ(c.line(1), 11);
  auto step = [&](const std::string& how) {
    c.body(how, {{"threadId", 1}});
    json stop = c.event("stopped");
    EXPECT_EQ(stop["body"]["reason"], "step") << how;
    EXPECT_EQ(stop["body"]["threadId"], 1) << how;
    return c.line(1);
  };
  EXPECT_EQ(step("next"), 12);
  EXPECT_EQ(step("next"), 13);
  EXPECT_EQ(step("stepIn"), 5);
  EXPECT_EQ(c.frames(1).size(), 2u);
  EXPECT_EQ(step("next"), 6);
  EXPECT_EQ(step("stepOut"), 14);
  EXPECT_EQ(c.frames(1).size(), 1u);
  EXPECT_EQ(c.variables(c.scope(1, "Globals"))["count"], "16");
  EXPECT_EQ(step("next"), 15);
  EXPECT_EQ(c.variables(c.scope(1, "Locals"))["k"], "17");
  // Over the call this time: bump runs whole.
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, NextStepsOverASubroutineCall) {
  Client c;
  c.start(launch(), program, {13});
  c.event("stopped");
  c.body("next", {{"threadId", 1}});
  c.event("stopped");
  EXPECT_EQ(c.line(1), 14);
  EXPECT_EQ(c.variables(c.scope(1, "Globals"))["count"], "16");
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, TwoTasksAreTwoThreads) {
  Client c;
  c.start(launch(), program, {22});
  json stop = c.event("stopped");
  EXPECT_EQ(stop["body"]["threadId"], 2);
  json threads = c.body("threads")["threads"];
  ASSERT_EQ(threads.size(), 2u) << threads;
  EXPECT_EQ(threads[0]["name"], "main");
  EXPECT_EQ(threads[0]["id"], 1);
  EXPECT_EQ(threads[1]["name"], "other");
  EXPECT_EQ(threads[1]["id"], 2);
  EXPECT_EQ(c.line(2), 22);
  EXPECT_EQ(c.frames(2)[0].first, "other");
  std::string main_in = c.frames(1)[0].first;
  EXPECT_TRUE(main_in == "main" || main_in == "bump") << main_in;
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, AScenarioInputIsSeenInTheVariables) {
  std::string scenario = dir.write("s.toml", "[[input]]\nat_ms = 50\nsensor = 1\nraw = 321\n");
  Client c;
  c.start(launch({{"scenario", scenario}}), program, {17});
  EXPECT_EQ(c.event("stopped")["body"]["reason"], "breakpoint");
  EXPECT_EQ(c.variables(c.scope(1, "Globals"))["seen"], "321");
  auto brick = c.variables(c.scope(1, "Brick"));
  EXPECT_EQ(brick["sensor 1"], "321");
  EXPECT_EQ(brick["output A"], "float fwd power 7");
  EXPECT_EQ(brick["time"].substr(0, 3), "1.0") << brick["time"];  // Wait(100) passed
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, StopOnEntryAndPause) {
  std::string busy = dir.write("busy.nqc", "int n;\ntask main() {\n  while (true) {\n    n++;\n  }\n}\n");
  Client c;
  c.start({{"program", busy}, {"stopOnEntry", true}, {"for", 1'000'000'000}});
  json stop = c.event("stopped");
  EXPECT_EQ(stop["body"]["reason"], "entry");
  EXPECT_EQ(c.line(1), 2);
  c.body("continue", {{"threadId", 1}});
  usleep(200'000);
  c.body("pause", {{"threadId", 1}});
  stop = c.event("stopped");
  EXPECT_EQ(stop["body"]["reason"], "pause");
  int line = c.line(1);
  EXPECT_TRUE(line == 3 || line == 4) << line;
  EXPECT_NE(c.variables(c.scope(1, "Globals"))["n"], "0");
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, TheEndOfTheProgramIsExitedAndTerminated) {
  std::string ends = dir.write("ends.nqc", "int n;\ntask main() {\n  n = 3;\n  OnFwd(OUT_A);\n}\n");
  Client c;
  c.start({{"program", ends}});
  EXPECT_EQ(c.event("exited")["body"]["exitCode"], 0);
  EXPECT_FALSE(c.event("terminated").is_null());
  bool saw_output = false;
  for (const auto& o : c.outputs) saw_output |= o["output"].get<std::string>().find("\"output\"") != std::string::npos;
  EXPECT_TRUE(saw_output);
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);

  Client limited;
  limited.start(launch({{"for", 500}}));
  EXPECT_EQ(limited.event("exited")["body"]["exitCode"], 2);  // task other never ends
  limited.body("disconnect");
  EXPECT_EQ(limited.finish(), 0);
}

TEST_F(Debug, BreakpointsInAnIncludedFile) {
  // A sub: an inline function's code counts as the line that calls it.
  dir.write("inc.nqh", "sub twice() {\n  count += 2;\n}\n");
  std::string main = dir.write("main.nqc", "int count;\n#include \"inc.nqh\"\ntask main() {\n  twice();\n  count += 1;\n}\n");
  Client c;
  json placed = c.start({{"program", main}}, dir.path + "/inc.nqh", {2});
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_TRUE(placed[0]["verified"]) << placed;
  EXPECT_EQ(c.event("stopped")["body"]["reason"], "breakpoint");
  json top = c.body("stackTrace", {{"threadId", 1}})["stackFrames"][0];
  EXPECT_EQ(top["line"], 2);
  EXPECT_EQ(top["source"]["name"], "inc.nqh");
  EXPECT_EQ(c.frames(1), (std::vector<std::pair<std::string, int>>{{"twice", 2}, {"main", 4}}));
  EXPECT_EQ(c.variables(c.scope(1, "Globals"))["count"], "0");
  c.body("next", {{"threadId", 1}});
  c.event("stopped");
  EXPECT_EQ(c.frames(1), (std::vector<std::pair<std::string, int>>{{"twice", 3}, {"main", 4}}));  // its return, at '}'
  c.body("next", {{"threadId", 1}});
  c.event("stopped");
  top = c.body("stackTrace", {{"threadId", 1}})["stackFrames"][0];
  EXPECT_EQ(top["line"], 5);
  EXPECT_EQ(top["source"]["name"], "main.nqc");
  EXPECT_EQ(c.variables(c.scope(1, "Globals"))["count"], "2");
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

// The program's events with breakpoints hit and continued are those of a
// run without: stopping changes nothing the program does, or when.
TEST_F(Debug, StoppingChangesNoEvent) {
  auto events_of = [&](const std::vector<int>& lines, int& stops) {
    Client c;
    std::string scenario = dir.write("s.toml", "[[input]]\nat_ms = 50\nsensor = 1\nraw = 321\n");
    c.start(launch({{"for", 3000}, {"scenario", scenario}}), program, lines);
    stops = 0;
    for (;;) {
      json e = c.event_of({"stopped", "exited"});
      if (e.is_null() || e["event"] == "exited") break;
      ++stops;
      c.send("continue", {{"threadId", e["body"]["threadId"]}});
    }
    std::vector<std::string> seen;
    for (const auto& o : c.outputs) seen.push_back(o["output"]);
    c.body("disconnect");
    EXPECT_EQ(c.finish(), 0);
    return seen;
  };
  int stops = 0;
  auto plain = events_of({}, stops);
  EXPECT_EQ(stops, 0);
  auto stopped = events_of({5, 14, 16, 22}, stops);
  EXPECT_GE(stops, 8);  // lines 5, 14 and 16 once, line 22 every 0.5 s for 3 s
  // The warning, two task starts, the input and its reading, main's end, the time limit.
  EXPECT_GE(plain.size(), 7u);
  EXPECT_EQ(plain, stopped);
}

// A loop's jump back carries a line of the loop (at -O0 here the Wait's,
// at -O2 the repeat's); it is no statement of its own: a breakpoint stops
// once an iteration, `next` goes from the body's last line to its first.
constexpr const char* kLoop =
    "int n;\n"                      // 1
    "sub bump() {\n"                // 2
    "  n += 5;\n"                   // 3
    "}\n"                           // 4
    "task main() {\n"               // 5
    "  repeat (3) {\n"              // 6
    "    n += 1;\n"                 // 7
    "    Wait(20);\n"               // 8
    "    bump();\n"                 // 9
    "    n = (n + 1) % 7;\n"        // 10
    "  }\n"                         // 11
    "  n = 0;\n"                    // 12
    "}\n";                          // 13

TEST_F(Debug, ALoopsBreakpointsStopOnceAnIteration) {
  std::string loop = dir.write("loop.nqc", kLoop);
  for (const char* optimize : {"0", "2"}) {
    Client c;
    c.start({{"program", loop}, {"optimize", optimize}}, loop, {6, 7, 8, 10});
    std::vector<int> lines;
    for (;;) {
      json e = c.event_of({"stopped", "exited"});
      if (e.is_null() || e["event"] == "exited") break;
      lines.push_back(c.line(1));
      c.send("continue", {{"threadId", 1}});
    }
    EXPECT_EQ(lines, (std::vector<int>{6, 7, 8, 10, 7, 8, 10, 7, 8, 10})) << "-O" << optimize;
    c.body("disconnect");
    EXPECT_EQ(c.finish(), 0);
  }
}

TEST_F(Debug, NextGoesRoundALoopLineByLine) {
  std::string loop = dir.write("loop.nqc", kLoop);
  Client c;
  c.start({{"program", loop}, {"stopOnEntry", true}});
  c.event("stopped");
  std::vector<int> lines{c.line(1)};
  for (int i = 0; i < 20; ++i) {
    c.body("next", {{"threadId", 1}});
    json e = c.event_of({"stopped", "exited"});
    if (e.is_null() || e["event"] == "exited") break;
    lines.push_back(c.line(1));
  }
  EXPECT_EQ(lines, (std::vector<int>{5, 6, 7, 8, 9, 10, 7, 8, 9, 10, 7, 8, 9, 10, 12, 13}));
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, ABreakpointAtNoLineIsRefused) {
  Client c;
  json placed = c.start(launch(), program, {0, -4});
  ASSERT_EQ(placed.size(), 2u);
  for (const auto& b : placed) {
    EXPECT_FALSE(b["verified"]) << b;
    EXPECT_NE(b.value("message", "").find("lines count from 1"), std::string::npos) << b;
  }
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, FramesArePagedAndAFrameThatIsNotThereHasNoScopes) {
  Client c;
  c.start(launch(), program, {5});
  c.event("stopped");
  json all = c.body("stackTrace", {{"threadId", 1}});
  ASSERT_EQ(all["stackFrames"].size(), 2u);
  json second = c.body("stackTrace", {{"threadId", 1}, {"startFrame", 1}, {"levels", 20}});
  ASSERT_EQ(second["stackFrames"].size(), 1u) << second;
  EXPECT_EQ(second["stackFrames"][0], all["stackFrames"][1]);
  EXPECT_EQ(second["totalFrames"], 2);
  json first = c.body("stackTrace", {{"threadId", 1}, {"startFrame", 0}, {"levels", 1}});
  ASSERT_EQ(first["stackFrames"].size(), 1u) << first;
  EXPECT_EQ(first["stackFrames"][0], all["stackFrames"][0]);
  EXPECT_EQ(first["totalFrames"], 2);
  for (json frame : {json(9999), json(-1), json(all["stackFrames"][0]["id"].get<int>() + 16 * 5)}) {
    json r = c.ask("scopes", {{"frameId", frame}});
    EXPECT_FALSE(r.value("success", true)) << frame << ": " << r;
  }
  EXPECT_TRUE(c.ask("scopes", {{"frameId", all["stackFrames"][1]["id"]}}).value("success", false));
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, ARequestWithoutACommandIsAnsweredWithAFailure) {
  Client c;
  c.write_raw(framed(R"({"seq":7,"type":"request","arguments":{}})"));
  json r = c.response(7);
  EXPECT_FALSE(r.value("success", true)) << r;
  EXPECT_NE(r.value("message", "").find("'command'"), std::string::npos) << r;
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, AMessageNestedAMillionDeepIsSaidNotFollowed) {
  // Copying or printing such JSON recurses once a level: it overflowed the stack.
  Client c;
  c.write_raw(framed(std::string(1'000'000, '[') + std::string(1'000'000, ']')));
  json said = c.event("output");
  EXPECT_NE(said["body"]["output"].get<std::string>().find("nested deeper than 100"), std::string::npos) << said;
  std::string deep = R"({"seq":1,"type":"request","command":"launch","arguments":)";
  for (int i = 0; i < 200'000; ++i) deep += R"({"a":)";
  deep += "1" + std::string(200'000, '}') + "}";
  c.write_raw(framed(deep));
  said = c.event("output");
  EXPECT_NE(said["body"]["output"].get<std::string>().find("nested deeper than 100"), std::string::npos) << said;
  // Strings are not counted: brackets in them are text.
  json launch = {{"program", std::string(150, '[') + ".nqc"}};
  json r = c.ask("launch", launch);
  EXPECT_FALSE(r.value("success", true));
  EXPECT_NE(r.value("message", "").find("[[[["), std::string::npos) << r;
  EXPECT_TRUE(c.ask("initialize").value("success", false));
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

// VS Code's Run Without Debugging launches with noDebug: the program runs
// to its end, past breakpoints and the entry.
TEST_F(Debug, NoDebugRunsThroughToTheEnd) {
  Client c;
  json placed = c.start(launch({{"noDebug", true}, {"stopOnEntry", true}, {"for", 500}}), program, {14});
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_FALSE(placed[0]["verified"]) << placed;
  json e = c.event_of({"stopped", "exited"});
  EXPECT_EQ(e["event"], "exited") << e;
  EXPECT_EQ(e["body"]["exitCode"], 2);  // task other never ends
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
  Client refused;
  refused.body("initialize");
  EXPECT_FALSE(refused.ask("launch", launch({{"noDebug", "yes"}})).value("success", true));
  refused.body("disconnect");
  EXPECT_EQ(refused.finish(), 0);
}

// A fault ends the run with exit code 1 and says where, by the source line.
TEST_F(Debug, AFaultIsSaidAtItsLine) {
  std::string faults = dir.write("fault.nqc", "int n;\ntask main() {\n  n = 1;\n  asm { 0x27, 0x7f };\n  n = 2;\n}\n");
  Client c;
  c.start({{"program", faults}});
  EXPECT_EQ(c.event("exited")["body"]["exitCode"], 1);
  std::string said;
  for (const auto& o : c.outputs)
    if (o["category"] == "stderr") said += o["output"].get<std::string>();
  EXPECT_NE(said.find("the program faulted in main at " + faults + ":4 (address "), std::string::npos) << said;
  EXPECT_NE(said.find("outside the code"), std::string::npos) << said;
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, AProgramThatDoesNotCompileFailsTheLaunchWithTheDiagnostic) {
  std::string bad = dir.write("bad.nqc", "task main() {\n  x = 1;\n}\n");
  Client c;
  c.body("initialize");
  json r = c.ask("launch", {{"program", bad}});
  EXPECT_FALSE(r["success"]);
  EXPECT_NE(r.value("message", "").find("bad.nqc:2:3: error"), std::string::npos) << r;
  json out = c.event("output");
  EXPECT_EQ(out["body"]["category"], "stderr");
  EXPECT_NE(out["body"]["output"].get<std::string>().find("bad.nqc:2:3: error"), std::string::npos) << out;
  json missing = c.ask("launch", {{"program", dir.path + "/none.nqc"}});
  EXPECT_FALSE(missing["success"]);
  EXPECT_NE(missing.value("message", "").find("none.nqc"), std::string::npos) << missing;
  for (const json& args : {json{{"program", program}, {"optimize", "3"}}, json{{"program", 5}},
                           json{{"program", program}, {"for", -1}}, json{{"program", program}, {"scenario", dir.path + "/no.toml"}},
                           json{{"program", program}, {"defines", {"1X"}}}}) {
    json refused = c.ask("launch", args);
    EXPECT_FALSE(refused["success"]) << args;
    EXPECT_FALSE(refused.value("message", "").empty()) << args;
  }
  c.body("disconnect");
  EXPECT_EQ(c.finish(), 0);
}

TEST_F(Debug, MalformedInputIsSaidAndTheSessionGoesOn) {
  Client c;
  c.write_raw(framed("{not json"));
  json said = c.event("output");
  EXPECT_NE(said["body"]["output"].get<std::string>().find("not JSON"), std::string::npos) << said;
  c.write_raw("Content-Type: x\r\n\r\n");
  said = c.event("output");
  EXPECT_NE(said["body"]["output"].get<std::string>().find("no Content-Length"), std::string::npos) << said;
  json unknown = c.ask("fly");
  EXPECT_FALSE(unknown["success"]);
  EXPECT_NE(unknown.value("message", "").find("'fly'"), std::string::npos);
  EXPECT_TRUE(c.ask("initialize").value("success", false));
  EXPECT_FALSE(c.ask("continue", {{"threadId", 1}}).value("success", true));  // nothing launched
  // A message cut short by the end of the input: said, exit 1, no hang.
  c.write_raw("Content-Length: 50\r\n\r\n{\"seq\":");
  EXPECT_EQ(c.finish(), 1);
  EXPECT_NE(c.errors().find("the input ended inside a message"), std::string::npos);
}

// The launch configuration the VS Code extension offers is one the adapter
// takes, and every attribute it declares is one the adapter reads (a value
// of the wrong kind is refused, naming it).
TEST_F(Debug, TheVsCodeLaunchConfigurationIsOneTheAdapterTakes) {
  json package = json::parse(rcxc::test::read_text_file(RCXC_SOURCE_DIR "/editors/vscode/package.json"));
  const json& debugger = package["contributes"]["debuggers"][0];
  EXPECT_EQ(debugger["type"], "rcxc");
  json config = debugger["initialConfigurations"][0];
  EXPECT_EQ(config["program"], "${file}");
  config["program"] = program;
  for (const char* vscode_own : {"type", "request", "name"}) config.erase(vscode_own);
  {
    Client c;
    c.body("initialize");
    EXPECT_TRUE(c.ask("launch", config).value("success", false)) << config;
    c.body("disconnect");
    EXPECT_EQ(c.finish(), 0);
  }
  const json& properties = debugger["configurationAttributes"]["launch"]["properties"];
  EXPECT_EQ(properties.size(), 7u);
  for (const auto& [key, schema] : properties.items()) {
    Client c;
    c.body("initialize");
    json args = {{"program", program}};
    args[key] = json::object();  // no attribute takes an object
    json refused = c.ask("launch", args);
    EXPECT_FALSE(refused.value("success", true)) << key;
    EXPECT_NE(refused.value("message", "").find("'" + key + "'"), std::string::npos) << key << ": " << refused;
    c.body("disconnect");
    EXPECT_EQ(c.finish(), 0);
  }
}

}  // namespace
}  // namespace rcxc::dap::test
