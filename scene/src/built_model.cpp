// A built model's parts and how it steps: DEM alone, FEM alone, or both through the coupler.
#include <strata/core/error.hpp>
#include <strata/scene/model.hpp>

#include <algorithm>
#include <cstring>

namespace strata::scene {

BuiltModel::BuiltModel() = default;
BuiltModel::~BuiltModel() = default;
BuiltModel::BuiltModel(BuiltModel&&) noexcept = default;
BuiltModel& BuiltModel::operator=(BuiltModel&&) noexcept = default;

dem::Simulation& BuiltModel::sim() {
  STRATA_ASSERT(has_particles());
  return dem_ ? *dem_ : dem_partition_->simulation();
}
const dem::Simulation& BuiltModel::sim() const {
  STRATA_ASSERT(has_particles());
  return dem_ ? *dem_ : dem_partition_->simulation();
}
fem::Solver& BuiltModel::fem() {
  STRATA_ASSERT(has_fem());
  return fem_partition_->solver();
}
const fem::Solver& BuiltModel::fem() const {
  STRATA_ASSERT(has_fem());
  return fem_partition_->solver();
}

std::string BuiltModel::fem_integrator() const {
  return has_fem() ? fem::to_string(fem().settings().scheme) : std::string();
}

std::string BuiltModel::execution() const { return coupled() ? couple::to_string(execution_mode) : "serial"; }

std::int64_t BuiltModel::step_count() const {
  if (has_particles()) return sim().step_count();
  return has_fem() ? fem().steps_done() : 0;
}

double BuiltModel::time() const {
  if (has_particles()) return sim().time();
  return has_fem() ? fem().time() : 0.0;
}

void BuiltModel::advance(std::int64_t n) {
  if (coupled()) {
    STRATA_ASSERT(n % eta == 0);
    coupler_->run(n / eta);
  } else if (dem_) {
    dem_->run(n);
  } else if (has_fem()) {
    fem().advance(n);
  }
}

std::int64_t BuiltModel::last_good_step() const {
  std::int64_t good = has_particles() ? sim().last_good_step() : step_count();
  // The FEM side counts FEM steps: η DEM steps each.
  if (has_fem()) good = std::min(good, fem().last_good_step() * (has_particles() ? eta : 1));
  return good;
}

std::uint64_t BuiltModel::state_hash() const {
  // The particles' own hash (unchanged for a model without FEM), then FNV-1a over the FEM
  // displacements and velocities.
  std::uint64_t h = has_particles() ? sim().state_hash() : 1469598103934665603ull;
  if (!has_fem()) return h;
  auto mix = [&h](const Eigen::VectorXd& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      unsigned char bytes[sizeof(double)];
      std::memcpy(bytes, &v[i], sizeof(double));
      for (unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ull;
      }
    }
  };
  mix(fem().u());
  mix(fem().v());
  return h;
}

}  // namespace strata::scene
