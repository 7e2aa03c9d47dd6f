// Error against run time of the coupled chain cases (Li et al. 2023): `strata report` and
// `strata check|run` of a coupled-chain scene share one path here:
//   resolve options -> stability (print; refuse) -> sweep -> files through a staging folder.
#include <strata/cases/chain_report.hpp>

#include <unistd.h>

#include <nlohmann/json.hpp>
#include <strata/cases/chain_sweep.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>

#include <strata/cases/wave_report.hpp>
#include <strata/core/clock.hpp>
#include <strata/scene/files.hpp>
#include <strata/scene/scene.hpp>

namespace strata::cases {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// ---- options -------------------------------------------------------------------------------

/// Options with the case defaults filled in.
struct ChainPlan {
  ReportOptions opt;
  double dt = 0;        ///< dt_DEM (s)
  double duration = 0;  ///< simulated time (s)
  fem::Scheme scheme = fem::Scheme::ExplicitNewmark;
  bool meta = false;  ///< the metamaterial case (else chain6)
};

ChainPlan resolve(const ReportOptions& opt) {
  STRATA_CHECK(opt.case_name == "chain6" || opt.case_name == "metamaterial", Input,
               "report: unknown case '{}' (chain6 or metamaterial)", opt.case_name);
  STRATA_CHECK(!opt.etas.empty(), Input, "report: no eta values");
  for (int e : opt.etas) STRATA_CHECK(e >= 1, Input, "report: eta = {} must be an integer >= 1", e);
  STRATA_CHECK(opt.modes == "serial" || opt.modes == "parallel" || opt.modes == "both", Input,
               "report: --modes {} (serial, parallel or both)", opt.modes);
  ChainPlan p;
  p.opt = opt;
  p.meta = opt.case_name == "metamaterial";
  p.dt = opt.dt_dem > 0 ? opt.dt_dem : p.meta ? 4e-6 : 1e-4;
  p.duration = opt.duration > 0 ? opt.duration : p.meta ? 0.075 : 20.0;
  const std::string scheme = opt.fem_scheme.empty() || opt.fem_scheme == "auto"
                                 ? (p.meta ? "implicit-newmark" : "explicit-newmark")
                                 : opt.fem_scheme;
  p.scheme = fem::scheme_from_string(scheme);
  return p;
}

couple::ChainModel model_of(const ChainPlan& p) {
  return p.meta ? couple::metamaterial_model({p.opt.pulse_amplitude, p.opt.pulse_duration})
                : couple::chain6_model();
}
std::vector<std::int64_t> fem_nodes(const ChainPlan& p) {
  return p.meta ? couple::metamaterial_fem_nodes() : std::vector<std::int64_t>{0, 1, 2, 3};
}
std::vector<std::int64_t> dem_nodes(const ChainPlan& p) {
  return p.meta ? couple::metamaterial_dem_nodes() : std::vector<std::int64_t>{2, 3, 4, 5};
}

// ---- stability -----------------------------------------------------------------------------

/// The stability numbers of a planned sweep: the whole chain and each partition (metamaterial:
/// couple::metamaterial_stability), and the coupler's own check at every η.
struct Stability {
  std::optional<couple::MetamaterialStability> meta;
  std::vector<couple::CoupledStability> per_eta;
  std::string dt_problem;                 ///< non-empty: dt_DEM is unstable (why, naming the limits)
  std::vector<std::string> eta_problems;  ///< "eta = 3: why", for points the coupler would refuse
  std::vector<int> refused;               ///< those η
};

Stability stability(const ChainPlan& p) {
  Stability s;
  if (p.meta) {
    s.meta = couple::metamaterial_stability();
    try {
      couple::check_metamaterial_dt(p.dt);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Input) throw;
      s.dt_problem = e.what();
    }
  }
  const couple::ChainModel model = model_of(p);
  for (int eta : p.opt.etas) {
    couple::CoupledChain c =
        couple::split_chain(model, fem_nodes(p), dem_nodes(p),
                            {.dt_dem = p.dt, .eta = eta, .fem_scheme = p.scheme, .allow_unstable = true});
    couple::Coupler declare(*c.fem, *c.dem, c.overlap, eta);  // makes the overlap DOFs external
    couple::CoupledStability cs = couple::coupled_stability(*c.fem, *c.dem, eta);
    const bool dem_bad = cs.dt_dem > cs.dem_dt_crit;
    if (dem_bad && s.dt_problem.empty())
      s.dt_problem = fmt::format("{}; use dt_DEM <= {:.3g} s", cs.problems.front(), cs.dem_dt_crit);
    // what the network scene refuses besides the coupler's check: the exchange interval
    // η·dt_DEM above the DEM partition's limit (scene/src/network_model.cpp)
    const bool exchange_bad = !dem_bad && eta * p.dt > cs.dem_dt_crit;
    if (cs.problems.size() > (dem_bad ? 1u : 0u)) {
      s.refused.push_back(eta);
      s.eta_problems.push_back(fmt::format("eta = {}: {}", eta, cs.problems.back()));
    } else if (exchange_bad) {
      s.refused.push_back(eta);
      s.eta_problems.push_back(
          fmt::format("eta = {}: the exchange interval eta x dt_DEM = {:.4g} s exceeds the DEM partition's "
                      "limit {:.4g} s "
                      "(the copied overlap drives it like a step of that length; the run grows unstable)",
                      eta, eta * p.dt, cs.dem_dt_crit));
    }
    s.per_eta.push_back(std::move(cs));
  }
  return s;
}

