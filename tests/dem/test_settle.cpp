// The settling stage: a block settles under its own weight while its prescribed motions and
// walls wait, then starts its run from the settled state.
#include "dem_test_util.hpp"

#include <strata/core/error.hpp>
#include <strata/dem/lattice_elastic.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

namespace {

constexpr int kRows = 12, kColumns = 20;
constexpr double kG = 1e4;  // m/s²: a strong gravity, so that the settlement stands far above round-off

// A kRows × kColumns block of unbreakable uniaxial-compression rock on a frictionless base, its sides free:
// the bottom row ("base") is prescribed in y only, to rise at 1 mm/s once loading starts (until then it
// waits, held where it is), and a wall beside the block moves towards it.
Simulation settling_block() {
  const preprocess::Lattice lat = preprocess::hex2d_rows(kRows, kColumns, kRockD, 0, 0, false);
  Settings set{.dt = 2e-8, .damping = Settings::Damping::Local, .local_alpha = 0.7, .gravity = {0, -kG, 0}};
  set.contact_detection = false;
  Simulation sim(2, set);
  add_lattice(sim, lat, sim.add_material(rock_material(false)));
  double lo = lat.x[0][1], hi = lo;
  for (const auto& p : lat.x) lo = std::min(lo, p[1]), hi = std::max(hi, p[1]);
  std::vector<std::uint32_t> base, top;
  for (std::uint32_t i = 0; i < lat.size(); ++i) {
    if (lat.x[i][1] < lo + 0.25 * kRockD) base.push_back(i);
    if (lat.x[i][1] > hi - 0.25 * kRockD) top.push_back(i);
  }
  EXPECT_EQ(base.size(), std::size_t(kColumns));
  EXPECT_EQ(top.size(), std::size_t(kColumns));
  sim.add_to_group(base, "base");
  sim.add_to_group(top, "top");
  sim.prescribe_velocity("base", {0, 1e-3, 0}, kY);
  sim.add_wall({-2 * kRockD, 0, 0}, {1, 0, 0}, {1.0, 0, 0}, 6.5e10);
  sim.bond_touching_pairs();
  sim.initialise();
  return sim;
}

double mean_y(const Simulation& sim, const std::string& group) {
  const auto x = sim.positions();
  const auto ids = sim.ids();
  std::vector<double> by_id(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) by_id[ids[i]] = x[i][1];
  const auto members = sim.group_members(group);
  double s = 0;
  for (auto id : members) s += by_id[id];
  return s / double(members.size());
}

}  // namespace

// The settled block carries its weight on its base and has shortened as a column of its
// stiffness does; time, steps, displacements and work start from there, and what waited
// (the base's velocity, the wall) starts only then.
TEST(DemSettle, BlockSettlesUnderItsWeightThenTheRunStarts) {
  Simulation sim = settling_block();
  const double top0 = mean_y(sim, "top");
  const double wall0 = sim.walls()[0].point[0];
  sim.settle(20000);

  EXPECT_EQ(sim.step_count(), 0);
  EXPECT_EQ(sim.time(), 0.0);
  EXPECT_EQ(sim.external_work(), 0.0);
  for (const auto& u : sim.displacements()) EXPECT_EQ(u[0] * u[0] + u[1] * u[1], 0.0);
  EXPECT_EQ(sim.walls()[0].point[0], wall0);  // the wall waited

  // Statics: the bonds press on the base row with the weight of the rows above it (the base
  // row's own weight rests on its constraint): once settled, to 1e-6.
  const double m = rock_mass();
  const double weight = double(sim.particle_count() - kColumns) * m * kG;
  EXPECT_NEAR(sim.group_force("base")[1], -weight, 1e-6 * weight);

  // Shortening of the column: each row interface (spacing h = d√3/2) carries the weight of
  // the rows above it through a strip of width kColumns·d and modulus E·t of the hexagonal
  // lattice, so the top row comes down by m_row·g·h/(E·t·w) · R(R−1)/2. The free sides make
  // the block a little softer than the infinite lattice (2.6 % more settlement): 3 %.
  const Material mat = rock_material(false);
  const double et = hex_elastic(mat.kn, mat.ks).E;
  const double h = kRockD * std::sqrt(3.0) / 2;
  const double expected = kColumns * m * kG * h / (et * kColumns * kRockD) * kRows * (kRows - 1) / 2.0;
  const double settled = top0 - mean_y(sim, "top");
  EXPECT_NEAR(settled, expected, 0.03 * expected) << "settlement " << settled << " m";

  // Loading starts now: the base rises at its velocity, the wall moves at its own.
  const double base0 = mean_y(sim, "base");
  sim.run(100);
  EXPECT_NEAR(mean_y(sim, "base") - base0, 1e-3 * 100 * 2e-8, 1e-15);
  EXPECT_NEAR(sim.walls()[0].point[0] - wall0, 1.0 * 100 * 2e-8, 1e-15);
}

// Settling in several calls gives the state of one call of the same total, and settling
// after the first step is refused.
TEST(DemSettle, ChunksGiveTheSameStateAndSettlingComesFirst) {
  Simulation once = settling_block();
  once.settle(3000);
  Simulation chunks = settling_block();
  chunks.settle(1000);
  chunks.settle(1500);
  chunks.settle(500);
  EXPECT_EQ(once.state_hash(), chunks.state_hash());

  once.run(1);
  EXPECT_THROW(once.settle(10), Error);
}
