// `strata report wave`: reflection of a 1D strain pulse at a coupled FEM–DEM interface built
// from a geometry file (see wave_report.hpp): the sweep, its tables, plots and stability
// report, and the [coupled] scenes of case = "wave". One run is wave_model.cpp's run_wave.
#include <strata/cases/wave_report.hpp>

#include "case_helpers.hpp"
#include "wave_internal.hpp"

#include <nlohmann/json.hpp>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>
#include <strata/couple/dem_partition.hpp>
#include <strata/couple/fem_partition.hpp>
#include <strata/dem/lattice_elastic.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/io/render.hpp>
#include <strata/scene/files.hpp>
#include <strata/scene/run.hpp>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include <strata/cases/chain_report.hpp>
#include <strata/core/clock.hpp>
#include <strata/scene/frames.hpp>
#include <strata/scene/scene.hpp>

namespace strata::cases {

namespace {
namespace fs = std::filesystem;
using nlohmann::json;
}  // namespace
using namespace wave_detail;

namespace {

std::string markdown_table(const std::vector<WaveRun>& rows, double dem_dt_crit) {
  std::string s =
      "| λ/d | η | mode | FEM integrator | dt_DEM (s) | dt_FEM (s) | dt_FEM / DEM limit | FEM steps | "
      "DEM steps | incident peak (m/s) | R (peak) | tail before R window | R_E (energy) | T (peak) | "
      "T_E (energy) | R_E + T_E | set-up (ms) | wall time (ms) |\n"
      "|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rows) {
    const double ratio = r.dt_fem / dem_dt_crit;
    if (r.status != "ok") {
      const std::string what = r.status.substr(0, r.status.find(':'));
      s += fmt::format(
          "| {:g} | {} | {} | {} | {:.4g} | {:.4g} | {:.3g} | {} | {} | – | {} | | | | | | | {} |\n",
          r.lambda_d, r.eta, couple::to_string(r.mode), r.fem_scheme, r.dt_dem, r.dt_fem, ratio, r.fem_steps,
          r.dem_steps, what, r.wall_s > 0 ? fmt::format("{:.1f}", 1e3 * r.wall_s) : "");
      continue;
    }
    s += fmt::format(
        "| {:g} | {} | {} | {} | {:.4g} | {:.4g} | {:.3g} | {} | {} | {:.4f} | {:.2e} | {:.1e} | {:.2e} | "
        "{:.4f} | "
        "{:.4f} | {:.4f} | {:.1f} | {:.1f} |\n",
        r.lambda_d, r.eta, couple::to_string(r.mode), r.fem_scheme, r.dt_dem, r.dt_fem, ratio, r.fem_steps,
        r.dem_steps, r.incident, r.r_peak, r.floor, r.r_energy, r.t_peak, r.t_energy, r.r_energy + r.t_energy,
        1e3 * r.setup_s, 1e3 * r.wall_s);
  }
  return s;
}

// FEM | DEM | FEM: both interfaces' reflections, the pulse in the strip and after it.
std::string markdown_table_embedded(const std::vector<WaveRun>& rows, double dem_dt_crit) {
  std::string s =
      "| λ/d | η | mode | FEM integrator | dt_FEM (s) | dt_FEM / DEM limit | FEM steps | DEM steps | "
      "incident peak "
      "(m/s) | R at Γ1 (peak) | tail before R window | R2 at Γ2 (peak) | T1 in strip (peak) | T after Γ2 "
      "(peak) "
      "| R_E | R2_E | T_E after Γ2 | R_E + R2_E + T_E | wall time (ms) |\n"
      "|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rows) {
    const double ratio = r.dt_fem / dem_dt_crit;
    if (r.status != "ok") {
      s += fmt::format("| {:g} | {} | {} | {} | {:.4g} | {:.3g} | {} | {} | – | {} | | | | | | | | | {} |\n",
                       r.lambda_d, r.eta, couple::to_string(r.mode), r.fem_scheme, r.dt_fem, ratio,
                       r.fem_steps, r.dem_steps, r.status.substr(0, r.status.find(':')),
                       r.wall_s > 0 ? fmt::format("{:.1f}", 1e3 * r.wall_s) : "");
      continue;
    }
    s += fmt::format(
        "| {:g} | {} | {} | {} | {:.4g} | {:.3g} | {} | {} | {:.4f} | {:.2e} | {:.1e} | {:.2e} | {:.4f} | "
        "{:.4f} | "
        "{:.2e} | {:.2e} | {:.4f} | {:.4f} | {:.1f} |\n",
        r.lambda_d, r.eta, couple::to_string(r.mode), r.fem_scheme, r.dt_fem, ratio, r.fem_steps, r.dem_steps,
        r.incident, r.r_peak, r.floor, r.r2_peak, r.t_peak, r.exit_peak, r.r_energy, r.r2_energy,
        r.exit_energy, r.r_energy + r.r2_energy + r.exit_energy, 1e3 * r.wall_s);
  }
  return s;
}

