#pragma once
/// Stability limits of the time integrators libfem offers (used by the DEM and the coupled
/// driver too, since a bonded lattice is a spring network with lumped mass).
#include <cmath>

namespace strata::fem {

/// Largest stable step of the explicit central-difference scheme for the highest mode of a
/// system, with circular frequency `omega` (rad/s) and damping ratio `xi` in that mode:
/// dt_crit = (2/omega)(sqrt(1 + xi^2) - xi)  (Belytschko, Liu & Moran, Nonlinear Finite
/// Elements, eq. 6.3.22). Damping lowers the limit; xi = 0 gives 2/omega.
inline double central_difference_dt_crit(double omega, double xi = 0.0) {
  return 2.0 / omega * (std::sqrt(1.0 + xi * xi) - xi);
}

/// Largest stable step of Newmark's scheme with parameters beta, gamma for an undamped mode
/// of frequency `omega`: unconditionally stable (returns +inf) when 2*beta >= gamma >= 1/2;
/// otherwise omega*dt <= 1/sqrt(gamma/2 - beta) (Hughes, The Finite Element Method, 1987,
/// ch. 9). With a lumped mass and the predictor-corrector form of Li, Jin, Wang, Pan & Yang
/// (2023), where a_{n+1} = M⁻¹(F − K ũ − C ṽ) at the predicted state, the scheme is explicit
/// and the limit is omega*dt <= 2 for gamma = 1/2 whatever beta: call with beta = 0 for that
/// case.
inline double newmark_dt_crit(double omega, double beta, double gamma) {
  if (gamma >= 0.5 && 2.0 * beta >= gamma) return INFINITY;
  return 1.0 / (omega * std::sqrt(gamma / 2.0 - beta));
}

}  // namespace strata::fem
