// The compiler and the emulator recurse over the program's nesting, up to
// the limits in frontend/nesting.h. Those limits are sized for this stack,
// so rcxc makes sure its work has it whatever stack the caller's `ulimit -s`
// gives the main thread (or the 2-8 MB a plain std::thread gets): the main
// thread's, its limit raised, or else a thread's of its own.
#pragma once

#include <cstddef>
#include <functional>

namespace rcxc::cli {

// 3200 levels of nesting need about 7 MB of stack under AddressSanitizer
// and 1-3 MB in a release build; this leaves ample room in both. It is
// address space reserved, not memory used: untouched pages cost nothing.
inline constexpr std::size_t kWorkStackBytes = std::size_t{64} << 20;

// Lets the main thread's stack grow to `bytes` by raising the soft stack
// limit (within the hard one); false when the hard limit is lower. Linux
// checks the limit each time the stack grows, and leaves at least 128 MB
// free below the main stack whatever limit the program started with, so
// the main thread can then do the work itself: starting a thread for it
// cost a fifth of a millisecond, a twentieth of compiling a short program.
// Programs rcxc starts (nqc, for `rcxc compare`) inherit the raised limit.
bool let_main_stack_grow_to(std::size_t bytes);

// Runs `body` on a new thread with a stack of `bytes` and waits for it;
// rethrows what `body` threw. The calling thread keeps every signal
// blocked afterwards (it is about to return from main, or is a worker).
// Under an address-space limit too small for that stack it tries a
// quarter, then a sixteenth; when no thread can be made at all, `body`
// runs on the calling thread.
void run_with_stack(std::size_t bytes, const std::function<void()>& body);

}  // namespace rcxc::cli
