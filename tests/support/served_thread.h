// A server loop (virtual RCX or NXT brick on a pty) run on a thread until
// the test ends: the loop watches `stop_fd`, and stop() writes to it and
// joins, so a fixture can end the server before it looks at the brick.
#pragma once

#include <unistd.h>

#include <thread>
#include <utility>

namespace rcxc::test {

class ServedThread {
 public:
  ServedThread() = default;
  ServedThread(const ServedThread&) = delete;
  ServedThread& operator=(const ServedThread&) = delete;
  ~ServedThread() { stop(); }

  // Runs `serve(stop_fd)` on the thread; false when no pipe could be made.
  template <class Serve>
  bool start(Serve serve) {
    if (::pipe(pipe_) != 0) return false;
    thread_ = std::thread([serve = std::move(serve), fd = pipe_[0]]() mutable { serve(fd); });
    return true;
  }

  void stop() {
    if (thread_.joinable()) {
      (void)!::write(pipe_[1], "x", 1);
      thread_.join();
    }
    for (int& fd : pipe_) {
      if (fd >= 0) ::close(fd);
      fd = -1;
    }
  }

 private:
  int pipe_[2] = {-1, -1};
  std::thread thread_;
};

}  // namespace rcxc::test
