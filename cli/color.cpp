#include "cli/color.h"

#include <unistd.h>

#include <cstdlib>
#include <string_view>

namespace rcxc::cli {

CLI::Option* add_color_option(CLI::App* cmd, std::string& when) {
  return cmd->add_option("--color", when, "Colour the diagnostics: auto (on a terminal, the default), always, never")
      ->check(CLI::IsMember({"auto", "always", "never"}));
}

bool color_on_stderr(const std::string& when) {
  if (when == "always") return true;
  if (when == "never") return false;
  const char* term = std::getenv("TERM");
  const char* no_color = std::getenv("NO_COLOR");
  return ::isatty(STDERR_FILENO) != 0 && !(term && std::string_view(term) == "dumb") && !(no_color && *no_color);
}

}  // namespace rcxc::cli
