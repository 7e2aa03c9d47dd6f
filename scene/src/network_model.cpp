// A network scene ([network]) built into a coupled model: the masses and springs split into
// an FEM part (libfem spring elements with lumped masses) and a particle part (velocity
// Verlet), which share one layer of nodes and exchange it once per system step.
#include <strata/core/error.hpp>
#include <strata/core/numbers.hpp>
#include <strata/couple/chains.hpp>

#include <algorithm>
#include <cmath>

#include "model_parts.hpp"

namespace strata::scene {

namespace {

/// The network of the scene's [network] (its rows checked with the scene).
couple::ChainModel chain_of(const NetworkTable& t) {
  couple::ChainModel c;
  c.net.mass = t.mass;
  for (const auto& r : t.springs.value) c.net.add_spring(std::int32_t(r[0]), std::int32_t(r[1]), r[2]);
  for (const auto& r : t.walls.value) c.net.add_ground_spring(std::int32_t(r[0]), r[1]);
  for (const auto& r : t.sine_loads.value)
    c.loads.push_back({.node = std::size_t(r[0]), .amplitude = r[1], .period = r[2], .end = r[3]});
  return c;
}

}  // namespace

BuiltModel build_network_model(const Scene& sc, bool force) {
  const NetworkTable& t = *sc.network;
  const SolverTable& solver = sc.solver;
  const bool allow = solver.allow_unstable || force;
  BuiltModel m;
  m.dim = 1;
  m.eta = int(solver.eta);
  m.execution_mode =
      solver.coupling == SolverCoupling::Parallel ? couple::Execution::Parallel : couple::Execution::Serial;
  m.dt_automatic = solver.dt == 0.0;
  const bool named = solver.fem_integrator.value != "auto";
  const fem::Scheme first_scheme =
      named ? fem::scheme_from_string(solver.fem_integrator.value) : fem::Scheme::CentralDifference;
  // With dt = 0 the step follows from the particle part's limit: split at a provisional step,
  // then set the real one.
  const double dt0 = m.dt_automatic ? 1.0 : double(solver.dt);
  couple::CoupledChain c = t.fem_nodes.blame([&] {
    return couple::split_chain(
        chain_of(t), t.fem_nodes, t.particle_nodes,
        {.dt_dem = dt0, .eta = m.eta, .fem_scheme = first_scheme, .allow_unstable = allow});
  });
  for (std::int64_t node : t.probe_nodes.value) {
    const auto owns = [node](const std::vector<std::int64_t>& global,
                             const std::vector<couple::Role>& roles) {
      const auto it = std::find(global.begin(), global.end(), node);
      return it != global.end() && roles[std::size_t(it - global.begin())] != couple::Role::External
                 ? std::optional<std::size_t>(std::size_t(it - global.begin()))
                 : std::nullopt;
    };
    if (const auto d = owns(c.dem_global, c.dem_roles))
      m.network_probes.push_back({node, false, *d});
    else if (const auto f = owns(c.fem_global, c.fem_roles))
      m.network_probes.push_back({node, true, *f});
    else
      t.probe_nodes.fail(fmt::format("node {} is in neither fem_nodes nor particle_nodes", node));
  }
  m.fem_partition_ = std::move(c.fem);
  m.network_ = std::move(c.dem);
  m.overlap_nodes = c.overlap.dem_to_fem.size();
  m.overlap_particles = c.overlap.fem_to_dem.size();
  m.coupler_ = std::make_unique<couple::Coupler>(*m.fem_partition_, *m.network_, std::move(c.overlap), m.eta,
                                                 m.execution_mode);  // declares the external nodes
  // The limits, with each part's external nodes held.
  m.fem_partition_->prepare();
  m.network_->prepare();
  fem::Solver& f = m.fem();
  m.dt_crit = m.network_->critical_dt();
  m.fem_explicit_dt_crit = f.stability().explicit_dt_crit;
  const double eta = double(m.eta);
  double dt = solver.dt;
  if (m.dt_automatic) {
    dt = solver.dt_safety * m.dt_crit;
    if (named && fem::is_explicit(first_scheme))
      dt = std::min(dt, solver.dt_safety * m.fem_explicit_dt_crit / eta);
    m.network_->set_dt(dt);
    f.set_dt(eta * dt);
  }
  if (dt > m.dt_crit && !allow) {
    const auto [dt_text, crit_text] = distinct_pair(dt, m.dt_crit);
    solver.dt.fail(fmt::format(
        "dt = {} s exceeds the critical time step {} s of the network's particle part (its external "
        "nodes held; dt/dt_crit = {}); the run would blow up. Allowed: dt <= {:.4g} s, or dt = 0 for {} x "
        "dt_crit; solver.allow_unstable = true or --force runs anyway",
        dt_text, crit_text, ratio_text(dt, m.dt_crit), m.dt_crit, solver.dt_safety.value));
  }
  // The exchange: the particle part's external nodes move with the copied velocity for a whole
  // system step, so copies η·dt apart drive it like a step of η·dt. Measured on the
  // metamaterial chain of Li et al. 2023: η·dt at 1.1 to 2.5 × the limit blew up within
  // 0.06–0.3 s, at 0.95–1.05 × within 0.4–0.9 s, while 0.5–0.8 × ran 2 s. Above the limit
  // strata refuses; below it the run's energy check still stops a slow growth.
  if (eta * dt > m.dt_crit && !allow)
    solver.eta.fail(fmt::format(
        "the exchange interval eta x dt = {} x {:.4g} s = {:.4g} s exceeds the particle part's critical step "
        "{:.4g} s: the copied overlap drives it like a step of that length and the coupled run grows "
        "unstable. Allowed: eta <= {}, or a smaller dt",
        m.eta, dt, eta * dt, m.dt_crit, std::max(1, int(std::floor(m.dt_crit / dt)))));
  if (!named) f.set_scheme(scheme_of(solver, eta * dt, m.fem_explicit_dt_crit));
  m.fem_dt_crit = f.stability().dt_crit;
  if (eta * dt > m.fem_dt_crit && !allow)
    solver.eta.fail(fmt::format(
        "the FEM step eta x dt = {} x {:.4g} s = {:.4g} s exceeds the limit {:.4g} s of the {} integrator "
        "(the overlap's external nodes held); allowed: eta <= {}, or fem_integrator = \"implicit-newmark\" "
        "(or \"auto\", which takes it above the explicit limit)",
        m.eta, dt, eta * dt, m.fem_dt_crit, fem::to_string(f.settings().scheme),
        std::max(1, int(std::floor(m.fem_dt_crit / dt)))));
  m.coupler_->initialise(allow);
  m.dt = dt;
  m.steps = step_count_of(solver, m.dt, m.eta);
  return m;
}

}  // namespace strata::scene
