// Opening the user's tower for the link commands (download, remote).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "link/transport.h"

namespace rcxc::cli {

// The port --port or RCX_PORT names (else the USB tower), or nullptr after
// telling the user why it could not be opened ("rcxc COMMAND: ...").
std::unique_ptr<rcx::Transport> open_tower(const std::string& command, const std::optional<std::string>& port);

}  // namespace rcxc::cli
