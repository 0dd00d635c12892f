#include "stdlib/stdlib.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

TEST(Stdlib, EmbeddedTextIsTheFileOnDisk) {
  auto text = rcxc::stdlib::find("rcx.nqh");
  ASSERT_TRUE(text.has_value());
  std::ifstream in(RCXC_SOURCE_DIR "/stdlib/rcx.nqh", std::ios::binary);
  std::stringstream disk;
  disk << in.rdbuf();
  EXPECT_EQ(*text, disk.str());
  EXPECT_FALSE(rcxc::stdlib::find("missing.nqh").has_value());
}

TEST(Stdlib, DefinedNumbersAreTheLibrarysPlainNumberDefines) {
  auto sounds = rcxc::stdlib::defined_numbers("SOUND_");
  ASSERT_EQ(sounds.size(), 6u);
  EXPECT_EQ(sounds[0].name, "SOUND_CLICK");
  EXPECT_EQ(sounds[0].value, 0);
  EXPECT_EQ(sounds[1].name, "SOUND_DOUBLE_BEEP");
  EXPECT_EQ(sounds[1].value, 1);
  EXPECT_EQ(sounds[5].name, "SOUND_FAST_UP");
  EXPECT_EQ(sounds[5].value, 5);
  // Hex literals are read; SENSOR_TOUCH (an expression) is not a plain number.
  auto modes = rcxc::stdlib::defined_numbers("SENSOR_MODE_");
  ASSERT_FALSE(modes.empty());
  EXPECT_EQ(modes.back().name, "SENSOR_MODE_ROTATION");
  EXPECT_EQ(modes.back().value, 0xe0);
  for (const auto& n : rcxc::stdlib::defined_numbers("SENSOR_")) EXPECT_NE(n.name, "SENSOR_TOUCH");
  EXPECT_TRUE(rcxc::stdlib::defined_numbers("NO_SUCH_PREFIX_").empty());
}
