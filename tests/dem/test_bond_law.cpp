// The solid-lattice law (Liu, Pollard & Shi 2013) on a single pair: thresholds, friction cap, separation.
#include "dem_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;
namespace ps = strata::dem::pair_state;

namespace {
SolidLatticeLaw rock_law(bool strengthen) {
  const Material m = rock_material();
  return {m.kn, m.ks, m.friction, m.tensile_strength, m.shear_strength, strengthen};
}

// One step of a pair as the step kernel takes it: the increment dus (here already in the
// tangent plane) added to the stored Us, then the law.
template <int NS>
PairOutcome<NS> advance(const SolidLatticeLaw& law, std::uint8_t& st, double un, double* us,
                        const double* dus) {
  for (int a = 0; a < NS; ++a) us[a] += dus[a];
  return law.apply<NS>(st, un, us, dus);
}
}  // namespace

TEST(BondLaw, TensionBreaksExactlyAtFnMax) {
  // Un at the threshold: Fn = Kn·Un = -Fn_max. At exactly -Fn_max the bond holds (the
  // criterion is Fn < -Fn_max); one ulp beyond it breaks. Exact comparisons: the law does
  // one multiplication.
  for (bool strengthen : {false, true}) {
    const SolidLatticeLaw law = rock_law(strengthen);
    std::uint8_t st = ps::kIntact;
    double us = 0, dus = 0;
    const double un_at = -law.fn_max / law.kn;
    auto o = advance<1>(law, st, un_at * (1 - 1e-12), &us, &dus);
    EXPECT_EQ(o.broke, 0);
    EXPECT_NEAR(o.fn, -law.fn_max, law.fn_max * 1e-11);
    o = advance<1>(law, st, un_at * (1 + 1e-12), &us, &dus);
    EXPECT_EQ(o.broke, 1);
    EXPECT_EQ(st & ps::kKindMask, ps::kBrokenTension);
    EXPECT_EQ(o.fn, 0.0);  // no tension after breaking
    EXPECT_EQ(o.fs[0], 0.0);
    EXPECT_TRUE(st & ps::kSeparated);
  }
}

TEST(BondLaw, ShearBreaksAtFs0PaperForm) {
  // default (paper) form: intact limit Fs0 regardless of Fn. Load Un so Fn = 1e5 N
  // (mu·Fn = 2.39e4 would matter for the other form), then shear in small increments.
  const SolidLatticeLaw law = rock_law(false);
  std::uint8_t st = ps::kIntact;
  double us = 0;
  const double un = 1e5 / law.kn;
  const double step = law.fs0 / law.ks / 1000;  // 1000 increments to the limit
  int breaks_at = -1;
  for (int k = 1; k <= 2000 && breaks_at < 0; ++k) {
    const auto o = advance<1>(law, st, un, &us, &step);
    if (o.broke) {
      breaks_at = k;
      EXPECT_EQ(o.broke, 2);
      EXPECT_EQ(st & ps::kKindMask, ps::kBrokenShear);
      // after breaking: Coulomb cap mu·Fn
      EXPECT_NEAR(std::abs(o.fs[0]), law.mu * o.fn, 1e-9 * law.mu * o.fn);
    }
  }
  // |Fs| = Ks·k·step > Fs0 first at k = 1001 (1000 reaches it exactly, to round-off)
  EXPECT_NEAR(breaks_at, 1001, 1);
}

TEST(BondLaw, ShearBreaksAtFs0PlusMuFnWhenFrictionStrengthens) {
  const SolidLatticeLaw law = rock_law(true);
  std::uint8_t st = ps::kIntact;
  double us = 0;
  const double fn = 1e5;
  const double un = fn / law.kn;
  const double limit = law.fs0 + law.mu * fn;
  const double step = limit / law.ks / 1000;
  int breaks_at = -1;
  for (int k = 1; k <= 2000 && breaks_at < 0; ++k)
    if (advance<1>(law, st, un, &us, &step).broke) breaks_at = k;
  EXPECT_NEAR(breaks_at, 1001, 1);
  // in tension the limit is Fs0 (max(Fn, 0))
  std::uint8_t st2 = ps::kIntact;
  double us2 = 0;
  const double un2 = -1e3 / law.kn;
  const double step2 = law.fs0 / law.ks / 1000;
  breaks_at = -1;
  for (int k = 1; k <= 2000 && breaks_at < 0; ++k)
    if (advance<1>(law, st2, un2, &us2, &step2).broke) breaks_at = k;
  EXPECT_NEAR(breaks_at, 1001, 1);
}

