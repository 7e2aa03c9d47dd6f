// The bond pass of every built-in law, instantiated as the step kernel instantiates it
// (libdem/src/step.cpp) and compiled under the same options, for the build check that every
// `#pragma omp simd` loop of bond_pass.hpp vectorises (tests/dem/check_vectorised.sh). A loop
// the compiler leaves scalar gives the same results, only slower, so no other test sees it.
#include <strata/dem/detail/law_entry.hpp>
#include <strata/dem/laws.hpp>

#include <vector>

namespace strata::dem::detail {

using AnyFn = void (*)();

namespace {
// run_chunks takes every rest-length mode of the bond pass (bond_chunks), as the step kernel does
template <class... L>
void add_laws(std::vector<AnyFn>& out, LawList<L...>) {
  (out.push_back(reinterpret_cast<AnyFn>(&run_chunks<2, L, false>)), ...);
  (out.push_back(reinterpret_cast<AnyFn>(&run_chunks<2, L, true>)), ...);
  (out.push_back(reinterpret_cast<AnyFn>(&run_chunks<3, L, false>)), ...);
  (out.push_back(reinterpret_cast<AnyFn>(&run_chunks<3, L, true>)), ...);
}
}  // namespace

// Their addresses leave this file, so every instantiation above is compiled.
std::vector<AnyFn> vectorised_probe() {
  std::vector<AnyFn> out;
  add_laws(out, BuiltinLaws{});
  return out;
}

}  // namespace strata::dem::detail
