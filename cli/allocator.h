// How the C library's allocator is set up for a command that compiles one
// program and exits (compile, run, compare, nqc's command line).
#pragma once

namespace rcxc::cli {

// Whether the command line `argv` compiles one program and ends: the
// allocator settings below suit it. Not `test` (its workers compile in
// parallel, each needing an arena of its own) nor the long-running
// commands (lsp, brick, remote), whose memory should go back to the system.
bool compiles_once(int argc, char** argv);

// glibc's defaults fit a long-running, many-threaded server. When rcxc does
// its work on a second thread (large_stack.h: only under a hard stack limit
// too low to raise), glibc gives that thread an arena of its own, which
// grows a page run at a time with one mprotect call each: 14 700 calls
// compiling 30 000 lines. This keeps every thread on the main arena, and
// grows that heap 16 MB at a time (a step that still fits under a tight
// `ulimit -v`). Large blocks stay separate mappings, given back when freed:
// keeping them in the heap saved page faults but could double a deeply
// nested program's footprint. A no-op outside glibc.
void tune_allocator_for_one_compile();

}  // namespace rcxc::cli