std::string chain_stability_text(const ChainPlan& p, const Stability& s) {
  std::string out;
  if (s.meta) out += s.meta->text(p.dt) + "\n";
  out += fmt::format("coupled steps: DEM velocity Verlet at dt_DEM = {:.4g} s, FEM {} at eta*dt_DEM\n", p.dt,
                     fem::to_string(p.scheme));
  if (!s.per_eta.empty()) {
    const auto& c = s.per_eta.front();
    out += fmt::format("  DEM partition: limit {:.4g} s (dt_DEM/limit = {:.3g}) -> {}\n", c.dem_dt_crit,
                       p.dt / c.dem_dt_crit, p.dt <= c.dem_dt_crit ? "ok" : "UNSTABLE");
  }
  for (const auto& c : s.per_eta) {
    const bool refused = std::find(s.refused.begin(), s.refused.end(), c.eta) != s.refused.end();
    const bool above = c.dt_fem > c.fem_explicit_dt_crit;
    out += fmt::format(
        "  eta = {:>2}: dt_FEM = {:.4g} s, FEM explicit limit {:.4g} s (ratio {:.3g}), {}; exchange interval "
        "{:.3g} x the DEM limit -> {}\n",
        c.eta, c.dt_fem, c.fem_explicit_dt_crit, c.dt_fem / c.fem_explicit_dt_crit, c.fem_integrator,
        c.dt_fem / c.dem_dt_crit,
        refused ? "REFUSED"
        : above ? "ok (implicit; an explicit FEM step would be unstable here)"
                : "ok");
  }
  for (const auto& e : s.eta_problems) out += "  " + e + "\n";
  out +=
      fmt::format("sweep: eta = {}; modes {}; {:.4g} s simulated ({} DEM steps)", fmt::join(p.opt.etas, ", "),
                  p.opt.modes, p.duration, static_cast<long long>(std::floor(p.duration / p.dt + 1e-9)));
  if (p.meta) out += fmt::format("; reference: monolithic implicit Newmark at dt = {:.3g} s", p.opt.dt_ref);
  return out + "\n";
}

