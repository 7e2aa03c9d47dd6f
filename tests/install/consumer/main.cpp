// A program outside strata that links the installed libraries: it builds the 1033-disk
// solid-lattice specimen of Liu, Pollard & Shi (2013) and prints its critical time step
// (2·√(m/(6Kn+2Ks)) = 1.44e-7 s).
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/lattice.hpp>

#include <cstdio>

int main() {
  const auto lattice = strata::preprocess::hex2d_box(0, 0, 0.030, 0.0305, 0.001);
  strata::dem::Settings settings;
  settings.dt = 2e-8;
  strata::dem::Simulation sim(2, settings);
  const int rock = sim.add_material({2650.0, 6.587e10, 2.371e10, 0.239, 1.252e4, 3.690e4});
  for (const auto& x : lattice.x) sim.add_particle(x, lattice.radius, rock);
  sim.bond_touching_pairs();
  sim.initialise();
  std::printf("particles = %zu, dt_crit = %.4e\n", sim.particle_count(), sim.critical_dt());
  return 0;
}
