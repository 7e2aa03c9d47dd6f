#pragma once
/// Finite strain of a particle model from where its particles started and where they are:
/// the shear zones (faults, shear bands) of granular or broken material, where bonds no longer
/// trace them.
#include <array>
#include <vector>

namespace strata::dem {

/// Maximum shear strain of each particle of a 2D model (z ignored). For particle i the
/// deformation gradient F is the least-squares map of the start offsets X_j − X_i of its
/// neighbours (the particles within `radius` of it at the start) onto their offsets now; the
/// principal stretches λ1 ≥ λ2 of F (square roots of the eigenvalues of FᵀF) give
/// γ = ln(λ1/λ2), which is ε1 − ε2, the engineering shear strain on the planes of greatest
/// shear, for small strains and stays finite for large ones. Rigid motion gives 0. A particle
/// with fewer than two neighbours, or neighbours on one line, gets 0. Linear in the number of
/// particles (a cell grid of side `radius`); deterministic.
std::vector<double> shear_strain_2d(const std::vector<std::array<double, 3>>& start,
                                    const std::vector<std::array<double, 3>>& now, double radius);

}  // namespace strata::dem