double scheme_code(const std::string& s) {
  return s == "central-difference" ? 0 : s == "explicit-newmark" ? 1 : 2;
}

void plot_png(const io::PlotRequest& pr) {
  try {
    io::plot_xy(pr);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Unsupported) throw;
    log::warn("no plot: {}", e.what());
  }
}

}  // namespace

namespace {

// A gauge signal v(t) as a plot line, time in µs.
io::PlotSeries gauge_series(std::string name, const std::vector<double>& t, const std::vector<double>& v) {
  io::PlotSeries s{std::move(name), {}, {}, false, true};
  for (std::size_t i = 0; i < t.size(); ++i) {
    s.x.push_back(1e6 * t[i]);
    s.y.push_back(v[i]);
  }
  return s;
}

// 100·v(t) over the arrival window of a pulse of duration T that arrives at t_arrival
// (the window measure_arrival() reads), so that a small reflection shows beside the incident pulse.
io::PlotSeries window_series(std::string name, const std::vector<double>& t, const std::vector<double>& v,
                             double t_arrival, double T) {
  io::PlotSeries s{std::move(name), {}, {}, false, true};
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= t_arrival - kBefore * T && t[i] <= t_arrival + kAfter * T) {
      s.x.push_back(1e6 * t[i]);
      s.y.push_back(100 * v[i]);
    }
  return s;
}

/// The wave's plots: R against η per wavelength, and the gauge signals of one run.
void write_plots(const WaveModel& m, const WaveOptions& opt, const std::vector<WaveRun>& rows,
                 const std::vector<couple::Execution>& modes, const fs::path& dir) {
  io::PlotRequest pr;
  pr.title = "coupled FEM-DEM wave: reflection coefficient against eta";
  pr.x_label = "eta = dt_FEM / dt_DEM";
  pr.y_label = "R = reflected / incident peak velocity";
  pr.log_y = true;
  pr.png = dir / "wave_sweep.png";
  // R (and, embedded, R2) against η of each wavelength's runs in the first mode
  auto r_series = [&](std::string name, double l, double WaveRun::*peak) {
    io::PlotSeries s{std::move(name), {}, {}, true, true};
    for (const auto& r : rows)
      if (r.lambda_d == l && r.mode == modes.front() && r.status == "ok" && r.*peak > 0) {
        s.x.push_back(r.eta);
        s.y.push_back(r.*peak);
      }
    if (!s.x.empty()) pr.series.push_back(std::move(s));
  };
  for (double l : opt.wavelengths) {
    r_series(fmt::format("lambda = {:g} d", l), l, &WaveRun::r_peak);
    if (m.embedded) r_series(fmt::format("lambda = {:g} d, second interface (R2)", l), l, &WaveRun::r2_peak);
  }
  plot_png(pr);

  // gauge signals of the middle wavelength's run at the smallest η
  const double gl = opt.wavelengths[opt.wavelengths.size() / 2];
  const WaveRun* g = nullptr;
  for (const auto& r : rows)
    if (r.status == "ok" && r.lambda_d == gl && (!g || r.eta < g->eta)) g = &r;
  if (!g) return;
  io::PlotRequest gp;
  gp.title = fmt::format("gauge velocities: lambda = {:g} d, eta = {}, {}", g->lambda_d, g->eta,
                         couple::to_string(g->mode));
  gp.x_label = "time [us]";
  gp.y_label = "velocity along the propagation direction [m/s]";
  gp.png = dir / "wave_gauges.png";
  gp.series = {gauge_series("FEM gauge: incident, then reflected", g->t_fem, g->v_fem),
               gauge_series("DEM gauge: transmitted", g->t_dem, g->v_dem),
               window_series("FEM gauge, reflected window x 100", g->t_fem, g->v_fem, g->t_ref, g->pulse_T)};
  if (m.embedded) {
    gp.series.push_back(gauge_series("exit FEM gauge: after both interfaces", g->t_fem, g->v_exit));
    gp.series.push_back(window_series("FEM gauge, second interface's window x 100", g->t_fem, g->v_fem,
                                      g->t_ref2, g->pulse_T));
  }
  plot_png(gp);
}

