// The listing in nqc's layout (`rcxc nqc -L`, `nqc -L`): tools and people
// who read nqc's listings (BricxCC's code window, scripts) read rcxc's code
// the same way. rcxc's own listing (listing.h) stays the richer one.
#pragma once

#include <functional>
#include <string>

#include "backend/codegen.h"
#include "rcx/image.h"

namespace rcxc::backend {

// The text to print above the instruction at `address` of a fragment (a
// source line, nqc's -s), or "" for none.
using SourceLineAt = std::function<std::string(rcx::FragmentType, int index, int address)>;

// Any image in nqc's layout: names from the image's symbols, tasks then
// subroutines in number order.
std::string nqc_listing(const rcx::Image& image, const SourceLineAt& source_line = {});

// A compiled program; with `sm`, each source line is printed above the
// first instruction made from it.
std::string nqc_listing(const Output& out, const SourceManager* sm);

}  // namespace rcxc::backend
