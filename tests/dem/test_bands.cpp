// The conjugate shear bands found in break points: synthetic bands of known inclination and
// width, with and without scattered breaks around them.
#include <strata/dem/hough.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace strata::dem;

namespace {
constexpr double kSpacing = 1e-3;  // particle diameter (m)

// Points of a band through (cx, cy) inclined by `deg` to the y axis (counter-clockwise
// positive), spread uniformly across a full width `width`, over a length of 24 mm.
void add_band(std::vector<std::array<double, 2>>& pts, double cx, double cy, double deg, double width,
              int count, std::mt19937_64& rng) {
  const double a = deg * std::numbers::pi / 180;
  const double dx = -std::sin(a), dy = std::cos(a);  // along the band
  std::uniform_real_distribution<double> along(-0.012, 0.012), across(-0.5 * width, 0.5 * width);
  for (int k = 0; k < count; ++k) {
    const double s = along(rng), t = across(rng);
    pts.push_back({cx + s * dx + t * dy, cy + s * dy - t * dx});
  }
}

void add_scatter(std::vector<std::array<double, 2>>& pts, int count, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 0.03);
  for (int k = 0; k < count; ++k) pts.push_back({u(rng), u(rng)});
}

const ShearBand* leaning(const std::vector<ShearBand>& bands, int sign) {
  for (const auto& b : bands)
    if ((b.angle_deg > 0) == (sign > 0)) return &b;
  return nullptr;
}
}  // namespace

// Two bands, +35° and -25° to the loading axis y, 2 and 3 mm wide, among scattered breaks:
// both found to within the Hough transform's one-degree bins, widths to within one
// histogram bin (half a spacing).
TEST(ShearBands, ConjugatePairAmongScatteredBreaks) {
  std::mt19937_64 rng(7);
  std::vector<std::array<double, 2>> pts;
  add_band(pts, 0.012, 0.016, 35, 2e-3, 400, rng);
  add_band(pts, 0.018, 0.014, -25, 3e-3, 400, rng);
  add_scatter(pts, 150, rng);
  const auto bands = conjugate_bands(pts, 1, kSpacing);
  ASSERT_EQ(bands.size(), 2u);
  const ShearBand* pos = leaning(bands, +1);
  const ShearBand* neg = leaning(bands, -1);
  ASSERT_TRUE(pos && neg);
  EXPECT_NEAR(pos->angle_deg, 35, 1.0);
  EXPECT_NEAR(neg->angle_deg, -25, 1.0);
  EXPECT_NEAR(pos->width, 2e-3, 0.5 * kSpacing);
  EXPECT_NEAR(neg->width, 3e-3, 0.5 * kSpacing);
  // most of each band's points, few of the scatter, lie within half a width of its line
  EXPECT_GT(pos->breaks, 300u);
  EXPECT_LT(pos->breaks, 450u);
  // the line passes through the band's centre
  EXPECT_NEAR(pos->line.distance({0.012, 0.016}), 0.0, kSpacing);
  EXPECT_TRUE(pos->holds({0.012, 0.016}));
}

// The same pair loaded along x: the angles are measured from x, so they are the
// complements, with the signs of the directions they lean.
TEST(ShearBands, AnglesAreMeasuredFromTheLoadingAxis) {
  std::mt19937_64 rng(11);
  std::vector<std::array<double, 2>> pts;
  add_band(pts, 0.015, 0.015, 60, 1.5e-3, 300, rng);  // 60° from y is -30° from x
  const auto bands = conjugate_bands(pts, 0, kSpacing);
  ASSERT_EQ(bands.size(), 1u);
  EXPECT_NEAR(bands[0].angle_deg, -30, 1.0);
}

// Breaks along the loading axis (axial splitting) or across it are not shear bands.
TEST(ShearBands, SplittingAndPlatenParallelCracksAreNotBands) {
  std::mt19937_64 rng(3);
  std::vector<std::array<double, 2>> pts;
  add_band(pts, 0.015, 0.015, 0, 1e-3, 300, rng);
  add_band(pts, 0.015, 0.005, 90, 1e-3, 300, rng);
  EXPECT_TRUE(conjugate_bands(pts, 1, kSpacing).empty());
}
