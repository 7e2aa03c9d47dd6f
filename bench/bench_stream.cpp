// The machine's memory bandwidth, as the STREAM benchmark measures it (McCalpin 1995): the
// triad a[i] = b[i] + s·c[i] over three arrays, counted as 24 bytes per element (two reads and
// one write; the cache line the write allocates is not counted). Arrays of 2 MiB each stay in
// the caches; arrays of 256 MiB each stream from memory. `scripts/bench bandwidth` puts these
// rates beside the bytes a DEM step moves (strata bench dem: streamed_bytes_per_particle_step).
// The first write to fresh memory is measured too: it bounds how fast a large model's set-up
// fills the arrays it has just allocated.
//
//   bench_stream --benchmark_counters_tabular=true
#include "machine_bench.hpp"

#include <benchmark/benchmark.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace {

// Three arrays of `n` doubles, first touched by the threads that use them (the pages then
// lie in those threads' memory).
struct Arrays {
  std::unique_ptr<double[]> a, b, c;
  explicit Arrays(std::ptrdiff_t n, int threads) : a(new double[n]), b(new double[n]), c(new double[n]) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      a[i] = 0.0;
      b[i] = 1.0;
      c[i] = 2.0;
    }
  }
};

// state.range(0): bytes per array; state.range(1): threads.
void BM_Triad(benchmark::State& state) {
  const std::ptrdiff_t n = state.range(0) / static_cast<std::ptrdiff_t>(sizeof(double));
  const int threads = static_cast<int>(state.range(1));
  Arrays m(n, threads);
  double* __restrict a = m.a.get();
  const double* __restrict b = m.b.get();
  const double* __restrict c = m.c.get();
  const double s = 3.0;
  for (auto _ : state) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::ptrdiff_t i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    benchmark::ClobberMemory();
  }
  benchmark::DoNotOptimize(a[n / 2]);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * n * 24);
  state.counters["threads"] = threads;
  state.counters["array_MiB"] = static_cast<double>(state.range(0)) / (1 << 20);
}

// The first write to fresh memory: state.range(0) bytes mapped anew each iteration, one write
// per page on state.range(1) threads, then unmapped. At each first write the kernel finds a
// page and clears it (in a virtual machine the host may have to back it first). Bytes counted:
// the pages made.
void BM_FirstTouch(benchmark::State& state) {
  const auto bytes = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const auto page = static_cast<std::ptrdiff_t>(sysconf(_SC_PAGESIZE));
  const auto pages = static_cast<std::ptrdiff_t>(bytes) / page;
  for (auto _ : state) {
    void* m = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) {
      state.SkipWithError("mmap failed");
      break;
    }
    auto* p = static_cast<volatile char*>(m);
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::ptrdiff_t i = 0; i < pages; ++i) p[i * page] = 1;
    munmap(m, bytes);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * pages * page);
  state.counters["threads"] = threads;
}

}  // namespace

// 1 and 2 threads, then doubling up to every hardware thread.
int main(int argc, char** argv) {
  const std::vector<std::int64_t> threads = strata::bench::thread_counts();
  benchmark::RegisterBenchmark("BM_Triad", BM_Triad)
      ->ArgsProduct({{2 << 20, 256 << 20}, threads})
      ->ArgNames({"bytes", "threads"})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_FirstTouch", BM_FirstTouch)
      ->ArgsProduct({{std::int64_t{1} << 30}, threads})
      ->ArgNames({"bytes", "threads"})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  return strata::bench::run_registered(argc, argv);
}
