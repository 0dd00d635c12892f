// Writing what a command produces (images, listings, traces).
#pragma once

#include <string>

namespace rcxc::cli {

// Writes `bytes` into a new file beside `path`, then renames it over
// `path`: a failed or interrupted write leaves what was there before. Anything
// else at `path` (a device, a pipe, a symbolic link) is written through.
bool write_file_atomically(const std::string& path, const std::string& bytes);

}  // namespace rcxc::cli
