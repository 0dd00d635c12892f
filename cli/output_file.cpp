#include "cli/output_file.h"

#include <filesystem>
#include <fstream>

namespace rcxc::cli {

bool write_file_atomically(const std::string& path, const std::string& bytes) {
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
