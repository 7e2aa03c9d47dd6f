#include <strata/core/error.hpp>
#include <strata/fem/element.hpp>
#include <strata/fem/stress.hpp>

#include <Eigen/Dense>
#include <cmath>

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
  auto X = [&](int a, int c) {
    return mesh.x[static_cast<std::size_t>(c)][static_cast<std::size_t>(node[a])];
  };
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
    case ElementType::Tri3: {
      // Shape-function gradients ∂N_a/∂x = b_a/2A, ∂N_a/∂y = c_a/2A (constant over the element).
      const double x1 = X(0, 0), y1 = X(0, 1), x2 = X(1, 0), y2 = X(1, 1), x3 = X(2, 0), y3 = X(2, 1);
      const double two_a = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1);
      STRATA_CHECK(std::abs(two_a) > 0, Input, "tri3 element {} (nodes {} {} {}) has zero area", e, node[0],
                   node[1], node[2]);
      const double b[3] = {y2 - y3, y3 - y1, y1 - y2}, c[3] = {x3 - x2, x1 - x3, x2 - x1};
      double eps[3] = {};  // εxx, εyy, γxy
      for (int a = 0; a < 3; ++a) {
        eps[0] += b[a] * U(a, 0) / two_a;
        eps[1] += c[a] * U(a, 1) / two_a;
        eps[2] += (c[a] * U(a, 0) + b[a] * U(a, 1)) / two_a;
      }
      double D[9];
      elasticity_matrix(mat, block.type, D);
      double s[3];
      for (int i = 0; i < 3; ++i) s[i] = D[3 * i] * eps[0] + D[3 * i + 1] * eps[1] + D[3 * i + 2] * eps[2];
      const double szz = mat.plane == PlaneMode::Strain ? mat.nu * (s[0] + s[1]) : 0.0;
      sigma = {s[0], s[1], szz, 0.0, 0.0, s[2]};
      return sigma;
    }
    case ElementType::Tet4: {
      // Displacement gradient G = Σ_a u_a ⊗ ∇N_a, with ∇N from the inverse Jacobian.
      Eigen::Matrix3d J;
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) J(c, a) = X(a + 1, c) - X(0, c);
      const double det = J.determinant();
      STRATA_CHECK(std::abs(det) > 0, Input, "tet4 element {} (nodes {} {} {} {}) has zero volume", e,
                   node[0], node[1], node[2], node[3]);
      const Eigen::Matrix3d Ji = J.inverse();
      Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
      for (int a = 0; a < 4; ++a) {
        Eigen::Vector3d grad;
        for (int c = 0; c < 3; ++c) grad[c] = a == 0 ? -(Ji(0, c) + Ji(1, c) + Ji(2, c)) : Ji(a - 1, c);
        const Eigen::Vector3d ua(U(a, 0), U(a, 1), U(a, 2));
        G += ua * grad.transpose();
      }
      const Eigen::Matrix3d eps = 0.5 * (G + G.transpose());
      const double lam = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu)), mu = mat.E / (2 * (1 + mat.nu));
      const Eigen::Matrix3d s = lam * eps.trace() * Eigen::Matrix3d::Identity() + 2 * mu * eps;
      sigma = {s(0, 0), s(1, 1), s(2, 2), s(1, 2), s(0, 2), s(0, 1)};
      return sigma;
    }
  }
  return sigma;
}

}  // namespace strata::fem
