#pragma once
/// `strata bench dem`: throughput and memory of the DEM step loop on a lattice block under
/// slow uniaxial compression (the micro-parameters of Liu, Pollard & Shi 2013, breakable bonds,
/// contact search on).
#include <cstdint>
#include <string>

namespace strata::app {

struct BenchDemOptions {
  int dim = 2;                     ///< 2 (hex disks) or 3 (close-packed spheres)
  std::int64_t particles = 16611;  ///< about this many particles (a square/cubic block)
  std::int64_t steps = 1000;       ///< steps timed
  int threads = 0;                 ///< 0: all hardware threads
  std::string lattice = "hcp";     ///< 3D packing: "hcp" or "fcc"
  bool normal_only = false;        ///< ks = 0: central forces only, and no shear history kept
};

/// Builds the block (platens: top and bottom rows/layers, moving inward along y (2D) or z
/// (3D) at an axial strain rate of 1/s), runs the steps with dt = 0.5·dt_crit and returns one
/// JSON object: dim, lattice, side (m, of the square or cube the lattice fills), particles,
/// bonds, steps, threads, seconds (stepping only), particle_steps_per_s, bytes_per_particle
/// (peak RSS of the process minus the RSS before the model was built, per particle),
/// model_bytes_per_particle (Simulation::memory_bytes()/N), streamed_bytes_per_particle_step
/// (Simulation::streamed_bytes_per_step()/N) and the rate it implies (streamed_gb_per_s), dt,
/// dt_over_dt_crit, broken_bonds, contacts, setup_seconds and state_hash (Simulation::state_hash()
/// after the steps: the same for every thread count).
std::string bench_dem_json(const BenchDemOptions& options);

}  // namespace strata::app
