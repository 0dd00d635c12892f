// Telegrams that must be refused, with a message that says what came back,
// and the decoded form -v prints.
#include <gtest/gtest.h>

#include "nxt/telegram.h"

namespace nxt {
namespace {

std::string error_of(std::variant<Decoded, TelegramError> r) {
  return std::holds_alternative<TelegramError>(r) ? std::get<TelegramError>(r).message : "accepted";
}

TEST(NxtTelegram, TruncatedOverlongAndUnknownTelegramsAreErrors) {
  EXPECT_EQ(error_of(decode_reply(Bytes{0x02, 0x0B})), "a reply needs 0x02, an opcode and a status; got 02 0b");
  EXPECT_EQ(error_of(decode_reply(Bytes{0x02, 0x0B, 0x00, 0x01})),
            "GetBatteryLevel reply has 1 bytes after its header where 2 are expected: 02 0b 00 01");
  EXPECT_EQ(error_of(decode_reply(Bytes{0x02, 0x0B, 0x00, 0x01, 0x02, 0x03})),
            "GetBatteryLevel reply has 3 bytes after its header where 2 are expected: 02 0b 00 01 02 03");
  EXPECT_EQ(error_of(decode_reply(Bytes{0x02, 0x77, 0x00})), "a reply to unknown opcode 0x77: 02 77 00");
  EXPECT_EQ(error_of(decode_reply(Bytes{0x00, 0x0B, 0x00})), "0x00 is not the reply type 0x02: 00 0b 00");
  EXPECT_EQ(error_of(decode_request(Bytes{0x03, 0x0B})),
            "0x03 is not a request type (0x00, 0x01, 0x80, 0x81): 03 0b");
  EXPECT_EQ(error_of(decode_request(Bytes{0x01, 0x0B})), "0x0b is not a system command: 01 0b");
  EXPECT_EQ(error_of(decode_request(Bytes{})), "a request needs a type and an opcode; got (nothing)");
  // Rest fields take any length at or above the fixed part.
  EXPECT_EQ(error_of(decode_request(Bytes{0x00, 0x09, 0x00})),
            "MessageWrite request has 1 bytes after its header where 2 or more are expected: 00 09 00");
}

TEST(NxtTelegram, EncodingChecksEachFieldsType) {
  const Command& tone = *find_command("PlayTone");
  auto big = encode_request(tone, std::vector<Value>{std::int64_t{70000}, std::int64_t{1}});
  ASSERT_TRUE(std::holds_alternative<TelegramError>(big));
  EXPECT_EQ(std::get<TelegramError>(big).message, "PlayTone frequency_hz: 70000 is out of range 0..65535");
  auto few = encode_request(tone, std::vector<Value>{std::int64_t{440}});
  EXPECT_EQ(std::get<TelegramError>(few).message, "PlayTone takes 2 fields, 1 given");
  auto name = encode_request(*find_command("StartProgram"), std::vector<Value>{std::string("a_very_long_name_indeed.rxe")});
  EXPECT_EQ(std::get<TelegramError>(name).message,
            "StartProgram name: \"a_very_long_name_indeed.rxe\" is longer than 19 characters");
  auto kind = encode_request(*find_command("StartProgram"), std::vector<Value>{std::int64_t{1}});
  EXPECT_EQ(std::get<TelegramError>(kind).message, "StartProgram name: text or bytes are needed");
  // A direct command over 64 bytes cannot be sent.
  auto longmsg = encode_request(*find_command("MessageWrite"),
                                std::vector<Value>{std::int64_t{0}, std::int64_t{0}, Bytes(61, 0)});
  EXPECT_EQ(std::get<TelegramError>(longmsg).message,
            "MessageWrite would be 65 bytes, more than the 64 a direct command may have");
}

TEST(NxtTelegram, DescribeNamesFieldsAndEnumerations) {
  auto d = std::get<Decoded>(decode_request(Bytes{0x00, 0x04, 0x00, 0x4B, 0x07, 0x01, 0x00, 0x20, 0x68, 0x01, 0x00, 0x00}));
  EXPECT_EQ(describe(d),
            "SetOutputState port=0 power=75 mode=MOTORON|BRAKE|REGULATED regulation=MOTOR_SPEED turn_ratio=0 "
            "run_state=RUNNING tacho_limit=360");
  auto s = std::get<Decoded>(decode_request(Bytes{0x80, 0x05, 0x01, 0x01, 0x20}));
  EXPECT_EQ(describe(s), "SetInputMode (no reply) port=1 type=SWITCH mode=BOOLEANMODE");
  auto m = std::get<Decoded>(decode_request(Bytes{0x00, 0x09, 0x00, 0x03, 'h', 'i', 0x00}));
  EXPECT_EQ(describe(m), "MessageWrite inbox=0 size=3 data=\"hi\\x00\"");
  auto r = std::get<Decoded>(decode_reply(Bytes{0x02, 0x13, 0x40}));
  EXPECT_EQ(describe(r), "MessageRead -> 0x40 queue_empty");
}

TEST(NxtTelegram, NamesFromTheSeed) {
  EXPECT_EQ(sensor_type_named("switch"), 0x01);
  EXPECT_EQ(sensor_type_named("LOWSPEED_9V"), 0x0B);
  EXPECT_EQ(sensor_mode_named("BOOLEAN"), 0x20);
  EXPECT_EQ(sensor_mode_named("PCTFULLSCALEMODE"), 0x80);
  EXPECT_FALSE(sensor_type_named("TOUCH"));
  EXPECT_EQ(status_message(0xBD), "request failed (i.e. specified file not found)");
  EXPECT_EQ(status_message(0x87), "file not found");
  EXPECT_EQ(status_message(0x42), "unknown status");
  // The seed's 17 error codes and spec's 19 file-system codes, plus success.
  EXPECT_EQ(statuses().size(), 37u);
}

}  // namespace
}  // namespace nxt
