// The host side of the link keeps its time bounds whatever the port does
// (issue 21): a port that never stops delivering bytes, and a brick that
// answers every firmware block with an error.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <chrono>
#include <deque>

#include "link/download.h"
#include "link/remote.h"
#include "link/session.h"
#include "rcx/opcodes.h"

namespace rcx {
namespace {

// /dev/zero or /dev/urandom as a port: every read returns bytes at once.
class EndlessPort : public Transport {
 public:
  explicit EndlessPort(std::uint8_t fill) : fill_(fill) {}
  std::optional<TransportError> write(std::span<const std::uint8_t>) override { return std::nullopt; }
  std::variant<std::vector<std::uint8_t>, TransportError> read(Millis) override {
    std::vector<std::uint8_t> bytes(256, fill_);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(b + counter_++ * 37);
    return bytes;
  }
  bool echoes() const override { return false; }
  void pause(Millis) override {}
  std::string describe() const override { return "endless port"; }

 private:
  std::uint8_t fill_;
  unsigned counter_ = 0;
};

// A brick that answers every request well-formed, with `transfer_error` as
// the error code of each Transfer data reply and 0 everywhere else.
class GrumpyBrick : public Transport {
 public:
  explicit GrumpyBrick(int transfer_error) : transfer_error_(transfer_error) {}
  std::optional<TransportError> write(std::span<const std::uint8_t> bytes) override {
    for (auto& event : feed(decoder_, bytes)) {
      const auto* p = std::get_if<Packet>(&event);
      if (p == nullptr) continue;
      ++requests;
      auto size = reply_size(p->payload);
      if (!std::holds_alternative<int>(size)) continue;
      Bytes reply(static_cast<std::size_t>(std::get<int>(size)), 0);
      reply[0] = static_cast<std::uint8_t>(~p->payload[0]);
      if ((p->payload[0] & ~0x08) == (info(Op::TransferData).code & ~0x08) && reply.size() > 1)
        reply[1] = static_cast<std::uint8_t>(transfer_error_);
      Bytes framed = frame(reply);
      pending_.insert(pending_.end(), framed.begin(), framed.end());
    }
    return std::nullopt;
  }
  std::variant<std::vector<std::uint8_t>, TransportError> read(Millis) override {
    std::vector<std::uint8_t> out(pending_.begin(), pending_.end());
    pending_.clear();
    return out;
  }
  bool echoes() const override { return false; }
  void pause(Millis) override {}
  std::string describe() const override { return "grumpy brick"; }
  int requests = 0;

 private:
  int transfer_error_;
  Decoder decoder_ = request_decoder();
  std::deque<std::uint8_t> pending_;
};

LinkOptions quick() {
  LinkOptions o;
  o.retries = 2;
  o.reply_grace = Millis(30);
  o.byte_seconds = 0;
  return o;
}

}  // namespace

TEST(HostilePort, EndlessBytesEndTheRequestAtItsDeadline) {
  for (std::uint8_t fill : {0x00, 0x55}) {
    EndlessPort port(fill);
    Link link = make_link(port, quick());
    auto start = std::chrono::steady_clock::now();
    auto r = transact(link, request_payload(info(Op::GetBatteryPower), {}));
    auto took = std::chrono::steady_clock::now() - start;
    ASSERT_TRUE(std::holds_alternative<LinkError>(r));
    EXPECT_NE(std::get<LinkError>(r).message.find("no valid reply"), std::string::npos)
        << std::get<LinkError>(r).message;
    // Three tries (greeting Alive and the request) of 30 ms each; a hang guard.
    EXPECT_LT(took, std::chrono::seconds(5));
  }
}

TEST(HostilePort, EndlessBytesEndADownload) {
  EndlessPort port(0);
  Link link = make_link(port, quick());
  Image image;
  image.fragments.push_back({FragmentType::Task, 0, {0x51, 0x01}});
  auto r = download(link, image, DownloadOptions{});
  ASSERT_TRUE(std::holds_alternative<DownloadError>(r));
}

TEST(HostilePort, FirmwareBlockErrorsForeverAreCounted) {
  GrumpyBrick brick(3);  // block checksum error, every time
  Link link = make_link(brick, quick());
  std::string srec;
  // Two 100-byte blocks' worth, so the first is not the last block.
  for (int a = 0x8000; a < 0x8000 + 200; a += 20) {
    std::vector<int> body{23, a >> 8, a & 0xff};
    for (int i = 0; i < 20; ++i) body.push_back(i);
    int sum = 0;
    std::string line = "S1";
    for (int b : body) {
      line += fmt::format("{:02X}", b);
      sum += b;
    }
    srec += line + fmt::format("{:02X}\n", ~sum & 0xff);
  }
  std::string path = ::testing::TempDir() + "rcxc-grumpy.srec";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(srec.c_str(), f);
    std::fclose(f);
  }
  auto r = run_remote(link, {"firmware", path});
  std::remove(path.c_str());
  ASSERT_TRUE(std::holds_alternative<RemoteError>(r));
  EXPECT_EQ(std::get<RemoteError>(r).message,
            "the RCX reported a checksum error for the firmware block at 0x8000 3 times in a row; giving up");
  EXPECT_LT(brick.requests, 10);
}

}  // namespace rcx
