#pragma once
// What the machine benchmarks (bench_stream, bench_peak) share: the thread counts they run,
// and Google Benchmark's main once their benchmarks are registered.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <thread>
#include <vector>

namespace strata::bench {

/// 1 and 2 threads, then doubling up to every hardware thread (which is run too).
inline std::vector<std::int64_t> thread_counts() {
  std::vector<std::int64_t> threads{1, 2};
  const auto hw = static_cast<std::int64_t>(std::thread::hardware_concurrency());
  for (std::int64_t t = 4; t < hw; t *= 2) threads.push_back(t);
  if (hw > 2) threads.push_back(hw);
  return threads;
}

/// Runs the registered benchmarks with the command line's options.
inline int run_registered(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace strata::bench
