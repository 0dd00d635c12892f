#include "savefile/savefile.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <optional>
#include <system_error>
#include <utility>
#include <fstream>
#include <vector>

namespace rcxc::savefile {
namespace {

bool write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// Of the target's name in its temporary's: 1 + 200 + 7 is well inside the
// 255 bytes a name may have on Linux file systems.
constexpr std::size_t kMostTemporaryStem = 200;

// The mode a new file gets from open(..., 0666): mkstemp makes 0600.
mode_t new_file_mode() {
  mode_t mask = ::umask(0);
  ::umask(mask);
  return 0666 & ~mask;
}

// The plain file a chain of symbolic links ends at, or nullopt: `path` is
// no link, the chain is broken, loops or runs long, or passes through /proc
// or /dev (/dev/stderr is a link to /proc/self/fd/2, which may be a log file
// open for appending: replacing that file would drop what it holds).
std::optional<std::string> plain_file_behind_link(const std::string& path) {
  namespace fs = std::filesystem;
  constexpr int kMostLinks = 40;  // as the kernel's own limit
  std::error_code ec;
  fs::path at = fs::absolute(path, ec);
  if (ec || !fs::is_symlink(fs::symlink_status(at, ec))) return std::nullopt;
  for (int hop = 0; hop < kMostLinks; ++hop) {
    std::string text = at.lexically_normal().string();
    if (text.starts_with("/proc/") || text.starts_with("/dev/")) return std::nullopt;
    auto status = fs::symlink_status(at, ec);
    if (ec) return std::nullopt;
    if (fs::is_regular_file(status)) return text;
    if (!fs::is_symlink(status)) return std::nullopt;
    fs::path next = fs::read_symlink(at, ec);
    if (ec) return std::nullopt;
    at = next.is_absolute() ? next : at.parent_path() / next;
  }
  return std::nullopt;
}

// A fresh temporary beside `target` (mkstemp: O_EXCL, a random name): its
// descriptor and name, or -1 with errno set.
std::pair<int, std::string> temporary_beside(const std::filesystem::path& target) {
  std::filesystem::path folder = target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
  // The name is cut to leave room for the dot and the random part: a file
  // named with 250 characters is allowed, its temporary would not be.
  std::string stem = target.filename().string().substr(0, kMostTemporaryStem);
  std::string pattern = (folder / ("." + stem + ".XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  int fd = ::mkstemp(name.data());
  return {fd, fd < 0 ? std::string() : std::string(name.data())};
}

}  // namespace

std::optional<std::string> check_writable(const std::string& given) {
  namespace fs = std::filesystem;
  std::string path = plain_file_behind_link(given).value_or(given);
  std::error_code ec;
  auto status = fs::symlink_status(path, ec);
  if (fs::is_directory(status)) return std::generic_category().message(EISDIR);
  if (fs::exists(status) && !fs::is_regular_file(status)) return std::nullopt;
  auto [fd, temp] = temporary_beside(fs::path(path));
  if (fd < 0) return std::generic_category().message(errno);
  ::close(fd);
  fs::remove(temp, ec);
  return std::nullopt;
}

std::optional<std::string> write_file_atomically(const std::string& given, const std::string& bytes) {
  namespace fs = std::filesystem;
  auto failure = [](int error) { return std::optional<std::string>(std::generic_category().message(error)); };
  // A symbolic link to a plain file (format -i on a linked source) has that
  // file replaced as any plain file is, the link left as it is: written
  // through, a failed write would leave the file cut short.
  std::string path = plain_file_behind_link(given).value_or(given);
  std::error_code status_error;
  // Anything else but a plain file (-o /dev/null, a FIFO, a symbolic link
  // such as /dev/stderr) is written through: renaming over it would replace
  // the device or the link itself with a regular file.
  auto status = fs::symlink_status(path, status_error);
  if (fs::is_directory(status)) return failure(EISDIR);
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    errno = 0;
    std::ofstream f(path, std::ios::binary);
    f << bytes;
    f.close();
    if (!f) return failure(errno != 0 ? errno : EIO);
    return std::nullopt;
  }
  // The temporary is made by mkstemp (O_CREAT|O_EXCL, a random name) in the
  // target's folder, so the rename stays on one file system and no one can
  // have put a link at the temporary's name beforehand.
  auto [fd, temp] = temporary_beside(fs::path(path));
  if (fd < 0) return failure(errno);
  struct stat old{};
  mode_t mode = ::stat(path.c_str(), &old) == 0 ? (old.st_mode & 07777) : new_file_mode();
  int error = 0;
  errno = 0;
  if (::fchmod(fd, mode) != 0 || !write_all(fd, bytes)) error = errno != 0 ? errno : EIO;
  if (::close(fd) != 0 && error == 0) error = errno;
  std::error_code ec;
  if (error == 0) fs::rename(temp, path, ec);
  if (error != 0 || ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    return error != 0 ? failure(error) : std::optional<std::string>(ec.message());
  }
  return std::nullopt;
}

bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::equivalent(a, b, ec) && !ec) return true;
  // Not both there yet: the same name, once made absolute and normal.
  auto normal = [](const std::string& p) {
    std::error_code e;
    return fs::weakly_canonical(fs::absolute(p, e), e).lexically_normal();
  };
  return normal(a) == normal(b);
}

}  // namespace rcxc::savefile