std::string wave_stability_text(const WaveModel& m, const WaveOptions& opt, const WaveStability& s) {
  std::string out = fmt::format(
      "coupled steps: DEM leapfrog at dt_DEM = {:.4g} s ({:g} x the hex lattice's critical step {:.4g} s), "
      "FEM at eta*dt_DEM ({})\n",
      m.dt_dem, opt.dt_fraction, m.dem_dt_crit,
      opt.fem_scheme == "auto"
          ? "auto: central-difference up to the FEM explicit limit, implicit-newmark above"
          : opt.fem_scheme);
  if (!s.per_eta.empty()) {
    const auto& c = s.per_eta.front();
    out += fmt::format(
        "  DEM partition: limit {:.4g} s (libdem, overlap externals held; dt_DEM/limit = {:.3g}) -> {}\n",
        c.dem_dt_crit, c.dt_dem / c.dem_dt_crit, c.dt_dem <= c.dem_dt_crit ? "ok" : "UNSTABLE");
    out += fmt::format("  FEM partition: explicit limit {:.4g} s (rollers and overlap externals held)\n",
                       c.fem_explicit_dt_crit);
  }
  for (const auto& c : s.per_eta) {
    const bool refused = std::find(s.refused.begin(), s.refused.end(), c.eta) != s.refused.end();
    out += fmt::format(
        "  eta = {:>2}: dt_FEM = {:.4g} s = {:.3g} x the FEM explicit limit, {:.3g} x the DEM limit; {} -> "
        "{}\n",
        c.eta, c.dt_fem, c.dt_fem / c.fem_explicit_dt_crit, c.dt_fem / c.dem_dt_crit, c.fem_integrator,
        refused ? "REFUSED" : "ok");
    for (const auto& n : c.notes) out += "      note: " + n + "\n";
    for (const auto& p : c.problems) out += "      refused: " + p + "\n";
  }
  const std::size_t modes = opt.modes == "both" ? 2 : 1;
  out +=
      fmt::format("sweep: wavelengths {} d; eta = {}; modes {}; {} coupled runs x {} repeat{}",
                  fmt::join(opt.wavelengths, ", "), fmt::join(opt.etas, ", "), opt.modes,
                  opt.wavelengths.size() * opt.etas.size() * modes, opt.repeats, opt.repeats == 1 ? "" : "s");
  if (opt.frames > 0)
    out += fmt::format("; then a series run (serial, eta = {}, {} frames)", opt.series_eta, opt.frames);
  return out + "\n";
}

json wave_stability_json(const WaveModel& m, const WaveOptions& opt, const WaveStability& s) {
  json j = {{"case", "wave"},
            {"title", opt.title},
            {"geometry", m.geometry.string()},
            {"particles", m.particles},
            {"fem_nodes", m.fem_nodes},
            {"fem_elements", m.fem_elements},
            {"wave_speed_m_s", m.c},
            {"dt_dem_s", m.dt_dem},
            {"lattice_dt_limit_s", m.dem_dt_crit},
            {"fem_explicit_dt_limit_s", m.fem_explicit_dt},
            {"fem_scheme", opt.fem_scheme},
            {"wavelengths_d", opt.wavelengths},
            {"etas", opt.etas},
            {"modes", opt.modes},
            {"ok", s.problems.empty()}};
  j["per_eta"] = per_eta_json(s.per_eta);
  return j;
}

