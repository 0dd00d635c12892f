// The host side of the IR link against a hostile brick: the input is what
// the "brick" sends back, in chunks, whatever the host asked. It runs
// through the session (transact), the downloader and the remote actions
// (datalog upload, get, a firmware download); every call must end, with a result or
// an error, within the retries the link allows. The port's clock is
// virtual: pauses and read timeouts cost nothing.
#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "link/download.h"
#include "link/remote.h"
#include "link/session.h"
#include "rcx/opcodes.h"

namespace {

// Replies come from the fuzz input: each read hands out the next chunk
// (its length is the chunk's first byte), an empty read (a timeout) once
// the input is used up.
class HostileBrick : public rcx::Transport {
 public:
  explicit HostileBrick(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::optional<rcx::TransportError> write(std::span<const std::uint8_t>) override { return std::nullopt; }
  std::variant<std::vector<std::uint8_t>, rcx::TransportError> read(rcx::Millis) override {
    if (at_ >= bytes_.size()) return std::vector<std::uint8_t>{};
    std::size_t want = bytes_[at_];
    ++at_;
    std::size_t n = std::min<std::size_t>(want, bytes_.size() - at_);
    std::vector<std::uint8_t> out(bytes_.begin() + static_cast<long>(at_), bytes_.begin() + static_cast<long>(at_ + n));
    at_ += n;
    return out;
  }
  bool echoes() const override { return echoes_; }
  void pause(rcx::Millis) override {}
  std::string describe() const override { return "hostile brick"; }
  bool echoes_ = false;

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

rcx::LinkOptions quick() {
  rcx::LinkOptions o;
  o.retries = 3;
  o.reply_grace = rcx::Millis(0);
  o.byte_seconds = 0;
  return o;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t mode = data[0];
  HostileBrick brick(std::span<const std::uint8_t>(data + 1, size - 1));
  brick.echoes_ = (mode & 0x80) != 0;
  rcx::Link link = rcx::make_link(brick, quick());
  // Mode bit 2 adds the firmware download to the four actions of bits 0-1.
  if ((mode & 0x04) != 0) {
    rcx::Firmware fw;
    fw.start = fw.entry = 0x8000;
    fw.bytes.assign(250, 0x5a);  // three blocks, the last one short
    (void)rcx::download_firmware(link, fw);
    return 0;
  }
  switch (mode & 0x03) {
    case 0: (void)rcx::transact(link, rcx::request_payload(rcx::info(rcx::Op::GetBatteryPower), {})); break;
    case 1: {
      rcx::Image image;
      image.fragments.push_back({rcx::FragmentType::Task, 0, std::vector<std::uint8_t>(300, 0x51)});
      image.fragments.push_back({rcx::FragmentType::Subroutine, 0, {0x51, 0x03, 0xF6}});
      (void)rcx::download(link, image, rcx::DownloadOptions{});
      break;
    }
    case 2: (void)rcx::run_remote(link, {"datalog"}); break;
    default: (void)rcx::run_remote(link, {"get", "var", "3"}); break;
  }
  return 0;
}
