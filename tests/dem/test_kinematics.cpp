// Driven particles (the coupling interface): a driven particle takes the displacement and
// velocity it is given, moves with that velocity, and pulls its bonded neighbour along.
#include "dem_test_util.hpp"

#include <strata/core/error.hpp>

#include <gtest/gtest.h>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

TEST(DemKinematics, DrivenParticleFollowsGivenMotionAndLoadsItsBonds) {
  const preprocess::Lattice lat = preprocess::hex2d_rows(6, 6, kRockD);
  Simulation sim(2, Settings{.dt = 1e-9, .contact_detection = false});
  add_lattice(sim, lat, sim.add_material(rock_material(false)));
  sim.add_to_group({0}, "driven");
  sim.drive("driven", kXY);
  sim.bond_touching_pairs();
  sim.initialise();
  EXPECT_THROW(sim.set_kinematics(1, {0, 0, 0}, {0, 0, 0}), Error);  // not driven

  const double u0 = 1e-9, v0 = 0.5;  // m, m/s
  sim.set_kinematics(0, {u0, 0, 0}, {v0, 0, 0});
  std::array<double, 3> u{}, v{};
  sim.kinematics(0, u, v);
  // u is stored as a position x0 + u: exact to the rounding of coordinates ~1e-3 m (2e-19 m)
  const double ulp_x = 1e-18;
  EXPECT_NEAR(u[0], u0, ulp_x);
  EXPECT_EQ(v[0], v0);
  const int steps = 20;
  sim.run(steps);
  sim.kinematics(0, u, v);
  // leapfrog: x += v·dt per step with v held at v0; exact up to one rounding per step
  EXPECT_NEAR(u[0], u0 + steps * v0 * sim.dt(), (steps + 1) * ulp_x);
  EXPECT_EQ(u[1], 0.0);
  EXPECT_EQ(v[0], v0);
  // the neighbour at +x (id 1) has been pushed: it moves in +x
  std::array<double, 3> u1{}, v1{};
  sim.kinematics(1, u1, v1);
  EXPECT_GT(u1[0], 0.0);
  EXPECT_GT(v1[0], 0.0);
  // the driven particle's motion did positive work on the lattice
  EXPECT_GT(sim.external_work(), 0.0);
}
