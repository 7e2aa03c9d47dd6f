#pragma once
/// The one place in strata that knows about OpenMP threads (with parallel.cpp): kernels call
/// parallel_for and the reductions below instead of opening parallel regions themselves.
///
/// Every loop is statically scheduled and every reduction is summed in a fixed order over
/// fixed-size blocks, so results are bit-for-bit identical for any number of threads.
#include <strata/config.hpp>

#include <algorithm>
#include <cstddef>
#include <vector>

#if STRATA_WITH_OPENMP
#include <omp.h>
#if defined(__GLIBCXX__)
#include <parallel/algorithm>
#endif
#endif

namespace strata::par {

/// Number of threads parallel loops use.
int threads();
/// The most threads strata asks OpenMP for: far above any machine it runs on (oversubscribing
/// a machine gains nothing), and small enough that OpenMP can start them.
inline constexpr int kMaxThreads = 1024;
/// Sets the number of threads parallel loops use; n <= 0 means all hardware threads. Throws
/// strata::Error (Input) above kMaxThreads.
void set_threads(int n);
/// Hardware threads available.
int hardware_threads();

/// Calls f(i) for i in [0, n), statically split over the threads.
template <typename F>
void parallel_for(std::ptrdiff_t n, F&& f) {
#if STRATA_WITH_OPENMP
#pragma omp parallel for schedule(static) if (n > 256)
  for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
#else
  for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
#endif
}

/// Calls f(begin, end) once per thread on contiguous, statically assigned ranges of [0, n).
template <typename F>
void parallel_ranges(std::ptrdiff_t n, F&& f) {
#if STRATA_WITH_OPENMP
  if (n > 256) {
#pragma omp parallel
    {
      const std::ptrdiff_t nt = omp_get_num_threads(), t = omp_get_thread_num();
      const std::ptrdiff_t b = n * t / nt, e = n * (t + 1) / nt;
      if (b < e) f(b, e);
    }
    return;
  }
#endif
  if (n > 0) f(std::ptrdiff_t{0}, n);
}

/// Block size of deterministic reductions: partial sums are formed per block of this many
/// items and added in block order, whatever the thread count.
inline constexpr std::ptrdiff_t kReduceBlock = 4096;

/// Sum of f(i) over [0, n), bit-for-bit the same for any number of threads.
template <typename T, typename F>
T parallel_sum(std::ptrdiff_t n, F&& f) {
  const std::ptrdiff_t nb = (n + kReduceBlock - 1) / kReduceBlock;
  std::vector<T> partial(static_cast<std::size_t>(nb), T{});
  parallel_for(nb, [&](std::ptrdiff_t b) {
    T s{};
    const std::ptrdiff_t e = std::min(n, (b + 1) * kReduceBlock);
    for (std::ptrdiff_t i = b * kReduceBlock; i < e; ++i) s += f(i);
    partial[static_cast<std::size_t>(b)] = s;
  });
  T total{};
  for (const T& s : partial) total += s;
  return total;
}

/// Runs f(thread, team_size) once on each of `nthreads` threads of one team (f(0, 1) when
/// nthreads <= 1 or without OpenMP). The team may be smaller than asked for (OpenMP is
/// allowed to give fewer threads): f must check team_size and cope.
template <typename F>
void parallel_team(int nthreads, F&& f) {
#if STRATA_WITH_OPENMP
  if (nthreads > 1) {
#pragma omp parallel num_threads(nthreads)
    f(omp_get_thread_num(), omp_get_num_threads());
    return;
  }
#endif
  f(0, 1);
}

/// Pages in the storage [p, p + bytes) on all threads before its first write. A process's
/// first write to a page makes the kernel find and clear one (in a virtual machine the host
/// may back it first): on a large model that is most of the time of filling a fresh array,
/// and it runs at the speed of the one thread that writes. Linux's MADV_POPULATE_WRITE,
/// each thread over its share of the pages, and nothing where the kernel lacks it or for
/// less than 64 MiB (the first writes then page it in as before). The contents are
/// unchanged: fresh pages read as zeros either way.
void page_in(void* p, std::size_t bytes);

/// v.reserve(n), the new storage paged in on all threads (page_in): the resize or assign
/// that follows then writes memory that is already there.
template <class V>
void reserve_paged(V& v, std::size_t n) {
  if (n <= v.capacity()) return;
  v.reserve(n);
  page_in(v.data(), n * sizeof(typename V::value_type));
}

/// v.resize(n), the new storage paged in on all threads first (reserve_paged).
template <class V>
void resize_paged(V& v, std::size_t n) {
  reserve_paged(v, n);
  v.resize(n);
}

/// Sorts [first, last) by `less` on all threads (libstdc++'s parallel mode where strata is
/// built with OpenMP, std::sort otherwise). The order is the same for any thread count only
/// when `less` is a total order (no two items equivalent): sort by a key and a unique index.
template <typename It, typename Less>
void sort(It first, It last, Less less) {
#if STRATA_WITH_OPENMP && defined(__GLIBCXX__)
  __gnu_parallel::sort(first, last, less);
#else
  std::sort(first, last, less);
#endif
}

}  // namespace strata::par
