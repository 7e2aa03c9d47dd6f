// Simulation: the run-time-dimension front end of the DEM; forwards to Model<D>.
#include "strata/dem/simulation.hpp"

#include "model.hpp"

#include <strata/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace strata::dem {

Simulation::Simulation(int dim, Settings settings) {
  STRATA_CHECK(dim == 2 || dim == 3, Input, "DEM dimension {} must be 2 or 3", dim);
  m_ = dim == 2 ? detail::make_model<2>(settings) : detail::make_model<3>(settings);
}
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

int Simulation::dim() const { return m_->dim(); }
const Settings& Simulation::settings() const { return m_->settings; }

int Simulation::add_material(const Material& m) {
  STRATA_CHECK(m.density > 0, Input, "material density = {} must be > 0", m.density);
  STRATA_CHECK(m.kn > 0, Input, "material kn = {} must be > 0 (N/m)", m.kn);
  STRATA_CHECK(m.ks >= 0, Input, "material ks = {} must be >= 0 (N/m)", m.ks);
  STRATA_CHECK(m.friction >= 0, Input, "material friction = {} must be >= 0", m.friction);
  STRATA_CHECK(m.tensile_strength >= 0, Input, "tensile_strength = {} must be >= 0 (N)", m.tensile_strength);
  STRATA_CHECK(m.shear_strength >= 0, Input, "shear_strength = {} must be >= 0 (N)", m.shear_strength);
  if (!detail::find_law(m.law)) {
    std::string known;
    for (const LawInfo& l : available_laws()) known += (known.empty() ? "" : ", ") + std::string(l.name);
    fail(ErrorKind::Input, "material law '{}' is not a known pair law (known: {})", m.law, known);
  }
  STRATA_CHECK(m_->materials.empty() || m_->materials[0].law == m.law, Input,
               "material law '{}': this model's materials use '{}' (one law per model)", m.law,
               m_->materials[0].law);
  m_->materials.push_back(m);
  return static_cast<int>(m_->materials.size()) - 1;
}
void Simulation::reserve(std::size_t n) { m_->reserve(n); }
std::size_t Simulation::add_particle(std::array<double, 3> x, double radius, int material, double mass) {
  return m_->add_particle(x, radius, material, mass);
}
std::size_t Simulation::add_particles(const std::vector<std::array<double, 3>>& x, double radius,
                                      int material, double mass) {
  return m_->add_particles(x, radius, material, mass);
}
std::size_t Simulation::particle_count() const { return m_->particle_count(); }
void Simulation::bond_touching_pairs(double tolerance) { m_->bond_touching_pairs(tolerance); }
void Simulation::set_bonds(const std::vector<std::uint32_t>& first, const std::vector<std::uint32_t>& second,
                           const std::vector<double>& factor, const std::vector<double>& strength) {
  m_->set_bonds(first, second, factor, strength);
}
void Simulation::set_velocity(std::size_t id, std::array<double, 3> v) { m_->set_velocity(id, v); }

int Simulation::group_index(const std::string& name) {
  auto& g = m_->group_names;
  const auto it = std::find(g.begin(), g.end(), name);
  if (it != g.end()) return static_cast<int>(it - g.begin());
  g.push_back(name);
  return static_cast<int>(g.size()) - 1;
}
void Simulation::add_to_group(const std::vector<std::uint32_t>& ids, const std::string& name) {
  m_->add_to_group(ids, static_cast<std::uint32_t>(group_index(name)));
}

namespace {
std::uint32_t existing_group(const detail::ModelBase& m, const std::string& name) {
  const auto& g = m.group_names;
  const auto it = std::find(g.begin(), g.end(), name);
  STRATA_CHECK(it != g.end(), Input, "no group named '{}'", name);
  return static_cast<std::uint32_t>(it - g.begin());
}
std::uint32_t group_of(Simulation& s, const std::string& name) {
  return static_cast<std::uint32_t>(s.group_index(name));
}
/// A value given per group set, per particle (internal order; at `rows` when listed).
template <typename T>
std::vector<T> per_particle(const detail::ModelBase& m, const std::vector<T>& of_set,
                            detail::Rows rows = {}) {
  const auto& sets = m.particle_sets();
  std::vector<T> out(rows.count(sets.size()));
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = of_set[sets[rows[k]]];
  return out;
}

/// Per group set: the last group it holds, -1 for none.
std::vector<std::int32_t> last_group_of_set(const detail::ModelBase& m) {
  std::vector<std::int32_t> of_set;
  for (const auto& s : m.group_sets) of_set.push_back(s.empty() ? -1 : static_cast<std::int32_t>(s.back()));
  return of_set;
}

/// Listed internal rows, each checked against the particle count.
detail::Rows listed(const detail::ModelBase& m, std::span<const std::uint32_t> rows) {
  const std::size_t n = m.particle_count();
  for (const std::uint32_t r : rows)
    STRATA_CHECK(r < n, Input, "particle row {} is out of range: the model has {} particles", r, n);
  return {rows, false};
}
}  // namespace

