#pragma once
// Internal to libfem: the strain–displacement matrix B of the constant-strain elements,
// shared by element_matrices() (K = Bᵀ D B · measure) and element_stress() (σ = D B u_e).
#include <strata/fem/mesh.hpp>

#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

namespace strata::fem {

// B of one Tri3 or Tet4 element, and its area (Tri3) or volume (Tet4).
// Rows are Voigt strains with engineering shear: (εxx, εyy, γxy) for Tri3,
// (εxx, εyy, εzz, γyz, γxz, γxy) for Tet4; columns the local DOFs in (node, component)
// order, so B is 3x6 (Tri3) or 6x12 (Tet4). Sized at run time, stored on the stack.
struct StrainDisplacement {
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor, 6, 12> B;
  double measure = 0;  // area (m²) of a Tri3, volume (m³) of a Tet4
};

// B and measure of element `e` of a Tri3 or Tet4 `type` block with global node ids `node`
// (the element's nodes_per_element(type) entries). Throws strata::Error(Input) for a
// zero-area or zero-volume element.
StrainDisplacement strain_displacement(const Mesh& mesh, ElementType type, std::size_t e,
                                       const std::int32_t* node);

}  // namespace strata::fem
