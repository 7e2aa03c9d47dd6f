#pragma once
/// Adding a pair law from outside strata (examples/api/ex2_custom_law.cpp shows one).
///
/// register_law<MyLaw>() compiles the DEM step loop for MyLaw in the calling program and
/// adds it to the registry under MyLaw::kName; a Material whose `law` is that name then
/// uses it. Call it before initialise() of a model that uses it. For results that are the
/// same bits for any thread count, compile the program as libdem is compiled (no implicit
/// FMA contraction: -ffp-contract=off with GCC and Clang).
#include <strata/dem/detail/law_entry.hpp>
#include <strata/dem/laws.hpp>

namespace strata::dem {

/// Adds Law to the registry; throws strata::Error (Input) when its name is taken.
template <PairLaw Law>
void register_law() {
  detail::add_law(detail::make_law_entry<Law>());
}

}  // namespace strata::dem
