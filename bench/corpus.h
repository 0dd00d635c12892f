// What the benchmarks against nqc share: the corpus of NQC programs (through
// RCXC_CORPUS_DIR, or ../shared/corpus beside the source tree) and nqc's
// listing of a program.
#pragma once

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace rcxc::bench {

inline std::filesystem::path corpus_dir() {
  if (const char* env = std::getenv("RCXC_CORPUS_DIR")) return env;
  return std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "shared" / "corpus";
}

// CPU seconds (user + system) the finished child processes spent so far:
// the benches time rcxc and nqc as processes, the same way for both.
inline double children_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

// A folder of its own in the system's temporary folder, removed with
// everything in it when the object goes: where a bench writes the programs
// it generates for both compilers to read.
struct ScratchDir {
  std::filesystem::path path;
  explicit ScratchDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(getpid()))) {
    std::filesystem::create_directories(path);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

// Every .nqc file under `dir`, sorted; empty when there is no such folder.
inline std::vector<std::filesystem::path> nqc_files_under(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  if (!std::filesystem::is_directory(dir)) return files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.path().extension() == ".nqc") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Every .nqc file of the corpus, sorted; empty without the corpus.
inline std::vector<std::filesystem::path> corpus_files() { return nqc_files_under(corpus_dir()); }

// Programs from elsewhere that the passes were never tuned on, in a folder
// outside the repository named by RCXC_OUTSIDE_DIR (their authors' files are
// not ours to commit; docs/compiler.md lists where they come from); empty
// when it is not set.
inline std::vector<std::filesystem::path> outside_files() {
  const char* env = std::getenv("RCXC_OUTSIDE_DIR");
  return env ? nqc_files_under(env) : std::vector<std::filesystem::path>{};
}

// `nqc -Trcx -L FILE`'s listing, or nullopt when nqc fails or is missing.
inline std::optional<std::string> nqc_listing(const std::filesystem::path& file) {
  // nqc looks for #include files in the current folder and -I, not beside
  // the file that includes them.
  std::string cmd = "nqc -Trcx -I'" + file.parent_path().string() + "' -L '" + file.string() + "' 2>/dev/null";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return std::nullopt;
  std::string text;
  std::array<char, 4096> buf{};
  while (std::size_t n = fread(buf.data(), 1, buf.size(), pipe)) text.append(buf.data(), n);
  if (pclose(pipe) != 0) return std::nullopt;
  return text;
}

// nqc's code size: its listing ends with "Total size: N bytes".
inline std::optional<int> nqc_bytes(const std::string& listing) {
  std::smatch m;
  if (!std::regex_search(listing, m, std::regex("Total size: ([0-9]+) bytes"))) return std::nullopt;
  return std::stoi(m[1]);
}

}  // namespace rcxc::bench
