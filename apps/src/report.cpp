// `strata report`: error against run time of the coupled chain cases (SPEC C3).
#include "report.hpp"

#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/couple/chains.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>

namespace strata::app {

namespace {

double mode_code(const std::string& m) { return m == "serial" ? 0 : m == "parallel" ? 1 : 2; }

void write_outputs(const ReportOptions& opt, const std::vector<couple::SweepRow>& rows,
                   const std::string& header) {
  std::filesystem::create_directories(opt.output);
  const std::string stem = opt.case_name + "_sweep";
  {
    io::CsvWriter csv(opt.output / (stem + ".csv"),
                      {"eta", "mode", "dt_dem_s", "dt_fem_s", "fem_steps", "dem_steps", "err_max_m",
                       "err_rms_m", "ref_max_m", "wall_s"});
    for (const auto& r : rows)
      csv.row({double(r.eta), mode_code(r.mode), r.dt_dem, r.dt_fem, double(r.fem_steps), double(r.dem_steps),
               r.err_max, r.err_rms, r.ref_max, r.wall_s});
    csv.close();
  }
  const std::string md = header + "\n" + couple::sweep_markdown(rows) +
                         "\nmode column of the CSV: 0 serial, 1 parallel, 2 monolithic baseline.\n";
  std::ofstream(opt.output / (stem + ".md")) << md;
  std::fwrite(md.data(), 1, md.size(), stdout);
  if (opt.no_plot) return;
  io::PlotRequest pr;
  pr.title = opt.case_name + ": error against run time over eta";
  pr.x_label = "wall time [s]";
  pr.y_label = "max error [m]";
  pr.log_x = pr.log_y = true;
  pr.png = opt.output / (stem + ".png");
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

}  // namespace

int report_cmd(const ReportOptions& opt) {
  STRATA_CHECK(opt.case_name == "chain6" || opt.case_name == "metamaterial", Input,
               "report: unknown case '{}' (chain6 or metamaterial)", opt.case_name);
  for (int e : opt.etas) STRATA_CHECK(e >= 1, Input, "report: eta = {} must be an integer >= 1", e);
  STRATA_CHECK(opt.modes == "serial" || opt.modes == "parallel" || opt.modes == "both", Input,
               "report: --modes {} (serial, parallel or both)", opt.modes);
  couple::SweepOptions so;
  so.etas = opt.etas;
  so.modes.clear();
  if (opt.modes != "parallel") so.modes.push_back(couple::Execution::Serial);
  if (opt.modes != "serial") so.modes.push_back(couple::Execution::Parallel);
  so.dt_dem = opt.dt_dem;
  so.duration = opt.duration;
  so.dt_ref = opt.dt_ref;
  so.repeats = opt.repeats;
  so.pulse = {opt.pulse_amplitude, opt.pulse_duration};

  if (opt.case_name == "metamaterial") {
    const double dt = opt.dt_dem > 0 ? opt.dt_dem : 5e-5;
    const couple::MetamaterialStability st = couple::metamaterial_stability();
    std::printf("%s\n", st.text(dt).c_str());
    couple::check_metamaterial_dt(dt);  // Input error (exit 2) at the paper's 1e-4 s
    if (opt.check_only) return 0;
    so.fem_scheme = fem::scheme_from_string(opt.fem_scheme.empty() ? "implicit-newmark" : opt.fem_scheme);
    const auto rows = couple::sweep_metamaterial(so);
    write_outputs(
        opt, rows,
        fmt::format("metamaterial chain (SPEC C3): FEM {} at eta*dt_DEM, DEM velocity Verlet at dt_DEM = "
                    "{:.3g} s; half-sine pulse {} N for {:.3g} s on outer mass 1; {:.3g} s simulated; "
                    "error of DEM mass 250 against monolithic implicit Newmark at dt = {:.3g} s",
                    fem::to_string(so.fem_scheme), dt, opt.pulse_amplitude, opt.pulse_duration,
                    opt.duration > 0 ? opt.duration : 0.075, opt.dt_ref));
    return 0;
  }
  if (opt.check_only) return 0;
  so.fem_scheme = fem::scheme_from_string(opt.fem_scheme.empty() ? "explicit-newmark" : opt.fem_scheme);
  const auto rows = couple::sweep_chain6(so);
  write_outputs(
      opt, rows,
      fmt::format("6-DOF chain (SPEC C3): FEM {} at eta*dt_DEM, DEM velocity Verlet at dt_DEM = {:.3g} s; "
                  "{:.3g} s simulated; error of m3 against the exact modal solution",
                  fem::to_string(so.fem_scheme), opt.dt_dem > 0 ? opt.dt_dem : 1e-4,
                  opt.duration > 0 ? opt.duration : 20.0));
  return 0;
}

}  // namespace strata::app
