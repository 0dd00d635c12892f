#include "rcx/program_io.h"

#include <gtest/gtest.h>

using namespace rcx;
using Bytes = std::vector<std::uint8_t>;

namespace {

Image one_task(Bytes code) {
  Image image;
  image.fragments.push_back({FragmentType::Task, 0, std::move(code)});
  return image;
}

}  // namespace

TEST(ProgramIo, ASetVariableFromSensorTwoReadsOnlySensorTwo) {
  // set var0 = SensorValue(1): source 9, argument 1 (sensor 2).
  auto reads = program_io(one_task({0x14, 0x00, 0x09, 0x01, 0x00}));
  EXPECT_TRUE(reads.complete);
  EXPECT_EQ(reads.sensors_read, (std::array<bool, 3>{false, true, false}));
  EXPECT_FALSE(reads.message_read);
}

TEST(ProgramIo, TestAndBranchOperandsOnEitherSideCount) {
  // chk 5 != SensorRaw(2), as rcxc encodes it: opsrc1 = NotEqual<<6 | immediate.
  auto raw = program_io(one_task({0x85, 0x82, 0x0C, 0x05, 0x00, 0x02, 0x03}));
  EXPECT_TRUE(raw.complete);
  EXPECT_EQ(raw.sensors_read, (std::array<bool, 3>{false, false, true}));
  // chk SensorValue(1) == var 0: the sensor is the first operand.
  auto value = program_io(one_task({0x85, 0xC9, 0x00, 0x01, 0x00, 0x00, 0x03}));
  EXPECT_TRUE(value.complete);
  EXPECT_EQ(value.sensors_read, (std::array<bool, 3>{false, true, false}));
  // chk 2 >= SensorBool(0).
  auto boolean = program_io(one_task({0x85, 0x42, 0x0D, 0x02, 0x00, 0x00, 0x03}));
  EXPECT_EQ(boolean.sensors_read, (std::array<bool, 3>{true, false, false}));
}

TEST(ProgramIo, TypeModeAndSettingsAreNotReadings) {
  // set var0 = SensorType(0); set var1 = SensorMode(2); senstype 1, touch; senstype 1, light; senstype 2, rotation.
  auto reads = program_io(one_task({0x14, 0x00, 0x0A, 0x00, 0x00, 0x14, 0x01, 0x0B, 0x02, 0x00, 0x32, 0x01, 0x01,
                                    0x32, 0x01, 0x03, 0x32, 0x02, 0x04}));
  EXPECT_TRUE(reads.complete);
  EXPECT_EQ(reads.sensors_read, (std::array<bool, 3>{false, false, false}));
  EXPECT_EQ(reads.sensor_types, (std::array<std::uint8_t, 3>{0, 0b1010, 0b10000}));
}

TEST(ProgramIo, SendMessageIsSeen) {
  // msgsend immediate 7
  auto io = program_io(one_task({0xB2, 0x02, 0x07}));
  EXPECT_TRUE(io.message_sent);
  EXPECT_FALSE(io.message_read);
}

TEST(ProgramIo, TheMessageSource) {
  auto reads = program_io(one_task({0x14, 0x00, 0x0F, 0x00, 0x00}));
  EXPECT_TRUE(reads.message_read);
  EXPECT_EQ(reads.sensors_read, (std::array<bool, 3>{false, false, false}));
}

TEST(ProgramIo, SubroutinesCountAndUndecodableBytesMakeItIncomplete) {
  Image image = one_task({0x14, 0x00, 0x02, 0x07, 0x00});
  image.fragments.push_back({FragmentType::Subroutine, 0, {0x14, 0x00, 0x09, 0x02, 0x00}});
  auto reads = program_io(image);
  EXPECT_TRUE(reads.complete);
  EXPECT_EQ(reads.sensors_read, (std::array<bool, 3>{false, false, true}));
  image.fragments.push_back({FragmentType::Task, 1, {0x14, 0x00}});  // truncated
  EXPECT_FALSE(program_io(image).complete);
}
