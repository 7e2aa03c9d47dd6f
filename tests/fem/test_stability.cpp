#include <gtest/gtest.h>
#include <strata/fem/stability.hpp>

#include <cmath>
#include <vector>

using namespace strata::fem;

// Central difference on one undamped/damped oscillator: x'' + 2 xi w x' + w^2 x = 0.
// Integrate with dt just below and just above the predicted limit; the amplitude must stay
// bounded below it and grow above it. This checks the formula, not just its arithmetic.
static double amplitude_after(double w, double xi, double dt, int steps) {
  double x = 1.0, v = 0.0;
  double a = -w * w * x - 2 * xi * w * v;
  double vh = v + 0.5 * dt * a;  // half-step velocity (leapfrog form of central difference)
  double peak = 0;
  for (int n = 0; n < steps; ++n) {
    x += dt * vh;
    // damping on the half-step velocity keeps the scheme explicit (the form libdem uses)
    a = -w * w * x - 2 * xi * w * vh;
    vh += dt * a;
    peak = std::max(peak, std::abs(x));
  }
  return peak;
}

TEST(Stability, CentralDifferenceUndampedLimitIsTwoOverOmega) {
  const double w = 3.0;
  EXPECT_DOUBLE_EQ(central_difference_dt_crit(w), 2.0 / w);
  EXPECT_LT(amplitude_after(w, 0.0, 0.999 * 2.0 / w, 20000), 100.0);
  EXPECT_GT(amplitude_after(w, 0.0, 1.001 * 2.0 / w, 20000), 1e6);
}

TEST(Stability, NewmarkAverageAccelerationIsUnconditional) {
  EXPECT_TRUE(std::isinf(newmark_dt_crit(1e4, 0.25, 0.5)));
  // explicit predictor-corrector with lumped mass: beta = 0, gamma = 1/2 -> omega dt <= 2
  EXPECT_DOUBLE_EQ(newmark_dt_crit(2.0, 0.0, 0.5), 1.0);
}

TEST(Stability, DampingLowersTheLimit) {
  const double w = 2.0, xi = 0.3;
  const double dt = central_difference_dt_crit(w, xi);
  EXPECT_LT(dt, 2.0 / w);
  EXPECT_NEAR(dt, (2.0 / w) * (std::sqrt(1 + xi * xi) - xi), 1e-15);
}