json chain_stability_json(const ChainPlan& p, const Stability& s) {
  json j = {{"case", p.opt.case_name},  {"dt_dem_s", p.dt},
            {"duration_s", p.duration}, {"fem_scheme", fem::to_string(p.scheme)},
            {"modes", p.opt.modes},     {"ok", s.dt_problem.empty() && s.eta_problems.empty()}};
  if (s.meta) {
    j["whole_chain"] = {{"omega_max_rad_s", s.meta->omega_whole}, {"dt_limit_s", s.meta->dt_whole}};
    j["dem_partition"] = {{"omega_max_rad_s", s.meta->omega_dem}, {"dt_limit_s", s.meta->dt_dem_crit}};
    j["fem_partition"] = {{"omega_max_rad_s", s.meta->omega_fem},
                          {"explicit_dt_limit_s", s.meta->dt_fem_explicit}};
  }
  j["per_eta"] = per_eta_json(s.per_eta);
  if (!s.dt_problem.empty()) j["dt_problem"] = s.dt_problem;
  return j;
}

/// Where a refusal points: a [coupled] key of the scene (file:line:col) or, for
/// `strata report`, nowhere.
struct Refuse {
  const scene::CoupledTable* table = nullptr;
  /// `key` is the field of the key the refusal names, e.g. &scene::CoupledTable::dt_dem.
  template <class T>
  [[noreturn]] void at(scene::Located<T> scene::CoupledTable::*key, const std::string& message) const {
    if (table) (table->*key).fail(message);
    fail(ErrorKind::Input, "{}", message);
  }
};

/// Throws Input (exit 2) when dt_DEM is unstable, or when an η point would be refused and the
/// plan asks for that (chain6 always: its sweep cannot show refused points).
void refuse_unstable(const ChainPlan& p, const Stability& s, const Refuse& refuse) {
  if (!s.dt_problem.empty()) refuse.at(&scene::CoupledTable::dt_dem, s.dt_problem);
  if (s.eta_problems.empty() || p.opt.run_unstable || !(p.opt.refuse_unstable_eta || !p.meta)) return;
  std::string why;
  for (const auto& e : s.eta_problems) why += "\n  " + e;
  refuse.at(&scene::CoupledTable::eta,
            fmt::format("eta = {} cannot run with dt_DEM = {} s and the FEM integrator {}: lower eta, "
                        "lower dt_dem, or (for the FEM's own limit) use fem_scheme = \"implicit-newmark\"{}",
                        fmt::join(s.refused, ", "), p.dt, fem::to_string(p.scheme), why));
}

// ---- the sweep and its files ---------------------------------------------------------------

std::vector<SweepRow> sweep(const ChainPlan& p) {
  SweepOptions so;
  so.etas = p.opt.etas;
  so.modes.clear();
  if (p.opt.modes != "parallel") so.modes.push_back(couple::Execution::Serial);
  if (p.opt.modes != "serial") so.modes.push_back(couple::Execution::Parallel);
  so.dt_dem = p.dt;
  so.duration = p.duration;
  so.dt_ref = p.opt.dt_ref;
  so.repeats = p.opt.repeats;
  so.pulse = {p.opt.pulse_amplitude, p.opt.pulse_duration};
  so.fem_scheme = p.scheme;
  so.run_unstable = p.opt.run_unstable;
  return p.meta ? sweep_metamaterial(so) : sweep_chain6(so);
}

std::string header(const ChainPlan& p) {
  std::string h = p.opt.title.empty() ? "" : p.opt.title + "\n\n";
  if (p.meta)
    return h +
           fmt::format(
               "metamaterial chain: FEM {} at eta*dt_DEM, DEM velocity Verlet at dt_DEM = {:.3g} "
               "s; "
               "half-sine pulse {} N for {:.3g} s on outer mass 1; {:.3g} s simulated; error of DEM mass 250 "
               "against monolithic implicit Newmark at dt = {:.3g} s\n",
               fem::to_string(p.scheme), p.dt, p.opt.pulse_amplitude, p.opt.pulse_duration, p.duration,
               p.opt.dt_ref);
  return h + fmt::format(
                 "6-DOF chain: FEM {} at eta*dt_DEM, DEM velocity Verlet at dt_DEM = {:.3g} s; "
                 "{:.3g} s "
                 "simulated; error of m3 against the exact modal solution\n",
                 fem::to_string(p.scheme), p.dt, p.duration);
}