TEST(BondLaw, BrokenContactFrictionCapSeparationAndReclosing) {
  const SolidLatticeLaw law = rock_law(false);
  std::uint8_t st = ps::kBrokenShear | ps::kTouching;
  double us = 0;
  const double un = 2e-7, fn = law.kn * un;
  // shear far beyond the cap: Fs stays at mu·Fn (slip), sign kept
  double dus = 1e-6;
  auto o = advance<1>(law, st, un, &us, &dus);
  EXPECT_NEAR(o.fn, fn, 1e-9 * fn);
  EXPECT_NEAR(o.fs[0], law.mu * fn, 1e-12 * fn);
  dus = -3e-6;
  o = advance<1>(law, st, un, &us, &dus);
  EXPECT_NEAR(o.fs[0], -law.mu * fn, 1e-12 * fn);
  // small reverse increment below the cap: elastic unloading from the cap
  dus = 1e-8;
  o = advance<1>(law, st, un, &us, &dus);
  EXPECT_NEAR(o.fs[0], -law.mu * fn + law.ks * 1e-8, 1e-9 * fn);
  // separation: zero force, shear history cleared
  dus = 0;
  o = advance<1>(law, st, -1e-9, &us, &dus);
  EXPECT_EQ(o.fn, 0.0);
  EXPECT_EQ(o.fs[0], 0.0);
  EXPECT_EQ(us, 0.0);
  EXPECT_FALSE(st & ps::kTouching);
  EXPECT_TRUE(st & ps::kSeparated);
  // touching again: friction contact with Us restarting from 0, flagged "closed again"
  dus = 1e-9;
  o = advance<1>(law, st, un, &us, &dus);
  EXPECT_NEAR(o.fs[0], law.ks * 1e-9, 1e-12 * law.ks * 1e-9);
  EXPECT_TRUE(st & ps::kReclosed);
  EXPECT_EQ(st & ps::kKindMask, ps::kBrokenShear);
}

TEST(BondLaw, ThreeDimensionalShearVector) {
  // 3D: |Us| is what breaks; two orthogonal components reaching Fs0 together.
  const SolidLatticeLaw law = rock_law(false);
  std::uint8_t st = ps::kIntact;
  double us[3] = {0, 0, 0};
  const double c = law.fs0 / law.ks / std::sqrt(2.0) / 100;
  const double dus[3] = {c, c, 0};
  int breaks_at = -1;
  for (int k = 1; k <= 200 && breaks_at < 0; ++k)
    if (advance<3>(law, st, 1e-8, us, dus).broke) breaks_at = k;
  EXPECT_NEAR(breaks_at, 101, 1);
}

TEST(BondLaw, PairInSimulationBreaksInTensionAtPredictedStep) {
  // Two disks, the left fixed, the right pulled at constant velocity V: Un = -V·dt·k after
  // k steps, so the bond breaks at the first k with Kn·V·dt·k > Fn_max. Within one step.
  const Material m = rock_material();
  const double dt = 1e-8, V = 0.5;
  Simulation sim = pulled_pair(m, Settings{.dt = dt, .contact_detection = true}, V);
  sim.bond_touching_pairs();
  sim.initialise();
  // the bond's force at step k uses the position after k steps (x(k) = k·V·dt)
  const double k_pred = std::floor(m.tensile_strength / (m.kn * V * dt)) + 1;
  sim.run(static_cast<std::int64_t>(k_pred) + 5);
  ASSERT_EQ(sim.breaks().size(), 1u);
  EXPECT_EQ(sim.breaks()[0].mode, BreakMode::Tension);
  EXPECT_NEAR(static_cast<double>(sim.breaks()[0].step), k_pred, 1.0);
  // separated: the group force is zero
  const auto f = sim.group_force("right");
  EXPECT_EQ(f[0], 0.0);
  EXPECT_EQ(sim.bonds()[0].kind, PairKind::BrokenTension);
}
