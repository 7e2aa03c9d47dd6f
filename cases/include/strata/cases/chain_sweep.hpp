#pragma once
/// The η sweeps of the coupled chains of Li, Jin, Wang, Pan & Yang (2023): each point is a
/// network scene ([network]: the chain's masses and springs, its split into an FEM part and a
/// particle part, the load) run through scene::Run; what is special about the chains is
/// analysis here: the probe's samples against the exact modal solution (the 6-DOF chain) or a
/// monolithic implicit Newmark run at a small step (the metamaterial chain), and the run time.
#include <strata/couple/chains.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace strata::cases {

/// One run of a sweep: error against the exact/reference answer and wall time.
struct SweepRow {
  std::string case_name;
  int eta = 1;
  std::string mode;  ///< serial / parallel / monolithic
  double dt_dem = 0, dt_fem = 0;
  std::int64_t dem_steps = 0, fem_steps = 0;
  double err_max = 0;  ///< max |u − u_ref| over the run (m)
  double err_rms = 0;  ///< RMS of u − u_ref over the samples (m)
  double ref_max = 0;  ///< max |u_ref| (m): divide for relative errors
  double wall_s =
      0;  ///< set-up of the model (scene to initialised partitions) + its steps, best of `repeats`
  std::string probe;  ///< what was compared
  /// Empty: the run completed. "refused": the scene refused the point (unstable step);
  /// "blew up": the run's energy check stopped it at `stopped_at` (s), the energy of both
  /// parts having grown past 10 × the work of the loads (the errors are then those up to
  /// the last sample before the stop, and no answer).
  std::string status;
  double stopped_at = 0;
  std::vector<double> t, u, u_ref;  ///< the samples (kept for plots)
};

struct SweepOptions {
  std::vector<int> etas{1, 2, 3, 4, 5, 10, 20};
  std::vector<couple::Execution> modes{couple::Execution::Serial, couple::Execution::Parallel};
  double dt_dem = 0;    ///< 0: case default (chain6 1e-4 s; metamaterial 4e-6 s)
  double duration = 0;  ///< 0: case default (chain6 20 s; metamaterial 75 ms)
  fem::Scheme fem_scheme = fem::Scheme::ExplicitNewmark;  ///< of the FEM part
  double dt_ref = 1e-6;                                   ///< metamaterial reference step (implicit Newmark)
  int repeats = 1;                                        ///< runs per point; the fastest is kept
  bool keep_samples = false;
  bool run_unstable = false;  ///< run points above a limit anyway (allow_unstable), to see them blow up
  couple::MetamaterialParams pulse;
};

/// The network scene of one coupled point: `model` split into `fem_nodes` and `dem_nodes`, the
/// FEM part at η·dt_dem with `scheme`, `steps` particle steps, `probe` listed in probe_nodes,
/// no pictures; with `allow_unstable` a step above a limit runs anyway. Every number is written
/// so that it reads back to the same double.
std::string chain_scene_text(const std::string& title, const couple::ChainModel& model,
                             const std::vector<std::int64_t>& fem_nodes,
                             const std::vector<std::int64_t>& dem_nodes, std::int64_t probe, double dt_dem,
                             int eta, couple::Execution mode, fem::Scheme scheme, std::int64_t steps,
                             bool allow_unstable = false);

std::vector<SweepRow> sweep_chain6(const SweepOptions& o);
std::vector<SweepRow> sweep_metamaterial(const SweepOptions& o);

/// Markdown table (η, mode, dt_DEM, dt_FEM, steps, max error, RMS error, relative max, wall time).
std::string sweep_markdown(const std::vector<SweepRow>& rows);

}  // namespace strata::cases
