// The bonds' shear histories in 32-bit steps (BondShear): what is held in 32 bits and what
// in double precision, and what the rounding costs over many steps.
#include "dem_test_util.hpp"

#include <strata/dem/detail/model_data.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;
namespace ps = strata::dem::pair_state;
using Shear2 = strata::dem::detail::BondShear<1>;
using Shear3 = strata::dem::detail::BondShear<3>;

TEST(BondShear, TheStepIsThePowerOfTwoThatSpansTwiceTheReach) {
  // 2^30 steps span between 2 and 4 times the reach: Fs0/Ks of the rock of Liu, Pollard &
  // Shi 2013 (1.556e-6 m) gives 2^-48 m = 3.55e-15 m.
  const Material m = rock_material();
  const double reach = m.shear_strength / m.ks;
  const double unit = Shear2::unit_for(reach);
  EXPECT_EQ(unit, std::ldexp(1.0, -48));
  EXPECT_GE(Shear2::kReach * unit, 2 * reach);
  EXPECT_LT(Shear2::kReach * unit, 4 * reach);
  EXPECT_EQ(Shear2::unit_for(1.0), std::ldexp(1.0, -29));  // 2 = 2^30 · 2^-29 exactly
}

TEST(BondShear, IntactBondsWithinTheReachIn32BitsTheOthersExactly) {
  const double unit = std::ldexp(1.0, -48);
  const double reach = Shear3::kReach * unit;
  const std::vector<double> u = {1.234567e-7,  -3.3e-9,     5e-16,         // intact, within
                                 1.1 * reach,  0,           0,             // intact, beyond
                                 2.5e-7,       -1e-6,       1e-20,         // broken
                                 -0.8 * reach, 0.5 * reach, 1.000001e-6};  // intact, |Us| within
  const std::vector<std::uint8_t> st = {ps::kIntact, ps::kIntact, ps::kBrokenShear | ps::kTouching,
                                        ps::kIntact};
  Shear3 h;
  h.take(u, st, unit);
  EXPECT_FALSE(Shear3::is_wide(h.q[0]));
  EXPECT_TRUE(Shear3::is_wide(h.q[3]));
  EXPECT_TRUE(Shear3::is_wide(h.q[6]));
  EXPECT_FALSE(Shear3::is_wide(h.q[9]));
  EXPECT_EQ(h.wide.size(), 6u);  // two wide bonds
  const std::vector<double> back = h.expanded();
  for (std::size_t k = 0; k < 4; ++k)
    for (int a = 0; a < 3; ++a) {
      const std::size_t i = k * 3 + a;
      if (k == 1 || k == 2)
        EXPECT_EQ(back[i], u[i]) << "a wide bond is held exactly";
      else
        EXPECT_LE(std::abs(back[i] - u[i]), 0.5 * unit) << "to the nearest step";
    }
  // values in steps come back exactly: a checkpoint reloads to the same bits
  Shear3 again;
  again.take(back, st, unit);
  EXPECT_EQ(again.expanded(), back);

  // a step: bond 0 leaves the reach (a wide entry at the step's end), bond 1 comes back into
  // it, bond 2 stays wide, bond 3 breaks (wide)
  h.fresh.resize(2);
  const std::uint32_t salt = Shear3::salt_of(7);
  const double beyond[3] = {0, -1.5 * reach, 0}, within[3] = {1e-7, 2e-7, 3e-7}, slip[3] = {1e-8, 0, 0},
               broke[3] = {4e-7, 0, -4e-7};
  h.store(0, 0, salt, true, beyond);
  h.store(0, 1, salt, true, within);
  h.store(1, 2, salt, false, slip);
  h.store(1, 3, salt, false, broke);
  EXPECT_FALSE(Shear3::is_wide(h.q[0])) << "its entry waits for the step's end";
  h.merge();
  EXPECT_TRUE(h.fresh[0].empty() && h.fresh[1].empty());
  double got[3];
  h.load(0, got);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(got[a], beyond[a]);
  h.load(1, got);
  EXPECT_FALSE(Shear3::is_wide(h.q[3]));
  for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(got[a] - within[a]), unit);
  h.load(2, got);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(got[a], slip[a]);
  h.load(3, got);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(got[a], broke[a]);
  // thread 0's new entries come before thread 1's, whatever the order of the stores
  EXPECT_LT(Shear3::index_of(h.q[0]), Shear3::index_of(h.q[9]));
}

TEST(BondShear, StochasticRoundingAddsNoDriftOverAMillionSteadySteps) {
  // A quasi-static run adds nearly the same increment every step: about 3e-13 m per step to
  // histories of up to 1.6e-6 m in the uniaxial test of 1 mm disks (84 steps of 2^-48 m).
  // Rounded to nearest, every step would make the same error (here 0.4 of a step, the
  // fraction of 84.4), 4e5 steps after 1e6 increments: 5e-3 of the history. Stochastic
  // rounding is unbiased; its error is a random walk of at most 1/2 step per increment:
  // a standard deviation of at most 500 steps after 1e6 increments. Allowed: 6 of them,
  // 3000 steps = 3.6e-5 of the history; the nearest rounding's drift is 133 times that.
  const double unit = std::ldexp(1.0, -48);
  const double inc = 84.4 * unit;
  const int steps = 1000000;
  Shear2 h;
  h.reset(1, unit);
  h.fresh.resize(1);
  double exact = 0, nearest = 0;
  for (int s = 0; s < steps; ++s) {
    double u;
    h.load(0, &u);
    u += inc;
    h.store(0, 0, Shear2::salt_of(s), true, &u);
    exact += inc;
    nearest = Shear2::nearest((nearest + inc) / unit) * unit;
  }
  double u;
  h.load(0, &u);
  const double err = std::abs(u - exact) / unit;
  const double drift = std::abs(nearest - exact) / unit;
  EXPECT_NEAR(drift, 0.4 * steps, 1.0) << "the nearest rounding's drift, for comparison";
  EXPECT_LT(err, 3000.0) << "stochastic rounding: " << err << " steps off after " << steps;
  RecordProperty("error_in_steps", std::to_string(err));
}
