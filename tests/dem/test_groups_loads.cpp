// Groups beyond any fixed count, and radial loads: the force on each particle points away
// from the load's centre (in 3D: normal to a borehole's axis) and has the given magnitude.
#include "dem_test_util.hpp"

#include <strata/core/error.hpp>
#include <strata/core/state_io.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

// Every particle of a 12 × 12 block in a group of its own, every row in another, and the
// whole block in one more: 157 groups. Each keeps its members, in_groups and last_group
// see them, and boundary conditions on the 132nd group and on a row act on their particles.
TEST(DemGroups, AnyNumberOfGroupsKeepTheirMembers) {
  const preprocess::Lattice lat = preprocess::hex2d_rows(12, 12, kRockD, 0, 0, false);
  Simulation sim(2, Settings{.dt = 1e-9, .contact_detection = false});
  add_lattice(sim, lat, sim.add_material(rock_material(false)));
  const auto n = static_cast<std::uint32_t>(lat.size());
  std::vector<std::uint32_t> all(n);
  for (std::uint32_t i = 0; i < n; ++i) all[i] = i;
  sim.add_to_group(all, "block");
  for (std::uint32_t i = 0; i < n; ++i) sim.add_to_group({i}, "p" + std::to_string(i));
  std::vector<int> row_of(n);
  for (int r = 0; r < 12; ++r) {
    std::vector<std::uint32_t> row;
    const double y = lat.x[0][1] + r * kRockD * std::sqrt(3.0) / 2;
    for (std::uint32_t i = 0; i < n; ++i)
      if (std::abs(lat.x[i][1] - y) < 1e-9) row.push_back(i), row_of[i] = r;
    ASSERT_EQ(row.size(), 12u);
    sim.add_to_group(row, "row" + std::to_string(r));
  }
  EXPECT_EQ(sim.group_index("row11"), 1 + int(n) + 11);
  EXPECT_EQ(sim.group_members("block").size(), n);
  for (std::uint32_t i = 0; i < n; i += 13)
    EXPECT_EQ(sim.group_members("p" + std::to_string(i)), std::vector{i});
  EXPECT_EQ(sim.group_members("row3").size(), 12u);

  const std::uint32_t held = 130;  // its own group has index 131
  EXPECT_EQ(sim.group_index("p130"), 131);
  sim.fix("p" + std::to_string(held), kXY);
  sim.prescribe_velocity("row0", {0, -1.0, 0}, kY);
  sim.bond_touching_pairs();
  sim.initialise();
  sim.run(50);

  const auto ids = sim.ids();
  const auto last = sim.last_group();
  const auto in_row0_or_p5 = sim.in_groups({"row0", "p5"});
  const auto u = sim.displacements();
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const bool row0 = row_of[ids[i]] == 0;
    // the last-made group of a particle is its row (rows were made after the single ones)
    EXPECT_EQ(last[i], 1 + int(n) + row_of[ids[i]]);
    EXPECT_EQ(in_row0_or_p5[i], row0 || ids[i] == 5 ? 1 : 0);
    if (ids[i] == held) {
      EXPECT_EQ(std::hypot(u[i][0], u[i][1]), 0.0);
    }
    // x += v·dt each step with v held: exact up to one rounding of x (~1e-2 m, 2e-18 m) a step
    if (row0) {
      EXPECT_NEAR(u[i][1], -50 * sim.dt(), 51 * 2e-18);
    }
  }
  EXPECT_THROW(sim.group_members("nothing"), Error);
}

namespace {
// Particles far apart (no bonds, no contacts): after one step each moves with v = F·dt/m.
Simulation loose_particles(int dim, const std::vector<std::array<double, 3>>& at) {
  Simulation sim(dim, Settings{.dt = 1e-6, .contact_detection = false});
  const int mat = sim.add_material(rock_material(false));
  std::vector<std::uint32_t> ids;
  for (const auto& x : at) ids.push_back(static_cast<std::uint32_t>(sim.add_particle(x, 0.5e-3, mat, 1.0)));
  sim.add_to_group(ids, "rim");
  return sim;
}
}  // namespace

