// Thrust wedges and shear strain: Dahlen's critical taper against its small-angle form and its
// limits, the taper and faults measured from synthetic wedges of known shape, and the shear
// strain of homogeneous and banded deformations of a lattice.
#include <gtest/gtest.h>
#include <strata/core/error.hpp>
#include <strata/dem/strain.hpp>
#include <strata/dem/wedge.hpp>

#include <cmath>
#include <numbers>
#include <random>

using namespace strata::dem;

namespace {
constexpr double kDeg = 180.0 / std::numbers::pi;
}

// For a small basal friction the wedge is thin: psi_0(alpha) = ½·asin(sin alpha / sin φ) − ½·alpha
// is alpha·(1/sin φ − 1)/2 to first order, so alpha = psi_b / (1 + (1/sin φ − 1)/2); at φ = 30°
// alpha = psi_b / 1.5. The fault dips add up to 90° − φ and differ by 2·psi_b.
TEST(CriticalTaper, ThinWedgeMatchesTheSmallAngleForm) {
  const double mu = std::tan(30 / kDeg);
  for (double mu_b : {0.05, 0.1, 0.2}) {
    const CriticalTaper t = critical_taper(mu, mu_b);
    const double phi_b = std::atan(mu_b);
    const double psi_b = 0.5 * std::asin(std::sin(phi_b) / 0.5) - 0.5 * phi_b;
    EXPECT_NEAR(t.psi_b_deg, psi_b * kDeg, 1e-12);
    // the neglected terms are third order in the angles: under 2 % of alpha here
    EXPECT_NEAR(t.taper_deg, psi_b * kDeg / 1.5, 0.02 * t.taper_deg) << "mu_b = " << mu_b;
    EXPECT_NEAR(t.forethrust_dip_deg + t.backthrust_dip_deg, 60.0, 1e-12);
    EXPECT_NEAR(t.backthrust_dip_deg - t.forethrust_dip_deg, 2 * t.psi_b_deg, 1e-12);
    EXPECT_LT(t.forethrust_dip_deg, t.backthrust_dip_deg);  // forethrusts are the gentler
  }
}

// A stronger base steepens the wedge, which stays below the angle of repose φ; a base as
// strong as the wedge, or without friction, has no critical taper.
TEST(CriticalTaper, StrongerBaseSteepensTheWedge) {
  double last = 0;
  for (double mu_b : {0.1, 0.2, 0.3, 0.4, 0.5, 0.59}) {
    const CriticalTaper t = critical_taper(0.6, mu_b);
    EXPECT_GT(t.taper_deg, last);
    EXPECT_LT(t.taper_deg, std::atan(0.6) * kDeg);
    last = t.taper_deg;
  }
  EXPECT_THROW(critical_taper(0.6, 0.6), strata::Error);
  EXPECT_THROW(critical_taper(0.6, 0.0), strata::Error);
}

TEST(CriticalTaper, DipsGiveBackTheirFrictions) {
  const CriticalTaper t = critical_taper(0.6, 0.3);
  const auto mu = frictions_from_dips(t.forethrust_dip_deg, t.backthrust_dip_deg);
  EXPECT_NEAR(mu[0], 0.6, 1e-9);
  EXPECT_NEAR(mu[1], 0.3, 1e-9);
  EXPECT_THROW(frictions_from_dips(50, 45), strata::Error);  // no friction angle above 0
}

