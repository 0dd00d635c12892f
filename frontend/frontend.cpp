#include "frontend/frontend.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "frontend/parse.h"
#include "frontend/preprocess.h"
#include "frontend/sema.h"

namespace rcxc::frontend {
namespace {

std::optional<std::uint32_t> load(const std::string& path, SourceManager& sm, Diagnostics& diags) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    diags.error({}, "'" + path + "' is a directory, not a source file");
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    diags.error({}, "cannot open '" + path + "'");
    return std::nullopt;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  if (std::string why = not_source_reason(path, text); !why.empty()) {
    diags.error({}, why);
    return std::nullopt;
  }
  return sm.add(path, std::move(text));
}

std::string folder_of(const std::string& path) {
  std::string dir = std::filesystem::path(path).parent_path().string();
  return dir.empty() ? "." : dir;
}

std::optional<ast::Program> run(std::uint32_t file, const std::string& dir, const Options& options,
                                SourceManager& sm, Diagnostics& diags) {
  Preprocessed pp = preprocess(file, dir, options, sm, diags);
  ast::Program program = parse_tokens(pp.tokens, diags);
  program.pragmas = std::move(pp.pragmas);
  // Checking a half-parsed program would mostly repeat the syntax errors.
  if (diags.has_errors()) return std::nullopt;
  check(program, diags);
  if (diags.has_errors()) return std::nullopt;
  return program;
}

}  // namespace

std::optional<ast::Program> parse_program(const std::string& path, const Options& options, SourceManager& sm,
                                          Diagnostics& diags) {
  auto file = load(path, sm, diags);
  if (!file) return std::nullopt;
  return run(*file, folder_of(path), options, sm, diags);
}

std::optional<ast::Program> parse_source(const std::string& name, std::string text, const Options& options,
                                         SourceManager& sm, Diagnostics& diags) {
  std::uint32_t file = sm.add(name, std::move(text));
  return run(file, folder_of(name), options, sm, diags);
}

std::optional<std::string> preprocess_file(const std::string& path, const Options& options, SourceManager& sm,
                                           Diagnostics& diags) {
  auto file = load(path, sm, diags);
  if (!file) return std::nullopt;
  Preprocessed pp = preprocess(*file, folder_of(path), options, sm, diags);
  if (diags.has_errors()) return std::nullopt;
  return tokens_to_text(pp.tokens, sm);
}

}  // namespace rcxc::frontend
