#pragma once
/// Critical time steps of explicit schemes from element eigenvalues (a rigorous bound) and
/// from the global highest frequency (Lanczos, for reporting), with Rayleigh damping.
///
/// Why element eigenvalues and not h/c: for linear triangles and tetrahedra the exact
/// element limit is only 0.67–0.92 of h_min/c (c = √((λ+2μ)/ρ), the dilatational wave
/// speed; the ratio depends on the element's shape and ν), so h/c is not conservative
/// (tests/fem/test_fem_dynamics.cpp shows it on irregular meshes).
/// The element bound: split every node's lumped mass among the elements that share it
/// (M = Σ_e M_e*); then uᵀKu = Σ_e uᵀK_e u ≤ Σ_e λ_e uᵀM_e* u ≤ (max_e λ_e)·uᵀMu, so
/// ω²_max ≤ max_e λmax(K_e, M_e*). Each element's share is its own lumped mass where every
/// element at the node has mass; otherwise (springs, point masses) it is proportional to the
/// element's diagonal stiffness at the node (this gives the Gershgorin row-sum bound for
/// spring networks).
#include <strata/fem/assembly.hpp>
#include <strata/fem/mesh.hpp>

#include <vector>

namespace strata::fem {

/// Damping ratio of Rayleigh damping C = alpha·M + beta·K in a mode of frequency omega.
inline double rayleigh_damping_ratio(double omega, double alpha, double beta) {
  return alpha / (2 * omega) + beta * omega / 2;
}

/// Critical step of the explicit schemes (central difference; the explicit predictor-
/// corrector Newmark with gamma = 1/2) for highest frequency omega_max with Rayleigh damping:
/// (2/ω)(√(1+ξ²) − ξ), ξ = ξ(ω_max). The limit decreases with ω for any alpha, beta >= 0,
/// so an upper bound of ω_max gives a conservative step.
double explicit_dt_crit(double omega_max, double alpha = 0, double beta = 0);

/// Upper bound of ω²_max of the (undamped) system from element eigenvalues (see file
/// comment). `mass` is the assembled lumped mass per DOF; DOFs with `constrained[d] != 0`
/// (fixed or prescribed) are left out (may be empty: none). Throws strata::Error(Input) when
/// a free DOF with stiffness has no mass.
double element_omega2_bound(const Mesh& mesh, const Eigen::VectorXd& mass,
                            const std::vector<char>& constrained = {});

/// Largest eigenvalue of M⁻¹K found by Lanczos on M^{-1/2} K M^{-1/2} (full
/// reorthogonalisation, deterministic start vector); constrained DOFs are removed.
struct LanczosResult {
  double omega_max = 0;  ///< sqrt of the largest Ritz value (a lower bound, converging up)
  double residual = 0;   ///< |A y − θ y| of the Ritz pair: an eigenvalue lies within it of θ
  int iterations = 0;
};
/// `constrained[d] != 0` marks DOFs held by boundary conditions (may be empty: none).
LanczosResult omega_max_lanczos(const SparseMatrix& K, const Eigen::VectorXd& mass,
                                const std::vector<char>& constrained = {}, int max_iterations = 300,
                                double tolerance = 1e-10);

/// The usual (non-conservative for Tri3/Tet4) estimate min over elements of h/c, with h the
/// shortest edge (Tri3/Tet4) or length (Bar) and c the P-wave speed; springs are skipped.
/// For comparison and documentation only.
double h_over_c_dt(const Mesh& mesh);

}  // namespace strata::fem
