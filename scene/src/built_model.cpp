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
couple::Coupler& BuiltModel::coupler() {
  STRATA_ASSERT(coupled());
  return *coupler_;
}
const couple::Coupler& BuiltModel::coupler() const {
  STRATA_ASSERT(coupled());
  return *coupler_;
}
couple::SpringNetworkPartition& BuiltModel::network() {
  STRATA_ASSERT(has_network());
  return *network_;
}
const couple::SpringNetworkPartition& BuiltModel::network() const {
  STRATA_ASSERT(has_network());
  return *network_;
}
std::pair<double, double> BuiltModel::network_probe(const NetworkProbe& p) const {
  if (p.fem) return {fem_partition_->displacement(p.dof), fem_partition_->velocity(p.dof)};
  return {network_->displacement(p.dof), network_->velocity(p.dof)};
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
  if (has_network()) return network_->steps_done();
  return has_fem() ? fem().steps_done() : 0;
}

double BuiltModel::time() const {
  if (has_particles()) return sim().time();
  if (has_network()) return network_->time();
  return has_fem() ? fem().time() : 0.0;
}

void BuiltModel::advance(std::int64_t n) {
  if (coupled()) {
    STRATA_ASSERT(n % eta == 0);
    take_initial_energy();
    for (std::int64_t left = n / eta; left > 0;) {
      const std::int64_t k = std::min(left, kCoupledCheckEvery);
      coupler_->run(k);
      left -= k;
      check_coupled_energy();
    }
  } else if (dem_) {
    dem_->run(n);
  } else if (has_fem()) {
    fem().advance(n);
  }
}

namespace {
/// Energy of the particles (or the network's particle part) and the FEM together (J).
double coupled_energy(const BuiltModel& m) {
  const double particles =
      m.has_network() ? m.network().energy() : m.sim().kinetic_energy() + m.sim().bond_energy();
  return particles + m.fem().kinetic_energy() + m.fem().strain_energy();
}
}  // namespace

void BuiltModel::take_initial_energy() {
  if (!coupled() || coupled_energy0 >= 0) return;
  coupled_energy0 = coupled_energy(*this);
  coupled_last_good = step_count();
}

void BuiltModel::check_coupled_energy() {
  const double e = coupled_energy(*this);
  // work of loads and boundary conditions: each part's work less what came from the other
  // (a network's particle part counts the work of its loads apart from what it is passed)
  const double w_dem = has_network() ? std::abs(network_->load_work())
                                     : std::abs(sim().external_work() - sim().exchange_work());
  const double w_fem = std::abs(fem().user_work());
  const double dem_floor = has_network() ? 1e-30 : sim().energy_floor();
  const double budget =
      10 * (std::max(coupled_energy0, 0.0) + w_dem + w_fem) + dem_floor + fem().energy_floor();
  if (!(e <= budget))
    fail(ErrorKind::Numerical,
         "coupled blow-up at step {}, t = {:.6g} s: particles and FEM hold {:.4g} J, more than {:.4g} J "
         "(10 x (initial {:.4g} J + work of loads and boundaries {:.4g} J)); the energy comes from the "
         "exchange between the parts: eta x dt = {} x {:.4g} s against the particles' critical step "
         "{:.4g} s; last good step {}",
         step_count(), time(), e, budget, std::max(coupled_energy0, 0.0), w_dem + w_fem, eta, dt, dt_crit,
         coupled_last_good);
  coupled_last_good = step_count();
}

std::int64_t BuiltModel::last_good_step() const {
  std::int64_t good = has_particles() ? sim().last_good_step()
                      : has_network() ? network_->last_good_step()
                                      : step_count();
  if (coupled()) good = std::min(good, coupled_last_good);
  // The FEM side counts FEM steps: η particle steps each.
  if (has_fem()) good = std::min(good, fem().last_good_step() * (coupled() ? eta : 1));
  return good;
}

std::uint64_t BuiltModel::state_hash() const {
  // The particles' own hash (unchanged for a model without FEM), then FNV-1a over the FEM
  // displacements and velocities.
  std::uint64_t h = has_particles() ? sim().state_hash() : 1469598103934665603ull;
  if (!has_fem()) return h;
  auto mix = [&h](const auto& v) {
    for (std::size_t i = 0; i < std::size_t(v.size()); ++i) {
      unsigned char bytes[sizeof(double)];
      std::memcpy(bytes, v.data() + i, sizeof(double));
      for (unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ull;
      }
    }
  };
  if (has_network()) {
    mix(network_->u());
    mix(network_->v());
  }
  mix(fem().u());
  mix(fem().v());
  return h;
}

}  // namespace strata::scene
