#include "cli/output_file.h"

#include <filesystem>
#include <fstream>

namespace rcxc::cli {

bool write_file_atomically(const std::string& path, const std::string& bytes) {
  // Anything but a plain file (-o /dev/null, a FIFO, a symbolic link such as
  // /dev/stderr) is written through: renaming over it would replace the
  // device or the link itself with a regular file.
  std::error_code status_error;
  auto status = std::filesystem::symlink_status(path, status_error);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    std::ofstream f(path, std::ios::binary);
    f << bytes;
    f.close();
    return static_cast<bool>(f);
  }
  std::string temp = path + ".rcxc-tmp";
  {
    std::ofstream f(temp, std::ios::binary);
    f << bytes;
    f.close();
    if (!f) {
      std::error_code ec;
      std::filesystem::remove(temp, ec);
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
  }
  return !ec;
}

}  // namespace rcxc::cli
