// Throughput of lattice filling from a geometry file (large models from meshes, as in ECC4D:
// Zhao, Qiao, Zhang, Sun & Chen 2021).
//   strata_fill_bench FILE D [hex|hcp|fcc] [min_boundary_distance] [threads]
// prints one JSON object: particles, seconds (fill only), particles_per_s, read_seconds,
// elements, peak_rss_bytes.
#include <strata/core/parallel.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/mesh_fill.hpp>

#include <strata/core/clock.hpp>
#include <strata/core/memory.hpp>

#include <cstdio>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  using namespace strata::preprocess;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s FILE D [hex|hcp|fcc] [min_boundary_distance] [threads]\n", argv[0]);
    return 2;
  }
  const std::string kind = argc > 3 ? argv[3] : "hcp";
  FillOptions o;
  o.kind = kind == "hex" ? LatticeKind::Hex2D : kind == "fcc" ? LatticeKind::FCC : LatticeKind::HCP;
  o.d = std::stod(argv[2]);
  o.min_boundary_distance = argc > 4 ? std::stod(argv[4]) : 0.0;
  if (argc > 5) strata::par::set_threads(std::stoi(argv[5]));
  try {
    const auto t0 = strata::WallClock::now();
    const Geometry g = read_geometry(argv[1]);
    const GeometryRegion r = g.region("");
    const double read_s = strata::seconds_since(t0);
    const RegionFill f = fill_region(r, o);
    std::printf(
        "{\"particles\": %zu, \"seconds\": %.4f, \"particles_per_s\": %.4g, \"read_seconds\": %.3f, "
        "\"elements\": %zu, "
        "\"candidates\": %zu, \"exact_tests\": %zu, \"packing\": %.5f, \"threads\": %d, \"peak_rss_bytes\": "
        "%zu}\n",
        f.lattice.size(), f.stats.seconds, double(f.lattice.size()) / f.stats.seconds, read_s,
        f.stats.elements, f.stats.candidates, f.stats.exact_tests, f.packing, strata::par::threads(),
        strata::sys::peak_rss_bytes());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
