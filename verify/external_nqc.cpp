#include "verify/external_nqc.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

extern char** environ;

namespace rcx::semtest {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// nqc reports errors as
//   # Error: <message>
//   File "<file>" ; line <N>
// (warnings say "# Warning:"); the pairs may come in either order.
std::vector<CompilerMessage> parse_nqc_messages(const std::string& text) {
  std::vector<CompilerMessage> out;
  std::istringstream in(text);
  std::string line;
  int pending_line = 0;
  while (std::getline(in, line)) {
    auto l = line.find("; line ");
    if (line.rfind("File \"", 0) == 0 && l != std::string::npos) {
      pending_line = std::atoi(line.c_str() + l + 7);
      if (!out.empty() && out.back().line == 0) out.back().line = pending_line;
      continue;
    }
    for (auto [tag, error] : {std::pair{"# Error: ", true}, std::pair{"# Warning: ", false}}) {
      if (line.rfind(tag, 0) == 0) out.push_back({error, 0, line.substr(std::string(tag).size())});
    }
  }
  return out;
}

}  // namespace

ExternalCompile compile_with_nqc(const std::string& nqc, const std::string& file,
                                 const std::vector<std::string>& args) {
  ExternalCompile result;
  std::string dir = (std::filesystem::temp_directory_path() / "rcxc-nqc-XXXXXX").string();
  if (!mkdtemp(dir.data())) {
    result.failure = "cannot create a temporary folder";
    return result;
  }
  std::string image_path = dir + "/out.rcx", log_path = dir + "/log.txt";
  std::string out_arg = "-O" + image_path;
  // nqc searches includes from the current folder; rcxc from the including
  // file's folder first. -I gives nqc the same start.
  std::string dir_arg = "-I" + (std::filesystem::path(file).parent_path().empty()
                                    ? std::string(".")
                                    : std::filesystem::path(file).parent_path().string());
  std::vector<char*> argv{const_cast<char*>(nqc.c_str()), const_cast<char*>("-Trcx"), dir_arg.data(), out_arg.data()};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(const_cast<char*>(file.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  int rc = posix_spawnp(&pid, nqc.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  if (rc == 0) waitpid(pid, &status, 0);
  std::string log = slurp(log_path);
  if (rc != 0) {
    result.failure = "cannot run '" + nqc + "' (is nqc installed?)";
  } else {
    result.messages = parse_nqc_messages(log);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      auto image = rcx::read_image_file(image_path);
      if (auto* img = std::get_if<rcx::Image>(&image)) result.image = std::move(*img);
      else result.failure = "nqc wrote an unreadable image: " + std::get<rcx::ImageError>(image).message;
    } else if (result.messages.empty()) {
      result.failure = "nqc failed: " + log;
    }
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return result;
}

}  // namespace rcx::semtest
