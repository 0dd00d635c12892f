// The compiler's listing (`rcxc compile --listing`): every task and
// subroutine with address, mnemonic and operands, the bytes, and the source
// line each instruction came from.
#pragma once

#include <string>

#include "backend/codegen.h"

namespace rcxc::backend {

// `sm` may be null: the listing then has no source lines.
std::string listing(const Output& out, const SourceManager* sm);

}  // namespace rcxc::backend
