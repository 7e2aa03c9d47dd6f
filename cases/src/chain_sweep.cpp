// The η sweeps of the coupled chains: each coupled point is a network scene run through
// scene::Run, its probe read through the coupler's own samples; the monolithic rows and the
// metamaterial reference are plain libfem runs of the whole chain.
#include <strata/cases/chain_sweep.hpp>

#include <unistd.h>

#include <fmt/format.h>
#include <strata/core/clock.hpp>
#include <strata/core/error.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>

#include "case_helpers.hpp"

namespace strata::cases {

namespace fs = std::filesystem;
using couple::ChainModel;
using couple::Execution;

std::string chain_scene_text(const std::string& title, const ChainModel& model,
                             const std::vector<std::int64_t>& fem_nodes,
                             const std::vector<std::int64_t>& dem_nodes, std::int64_t probe, double dt_dem,
                             int eta, Execution mode, fem::Scheme scheme, std::int64_t steps,
                             bool allow_unstable) {
  // fmt writes the shortest text that reads back to the same double
  const couple::SpringNetwork& n = model.net;
  std::string springs, walls, loads;
  for (std::size_t s = 0; s < n.k.size(); ++s)
    springs += fmt::format("{}[{}, {}, {}]", s ? ",\n  " : "", n.i[s], n.j[s], n.k[s]);
  for (std::size_t s = 0; s < n.ground_k.size(); ++s)
    walls += fmt::format("{}[{}, {}]", s ? ", " : "", n.ground_i[s], n.ground_k[s]);
  for (std::size_t s = 0; s < model.loads.size(); ++s) {
    const couple::SineLoad& l = model.loads[s];
    loads += fmt::format("{}[{}, {}, {}, {}]", s ? ", " : "", l.node, l.amplitude, l.period, l.end);
  }
  return fmt::format(
      "[network]\n"
      "title = \"{}\"\n"
      "mass = [{}]\n"
      "springs = [\n  {}]\n"
      "walls = [{}]\n"
      "fem_nodes = [{}]\n"
      "particle_nodes = [{}]\n"
      "sine_loads = [{}]\n"
      "probe_nodes = [{}]\n\n"
      "[solver]\n"
      "dt = {}\n"
      "steps = {}\n"
      "eta = {}\n"
      "coupling = \"{}\"\n"
      "fem_integrator = \"{}\"\n"
      "allow_unstable = {}\n\n"
      "[output]\n"
      "probe_every = {}\n"
      "render = false\n",
      title, fmt::join(n.mass, ", "), springs, walls, fmt::join(fem_nodes, ", "), fmt::join(dem_nodes, ", "),
      loads, probe, dt_dem, steps, eta, couple::to_string(mode), fem::to_string(scheme), allow_unstable,
      std::max<std::int64_t>(steps, 1));
}

namespace {

void errors_against(SweepRow& r, const std::vector<double>& t, const std::vector<double>& u,
                    const std::function<double(double)>& ref, bool keep) {
  double emax = 0, e2 = 0, rmax = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double ur = ref(t[k]), e = u[k] - ur;
    emax = std::max(emax, std::abs(e));
    e2 += e * e;
    rmax = std::max(rmax, std::abs(ur));
    if (keep) r.u_ref.push_back(ur);
  }
  r.err_max = std::isfinite(e2) ? emax : INFINITY;
  r.err_rms = std::sqrt(e2 / static_cast<double>(std::max<std::size_t>(t.size(), 1)));
  r.ref_max = rmax;
  if (keep) {
    r.t = t;
    r.u = u;
  }
}

/// The nodes of a chain's two parts and the node whose displacement is compared.
struct Split {
  std::vector<std::int64_t> fem, dem;
  std::int64_t probe = 0;
};

/// Runs one coupled point as a network scene: set-up (reading the scene, splitting, both parts
/// initialised) and the steps are timed, the run's files go to a scratch folder. Throws
/// strata::Error (Input) when the scene refuses the point.
SweepRow coupled_point(const std::string& name, const ChainModel& model, const Split& split, int eta,
                       Execution mode, const SweepOptions& o, double dt_dem, double duration,
                       fem::Scheme scheme, const std::function<double(double)>& ref) {
  SweepRow r;
  r.case_name = name;
  r.eta = eta;
  r.mode = couple::to_string(mode);
  r.dt_dem = dt_dem;
  r.dt_fem = eta * dt_dem;
  const auto nsys = static_cast<std::int64_t>(std::floor(duration / r.dt_fem + 1e-9));
  r.fem_steps = nsys;
  r.dem_steps = nsys * eta;
  const std::string text =
      chain_scene_text(fmt::format("{}, eta = {}, {}", name, eta, r.mode), model, split.fem, split.dem,
                       split.probe, dt_dem, eta, mode, scheme, nsys * eta, o.run_unstable);
  static std::atomic<int> counter{0};
  const fs::path dir = fs::temp_directory_path() / fmt::format("strata_chain_{}_{}", ::getpid(), counter++);
  struct Scratch {
    fs::path dir;
    ~Scratch() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } scratch{dir};
  double best = INFINITY;
  std::vector<double> t, u;
  for (int rep = 0; rep < std::max(1, o.repeats); ++rep) {
    const auto t0 = WallClock::now();
    const scene::Scene sc = scene::parse(text, dir / "chain.generated.toml", {});
    scene::Run run(sc, {dir, /*force=*/false, {}});
    scene::BuiltModel& m = run.model();
    const scene::BuiltModel::NetworkProbe& p = m.network_probes.front();
    if (p.fem)
      m.coupler().probe_fem(p.dof, "probe");
    else
      m.coupler().probe_dem(p.dof, "probe");
    const double setup = seconds_since(t0);
    scene::RunObserver quiet;
    try {
      const scene::RunResult res = run.execute(quiet);
      best = std::min(best, setup + res.step_seconds);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Numerical) throw;
      r.status = "blew up";
      r.stopped_at = m.time();
      r.probe = e.what();
      break;  // a blow-up repeats: no run time to measure
    }
    const couple::ProbeHistory& h = p.fem ? m.coupler().fem_probes()[0] : m.coupler().dem_probes()[0];
    t = h.t;
    u = h.u;
  }
  if (!r.status.empty()) {
    r.err_max = r.err_rms = r.wall_s = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  r.wall_s = best;
  errors_against(r, t, u, ref, o.keep_samples);
  return r;
}

/// Monolithic run of the whole model with one scheme (baseline rows).
SweepRow monolithic_point(const std::string& name, const ChainModel& model, std::int64_t probe_node,
                          fem::Scheme scheme, double dt, double duration, const SweepOptions& o,
                          const std::function<double(double)>& ref) {
  SweepRow r;
  r.case_name = name;
  r.eta = 1;
  r.mode = "monolithic " + fem::to_string(scheme);
  r.dt_dem = r.dt_fem = dt;
  const auto n = static_cast<std::int64_t>(std::floor(duration / dt + 1e-9));
  r.fem_steps = n;
  std::vector<double> t, u;
  double best = INFINITY;
  for (int rep = 0; rep < std::max(1, o.repeats); ++rep) {
    t.clear();
    u.clear();
    const auto t0 = WallClock::now();
    fem::Solver s = couple::monolithic_solver(model, fem::SolverSettings{.scheme = scheme, .dt = dt});
    s.initialise();
    t.push_back(0);
    u.push_back(s.u()[probe_node]);
    for (std::int64_t k = 0; k < n; ++k) {
      s.step();
      t.push_back(s.time());
      u.push_back(s.u()[probe_node]);
    }
    best = std::min(best, seconds_since(t0));
  }
  r.wall_s = best;
  errors_against(r, t, u, ref, o.keep_samples);
  return r;
}

}  // namespace

