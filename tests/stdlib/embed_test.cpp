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
