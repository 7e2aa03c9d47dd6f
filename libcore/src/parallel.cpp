#include "strata/core/parallel.hpp"

#include "strata/core/error.hpp"

#include <cstdint>
#include <thread>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

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

void page_in(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  constexpr std::size_t kLeast = std::size_t{64} << 20;
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  if (bytes < kLeast || page == 0 || threads() < 2) return;
  // whole pages inside the range: a page the range shares with other data is left alone
  const std::uintptr_t lo = (reinterpret_cast<std::uintptr_t>(p) + page - 1) / page * page;
  const std::uintptr_t hi = (reinterpret_cast<std::uintptr_t>(p) + bytes) / page * page;
  if (hi <= lo) return;
  const auto pages = static_cast<std::ptrdiff_t>((hi - lo) / page);
  parallel_ranges(pages, [&](std::ptrdiff_t b, std::ptrdiff_t e) {
    // a failure (an old kernel: EINVAL) leaves the pages to the first writes
    (void)madvise(reinterpret_cast<void*>(lo + static_cast<std::uintptr_t>(b) * page),
                  static_cast<std::size_t>(e - b) * page, MADV_POPULATE_WRITE);
  });
#else
  (void)p;
  (void)bytes;
#endif
}
}  // namespace strata::par
