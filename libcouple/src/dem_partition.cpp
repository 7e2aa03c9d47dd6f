// A libdem Simulation as a coupled partition (see dem_partition.hpp).
#include <strata/core/error.hpp>
#include <strata/couple/dem_partition.hpp>

namespace strata::couple {

namespace {
constexpr const char* kGroup[3] = {"couple_external_x", "couple_external_y", "couple_external_z"};
}

DemPartition::DemPartition(dem::Simulation sim, std::string name)
    : sim_(std::move(sim)), name_(std::move(name)), dim_(sim_.dim()) {
  STRATA_CHECK(sim_.particle_count() > 0, Input, "{} partition: the DEM model has no particles", name_);
  ext_index_.assign(sim_.particle_count(), -1);
}

DemPartition::Driven* DemPartition::driven_of(std::size_t d, const char* what) {
  STRATA_CHECK(d < dofs(), Input, "{} partition: {}: DOF {} out of range ({} DOFs)", name_, what, d, dofs());
  const std::int32_t k = ext_index_[d / static_cast<std::size_t>(dim_)];
  const unsigned bit = 1u << (d % static_cast<std::size_t>(dim_));
  STRATA_CHECK(k >= 0 && (ext_[static_cast<std::size_t>(k)].axes & bit), Input,
               "{} partition: {}: DOF {} (particle {}, axis {}) is not external", name_, what, d,
               d / static_cast<std::size_t>(dim_), d % static_cast<std::size_t>(dim_));
  return &ext_[static_cast<std::size_t>(k)];
}

void DemPartition::make_external(std::size_t d) {
  STRATA_CHECK(!prepared_, Input, "{} partition: make_external({}) after prepare()/initialise()", name_, d);
  STRATA_CHECK(d < dofs(), Input, "{} partition: make_external: DOF {} out of range ({} DOFs)", name_, d,
               dofs());
  const std::size_t id = d / static_cast<std::size_t>(dim_);
  if (ext_index_[id] < 0) {
    ext_index_[id] = static_cast<std::int32_t>(ext_.size());
    ext_.push_back(Driven{static_cast<std::uint32_t>(id)});
  }
  ext_[static_cast<std::size_t>(ext_index_[id])].axes |= 1u << (d % static_cast<std::size_t>(dim_));
}

void DemPartition::set_external(std::size_t d, double u, double v) {
  Driven* p = driven_of(d, "set_external");
  const std::size_t a = d % static_cast<std::size_t>(dim_);
  p->u[a] = u;
  p->v[a] = v;
  if (!p->dirty) {
    p->dirty = true;
    dirty_.push_back(static_cast<std::uint32_t>(ext_index_[p->id]));
  }
}

double DemPartition::displacement(std::size_t d) const {
  STRATA_CHECK(d < dofs(), Input, "{} partition: DOF {} out of range", name_, d);
  const std::size_t id = d / static_cast<std::size_t>(dim_), a = d % static_cast<std::size_t>(dim_);
  const std::int32_t k = ext_index_[id];
  if (k >= 0 && ext_[static_cast<std::size_t>(k)].dirty && (ext_[static_cast<std::size_t>(k)].axes >> a & 1u))
    return ext_[static_cast<std::size_t>(k)].u[a];
  std::array<double, 3> u, v;
  sim_.kinematics(id, u, v);
  return u[a];
}

double DemPartition::velocity(std::size_t d) const {
  STRATA_CHECK(d < dofs(), Input, "{} partition: DOF {} out of range", name_, d);
  const std::size_t id = d / static_cast<std::size_t>(dim_), a = d % static_cast<std::size_t>(dim_);
  const std::int32_t k = ext_index_[id];
  if (k >= 0 && ext_[static_cast<std::size_t>(k)].dirty && (ext_[static_cast<std::size_t>(k)].axes >> a & 1u))
    return ext_[static_cast<std::size_t>(k)].v[a];
  std::array<double, 3> u, v;
  sim_.kinematics(id, u, v);
  return v[a];
}

void DemPartition::prepare() {
  if (prepared_) return;
  for (int a = 0; a < dim_; ++a) {
    std::vector<std::uint32_t> ids;
    for (const Driven& p : ext_)
      if (p.axes >> a & 1u) ids.push_back(p.id);
    if (ids.empty()) continue;
    sim_.add_to_group(ids, kGroup[a]);
    // after the model's own conditions: overrides them on this axis; its work is exchange
    sim_.drive(kGroup[a], 1u << a, /*exchange=*/true);
  }
  sim_.initialise();
  prepared_ = true;
}

void DemPartition::initialise() {
  prepare();
  flush();
  initialised_ = true;
}

void DemPartition::flush() {
  if (!prepared_) return;  // before initialise the values wait in the cache
  for (std::uint32_t k : dirty_) {
    Driven& p = ext_[k];
    sim_.set_kinematics(p.id, p.u, p.v);
    p.dirty = false;
  }
  dirty_.clear();
}

void DemPartition::step() {
  STRATA_CHECK(initialised_, Input, "{} partition: step() before initialise()", name_);
  flush();
  sim_.run(1, /*energies=*/false);  // energies only at the blow-up checks
}

double DemPartition::critical_dt() const {
  STRATA_CHECK(prepared_, Input,
               "{} partition: the critical step is known after prepare() (libdem computes it when the "
               "model is initialised)",
               name_);
  return sim_.critical_dt();
}

}  // namespace strata::couple
