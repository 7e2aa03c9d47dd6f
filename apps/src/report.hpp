#pragma once
/// `strata report chain6|metamaterial`: error-versus-run-time sweeps of the coupled chain
/// cases of SPEC C3 over η (serial and parallel), written as CSV, Markdown and a PNG plot.
#include <filesystem>
#include <string>
#include <vector>

namespace strata::app {

struct ReportOptions {
  std::string case_name;                         ///< "chain6" or "metamaterial"
  std::filesystem::path output = "out/report";   ///< directory for <case>_sweep.{csv,md,png}
  std::vector<int> etas{1, 2, 3, 4, 5, 10, 20};  ///< integer η >= 1
  std::string modes = "both";                    ///< serial, parallel or both
  double dt_dem = 0;                             ///< s; 0: case default (chain6 1e-4, metamaterial 5e-5)
  double duration = 0;                           ///< s; 0: case default (chain6 20, metamaterial 0.075)
  std::string fem_scheme;  ///< empty: case default (chain6 explicit-newmark, metamaterial implicit-newmark)
  double dt_ref = 1e-6;    ///< metamaterial reference step (implicit Newmark)
  double pulse_amplitude = 100;  ///< metamaterial half-sine pulse (N)
  double pulse_duration = 1e-3;  ///< s
  int repeats = 3;               ///< runs per point, fastest kept
  bool check_only = false;       ///< print the stability numbers and stop (exit 2 when unstable)
  bool no_plot = false;
};

/// Runs the sweep and writes the files; returns the exit status (throws strata::Error, e.g.
/// Input for an unstable dt_DEM, which main() maps to exit status 2).
int report_cmd(const ReportOptions& opt);

}  // namespace strata::app
