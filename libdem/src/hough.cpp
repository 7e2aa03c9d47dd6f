// Hough transform for straight features (shear bands) in 2D point sets.
#include "strata/dem/hough.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace strata::dem {

double HoughLine::direction_deg() const {
  double d = theta * 180.0 / std::numbers::pi + 90.0;
  while (d >= 180.0) d -= 180.0;
  return d;
}

std::vector<HoughLine> hough_lines(const std::vector<std::array<double, 2>>& points, const HoughOptions& o) {
  std::vector<HoughLine> out;
  if (points.empty() || o.theta_bins < 2) return out;
  double lo[2] = {points[0][0], points[0][1]}, hi[2] = {lo[0], lo[1]};
  for (const auto& p : points)
    for (int a = 0; a < 2; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  // centre the points so rho is measured from the middle of the cloud
  const double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
  const double rmax = 0.5 * std::hypot(hi[0] - lo[0], hi[1] - lo[1]) + 1e-300;
  const double rb = o.rho_bin > 0 ? o.rho_bin : std::max(2 * rmax / 100, 1e-300);
  const int nr = static_cast<int>(std::ceil(2 * rmax / rb)) + 1;
  const int nt = o.theta_bins;
  std::vector<double> acc(static_cast<std::size_t>(nt) * nr, 0.0);
  std::vector<double> ct(nt), st(nt);
  for (int t = 0; t < nt; ++t) {
    const double th = std::numbers::pi * t / nt;
    ct[t] = std::cos(th);
    st[t] = std::sin(th);
  }
  for (const auto& p : points) {
    const double x = p[0] - cx, y = p[1] - cy;
    for (int t = 0; t < nt; ++t) {
      const int r = static_cast<int>(std::floor((x * ct[t] + y * st[t] + rmax) / rb));
      if (r >= 0 && r < nr) acc[static_cast<std::size_t>(t) * nr + r] += 1.0;
    }
  }
  const int sup_t = std::max(1, static_cast<int>(std::lround(o.suppress_theta_deg / 180.0 * nt)));
  const int sup_r = o.suppress_rho > 0 ? std::max(1, static_cast<int>(std::lround(o.suppress_rho / rb))) : 10;
  for (int l = 0; l < o.lines; ++l) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < acc.size(); ++k)
      if (acc[k] > acc[best]) best = k;
    if (acc[best] <= 0) break;
    const int bt = static_cast<int>(best / nr), br = static_cast<int>(best % nr);
    const double th = std::numbers::pi * bt / nt;
    const double rho = (br + 0.5) * rb - rmax;
    // rho relative to the original origin
    out.push_back({th, rho + cx * std::cos(th) + cy * std::sin(th), acc[best]});
    // suppress the neighbourhood (theta wraps with rho -> -rho)
    for (int dt = -sup_t; dt <= sup_t; ++dt) {
      int t = bt + dt;
      bool flip = false;
      if (t < 0) {
        t += nt;
        flip = true;
      } else if (t >= nt) {
        t -= nt;
        flip = true;
      }
      const int rc = flip ? nr - 1 - br : br;
      for (int dr = -sup_r; dr <= sup_r; ++dr) {
        const int r = rc + dr;
        if (r >= 0 && r < nr) acc[static_cast<std::size_t>(t) * nr + r] = 0;
      }
    }
  }
  return out;
}

}  // namespace strata::dem
