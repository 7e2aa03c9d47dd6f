#pragma once
// Helpers shared by the DEM tests: C1 parameters and block builders.
#include <strata/core/error.hpp>
#include <strata/dem/presets.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/lattice.hpp>

#include <cmath>
#include <limits>

namespace strata::dem::test {

/// Micro-parameters of the rock of Liu, Pollard & Shi (2013).
inline Material c1_material(bool breakable = true) {
  Material m = liu2013_rock();
  if (!breakable) m.tensile_strength = m.shear_strength = std::numeric_limits<double>::infinity();
  return m;
}
inline constexpr double kC1d = 1e-3;
/// m = ρ·(√3/2)·d² (the hexagonal cell area times the density per unit thickness)
inline double c1_mass() { return 2.65e3 * std::sqrt(3.0) / 2 * kC1d * kC1d; }

/// Adds the lattice's sites to the simulation (ids = lattice indices).
inline void add_lattice(Simulation& sim, const preprocess::Lattice& lat, int mat) {
  sim.reserve(lat.size());
  for (const auto& p : lat.x) sim.add_particle(p, lat.radius, mat);
}

}  // namespace strata::dem::test
