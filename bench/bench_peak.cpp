// The machine's arithmetic peak, as the DEM step kernel can use it: double-precision
// multiplies and adds in the widest vectors the build targets (512 bits with AVX-512, else
// 256), kept apart as libdem keeps them (this file is compiled with the step kernel's
// options: no fused multiply-add), and the square roots and divisions of a bond's length
// and normal, which run on a unit of their own. Independent chains in registers, so that
// the pipes, not the latencies, set the rate. `scripts/bench peak` runs it beside the
// instruction mix of the bond pass.
//
//   bench_peak --benchmark_counters_tabular=true
#include "machine_bench.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

#if defined(__AVX512F__)
constexpr int kLanes = 8;
#else
constexpr int kLanes = 4;
#endif
using Vec = double __attribute__((vector_size(kLanes * sizeof(double))));
// Twelve chains: enough to cover a multiply's and an add's latency on two pipes each, and
// with the two constants still within the 16 registers of AVX2.
constexpr int kChains = 12;
constexpr std::int64_t kRounds = 1 << 16;

Vec splat(double x) {
  Vec v;
  for (int l = 0; l < kLanes; ++l) v[l] = x;
  return v;
}

double sum_of(const Vec* acc) {
  double s = 0;
  for (int c = 0; c < kChains; ++c)
    for (int l = 0; l < kLanes; ++l) s += acc[c][l];
  return s;
}

// x <- x·m + a in every lane of every chain: two flops per lane and round, converging on
// a/(1-m) = 2 (no overflow, no subnormals).
double mul_add_rounds() {
  Vec acc[kChains];
  for (int c = 0; c < kChains; ++c) acc[c] = splat(1.0 + 0.01 * c);
  const Vec m = splat(0.5), a = splat(1.0);
  for (std::int64_t r = 0; r < kRounds; ++r)
    for (int c = 0; c < kChains; ++c) acc[c] = acc[c] * m + a;
  return sum_of(acc);
}

// x <- k / sqrt(x): one square root and one division per lane and round, as a bond's length
// and its inverse; converging on k^(2/3) = 2^(2/3), a value with a full mantissa.
double sqrt_div_rounds() {
  Vec acc[kChains];
  for (int c = 0; c < kChains; ++c) acc[c] = splat(1.0 + 0.01 * c);
  const Vec k = splat(2.0);
  for (std::int64_t r = 0; r < kRounds; ++r)
    for (int c = 0; c < kChains; ++c) {
      Vec s;
      for (int l = 0; l < kLanes; ++l) s[l] = std::sqrt(acc[c][l]);
      acc[c] = k / s;
    }
  return sum_of(acc);
}

// state.range(0): threads, each running its own chains. Counters: lane_rounds, the rounds
// of one lane per second (for BM_SqrtDiv: pairs of a square root and a division); flops,
// two per lane and round.
template <double (*Kernel)()>
void run(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    double sink = 0;
#pragma omp parallel num_threads(threads) reduction(+ : sink)
    sink += Kernel();
    benchmark::DoNotOptimize(sink);
  }
  const double rounds =
      static_cast<double>(threads) * kRounds * kChains * kLanes * static_cast<double>(state.iterations());
  state.counters["lane_rounds"] = benchmark::Counter(rounds, benchmark::Counter::kIsRate);
  state.counters["flops"] = benchmark::Counter(2 * rounds, benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
  state.counters["lanes"] = kLanes;
}

void BM_MulAdd(benchmark::State& state) { run<mul_add_rounds>(state); }
void BM_SqrtDiv(benchmark::State& state) { run<sqrt_div_rounds>(state); }

}  // namespace

// 1 and 2 threads, then doubling up to every hardware thread.
int main(int argc, char** argv) {
  const std::vector<std::int64_t> threads = strata::bench::thread_counts();
  for (auto* b : {benchmark::RegisterBenchmark("BM_MulAdd", BM_MulAdd),
                  benchmark::RegisterBenchmark("BM_SqrtDiv", BM_SqrtDiv)})
    b->ArgsProduct({threads})->ArgNames({"threads"})->UseRealTime()->Unit(benchmark::kMillisecond);
  return strata::bench::run_registered(argc, argv);
}
