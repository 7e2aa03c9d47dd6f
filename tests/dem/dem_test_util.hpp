#pragma once
// Helpers shared by the DEM tests: the uniaxial-compression rock's parameters and block builders.
#include <strata/core/error.hpp>
#include <strata/dem/presets.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/lattice.hpp>

#include <cmath>
#include <limits>

namespace strata::dem::test {

/// Micro-parameters of the rock of Liu, Pollard & Shi (2013).
inline Material rock_material(bool breakable = true) {
  Material m = liu2013_rock();
  if (!breakable) m.tensile_strength = m.shear_strength = std::numeric_limits<double>::infinity();
  return m;
}
inline constexpr double kRockD = 1e-3;
/// m = ρ·(√3/2)·d² (the hexagonal cell area times the density per unit thickness)
inline double rock_mass() { return 2.65e3 * std::sqrt(3.0) / 2 * kRockD * kRockD; }

/// Adds the lattice's sites to the simulation (ids = lattice indices).
inline void add_lattice(Simulation& sim, const preprocess::Lattice& lat, int mat) {
  sim.reserve(lat.size());
  for (const auto& p : lat.x) sim.add_particle(p, lat.radius, mat);
}

/// The 1033-disk specimen of the uniaxial-compression example (35 rows of 30 and 29 disks of
/// 1 mm), bonded where disks touch; not initialised yet.
inline Simulation uniaxial_specimen(Settings settings) {
  const auto lat = preprocess::hex2d_box(0, 0, 0.030, 0.0305, kRockD);
  Simulation sim(2, settings);
  add_lattice(sim, lat, sim.add_material(rock_material()));
  sim.bond_touching_pairs();
  return sim;
}

/// Two 1 mm disks touching along x in material `m`: the left one (group "left") held, the
/// right one (group "right") moved away at speed v (m/s). Not bonded and not initialised yet.
inline Simulation pulled_pair(const Material& m, Settings settings, double v) {
  Simulation sim(2, settings);
  const int mat = sim.add_material(m);
  sim.add_particle({0, 0, 0}, 0.5e-3, mat);
  sim.add_particle({1e-3, 0, 0}, 0.5e-3, mat);
  sim.add_to_group({0}, "left");
  sim.add_to_group({1}, "right");
  sim.fix("left", kXY);
  sim.prescribe_velocity("right", {v, 0, 0}, kXY);
  return sim;
}

}  // namespace strata::dem::test