json finite_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

}  // namespace

WaveOptions wave_report_defaults(WaveOptions opt) {
  if (opt.embedded && !opt.quick) {
    if (opt.etas == kWaveEtas) opt.etas = kWaveEmbeddedEtas;
    if (opt.wavelengths == kWaveWavelengths) opt.wavelengths = kWaveEmbeddedWavelengths;
  }
  if (opt.quick) {
    opt.etas = {1, 5};
    opt.wavelengths = {20};
  }
  if (opt.frames < 0) opt.frames = opt.quick ? 3 : 12;
  return opt;
}

int wave_sweep(const WaveOptions& in, const WaveRefuse& refuse_at, bool json_out) {
  WaveOptions opt = in;
  // A refusal points at the scene key when there is one, else it is a plain Input error.
  // `key` is the field of the key the refusal names, e.g. &scene::CoupledTable::wavelengths.
  auto refuse = [&]<class T>(scene::Located<T> scene::CoupledTable::*key, const std::string& message) {
    if (refuse_at.table) (refuse_at.table->*key).fail(message);
    fail(ErrorKind::Input, "{}", message);
  };
  if (opt.frames < 0) opt.frames = 12;
  STRATA_CHECK(!opt.etas.empty(), Input, "report wave: no eta values");
  STRATA_CHECK(!opt.wavelengths.empty(), Input, "report wave: no wavelengths");
  STRATA_CHECK(opt.series_eta >= 1, Input, "report wave: --series-eta {} must be an integer >= 1",
               opt.series_eta);
  for (int e : opt.etas) STRATA_CHECK(e >= 1, Input, "report wave: eta = {} must be an integer >= 1", e);
  STRATA_CHECK(opt.modes == "serial" || opt.modes == "parallel" || opt.modes == "both", Input,
               "report wave: --modes {} (serial, parallel or both)", opt.modes);
  STRATA_CHECK(opt.fem_scheme == "auto" || opt.fem_scheme == "central-difference" ||
                   opt.fem_scheme == "explicit-newmark" || opt.fem_scheme == "pc-newmark" ||
                   opt.fem_scheme == "implicit-newmark",
               Input,
               "report wave: --fem-scheme {} (auto, central-difference, explicit-newmark, implicit-newmark)",
               opt.fem_scheme);
  STRATA_CHECK(opt.repeats >= 1, Input, "report wave: repeats = {} must be >= 1", opt.repeats);
  std::vector<couple::Execution> modes;
  if (opt.modes != "parallel") modes.push_back(couple::Execution::Serial);
  if (opt.modes != "serial") modes.push_back(couple::Execution::Parallel);

  const WaveModel m = [&]() -> WaveModel {
    try {
      return build_wave_model(opt);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Input || !refuse_at.table) throw;
      refuse(&scene::CoupledTable::geometry, e.what());
      throw;
    }
  }();
  for (double l : opt.wavelengths) {  // refuse a too long pulse before running
    try {
      (void)plan_of(m, opt, l);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Input) throw;
      refuse(&scene::CoupledTable::wavelengths, e.what());
    }
  }
  const std::string header1 = fmt::format(
      "2D coupled wave: {} ('{}' particles, '{}' FEM); {} particles of d = {:g} m (hex lattice, "
      "Kn = {:.4g} N/m, Ks = {:.4g} N/m, rho = {:g} kg/m^2), {} FEM nodes / {} linear triangles (plane "
      "stress, "
      "E = {:.4g} Pa, nu = {:.4f}); long-wave P speed c = {:.1f} m/s; preprocess {:.2f} s.\n"
      "dt_DEM = {:.4g} s = {:g} x the lattice's critical step {:.4g} s; FEM explicit limit (overlap held) "
      "{:.4g} s.\n"
      "Threads per partition: {}. Load: sin^2 traction pulse, incident peak velocity v0 = {:g} m/s, length "
      "lambda = c*T; rollers on "
      "both "
      "lateral sides. Gauges: FEM band {:.4g} m from the interface (load side {:.4g} m away), DEM column "
      "{:.4g} m "
      "into the particles (particle block {:.4g} m long). R, R_E: reflected/incident peak and energy at the "
      "FEM "
      "gauge; T, T_E: transmitted (DEM gauge) / incident. Matched impedance, 1D: R = 0, T = 1, R_E + T_E = "
      "1.\n",
      m.geometry.filename().string(), opt.particle_region, opt.fem_region, m.particles, m.d, m.kn, m.ks,
      m.rho, m.fem_nodes, m.fem_elements, m.E, m.nu, m.c, m.build_s, m.dt_dem, opt.dt_fraction, m.dem_dt_crit,
      m.fem_explicit_dt, opt.threads, opt.peak_velocity, m.fem_gauge_depth, m.load_depth, m.dem_gauge_depth,
      m.dem_length);
  const std::string header =
      header1 +
      (m.embedded ? fmt::format("FEM | DEM | FEM: exit region '{}' beyond a particle strip of D = {:.4g} m "
                                "({} row spacings); exit gauge {:.4g} m past the second interface (exit "
                                "block {:.4g} m deep). R: first interface, R2: second (at the FEM gauge "
                                "2D/c after R), T1: in the strip (DEM gauge), T: after both.\n",
                                m.overlap.fem.group_names.back(), m.dem_length,
                                std::lround(m.dem_length / m.overlap.layer_spacing), m.exit_gauge_depth,
                                m.exit_length)
                  : std::string());
  const WaveStability stab = wave_stability(m, opt);
  if (json_out) {
    std::printf("%s\n", wave_stability_json(m, opt, stab).dump(2).c_str());
  } else {
    if (!opt.title.empty()) std::printf("%s\n\n", opt.title.c_str());
    std::fputs(header.c_str(), stdout);
    std::fputs(wave_stability_text(m, opt, stab).c_str(), stdout);
  }
  std::fflush(stdout);
  if (opt.refuse_unstable_eta && !stab.problems.empty()) {
    std::string why;
    for (const auto& p : stab.problems) why += "\n  " + p;
    if (stab.dem_problem)
      refuse(&scene::CoupledTable::dt_fraction,
             fmt::format("dt_DEM = {:.4g} s is above the DEM partition's limit: lower "
                         "dt_fraction{}",
                         m.dt_dem, why));
    const std::string message = fmt::format(
        "eta = {} cannot run with fem_scheme = \"{}\": use \"auto\" or \"implicit-newmark\", or "
        "lower eta{}",
        fmt::join(stab.refused, ", "), opt.fem_scheme, why);
    if (opt.fem_scheme != "auto") refuse(&scene::CoupledTable::fem_scheme, message);
    refuse(&scene::CoupledTable::eta, message);
  }
  if (opt.check_only) return 0;

  // Everything is validated: run the whole sweep into a staging folder, then move its files
  // into the output folder all at once.
  const auto t0 = WallClock::now();
  scene::Staging stage(opt.output);
  const fs::path& dir = stage.path();
  std::vector<WaveRun> rows;
  for (double l : opt.wavelengths)
    for (int eta : opt.etas)
      for (auto mode : modes) {
        WaveRun best;
        for (int k = 0; k < opt.repeats; ++k) {
          WaveRun r = run_wave(m, opt, l, eta, mode, opt.fem_scheme);
          if (k == 0 || r.wall_s < best.wall_s) best = std::move(r);
          if (best.status != "ok") break;
        }
        if (best.status != "ok") log::warn("lambda = {} d, eta = {}: {}", l, eta, best.status);
        rows.push_back(std::move(best));
      }
  // serial and parallel must agree bit for bit (the Jacobi exchange); say so if they do not
  for (const auto& a : rows)
    for (const auto& b : rows)
      if (&a != &b && a.mode == couple::Execution::Serial && b.mode == couple::Execution::Parallel &&
          a.eta == b.eta && a.lambda_d == b.lambda_d && a.status == "ok" && b.status == "ok")
        STRATA_CHECK(
            a.v_fem == b.v_fem && a.v_dem == b.v_dem && a.dem_hash == b.dem_hash && a.fem_u == b.fem_u,
            Internal, "wave: serial and parallel runs differ at lambda = {} d, eta = {}", a.lambda_d, a.eta);

  {
    io::CsvWriter csv(dir / "wave_sweep.csv",
                      {"lambda_d",   "eta",       "mode",        "fem_scheme",   "ok",           "dt_dem_s",
                       "dt_fem_s",   "fem_steps", "dem_steps",   "v0_m_s",       "incident_m_s", "R_peak",
                       "tail_floor", "R_energy",  "T_peak",      "T_energy",     "setup_s",      "wall_s",
                       "R2_peak",    "R2_energy", "T_exit_peak", "T_exit_energy"});
    for (const auto& r : rows)
      csv.row({r.lambda_d,
               double(r.eta),
               r.mode == couple::Execution::Serial ? 0.0 : 1.0,
               scheme_code(r.fem_scheme),
               r.status == "ok"                    ? 1.0
               : r.status.rfind("refused", 0) == 0 ? 0.0
                                                   : -1.0,
               r.dt_dem,
               r.dt_fem,
               double(r.fem_steps),
               double(r.dem_steps),
               r.v0,
               r.incident,
               r.r_peak,
               r.floor,
               r.r_energy,
               r.t_peak,
               r.t_energy,
               r.setup_s,
               r.wall_s,
               r.r2_peak,
               r.r2_energy,
               r.exit_peak,
               r.exit_energy});
    csv.close();
  }
  const std::string md =
      header + "\n" +
      (m.embedded ? markdown_table_embedded(rows, m.dem_dt_crit) : markdown_table(rows, m.dem_dt_crit)) +
      "\nCSV codes: mode 0 serial, 1 parallel; fem_scheme 0 central-difference, 1 explicit-newmark, "
      "2 implicit-newmark; ok 1 = ok, 0 = refused by the coupler, -1 = unstable (a gauge above 2 v0) or blew "
      "up.\n";
  std::ofstream(dir / "wave_sweep.md") << md;
  std::fwrite(md.data() + header.size(), 1, md.size() - header.size(), stdout);

  // VTK series (and pictures) of one representative run: serial, η = series_eta, the longest pulse
  if (opt.frames > 0 && !STRATA_WITH_VTK)
    log::warn("no series: this build of strata leaves out STRATA_WITH_VTK");
  if (opt.frames > 0 && STRATA_WITH_VTK) {
    WaveSeries ws;
    ws.dir = dir / "series";
    ws.frames = opt.frames;
    ws.pictures = !opt.no_plot;
    const double l = *std::max_element(opt.wavelengths.begin(), opt.wavelengths.end());
    const WaveRun sr = run_wave(m, opt, l, opt.series_eta, couple::Execution::Serial, opt.fem_scheme, &ws);
    if (sr.status != "ok")
      log::warn("series run (lambda = {} d, eta = {}): {}", l, opt.series_eta, sr.status);
    std::printf("\nseries: lambda = %g d, eta = %d, serial: %d frames in %s (particles.pvd, fem.pvd)", l,
                opt.series_eta, opt.frames, (opt.output / "series").string().c_str());
    if (!ws.pngs.empty())
      std::printf("; %zu pictures in %s", ws.pngs.size(), (opt.output / "series" / "png").string().c_str());
    std::printf("\n");
  }
  if (!opt.no_plot) write_plots(m, opt, rows, modes, dir);

  json summary = {{"status", "completed"},
                  {"case", "wave"},
                  {"title", opt.title},
                  {"geometry", m.geometry.string()},
                  {"embedded", m.embedded},
                  {"dt_dem_s", m.dt_dem},
                  {"wave_speed_m_s", m.c},
                  {"fem_scheme", opt.fem_scheme},
                  {"wavelengths_d", opt.wavelengths},
                  {"etas", opt.etas},
                  {"modes", opt.modes},
                  {"wall_seconds", seconds_since(t0)}};
  if (!opt.scene.empty()) summary["scene"] = opt.scene.string();
  json jr = json::array();
  for (const auto& r : rows)
    jr.push_back({{"lambda_d", r.lambda_d},
                  {"eta", r.eta},
                  {"mode", couple::to_string(r.mode)},
                  {"fem_scheme", r.fem_scheme},
                  {"status", r.status},
                  {"R_peak", finite_or_null(r.r_peak)},
                  {"R_energy", finite_or_null(r.r_energy)},
                  {"T_peak", finite_or_null(r.t_peak)},
                  {"T_energy", finite_or_null(r.t_energy)},
                  {"R2_peak", finite_or_null(r.r2_peak)},
                  {"T_exit_peak", finite_or_null(r.exit_peak)},
                  {"wall_s", r.wall_s}});
  summary["rows"] = jr;
  std::ofstream(dir / "summary.json") << summary.dump(2) << "\n";

  const auto written = stage.commit(opt.output);
  std::printf("wrote:\n");
  for (const auto& f : written) std::printf("  %s\n", f.string().c_str());
  return 0;
}

