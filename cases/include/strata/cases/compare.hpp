#pragma once
/// Error against run time of one scene at several time-step ratios η, measured against a
/// reference scene of the same geometry (e.g. a coupled FEM–DEM model against an all-particle
/// one): `strata compare SCENE --reference REF --eta 1 2 4`.
///
/// Every run goes through scene::Run, like `strata run`. The two scenes must record the same
/// gauges ([probe] gauges: the mean displacement of a group of particles or FEM nodes, columns
/// <gauge>_ux, _uy, _uz of probes.csv). The error of one gauge is
///
///     e_g = max over the run's probe rows and the gauge's columns of |u(t) − u_ref(t)|
///           / max over the reference's rows and the same columns of |u_ref|,
///
/// with u_ref interpolated linearly in time at the run's probe times (rows outside the
/// reference's time span are left out); the error of a run is its worst gauge's. Run time is the time spent
/// stepping (probes included; the final checkpoint, summary and pictures not), the fastest of `repeats` runs.
#include <strata/scene/run.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace strata::cases {

struct CompareOptions {
  std::filesystem::path scene;                   ///< the scene studied (its solver.eta is replaced per run)
  std::filesystem::path reference;               ///< the reference scene: same geometry and gauges
  std::vector<std::string> overrides;            ///< `--set KEY=VALUE`, applied to both scenes
  std::vector<int> etas;                         ///< η values (>= 1); empty: the scene's own solver.eta
  std::filesystem::path output = "out/compare";  ///< compare.{csv,md,png}, summary.json, runs/
  int repeats = 1;                               ///< runs per point; the fastest is reported
  bool force = false;                            ///< run η values that strata would refuse
  bool no_plot = false;                          ///< leave out the PNG plots
};

/// One row of the table: the reference or one η.
struct CompareRow {
  std::string label;  ///< "reference" or "eta = 2"
  int eta = 0;        ///< 0 for the reference
  /// "completed"; "refused" (the scene cannot run at this η, see `note`); "failed" (the run
  /// blew up: `note` says where; its probes up to the failure are in `directory`).
  std::string status;
  std::string note;
  std::size_t particles = 0, fem_nodes = 0;
  std::int64_t steps = 0;
  double seconds = 0;                ///< stepping time, fastest of the repeats
  double error = 0;                  ///< the largest gauge error (see the file comment); 0 for the reference
  std::vector<double> gauge_errors;  ///< per gauge, in CompareResult::gauges order
  std::filesystem::path directory;   ///< the run's output folder
};

struct CompareResult {
  std::vector<std::string> gauges;  ///< gauge names (columns <gauge>_u<axis> of probes.csv)
  std::vector<CompareRow> rows;     ///< the reference first, then one row per η
  std::vector<std::filesystem::path> written;
  std::string markdown;  ///< the table as compare.md holds it
};

/// Shows the runs of a comparison; `begin` and `end` bracket each run, the RunObserver calls
/// of scene::Run come in between.
class CompareObserver : public scene::RunObserver {
 public:
  virtual void begin(const std::string& label, int repeat) { (void)label, (void)repeat; }
  virtual void end(const CompareRow& row) { (void)row; }
};

/// Runs the reference once per repeat and the scene at every η, then writes
/// compare.csv, compare.md, compare.png (error against run time), compare_gauges.png (the
/// gauge histories) and summary.json into `opt.output`, and each run's own outputs into
/// `opt.output`/runs/<label>. Throws strata::Error: Input for a scene that does not load,
/// a reference that cannot run, gauges missing from either scene, or when no η can run.
CompareResult compare_runs(const CompareOptions& opt, CompareObserver& observer);

/// The relative error of the columns `run[j]` (sampled at `run_time`) against `ref[j]`
/// (sampled at `ref_time`, increasing), j over the same columns: max |run − ref| over the
/// run's rows inside the reference's time span, over max |ref|. 0 when the reference is zero
/// everywhere and the run agrees; infinite when it does not, or a value is not finite.
double gauge_error(const std::vector<double>& ref_time, const std::vector<std::vector<double>>& ref,
                   const std::vector<double>& run_time, const std::vector<std::vector<double>>& run);

}  // namespace strata::cases
