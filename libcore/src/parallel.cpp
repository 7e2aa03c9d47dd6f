#include "strata/core/parallel.hpp"

#include "strata/core/error.hpp"

#include <thread>

namespace strata::par {

int hardware_threads() {
#if STRATA_WITH_OPENMP
  return omp_get_num_procs();
#else
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
#endif
}

int threads() {
#if STRATA_WITH_OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

void set_threads(int n) {
  STRATA_CHECK(n <= kMaxThreads, Input, "threads = {}: at most {} (0: all {} hardware threads)", n,
               kMaxThreads, hardware_threads());
#if STRATA_WITH_OPENMP
  omp_set_num_threads(n > 0 ? n : hardware_threads());
#else
  (void)n;
#endif
}
}  // namespace strata::par