// A synthetic wedge: disks of diameter 10 m filling a cover 200 m thick on a base at y = 0,
// raised near a backstop at x = 3000 m into a surface of slope 8° reaching 1500 m out, and
// shear breaks scattered along a forethrust dipping 25° towards the backstop and a
// backthrust dipping 45° away from it.
TEST(Wedge, MeasuresTaperToeAndFaultsOfASyntheticWedge) {
  WedgeInput in;
  in.spacing = 10;
  in.base = 0;
  in.initial_top = 200;
  in.backstop_x = 3000;
  in.backstop_side = 1;
  const double alpha = 8 / kDeg, width = 1500;
  for (double x = 5; x < 3000; x += 10) {
    const double d = 3000 - x;
    const double top = 200 + (d < width ? std::tan(alpha) * (width - d) : 0.0);
    for (double y = 5; y + 5 <= top; y += 10) in.particles.push_back({x, y, 5});
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> along(0, 1), across(-3, 3);
  auto fault = [&](double x0, double dip_deg, double length, int n) {
    const double c = std::cos(dip_deg / kDeg), s = std::sin(dip_deg / kDeg);
    for (int k = 0; k < n; ++k) {
      const double t = along(rng) * length;
      in.fault_points.push_back({x0 + t * c - s * across(rng), t * s + c * across(rng)});
    }
  };
  fault(2000, 180 - 25, 400, 300);  // up to the left from x = 2000: dips towards the backstop
  fault(2200, 45, 300, 200);        // up to the right from x = 2200: dips away from it
  for (int k = 0; k < 100; ++k)     // diffuse damage
    in.fault_points.push_back({1500 + 1500 * along(rng), 300 * along(rng)});

  const Wedge w = measure_wedge(in);
  EXPECT_NEAR(w.taper_deg, 8.0, 0.3);
  // the toe is where the surface stands one spacing above the start: spacing/tan(alpha) short
  // of the wedge's geometric tip; within two bins of 20 m
  EXPECT_NEAR(w.toe_x, 3000 - width + 10 / std::tan(alpha), 40);
  EXPECT_NEAR(w.max_uplift, std::tan(alpha) * width, 15);
  ASSERT_GE(w.faults.size(), 2u);
  const Fault* fore = nullptr;
  const Fault* back = nullptr;
  for (const auto& f : w.faults) {
    if (f.forethrust && !fore) fore = &f;
    if (!f.forethrust && !back) back = &f;
  }
  ASSERT_TRUE(fore && back);
  EXPECT_NEAR(fore->dip_deg, 25, 2);
  EXPECT_NEAR(fore->x_at_base, 2000, 30);
  EXPECT_NEAR(back->dip_deg, 45, 2);
  EXPECT_NEAR(back->x_at_base, 2200, 30);
}

// The same wedge mirrored (backstop on the left) measures the same.
TEST(Wedge, BackstopOnEitherSide) {
  WedgeInput in;
  in.spacing = 10;
  in.initial_top = 100;
  in.backstop_x = 0;
  in.backstop_side = -1;
  for (double x = 5; x < 2000; x += 10) {
    const double top = 100 + (x < 1000 ? std::tan(6 / kDeg) * (1000 - x) : 0.0);
    for (double y = 5; y + 5 <= top; y += 10) in.particles.push_back({x, y, 5});
  }
  const Wedge w = measure_wedge(in);
  EXPECT_NEAR(w.taper_deg, 6.0, 0.3);
  EXPECT_NEAR(w.toe_x, 1000 - 10 / std::tan(6 / kDeg), 40);
  EXPECT_TRUE(w.faults.empty());
}

// Shear strain of a lattice deformed homogeneously: simple shear by k gives
// ln(λ1/λ2) = asinh(k/2)·2 (the principal stretches of F = [[1, k], [0, 1]] are
// √(1 + k²/4) ± k/2), a rotation gives 0, and a pure shear by stretches a, 1/a gives 2·ln a.
TEST(ShearStrain, HomogeneousDeformationsOfALattice) {
  std::vector<std::array<double, 3>> start;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) start.push_back({i + 0.5 * (j % 2), j * std::sqrt(3.0) / 2, 0});
  auto map = [&](double f00, double f01, double f10, double f11) {
    std::vector<std::array<double, 3>> now;
    for (const auto& p : start) now.push_back({f00 * p[0] + f01 * p[1] + 3, f10 * p[0] + f11 * p[1] - 2, 0});
    return shear_strain_2d(start, now, 1.5);
  };
  const double k = 0.4;
  for (double g : map(1, k, 0, 1)) EXPECT_NEAR(g, 2 * std::asinh(k / 2), 1e-12);
  const double c = std::cos(0.7), s = std::sin(0.7);
  for (double g : map(c, -s, s, c)) EXPECT_NEAR(g, 0.0, 1e-12);
  for (double g : map(1.3, 0, 0, 1 / 1.3)) EXPECT_NEAR(g, 2 * std::log(1.3), 1e-12);
}

// A band of simple shear between rigid blocks: the strain is found in the band and not outside.
TEST(ShearStrain, LocalisesInAShearBand) {
  std::vector<std::array<double, 3>> start, now;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 30; ++j) {
      const double x = i + 0.5 * (j % 2), y = j * std::sqrt(3.0) / 2;
      start.push_back({x, y, 0});
      // y < 10: still; 10 <= y < 15: sheared by 0.5; above: moved rigidly by 2.5
      const double u = y < 10 ? 0.0 : y < 15 ? 0.5 * (y - 10) : 2.5;
      now.push_back({x + u, y, 0});
    }
  const auto g = shear_strain_2d(start, now, 1.5);
  for (std::size_t i = 0; i < start.size(); ++i) {
    const double y = start[i][1];
    if (y > 11.5 && y < 13.5) {
      EXPECT_NEAR(g[i], 2 * std::asinh(0.25), 1e-12) << y;
    }
    if (y < 8.5 || y > 16.5) {
      EXPECT_NEAR(g[i], 0.0, 1e-12) << y;
    }
  }
}
