// How the C library's allocator is set up for a command that compiles one
// program and exits (compile, run, compare, nqc's command line).
#pragma once

namespace rcxc::cli {

// Whether the command line `argv` compiles one program and ends: the
// allocator settings below suit it. Not `test` (its workers compile in
// parallel, each needing an arena of its own) nor the long-running
// commands (lsp, brick, remote), whose memory should go back to the system.
bool compiles_once(int argc, char** argv);

// glibc's defaults fit a long-running, many-threaded server. rcxc does its
// work on one second thread (large_stack.h), which glibc gives an arena of
// its own, and such an arena grows a page run at a time with one mprotect
// call each: 14 700 calls compiling 30 000 lines. This puts the work thread
// on the main arena, which grows the heap 16 MB at a time (a step that
// still fits under a tight `ulimit -v`). Large blocks stay separate
// mappings, given back when freed: keeping them in the heap saved page
// faults but could double a deeply nested program's footprint. A no-op
// outside glibc.
void tune_allocator_for_one_compile();

}  // namespace rcxc::cli
