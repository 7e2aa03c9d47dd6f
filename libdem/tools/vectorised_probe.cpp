// The bond pass of every built-in law, instantiated as the step kernel instantiates it
// (libdem/src/step.cpp) and compiled under the same options, for the build check that every
// `#pragma omp simd` loop of bond_pass.hpp vectorises (tests/dem/check_vectorised.sh). A loop
// the compiler leaves scalar gives the same results, only slower, so no other test sees it.
#include <strata/dem/detail/bond_pass.hpp>
#include <strata/dem/laws.hpp>

#include <vector>

namespace strata::dem::detail {

using AnyFn = void (*)();

namespace {
template <int D, class Law, bool kEnergy>
void add_rests(std::vector<AnyFn>& out) {
  out.push_back(reinterpret_cast<AnyFn>(&bond_chunks<D, Law, kEnergy, kRadiusSum>));
  out.push_back(reinterpret_cast<AnyFn>(&bond_chunks<D, Law, kEnergy, kUniform>));
  out.push_back(reinterpret_cast<AnyFn>(&bond_chunks<D, Law, kEnergy, kPerBond>));
}

template <class... L>
void add_laws(std::vector<AnyFn>& out, LawList<L...>) {
  (add_rests<2, L, false>(out), ...);
  (add_rests<2, L, true>(out), ...);
  (add_rests<3, L, false>(out), ...);
  (add_rests<3, L, true>(out), ...);
}
}  // namespace

// Their addresses leave this file, so every instantiation above is compiled.
std::vector<AnyFn> vectorised_probe() {
  std::vector<AnyFn> out;
  add_laws(out, BuiltinLaws{});
  return out;
}

}  // namespace strata::dem::detail
