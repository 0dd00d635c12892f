// Inlay hints: each argument of a call gets its parameter's name before it.
// Every expected line and character is counted by hand from the test text
// (LSP counts from 0).
#include <gtest/gtest.h>

#include <tuple>

#include "tests/lsp/session.h"

namespace rcxc::lsp {
namespace {

using Hints = std::vector<std::tuple<int, int, std::string>>;

Hints hints(Session& s, json range) {
  Hints out;
  for (const auto& h : s.ask("textDocument/inlayHint", {{"range", range}})) {
    EXPECT_EQ(h["kind"], 2);  // Parameter
    EXPECT_EQ(h["paddingRight"], true);
    out.emplace_back(h["position"]["line"], h["position"]["character"], h["label"]);
  }
  return out;
}

json whole(int lines) { return {{"start", pos(0, 0)}, {"end", pos(lines, 0)}}; }

TEST(LspInlayHints, NameTheParametersOfApiCallsFunctionsAndMacros) {
  Session s(
      "#define TURN(ms, power) SetPower(OUT_A, power); Wait(ms)\n"  // 0
      "void drive(const int &speed, int time) { Wait(time); }\n"    // 1
      "task main()\n"                                               // 2
      "{\n"                                                         // 3
      "  int time = 5;\n"                                           // 4
      "  PlayTone(440, 2 * (3 + 1));\n"                             // 5
      "  drive(Random(3), time);\n"                                 // 6
      "  TURN(100, 7);\n"                                           // 7
      "  SetSensor(SENSOR_1, SENSOR_TOUCH);\n"                      // 8
      "}\n");                                                       // 9
  EXPECT_EQ(hints(s, whole(10)), (Hints{
                                     // The macro's body calls the API with its own parameters.
                                     // SetPower's `power` passed as `power` needs no hint.
                                     {0, 33, "outputs:"},
                                     {0, 53, "ticks:"},
                                     // drive's own parameter list is no call; its body's Wait is.
                                     {1, 46, "ticks:"},
                                     {5, 11, "frequency:"},
                                     {5, 16, "duration:"},
                                     // A call in an argument: both get theirs; `time` passed as
                                     // `time` needs none.
                                     {6, 8, "speed:"},
                                     {6, 15, "n:"},
                                     {7, 7, "ms:"},
                                     {7, 12, "power:"},
                                     {8, 12, "sensor:"},
                                     {8, 22, "config:"},
                                 }));
}

TEST(LspInlayHints, OnlyInTheRangeAsked) {
  Session s(
      "task main()\n"              // 0
      "{\n"                        // 1
      "  PlayTone(440, 50);\n"     // 2
      "  PlayTone(880,\n"          // 3
      "           100);\n"         // 4
      "}\n");                      // 5
  // From line 3 to the middle of line 4's argument: its start is inside.
  EXPECT_EQ(hints(s, {{"start", pos(3, 0)}, {"end", pos(4, 12)}}), (Hints{{3, 11, "frequency:"}, {4, 11, "duration:"}}));
  // A range ending at an argument's first character leaves it out.
  EXPECT_EQ(hints(s, {{"start", pos(2, 0)}, {"end", pos(2, 16)}}), (Hints{{2, 11, "frequency:"}}));
}

TEST(LspInlayHints, ExtraEmptyAndBrokenArgumentsGetNone) {
  Session s(
      "task main()\n"                   // 0
      "{\n"                             // 1
      "  PlayTone(440, 50, 7);\n"       // 2: one argument too many
      "  PlayTone(, 50);\n"             // 3: an empty first argument
      "  Wait(\n"                       // 4: left open by a typo
      "  Off(OUT_A);\n"                 // 5
      "  unknown(3);\n"                 // 6: nothing known of it
      "  if (Random(4) > 1) Wait((2));\n"  // 7: a grouping '(' is no call
      "  Wait(;\n"                       // 8: a statement's end is no argument
      "}\n");                           // 9
  EXPECT_EQ(hints(s, whole(10)), (Hints{{2, 11, "frequency:"},
                                       {2, 16, "duration:"},
                                       {3, 13, "duration:"},
                                       // What the typo leaves open takes Off's call as
                                       // its argument, up to the statement's end.
                                       {5, 2, "ticks:"},
                                       {5, 6, "outputs:"},
                                       {7, 13, "n:"},
                                       {7, 26, "ticks:"}}));
}

TEST(LspInlayHints, TheServerSaysItHasThem) {
  Server server;
  auto out = handle(server, request(1, "initialize", {{"capabilities", json::object()}}));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["result"]["capabilities"]["inlayHintProvider"], true);
}

}  // namespace
}  // namespace rcxc::lsp
