#include "cli/large_stack.h"

#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>

#include <exception>

namespace rcxc::cli {
namespace {

struct Job {
  const std::function<void()>* body;
  sigset_t mask;  // the caller's
  std::exception_ptr thrown;
};

void* run_job(void* arg) {
  auto* job = static_cast<Job*>(arg);
  pthread_sigmask(SIG_SETMASK, &job->mask, nullptr);
  try {
    (*job->body)();
  } catch (...) {
    job->thrown = std::current_exception();
  }
  return nullptr;
}

}  // namespace

bool let_main_stack_grow_to(std::size_t bytes) {
  rlimit limit{};
  if (::getrlimit(RLIMIT_STACK, &limit) != 0) return false;
  if (limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur >= bytes) return true;
  if (limit.rlim_max != RLIM_INFINITY && limit.rlim_max < bytes) return false;
  limit.rlim_cur = bytes;
  return ::setrlimit(RLIMIT_STACK, &limit) == 0;
}

void run_with_stack(std::size_t bytes, const std::function<void()>& body) {
  // The waiting thread blocks every signal, so a signal sent to the process
  // (Ctrl-C) reaches the worker, which has the caller's mask: what `body`
  // does with signals (a signalfd for SIGINT) works as on the main thread.
  Job job{&body, {}, nullptr};
  sigset_t all;
  sigfillset(&all);
  pthread_sigmask(SIG_SETMASK, &all, &job.mask);
  // Under an address-space limit too tight for the whole stack, a quarter
  // or a sixteenth of it still beats the main thread's.
  bool started = false;
  pthread_t thread;
  for (std::size_t size = bytes; !started && size >= bytes / 16; size /= 4) {
    pthread_attr_t attr;
    if (pthread_attr_init(&attr) != 0) break;
    started = pthread_attr_setstacksize(&attr, size) == 0 && pthread_create(&thread, &attr, run_job, &job) == 0;
    pthread_attr_destroy(&attr);
  }
  if (!started) {
    pthread_sigmask(SIG_SETMASK, &job.mask, nullptr);
    body();
    return;
  }
  pthread_join(thread, nullptr);
  // The mask stays: a signal `body` blocked and left pending (a second
  // Ctrl-C its signalfd never read) would otherwise be delivered here and
  // end the process with it, where one thread would have exited normally.
  if (job.thrown) std::rethrow_exception(job.thrown);
}

}  // namespace rcxc::cli