std::vector<std::uint32_t> Simulation::group_members(const std::string& name) const {
  return m_->members(existing_group(*m_, name));
}
std::vector<std::uint8_t> Simulation::in_groups(const std::vector<std::string>& names) const {
  std::vector<std::uint32_t> groups;
  for (const auto& name : names) groups.push_back(existing_group(*m_, name));
  return per_particle(*m_, m_->sets_holding(groups));
}
std::vector<std::int32_t> Simulation::last_group() const { return per_particle(*m_, last_group_of_set(*m_)); }
std::vector<std::int32_t> Simulation::last_group(std::span<const std::uint32_t> rows) const {
  return per_particle(*m_, last_group_of_set(*m_), listed(*m_, rows));
}

const std::vector<std::string>& Simulation::group_names() const { return m_->group_names; }

void Simulation::fix(const std::string& group, unsigned axes) {
  m_->bc_specs.push_back({detail::BcSpec::Fix, group_of(*this, group), axes, {}, 0, -1});
  m_->bcs_changed();
}
void Simulation::prescribe_velocity(const std::string& group, std::array<double, 3> v, unsigned axes) {
  m_->bc_specs.push_back({detail::BcSpec::Velocity, group_of(*this, group), axes, v, 0, -1});
  m_->bcs_changed();
}
void Simulation::drive(const std::string& group, unsigned axes, bool exchange) {
  m_->bc_specs.push_back({detail::BcSpec::Velocity, group_of(*this, group), axes, {}, 0, -1, exchange});
  m_->bcs_changed();
}
void Simulation::set_kinematics(std::size_t id, const std::array<double, 3>& u,
                                const std::array<double, 3>& v) {
  m_->set_kinematics(id, u, v);
}
void Simulation::kinematics(std::size_t id, std::array<double, 3>& u, std::array<double, 3>& v) const {
  m_->kinematics(id, u, v);
}
void Simulation::step_displacement(const std::string& group, std::array<double, 3> increment,
                                   std::int64_t every_steps, unsigned axes) {
  STRATA_CHECK(every_steps >= 1, Input, "step_displacement: every_steps = {} must be >= 1", every_steps);
  if (axes == 0)
    for (int a = 0; a < 3; ++a)
      if (increment[a] != 0) axes |= 1u << a;
  for (int a = 0; a < 3; ++a)
    STRATA_CHECK((axes >> a & 1u) || increment[a] == 0, Input,
                 "step_displacement: an increment of {} along axis {} that is not prescribed", increment[a],
                 a);
  m_->bc_specs.push_back(
      {detail::BcSpec::StepDisp, group_of(*this, group), axes, increment, every_steps, -1});
  m_->bcs_changed();
}
void Simulation::force_history(const std::string& group, std::vector<double> times,
                               std::vector<std::array<double, 3>> forces, Ramp ramp) {
  STRATA_CHECK(!times.empty() && times.size() == forces.size(), Input,
               "force_history: {} times and {} forces (need the same number, at least one)", times.size(),
               forces.size());
  STRATA_CHECK(std::is_sorted(times.begin(), times.end()), Input, "force_history: times must be ascending");
  m_->histories.push_back({std::move(times), std::move(forces)});
  m_->histories.back().ramp = ramp;
  const int h = static_cast<int>(m_->histories.size()) - 1;
  m_->bc_specs.push_back({detail::BcSpec::Force, group_of(*this, group), 0, {}, 0, h});
  m_->bcs_changed();
}
void Simulation::radial_force_history(const std::string& group, std::vector<double> times,
                                      std::vector<double> magnitudes, std::array<double, 3> centre,
                                      std::array<double, 3> axis, Ramp ramp) {
  std::vector<std::array<double, 3>> f;
  for (double m : magnitudes) f.push_back({m, 0, 0});
  force_history(group, std::move(times), std::move(f), ramp);
  detail::ForceHistory& h = m_->histories.back();
  h.radial = true;
  h.centre = centre;
  h.axis = axis;
}
std::array<double, 3> Simulation::radial_direction(const std::array<double, 3>& x,
                                                   const std::array<double, 3>& centre,
                                                   const std::array<double, 3>& axis, int dim) {
  double r[3] = {0, 0, 0}, along = 0, len2 = 0, axis2 = 0;
  for (int a = 0; a < dim; ++a) {
    r[a] = x[a] - centre[a];
    along += r[a] * axis[a];
    axis2 += axis[a] * axis[a];
  }
  if (axis2 > 0)
    for (int a = 0; a < dim; ++a) r[a] -= along / axis2 * axis[a];
  for (int a = 0; a < dim; ++a) len2 += r[a] * r[a];
  const double len = std::sqrt(len2);
  std::array<double, 3> out{};
  for (int a = 0; a < dim; ++a) out[a] = len > 0 ? r[a] / len : 0.0;
  return out;
}
void Simulation::add_wall(std::array<double, 3> point, std::array<double, 3> normal,
                          std::array<double, 3> velocity, double stiffness) {
  double l = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  STRATA_CHECK(l > 0, Input, "add_wall: the normal must not be zero");
  STRATA_CHECK(stiffness > 0, Input, "add_wall: stiffness = {} must be > 0 (N/m)", stiffness);
  detail::Wall w{};
  for (int a = 0; a < 3; ++a) {
    w.p[a] = point[a];
    w.n[a] = normal[a] / l;
    w.v[a] = velocity[a];
  }
  w.k = stiffness;
  m_->walls.push_back(w);
  m_->walls_changed();
}

