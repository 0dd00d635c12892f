// The IR packet codec: framing facts from formats.md, round trips over the
// whole opcode table, and every way the decoder rejects bytes.
#include <gtest/gtest.h>

#include "link/packet.h"
#include "link/session.h"
#include "rcx/opcodes.h"

namespace rcx {
namespace {

std::vector<Packet> packets(const std::vector<DecodeEvent>& events) {
  std::vector<Packet> out;
  for (const auto& e : events)
    if (auto* p = std::get_if<Packet>(&e)) out.push_back(*p);
  return out;
}

std::vector<std::string> rejections(const std::vector<DecodeEvent>& events) {
  std::vector<std::string> out;
  for (const auto& e : events)
    if (auto* r = std::get_if<Rejected>(&e)) out.push_back(r->reason);
  return out;
}

bool any_contains(const std::vector<std::string>& reasons, std::string_view what) {
  for (const auto& r : reasons)
    if (r.find(what) != std::string::npos) return true;
  return false;
}

TEST(LinkPacket, FramesAliveAsTheSpecSays) {
  // formats.md: 55 FF 00, each byte and its complement, sum and complement.
  EXPECT_EQ(frame(Bytes{0x10}), (Bytes{0x55, 0xFF, 0x00, 0x10, 0xEF, 0x10, 0xEF}));
  // Play sound 5: sum 0x56.
  EXPECT_EQ(frame(Bytes{0x51, 0x05}), (Bytes{0x55, 0xFF, 0x00, 0x51, 0xAE, 0x05, 0xFA, 0x56, 0xA9}));
}

TEST(LinkPacket, ChecksumWrapsModulo256) {
  Bytes f = frame(Bytes{0xF0, 0x20});
  EXPECT_EQ(f[f.size() - 2], 0x10);
  EXPECT_EQ(f[f.size() - 1], 0xEF);
}

TEST(LinkPacket, ReplyCodeIsTheComplementOfTheFormReceived) {
  EXPECT_EQ(reply_code(0x10), 0xEF);
  EXPECT_EQ(reply_code(0x18), 0xE7);
  EXPECT_TRUE(answers(Bytes{0xE7}, Bytes{0x18}));
  EXPECT_FALSE(answers(Bytes{0xEF}, Bytes{0x18}));
}

TEST(LinkPacket, TogglePicksEitherFormAndLeavesSetMessageAlone) {
  EXPECT_EQ(with_toggle(Bytes{0x10}, true)[0], 0x18);
  EXPECT_EQ(with_toggle(Bytes{0x18}, false)[0], 0x10);
  EXPECT_EQ(with_toggle(Bytes{0x45, 1, 0}, true)[0], 0x4D);
  EXPECT_EQ(with_toggle(Bytes{0xF7, 3}, true)[0], 0xF7);
}

// Every request of the table, in both forms, framed and decoded, is itself;
// and its reply, framed and decoded by a host waiting for it, is itself.
TEST(LinkPacket, EveryRequestAndReplyRoundTrips) {
  int checked = 0;
  for (const auto& op : opcodes()) {
    if (!op.is_request()) continue;
    for (bool toggle : {false, true}) {
      Bytes request;
      if (op.op == Op::TransferData) {
        Bytes data{1, 2, 3, 250};
        request = with_toggle(transfer_payload(2, data), toggle);
      } else {
        std::vector<int> values(16, 7);
        request = with_toggle(request_payload(op, values), toggle);
      }
      auto size = request_size(request);
      ASSERT_TRUE(std::holds_alternative<int>(size)) << op.name;
      EXPECT_EQ(std::get<int>(size), static_cast<int>(request.size())) << op.name;
      Decoder d = request_decoder();
      auto got = packets(feed(d, frame(request)));
      ASSERT_EQ(got.size(), 1u) << op.name;
      EXPECT_EQ(got[0].payload, request) << op.name;
      if (!op.replies) continue;
      auto reply_len = reply_size(request);
      ASSERT_TRUE(std::holds_alternative<int>(reply_len)) << op.name;
      Bytes reply(static_cast<std::size_t>(std::get<int>(reply_len)), 0x21);
      reply[0] = reply_code(request[0]);
      Decoder r = reply_decoder(request);
      auto replies = packets(feed(r, frame(reply)));
      ASSERT_EQ(replies.size(), 1u) << op.name;
      EXPECT_EQ(replies[0].payload, reply) << op.name;
      ++checked;
    }
  }
  EXPECT_GE(checked, 2 * 40);
}

TEST(LinkPacket, ReplySizesComeFromTheTable) {
  EXPECT_EQ(std::get<int>(reply_size(Bytes{0x10})), 1);                      // Alive: void
  EXPECT_EQ(std::get<int>(reply_size(Bytes{0x20})), 1 + 2 * 94);             // memory map
  EXPECT_EQ(std::get<int>(reply_size(Bytes{0x15, 1, 3, 5, 7, 11})), 1 + 8);  // versions
  EXPECT_EQ(std::get<int>(reply_size(Bytes{0xA5, 76, 69, 71, 79, 174})), 1 + 25);
  // Upload datalog: 3 bytes per requested record.
  EXPECT_EQ(std::get<int>(reply_size(Bytes{0xA4, 0, 0, 5, 0})), 1 + 15);
  EXPECT_TRUE(std::holds_alternative<SizeError>(reply_size(Bytes{0xF7, 1})));  // set message: no reply
  EXPECT_TRUE(std::holds_alternative<SizeError>(reply_size(Bytes{0x27})));     // a command only
}

TEST(LinkPacket, DecodesByteByByteAndBackToBack) {
  Bytes a = frame(Bytes{0x51, 0x03});
  Bytes b = frame(transfer_payload(1, Bytes{9, 8, 7}));
  Bytes stream = a;
  stream.insert(stream.end(), b.begin(), b.end());
  Decoder d = request_decoder();
  std::vector<Packet> got;
  for (auto byte : stream) {
    auto p = packets(feed(d, Bytes{byte}));
    got.insert(got.end(), p.begin(), p.end());
  }
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].payload, (Bytes{0x51, 0x03}));
  EXPECT_EQ(got[1].payload, transfer_payload(1, Bytes{9, 8, 7}));
  EXPECT_EQ(pending(d), 0u);
}

