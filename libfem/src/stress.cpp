#include <strata/core/error.hpp>
#include <strata/fem/element.hpp>
#include <strata/fem/stress.hpp>

#include "strain_displacement.hpp"

#include <Eigen/Core>

namespace strata::fem {

std::array<double, 6> element_stress(const Mesh& mesh, const ElementBlock& block, std::size_t e,
                                     const Eigen::VectorXd& u) {
  STRATA_CHECK(static_cast<std::size_t>(u.size()) == mesh.dofs(), Input,
               "element_stress: displacement vector has {} values, the mesh has {} DOFs", u.size(),
               mesh.dofs());
  const int npe = nodes_per_element(block.type), dim = mesh.dim;
  const Material& mat = block.material;
  std::int32_t node[4] = {};
  for (int a = 0; a < npe; ++a)
    node[a] = block.conn[e * static_cast<std::size_t>(npe) + static_cast<std::size_t>(a)];
  auto U = [&](int a, int c) { return u[static_cast<Eigen::Index>(node[a]) * dim + c]; };
  std::array<double, 6> sigma{};

  switch (block.type) {
    case ElementType::Spring:
      return sigma;
    case ElementType::Bar: {
      // Axial strain (Δu·n)/L along the unit vector n from node 0 to node 1.
      double n[3];
      const double L = two_node_axis(mesh, node[0], node[1], n);
      STRATA_CHECK(L > 0, Input, "bar element {} has zero length", e);
      double du = 0;
      for (int c = 0; c < dim; ++c) du += (U(1, c) - U(0, c)) * n[c];
      const double s = mat.E * du / L;
      sigma = {s * n[0] * n[0], s * n[1] * n[1], s * n[2] * n[2],
               s * n[1] * n[2], s * n[0] * n[2], s * n[0] * n[1]};
      return sigma;
    }
    case ElementType::Tri3:
    case ElementType::Tet4: {
      // Constant strain ε = B u_e (Voigt, engineering shear), σ = D ε.
      const StrainDisplacement sd = strain_displacement(mesh, block.type, e, node);
      const Eigen::Index ns = sd.B.rows(), nd = sd.B.cols();
      double ue[kMaxElementDofs];
      for (int a = 0; a < npe; ++a)
        for (int c = 0; c < dim; ++c) ue[a * dim + c] = U(a, c);
      double eps[6], s[6], D[36];
      for (Eigen::Index i = 0; i < ns; ++i) {
        eps[i] = 0;
        for (Eigen::Index j = 0; j < nd; ++j) eps[i] += sd.B(i, j) * ue[j];
      }
      elasticity_matrix(mat, block.type, D);
      for (Eigen::Index i = 0; i < ns; ++i) {
        s[i] = 0;
        for (Eigen::Index k = 0; k < ns; ++k) s[i] += D[i * ns + k] * eps[k];
      }
      if (block.type == ElementType::Tet4) {
        sigma = {s[0], s[1], s[2], s[3], s[4], s[5]};
      } else {
        // Tri3 strains are (εxx, εyy, γxy); plane strain adds σzz = ν(σxx + σyy).
        const double szz = mat.plane == PlaneMode::Strain ? mat.nu * (s[0] + s[1]) : 0.0;
        sigma = {s[0], s[1], szz, 0.0, 0.0, s[2]};
      }
      return sigma;
    }
  }
  return sigma;
}

}  // namespace strata::fem
