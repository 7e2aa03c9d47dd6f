// Boundary conditions of the DEM: group specs resolved into per-particle records (fixed
// axes, prescribed velocity, step displacement, force histories), and driven particles
// (coupling). The conditions act in the step's update (strata/dem/detail/step_kernel.hpp);
// walls are applied there as well.
#include "model.hpp"

#include <strata/core/error.hpp>

#include <algorithm>

namespace strata::dem::detail {

std::array<double, 3> ForceHistory::at(double time) const {
  if (t.empty()) return {};
  std::array<double, 3> r{};
  if (time <= t.front()) {
    r = f.front();
  } else if (time >= t.back()) {
    r = f.back();
  } else {
    const auto it = std::upper_bound(t.begin(), t.end(), time);
    const std::size_t k = static_cast<std::size_t>(it - t.begin());
    const double w = ramp_weight((time - t[k - 1]) / (t[k] - t[k - 1]), ramp);
    for (int a = 0; a < 3; ++a) r[a] = (1 - w) * f[k - 1][a] + w * f[k][a];
  }
  if (radial) r[1] = r[2] = r[0];  // the magnitude, for every axis of load_dir
  return r;
}

// Resolves the group specs into per-particle records (later specs override earlier ones
// per axis).
template <int D>
void Model<D>::resolve_bcs() {
  std::vector<BcParticle> out;
  // the specs that apply to each set of groups, in the order they were given
  std::vector<std::vector<const BcSpec*>> specs_of(group_sets.size());
  for (std::size_t k = 0; k < group_sets.size(); ++k)
    for (const auto& s : bc_specs)
      if (std::binary_search(group_sets[k].begin(), group_sets[k].end(), s.group)) specs_of[k].push_back(&s);
  const std::size_t N = n();
  for (std::size_t p = 0; p < N; ++p) {
    flags[p] = 0;
    if (specs_of[grp[p]].empty()) continue;
    BcParticle b;
    b.index = static_cast<std::uint32_t>(p);
    for (const BcSpec* sp : specs_of[grp[p]]) {
      const BcSpec& s = *sp;
      if (s.kind == BcSpec::Force) {
        b.history = s.history;
        continue;
      }
      for (int a = 0; a < D; ++a) {
        if (!(s.axes & (1u << a))) continue;
        b.exchange &= std::uint8_t(~(1u << a));  // a later spec takes the axis over
        if (s.kind == BcSpec::Fix) {
          b.mode[a] = 1;
          b.value[a] = 0;
        } else if (s.kind == BcSpec::Velocity) {
          b.mode[a] = 2;
          b.value[a] = s.value[a];
          if (s.exchange) b.exchange |= std::uint8_t(1u << a);
        } else {
          b.mode[a] = 3;
          b.value[a] = s.value[a];
          b.every[a] = s.every;
        }
      }
    }
    // keep the trapezoid history of particles that already had a condition
    auto old = std::lower_bound(bcp.begin(), bcp.end(), b.index,
                                [](const BcParticle& q, std::uint32_t i) { return q.index < i; });
    if (old != bcp.end() && old->index == b.index) {
      std::copy(old->dx_prev, old->dx_prev + 3, b.dx_prev);
      std::copy(old->f_int, old->f_int + 3, b.f_int);
    }
    flags[p] = 1;
    out.push_back(b);
  }
  bcp = std::move(out);
  set_load_directions();
  bcs_dirty = false;
  v2_alarm = -1;  // the speed test between checks is set anew for these conditions
}

template <int D>
void Model<D>::set_load_directions() {
  for (BcParticle& b : bcp) {
    std::fill(b.load_dir, b.load_dir + 3, 1.0);
    if (b.history < 0 || !histories[static_cast<std::size_t>(b.history)].radial) continue;
    const ForceHistory& h = histories[static_cast<std::size_t>(b.history)];
    // the start position: x0, set by initialise() after it resolved the conditions a first
    // time (then the particle is still where it started) or loaded with a state
    std::array<double, 3> start{};
    for (int a = 0; a < D; ++a) start[a] = x0[a].empty() ? x[a][b.index] : x0[a][b.index];
    const auto dir = Simulation::radial_direction(start, h.centre, h.axis, D);
    std::copy(dir.begin(), dir.end(), b.load_dir);
  }
}

template <int D>
void Model<D>::set_kinematics(std::size_t ident, const std::array<double, 3>& u,
                              const std::array<double, 3>& vel) {
  STRATA_CHECK(initialised, Input, "set_kinematics: call initialise() first");
  if (bcs_dirty) resolve_bcs();
  const std::size_t i = index_of(ident, "set_kinematics");
  auto it = std::lower_bound(bcp.begin(), bcp.end(), static_cast<std::uint32_t>(i),
                             [](const BcParticle& q, std::uint32_t k) { return q.index < k; });
  STRATA_CHECK(it != bcp.end() && it->index == i, Input,
               "set_kinematics: particle {} is not driven (put it in a group passed to drive())", ident);
  for (int a = 0; a < D; ++a) {
    if (it->mode[a] != 2) continue;
    x[a][i] = x0[a][i] + u[a];
    v[a][i] = vel[a];
    it->value[a] = vel[a];
  }
  energy_valid = false;
}

template <int D>
void Model<D>::kinematics(std::size_t ident, std::array<double, 3>& u, std::array<double, 3>& vel) const {
  const std::size_t i = index_of(ident, "kinematics");
  u = {0, 0, 0};
  vel = {0, 0, 0};
  for (int a = 0; a < D; ++a) {
    u[a] = initialised ? x[a][i] - x0[a][i] : 0.0;
    vel[a] = v[a][i];
  }
}

#define STRATA_DEM_INSTANTIATE(D)                                                   \
  template void Model<D>::resolve_bcs();                                            \
  template void Model<D>::set_load_directions();                                    \
  template void Model<D>::set_kinematics(std::size_t, const std::array<double, 3>&, \
                                         const std::array<double, 3>&);             \
  template void Model<D>::kinematics(std::size_t, std::array<double, 3>&, std::array<double, 3>&) const;
STRATA_DEM_INSTANTIATE(2)
STRATA_DEM_INSTANTIATE(3)
#undef STRATA_DEM_INSTANTIATE

}  // namespace strata::dem::detail
