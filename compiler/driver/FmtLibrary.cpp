// fmt's compiled part, built into ldaec from fmt's own implementation
// header: the system has fmt only as a shared library, which would load
// the shared C++ runtime that ldaec links statically
// (cmake/LdaeSelfContained.cmake). The two templates are the ones ldaec's
// code instantiates with char and the header leaves to the library.
#include <fmt/format-inl.h>

FMT_BEGIN_NAMESPACE
namespace detail {
template FMT_API auto decimal_point_impl(locale_ref) -> char;
template FMT_API auto thousands_sep_impl(locale_ref)
    -> thousands_sep_result<char>;
} // namespace detail
FMT_END_NAMESPACE