void Simulation::initialise() { m_->initialise(); }
double Simulation::critical_dt() const { return m_->critical_dt(); }
double Simulation::lambda_bound() const { return m_->lambda_bound(); }
double Simulation::lambda_estimate() const { return m_->lambda_estimate(); }
double Simulation::dt() const { return m_->settings.dt; }
void Simulation::set_dt(double dt) {
  STRATA_CHECK(dt > 0 && std::isfinite(dt), Input, "dt = {} must be > 0 (s)", dt);
  const double old = m_->settings.dt;
  m_->settings.dt = dt;
  try {
    m_->check_dt();
  } catch (...) {
    m_->settings.dt = old;
    throw;
  }
}
void Simulation::run(std::int64_t steps, bool energies) { m_->run(steps, energies); }
void Simulation::settle(std::int64_t steps) { m_->settle(steps); }
std::int64_t Simulation::step_count() const { return m_->step_count(); }
double Simulation::time() const { return m_->time(); }
std::int64_t Simulation::last_good_step() const { return m_->last_good_step(); }

std::array<double, 3> Simulation::group_force(const std::string& group) const {
  return m_->group_force(existing_group(*m_, group));
}
double Simulation::kinetic_energy() const { return m_->kinetic_energy(); }
double Simulation::bond_energy() const { return m_->bond_energy(); }
double Simulation::external_work() const { return m_->external_work(); }
double Simulation::exchange_work() const { return m_->exchange_work(); }
double Simulation::energy_floor() const { return m_->energy_floor(); }
double Simulation::damping_dissipation() const { return m_->damping_dissipation(); }
std::size_t Simulation::broken_count(BreakMode mode) const {
  return m_->broken_count(static_cast<int>(mode));
}
std::size_t Simulation::broken_count() const { return m_->broken_count(0); }
std::size_t Simulation::bond_count() const { return m_->bond_count(); }
std::size_t Simulation::contact_count() const { return m_->contact_count(); }
std::int64_t Simulation::steps_in_lattice_slots() const { return m_->steps_in_lattice_slots(); }
const std::vector<BreakEvent>& Simulation::breaks() const { return m_->breaks(); }
std::vector<std::array<std::uint32_t, 2>> Simulation::touching_pairs() const { return m_->touching_pairs(); }
std::vector<std::array<double, 3>> Simulation::positions() const { return m_->positions({}); }
std::vector<std::array<double, 3>> Simulation::velocities() const { return m_->velocities({}); }
std::vector<std::array<double, 3>> Simulation::displacements() const { return m_->displacements({}); }
std::vector<double> Simulation::radii() const { return m_->radii({}); }
std::vector<std::uint32_t> Simulation::ids() const { return m_->ids({}); }
std::vector<float> Simulation::damage() const { return m_->damage({}); }
std::vector<std::array<double, 3>> Simulation::positions(std::span<const std::uint32_t> rows) const {
  return m_->positions(listed(*m_, rows));
}
std::vector<std::array<double, 3>> Simulation::velocities(std::span<const std::uint32_t> rows) const {
  return m_->velocities(listed(*m_, rows));
}
std::vector<std::array<double, 3>> Simulation::displacements(std::span<const std::uint32_t> rows) const {
  return m_->displacements(listed(*m_, rows));
}
std::vector<double> Simulation::radii(std::span<const std::uint32_t> rows) const {
  return m_->radii(listed(*m_, rows));
}
std::vector<std::uint32_t> Simulation::ids(std::span<const std::uint32_t> rows) const {
  return m_->ids(listed(*m_, rows));
}
std::vector<float> Simulation::damage(std::span<const std::uint32_t> rows) const {
  return m_->damage(listed(*m_, rows));
}
std::vector<std::uint8_t> Simulation::bond_counts() const { return m_->bond_counts(); }
std::vector<PairView> Simulation::bonds() const { return m_->pairs(detail::PairSet::Bonds); }
std::vector<PairView> Simulation::broken_bonds() const { return m_->pairs(detail::PairSet::BrokenBonds); }
std::vector<PairView> Simulation::contacts() const { return m_->pairs(detail::PairSet::Contacts); }
std::vector<WallView> Simulation::walls() const {
  std::vector<WallView> out;
  for (const detail::Wall& w : m_->walls)
    out.push_back({{w.p[0], w.p[1], w.p[2]}, {w.n[0], w.n[1], w.n[2]}, {w.v[0], w.v[1], w.v[2]}, w.k});
  return out;
}
std::size_t Simulation::memory_bytes() const { return m_->memory_bytes(); }
std::size_t Simulation::streamed_bytes_per_step() const { return m_->streamed_bytes_per_step(); }
std::uint64_t Simulation::state_hash() const { return m_->state_hash(); }

