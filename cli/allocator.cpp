#include "cli/allocator.h"

#include <string_view>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "cli/nqc_mode.h"

namespace rcxc::cli {

bool compiles_once(int argc, char** argv) {
  if (argc > 0 && started_as_nqc(argv[0])) return true;
  if (argc < 2) return false;
  std::string_view command = argv[1];
  return command == "compile" || command == "run" || command == "compare" || command == "nqc";
}

void tune_allocator_for_one_compile() {
#if defined(__GLIBC__)
  // Arena settings take effect only before the work thread first allocates.
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_TOP_PAD, 16 << 20);
#endif
}

}  // namespace rcxc::cli