std::vector<SweepRow> sweep_chain6(const SweepOptions& o) {
  const double dt = o.dt_dem > 0 ? o.dt_dem : 1e-4, T = o.duration > 0 ? o.duration : 20.0;
  const ChainModel model = couple::chain6_model();
  const couple::Chain6Exact exact;
  const auto ref = [&exact](double t) { return exact.u(2, t); };  // m3
  std::vector<SweepRow> rows;
  for (Execution mode : o.modes)
    for (int eta : o.etas) {
      SweepRow r = coupled_point("chain6", model, {{0, 1, 2, 3}, {2, 3, 4, 5}, 2}, eta, mode, o, dt, T,
                                 o.fem_scheme, ref);
      if (r.status.empty()) r.probe = "m3 (FEM boundary node)";
      rows.push_back(std::move(r));
    }
  SweepRow mono = monolithic_point("chain6", model, 2, fem::Scheme::CentralDifference, dt, T, o, ref);
  mono.probe = "m3";
  rows.push_back(std::move(mono));
  return rows;
}

std::vector<SweepRow> sweep_metamaterial(const SweepOptions& o) {
  const double dt = o.dt_dem > 0 ? o.dt_dem : 4e-6, T = o.duration > 0 ? o.duration : 0.075;
  couple::check_metamaterial_dt(dt);
  const ChainModel model = couple::metamaterial_model(o.pulse);
  const std::int64_t probe = couple::metamaterial_dem_mass(250);
  // reference: monolithic implicit Newmark at a small step, sampled every step
  fem::Solver ref_solver = couple::monolithic_solver(
      model, fem::SolverSettings{.scheme = fem::Scheme::ImplicitNewmark, .dt = o.dt_ref});
  ref_solver.initialise();
  const auto nref = static_cast<std::int64_t>(std::ceil(T / o.dt_ref)) + 1;
  std::vector<double> uref{ref_solver.u()[probe]};
  for (std::int64_t k = 0; k < nref; ++k) {
    ref_solver.step();
    uref.push_back(ref_solver.u()[probe]);
  }
  const double dref = o.dt_ref;
  const auto ref = [&uref, dref](double t) {  // linear interpolation between reference steps
    const double x = t / dref;
    const auto k = std::min<std::size_t>(static_cast<std::size_t>(x), uref.size() - 2);
    const double w = x - static_cast<double>(k);
    return (1 - w) * uref[k] + w * uref[k + 1];
  };
  const Split split{couple::metamaterial_fem_nodes(), couple::metamaterial_dem_nodes(), probe};
  std::vector<SweepRow> rows;
  for (Execution mode : o.modes)
    for (int eta : o.etas) {
      SweepRow r;
      try {
        r = coupled_point("metamaterial", model, split, eta, mode, o, dt, T, o.fem_scheme, ref);
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::Input) throw;
        r.case_name = "metamaterial";
        r.eta = eta;
        r.mode = couple::to_string(mode);
        r.dt_dem = dt;
        r.dt_fem = eta * dt;
        r.err_max = r.err_rms = std::numeric_limits<double>::quiet_NaN();
        r.wall_s = std::numeric_limits<double>::quiet_NaN();
        r.status = "refused";
        r.probe = e.what();
        rows.push_back(std::move(r));
        continue;
      }
      if (r.status.empty()) r.probe = "DEM mass 250 (outer mass 550)";
      rows.push_back(std::move(r));
    }
  SweepRow mono =
      monolithic_point("metamaterial", model, probe, fem::Scheme::CentralDifference, dt, T, o, ref);
  mono.probe = "DEM mass 250 (outer mass 550)";
  rows.push_back(std::move(mono));
  return rows;
}

