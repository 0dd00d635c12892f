// The firmware S-record reader: what a real file gives, and that every
// address, count, checksum and record type is checked before a byte is
// stored (issue 21: a 19-byte file wrote to an address taken from it).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "link/remote.h"

using namespace rcx;

namespace {

// One S-record line: type digit, address of `addr_len` bytes, data, with
// the count and checksum computed here (not by the reader under test).
std::string record(char type, std::uint64_t addr, int addr_len, const std::vector<int>& data) {
  std::vector<int> body;
  body.push_back(addr_len + static_cast<int>(data.size()) + 1);
  for (int i = addr_len - 1; i >= 0; --i) body.push_back(static_cast<int>((addr >> (8 * i)) & 0xff));
  body.insert(body.end(), data.begin(), data.end());
  int sum = 0;
  std::string line = fmt::format("S{}", type);
  for (int b : body) {
    line += fmt::format("{:02X}", b);
    sum += b;
  }
  return line + fmt::format("{:02X}\n", ~sum & 0xff);
}

std::string error_of(const std::string& text) {
  auto r = parse_srec(text);
  return std::holds_alternative<std::string>(r) ? std::get<std::string>(r) : "(parsed)";
}

}  // namespace

TEST(Srec, DataFrom0x8000WithEntry) {
  auto r = parse_srec(record('0', 0, 2, {'f', 'w'}) + record('1', 0x8000, 2, {1, 2}) +
                      record('1', 0x8004, 2, {3}) + record('9', 0x8002, 2, {}));
  ASSERT_TRUE(std::holds_alternative<Firmware>(r)) << std::get<std::string>(r);
  const auto& fw = std::get<Firmware>(r);
  EXPECT_EQ(fw.start, 0x8000);
  EXPECT_EQ(fw.entry, 0x8002);
  EXPECT_EQ(fw.bytes, (Bytes{1, 2, 0, 0, 3}));
}

TEST(Srec, DataAfter0x8000IsPlacedWhereTheRomStoresIt) {
  // The ROM stores the download from 0x8000 on, so a file starting later is
  // padded to its real place rather than shifted down.
  auto r = parse_srec(record('1', 0x8002, 2, {7}));
  ASSERT_TRUE(std::holds_alternative<Firmware>(r));
  EXPECT_EQ(std::get<Firmware>(r).bytes, (Bytes{0, 0, 7}));
  EXPECT_EQ(std::get<Firmware>(r).entry, 0x8000);
}

TEST(Srec, AddressesOutsideTheFirmwareRamAreErrorsNamingTheLine) {
  EXPECT_EQ(error_of(record('1', 0x7fff, 2, {1})),
            "line 1: data at 0x7fff..0x7fff is outside the firmware's RAM 0x8000..0xffff");
  EXPECT_EQ(error_of(record('1', 0xffff, 2, {1, 2})),
            "line 1: data at 0xffff..0x10000 is outside the firmware's RAM 0x8000..0xffff");
  // 32-bit addresses: the top bit set (once a negative int) and the last
  // address (once wrapping to the lowest).
  EXPECT_EQ(error_of(record('3', 0x80000000, 4, {1})),
            "line 1: data at 0x80000000..0x80000000 is outside the firmware's RAM 0x8000..0xffff");
  EXPECT_EQ(error_of(record('3', 0xffffffff, 4, {1, 2})),
            "line 1: data at 0xffffffff..0x100000000 is outside the firmware's RAM 0x8000..0xffff");
  EXPECT_EQ(error_of(record('2', 0x10000, 3, {1})),
            "line 1: data at 0x10000..0x10000 is outside the firmware's RAM 0x8000..0xffff");
  EXPECT_EQ(error_of(record('1', 0x8000, 2, {1}) + record('7', 0xfffffff0, 4, {})),
            "line 2: entry address 0xfffffff0 is outside the firmware's RAM 0x8000..0xffff");
}

TEST(Srec, MalformedRecordsAreErrors) {
  EXPECT_EQ(error_of("hello\n"), "line 1: not an S-record");
  EXPECT_EQ(error_of(record('4', 0x8000, 2, {1})), "line 1: unknown record type S4");
  EXPECT_EQ(error_of("S1058000010278\n"), "line 1: bad record checksum");
  EXPECT_EQ(error_of("S10680000102\n"), "line 1: the count does not match the record length");
  EXPECT_EQ(error_of("S3030000FC\n"), "line 1: too short for its address");
  EXPECT_EQ(error_of(record('0', 0, 2, {})), "no data records");
  EXPECT_EQ(error_of(""), "no data records");
}

TEST(Srec, TheWholeRamFillsAndNoMore) {
  std::string text;
  for (std::uint32_t a = 0x8000; a < 0x10000; a += 32) text += record('1', a, 2, std::vector<int>(32, 0xab));
  auto r = parse_srec(text);
  ASSERT_TRUE(std::holds_alternative<Firmware>(r));
  EXPECT_EQ(std::get<Firmware>(r).bytes.size(), 0x8000u);
}
