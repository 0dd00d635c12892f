// Decoding bytecode through the opcode table: a request-only opcode in a
// program (an asm block's Upload datalog) is no instruction a task runs,
// but a listing can name it with the request's layout. The bytes and values
// are worked out by hand from the seed's layouts (Upload datalog 0xa4/0xac:
// short first, short count, little-endian).
#include "rcx/decode.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

using namespace rcx;

namespace {

constexpr auto kNotACommand = static_cast<std::uint8_t>(DecodeError::NotACommand);
constexpr auto kTruncated = static_cast<std::uint8_t>(DecodeError::Truncated);

TEST(Decode, ARequestIsNoCommandForATask) {
  const std::vector<std::uint8_t> code = {0xa4, 0x01, 0x00, 0x02, 0x00};
  Decoded d = decode_command(code, 0);
  EXPECT_EQ(d.error, kNotACommand);
  EXPECT_EQ(d.size, 1);  // what the emulator faults on, one byte
}

TEST(Decode, UploadDatalogInCodeHasItsRequestLayout) {
  const std::vector<std::uint8_t> code = {0x10, 0xa4, 0x01, 0x00, 0x02, 0x01, 0xac, 0x00, 0x00, 0x05, 0x00};
  auto d = decode_request(code, 1);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->op, Op::UploadDatalog);
  EXPECT_EQ(d->error, kNotACommand);
  EXPECT_EQ(d->size, 5);
  EXPECT_EQ(d->v[0], 1);      // first
  EXPECT_EQ(d->v[1], 0x0102);  // count, little-endian
  // The toggled form is the same request.
  auto toggled = decode_request(code, 6);
  ASSERT_TRUE(toggled);
  EXPECT_EQ(toggled->op, Op::UploadDatalog);
  EXPECT_EQ(toggled->size, 5);
  EXPECT_EQ(toggled->v[0], 0);
  EXPECT_EQ(toggled->v[1], 5);
  auto alive = decode_request(code, 0);
  ASSERT_TRUE(alive);
  EXPECT_EQ(alive->op, Op::Alive);
  EXPECT_EQ(alive->size, 1);
}

TEST(Decode, ARequestCutShortIsTruncated) {
  const std::vector<std::uint8_t> code = {0xa4, 0x01, 0x00};
  auto d = decode_request(code, 0);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->op, Op::UploadDatalog);
  EXPECT_EQ(d->error, kTruncated);
  EXPECT_EQ(d->size, 1);
}

TEST(Decode, OnlyRequestOnlyOpcodesDecodeAsRequests) {
  // Set variable (0x14) is a command too; 0x00 is nothing; Transfer data's
  // size comes from its own length field; past the end is nothing.
  const std::vector<std::uint8_t> code = {0x14, 0x00, 0x45, 0x00, 0x00, 0x01, 0x00, 0x07, 0x07};
  EXPECT_FALSE(decode_request(code, 0));
  EXPECT_FALSE(decode_request(code, 1));
  EXPECT_FALSE(decode_request(code, 2));
  EXPECT_FALSE(decode_request(code, 9));
  EXPECT_FALSE(decode_request(code, -1));
}

}  // namespace
