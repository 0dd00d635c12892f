#include "rcx/image.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace rcx;
using Bytes = std::vector<std::uint8_t>;

namespace {

// An image as `nqc -Trcx -O` writes it for a one-task program with two
// variables: header, task 0 of 6 bytes (+2 pad), symbols main, x, y.
const Bytes kNqcImage = {
    0x52, 0x43, 0x58, 0x49, 0x02, 0x01, 0x01, 0x00, 0x03, 0x00, 0x00, 0x00,  // header
    0x00, 0x00, 0x06, 0x00,                                                  // task 0, 6 bytes
    0x13, 0x07, 0x02, 0x07, 0xe1, 0x87, 0x00, 0x00,                          // code + pad
    0x00, 0x00, 0x05, 0x00, 'm', 'a', 'i', 'n', 0x00,                        // task 0 "main"
    0x02, 0x00, 0x02, 0x00, 'x', 0x00,                                       // var 0 "x"
    0x02, 0x01, 0x02, 0x00, 'y', 0x00,                                       // var 1 "y"
};

std::string error_of(const Bytes& b) {
  auto r = read_image(b);
  if (auto* e = std::get_if<ImageError>(&r)) return e->message;
  return "";
}

}  // namespace

TEST(Image, ReadsWhatNqcWrites) {
  auto r = read_image(kNqcImage);
  ASSERT_TRUE(std::holds_alternative<Image>(r)) << std::get<ImageError>(r).message;
  const Image& img = std::get<Image>(r);
  ASSERT_EQ(img.fragments.size(), 1u);
  EXPECT_EQ(img.fragments[0].type, FragmentType::Task);
  EXPECT_EQ(img.fragments[0].code, (Bytes{0x13, 0x07, 0x02, 0x07, 0xe1, 0x87}));
  EXPECT_EQ(img.name_of(SymbolType::Task, 0), "main");
  EXPECT_EQ(img.name_of(SymbolType::Variable, 1), "y");
  EXPECT_EQ(img.name_of(SymbolType::Variable, 2), "");
}

TEST(Image, WritesTheSameBytesBack) {
  auto img = std::get<Image>(read_image(kNqcImage));
  EXPECT_EQ(write_image(img), kNqcImage);
}

TEST(Image, RoundTripsSubroutinesAndOddLengths) {
  Image img;
  img.fragments.push_back({FragmentType::Task, 0, {0x50}});
  img.fragments.push_back({FragmentType::Subroutine, 7, {1, 2, 3, 4, 5}});
  img.symbols.push_back({SymbolType::Subroutine, 7, "helper"});
  auto bytes = write_image(img);
  EXPECT_EQ(bytes.size(), 12u + 4 + 4 + 4 + 8 + 4 + 7);
  auto back = std::get<Image>(read_image(bytes));
  ASSERT_EQ(back.fragments.size(), 2u);
  EXPECT_EQ(back.fragments[1].code, (Bytes{1, 2, 3, 4, 5}));
  EXPECT_EQ(back.name_of(SymbolType::Subroutine, 7), "helper");
}

TEST(Image, RejectsBadInput) {
  EXPECT_NE(error_of({}).find("too short"), std::string::npos);
  Bytes b = kNqcImage;
  b[0] = 'X';
  EXPECT_NE(error_of(b).find("signature"), std::string::npos);
  b = kNqcImage;
  b[4] = 0x03;
  EXPECT_NE(error_of(b).find("version"), std::string::npos);
  b = kNqcImage;
  b[14] = 0x40;  // code length 64 runs past the end
  EXPECT_NE(error_of(b).find("past the end"), std::string::npos);
  b = kNqcImage;
  b[13] = 10;  // task index 10
  EXPECT_NE(error_of(b).find("out of range"), std::string::npos);
  b = kNqcImage;
  b[12] = 5;  // fragment type 5
  EXPECT_NE(error_of(b).find("unknown type"), std::string::npos);
  b = kNqcImage;
  b.resize(b.size() - 3);  // last symbol name cut
  EXPECT_NE(error_of(b).find("past the end"), std::string::npos);
  b = kNqcImage;
  b.push_back(0);
  EXPECT_NE(error_of(b).find("unexpected bytes"), std::string::npos);
}

TEST(Image, RejectsDuplicateFragments) {
  Image img;
  img.fragments.push_back({FragmentType::Task, 1, {0x50}});
  img.fragments.push_back({FragmentType::Task, 1, {0x50}});
  EXPECT_NE(error_of(write_image(img)).find("duplicate task 1"), std::string::npos);
}

TEST(Image, ErrorsSayWhere) {
  Bytes b = kNqcImage;
  b[4] = 0x03;
  EXPECT_EQ(error_of(b).rfind("offset 4:", 0), 0u);
}

// Found by the command-line property test: `rcxc disasm .` aborted, because
// reading a directory through a filebuf throws instead of failing.
TEST(Image, ReadingADirectoryIsAnErrorNotACrash) {
  auto dir = std::filesystem::temp_directory_path() / "rcxc-image-test-dir.rcx";
  std::filesystem::create_directories(dir);
  auto result = read_image_file(dir.string());
  std::filesystem::remove(dir);
  ASSERT_TRUE(std::holds_alternative<ImageError>(result));
  EXPECT_EQ(std::get<ImageError>(result).message, dir.string() + ": is a directory, not an .rcx image");
}
