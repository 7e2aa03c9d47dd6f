// Reduced uniaxial compression of the 1033-disk specimen (Li, Yin, Liu & Cai 2017): order of events, peak,
// stress drop, band angles.
#include "dem_test_util.hpp"

#include <strata/dem/hough.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

namespace {
struct Curve {
  std::vector<double> strain, stress;
  double peak = 0, peak_strain = 0, first_break_strain = -1, first_shear_strain = -1;
  BreakMode first_mode = BreakMode::Shear;
  std::vector<BreakEvent> breaks;
};

// The 1033-disk uniaxial-compression specimen between frictionless platens (top and bottom rows move along y
// at ±v, free along x), its micro-parameters and damping, dt = 0.5·dt_crit. The loading is
// faster than the paper's (v = 0.0125 m/s instead of 2.4e-4 m/s) but still quasi-static:
// the time to the peak is about 400 wave transits of the specimen.
Curve compress(bool strengthen, std::int64_t steps) {
  const auto lat = preprocess::hex2d_box(0, 0, 0.030, 0.0305, kRockD);
  Material m = rock_material();
  m.friction_strengthens_bonds = strengthen;
  Simulation sim(2, Settings{.dt = 1e-12, .damping = Settings::Damping::Viscous, .viscous_c = 1.16e3});
  add_lattice(sim, lat, sim.add_material(m));
  const auto top = preprocess::top_row(lat), bottom = preprocess::bottom_row(lat);
  const double height = lat.x[top[0]][1] - lat.x[bottom[0]][1];
  sim.add_to_group(top, "top");
  sim.add_to_group(bottom, "bottom");
  const double v = 0.0125;
  sim.prescribe_velocity("top", {0, -v, 0}, kY);
  sim.prescribe_velocity("bottom", {0, v, 0}, kY);
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(0.5 * sim.critical_dt());
  Curve c;
  for (std::int64_t k = 0; k < steps; k += 500) {
    sim.run(500);
    const double eps = 2 * v * sim.time() / height;
    const double sig = sim.group_force("top")[1] / 0.030;  // N/m: stress × thickness
    c.strain.push_back(eps);
    c.stress.push_back(sig);
    if (sig > c.peak) {
      c.peak = sig;
      c.peak_strain = eps;
    }
    if (c.first_break_strain < 0 && sim.broken_count() > 0) {
      c.first_break_strain = eps;
      c.first_mode = sim.breaks()[0].mode;
    }
    if (c.first_shear_strain < 0 && sim.broken_count(BreakMode::Shear) > 0) c.first_shear_strain = eps;
  }
  c.breaks = sim.breaks();
  return c;
}
}  // namespace

TEST(Uniaxial, C1TensileFirstThenPeakThenDropAndConjugateBands) {
  const Curve c = compress(false, 90000);
  std::printf(
      "first break at strain %.3e (mode %d), first shear %.3e, peak %.4e N/m at strain %.3e, final %.4e\n",
      c.first_break_strain, static_cast<int>(c.first_mode), c.first_shear_strain, c.peak, c.peak_strain,
      c.stress.back());
  // Elastic part: E·t from the first points within 5 % of the lattice value 9.236e10 N/m (the
  // dynamic loading and the discrete sampling cost a few per cent).
  EXPECT_NEAR(c.stress[3] / c.strain[3] / 9.236e10, 1.0, 0.05);
  // Tensile cracking first, near strain 7e-4 (published run) / 1.0e-3 (affine estimate).
  EXPECT_EQ(c.first_mode, BreakMode::Tension);
  EXPECT_GT(c.first_break_strain, 6e-4);
  EXPECT_LT(c.first_break_strain, 1.3e-3);
  // shear breaks come later, at failure
  EXPECT_GT(c.first_shear_strain, c.first_break_strain);
  // a peak, then a stress drop: at the end less than half the peak
  EXPECT_GT(c.peak_strain, 1.2e-3);
  EXPECT_LT(c.peak_strain, 4e-3);
  EXPECT_LT(c.stress.back(), 0.5 * c.peak);
  // Bands: Hough transform of the shear-break midpoints. Expect two dominant families of
  // lines inclined to the loading axis (y) by opposite angles of 15..50 degrees, equal
  // within 10 degrees. (In this perfect lattice the bands follow the lattice rows at ±30°,
  // and the two families collect the same number of votes: look at the strongest four.)
  std::vector<std::array<double, 2>> pts;
  for (const auto& b : c.breaks)
    if (b.mode == BreakMode::Shear) pts.push_back({b.position[0], b.position[1]});
  ASSERT_GT(pts.size(), 50u);
  HoughOptions ho;
  ho.lines = 4;
  ho.rho_bin = kRockD;
  ho.suppress_theta_deg = 20;
  const auto lines = hough_lines(pts, ho);
  ASSERT_GE(lines.size(), 2u);
  double pos = 0, neg = 0;  // strongest line leaning each way (angle from the y axis)
  for (const auto& l : lines) {
    if (l.votes < 0.8 * lines[0].votes) continue;
    const double a = l.direction_deg() - 90;
    std::printf("band: %.1f degrees from the loading axis, %.0f votes\n", a, l.votes);
    if (a > 0 && pos == 0) pos = a;
    if (a < 0 && neg == 0) neg = a;
  }
  EXPECT_GT(pos, 15.0);
  EXPECT_LT(pos, 50.0);
  EXPECT_LT(neg, -15.0);
  EXPECT_GT(neg, -50.0);
  EXPECT_NEAR(pos, -neg, 10.0);
}

TEST(Uniaxial, FrictionStrengthenedBondsPeakLater) {
  // With the intact shear limit Fs0 + μ·max(Fn, 0) the bonds of the compressed lattice are
  // stronger in shear: the peak must come at a larger strain than with the default Fs0
  // (measured: 1.8e-3 default vs 3.2e-3 strengthened; the paper reports 2.8e-3).
  const Curve a = compress(false, 90000), b = compress(true, 130000);
  std::printf("peak strain: default %.3e, friction-strengthened %.3e\n", a.peak_strain, b.peak_strain);
  EXPECT_GT(b.peak_strain, 1.3 * a.peak_strain);
  EXPECT_EQ(b.first_mode, BreakMode::Tension);
}