// A ring of 16 particles around (0.3, -0.2) with a radial load of magnitude F(t) rising
// linearly: each particle's velocity after a step is F(t0)·dt/m along its own outward
// unit vector (the force acts along the unit vector from the centre, exactly).
TEST(DemLoads, RadialLoadPushesEachParticleAwayFromTheCentre) {
  const double cx = 0.3, cy = -0.2, R = 0.05;
  std::vector<std::array<double, 3>> at;
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * std::numbers::pi * k / 16 + 0.1;
    at.push_back({cx + R * std::cos(a), cy + R * std::sin(a), 0});
  }
  Simulation sim = loose_particles(2, at);
  const double F = 250.0;  // N at t >= 1 s; 0 at t = 0
  sim.radial_force_history("rim", {0.0, 1.0}, {0.0, F}, {cx, cy, 0});
  sim.initialise();
  sim.set_dt(0.25);  // free particles: any step is stable
  sim.run(1);        // F(0) = 0: nothing moves
  sim.run(1);        // F(0.25) = 62.5 N
  const auto v = sim.velocities();
  const auto ids = sim.ids();
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const auto& x = at[ids[i]];
    const double ex = (x[0] - cx) / R, ey = (x[1] - cy) / R;
    const double expect = 0.25 * F * 0.25 / 1.0;  // F(0.25)·dt/m
    EXPECT_NEAR(v[i][0], expect * ex, 1e-12 * expect) << "particle " << ids[i];
    EXPECT_NEAR(v[i][1], expect * ey, 1e-12 * expect) << "particle " << ids[i];
  }
  // the applied forces did work: Σ F·v·dt over the second step
  EXPECT_GT(sim.external_work(), 0.0);
}

// 3D: with an axis, the push is normal to it (a borehole); without, radial from the point.
TEST(DemLoads, RadialLoadIn3DIsNormalToTheBoreholeAxis) {
  const std::array<double, 3> c{0.1, 0.2, 0.3}, axis{0, 1, 1};  // axis need not be unit
  std::vector<std::array<double, 3>> at = {
      {0.15, 0.2, 0.3}, {0.1, 0.25, 0.32}, {0.07, 0.18, 0.36}, {0.12, 0.1, 0.22}};
  for (const bool with_axis : {true, false}) {
    Simulation sim = loose_particles(3, at);
    sim.radial_force_history("rim", {0.0}, {10.0}, c, with_axis ? axis : std::array<double, 3>{});
    sim.initialise();
    sim.set_dt(0.5);
    sim.run(1);
    const auto v = sim.velocities();
    const auto ids = sim.ids();
    for (std::size_t i = 0; i < ids.size(); ++i) {
      std::array<double, 3> r{};
      for (int a = 0; a < 3; ++a) r[a] = at[ids[i]][a] - c[a];
      if (with_axis) {
        const double along = (r[1] + r[2]) / 2;  // r·axis / |axis|²
        r[1] -= along;
        r[2] -= along;
      }
      const double len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(v[i][a], 10.0 * 0.5 * r[a] / len, 1e-12) << i << " axis " << a;
      if (with_axis) {
        EXPECT_NEAR(v[i][1] + v[i][2], 0.0, 1e-12) << "no push along the axis";
      }
    }
  }
}

// A smooth ramp through forces [0, P, 0] at times [0, T/2, T] is the sin² pulse P·sin²(πt/T).
// A free particle of unit mass takes its impulse: at T/4 the velocity is P·T·(1/8 − 1/(4π))
// (a linear ramp would give P·T/16, 38 % more), and after the pulse P·T/2 (the leapfrog's
// sum of the force at the step times integrates a sin² period exactly).
TEST(DemLoads, SmoothRampIsTheSin2Pulse) {
  const double P = 40.0, T = 1.0;
  const int n = 4000;  // steps per pulse
  Simulation sim = loose_particles(2, {{0.0, 0.0, 0.0}});
  sim.force_history("rim", {0.0, T / 2, T}, {{0, 0, 0}, {P, 0, 0}, {0, 0, 0}}, strata::Ramp::Smooth);
  sim.initialise();
  sim.set_dt(T / n);
  sim.run(n / 4);
  const double quarter = P * T * (1.0 / 8 - 1.0 / (4 * std::numbers::pi));
  // the leapfrog's left sum of the rising force lags the integral by F(T/4)·dt/2, up to
  // F'(T/4)·dt²/12 = 6.5e-7 (Euler-Maclaurin)
  EXPECT_NEAR(sim.velocities()[0][0], quarter - (P / 2) * (T / n) / 2, 2e-6);
  sim.run(n - n / 4);
  EXPECT_NEAR(sim.velocities()[0][0], P * T / 2, 1e-12 * P * T);
  EXPECT_EQ(sim.velocities()[0][1], 0.0);
  // and the ramp is kept in a checkpoint (format 4)
  strata::MemoryState st;
  sim.save_state(st);
  EXPECT_EQ(st.get_scalar<std::int64_t>("dem/force_histories/0/ramp"), 1);
}
