// Right shifts without a test of the sign (ir/shiftright.cpp) on whole
// programs: every shift count over the whole 16-bit range gives the
// logical shift the firmware-less `>>` means (checked against C++'s
// unsigned shift), at every level, and the bytes each form saves.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "tests/support/compiled.h"

namespace rcxc {
namespace {

int16_t logical_shift(int v, int n) { return static_cast<int16_t>(static_cast<uint16_t>(v) >> n); }
int16_t wrap(long v) { return static_cast<int16_t>(static_cast<uint16_t>(v & 0xffff)); }

// One checksum per shift count, s_n = s_n * 31 + (v >> n), over v from
// -32768 to 32767 in steps of 257 and over -70..70 (both signs of every
// low bit pattern near zero, -1 included).
TEST(ShiftRight, EveryCountOverTheWholeRangeShiftsInZeros) {
  std::string body, vars = "int v";
  for (int n = 1; n <= 15; ++n) {
    vars += fmt::format(", s{}", n);
    body += fmt::format("    s{0} = s{0} * 31 + (v >> {0});\n", n);
  }
  std::string text = vars + ";\ntask main() {\n  v = -32768;\n  repeat (256) {\n" + body +
                     "    v += 257;\n  }\n  v = -70;\n  repeat (141) {\n" + body + "    v += 1;\n  }\n}\n";
  int16_t expected[16] = {};
  auto accumulate = [&](int v) {
    for (int n = 1; n <= 15; ++n) expected[n] = wrap(expected[n] * 31L + logical_shift(v, n));
  };
  for (int k = 0; k < 256; ++k) accumulate(-32768 + 257 * k);
  for (int v = -70; v <= 70; ++v) accumulate(v);
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O1, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 600'000);
    for (int n = 1; n <= 15; ++n)
      EXPECT_EQ(test::global_value(m, c.out->image, fmt::format("s{}", n)), expected[n])
          << "shift by " << n << " at level " << static_cast<int>(level);
  }
}

// A shift by a count known only at run time shifts one place per pass:
// the same values.
TEST(ShiftRight, AShiftByAVariableCountShiftsInZeros) {
  const char* text = R"(
int a, b, c, n;
task main() {
  n = 3; a = -1; b = -32768; c = 12345;
  a = a >> n;
  n = 14;
  b = b >> n;
  n = 1;
  c = (c - 32000) >> n;
}
)";
  for (auto level : {ir::OptLevel::O0, ir::OptLevel::O2, ir::OptLevel::Os}) {
    auto c = test::compile_program(text, level);
    ASSERT_TRUE(c.out);
    auto m = test::run_image(c.out->image, 2000);
    EXPECT_EQ(test::global_value(m, c.out->image, "a"), logical_shift(-1, 3));
    EXPECT_EQ(test::global_value(m, c.out->image, "b"), logical_shift(-32768, 14));
    EXPECT_EQ(test::global_value(m, c.out->image, "c"), logical_shift(12345 - 32000, 1));
  }
}

int code_bytes(const std::string& text, ir::OptLevel level) {
  auto c = test::compile_program(text, level);
  EXPECT_TRUE(c.out);
  return c.out ? c.out->code_bytes : 0;
}

// In place, `a >>= 3` is a test (7 bytes), and, divide, or, jump (17) and
// a divide (5) at -O2; at -Os three instructions (15). `a >>= 15` sets 0
// or 1 after a test (19 bytes, two or three instructions) at -O1 and is
// an and and a divide (10 bytes, two instructions) from -O2.
TEST(ShiftRight, BytesEachFormSaves) {
  const char* three = "int a;\ntask main() {\n  a = -5;\n  a >>= 3;\n}\n";
  EXPECT_EQ(code_bytes(three, ir::OptLevel::Os), code_bytes(three, ir::OptLevel::O2) - 14);
  const char* fifteen = "int a;\ntask main() {\n  a = -5;\n  a >>= 15;\n}\n";
  EXPECT_EQ(code_bytes(fifteen, ir::OptLevel::O2), code_bytes(fifteen, ir::OptLevel::O1) - 9);
}

}  // namespace
}  // namespace rcxc
