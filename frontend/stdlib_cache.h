// rcx.nqh read and parsed once, for callers that compile many small
// programs (the fuzz targets, tests): reading the stdlib is about three
// quarters of the front end's work for a program of a few lines.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "frontend/ast.h"
#include "frontend/diagnostics.h"
#include "frontend/frontend.h"

namespace rcxc::frontend {

struct StdlibCache;

// The stdlib preprocessed and parsed with `options`' -D and -U; nullptr
// with -n. Whole declarations are parsed on their own, so a program after
// them parses as if it followed rcx.nqh.
std::shared_ptr<const StdlibCache> make_stdlib_cache(const Options& options);

// parse_source(), starting from `stdlib` when it was made with the same -D,
// -U and -n and `sm` is fresh (the stdlib's files then get the ids they
// had); otherwise the stdlib is read as usual. The result is the same
// either way.
std::optional<ast::Program> parse_source(const std::string& name, std::string text, const Options& options,
                                         const StdlibCache* stdlib, SourceManager& sm, Diagnostics& diags);

}  // namespace rcxc::frontend
