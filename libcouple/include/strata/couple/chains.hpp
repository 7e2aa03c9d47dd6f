#pragma once
/// The chain cases of Li, Jin, Wang, Pan & Yang (2023), "Parallel computing method of
/// FEM–DEM with multiple-time step based on overlapping boundary" (their η sweeps, behind
/// `strata report`, run them as scenes: cases/chain_sweep.hpp):
///  - the 6-DOF chain wall–k1–m1–…–k6–m6 (k = 1 N/m, m = 1 kg, P·sin(ωt) on m2, P = 1 N,
///    ω = π/2; FEM m1..m4, DEM m3..m6) against its exact modal solution;
///  - the metamaterial chain (800 outer masses, 200 resonators) against a monolithic implicit
///    Newmark reference at a small step.
/// Both are split into an FEM partition (libfem, spring elements + point masses) and a DEM
/// partition (SpringNetworkPartition, velocity Verlet) that overlap by one layer.
#include <strata/couple/coupler.hpp>
#include <strata/couple/fem_partition.hpp>
#include <strata/couple/spring_partition.hpp>
#include <strata/fem/solver.hpp>

#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace strata::couple {

/// A sinusoidal force on one node: amplitude·sin(2π t / period) from t = 0 until `end`
/// (0: no end), zero after. A half-sine pulse of length T is period = 2T, end = T.
struct SineLoad {
  std::size_t node = 0;
  double amplitude = 0;  ///< N
  double period = 1;     ///< s
  double end = 0;        ///< s; 0: for ever
  double operator()(double t) const {
    return t >= 0 && (end <= 0 || t <= end) ? amplitude * std::sin(2 * M_PI * t / period) : 0.0;
  }
};

/// A whole (monolithic) 1-DOF-per-node network with loads, before splitting.
struct ChainModel {
  SpringNetwork net;
  std::vector<SineLoad> loads;
};

/// The two partitions of a ChainModel, their roles and the overlap.
struct CoupledChain {
  std::unique_ptr<FemPartition> fem;
  std::unique_ptr<SpringNetworkPartition> dem;
  std::vector<std::int64_t> fem_global, dem_global;  ///< local DOF -> global node
  std::vector<Role> fem_roles, dem_roles;
  Overlap overlap;
  std::size_t fem_local(std::int64_t global) const;
  std::size_t dem_local(std::int64_t global) const;
};

struct SplitSettings {
  double dt_dem = 1e-4;
  int eta = 1;
  fem::Scheme fem_scheme = fem::Scheme::ExplicitNewmark;
  bool allow_unstable = false;
};

/// Splits `model` into FEM nodes `fem_nodes` and DEM nodes `dem_nodes`, which must overlap by
/// one layer. Roles: an overlap node linked to a DEM-only node is FEM external / DEM
/// boundary; one linked to an FEM-only node is FEM boundary / DEM external. Springs go to
/// every partition holding both ends (so the overlap spring is in both); loads go to the
/// partition that owns the node. Throws strata::Error(Input) if the overlap is not one layer.
CoupledChain split_chain(const ChainModel& model, const std::vector<std::int64_t>& fem_nodes,
                         const std::vector<std::int64_t>& dem_nodes, const SplitSettings& s);

/// A monolithic libfem solver of the whole model (walls as fixed nodes).
fem::Solver monolithic_solver(const ChainModel& model, const fem::SolverSettings& s);

// ---- the 6-DOF chain ----------------------------------------------------------------

/// The 6-DOF chain (global nodes 0..5 = m1..m6). FEM nodes {0,1,2,3}, DEM {2,3,4,5}.
ChainModel chain6_model();
/// Exact displacement of every mass, from rest, by modal superposition:
/// q_j(t) = p_j/(ω_j² − Ω²)·(sin Ωt − (Ω/ω_j) sin ω_j t), u = Σ φ_j q_j (M = I).
class Chain6Exact {
 public:
  Chain6Exact();
  /// Displacement of mass `i` (0-based: 0 = m1) at time t.
  double u(int i, double t) const;
  const Eigen::VectorXd& omega() const { return w_; }

 private:
  Eigen::MatrixXd phi_;
  Eigen::VectorXd w_, p_;
};

// ---- the metamaterial chain ---------------------------------------------------------

/// The "metamaterial" chain: outer masses 1..800 (global 0..799, m_s = 0.05 kg, k_n =
/// 7.8e6 N/m between neighbours), outer mass 800 tied to a wall by k_n, resonators (global
/// 800..999, m_v = 0.05 kg, k_s = 2.49e6 N/m) on outer masses 101..300. A half-sine force
/// pulse P(t) = amplitude·sin(π t / duration), 0 <= t <= duration, on outer mass 1 (free end);
/// the paper shows its pulse only in a figure, so amplitude and duration are strata's.
struct MetamaterialParams {
  double pulse_amplitude = 100;  ///< N
  double pulse_duration = 1e-3;  ///< s
};
ChainModel metamaterial_model(const MetamaterialParams& p = {});
/// FEM: outer 1..300 + resonators, plus outer 301 as external; DEM: outer 301..800, plus
/// outer 300 as external. Overlap: outer 300 and 301 and the spring between them.
std::vector<std::int64_t> metamaterial_fem_nodes();
std::vector<std::int64_t> metamaterial_dem_nodes();
/// Global node of "DEM mass n" (1-based among the 500 DEM outer masses): outer 300 + n.
std::int64_t metamaterial_dem_mass(int n);

/// Stability numbers of the metamaterial chain at a DEM step.
struct MetamaterialStability {
  double omega_whole = 0;        ///< exact ω_max of the whole chain (Lanczos) (rad/s)
  double dt_whole = 0;           ///< 2/ω_whole: explicit limit of a monolithic explicit run
  double omega_whole_bound = 0;  ///< element (Gershgorin) bound of the whole chain
  double omega_dem = 0;          ///< DEM partition bound 2√(k_n/m_s) (rad/s)
  double dt_dem_crit = 0;        ///< 2/omega_dem
  double omega_fem = 0;          ///< FEM partition exact ω_max (externals held)
  double dt_fem_explicit = 0;
  std::string text(double dt_dem) const;
};
MetamaterialStability metamaterial_stability();
/// Throws strata::Error(Input) when dt_dem exceeds the stable limit, naming the limits
/// (7.68e-5 s whole chain; 8.0e-5 s DEM partition alone): what `strata check` reports for
/// the paper's dt_DEM = 1e-4 s, which is unstable for any explicit scheme.
void check_metamaterial_dt(double dt_dem, bool allow_unstable = false);

}  // namespace strata::couple
