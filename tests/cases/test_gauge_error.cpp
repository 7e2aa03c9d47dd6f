// The gauge error of `strata compare`: max |u − u_ref| over the rows and columns of a run,
// the reference interpolated in time, over max |u_ref|.
#include <gtest/gtest.h>
#include <strata/cases/compare.hpp>

#include <cmath>
#include <limits>
#include <vector>

using strata::cases::gauge_error;
using Cols = std::vector<std::vector<double>>;

TEST(GaugeError, IdenticalHistoriesHaveNone) {
  const std::vector<double> t{0, 1, 2, 3};
  const Cols u{{0, 1, -2, 3}, {0, 0.5, 0.5, 0}};
  EXPECT_EQ(gauge_error(t, u, t, u), 0.0);
}

TEST(GaugeError, IsTheLargestDifferenceOverTheLargestReferenceValue) {
  const std::vector<double> t{0, 1, 2};
  const Cols ref{{0, 2, 4}, {0, -1, 1}};
  const Cols run{{0, 2.2, 4}, {0, -1, 0.5}};  // differences 0.2 and 0.5; largest |ref| = 4
  EXPECT_DOUBLE_EQ(gauge_error(t, ref, t, run), 0.5 / 4);
}

TEST(GaugeError, InterpolatesTheReferenceInTime) {
  // a linear reference sampled coarsely, a run of the same line sampled elsewhere: no error
  const std::vector<double> tr{0, 1, 2, 3};
  const Cols ref{{0, 3, 6, 9}};
  const std::vector<double> tu{0.25, 0.5, 1.75, 2.9};
  const Cols run{{0.75, 1.5, 5.25, 8.7}};
  EXPECT_NEAR(gauge_error(tr, ref, tu, run), 0.0, 1e-15);
}

TEST(GaugeError, RowsOutsideTheReferenceAreLeftOut) {
  const std::vector<double> tr{0, 1};
  const Cols ref{{0, 1}};
  const std::vector<double> tu{0.5, 2.0};  // t = 2 lies beyond the reference
  const Cols run{{0.5, 100}};
  EXPECT_EQ(gauge_error(tr, ref, tu, run), 0.0);
}

TEST(GaugeError, NonFiniteValuesAndAZeroReferenceThatDisagrees) {
  const std::vector<double> t{0, 1};
  EXPECT_TRUE(std::isinf(gauge_error(t, Cols{{0, 1}}, t, Cols{{0, std::nan("")}})));
  EXPECT_TRUE(std::isinf(gauge_error(t, Cols{{0, 0}}, t, Cols{{0, 1e-30}})));
  EXPECT_EQ(gauge_error(t, Cols{{0, 0}}, t, Cols{{0, 0}}), 0.0);
}
