#pragma once
// Not API: the broken-bond form of the bond pass (bond_span with kBroken: a chunk holding a
// broken bond or a wide shear history) for every built-in law, named once for two uses:
// broken_spans.cpp compiles them, with the compiler's own choice of loads, and step.cpp
// declares them so that it does not compile them again under its own options.
//
// step.cpp compiles the step kernel without gather instructions, which makes the intact form
// faster (the stepping benchmarks 1.1-1.4x on the AMD EPYC of docs/performance.md); the
// broken form, whose geometry and friction law run as two loops, ran 10 % slower that way
// (the uniaxial-compression example after its peak). Either way the loads fetch the same
// values into the same lanes: the same bits.
#include <strata/dem/detail/bond_pass.hpp>
#include <strata/dem/laws.hpp>

#include <cstddef>

// X(D, Law, kEnergy, kRest, kShear) for every form of the broken-bond bond pass of Law.
#define STRATA_BROKEN_SPANS_REST(X, D, L, E, R) X(D, L, E, R, true) X(D, L, E, R, false)
#define STRATA_BROKEN_SPANS_ENERGY(X, D, L, E)           \
  STRATA_BROKEN_SPANS_REST(X, D, L, E, Rest::kRadiusSum) \
  STRATA_BROKEN_SPANS_REST(X, D, L, E, Rest::kUniform)   \
  STRATA_BROKEN_SPANS_REST(X, D, L, E, Rest::kPerBond)
#define STRATA_BROKEN_SPANS_DIM(X, D, L) \
  STRATA_BROKEN_SPANS_ENERGY(X, D, L, true) STRATA_BROKEN_SPANS_ENERGY(X, D, L, false)
#define STRATA_BROKEN_SPANS_OF(X, L) STRATA_BROKEN_SPANS_DIM(X, 2, L) STRATA_BROKEN_SPANS_DIM(X, 3, L)

// One row per law of BuiltinLaws (laws.hpp); broken_spans.cpp checks that the two agree.
#define STRATA_BROKEN_SPANS(X) STRATA_BROKEN_SPANS_OF(X, SolidLatticeLaw)

// The signature of one form, for an explicit instantiation (extern: its declaration).
#define STRATA_BROKEN_SPAN_SIGNATURE(D, L, E, R, S) \
  void bond_span<D, L, E, R, true, S>(const BondSpan&, const L&, double, double, std::size_t, std::size_t);
#define STRATA_DECLARE_BROKEN_SPAN(D, L, E, R, S) extern template STRATA_BROKEN_SPAN_SIGNATURE(D, L, E, R, S)
#define STRATA_DEFINE_BROKEN_SPAN(D, L, E, R, S) template STRATA_BROKEN_SPAN_SIGNATURE(D, L, E, R, S)

namespace strata::dem::detail {
STRATA_BROKEN_SPANS(STRATA_DECLARE_BROKEN_SPAN)
}  // namespace strata::dem::detail
