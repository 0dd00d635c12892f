#include "cli/tower.h"

#include <iostream>

namespace rcxc::cli {

std::unique_ptr<rcx::Transport> open_tower(const std::string& command, const std::optional<std::string>& port) {
  auto opened = rcx::open_user_port(port);
  if (auto* e = std::get_if<rcx::TransportError>(&opened)) {
    std::cerr << "rcxc " << command << ": " << e->message << "\n";
    return nullptr;
  }
  return std::move(std::get<std::unique_ptr<rcx::Transport>>(opened));
}

}  // namespace rcxc::cli
