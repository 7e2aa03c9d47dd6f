// The step kernel of every built-in law (BuiltinLaws in laws.hpp), compiled here: the bond
// pass, the two phases of a step and the update (strata/dem/detail/step_kernel.hpp), each
// in this one translation unit with everything it inlines, under libdem's floating-point
// flags and without gather instructions (libdem/CMakeLists.txt).
#include <strata/dem/detail/law_entry.hpp>
#include <strata/dem/laws.hpp>

#include <vector>

namespace strata::dem::detail {

namespace {
template <class... L>
std::vector<LawEntry> entries_of(LawList<L...>) {
  std::vector<LawEntry> out;
  (out.push_back(make_law_entry<L>()), ...);
  return out;
}
}  // namespace

// The registry rows of the built-in laws, in the order of BuiltinLaws.
std::vector<LawEntry> builtin_law_entries() { return entries_of(BuiltinLaws{}); }

}  // namespace strata::dem::detail
