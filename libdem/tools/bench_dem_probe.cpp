// Development driver of strata::app::bench_dem_json:
//   strata_bench_dem_probe [dim] [particles] [steps] [threads] [hcp|fcc]
#include "bench_dem.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>

int main(int argc, char** argv) {
  strata::app::BenchDemOptions o;
  if (argc > 1) o.dim = std::atoi(argv[1]);
  if (argc > 2) o.particles = std::atoll(argv[2]);
  if (argc > 3) o.steps = std::atoll(argv[3]);
  if (argc > 4) o.threads = std::atoi(argv[4]);
  if (argc > 5) o.lattice = argv[5];
  try {
    std::printf("%s\n", strata::app::bench_dem_json(o).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
