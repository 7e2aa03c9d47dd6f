#pragma once
/// Hough transform of 2D points: finds dominant straight lines, e.g. shear bands traced by
/// broken-bond midpoints (in uniaxial compression: two conjugate, X-shaped bands).
#include <array>
#include <vector>

namespace strata::dem {

/// A line x·cos(theta) + y·sin(theta) = rho.
struct HoughLine {
  double theta;  ///< angle of the line's normal, radians in [0, π)
  double rho;    ///< signed distance of the line from the origin (m)
  double votes;  ///< (weighted) number of points within half a rho bin of the line
  /// Direction of the line itself, degrees in [0, 180) measured from the +x axis.
  double direction_deg() const;
};

struct HoughOptions {
  int theta_bins = 180;            ///< bins over [0, π)
  double rho_bin = 0;              ///< rho bin width (m); 0: 1/100 of the points' extent
  int lines = 2;                   ///< number of lines to return
  double suppress_theta_deg = 15;  ///< non-maximum suppression window in angle (degrees)
  double suppress_rho = 0;         ///< and in rho (m); 0: 10 rho bins
};

/// The strongest lines through `points` (x, y), strongest first. Deterministic.
std::vector<HoughLine> hough_lines(const std::vector<std::array<double, 2>>& points,
                                   const HoughOptions& options = {});

}  // namespace strata::dem
