// Micro-benchmarks of the DEM kernels (Google Benchmark). The product-level benchmark is
// `strata bench dem` (apps/src/bench_dem.cpp).
#include <strata/core/parallel.hpp>
#include <strata/dem/laws.hpp>
#include <strata/dem/presets.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/lattice.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

using namespace strata;

namespace {
// The solid-lattice rock of Liu, Pollard & Shi (2013) for 1 mm disks.
dem::Material lattice_rock() { return dem::liu2013_rock(); }

// The solid-lattice law alone on a stream of intact pairs (the hot path of the step loop).
void BM_SolidLatticeLawIntact(benchmark::State& state) {
  const auto m = lattice_rock();
  const dem::SolidLatticeLaw law{m.kn, m.ks, m.friction, m.tensile_strength, m.shear_strength, false};
  const std::size_t n = 4096;
  std::vector<std::uint8_t> st(n, dem::pair_state::kIntact);
  std::vector<double> us(n, 0.0), un(n), dus(n);
  for (std::size_t i = 0; i < n; ++i) {
    un[i] = 1e-8 * std::sin(static_cast<double>(i));
    dus[i] = 1e-12 * std::cos(static_cast<double>(i));
  }
  double acc = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      us[i] += dus[i];  // the caller adds the increment (the step kernel's pair_force)
      const auto o = law.apply<1>(st[i], un[i], &us[i], &dus[i]);
      acc += o.fn + o.fs[0];
    }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
}
BENCHMARK(BM_SolidLatticeLawIntact);

// Whole steps of a bonded block (force + gather + update) per thread count.
void BM_Step(benchmark::State& state) {
  const int dim = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  par::set_threads(threads);
  const double d = 1e-3;
  const double side = preprocess::box_side_for(dim, 100000, d);
  const auto lat =
      dim == 2 ? preprocess::hex2d_box(0, 0, side, side, d)
               : preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0}, {side, side, side}, d);
  dem::Settings s;
  s.dt = 1e-15;
  dem::Simulation sim(dim, s);
  const int mat = sim.add_material(lattice_rock());
  for (const auto& p : lat.x) sim.add_particle(p, lat.radius, mat);
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(0.5 * sim.critical_dt());
  for (auto _ : state) sim.run(10);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * 10 * lat.size()));
  par::set_threads(0);
}
BENCHMARK(BM_Step)->Args({2, 1})->Args({2, 2})->Args({3, 1})->Args({3, 2})->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();
