// Golden bytes for every command of the table, written by hand from the seed
// (../shared/seeds/001_f69dcae862ddbdb7.txt) and spec/nxt.md, never produced
// by the encoder: each request is encoded and compared, then decoded back to
// the same fields; replies likewise.
#include <gtest/gtest.h>

#include <set>

#include <fmt/format.h>

#include "nxt/commands.h"
#include "nxt/telegram.h"

namespace nxt {
namespace {

Bytes from_hex(std::string_view text) {
  Bytes out;
  for (std::size_t i = 0; i < text.size();) {
    if (text[i] == ' ') {
      ++i;
      continue;
    }
    out.push_back(static_cast<std::uint8_t>(std::stoi(std::string(text.substr(i, 2)), nullptr, 16)));
    i += 2;
  }
  return out;
}

// A file name field: the name, then NULs to 20 bytes.
std::string name20(std::string_view name) {
  std::string h;
  for (char c : name) h += fmt::format("{:02x} ", static_cast<unsigned char>(c));
  for (std::size_t i = name.size(); i < 20; ++i) h += "00 ";
  return h;
}

std::string zeros(int n) {
  std::string h;
  for (int i = 0; i < n; ++i) h += "00 ";
  return h;
}

using V = std::vector<Value>;
Value n(std::int64_t v) { return v; }
Value s(std::string v) { return v; }
Value b(Bytes v) { return v; }

struct Golden {
  std::string_view command;
  V request;
  std::string request_hex;
  V reply;  // with status 0
  std::string reply_hex;
};

std::vector<Golden> goldens() {
  Bytes message_59(59, 0);
  message_59[0] = 'h';
  message_59[1] = 'i';
  return {
      // Seed, byte by byte.
      {"StartProgram", {s("prog.rxe")}, "00 00 " + name20("prog.rxe"), {}, "02 00 00"},
      {"StopProgram", {}, "00 01", {}, "02 01 00"},
      {"PlaySoundFile", {n(1), s("a.rso")}, "00 02 01 " + name20("a.rso"), {}, "02 02 00"},
      // 440 Hz = 0x01B8, 500 ms = 0x01F4, little-endian.
      {"PlayTone", {n(440), n(500)}, "00 03 b8 01 f4 01", {}, "02 03 00"},
      // Port A, power 75, MOTORON|REGULATED, speed regulation, turn 0, RUNNING, 360 degrees (bytes 8-11).
      {"SetOutputState", {n(0), n(75), n(0x05), n(1), n(0), n(0x20), n(360)}, "00 04 00 4b 05 01 00 20 68 01 00 00", {}, "02 04 00"},
      {"SetInputMode", {n(0), n(0x01), n(0x20)}, "00 05 00 01 20", {}, "02 05 00"},
      // Power -100 is 0x9c; counts 720, -5, 1000.
      {"GetOutputState", {n(1)}, "00 06 01",
       {n(1), n(-100), n(0x03), n(0), n(0), n(0x20), n(0), n(720), n(-5), n(1000)},
       "02 06 00 01 9c 03 00 00 20 00 00 00 00 d0 02 00 00 fb ff ff ff e8 03 00 00"},
      {"GetInputValues", {n(2)}, "00 07 02",
       {n(2), n(1), n(0), n(0x01), n(0x20), n(183), n(183), n(1), n(183)},
       "02 07 00 02 01 00 01 20 b7 00 b7 00 01 00 b7 00"},
      {"ResetInputScaledValue", {n(3)}, "00 08 03", {}, "02 08 00"},
      // Size counts the NUL: "hi\0" is 3.
      {"MessageWrite", {n(1), n(3), b({'h', 'i', 0})}, "00 09 01 03 68 69 00", {}, "02 09 00"},
      {"ResetMotorPosition", {n(2), n(1)}, "00 0a 02 01", {}, "02 0a 00"},
      {"GetBatteryLevel", {}, "00 0b", {n(7800)}, "02 0b 00 78 1e"},
      {"StopSoundPlayback", {}, "00 0c", {}, "02 0c 00"},
      // 600 000 ms = 0x000927C0.
      {"KeepAlive", {}, "00 0d", {n(600000)}, "02 0d 00 c0 27 09 00"},
      {"LSGetStatus", {n(0)}, "00 0e 00", {n(1)}, "02 0e 00 01"},
      // Ultrasonic: device address 0x02, register 0x42, one byte back.
      {"LSWrite", {n(3), n(2), n(1), b({0x02, 0x42})}, "00 0f 03 02 01 02 42", {}, "02 0f 00"},
      {"LSRead", {n(3)}, "00 10 03", {n(1), b({42})}, "02 10 00 01 2a " + zeros(15)},
      {"GetCurrentProgramName", {}, "00 11", {s("prog.rxe")}, "02 11 00 " + name20("prog.rxe")},
      // The seed's own example: 0x05, 0x00, 0x00, 0x13, 0x0A, 0x00, 0x01
      // (length 5, then read remote box 10 into local box 0 and remove).
      {"MessageRead", {n(10), n(0), n(1)}, "00 13 0a 00 01", {n(0), n(3), b(message_59)},
       "02 13 00 00 03 68 69 " + zeros(57)},
      // Firmware direct commands.
      {"GetButtonState", {}, "00 12", {}, "02 12 00"},
      {"DatalogRead", {n(1)}, "00 19 01", {n(0), b({})}, "02 19 00 00 " + zeros(60)},  // 64 bytes in all
      {"DatalogSetTimes", {n(0x01020304)}, "00 1a 04 03 02 01", {}, "02 1a 00"},
      {"BTGetContactCount", {}, "00 1b", {n(30)}, "02 1b 00 1e"},
      {"BTGetContactName", {n(0)}, "00 1c 00", {n(0), s("")}, "02 1c 00 00 " + zeros(17)},
      {"BTGetConnCount", {}, "00 1d", {n(4)}, "02 1d 00 04"},
      {"BTGetConnName", {n(1)}, "00 1e 01", {n(0), s("")}, "02 1e 00 00 " + zeros(17)},
      // Property 2 (sleep timeout) takes a u32 of ms: 300 000 = 0x000493E0.
      {"SetProperty", {n(2), b({0xe0, 0x93, 0x04, 0x00})}, "00 1f 02 e0 93 04 00", {}, "02 1f 00"},
      {"GetProperty", {n(1)}, "00 20 01", {b({3})}, "02 20 00 03"},
      {"UpdateResetCount", {n(0)}, "00 21 00", {}, "02 21 00"},
      // System commands (type 0x01).
      {"OpenRead", {s("a.txt")}, "01 80 " + name20("a.txt"), {n(0), n(100)}, "02 80 00 00 64 00 00 00"},
      {"OpenWrite", {s("p.rxe"), n(300)}, "01 81 " + name20("p.rxe") + "2c 01 00 00", {n(1)}, "02 81 00 01"},
      {"Read", {n(0), n(58)}, "01 82 00 3a 00", {n(0), n(2), b({0xaa, 0xbb})}, "02 82 00 00 02 00 aa bb"},
      {"Write", {n(1), b({1, 2, 3})}, "01 83 01 01 02 03", {n(1), n(3)}, "02 83 00 01 03 00"},
      {"Close", {n(1)}, "01 84 01", {n(1)}, "02 84 00 01"},
      {"Delete", {s("a.txt")}, "01 85 " + name20("a.txt"), {s("a.txt")}, "02 85 00 " + name20("a.txt")},
      {"FindFirst", {s("*.*")}, "01 86 " + name20("*.*"), {n(0), s("a.txt"), n(5)}, "02 86 00 00 " + name20("a.txt") + "05 00 00 00"},
      {"FindNext", {n(0)}, "01 87 00", {n(0), s("b.rxe"), n(0x10000)}, "02 87 00 00 " + name20("b.rxe") + "00 00 01 00"},
      // Protocol 1.124, firmware 1.31: minor byte first.
      {"GetFirmwareVersion", {}, "01 88", {n(124), n(1), n(31), n(1)}, "02 88 00 7c 01 1f 01"},
      {"OpenWriteLinear", {s("p.rxe"), n(16)}, "01 89 " + name20("p.rxe") + "10 00 00 00", {n(2)}, "02 89 00 02"},
      {"OpenWriteData", {s("log.dat"), n(64)}, "01 8b " + name20("log.dat") + "40 00 00 00", {n(3)}, "02 8b 00 03"},
      {"OpenAppendData", {s("log.dat")}, "01 8c " + name20("log.dat"), {n(3), n(60)}, "02 8c 00 03 3c 00 00 00"},
      {"FindFirstModule", {s("*.*")}, "01 90 " + name20("*.*"), {n(0), s("Ui.mod"), n(0x000C0001), n(0), n(40)},
       "02 90 00 00 " + name20("Ui.mod") + "01 00 0c 00 00 00 00 00 28 00"},
      {"FindNextModule", {n(0)}, "01 91 00", {n(0), s("Ui.mod"), n(0x000C0001), n(0), n(40)},
       "02 91 00 00 " + name20("Ui.mod") + "01 00 0c 00 00 00 00 00 28 00"},
      {"CloseModuleHandle", {n(0)}, "01 92 00", {n(0)}, "02 92 00 00"},
      {"ReadIOMap", {n(0x000C0001), n(4), n(2)}, "01 94 01 00 0c 00 04 00 02 00", {n(0x000C0001), n(2), b({7, 8})},
       "02 94 00 01 00 0c 00 02 00 07 08"},
      {"WriteIOMap", {n(0x000C0001), n(4), n(2), b({7, 8})}, "01 95 01 00 0c 00 04 00 02 00 07 08",
       {n(0x000C0001), n(2)}, "02 95 00 01 00 0c 00 02 00"},
      // "Let's dance: SAMBA" and its NUL; the answer "Yes\0".
      {"Boot", {s("Let's dance: SAMBA")}, "01 97 4c 65 74 27 73 20 64 61 6e 63 65 3a 20 53 41 4d 42 41 00",
       {s("Yes")}, "02 97 00 59 65 73 00"},
      {"SetBrickName", {s("Robo")}, "01 98 52 6f 62 6f " + zeros(12), {}, "02 98 00"},
      // 33 bytes: name[15], address[7], signal u32, free flash u32.
      {"GetDeviceInfo", {}, "01 9b",
       {s("NXT"), b({0x00, 0x16, 0x53, 0x01, 0x02, 0x03, 0x00}), n(0), n(100000)},
       "02 9b 00 4e 58 54 " + zeros(12) + "00 16 53 01 02 03 00 00 00 00 00 a0 86 01 00"},
      {"DeleteUserFlash", {}, "01 a0", {}, "02 a0 00"},
      {"PollCommandLength", {n(0)}, "01 a1 00", {n(0), n(0)}, "02 a1 00 00 00"},
      {"PollCommand", {n(0), n(10)}, "01 a2 00 0a", {n(0), n(0), b({})}, "02 a2 00 00 00"},
  };
}

TEST(NxtGolden, EveryCommandOfTheTableHasAGolden) {
  std::set<std::string_view> covered;
  for (const auto& g : goldens()) covered.insert(g.command);
  for (const auto& c : commands()) EXPECT_TRUE(covered.count(c.name)) << c.name << " has no golden bytes";
  EXPECT_EQ(covered.size(), commands().size());
}

TEST(NxtGolden, RequestsEncodeAndDecodeToTheHandWrittenBytes) {
  for (const auto& g : goldens()) {
    const Command* c = find_command(g.command);
    ASSERT_NE(c, nullptr) << g.command;
    auto encoded = encode_request(*c, g.request);
    ASSERT_TRUE(std::holds_alternative<Bytes>(encoded)) << g.command << ": " << std::get<TelegramError>(encoded).message;
    EXPECT_EQ(hex(std::get<Bytes>(encoded)), hex(from_hex(g.request_hex))) << g.command;
    auto decoded = decode_request(from_hex(g.request_hex));
    ASSERT_TRUE(std::holds_alternative<Decoded>(decoded)) << g.command << ": " << std::get<TelegramError>(decoded).message;
    const auto& d = std::get<Decoded>(decoded);
    EXPECT_EQ(d.command, c);
    EXPECT_TRUE(d.reply_wanted);
    EXPECT_EQ(d.fields, g.request) << g.command;
  }
}

TEST(NxtGolden, RepliesEncodeAndDecodeToTheHandWrittenBytes) {
  for (const auto& g : goldens()) {
    const Command* c = find_command(g.command);
    ASSERT_NE(c, nullptr);
    auto encoded = encode_reply(*c, 0, g.reply);
    ASSERT_TRUE(std::holds_alternative<Bytes>(encoded)) << g.command << ": " << std::get<TelegramError>(encoded).message;
    EXPECT_EQ(hex(std::get<Bytes>(encoded)), hex(from_hex(g.reply_hex))) << g.command;
    auto decoded = decode_reply(from_hex(g.reply_hex));
    ASSERT_TRUE(std::holds_alternative<Decoded>(decoded)) << g.command << ": " << std::get<TelegramError>(decoded).message;
    EXPECT_EQ(std::get<Decoded>(decoded).command, c);
    EXPECT_EQ(std::get<Decoded>(decoded).status, 0);
  }
}

TEST(NxtGolden, TheSeedsMessageReadExampleIsSevenBytesOnBluetooth) {
  // The seed shows the Bluetooth length prefix too: 5 bytes follow it.
  auto req = std::get<Bytes>(encode_request(*find_command("MessageRead"), V{n(11), n(1), n(1)}));
  EXPECT_EQ(hex(req), "00 13 0b 01 01");
  EXPECT_EQ(req.size(), 5u);
}

TEST(NxtGolden, NoReplyTelegramsSetTheHighBit) {
  auto stop = std::get<Bytes>(encode_request(*find_command("StopProgram"), V{}, false));
  EXPECT_EQ(hex(stop), "80 01");
  auto del = std::get<Bytes>(encode_request(*find_command("Delete"), V{s("x.txt")}, false));
  EXPECT_EQ(del[0], 0x81);
  auto d = std::get<Decoded>(decode_request(stop));
  EXPECT_FALSE(d.reply_wanted);
}

TEST(NxtGolden, AnErrorReplyIsZeroFilledToFullLength) {
  // spec/nxt.md: an illegal port answers 0xC0 with a zero-filled body of full length.
  auto r = std::get<Bytes>(encode_reply(*find_command("GetOutputState"), 0xC0, V{}));
  EXPECT_EQ(r.size(), 25u);
  EXPECT_EQ(hex(r), "02 06 c0 " + std::string(hex(Bytes(22, 0))));
  // ... and the decoder takes a bare status as well.
  auto d = decode_reply(from_hex("02 06 c0"));
  ASSERT_TRUE(std::holds_alternative<Decoded>(d));
  EXPECT_EQ(std::get<Decoded>(d).status, 0xC0);
}

}  // namespace
}  // namespace nxt