std::string sweep_markdown(const std::vector<SweepRow>& rows) {
  std::string s =
      "| η | mode | dt_DEM (s) | dt_FEM (s) | FEM steps | DEM steps | max error (m) | RMS error (m) | max "
      "error / "
      "max abs(u_ref) | wall time (ms) |\n"
      "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SweepRow& r : rows) {
    if (r.status == "refused") {
      s += fmt::format("| {} | {} | {:.3g} | {:.3g} | – | – | refused | – | – | – |\n", r.eta, r.mode,
                       r.dt_dem, r.dt_fem);
      continue;
    }
    if (r.status == "blew up") {
      s += fmt::format("| {} | {} | {:.3g} | {:.3g} | {} | {} | blew up at t = {:.4g} s | – | – | – |\n",
                       r.eta, r.mode, r.dt_dem, r.dt_fem, r.fem_steps, r.dem_steps, r.stopped_at);
      continue;
    }
    s += fmt::format("| {} | {} | {:.3g} | {:.3g} | {} | {} | {:.3e} | {:.3e} | {:.3e} | {:.2f} |\n", r.eta,
                     r.mode, r.dt_dem, r.dt_fem, r.fem_steps, r.dem_steps, r.err_max, r.err_rms,
                     r.ref_max > 0 ? r.err_max / r.ref_max : 0.0, 1e3 * r.wall_s);
  }
  return s;
}

}  // namespace strata::cases
