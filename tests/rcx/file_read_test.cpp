#include "rcx/file_read.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace rcx;

TEST(FileRead, BytesComeBackUnchanged) {
  auto path = std::filesystem::temp_directory_path() / "rcxc-file-read-test.bin";
  const std::string bytes("a\r\nb\0c\xff", 7);
  std::ofstream(path, std::ios::binary) << bytes;
  auto result = read_file(path.string());
  std::filesystem::remove(path);
  ASSERT_TRUE(std::holds_alternative<std::string>(result));
  EXPECT_EQ(std::get<std::string>(result), bytes);
}

TEST(FileRead, DirectoryAndMissingFileAreProblems) {
  auto dir = std::filesystem::temp_directory_path() / "rcxc-file-read-test-dir";
  std::filesystem::create_directories(dir);
  auto from_dir = read_file(dir.string());
  std::filesystem::remove(dir);
  ASSERT_TRUE(std::holds_alternative<FileProblem>(from_dir));
  EXPECT_EQ(std::get<FileProblem>(from_dir), FileProblem::Directory);
  auto missing = read_file((dir / "no-such-file").string());
  ASSERT_TRUE(std::holds_alternative<FileProblem>(missing));
  EXPECT_EQ(std::get<FileProblem>(missing), FileProblem::CannotOpen);
}
