#include "link/download.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "rcx/opcodes.h"

namespace rcx {
namespace {

// The sound nqc plays when a download is complete (fast upward tones).
constexpr int kDownloadDoneSound = 5;
// Transfer data error codes (seed): 3 block checksum, 6 no download start.
constexpr int kBlockChecksumError = 3;

using Result = std::variant<Bytes, DownloadError>;

DownloadError link_failure(const LinkError& e, bool first_contact) {
  if (first_contact && e.brick_silent) return {DownloadFailure::NoBrick, e.message};
  return {DownloadFailure::LinkFailed, e.message};
}

Result call(Link& link, Op op, std::initializer_list<int> values, bool first_contact = false) {
  std::vector<int> v(values);
  auto r = transact(link, request_payload(info(op), v));
  if (auto* e = std::get_if<LinkError>(&r)) return link_failure(*e, first_contact);
  return std::get<Bytes>(r);
}

int error_code(Op op, const Bytes& reply) { return reply_field(info(op), reply, "errorcode"); }

struct Sender {
  Link& link;
  const DownloadOptions& options;
  const ProgressFn& progress;
  DownloadReport report;
  DownloadProgress where;
  int block = 0;    // current block size, adapted to the line
  int ceiling = 0;  // blocks grow back up to this; lowered by each restart
};

void report_progress(Sender& s) {
  if (s.progress) s.progress(s.where);
}

// Sends one fragment's blocks after its Start download. Returns an error, or
// nothing when every block was acknowledged.
std::optional<DownloadError> send_blocks(Sender& s, const Fragment& f) {
  std::size_t offset = 0;
  int sequence = 1;
  const std::size_t size = f.code.size();
  do {
    std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(s.block), size - offset);
    bool last = offset + n == size;
    auto data = std::span(f.code).subspan(offset, n);
    int before = s.link.stats.attempts;
    const int retries = s.link.options.retries;
    // Big blocks get few tries before the fragment restarts with smaller
    // ones; the smallest blocks get every retry the link allows.
    if (s.block > s.options.min_block) s.link.options.retries = std::min(retries, s.options.block_attempts - 1);
    auto r = transact(s.link, transfer_payload(last ? 0 : sequence, data));
    s.link.options.retries = retries;
    if (auto* e = std::get_if<LinkError>(&r)) {
      return DownloadError{DownloadFailure::LinkFailed, e->message};
    }
    int code = error_code(Op::TransferData, std::get<Bytes>(r));
    if (code != 0) {
      return DownloadError{DownloadFailure::LinkFailed,
                           fmt::format("the RCX rejected block {} with error {}{}", sequence, code,
                                       code == kBlockChecksumError ? " (block checksum)" : "")};
    }
    // Adapt: a block that needed retries means a noisy line, so halve the
    // next ones; a clean one lets them grow back, slowly.
    bool retried = s.link.stats.attempts - before > 1;
    s.block = retried ? std::max(s.options.min_block, s.block / 2)
                      : std::min(s.ceiling, s.block + std::max(1, s.block / 4));
    offset += n;
    ++sequence;
    ++s.report.blocks;
    s.where.done += n;
    report_progress(s);
  } while (offset < size);
  return std::nullopt;
}

std::optional<DownloadError> send_fragment(Sender& s, const Fragment& f) {
  const bool task = f.type == FragmentType::Task;
  const Op start = task ? Op::StartTaskDownload : Op::StartSubroutineDownload;
  const char* what = task ? "task" : "subroutine";
  std::optional<DownloadError> last_error;
  for (int attempt = 0; attempt < s.options.fragment_attempts; ++attempt) {
    std::size_t done_before = s.where.done;
    auto r = call(s.link, start, {0, f.index, static_cast<int>(f.code.size())});
    if (auto* e = std::get_if<DownloadError>(&r)) return *e;
    int code = error_code(start, std::get<Bytes>(r));
    if (code == 1)
      return DownloadError{DownloadFailure::BrickRefused,
                           fmt::format("the RCX has no room for {} {} ({} bytes)", what, f.index, f.code.size())};
    if (code != 0)
      return DownloadError{DownloadFailure::BrickRefused,
                           fmt::format("the RCX refused {} {} (error {})", what, f.index, code)};
    last_error = send_blocks(s, f);
    if (!last_error) return std::nullopt;
    s.where.done = done_before;
    s.block = std::max(s.options.min_block, s.block / 4);
    s.ceiling = s.block;  // a restart loses the fragment's progress: never risk it twice
  }
  return last_error;
}

std::optional<DownloadError> check_image(const Image& image, const DownloadOptions& options) {
  if (options.program < 1 || options.program > 5)
    return DownloadError{DownloadFailure::BadInput, fmt::format("program slot {} is not 1..5", options.program)};
  if (image.fragments.empty()) return DownloadError{DownloadFailure::BadInput, "the image has no tasks"};
  // Start task/subroutine download carries the length in 15 bits.
  for (const auto& f : image.fragments)
    if (f.code.size() > 0x7fff)
      return DownloadError{DownloadFailure::BadInput,
                           fmt::format("{} {} is {} bytes, more than the 32767 a download can carry",
                                       f.type == FragmentType::Task ? "task" : "subroutine", f.index, f.code.size())};
  if (options.min_block < 1 || options.max_block < options.min_block || options.max_block > kMaxTransferBlock)
    return DownloadError{DownloadFailure::BadInput, "block sizes are out of range"};
  if (options.block_attempts < 1 || options.fragment_attempts < 1)
    return DownloadError{DownloadFailure::BadInput, "attempt counts must be at least 1"};
  return std::nullopt;
}

}  // namespace

std::variant<DownloadReport, DownloadError> download(Link& link, const Image& image, const DownloadOptions& options,
                                                     const ProgressFn& progress) {
  if (auto e = check_image(image, options)) return *e;
  Sender s{link, options, progress, {}, {}, options.max_block, options.max_block};
  for (const auto& f : image.fragments) s.where.total += f.code.size();

  auto step = [&](Op op, std::initializer_list<int> values, bool first = false) -> std::optional<DownloadError> {
    auto r = call(link, op, values, first);
    if (auto* e = std::get_if<DownloadError>(&r)) return *e;
    return std::nullopt;
  };
  // First contact gets few retries: a brick that is off should be reported
  // in a second or two; once it has answered, the line is worth persisting on.
  const int retries = link.options.retries;
  link.options.retries = std::min(retries, options.contact_retries);
  auto contact = step(Op::Alive, {}, true);
  link.options.retries = retries;
  if (contact) return *contact;
  if (auto e = step(Op::StopAllTasks, {})) {
    // It answered Alive but not this: without firmware only the ROM answers.
    e->message += " (if the RCX shows no program number, install firmware: rcxc remote firmware FILE.srec)";
    return *e;
  }
  if (auto e = step(Op::SetProgramNumber, {options.program - 1})) return *e;
  if (auto e = step(Op::DeleteAllTasks, {})) return *e;
  if (auto e = step(Op::DeleteAllSubroutines, {})) return *e;
  report_progress(s);
  // Subroutines first, as nqc does, then tasks.
  for (FragmentType type : {FragmentType::Subroutine, FragmentType::Task})
    for (const auto& f : image.fragments)
      if (f.type == type)
        if (auto e = send_fragment(s, f)) return *e;
  if (options.sound)
    if (auto e = step(Op::PlaySound, {kDownloadDoneSound})) return *e;
  if (options.run)
    if (auto e = step(Op::StartTask, {0})) return *e;
  s.report.bytes = s.where.done;
  s.report.link = link.stats;
  return s.report;
}

}  // namespace rcx
