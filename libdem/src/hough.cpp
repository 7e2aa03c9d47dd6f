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

double HoughLine::distance(const std::array<double, 2>& p) const {
  return p[0] * std::cos(theta) + p[1] * std::sin(theta) - rho;
}

bool ShearBand::holds(const std::array<double, 2>& p) const { return std::abs(line.distance(p)) <= reach; }

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

namespace {

// Full width at half maximum of the distances `s` (m) around 0: histogram bins of h over
// [-half_range, half_range], the highest bin within one spacing of 0, and the half-maximum
// crossings on either side interpolated linearly between bin centres.
double fwhm(const std::vector<double>& s, double h, double half_range, double spacing) {
  const int nb = 2 * static_cast<int>(std::ceil(half_range / h));
  std::vector<double> c(static_cast<std::size_t>(nb), 0.0);
  for (double d : s) {
    const int b = static_cast<int>(std::floor((d + 0.5 * nb * h) / h));
    if (b >= 0 && b < nb) c[static_cast<std::size_t>(b)] += 1;
  }
  auto centre = [&](int b) { return (b + 0.5) * h - 0.5 * nb * h; };
  int top = -1;
  for (int b = 0; b < nb; ++b)
    if (std::abs(centre(b)) <= spacing && (top < 0 || c[b] > c[top])) top = b;
  if (top < 0 || c[top] <= 0) return 0;
  const double half = 0.5 * c[top];
  auto crossing = [&](int step) {
    int b = top;
    while (b + step >= 0 && b + step < nb && c[b + step] >= half) b += step;
    const double next = (b + step >= 0 && b + step < nb) ? c[b + step] : 0.0;
    return centre(b) + step * h * (c[b] - half) / (c[b] - next);
  };
  return crossing(+1) - crossing(-1);
}

}  // namespace

void take_lines(std::vector<std::array<double, 2>> points, HoughOptions options, int rounds,
                std::size_t min_points, double min_fraction,
                const std::function<double(const HoughLine&, const std::vector<double>&)>& take) {
  options.lines = 1;
  double strongest = 0;
  std::vector<double> dist;
  for (int round = 0; round < rounds && points.size() >= min_points; ++round) {
    const auto lines = hough_lines(points, options);
    if (lines.empty()) break;
    const HoughLine& l = lines.front();
    if (round == 0) strongest = l.votes;
    if (l.votes < min_fraction * strongest) break;
    dist.clear();
    for (const auto& p : points) dist.push_back(l.distance(p));
    const double reach = take(l, dist);
    if (reach < 0) break;
    std::vector<std::array<double, 2>> rest;
    for (std::size_t k = 0; k < points.size(); ++k)
      if (std::abs(dist[k]) > reach) rest.push_back(points[k]);
    points.swap(rest);
  }
}

std::vector<ShearBand> conjugate_bands(const std::vector<std::array<double, 2>>& points, int axis,
                                       double spacing) {
  std::vector<ShearBand> out;
  if (points.size() < 2 || !(spacing > 0)) return out;
  HoughOptions o;
  o.rho_bin = spacing;
  // Each line's points (within one band width of it) are set aside before the next is sought,
  // so that lines through the same band at nearby angles are not counted again.
  bool found[2] = {false, false};  // leaning clockwise, counter-clockwise
  take_lines(points, o, 8, 2, 0.4, [&](const HoughLine& l, const std::vector<double>& dist) {
    const double width = fwhm(dist, 0.5 * spacing, 8 * spacing, spacing);
    // the line's direction against the loading axis's (90 degrees for y, 0 for x)
    double a = l.direction_deg() - (axis == 1 ? 90.0 : 0.0);
    if (a > 90) a -= 180;
    if (a <= -90) a += 180;
    const int side = a > 0 ? 1 : 0;
    if (std::abs(a) >= 10 && std::abs(a) <= 80 && !found[side]) {
      found[side] = true;
      ShearBand band;
      band.angle_deg = a;
      band.line = l;
      band.width = width;
      band.reach = 0.5 * std::max(width, spacing);
      for (double d : dist) band.breaks += std::abs(d) <= band.reach;
      out.push_back(band);
    }
    if (found[0] && found[1]) return -1.0;  // both bands: done
    return std::max(width, spacing);
  });
  return out;
}

}  // namespace strata::dem
