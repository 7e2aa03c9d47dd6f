// Bonds given as data (eccentric lattices, Zhao, Qiao, Zhang, Sun & Chen 2021): per-bond rest length and
// stiffness factor.
#include "dem_test_util.hpp"

#include <strata/preprocess/ecc.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

namespace {
preprocess::Lattice block(int dim) {
  return dim == 2
             ? preprocess::hex2d_rows(16, 16, kRockD)
             : preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0}, {6e-3, 6e-3, 6e-3}, kRockD);
}

void set_bonds(Simulation& sim, const preprocess::BondList& b) {
  std::vector<double> f(b.stiffness_factor.begin(), b.stiffness_factor.end());
  sim.set_bonds(b.i, b.j, f);
}
}  // namespace

// Rest lengths are the initial distances, so an eccentric lattice starts unloaded: no
// force, no motion, exactly, however large the offsets (Ra = 0.9).
TEST(EccBonds, EccentricLatticeStartsAtRest) {
  for (int dim : {2, 3}) {
    const auto ecc = preprocess::make_eccentric(
        block(dim),
        {.type = preprocess::Eccentricity::Sphere, .ra = 0.9, .rc = 0.5, .gamma = 0.001, .seed = 7});
    ASSERT_GT(ecc.bonds.weakened(), 0u);
    Simulation sim(dim, Settings{.dt = 1e-9, .contact_detection = false});
    add_lattice(sim, ecc.lattice, sim.add_material(rock_material(false)));
    set_bonds(sim, ecc.bonds);
    EXPECT_EQ(sim.bond_count(), ecc.bonds.size());
    sim.initialise();
    sim.set_dt(0.5 * sim.critical_dt());
    sim.run(200);
    EXPECT_EQ(sim.kinetic_energy(), 0.0) << dim << "D";
    EXPECT_EQ(sim.bond_energy(), 0.0) << dim << "D";
  }
}

// A stiffness factor f on every bond slows the dynamics by √f: with dt/√f and the same
// number of steps, the leapfrog trajectory is the same up to rounding (v scales by √f,
// forces by f). The critical step grows by 1/√f (Lanczos estimate, 1 % margin).
TEST(EccBonds, StiffnessFactorScalesTimeByItsSquareRoot) {
  for (int dim : {2, 3}) {
    const auto lat = block(dim);
    const auto bonds = preprocess::touching_pairs(lat);
    double base_dt = 0;  // 0.3 dt_crit of the first run
    auto run = [&](double factor, double dt_scale, double& dt_crit) {
      Simulation sim(dim, Settings{.dt = 1e-15, .contact_detection = false});
      add_lattice(sim, lat, sim.add_material(rock_material(false)));
      sim.set_bonds(bonds.i, bonds.j, std::vector<double>(bonds.size(), factor));
      sim.initialise();
      dt_crit = sim.critical_dt();
      if (base_dt == 0) base_dt = 0.3 * dt_crit;
      sim.set_dt(dt_scale * base_dt);
      // the same smooth velocity field, scaled by √factor
      const double s = std::sqrt(factor), vs = 0.05 * kRockD / (300 * base_dt);
      for (std::size_t i = 0; i < lat.size(); ++i) {
        const auto& p = lat.x[i];
        sim.set_velocity(i, {s * vs * std::sin(p[1] * 300.0), s * vs * 0.6 * std::cos(p[0] * 200.0),
                             dim == 3 ? s * vs * 0.4 * std::sin(p[0] * 250) : 0});
      }
      sim.run(300);
      return sim.displacements();
    };
    double dc1 = 0, dc4 = 0;
    const auto u1 = run(1.0, 1.0, dc1);
    const auto u4 = run(0.25, 2.0, dc4);
    EXPECT_NEAR(dc4 / dc1, 2.0, 0.02) << dim << "D";
    double umax = 0, diff = 0;
    for (std::size_t i = 0; i < u1.size(); ++i)
      for (int a = 0; a < 3; ++a) {
        umax = std::max(umax, std::abs(u1[i][a]));
        diff = std::max(diff, std::abs(u1[i][a] - u4[i][a]));
      }
    ASSERT_GT(umax, 1e-12);
    // rounding only: rest lengths are distances (not exactly 2r), factors 0.25 and 2 are exact
    EXPECT_LT(diff, 1e-9 * umax) << dim << "D";
  }
}