double mode_code(const std::string& m) { return m == "serial" ? 0 : m == "parallel" ? 1 : 2; }
double status_code(const std::string& s) { return s.empty() ? 0 : s == "refused" ? 1 : 2; }

/// Writes <case>_sweep.{csv,md,png} and summary.json into `dir`; prints the Markdown table.
void write_files(const ChainPlan& p, const std::vector<SweepRow>& rows, const fs::path& dir, double wall_s) {
  const ReportOptions& opt = p.opt;
  const std::string stem = opt.case_name + "_sweep";
  {
    io::CsvWriter csv(dir / (stem + ".csv"),
                      {"eta", "mode", "dt_dem_s", "dt_fem_s", "fem_steps", "dem_steps", "err_max_m",
                       "err_rms_m", "ref_max_m", "wall_s", "status", "stopped_at_s"});
    for (const auto& r : rows)
      csv.row({double(r.eta), mode_code(r.mode), r.dt_dem, r.dt_fem, double(r.fem_steps), double(r.dem_steps),
               r.err_max, r.err_rms, r.ref_max, r.wall_s, status_code(r.status), r.stopped_at});
    csv.close();
  }
  const std::string md = header(p) + "\n" + sweep_markdown(rows) +
                         "\nmode column of the CSV: 0 serial, 1 parallel, 2 monolithic baseline; status: 0 "
                         "completed, 1 refused, 2 blew up (stopped by the energy check at stopped_at_s).\n";
  std::ofstream(dir / (stem + ".md")) << md;
  std::fwrite(md.data(), 1, md.size(), stdout);

  json summary = {
      {"status", "completed"}, {"case", opt.case_name},    {"title", opt.title},
      {"dt_dem_s", p.dt},      {"duration_s", p.duration}, {"fem_scheme", fem::to_string(p.scheme)},
      {"etas", opt.etas},      {"modes", opt.modes},       {"wall_seconds", wall_s}};
  if (!opt.scene.empty()) summary["scene"] = opt.scene.string();
  json jr = json::array();
  for (const auto& r : rows) {
    jr.push_back({{"eta", r.eta},
                  {"mode", r.mode},
                  {"dt_fem_s", r.dt_fem},
                  {"err_max_m", std::isfinite(r.err_max) ? json(r.err_max) : json(nullptr)},
                  {"err_rms_m", std::isfinite(r.err_rms) ? json(r.err_rms) : json(nullptr)},
                  {"ref_max_m", r.ref_max},
                  {"wall_s", std::isfinite(r.wall_s) ? json(r.wall_s) : json(nullptr)},
                  {"status", r.status.empty() ? "completed" : r.status},
                  {"probe", r.probe}});
    if (r.status == "blew up") jr.back()["stopped_at_s"] = r.stopped_at;
  }
  summary["rows"] = jr;
  std::ofstream(dir / "summary.json") << summary.dump(2) << "\n";

  if (opt.no_plot) return;
  io::PlotRequest pr;
  pr.title = opt.case_name + ": error against run time over eta";
  pr.x_label = "wall time [s]";
  pr.y_label = "max error [m]";
  pr.log_x = pr.log_y = true;
  pr.png = dir / (stem + ".png");
  for (const std::string mode : {"serial", "parallel"}) {
    io::PlotSeries s{mode, {}, {}, true, true};
    for (const auto& r : rows)
      if (r.mode == mode && std::isfinite(r.wall_s) && r.err_max > 0) {
        s.x.push_back(r.wall_s);
        s.y.push_back(r.err_max);
      }
    if (!s.x.empty()) pr.series.push_back(std::move(s));
  }
  for (const auto& r : rows)
    if (r.mode.rfind("monolithic", 0) == 0 && r.err_max > 0)
      pr.series.push_back({r.mode, {r.wall_s}, {r.err_max}, true, false});
  try {
    io::plot_xy(pr);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Unsupported) throw;
    log::warn("no plot: {}", e.what());
  }
}

