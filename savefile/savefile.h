// Writing a file whole or not at all: what a command produces (images,
// listings, traces) and the language server's copy of the standard library.
#pragma once

#include <optional>
#include <string>

namespace rcxc::savefile {

// Writes `bytes` into a temporary beside `path` (mkstemp: a fresh random
// name, O_EXCL), then renames it over `path`: a failed or interrupted write
// leaves what was there before, and no predictable name exists for a
// symbolic link to redirect. The file keeps the mode of the one it replaces
// (new ones get 0666 less the umask). A symbolic link to a plain file has
// that file replaced so, the link kept. Anything else at `path` (a device, a
// pipe, a link to one, a link to nothing) is written through. Returns why the write failed
// ("No such file or directory", "Is a directory"), or nullopt when it worked.
std::optional<std::string> write_file_atomically(const std::string& path, const std::string& bytes);

// Why write_file_atomically(path, ...) would fail before any byte is
// written, or nullopt when it looks able to: a folder at `path`, no folder
// for it, a folder that takes no new file (tried with a temporary, made and
// removed, so read-only mounts and /proc count too). For a command to say
// so before slow work (a download) rather than after. A device, pipe or
// link to one is not tried: opening may block.
std::optional<std::string> check_writable(const std::string& path);

// Whether two paths name the same file (or would, once written).
bool same_file(const std::string& a, const std::string& b);

}  // namespace rcxc::savefile