TEST(LinkPacket, ResynchronisesAfterGarbage) {
  Bytes stream{0x12, 0x55, 0x34, 0xFF};
  Bytes f = frame(Bytes{0x10});
  stream.insert(stream.end(), f.begin(), f.end());
  Decoder d = request_decoder();
  auto events = feed(d, stream);
  auto got = packets(events);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].payload, Bytes{0x10});
  EXPECT_TRUE(any_contains(rejections(events), "not a packet header"));
}

TEST(LinkPacket, RejectsAComplementMismatchAndFindsTheNextPacket) {
  Bytes bad = frame(Bytes{0x51, 0x02});
  bad[6] ^= 0x01;  // the complement of 0x02
  Bytes good = frame(Bytes{0x10});
  bad.insert(bad.end(), good.begin(), good.end());
  Decoder d = request_decoder();
  auto events = feed(d, bad);
  EXPECT_TRUE(any_contains(rejections(events), "not followed by its complement"));
  auto got = packets(events);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].payload, Bytes{0x10});
}

TEST(LinkPacket, RejectsABadChecksum) {
  Bytes f = frame(Bytes{0x51, 0x02});
  f[7] = 0x00;
  f[8] = 0xFF;  // a well-formed pair, the wrong sum
  Decoder d = request_decoder();
  auto events = feed(d, f);
  EXPECT_TRUE(packets(events).empty());
  EXPECT_TRUE(any_contains(rejections(events), "checksum"));
}

TEST(LinkPacket, RejectsAnUnknownRequestOpcode) {
  Decoder d = request_decoder();
  auto events = feed(d, frame(Bytes{0x27, 0x05}));  // branch: a command, never a request
  EXPECT_TRUE(packets(events).empty());
  EXPECT_TRUE(any_contains(rejections(events), "0x27 is not a request opcode"));
}

