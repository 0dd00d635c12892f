// A sensor read but never given a type or mode warns once, where it is
// first read, at every level (ir/sensor_setup.cpp). Lines and columns are
// counted by hand from the test texts.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

constexpr ir::OptLevel kLevels[] = {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os};

// "line:column SENSOR_n" for each warning about a sensor never set up.
std::vector<std::string> unset_sensors(const std::string& text, ir::OptLevel level) {
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  auto out = backend::compile_source("test.nqc", text, frontend::Options{}, level, sm, diags, log);
  EXPECT_TRUE(out.has_value());
  std::vector<std::string> found;
  for (const Diagnostic& d : diags.all())
    if (d.severity == Severity::Warning && d.message.find("never set up") != std::string::npos)
      found.push_back(std::to_string(d.span.begin.line) + ":" + std::to_string(d.span.begin.column) + " " +
                      d.message.substr(0, d.message.find(' ')));
  return found;
}

TEST(SensorSetup, ASensorReadButNeverSetUpWarnsWhereItIsFirstRead) {
  const std::string text =
      "task main()\n"                          // 1
      "{\n"                                    // 2
      "  SetSensor(SENSOR_2, SENSOR_LIGHT);\n" // 3
      "  while (true)\n"                       // 4
      "  {\n"                                  // 5
      "    if (SENSOR_1 == 1) PlaySound(1);\n" // 6
      "    until (SENSOR_3 > 40);\n"           // 7
      "    if (SENSOR_1 == 0 && SENSOR_2 > 50) PlaySound(2);\n"  // 8
      "  }\n"                                  // 9
      "}\n";                                   // 10
  for (auto level : kLevels)
    EXPECT_EQ(unset_sensors(text, level), (std::vector<std::string>{"6:5 SENSOR_1", "7:5 SENSOR_3"}))
        << "level " << static_cast<int>(level);
}

TEST(SensorSetup, SetUpAnywhereByTypeOrModeOrInAFunctionOrAnotherTask) {
  // SENSOR_1's type is set in a function, SENSOR_2's mode alone, SENSOR_3's
  // in another task: none warns. Raw readings need no set-up.
  const std::string text =
      "void setup(const int &s) { SetSensorType(s, SENSOR_TYPE_TOUCH); }\n"
      "task other() { SetSensor(SENSOR_3, SENSOR_ROTATION); }\n"
      "int x;\n"
      "task main()\n"
      "{\n"
      "  setup(SENSOR_1);\n"
      "  SetSensorMode(SENSOR_2, SENSOR_MODE_PERCENT);\n"
      "  start other;\n"
      "  x = SENSOR_1 + SENSOR_2 + SENSOR_3 + SensorValueRaw(0) + SensorValueRaw(1);\n"
      "}\n";
  for (auto level : kLevels) EXPECT_EQ(unset_sensors(text, level), std::vector<std::string>{});
}

TEST(SensorSetup, AProgramWhoseAsmBytesMaySetASensorUpIsNotJudged) {
  // The bytes may set SENSOR_1 up (here they do: senstype 0, 1).
  const std::string text = "int x;\ntask main()\n{\n  asm { 0x32, 0, 1 };\n  x = SENSOR_1;\n}\n";
  EXPECT_EQ(unset_sensors(text, ir::OptLevel::O2), std::vector<std::string>{});
  // UploadDatalog is asm bytes too, none of them a sensor's set-up.
  const std::string upload = "int x;\ntask main()\n{\n  UploadDatalog(0, 1);\n  x = SENSOR_1;\n}\n";
  EXPECT_EQ(unset_sensors(upload, ir::OptLevel::O2), std::vector<std::string>{"5:3 SENSOR_1"});
}

}  // namespace
}  // namespace rcxc
