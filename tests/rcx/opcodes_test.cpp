// The opcode table checked against numbers taken from the firmware reference.
#include "rcx/opcodes.h"

#include <gtest/gtest.h>

#include <set>

using namespace rcx;

TEST(Opcodes, EveryOpHasOneRowInOrder) {
  auto table = opcodes();
  ASSERT_EQ(table.size(), kOpcodeCount);
  for (std::size_t i = 0; i < table.size(); ++i) EXPECT_EQ(static_cast<std::size_t>(table[i].op), i);
}

TEST(Opcodes, SeedListsFiftyEightOpcodes) {
  // The seed's index names 58 operations.
  EXPECT_EQ(kOpcodeCount, 58u);
}

TEST(Opcodes, ProgramFormsAreUnique) {
  std::set<int> seen;
  for (const auto& row : opcodes())
    if (row.is_command()) {
      EXPECT_TRUE(seen.insert(row.code).second) << row.name;
    }
}

TEST(Opcodes, RequestFormsIncludingTogglesAreUnique) {
  std::set<int> seen;
  for (const auto& row : opcodes()) {
    if (!row.is_request()) continue;
    EXPECT_TRUE(seen.insert(row.code).second) << row.name;
    if (row.toggles) {
      EXPECT_TRUE(seen.insert(alternate_form(row.code)).second) << row.name;
    }
  }
}

TEST(Opcodes, SeedCodesAndReplies) {
  // (op, code, the two reply bytes the seed lists for the two request forms)
  struct Row { Op op; int code; int reply_a; int reply_b; };
  const Row rows[] = {
      {Op::AbsoluteValue, 0x74, 0x83, 0x8b}, {Op::Alive, 0x10, 0xe7, 0xef},
      {Op::AddToVariable, 0x24, 0xd3, 0xdb}, {Op::AndVariable, 0x84, 0x73, 0x7b},
      {Op::ClearSensorValue, 0xd1, 0x26, 0x2e}, {Op::ClearTimer, 0xa1, 0x56, 0x5e},
      {Op::DeleteAllSubroutines, 0x70, 0x87, 0x8f}, {Op::DeleteAllTasks, 0x40, 0xb7, 0xbf},
      {Op::DatalogNext, 0x62, 0x95, 0x9d}, {Op::DeleteFirmware, 0x65, 0x92, 0x9a},
      {Op::DeleteSubroutine, 0xc1, 0x36, 0x3e}, {Op::DeleteTask, 0x61, 0x96, 0x9e},
      {Op::DivideVariable, 0x44, 0xb3, 0xbb}, {Op::GetMemoryMap, 0x20, 0xd7, 0xdf},
      {Op::GetBatteryPower, 0x30, 0xc7, 0xcf}, {Op::GetValue, 0x12, 0xe5, 0xed},
      {Op::GetVersions, 0x15, 0xe2, 0xea}, {Op::MultiplyVariable, 0x54, 0xa3, 0xab},
      {Op::OrVariable, 0x94, 0x63, 0x6b}, {Op::PowerOff, 0x60, 0x97, 0x9f},
      {Op::PlaySound, 0x51, 0xa6, 0xae}, {Op::PlayTone, 0x23, 0xd4, 0xdc},
      {Op::SetDatalogSize, 0x52, 0xa5, 0xad}, {Op::SetDisplay, 0x33, 0xc4, 0xcc},
      {Op::SetMotorOnOff, 0x21, 0xd6, 0xde}, {Op::SetMotorDirection, 0xe1, 0x16, 0x1e},
      {Op::SetMotorPower, 0x13, 0xe4, 0xec}, {Op::SetPowerDownDelay, 0xb1, 0x46, 0x4e},
      {Op::SetProgramNumber, 0x91, 0x66, 0x6e}, {Op::SetSensorMode, 0x42, 0xb5, 0xbd},
      {Op::SetSensorType, 0x32, 0xc5, 0xcd}, {Op::SetTime, 0x22, 0xd5, 0xdd},
      {Op::SetTransmitterRange, 0x31, 0xc6, 0xce}, {Op::SetVariable, 0x14, 0xe3, 0xeb},
      {Op::SignVariable, 0x64, 0x93, 0x9b}, {Op::StartFirmwareDownload, 0x75, 0x82, 0x8a},
      {Op::StartTaskDownload, 0x25, 0xd2, 0xda}, {Op::StopAllTasks, 0x50, 0xa7, 0xaf},
      {Op::StartSubroutineDownload, 0x35, 0xc2, 0xca}, {Op::StartTask, 0x71, 0x86, 0x8e},
      {Op::StopTask, 0x81, 0x76, 0x7e}, {Op::SubtractFromVariable, 0x34, 0xc3, 0xcb},
      {Op::TransferData, 0x45, 0xb2, 0xba}, {Op::UnlockFirmware, 0xa5, 0x52, 0x5a},
      {Op::UploadDatalog, 0xa4, 0x53, 0x5b},
  };
  for (const auto& r : rows) {
    const auto& row = info(r.op);
    SCOPED_TRACE(std::string(row.name));
    EXPECT_EQ(row.code, r.code);
    ASSERT_TRUE(row.replies);
    ASSERT_TRUE(row.toggles);
    std::set<int> replies{reply_code(row.code), reply_code(alternate_form(row.code))};
    EXPECT_EQ(replies, (std::set<int>{r.reply_a, r.reply_b}));
  }
}