double hex_lattice_lambda_max(double kn, double ks, double mass) {
  // largest eigenvalue of D(k) = Σ_b 2(1 - cos k·a_b)·K_b over the Brillouin zone: a grid
  // over the reciprocal cell, then a shrinking pattern search around the best point
  const double s3 = std::sqrt(3.0);
  const double a[3][2] = {{1, 0}, {0.5, s3 / 2}, {-0.5, s3 / 2}};
  auto lam = [&](double kx, double ky) {
    double m00 = 0, m01 = 0, m11 = 0;
    for (const auto& n : a) {
      const double w = 2 * (1 - std::cos(kx * n[0] + ky * n[1]));
      m00 += w * (ks + (kn - ks) * n[0] * n[0]);
      m01 += w * (kn - ks) * n[0] * n[1];
      m11 += w * (ks + (kn - ks) * n[1] * n[1]);
    }
    return 0.5 * (m00 + m11) + std::sqrt(0.25 * (m00 - m11) * (m00 - m11) + m01 * m01);
  };
  const double pi = 3.14159265358979323846;
  double bx = 0, by = 0, best = -1;
  const int n = 120;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double kx = 2 * pi * i / n, ky = 2 * pi * j / n * 2 / s3;
      const double l = lam(kx, ky);
      if (l > best) {
        best = l;
        bx = kx;
        by = ky;
      }
    }
  for (double h = 2 * pi / n; h > 1e-12; h *= 0.5) {
    bool moved = true;
    while (moved) {
      moved = false;
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
          const double l = lam(bx + dx * h, by + dy * h);
          if (l > best) {
            best = l;
            bx += dx * h;
            by += dy * h;
            moved = true;
          }
        }
    }
  }
  return best / mass;
}

}  // namespace strata::dem
