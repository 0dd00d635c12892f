// fmt's implementation, compiled once for the whole project.
//
// Header-only fmt (FMT_HEADER_ONLY) made every file that formats anything
// compile fmt's formatting engine again: about 4 s of CPU per file at -O2,
// a third of a clean build. Debian ships fmt only as a shared library, and
// rcxc links libstdc++ statically for its start-up time (CMakeLists.txt),
// which libfmt.so would undo. So this file compiles fmt's out-of-line
// definitions into the static rcxc_fmt library, and every other file sees
// only their declarations.
#include <fmt/format-inl.h>

FMT_BEGIN_NAMESPACE
namespace detail {
// format.h declares these `extern template` when fmt is not header-only,
// so some file of the program must instantiate them.
template auto thousands_sep_impl<char>(locale_ref) -> thousands_sep_result<char>;
template auto decimal_point_impl<char>(locale_ref) -> char;
}  // namespace detail
FMT_END_NAMESPACE
