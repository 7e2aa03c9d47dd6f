#pragma once
/// Error-versus-run-time sweeps of the coupled chain cases of Li et al. 2023 (the 6-DOF chain
/// and the 800-mass metamaterial chain) over η (serial and parallel), written as CSV,
/// Markdown, a PNG plot and summary.json. Two entry points share
/// one path: `strata report chain6|metamaterial [options]` and `strata check|run SCENE` of a
/// coupled-chain scene ([coupled], see docs/scene-reference.md). A [coupled] scene with
/// case = "wave" goes to the coupled wave's path instead (wave_report.hpp), through the same
/// check_coupled_scene / run_coupled_scene.
#include <strata/couple/coupler.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace strata::scene {
class Scene;
}

namespace strata::cases {

struct ReportOptions {
  std::string case_name;                         ///< "chain6" or "metamaterial"
  std::filesystem::path output = "out/report";   ///< directory for <case>_sweep.{csv,md,png}
  std::vector<int> etas{1, 2, 3, 4, 5, 10, 20};  ///< integer η >= 1
  std::string modes = "both";                    ///< serial, parallel or both
  double dt_dem = 0;                             ///< s; 0: case default (chain6 1e-4, metamaterial 4e-6)
  double duration = 0;                           ///< s; 0: case default (chain6 20, metamaterial 0.075)
  std::string fem_scheme;  ///< empty: case default (chain6 explicit-newmark, metamaterial implicit-newmark)
  double dt_ref = 1e-6;    ///< metamaterial reference step (implicit Newmark)
  double pulse_amplitude = 100;  ///< metamaterial half-sine pulse (N)
  double pulse_duration = 1e-3;  ///< s
  int repeats = 3;               ///< runs per point, fastest kept
  bool check_only = false;       ///< print the stability numbers and stop (exit 2 when unstable)
  bool no_plot = false;
  /// Refuse the whole sweep (exit 2, before it starts) when an η point would be refused (η·dt_DEM
  /// above the explicit FEM limit or the DEM partition's, the exchange's). Otherwise the
  /// metamaterial table shows such points as "refused"; chain6 is always refused as a whole.
  bool refuse_unstable_eta = false;
  /// Run the points that would be refused anyway (allow_unstable in their scenes), to see them
  /// blow up: their rows read "blew up at t = …" (`strata report --run-unstable`, `strata run
  /// --force`). An unstable dt_DEM is refused all the same.
  bool run_unstable = false;
  std::string title;            ///< shown in the Markdown header and summary.json
  std::filesystem::path scene;  ///< the scene file (summary.json); empty for `strata report`
};

/// `strata report`: prints the stability numbers, runs the sweep and writes the files; returns
/// the exit status. Throws strata::Error, e.g. Input for an unstable dt_DEM, which main() maps
/// to exit status 2; nothing is written then, and the files appear in `output` all at once.
int report_cmd(const ReportOptions& opt);

/// The per-η stability checks of a coupled sweep as JSON (`strata check --json`,
/// summary.json): step, limits, integrator, ok, problems, notes.
nlohmann::json per_eta_json(const std::vector<couple::CoupledStability>& per_eta);

/// The report options of a coupled-chain scene ([coupled], case chain6 or metamaterial);
/// output is the scene's output.directory, no_plot is !output.render, refuse_unstable_eta is
/// !force and run_unstable is force.
ReportOptions coupled_report_options(const scene::Scene& sc, bool force);

/// [coupled].threads of a coupled scene, or its case's default (chains 0 = all, wave 1).
int coupled_threads(const scene::Scene& sc);

/// `strata check SCENE` of a coupled scene: the stability numbers per partition and per η;
/// throws Input (exit 2) at the scene key (file:line:col) when dt_DEM or an η is unstable
/// (the wave: when the coupler would refuse an η, unless `force`).
int check_coupled_scene(const scene::Scene& sc, bool json, bool force);

/// `strata run SCENE` of a coupled scene: the same checks, then the sweep, written to
/// `output` (empty: the scene's output.directory) through a staging folder. `threads` >= 0
/// (`strata run --threads`) overrides [coupled].threads.
int run_coupled_scene(const scene::Scene& sc, const std::filesystem::path& output, bool force,
                      int threads = -1);

}  // namespace strata::cases
