// Thrust wedges: Dahlen's critical taper and the taper and faults of a shortened 2D model.
#include "strata/dem/wedge.hpp"

#include "strata/dem/hough.hpp"

#include <strata/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace strata::dem {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

/// The angle psi between the greatest compression and a boundary of friction angle phi_s in a
/// material of friction angle phi: ½·asin(sin phi_s / sin phi) − ½·phi_s (radians).
double psi(double phi_s, double phi) {
  return 0.5 * std::asin(std::sin(phi_s) / std::sin(phi)) - 0.5 * phi_s;
}

}  // namespace

CriticalTaper critical_taper(double internal_friction, double basal_friction) {
  STRATA_CHECK(basal_friction > 0 && basal_friction < internal_friction, Input,
               "critical taper: the basal friction {} must be above 0 and below the internal friction {} "
               "(a base as strong as the wedge gives no wedge)",
               basal_friction, internal_friction);
  const double phi = std::atan(internal_friction), phi_b = std::atan(basal_friction);
  const double psi_b = psi(phi_b, phi);
  // alpha + psi(alpha, phi) rises from 0 (alpha = 0) to phi + psi(phi, phi) = phi + pi/4 - phi/2
  // (alpha = phi), above psi_b: one root, by bisection.
  double lo = 0, hi = phi;
  for (int k = 0; k < 200 && hi - lo > 1e-15; ++k) {
    const double mid = 0.5 * (lo + hi);
    (mid + psi(mid, phi) < psi_b ? lo : hi) = mid;
  }
  CriticalTaper t;
  t.taper_deg = 0.5 * (lo + hi) * kDeg;
  t.psi_b_deg = psi_b * kDeg;
  const double coulomb = 45.0 - 0.5 * phi * kDeg;
  t.forethrust_dip_deg = coulomb - t.psi_b_deg;
  t.backthrust_dip_deg = coulomb + t.psi_b_deg;
  return t;
}

std::array<double, 2> frictions_from_dips(double forethrust_dip_deg, double backthrust_dip_deg) {
  const double phi = (90.0 - forethrust_dip_deg - backthrust_dip_deg) / kDeg;
  const double psi_b = 0.5 * (backthrust_dip_deg - forethrust_dip_deg) / kDeg;
  STRATA_CHECK(phi > 0 && phi < 0.5 * std::numbers::pi, Input,
               "fault dips {} and {} degrees imply no friction angle between 0 and 90 degrees",
               forethrust_dip_deg, backthrust_dip_deg);
  // psi_b = ½·asin(sin phi_b / sin phi) − ½·phi_b rises with phi_b from 0: bisection.
  double lo = 0, hi = phi;
  STRATA_CHECK(psi_b >= 0 && psi_b <= psi(phi, phi), Input,
               "fault dips {} and {} degrees imply no basal friction below the internal one",
               forethrust_dip_deg, backthrust_dip_deg);
  for (int k = 0; k < 200 && hi - lo > 1e-15; ++k) {
    const double mid = 0.5 * (lo + hi);
    (psi(mid, phi) < psi_b ? lo : hi) = mid;
  }
  return {std::tan(phi), std::tan(0.5 * (lo + hi))};
}

Wedge measure_wedge(const WedgeInput& in) {
  STRATA_CHECK(in.spacing > 0, Input, "measure_wedge: the spacing must be > 0");
  Wedge w;
  const int s = in.backstop_side >= 0 ? 1 : -1;
  // Surface profile: the highest top per bin, bins counted from the backstop towards the toe.
  const double bin = 2 * in.spacing;
  std::map<long, double> top;
  for (const auto& p : in.particles) {
    const long k = static_cast<long>(std::floor(s * (in.backstop_x - p[0]) / bin));
    if (k < 0) continue;
    auto [it, fresh] = top.try_emplace(k, p[1] + p[2]);
    if (!fresh) it->second = std::max(it->second, p[1] + p[2]);
  }
  if (top.empty()) return w;
  const double raised = in.initial_top + in.spacing;
  long toe = -1;
  int quiet = 0;
  for (const auto& [k, h] : top) {
    w.max_uplift = std::max(w.max_uplift, h - in.initial_top);
    if (h >= raised) {
      toe = k;
      quiet = 0;
    } else if (++quiet >= 5) {
      break;
    }
  }
  if (toe < 0) return w;
  w.toe_x = in.backstop_x - s * (toe + 1) * bin;
  w.width = std::abs(in.backstop_x - w.toe_x);
  // Least-squares line h(d) over the bins from the toe to one spacing short of the backstop,
  // d = distance from the backstop: the taper is its downward slope towards the toe.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& [k, h] : top) {
    if (k > toe) break;
    const double d = (k + 0.5) * bin;
    if (d < in.spacing) continue;
    sx += d, sy += h, sxx += d * d, sxy += d * h;
    ++w.profile_bins;
  }
  if (w.profile_bins >= 3) {
    const double n = static_cast<double>(w.profile_bins);
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    w.taper_deg = std::atan(-slope) * kDeg;
  }

  // Faults: Hough lines through the fault points over the wedge, one at a time.
  std::vector<std::array<double, 2>> left;
  for (const auto& b : in.fault_points) {
    const double d = s * (in.backstop_x - b[0]);
    if (d >= 0 && d <= w.width + 2 * in.spacing) left.push_back(b);
  }
  HoughOptions o;
  o.rho_bin = in.spacing;
  take_lines(std::move(left), o, 12, 10, 0.3, [&](const HoughLine& l, const std::vector<double>& dist) {
    const double reach = 2 * in.spacing;  // a fault zone's points are set aside
    // direction in [0, 180) from +x; dip from the horizontal
    const double a = l.direction_deg();
    const double dip = a <= 90 ? a : 180 - a;
    if (dip < 10 || dip > 80) return reach;
    Fault f;
    f.dip_deg = dip;
    for (double d : dist) f.points += std::abs(d) <= reach;
    // rising towards +x (a < 90) dips towards −x: a forethrust when the backstop is at −x
    f.forethrust = (a < 90) == (s < 0);
    // x where the line meets y = base: x·cos θ + base·sin θ = rho
    const double c = std::cos(l.theta);
    f.x_at_base = std::abs(c) > 1e-12 ? (l.rho - in.base * std::sin(l.theta)) / c : 0.0;
    w.faults.push_back(f);
    return reach;
  });
  return w;
}

}  // namespace strata::dem
