#pragma once
/// Element kernels: stiffness matrix and lumped mass of one linear elastic element.
/// Small stateless functions with no virtual dispatch; the assembly loop calls
/// element_matrices().
#include <strata/fem/mesh.hpp>

#include <cstdint>

namespace strata::fem {

/// Largest local DOF count (Tet4 in 3D: 4 nodes x 3).
inline constexpr int kMaxElementDofs = 12;

/// Stiffness and lumped mass of one element.
struct ElementMatrices {
  int nd = 0;                                       ///< local DOFs = nodes_per_element * dim
  double K[kMaxElementDofs][kMaxElementDofs] = {};  ///< local stiffness, DOF order (node, component)
  double m[4] = {};                                 ///< lumped mass per element node (kg)
  std::int32_t node[4] = {};                        ///< global node ids
};

/// Computes the stiffness and lumped mass of element `e` of `block`.
/// Spring/Bar: k·[n nᵀ, −n nᵀ; −n nᵀ, n nᵀ] with n the unit node-to-node vector (n = +x in 1D).
/// Tri3: t·A·Bᵀ D B (constant strain), mass ρ·t·A/3 per node.
/// Tet4: V·Bᵀ D B, mass ρ·V/4 per node.
/// Throws strata::Error(Input) for degenerate (zero length/area/volume) or inverted elements.
void element_matrices(const Mesh& mesh, const ElementBlock& block, std::size_t e, ElementMatrices& out);

/// Length L of a two-node element (nodes a -> b) and its unit axis n (normalised when
/// L > 0 in 2D/3D; +x in 1D, where springs act along x whatever their length).
double two_node_axis(const Mesh& mesh, std::int32_t a, std::int32_t b, double n[3]);

/// Elasticity matrix (Voigt, engineering shear strain) of a block: 3x3 for Tri3 (plane
/// stress or strain), 6x6 for Tet4. Written into D (row-major, size 9 or 36).
void elasticity_matrix(const Material& m, ElementType t, double* D);

/// Dilatational (P-) wave speed of a material as used by a Tri3/Tet4 block:
/// 3D and plane strain sqrt((λ+2μ)/ρ); plane stress sqrt(E/(ρ(1−ν²))). Bar: sqrt(E/ρ).
double p_wave_speed(const Material& m, ElementType t);

}  // namespace strata::fem
