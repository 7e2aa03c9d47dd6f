#pragma once
/// FEM–DEM coupling through a one-layer overlapping boundary with an integer time-step
/// ratio η (SPEC C3, seed 001):
///
///   FEM nodes and DEM particles are internal (I), boundary (B) or external (E); FEM B + E
///   coincide with DEM E + B. One system step = one FEM step of η·dt_DEM = η DEM steps.
///   At the start of every system step both sides copy displacement and velocity, with no
///   interpolation:  X_E(DEM) = X_B(FEM),  X_E(FEM) = X_B(DEM).
///   During the step each side moves its external DOFs with the copied velocity
///   (u_E(t) = u_E + v_E·(t − t_n)), then both advance from the same copied state.
///
/// Because both sides read the state at t_n (a Jacobi exchange), the serial order does not
/// matter and the parallel mode — each partition on its own thread, meeting at one barrier
/// per system step and exchanging only the overlap through double-buffered mailboxes —
/// gives bit-identical results (tested).
#include <strata/couple/partition.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace strata::couple {

/// One copied DOF: value of `from` on one side is prescribed on `to` of the other side.
struct Link {
  std::size_t from;
  std::size_t to;
};

/// The overlap: FEM boundary → DEM external, DEM boundary → FEM external.
struct Overlap {
  std::vector<Link> fem_to_dem;
  std::vector<Link> dem_to_fem;
};

/// Builds the overlap from per-DOF roles and a common id per DOF (global node id, or the
/// id of the coincident FEM node / particle centre from `preprocess`). Checks the SPEC rule
/// (every FEM B matches one DEM E, every DEM B one FEM E); throws strata::Error(Input).
Overlap make_overlap(const std::vector<std::int64_t>& fem_ids, const std::vector<Role>& fem_roles,
                     const std::vector<std::int64_t>& dem_ids, const std::vector<Role>& dem_roles);

enum class Execution { Serial, Parallel };
std::string to_string(Execution e);

/// The numbers behind the coupled step check.
struct CoupledStability {
  int eta = 1;
  double dt_dem = 0, dt_fem = 0;
  double dem_dt_crit = 0;           ///< DEM partition's own limit (externals held)
  double fem_explicit_dt_crit = 0;  ///< FEM partition's explicit limit
  double fem_dt_crit = 0;           ///< limit of the FEM integrator in use (+inf: implicit)
  std::string fem_integrator;
  bool ok = true;
  std::vector<std::string> problems;  ///< why not ok
  std::vector<std::string> notes;     ///< e.g. "implicit Newmark required at this η"
  std::string text() const;           ///< one paragraph for `strata check`
};

/// Checks each partition against its own limit: dt_DEM against the DEM limit; η·dt_DEM
/// against the FEM integrator's limit. When η·dt_DEM exceeds the FEM partition's explicit
/// limit it says so, and only the implicit Newmark is allowed.
CoupledStability coupled_stability(const Partition& fem, const Partition& dem, int eta);

/// Samples of one DOF over the run.
struct ProbeHistory {
  std::string name;
  std::vector<double> t, u;
};

class Coupler {
 public:
  /// `fem.dt()` must equal eta·`dem.dt()` (relative 1e-12). Declares the external DOFs.
  Coupler(Partition& fem, Partition& dem, Overlap overlap, int eta, Execution mode = Execution::Serial);

  /// Records displacement of a DOF after every step of its partition (and at t = 0).
  void probe_fem(std::size_t dof, std::string name);
  void probe_dem(std::size_t dof, std::string name);
  /// Calls `f(partition)` after every step of that partition (and once at t = 0, after
  /// initialise), on the thread that runs it: gauges that average several DOFs, energies.
  /// An observer must only read its own partition (in parallel mode the other one is moving).
  using Observer = std::function<void(const Partition&)>;
  void observe_fem(Observer f) { fem_obs_.push_back(std::move(f)); }
  void observe_dem(Observer f) { dem_obs_.push_back(std::move(f)); }

  /// Prepares both partitions (Partition::prepare), checks stability (throws
  /// strata::Error(Input) naming the limits unless allow_unstable), initialises both
  /// partitions and copies the initial overlap.
  void initialise(bool allow_unstable = false);
  /// Runs `system_steps` system steps (each: exchange, 1 FEM step, η DEM steps).
  void run(std::int64_t system_steps);

  const std::vector<ProbeHistory>& fem_probes() const { return fem_hist_; }
  const std::vector<ProbeHistory>& dem_probes() const { return dem_hist_; }
  const CoupledStability& stability() const { return stab_; }
  int eta() const { return eta_; }
  std::int64_t system_steps_done() const { return done_; }

 private:
  void record_fem();
  void record_dem();

  Partition& fem_;
  Partition& dem_;
  Overlap overlap_;
  int eta_;
  Execution mode_;
  CoupledStability stab_;
  std::vector<std::size_t> fem_probe_dofs_, dem_probe_dofs_;
  std::vector<ProbeHistory> fem_hist_, dem_hist_;
  std::vector<Observer> fem_obs_, dem_obs_;
  std::int64_t done_ = 0;
  bool initialised_ = false;
};

}  // namespace strata::couple
