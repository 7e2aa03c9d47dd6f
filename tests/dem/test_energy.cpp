// Energy balance without damping: KE + stored energy - external work stays constant.
#include "dem_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

namespace {
struct Drift {
  double e0, max_rel;
};

// Block of unbreakable bonds; a smooth initial velocity field (a stretching mode plus a
// shear mode) excites the lattice; no damping, no contacts. Returns the largest deviation
// of KE + Eb - W from its value at the first probe, relative to that value.
Drift run_block(int dim, double dt_factor, bool with_platens, std::int64_t steps, std::int64_t chunk) {
  preprocess::Lattice lat =
      dim == 2 ? preprocess::hex2d_rows(20, 20, kC1d)
               : preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0}, {8e-3, 8e-3, 8e-3}, kC1d);
  Simulation sim(dim, Settings{.dt = 1e-12, .contact_detection = false, .energy_check_every = 500});
  add_lattice(sim, lat, sim.add_material(c1_material(false)));
  for (std::size_t i = 0; i < lat.size(); ++i) {
    const auto& p = lat.x[i];
    sim.set_velocity(i, {0.05 * std::sin(p[1] * 300.0), 0.03 * std::cos(p[0] * 200.0),
                         dim == 3 ? 0.02 * std::sin(p[0] * 250) : 0});
  }
  if (with_platens) {
    sim.add_to_group(preprocess::top_row(lat), "top");
    sim.add_to_group(preprocess::bottom_row(lat), "bottom");
    const unsigned ax = dim == 2 ? kY : kZ;
    std::array<double, 3> vt{0, 0, 0};
    vt[dim - 1] = -0.2;
    sim.prescribe_velocity("top", vt, ax);
    sim.fix("bottom", ax);
  }
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(dt_factor * sim.critical_dt());
  sim.run(2);  // from step 2 on, KE = ½m·v(n-½)·v(n+½) includes the platen's motion
  Drift d{sim.kinetic_energy() + sim.bond_energy() - sim.external_work(), 0};
  for (std::int64_t s = 1; s < steps; s += chunk) {
    sim.run(chunk);
    const double e = sim.kinetic_energy() + sim.bond_energy() - sim.external_work();
    d.max_rel = std::max(d.max_rel, std::abs(e - d.e0) / std::max(d.e0, sim.bond_energy()));
  }
  return d;
}
}  // namespace

TEST(Energy, ConservedWithoutDamping2D) {
  // Leapfrog is symplectic: the energy error oscillates at O((ω·dt)²) and does not drift.
  // The probe uses KE = ½m·v(n-½)·v(n+½), which is exact for a harmonic mode up to that
  // order; at dt = 0.2·dt_crit the smooth modes excited here have ω·dt << 0.4.
  // Tolerance 1e-3 (measured about 1e-5; the margin covers other compilers' round-off).
  const Drift d = run_block(2, 0.2, false, 20000, 250);
  EXPECT_GT(d.e0, 0);
  EXPECT_LT(d.max_rel, 1e-3);
}

TEST(Energy, ConservedWithoutDamping3D) {
  const Drift d = run_block(3, 0.2, false, 3000, 250);
  EXPECT_GT(d.e0, 0);
  EXPECT_LT(d.max_rel, 1e-3);
}

TEST(Energy, WorkOfMovingPlatenBalancesStoredEnergy) {
  // A platen pushing at constant velocity: the work it does (trapezoid rule on the
  // reaction) must equal the change in KE + stored energy. 1e-3 relative to the energy.
  const Drift d = run_block(2, 0.2, true, 20000, 250);
  EXPECT_LT(d.max_rel, 1e-3);
}

TEST(Energy, BlowUpIsDetected) {
  // dt = 1.5·dt_crit with allow_unstable: the highest mode grows; the energy check must
  // stop the run with a Numerical error naming the step.
  const auto lat = preprocess::hex2d_rows(12, 12, kC1d);
  Simulation sim(
      2,
      Settings{.dt = 1e-12, .allow_unstable = true, .contact_detection = false, .energy_check_every = 100});
  add_lattice(sim, lat, sim.add_material(c1_material(false)));
  for (std::size_t i = 0; i < lat.size(); ++i) sim.set_velocity(i, {1e-3 * ((i % 2) ? 1 : -1), 0, 0});
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(1.5 * sim.critical_dt());
  try {
    sim.run(100000);
    FAIL() << "no blow-up detected";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Numerical);
    EXPECT_NE(std::string(e.what()).find("blow-up at step"), std::string::npos) << e.what();
    EXPECT_LT(sim.last_good_step(), sim.step_count());
  }
}
