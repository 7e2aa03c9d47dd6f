// Force-included (-include) before every strata source compiled by GCC 12 or older on x86.
//
// GCC 12's AVX-512 intrinsics header initialises a variable from itself
// (`__m256d __Y = __Y;`, GCC bug 105593, fixed in GCC 13), and -Wmaybe-uninitialized (at -O2
// and above) or -Wuninitialized (at -O1) reports it once for every Eigen kernel that inlines
// one of those intrinsics: hundreds of warnings that point into the compiler's own header,
// never at strata's code. The intrinsics are read here, first, with those two warnings off;
// every later line of every source keeps them.
#pragma once
#if defined(__GNUC__) && !defined(__clang__) && (defined(__x86_64__) || defined(__i386__))
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif
