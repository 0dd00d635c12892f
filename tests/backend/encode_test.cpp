// Encoding through the opcode table, checked against byte sequences the
// reference compiler's listings show for the same instructions.
#include "backend/encode.h"

#include <gtest/gtest.h>

#include "backend/codegen.h"

using rcx::Op;
using rcx::info;
using Bytes = std::vector<std::uint8_t>;

static Bytes enc(Op op, std::vector<int> v) {
  Bytes out;
  std::string err = rcxc::backend::encode(info(op), v, out);
  EXPECT_EQ(err, "");
  return out;
}

TEST(Encode, SetVariableImmediate) {
  EXPECT_EQ(enc(Op::SetVariable, {1, 2, 300}), (Bytes{0x14, 0x01, 0x02, 0x2c, 0x01}));
}

TEST(Encode, TestAndBranchNear) {
  // if (SENSOR_1 > 40): 40 >= sensor(0), op 1, src1 immediate
  EXPECT_EQ(enc(Op::TestAndBranchNear, {0x42, 9, 40, 0, 6}), (Bytes{0x85, 0x42, 0x09, 0x28, 0x00, 0x00, 0x06}));
}

TEST(Encode, TestAndBranchFarNegativeOffset) {
  EXPECT_EQ(enc(Op::TestAndBranchFar, {0x42, 0, 4, 0, -11}),
            (Bytes{0x95, 0x42, 0x00, 0x04, 0x00, 0x00, 0xf5, 0xff}));
}

TEST(Encode, MotorPowerAndTone) {
  EXPECT_EQ(enc(Op::SetMotorPower, {7, 2, 7}), (Bytes{0x13, 0x07, 0x02, 0x07}));
  EXPECT_EQ(enc(Op::PlayTone, {440, 50}), (Bytes{0x23, 0xb8, 0x01, 0x32}));
  EXPECT_EQ(enc(Op::StopAllTasks, {}), (Bytes{0x50}));
}

TEST(Encode, RejectsDisallowedSource) {
  Bytes out;
  // add only takes variable or immediate; timer (1) is refused
  auto err = rcxc::backend::encode(info(Op::AddToVariable), std::vector<int>{0, 1, 0}, out);
  EXPECT_NE(err.find("not allowed"), std::string::npos);
  EXPECT_TRUE(out.empty());
  // test-and-branch second value cannot be an immediate
  err = rcxc::backend::encode(info(Op::TestAndBranchNear), std::vector<int>{0x00, 2, 0, 5, 3}, out);
  EXPECT_NE(err.find("not allowed"), std::string::npos);
}

TEST(Encode, RejectsValuesThatDoNotFitAndWrongCounts) {
  Bytes out;
  EXPECT_NE(rcxc::backend::encode(info(Op::PlaySound), std::vector<int>{256}, out), "");
  EXPECT_NE(rcxc::backend::encode(info(Op::PlaySound), std::vector<int>{}, out), "");
  EXPECT_NE(rcxc::backend::encode(info(Op::PlaySound), std::vector<int>{1, 2}, out), "");
  EXPECT_TRUE(out.empty());
}

TEST(Encode, AppendsToWhatIsThereAndAnErrorPartWayLeavesItAsItWas) {
  Bytes out{0xaa, 0xbb};
  EXPECT_EQ(rcxc::backend::encode(info(Op::PlaySound), std::vector<int>{1}, out), "");
  const Bytes before{0xaa, 0xbb, 0x51, 0x01};
  EXPECT_EQ(out, before);
  // The first two fields fit and are written before the third is refused.
  EXPECT_NE(rcxc::backend::encode(info(Op::SetVariable), std::vector<int>{1, 2, 70000}, out), "");
  EXPECT_EQ(out, before);
  EXPECT_NE(rcxc::backend::encode(info(Op::SetVariable), std::vector<int>{1, 2, 3, 4}, out), "");
  EXPECT_EQ(out, before);
}

// Code selection fills an instruction's fields in an array of this size.
TEST(Encode, EveryRowOfTheTableFitsTheSelectorsFields) {
  for (const auto& row : rcx::opcodes()) EXPECT_LE(row.operands.size(), rcxc::backend::kMaxTableOperands) << row.name;
}