/// The one path behind `strata report` and `strata check|run SCENE`.
int run_plan(const ChainPlan& p, const Refuse& refuse, bool check_only, bool json_out = false) {
  const Stability s = stability(p);
  if (json_out)
    std::printf("%s\n", chain_stability_json(p, s).dump(2).c_str());
  else
    std::printf("%s", chain_stability_text(p, s).c_str());
  std::fflush(stdout);
  refuse_unstable(p, s, refuse);
  if (check_only) return 0;

  // Everything is validated: run the whole sweep, then write its files all at once.
  const auto t0 = WallClock::now();
  const auto rows = sweep(p);
  const double wall = seconds_since(t0);
  scene::Staging stage(p.opt.output);
  write_files(p, rows, stage.path(), wall);
  const auto written = stage.commit(p.opt.output);
  std::printf("wrote:\n");
  for (const auto& f : written) std::printf("  %s\n", f.string().c_str());
  return 0;
}

}  // namespace

json per_eta_json(const std::vector<couple::CoupledStability>& per_eta) {
  json etas = json::array();
  for (const auto& c : per_eta)
    etas.push_back({{"eta", c.eta},
                    {"dt_fem_s", c.dt_fem},
                    {"dem_dt_limit_s", c.dem_dt_crit},
                    {"fem_explicit_dt_limit_s", c.fem_explicit_dt_crit},
                    {"fem_integrator", c.fem_integrator},
                    {"ok", c.ok},
                    {"problems", c.problems},
                    {"notes", c.notes}});
  return etas;
}

int report_cmd(const ReportOptions& opt) { return run_plan(resolve(opt), Refuse{}, opt.check_only); }

ReportOptions coupled_report_options(const scene::Scene& sc, bool force) {
  STRATA_CHECK(sc.coupled, Internal, "coupled_report_options: {} has no [coupled] table", sc.file.string());
  const scene::CoupledTable& c = *sc.coupled;
  const scene::OutputTable& out = sc.output;
  ReportOptions o;
  o.case_name = c.case_name;
  o.title = c.title;
  o.scene = sc.file;
  o.output = out.directory;
  o.no_plot = !out.render;
  if (c.eta.given) {  // else the paper's list, ReportOptions' default
    o.etas.clear();
    for (std::int64_t e : c.eta.value) o.etas.push_back(static_cast<int>(e));
  }
  o.modes = c.modes;
  o.dt_dem = c.dt_dem;
  o.duration = c.duration;
  o.fem_scheme = c.fem_scheme;
  o.dt_ref = c.dt_ref;
  o.pulse_amplitude = c.pulse_amplitude;
  o.pulse_duration = c.pulse_duration;
  if (c.repeats.given) o.repeats = static_cast<int>(c.repeats);
  o.refuse_unstable_eta = !force;
  o.run_unstable = force;
  return o;
}

int coupled_threads(const scene::Scene& sc) {
  const scene::CoupledTable& c = *sc.coupled;
  if (c.threads.given) return static_cast<int>(c.threads);
  return c.case_name == "wave" ? WaveOptions{}.threads : 0;
}

int check_coupled_scene(const scene::Scene& sc, bool json_out, bool force) {
  if (sc.coupled->case_name == "wave") return check_wave_scene(sc, json_out, force);
  const ReportOptions o = coupled_report_options(sc, force);
  if (!json_out)
    std::printf("scene        %s (coupled chain, case %s)\n", sc.file.string().c_str(), o.case_name.c_str());
  return run_plan(resolve(o), Refuse{&*sc.coupled}, /*check_only=*/true, json_out);
}

int run_coupled_scene(const scene::Scene& sc, const fs::path& output, bool force, int threads) {
  if (sc.coupled->case_name == "wave") return run_wave_scene(sc, output, force, threads);
  ReportOptions o = coupled_report_options(sc, force);
  if (!output.empty()) o.output = output;
  std::printf("scene        %s (coupled chain, case %s)\n", sc.file.string().c_str(), o.case_name.c_str());
  return run_plan(resolve(o), Refuse{&*sc.coupled}, /*check_only=*/false);
}

}  // namespace strata::cases
