#pragma once
/// FEM–DEM coupling through overlapping domains with an integer time-step ratio η:
///
///   FEM nodes and DEM particles are internal (I), boundary (B) or external (E). The two
///   models overlap: a zone where both compute, each side's outermost DOFs (its externals)
///   lying inside the other side's domain. One system step = one FEM step of η·dt_DEM = η DEM
///   steps. At the start of every system step both sides transfer displacement and velocity:
///   X_E(DEM) = Σ w·X_B(FEM),  X_E(FEM) = Σ w·X_B(DEM), each external DOF a weighted sum of
///   the other side's boundary DOFs (one Link per external DOF). During the step each side moves its
///   external DOFs with the transferred velocity (u_E(t) = u_E + v_E·(t − t_n)), then both
///   advance from the same transferred state.
///
///   A coincident overlap (node on particle) is the special case of one source of weight 1:
///   the value is copied, bit for bit (make_overlap builds such links). An interpolating
///   overlap (preprocess::build_coupled_model, general path) uses the FEM shape functions at
///   a DEM external particle and a linear least-squares fit to the particles at an FEM
///   external node: both reproduce affine fields exactly (the patch property), so a rigid
///   motion or a uniform strain crosses the overlap unchanged.
///
/// Because both sides read the state at t_n (a Jacobi exchange), the serial order does not
/// matter and the parallel mode — each partition on its own thread, meeting at one barrier
/// per system step and exchanging only the transferred values through double-buffered
/// mailboxes — gives bit-identical results (tested). Each side evaluates the weighted sums
/// of its own boundary values, in the same order in both modes.
#include <strata/couple/partition.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace strata::couple {

/// One external DOF `to` of one side and where its value comes from on the other side:
/// with `sources` empty, a copy of DOF `from` (the value itself, bit for bit); otherwise the
/// weighted sum Σ weight[k]·value(sources[k]), in the order listed (interpolating overlaps;
/// `from` is then informative, e.g. sources[0]). A single source of weight exactly 1 is a
/// copy too.
struct Link {
  std::size_t from;
  std::size_t to;
  std::vector<std::size_t> sources;
  std::vector<double> weight;
};

/// The overlap: FEM boundary → DEM external, DEM boundary → FEM external.
struct Overlap {
  std::vector<Link> fem_to_dem;
  std::vector<Link> dem_to_fem;
};

/// Builds a copying overlap from per-DOF roles and a common id per DOF (global node id, or
/// the id of the coincident FEM node / particle centre from `preprocess`). Checks that every
/// FEM B matches one DEM E and every DEM B one FEM E; throws strata::Error(Input).
Overlap make_overlap(const std::vector<std::int64_t>& fem_ids, const std::vector<Role>& fem_roles,
                     const std::vector<std::int64_t>& dem_ids, const std::vector<Role>& dem_roles);

/// Links between points (particles, nodes) expanded to links between their DOFs: point p,
/// axis a is DOF p·dim + a, and every axis takes the point's sources and weights.
std::vector<Link> dof_links(const std::vector<Link>& point_links, int dim);

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
  /// `fem.dt()` must equal eta·`dem.dt()` (relative 1e-12). Declares the external DOFs (the
  /// `to` of the links). Throws strata::Error(Input) for a DOF out of range, a weight that
  /// is not finite, or a source that is itself external on its side (a transfer must read
  /// values its side computes).
  Coupler(Partition& fem, Partition& dem, Overlap overlap, int eta, Execution mode = Execution::Serial);

  /// Records displacement of a DOF after every step of its partition, and at t = 0 (or now,
  /// when the coupler is already initialised).
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
  /// partitions and transfers the initial overlap.
  void initialise(bool allow_unstable = false);
  /// Runs `system_steps` system steps (each: exchange, 1 FEM step, η DEM steps).
  void run(std::int64_t system_steps);

  const std::vector<ProbeHistory>& fem_probes() const { return fem_hist_; }
  const std::vector<ProbeHistory>& dem_probes() const { return dem_hist_; }
  const CoupledStability& stability() const { return stab_; }
  int eta() const { return eta_; }
  std::int64_t system_steps_done() const { return done_; }

  /// What the next exchange prescribes on one side's external DOFs, from the other side's
  /// state now (the same arithmetic as the exchange, so the same bits): for each external
  /// DOF, its displacement and velocity.
  struct Exchanged {
    std::vector<std::size_t> dof;
    std::vector<double> u, v;
  };
  Exchanged exchanged_to_dem() const { return exchanged(to_dem_, fem_); }
  Exchanged exchanged_to_fem() const { return exchanged(to_fem_, dem_); }
  /// The role of every DOF of the FEM side (or the DEM side) in the overlap: 0 internal,
  /// 1 boundary (a source of the other side's externals), 2 external.
  std::vector<std::uint8_t> fem_roles() const { return roles(fem_, to_fem_, to_dem_); }
  std::vector<std::uint8_t> dem_roles() const { return roles(dem_, to_dem_, to_fem_); }

 private:
  /// The links of one direction in compressed rows: external DOF to[k] takes
  /// Σ weight[j]·value(from[j]) over j in [first[k], first[k+1]); copy[k] when that is one
  /// source of weight 1.
  struct Transfer {
    std::vector<std::size_t> to, first, from;
    std::vector<double> weight;
    std::vector<char> copy;
    /// Displacement and velocity of every target (2 per target) from the source side.
    void gather(const Partition& src, std::vector<double>& out) const;
    /// Prescribes gathered values on the target side.
    void scatter(Partition& dst, const std::vector<double>& in) const;
  };
  static Exchanged exchanged(const Transfer& t, const Partition& src);
  static std::vector<std::uint8_t> roles(const Partition& side, const Transfer& into, const Transfer& out_of);
  static Transfer compile(const std::vector<Link>& links, const Partition& src, const Partition& dst,
                          const char* what);
  void exchange();
  void record_fem();
  void record_dem();

  Partition& fem_;
  Partition& dem_;
  Overlap overlap_;
  Transfer to_dem_, to_fem_;
  std::vector<double> buf_dem_, buf_fem_;
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
