#include "rcx/file_read.h"

#include <filesystem>
#include <fstream>
#include <iterator>

namespace rcx {

std::variant<std::string, FileProblem> read_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return FileProblem::Directory;
  std::ifstream in(path, std::ios::binary);
  if (!in) return FileProblem::CannotOpen;
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return FileProblem::ReadError;
  return bytes;
}

}  // namespace rcx