// Stiff bonds left among soft ones: an eccentric lattice (Type B, Ra = 0.3, Rc = 0.6, γ = 1e-3,
// a 10 mm HCP block) keeps a few short bonds at full stiffness inside a network weakened a
// thousandfold. Two particles moving apart along such a bond have λ = 2·kn/m by themselves, so
// the critical step is at most √(2m/kn) whatever the iteration finds (measured here: 4.48e-9 s
// against 5.51e-9 s), and a run at 0.9 of it holds every particle's oscillation without a
// blow-up. (The scene test SceneCriticalStep.StiffPairsInASoftNetworkBoundTheStep has a
// block where the iteration misses those pairs.)
TEST(EccBonds, StiffPairsInASoftNetworkSetTheStep) {
  const auto lat =
      preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0}, {1e-2, 1e-2, 1e-2}, kRockD);
  const auto ecc = preprocess::make_eccentric(
      lat, {.type = preprocess::Eccentricity::Sphere, .ra = 0.3, .rc = 0.6, .gamma = 0.001, .seed = 2});
  ASSERT_GT(ecc.bonds.weakened(), ecc.bonds.size() / 2);
  ASSERT_LT(ecc.bonds.weakened(), ecc.bonds.size());
  Simulation sim(3, Settings{.dt = 1e-15, .contact_detection = false});
  const double m = 1e-6;  // kg
  Material mat = rock_material(false);
  mat.ks = 0;
  const int id = sim.add_material(mat);
  for (const auto& p : ecc.lattice.x) sim.add_particle(p, ecc.lattice.radius, id, m);
  set_bonds(sim, ecc.bonds);
  sim.initialise();
  const double pair_limit = std::sqrt(2 * m / mat.kn);
  std::printf("dt_crit %.4g s, a stiff pair alone %.4g s; Lanczos %.4g, bound %.4g\n", sim.critical_dt(),
              pair_limit, sim.lambda_estimate(), sim.lambda_bound());
  EXPECT_LE(sim.critical_dt(), pair_limit * (1 + 1e-9));
  // every particle given a velocity of its own, then let go
  for (std::size_t i = 0; i < ecc.lattice.size(); ++i)
    sim.set_velocity(i, {1e-3 * std::sin(7.0 * double(i)), 1e-3 * std::cos(5.0 * double(i)),
                         1e-3 * std::sin(3.0 * double(i))});
  const double e0 = sim.kinetic_energy();
  sim.set_dt(0.9 * sim.critical_dt());
  EXPECT_NO_THROW(sim.run(500));
  EXPECT_LE(sim.kinetic_energy() + sim.bond_energy(), 1.0001 * e0);  // no damping: energy kept
}

TEST(EccBonds, BadBondListsAreRefused) {
  const auto lat = block(2);
  Simulation sim(2, Settings{.dt = 1e-9});
  add_lattice(sim, lat, sim.add_material(rock_material(false)));
  EXPECT_THROW(sim.set_bonds({0, 1}, {1}), Error);          // counts differ
  EXPECT_THROW(sim.set_bonds({0}, {0}), Error);             // self bond
  EXPECT_THROW(sim.set_bonds({0}, {1}, {1.5}), Error);      // factor > 1
  EXPECT_THROW(sim.set_bonds({0}, {1}, {}, {0.0}), Error);  // strength factor not > 0
  EXPECT_THROW(sim.set_bonds({0, 1}, {1, 0}), Error);       // the same bond twice
  EXPECT_THROW(sim.set_bonds({0}, {99999}), Error);         // no such particle
}

// A strength factor s on a bond scales its tensile strength: two disks pulled apart at a
// constant speed break apart when the bond's tension Kn·δ first exceeds s·Fn_max, i.e. at
// the stretch s·Fn_max/Kn (to within one step of stretch), for s below and above 1.
TEST(EccBonds, StrengthFactorScalesTheBreakingStretch) {
  const Material m = rock_material(true);
  for (const double s : {0.4, 1.0, 1.7}) {
    const double v = 0.05;  // m/s: 5e-11 m of stretch per step
    Simulation sim = pulled_pair(m, Settings{.dt = 1e-9, .contact_detection = false}, v);
    sim.set_bonds({0}, {1}, {}, {s});
    sim.initialise();
    const double stretch = s * m.tensile_strength / m.kn;
    std::int64_t steps = 0;
    while (sim.broken_count() == 0 && steps < 100000) sim.run(1), ++steps;
    ASSERT_EQ(sim.broken_count(dem::BreakMode::Tension), 1u) << "s = " << s;
    EXPECT_NEAR(double(steps) * v * sim.dt(), stretch, 2 * v * sim.dt()) << "s = " << s;
  }
}