int wave_report_cmd(const WaveOptions& opt) { return wave_sweep(wave_report_defaults(opt)); }

WaveOptions wave_scene_options(const scene::Scene& sc, bool force) {
  STRATA_CHECK(sc.coupled && sc.coupled->case_name == "wave", Internal,
               "wave_scene_options: {} is not a [coupled] scene with case = \"wave\"", sc.file.string());
  const scene::CoupledTable& c = *sc.coupled;
  const scene::OutputTable& out = sc.output;
  WaveOptions o;
  o.title = c.title;
  o.scene = sc.file;
  o.output = out.directory;
  o.no_plot = !out.render;
  o.geometry = c.geometry;
  o.particle_region = c.particle_region;
  o.fem_region = c.fem_region;
  o.exit_region = c.exit_region;
  o.embedded = c.embedded;
  if (c.eta.given) {
    o.etas.clear();
    for (std::int64_t e : c.eta.value) o.etas.push_back(static_cast<int>(e));
  } else {
    o.etas = o.embedded ? kWaveEmbeddedEtas : kWaveEtas;
  }
  o.wavelengths = c.wavelengths.given ? c.wavelengths.value
                  : o.embedded        ? kWaveEmbeddedWavelengths
                                      : kWaveWavelengths;
  o.modes = c.modes;
  o.fem_scheme = c.fem_scheme;
  o.d = c.diameter;
  o.dt_fraction = c.dt_fraction;
  o.fem_far_size = c.fem_far_size;
  o.fem_growth = c.fem_growth;
  o.peak_velocity = c.peak_velocity;
  o.frames = static_cast<int>(c.frames);
  o.series_eta = static_cast<int>(c.series_eta);
  o.repeats = c.repeats.given ? static_cast<int>(c.repeats) : 1;
  o.threads = c.threads.given ? static_cast<int>(c.threads) : WaveOptions{}.threads;
  o.refuse_unstable_eta = !force;
  return o;
}

int check_wave_scene(const scene::Scene& sc, bool json_out, bool force) {
  WaveOptions o = wave_scene_options(sc, force);
  o.check_only = true;
  if (!json_out) std::printf("scene        %s (coupled wave)\n", sc.file.string().c_str());
  return wave_sweep(o, WaveRefuse{&*sc.coupled}, json_out);
}

int run_wave_scene(const scene::Scene& sc, const fs::path& output, bool force, int threads) {
  WaveOptions o = wave_scene_options(sc, force);
  if (!output.empty()) o.output = output;
  if (threads >= 0) o.threads = threads;
  std::printf("scene        %s (coupled wave)\n", sc.file.string().c_str());
  return wave_sweep(o, WaveRefuse{&*sc.coupled});
}

}  // namespace strata::cases
