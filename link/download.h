// Downloading a program image into an RCX program slot over the IR link.
//
// The sequence: Alive, Stop all tasks, Set program number, Delete all tasks,
// Delete all subroutines, then every subroutine and task as Start download +
// Transfer data blocks (numbered 1, 2, ..., the last one 0), then the
// download-done sound and optionally Start task 0. Every request is retried
// by the link; a fragment whose block could not be delivered is restarted from
// its Start download. Success is reported only when every block was
// acknowledged with error code 0.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <variant>

#include "rcx/image.h"
#include "link/session.h"

namespace rcx {

struct DownloadOptions {
  int program = 1;            // slot 1..5 as users count (sent as 0..4)
  bool run = false;         // start task 0 afterwards
  int max_block = 64;       // largest Transfer data block
  int min_block = 4;        // blocks shrink towards this on a noisy link
  // A block larger than min_block that fails this many times restarts its
  // fragment with blocks a quarter the size: a block the brick may have taken
  // cannot be resent smaller, but a fresh Start download can use any size.
  int block_attempts = 8;
  int fragment_attempts = 12;  // Start downloads per fragment
  int contact_retries = 7;     // retries of the first Alive
  bool sound = true;        // play the download-done sound
};

struct DownloadProgress {
  std::size_t done = 0;   // bytes acknowledged
  std::size_t total = 0;  // bytes to send
};

enum class DownloadFailure : std::uint8_t {
  BadInput,      // nothing to download / a fragment too large for the RCX
  NoBrick,       // the brick never answered
  LinkFailed,    // the brick answered, but a request failed after every retry
  BrickRefused,  // the brick answered with an error (no memory, bad index)
};

struct DownloadError {
  DownloadFailure kind;
  std::string message;
};

struct DownloadReport {
  std::size_t bytes = 0;  // program bytes delivered
  int blocks = 0;         // blocks acknowledged
  LinkStats link;
};

using ProgressFn = std::function<void(const DownloadProgress&)>;

std::variant<DownloadReport, DownloadError> download(Link& link, const Image& image, const DownloadOptions& options,
                                                     const ProgressFn& progress = {});

}  // namespace rcx
