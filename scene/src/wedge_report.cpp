// The thrust-wedge section of summary.json: the cover's taper and faults measured by
// dem::measure_wedge against Coulomb wedge theory.
#include "wedge_report.hpp"

#include <strata/core/error.hpp>
#include <strata/dem/wedge.hpp>
#include <strata/scene/frames.hpp>

#include <algorithm>
#include <cmath>
#include <map>

namespace strata::scene {

using nlohmann::json;

json wedge_report(const dem::Simulation& sim, const std::string& group, const std::string& backstop,
                  const std::vector<double>& friction) {
  const auto in = sim.in_groups({group});
  const auto pos = sim.positions();
  const auto disp = sim.displacements();
  const auto rad = sim.radii();
  // where the particles started: after settling
  std::vector<std::array<double, 3>> start(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i)
    for (int a = 0; a < 3; ++a) start[i][a] = pos[i][a] - disp[i][a];
  dem::WedgeInput w;
  std::vector<double> radii;
  double mean_x = 0;
  std::map<long, double> start_top;  // highest start top per bin of five diameters
  w.base = INFINITY;
  for (std::size_t i = 0; i < pos.size(); ++i) {
    if (!in[i]) continue;
    w.particles.push_back({pos[i][0], pos[i][1], rad[i]});
    radii.push_back(rad[i]);
    mean_x += pos[i][0];
    w.base = std::min(w.base, start[i][1] - rad[i]);
  }
  STRATA_CHECK(!radii.empty(), Input, "the wedge group '{}' has no particles", group);
  mean_x /= double(radii.size());
  std::nth_element(radii.begin(), radii.begin() + long(radii.size() / 2), radii.end());
  w.spacing = 2 * radii[radii.size() / 2];
  for (std::size_t i = 0; i < pos.size(); ++i) {
    if (!in[i]) continue;
    const long k = long(std::floor(start[i][0] / (5 * w.spacing)));
    auto [it, fresh] = start_top.try_emplace(k, start[i][1] + rad[i]);
    if (!fresh) it->second = std::max(it->second, start[i][1] + rad[i]);
  }
  // the start top: the median of the bins' highest tops (a grain standing proud does not count)
  std::vector<double> tops;
  for (const auto& [k, h] : start_top) tops.push_back(h);
  std::nth_element(tops.begin(), tops.begin() + long(tops.size() / 2), tops.end());
  w.initial_top = tops[tops.size() / 2];
  if (!backstop.empty()) {
    // the backstop: the face of a group of particles (a piston driven along x) towards the cover
    const auto on = sim.in_groups({backstop});
    double lo = INFINITY, hi = -INFINITY, mean_b = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < pos.size(); ++i) {
      if (!on[i]) continue;
      lo = std::min(lo, pos[i][0] - rad[i]);
      hi = std::max(hi, pos[i][0] + rad[i]);
      mean_b += pos[i][0];
      ++n;
    }
    STRATA_CHECK(n > 0, Input, "the wedge backstop '{}' has no particles", backstop);
    w.backstop_side = mean_b / double(n) > mean_x ? 1 : -1;
    w.backstop_x = w.backstop_side > 0 ? lo : hi;
  } else {
    // the backstop: the wall that moves along x
    const auto walls = sim.walls();
    const dem::WallView* wall = nullptr;
    for (const auto& v : walls)
      if (v.velocity[0] != 0 && (!wall || std::abs(v.velocity[0]) > std::abs(wall->velocity[0]))) wall = &v;
    STRATA_CHECK(wall, Input,
                 "the wedge of '{}' needs a [[wall]] moving along x to shorten it, or a wedge_backstop group",
                 group);
    w.backstop_x = wall->point[0];
    w.backstop_side = wall->point[0] > mean_x ? 1 : -1;
  }
  // The faults are the cover's shear zones: its particles strained most since the start (the
  // top fifth, and at least gamma = 0.2, of those between the backstop and five thicknesses
  // out): in a granular cover bonds, if any are left, no longer trace them.
  const auto gamma = shear_strain_since_start(start, pos, rad, in);
  const double reach = 5 * (w.initial_top - w.base);
  std::vector<double> near;
  for (std::size_t i = 0; i < pos.size(); ++i)
    if (in[i] && w.backstop_side * (w.backstop_x - pos[i][0]) <= reach) near.push_back(gamma[i]);
  double threshold = 0.2;
  if (!near.empty()) {
    std::nth_element(near.begin(), near.begin() + long(near.size() * 4 / 5), near.end());
    threshold = std::max(threshold, near[near.size() * 4 / 5]);
  }
  for (std::size_t i = 0; i < pos.size(); ++i)
    if (in[i] && gamma[i] >= threshold) w.fault_points.push_back({pos[i][0], pos[i][1]});
  const dem::Wedge wedge = dem::measure_wedge(w);

  json j;
  j["group"] = group;
  j["spacing_m"] = w.spacing;
  j["initial_top_m"] = w.initial_top;
  j["backstop_x_m"] = w.backstop_x;
  j["toe_x_m"] = wedge.toe_x;
  j["width_m"] = wedge.width;
  j["max_uplift_m"] = wedge.max_uplift;
  j["taper_deg"] = wedge.taper_deg;
  j["profile_bins"] = wedge.profile_bins;
  j["fault_strain_threshold"] = threshold;
  j["fault_points"] = w.fault_points.size();
  j["faults"] = json::array();
  const dem::Fault* fore = nullptr;
  const dem::Fault* back = nullptr;
  for (const auto& f : wedge.faults) {
    j["faults"].push_back({{"kind", f.forethrust ? "forethrust" : "backthrust"},
                           {"dip_deg", f.dip_deg},
                           {"x_at_base_m", f.x_at_base},
                           {"points", f.points}});
    if (f.forethrust && !fore) fore = &f;
    if (!f.forethrust && !back) back = &f;
  }
  auto theory = [](const dem::CriticalTaper& t, double mu, double mu_b) {
    return json{{"internal_friction", mu},
                {"basal_friction", mu_b},
                {"taper_deg", t.taper_deg},
                {"forethrust_dip_deg", t.forethrust_dip_deg},
                {"backthrust_dip_deg", t.backthrust_dip_deg}};
  };
  if (friction.size() == 2)
    j["critical_taper"] = theory(dem::critical_taper(friction[0], friction[1]), friction[0], friction[1]);
  if (fore && back) {
    // the frictions the strongest fore- and backthrust imply, and their critical taper
    try {
      const auto mu = dem::frictions_from_dips(fore->dip_deg, back->dip_deg);
      if (mu[1] > 0 && mu[1] < mu[0])
        j["implied_by_faults"] = theory(dem::critical_taper(mu[0], mu[1]), mu[0], mu[1]);
    } catch (const Error&) {
      // dips that no pair of frictions explains: nothing implied
    }
  }
  return j;
}

}  // namespace strata::scene