TEST(Opcodes, CommandOnlyCodes) {
  // The seed's "xx/Command" opcodes: no second form, no reply.
  const std::pair<Op, int> rows[] = {
      {Op::BranchAlwaysFar, 0x72}, {Op::BranchAlwaysNear, 0x27}, {Op::CallSubroutine, 0x17},
      {Op::ClearMessage, 0x90}, {Op::DecrementLoopCounterNear, 0x37}, {Op::DecrementLoopCounterFar, 0x92},
      {Op::ReturnFromSubroutine, 0xf6}, {Op::SendMessage, 0xb2}, {Op::SetLoopCounter, 0x82},
      {Op::TestAndBranchFar, 0x95}, {Op::TestAndBranchNear, 0x85}, {Op::Wait, 0x43},
  };
  for (auto [op, code] : rows) {
    const auto& row = info(op);
    SCOPED_TRACE(std::string(row.name));
    EXPECT_EQ(row.code, code);
    EXPECT_EQ(row.kind, Kind::Command);
    EXPECT_FALSE(row.toggles);
    EXPECT_FALSE(row.replies);
    EXPECT_EQ(command_at(static_cast<std::uint8_t>(code)), &row);
    EXPECT_EQ(request_at(static_cast<std::uint8_t>(code)), nullptr);
  }
}

TEST(Opcodes, SetMessageIsTheOnlyRequestWithoutReply) {
  for (const auto& row : opcodes()) {
    if (!row.is_request()) continue;
    EXPECT_EQ(row.replies, row.op != Op::SetMessage) << row.name;
  }
  EXPECT_EQ(info(Op::SetMessage).code, 0xf7);
}

TEST(Opcodes, LookupByByte) {
  EXPECT_EQ(request_at(0x10)->op, Op::Alive);
  EXPECT_EQ(request_at(0x18)->op, Op::Alive);
  EXPECT_EQ(command_at(0x10), nullptr);  // Alive is request-only
  EXPECT_EQ(command_at(0x14)->op, Op::SetVariable);
  EXPECT_EQ(command_at(0x1c), nullptr);  // programs use the first form only
  EXPECT_EQ(command_at(0x00), nullptr);
}