TEST(LinkPacket, NeverTrustsAnOversizedTransferLength) {
  // Transfer data claiming 0x7000 bytes: rejected as soon as the length is seen,
  // without waiting for (or buffering) 28 KB.
  Bytes header{0x45, 0x01, 0x00, 0x00, 0x70};
  Decoder d = request_decoder();
  auto events = feed(d, frame(header));
  EXPECT_TRUE(packets(events).empty());
  EXPECT_TRUE(any_contains(rejections(events), "data length"));
  EXPECT_LT(pending(d), 16u);
}

TEST(LinkPacket, WaitsForMoreBytesOfATruncatedPacket) {
  Bytes f = frame(Bytes{0x51, 0x02});
  f.pop_back();
  Decoder d = request_decoder();
  EXPECT_TRUE(feed(d, f).empty());
  EXPECT_EQ(pending(d), f.size());
  auto got = packets(feed(d, Bytes{static_cast<std::uint8_t>(~0x53)}));
  ASSERT_EQ(got.size(), 1u);
}

TEST(LinkPacket, HostRejectsAReplyToTheOtherForm) {
  Decoder d = reply_decoder(Bytes{0x18});
  auto events = feed(d, frame(Bytes{0xEF}));  // answers 0x10, the previous request
  EXPECT_TRUE(packets(events).empty());
  EXPECT_TRUE(any_contains(rejections(events), "previous request"));
  events = feed(d, frame(Bytes{0xE7}));
  EXPECT_EQ(packets(events).size(), 1u);
}

TEST(LinkPacket, HostRejectsAnUnrelatedReply) {
  Decoder d = reply_decoder(Bytes{0x30});
  auto events = feed(d, frame(Bytes{0xEF}));
  EXPECT_TRUE(any_contains(rejections(events), "is not the reply 0xcf"));
}

TEST(LinkPacket, DatalogReplyWithoutRecordsIsAccepted) {
  // The brick answers an out-of-range upload with no records (seed).
  Bytes request{0xA4, 0x05, 0x00, 0x02, 0x00};
  Decoder d = reply_decoder(request);
  auto got = packets(feed(d, frame(Bytes{0x5B})));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].payload, Bytes{0x5B});
  // And a full one: two records.
  Bytes full{0x5B, 0x00, 0x2A, 0x00, 0x20, 0x10, 0x00};
  Decoder d2 = reply_decoder(request);
  got = packets(feed(d2, frame(full)));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].payload, full);
}

TEST(LinkPacket, ParsesHex) {
  std::string error;
  EXPECT_EQ(parse_hex("12 1a", error), (Bytes{0x12, 0x1A}));
  EXPECT_EQ(parse_hex("0x51,0x05", error), (Bytes{0x51, 0x05}));
  EXPECT_EQ(parse_hex("a4000001 00", error), (Bytes{0xA4, 0x00, 0x00, 0x01, 0x00}));
  EXPECT_FALSE(parse_hex("1", error));
  EXPECT_NE(error.find("odd"), std::string::npos);
  EXPECT_FALSE(parse_hex("zz", error));
  EXPECT_FALSE(parse_hex("", error));
  EXPECT_EQ(hex(Bytes{0x55, 0xFF, 0x00}), "55 ff 00");
}

TEST(LinkPacket, RequestPayloadFollowsTheTableLayout) {
  // Start task download: byte unknown, short task, short length (little-endian).
  std::vector<int> v{0, 3, 0x0118};
  EXPECT_EQ(request_payload(info(Op::StartTaskDownload), v), (Bytes{0x25, 0x00, 0x03, 0x00, 0x18, 0x01}));
  // Transfer data: index, length, data, checksum of the data.
  EXPECT_EQ(transfer_payload(0, Bytes{0x80, 0x90}), (Bytes{0x45, 0x00, 0x00, 0x02, 0x00, 0x80, 0x90, 0x10}));
  // Versions reply: big-endian shorts.
  Bytes reply{0xE2, 0x00, 0x03, 0x00, 0x01, 0x00, 0x03, 0x00, 0x09};
  EXPECT_EQ(reply_field(info(Op::GetVersions), reply, "rom", 0), 3);
  EXPECT_EQ(reply_field(info(Op::GetVersions), reply, "rom", 1), 1);
  EXPECT_EQ(reply_field(info(Op::GetVersions), reply, "firmware", 1), 9);
}

}  // namespace
}  // namespace rcx
