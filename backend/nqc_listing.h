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

// nqc -L's layout, or with nqc's -c the one LASM (the RCX SDK's assembler)
// reads: each operand field as a number in the SDK's order, branch
// targets as labels (t0010017: task 1, address 17; s... in subroutines).
enum class ListingStyle { Nqc, Lasm };

// Any image in nqc's layout: names from the image's symbols, tasks then
// subroutines in number order.
std::string nqc_listing(const rcx::Image& image, const SourceLineAt& source_line = {},
                        ListingStyle style = ListingStyle::Nqc);

// A compiled program; with `sm`, each source line is printed above the
// first instruction made from it.
std::string nqc_listing(const Output& out, const SourceManager* sm, ListingStyle style = ListingStyle::Nqc);

}  // namespace rcxc::backend