TEST(Opcodes, CommandSizesMatchTheSeedLayouts) {
  // Sizes from the seed's operand lists (opcode byte included).
  EXPECT_EQ(command_size(info(Op::SetVariable)), 5);       // index, source, short
  EXPECT_EQ(command_size(info(Op::TestAndBranchNear)), 7);  // opsrc1 src2 arg1(2) arg2 offset
  EXPECT_EQ(command_size(info(Op::TestAndBranchFar)), 8);
  EXPECT_EQ(command_size(info(Op::BranchAlwaysNear)), 2);
  EXPECT_EQ(command_size(info(Op::BranchAlwaysFar)), 3);
  EXPECT_EQ(command_size(info(Op::DecrementLoopCounterFar)), 3);
  EXPECT_EQ(command_size(info(Op::SetLoopCounter)), 3);
  EXPECT_EQ(command_size(info(Op::Wait)), 4);
  EXPECT_EQ(command_size(info(Op::SetMotorPower)), 4);
  EXPECT_EQ(command_size(info(Op::PlayTone)), 4);
  EXPECT_EQ(command_size(info(Op::ReturnFromSubroutine)), 1);
  EXPECT_EQ(command_size(info(Op::TransferData)), std::nullopt);
  EXPECT_EQ(fixed_size(info(Op::GetMemoryMap).reply), 94 * 2);
  EXPECT_EQ(fixed_size(info(Op::GetVersions).reply), 8);
  EXPECT_EQ(fixed_size(info(Op::UnlockFirmware).reply), 25);
}

TEST(Opcodes, AllowedSourcesPerSeed) {
  auto src_of = [](Op op, std::size_t operand) { return info(op).operands[operand].allowed; };
  EXPECT_EQ(src_of(Op::AddToVariable, 1), sources({0, 2}));
  EXPECT_EQ(src_of(Op::Wait, 0), sources({0, 2, 4}));
  EXPECT_EQ(src_of(Op::SetLoopCounter, 0), sources({0, 2, 4}));
  EXPECT_EQ(src_of(Op::DatalogNext, 0), sources({0, 1, 9, 14}));
  const auto set_var = src_of(Op::SetVariable, 1);
  // Seed: "All sources are allowed" (5-7 read 0 on the RCX, docs/emulator.md).
  for (int s = 0; s < 16; ++s) EXPECT_TRUE(allows(set_var, s)) << s;
  const auto test1 = src_of(Op::TestAndBranchNear, 0);
  const auto test2 = src_of(Op::TestAndBranchNear, 1);
  EXPECT_FALSE(allows(test1, 4));
  EXPECT_FALSE(allows(test1, 8));
  EXPECT_TRUE(allows(test1, 2));
  EXPECT_FALSE(allows(test2, 2));
  EXPECT_TRUE(allows(test2, 9));
  EXPECT_FALSE(allows(src_of(Op::GetValue, 0), 2));
}

TEST(Opcodes, FieldEndianness) {
  std::uint8_t buf[2];
  write_field(FieldType::Short, 300, buf);
  EXPECT_EQ(buf[0], 0x2c);
  EXPECT_EQ(buf[1], 0x01);
  EXPECT_EQ(read_field(FieldType::Short, buf), 300);
  write_field(FieldType::UShortBE, 0x8000, buf);
  EXPECT_EQ(buf[0], 0x80);
  EXPECT_EQ(read_field(FieldType::UShortBE, buf), 0x8000);
  write_field(FieldType::Short, -11, buf);
  EXPECT_EQ(read_field(FieldType::Short, buf), -11);
  EXPECT_EQ(read_field(FieldType::UShort, buf), 0xfff5);
}

TEST(Opcodes, MnemonicsAreUnique) {
  std::set<std::string_view> seen;
  for (const auto& row : opcodes()) {
    EXPECT_TRUE(seen.insert(row.mnemonic).second) << row.mnemonic;
    EXPECT_EQ(by_mnemonic(row.mnemonic), &row);
  }
  EXPECT_EQ(by_mnemonic("nope"), nullptr);
}
