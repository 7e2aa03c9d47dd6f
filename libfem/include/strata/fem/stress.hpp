#pragma once
/// Element stress of the linear elastic elements from nodal displacements (small strain).
#include <strata/fem/mesh.hpp>

#include <array>
#include <cstddef>

#include <Eigen/Core>

namespace strata::fem {

/// Stress of element `e` of `block` under the global displacement vector `u` (mesh.dofs()
/// values, DOF i*dim + a), as the full symmetric tensor in Voigt order
/// (σxx, σyy, σzz, σyz, σxz, σxy), in Pa. Linear elements have one constant strain each:
///  - Tri3, Tet4: ε = B u_e from the shape-function gradients (the B that the stiffness
///    uses), σ = D ε (elasticity_matrix; for Tet4 that is σ = λ tr(ε) I + 2μ ε).
///    Tri3 plane stress has σzz = 0, plane strain σzz = ν(σxx + σyy).
///  - Bar: uniaxial σ = E ε_axial along the bar, σ = σ_axial n⊗n.
///  - Spring: zero (a spring has a stiffness but no cross-section).
/// Throws strata::Error(Input) for a degenerate element or a `u` of the wrong size.
std::array<double, 6> element_stress(const Mesh& mesh, const ElementBlock& block, std::size_t e,
                                     const Eigen::VectorXd& u);

}  // namespace strata::fem
