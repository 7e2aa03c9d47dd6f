// The broken-bond form of the bond pass for every built-in law (broken_spans.hpp), compiled
// with the compiler's own choice of loads, apart from the rest of the step kernel (step.cpp).
#include "broken_spans.hpp"

#include <type_traits>

namespace strata::dem::detail {

// The laws of STRATA_BROKEN_SPANS: a law added to BuiltinLaws gets its row there and here
// (a law without a batch form has no broken-bond form to compile: list it here only).
static_assert(std::is_same_v<BuiltinLaws, LawList<SolidLatticeLaw>>,
              "a law added to BuiltinLaws needs its row in STRATA_BROKEN_SPANS (broken_spans.hpp) and here");

STRATA_BROKEN_SPANS(STRATA_DEFINE_BROKEN_SPAN)

}  // namespace strata::dem::detail
