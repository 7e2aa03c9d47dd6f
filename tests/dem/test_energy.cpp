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
  preprocess::Lattice lat = dim == 2 ? preprocess::hex2d_rows(20, 20, kRockD)
                                     : preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0},
                                                                    {8e-3, 8e-3, 8e-3}, kRockD);
  Simulation sim(dim, Settings{.dt = 1e-12, .contact_detection = false, .energy_check_every = 500});
  add_lattice(sim, lat, sim.add_material(rock_material(false)));
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
  const auto lat = preprocess::hex2d_rows(12, 12, kRockD);
  Simulation sim(
      2,
      Settings{.dt = 1e-12, .allow_unstable = true, .contact_detection = false, .energy_check_every = 100});
  add_lattice(sim, lat, sim.add_material(rock_material(false)));
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

namespace {
/// A bonded 2D block of breakable rock squeezed by its top row (0.05 m/s, bottom fixed), at
/// dt = factor·dt_crit with viscous damping of `c` (N·s/m). Returns the step at which the
/// run stopped with a Numerical error, or -1 when it ran `steps` steps.
std::int64_t squeezed_block_stops_at(double factor, double c, std::int64_t steps) {
  const auto lat = preprocess::hex2d_rows(16, 16, kRockD);
  Simulation sim(2, Settings{.dt = 1e-12,
                             .allow_unstable = true,
                             .damping = Settings::Damping::Viscous,
                             .viscous_c = c,
                             .contact_detection = true});
  add_lattice(sim, lat, sim.add_material(rock_material(true)));
  sim.add_to_group(preprocess::top_row(lat), "top");
  sim.add_to_group(preprocess::bottom_row(lat), "bottom");
  sim.prescribe_velocity("top", {0, -0.05, 0}, kY);
  sim.fix("bottom", kY);
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(factor * sim.critical_dt());
  try {
    sim.run(steps);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Numerical);
    EXPECT_LT(sim.last_good_step(), sim.step_count());
    return sim.step_count();
  }
  return -1;
}
}  // namespace

TEST(Energy, BlowUpUnderHeavyDampingIsCaughtWithinAFewSteps) {
  // At 2·dt_crit the fastest mode grows by |g| ≈ 14 per step (g + 1/g = 2 − (ω·dt)², ω·dt =
  // 4); with damping strong enough to calm the debris between two full checks, only the
  // speed test of every step sees it: the run must stop within a few steps, not complete.
  for (double c : {0.0, 100.0, 1000.0}) {
    const std::int64_t at = squeezed_block_stops_at(2.0, c, 5000);
    EXPECT_GT(at, 0) << "viscous_c = " << c << ": the run completed";
    EXPECT_LE(at, 12) << "viscous_c = " << c;
  }
  // the same block at 0.5·dt_crit runs to the end
  EXPECT_EQ(squeezed_block_stops_at(0.5, 1000.0, 500), -1);
}

TEST(Energy, SlightlyUnstableStepIsCaught) {
  // Just above the limit the fastest mode grows slowly (|g| ≈ 1.2 per step at ω·dt = 2.01)
  // from the platen's start: caught by the speed test or a full check within 100 steps.
  // (dt_crit keeps a 1 % margin on the Lanczos estimate of λmax, so 1.01·dt_crit is still
  // stable here; 1.02·dt_crit is not)
  const std::int64_t at = squeezed_block_stops_at(1.02, 0.0, 20000);
  EXPECT_GT(at, 0) << "the run completed at 1.02 dt_crit";
  EXPECT_LE(at, 100);  // measured: step 48
}

TEST(Energy, StiffWallLimitsTheCriticalStep) {
  // A penalty wall of stiffness k adds k·n nᵀ to a touching particle's stiffness, so
  // λmax grows by up to k/m: dt_crit <= 2/√(k/m). Stepping at the lattice's own limit with
  // such a wall pressed into the block would blow up; at the new limit it runs.
  const auto lat = preprocess::hex2d_rows(10, 10, kRockD);
  auto make = [&](double kwall) {
    auto sim = std::make_unique<Simulation>(2, Settings{.dt = 1e-12, .contact_detection = true});
    add_lattice(*sim, lat, sim->add_material(rock_material(false)));
    sim->bond_touching_pairs();
    if (kwall > 0) {
      double ymax = -1e9;
      for (const auto& x : lat.x) ymax = std::max(ymax, x[1]);
      sim->add_wall({0, ymax + 0.5 * kRockD - 1e-6, 0}, {0, -1, 0}, {0, -0.5, 0}, kwall);
    }
    sim->initialise();
    return sim;
  };
  const double kwall = 1e3 * 6.587e10;  // a thousand times the bonds' Kn
  const double plain = make(0)->critical_dt();
  auto walled = make(kwall);
  EXPECT_LE(walled->critical_dt(), 2 / std::sqrt(kwall / rock_mass()) * (1 + 1e-12));
  EXPECT_LT(walled->critical_dt(), 0.1 * plain);
  walled->set_dt(0.9 * walled->critical_dt());
  EXPECT_NO_THROW(walled->run(3000));
  EXPECT_THROW(walled->set_dt(0.9 * plain), Error);  // refused: above the limit the wall sets
}
