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

// A symbol name of 1000 bytes (its length byte, 1001 in one byte, is 233)
// was "name is not NUL-terminated": the NUL is there, 767 bytes later. The
// name is longer than the format allows, and the message says the limit.
TEST(Image, ASymbolNameLongerThanTheFormatAllowsSaysTheLimit) {
  auto image_with_name = [](std::size_t length_byte, const std::string& name_bytes) {
    Bytes b = {0x52, 0x43, 0x58, 0x49, 0x02, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00};
    for (int v : {2, 0, static_cast<int>(length_byte), 0}) b.push_back(static_cast<std::uint8_t>(v));
    b.insert(b.end(), name_bytes.begin(), name_bytes.end());
    return b;
  };
  std::string long_name(1000, 'a');
  EXPECT_EQ(error_of(image_with_name(1001 & 0xff, long_name + '\0')),
            "offset 16: symbol 1: name of 1000 bytes, longer than an image can hold: its length is one byte counting "
            "the NUL too, so a name has at most 254 bytes (this one's length byte says 233)");
  EXPECT_EQ(kMaxSymbolName, 254u);
  // The longest name there may be is read, and written back the same.
  std::string longest(kMaxSymbolName, 'b');
  auto at_limit = image_with_name(255, longest + '\0');
  auto read = read_image(at_limit);
  ASSERT_TRUE(std::holds_alternative<Image>(read)) << std::get<ImageError>(read).message;
  EXPECT_EQ(std::get<Image>(read).name_of(SymbolType::Variable, 0), longest);
  EXPECT_EQ(write_image(std::get<Image>(read)), at_limit);
  // Other mistakes in a name say what they are, not all "not NUL-terminated".
  EXPECT_EQ(error_of(image_with_name(5, std::string("ab\0d\0", 5))),
            "offset 18: symbol 1: name holds a NUL after 2 of the 5 bytes its length gives (the length counts the "
            "name and the one NUL that ends it)");
  EXPECT_EQ(error_of(image_with_name(3, std::string("abcd\0", 5))),
            "offset 18: symbol 1: name of 4 bytes runs on past the 2 its length byte gives (the length counts the "
            "name and its NUL)");
  EXPECT_EQ(error_of(image_with_name(3, "abcd")),
            "offset 18: symbol 1: name is not NUL-terminated (no NUL in its 3 bytes or in the rest of the file)");
  EXPECT_EQ(error_of(image_with_name(9, "abc")), "offset 19: symbol 1: name runs past the end of the file");
  EXPECT_EQ(error_of(image_with_name(0, "")),
            "offset 14: symbol 1: name length 0, which leaves no room for the NUL that ends a name (the length counts "
            "it)");
}

// The other fields of a symbol say what they may be.
TEST(Image, ASymbolsTypeAndIndexSayWhatTheyMayBe) {
  Bytes b = kNqcImage;
  b[34] = 40;  // var "x" at index 40
  EXPECT_EQ(error_of(b), "offset 34: symbol 'x': variable index 40 out of range 0..31");
  b = kNqcImage;
  b[24] = 3;  // symbol "main" of type 3
  EXPECT_EQ(error_of(b), "offset 24: symbol 1: unknown type 3 (0 = task, 1 = subroutine, 2 = variable)");
}

// A name past the limit was written with its length byte wrapped (301 as
// 45, as nqc writes it): an image rcxc itself then refused. It is cut.
TEST(Image, ANameTooLongForTheFormatIsWrittenCutToTheLimit) {
  Image img;
  img.fragments.push_back({FragmentType::Task, 0, {0x50}});
  img.symbols.push_back({SymbolType::Variable, 0, std::string(300, 'v')});
  img.symbols.push_back({SymbolType::Task, 0, "main"});
  auto read = read_image(write_image(img));
  ASSERT_TRUE(std::holds_alternative<Image>(read)) << std::get<ImageError>(read).message;
  EXPECT_EQ(std::get<Image>(read).name_of(SymbolType::Variable, 0), std::string(kMaxSymbolName, 'v'));
  EXPECT_EQ(std::get<Image>(read).name_of(SymbolType::Task, 0), "main");
}
