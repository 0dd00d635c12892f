#include "rcx/file_read.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

using namespace rcx;

TEST(FileRead, BytesComeBackUnchanged) {
  auto path = std::filesystem::temp_directory_path() / "rcxc-file-read-test.bin";
  const std::string bytes("a\r\nb\0c\xff", 7);
  std::ofstream(path, std::ios::binary) << bytes;
  auto result = read_file(path.string(), kSourceFile);
  std::filesystem::remove(path);
  ASSERT_TRUE(std::holds_alternative<std::string>(result));
  EXPECT_EQ(std::get<std::string>(result), bytes);
}

TEST(FileRead, DirectoryAndMissingFileAreProblems) {
  auto dir = std::filesystem::temp_directory_path() / "rcxc-file-read-test-dir";
  std::filesystem::create_directories(dir);
  auto from_dir = read_file(dir.string(), kSourceFile);
  std::filesystem::remove(dir);
  ASSERT_TRUE(std::holds_alternative<FileProblem>(from_dir));
  EXPECT_EQ(std::get<FileProblem>(from_dir), FileProblem::Directory);
  auto missing = read_file((dir / "no-such-file").string(), kSourceFile);
  ASSERT_TRUE(std::holds_alternative<FileProblem>(missing));
  EXPECT_EQ(std::get<FileProblem>(missing), FileProblem::CannotOpen);
}

// "cannot open 'P'" alone left the user to guess between a mistyped name
// and a file they may not read.
TEST(FileRead, AFileThatCannotBeOpenedSaysWhy) {
  auto dir = std::filesystem::temp_directory_path() / "rcxc-file-read-reason";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  EXPECT_EQ(cannot_open_reason((dir / "missing.nqc").string()), "no such file");
  std::filesystem::create_symlink(dir / "nowhere", dir / "dangling.nqc");
  EXPECT_EQ(cannot_open_reason((dir / "dangling.nqc").string()), "a symbolic link to nothing");
  auto locked = dir / "locked.nqc";
  std::ofstream(locked) << "task main() {}\n";
  std::filesystem::permissions(locked, std::filesystem::perms::none);
  // root reads any file, so the refusal shows only to other users.
  if (::geteuid() != 0) {
    EXPECT_TRUE(std::holds_alternative<FileProblem>(read_file(locked.string(), kSourceFile)));
    EXPECT_EQ(cannot_open_reason(locked.string()), "permission denied");
  }
  std::filesystem::remove_all(dir);
}

// Two links leading to each other (`ln -s a b; ln -s b a`) were "a
// symbolic link to nothing": the name is there, and so is what it leads
// to, round and round (ELOOP).
TEST(FileRead, ALoopOfLinksIsSaidToBeOne) {
  auto dir = std::filesystem::temp_directory_path() / "rcxc-file-read-loop";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::filesystem::create_symlink("b.nqc", dir / "a.nqc");
  std::filesystem::create_symlink("a.nqc", dir / "b.nqc");
  std::filesystem::create_symlink("self", dir / "self");
  const std::string loop = "a loop of symbolic links that never reaches a file";
  EXPECT_TRUE(std::holds_alternative<FileProblem>(read_file((dir / "a.nqc").string(), kSourceFile)));
  EXPECT_EQ(cannot_open_reason((dir / "a.nqc").string()), loop);
  EXPECT_EQ(cannot_open_reason((dir / "self").string()), loop);
  // A loop on the way to the file, in a folder of its path.
  EXPECT_EQ(cannot_open_reason((dir / "self" / "p.nqc").string()), loop);
  EXPECT_EQ(cannot_open_reason(""), "no file name");
  std::filesystem::remove_all(dir);
}

TEST(FileRead, EndlessDevicesStopAtTheCap) {
  // /dev/zero never ends: the reader stops one byte past the cap.
  FileKind tiny{"test file", 4096};
  auto zero = read_file("/dev/zero", tiny);
  ASSERT_TRUE(std::holds_alternative<FileProblem>(zero));
  EXPECT_EQ(std::get<FileProblem>(zero), FileProblem::TooLarge);
  auto urandom = read_file("/dev/urandom", kImageFile);
  ASSERT_TRUE(std::holds_alternative<FileProblem>(urandom));
  EXPECT_EQ(std::get<FileProblem>(urandom), FileProblem::TooLarge);
  EXPECT_EQ(too_large_message("/dev/zero", kScenarioFile),
            "/dev/zero: larger than a scenario file may be (1 MiB); is it the right file?");
}

TEST(FileRead, AFileOfExactlyTheCapIsRead) {
  auto path = std::filesystem::temp_directory_path() / "rcxc-file-read-cap.bin";
  std::ofstream(path, std::ios::binary) << std::string(4096, 'x');
  auto exact = read_file(path.string(), FileKind{"test file", 4096});
  auto over = read_file(path.string(), FileKind{"test file", 4095});
  std::filesystem::remove(path);
  ASSERT_TRUE(std::holds_alternative<std::string>(exact));
  EXPECT_EQ(std::get<std::string>(exact).size(), 4096u);
  ASSERT_TRUE(std::holds_alternative<FileProblem>(over));
}

TEST(FileRead, BinaryDataIsAnImageSignatureOrANulInTheFirst4KiB) {
  EXPECT_TRUE(rcx::starts_as_image(std::string("RCXI\x01\x02", 6)));
  EXPECT_FALSE(rcx::starts_as_image("RCX"));
  EXPECT_TRUE(rcx::holds_binary_data("RCXI"));
  EXPECT_TRUE(rcx::holds_binary_data(std::string("task\0main", 9)));
  EXPECT_FALSE(rcx::holds_binary_data("task main() {}\n"));
  std::string late(4096, 'x');
  late += '\0';  // byte 4096: past what is looked at
  EXPECT_FALSE(rcx::holds_binary_data(late));
  late[4095] = '\0';
  EXPECT_TRUE(rcx::holds_binary_data(late));
}
