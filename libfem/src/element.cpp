#include <strata/core/error.hpp>
#include <strata/fem/element.hpp>

#include "strain_displacement.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace strata::fem {

void elasticity_matrix(const Material& m, ElementType t, double* D) {
  const double E = m.E, nu = m.nu;
  if (t == ElementType::Tri3) {
    double c, d11, d12, d33;
    if (m.plane == PlaneMode::Stress) {
      c = E / (1 - nu * nu);
      d11 = c;
      d12 = c * nu;
      d33 = c * (1 - nu) / 2;
    } else {
      c = E / ((1 + nu) * (1 - 2 * nu));
      d11 = c * (1 - nu);
      d12 = c * nu;
      d33 = c * (1 - 2 * nu) / 2;
    }
    const double v[9] = {d11, d12, 0, d12, d11, 0, 0, 0, d33};
    for (int i = 0; i < 9; ++i) D[i] = v[i];
    return;
  }
  const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  for (int i = 0; i < 36; ++i) D[i] = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) D[i * 6 + j] = lam;
    D[i * 6 + i] = lam + 2 * mu;
    D[(i + 3) * 6 + (i + 3)] = mu;
  }
}

double p_wave_speed(const Material& m, ElementType t) {
  switch (t) {
    case ElementType::Bar:
      return std::sqrt(m.E / m.rho);
    case ElementType::Tri3:
      if (m.plane == PlaneMode::Stress) return std::sqrt(m.E / (m.rho * (1 - m.nu * m.nu)));
      [[fallthrough]];
    case ElementType::Tet4:
      return std::sqrt(m.E * (1 - m.nu) / (m.rho * (1 + m.nu) * (1 - 2 * m.nu)));
    case ElementType::Spring:
      return 0;
  }
  return 0;
}

namespace {

// K = scale · Bᵀ D B, with D the B.rows() x B.rows() elasticity matrix (row-major).
void btdb(const StrainDisplacement& sd, const double* D, double scale, ElementMatrices& out) {
  const auto& B = sd.B;
  const Eigen::Index ns = B.rows(), nd = B.cols();
  double DB[6][kMaxElementDofs];
  for (Eigen::Index i = 0; i < ns; ++i)
    for (Eigen::Index j = 0; j < nd; ++j) {
      double s = 0;
      for (Eigen::Index k = 0; k < ns; ++k) s += D[i * ns + k] * B(k, j);
      DB[i][j] = s;
    }
  for (Eigen::Index i = 0; i < nd; ++i)
    for (Eigen::Index j = 0; j < nd; ++j) {
      double s = 0;
      for (Eigen::Index k = 0; k < ns; ++k) s += B(k, i) * DB[k][j];
      out.K[i][j] = scale * s;
    }
}

}  // namespace

double two_node_axis(const Mesh& mesh, std::int32_t a, std::int32_t b, double n[3]) {
  const int dim = mesh.dim;
  n[0] = 1;
  n[1] = n[2] = 0;
  double L = 0;
  for (int c = 0; c < dim; ++c) {
    n[c] = mesh.x[static_cast<std::size_t>(c)][static_cast<std::size_t>(b)] -
           mesh.x[static_cast<std::size_t>(c)][static_cast<std::size_t>(a)];
    L += n[c] * n[c];
  }
  L = std::sqrt(L);
  if (dim == 1)
    n[0] = 1;
  else if (L > 0)
    for (int c = 0; c < dim; ++c) n[c] /= L;
  return L;
}

StrainDisplacement strain_displacement(const Mesh& mesh, ElementType type, std::size_t e,
                                       const std::int32_t* node) {
  auto X = [&](int a, int c) {
    return mesh.x[static_cast<std::size_t>(c)][static_cast<std::size_t>(node[a])];
  };
  StrainDisplacement sd;
  if (type == ElementType::Tri3) {
    // Shape-function gradients ∂N_a/∂x = b_a/2A, ∂N_a/∂y = c_a/2A (constant over the element).
    const double x1 = X(0, 0), y1 = X(0, 1), x2 = X(1, 0), y2 = X(1, 1), x3 = X(2, 0), y3 = X(2, 1);
    const double two_a = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1);
    STRATA_CHECK(std::abs(two_a) > 0, Input, "tri3 element {} (nodes {} {} {}) has zero area", e, node[0],
                 node[1], node[2]);
    const double b[3] = {y2 - y3, y3 - y1, y1 - y2}, c[3] = {x3 - x2, x1 - x3, x2 - x1};
    sd.B.setZero(3, 6);
    for (int a = 0; a < 3; ++a) {
      sd.B(0, 2 * a) = b[a] / two_a;
      sd.B(1, 2 * a + 1) = c[a] / two_a;
      sd.B(2, 2 * a) = c[a] / two_a;
      sd.B(2, 2 * a + 1) = b[a] / two_a;
    }
    sd.measure = 0.5 * std::abs(two_a);
    return sd;
  }
  STRATA_ASSERT(type == ElementType::Tet4, "strain_displacement: a {} element has no B matrix",
                to_string(type));
  // ∇N_a from the inverse Jacobian of the map from the reference tetrahedron.
  Eigen::Matrix3d J;
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) J(c, a) = X(a + 1, c) - X(0, c);
  const double det = J.determinant();
  STRATA_CHECK(std::abs(det) > 0, Input, "tet4 element {} (nodes {} {} {} {}) has zero volume", e, node[0],
               node[1], node[2], node[3]);
  const Eigen::Matrix3d Ji = J.inverse();  // rows: gradients of the natural coordinates
  double g[4][3];
  for (int c = 0; c < 3; ++c) {
    g[0][c] = -(Ji(0, c) + Ji(1, c) + Ji(2, c));
    for (int a = 1; a < 4; ++a) g[a][c] = Ji(a - 1, c);
  }
  sd.B.setZero(6, 12);
  for (int a = 0; a < 4; ++a) {
    const double gx = g[a][0], gy = g[a][1], gz = g[a][2];
    sd.B(0, 3 * a) = gx;
    sd.B(1, 3 * a + 1) = gy;
    sd.B(2, 3 * a + 2) = gz;
    sd.B(3, 3 * a + 1) = gz;  // γ_yz
    sd.B(3, 3 * a + 2) = gy;
    sd.B(4, 3 * a) = gz;  // γ_xz
    sd.B(4, 3 * a + 2) = gx;
    sd.B(5, 3 * a) = gy;  // γ_xy
    sd.B(5, 3 * a + 1) = gx;
  }
  sd.measure = std::abs(det) / 6;
  return sd;
}

void element_matrices(const Mesh& mesh, const ElementBlock& block, std::size_t e, ElementMatrices& out) {
  const int npe = nodes_per_element(block.type), dim = mesh.dim;
  const Material& mat = block.material;
  out.nd = npe * dim;
  for (int a = 0; a < npe; ++a)
    out.node[a] = block.conn[e * static_cast<std::size_t>(npe) + static_cast<std::size_t>(a)];

  switch (block.type) {
    case ElementType::Spring:
    case ElementType::Bar: {
      // axial two-node element: k [n nᵀ, −n nᵀ; −n nᵀ, n nᵀ]
      double n[3];
      const double L = two_node_axis(mesh, out.node[0], out.node[1], n);
      STRATA_CHECK(dim == 1 || L > 0, Input, "{} element {} joins coincident nodes {} and {}",
                   to_string(block.type), e, out.node[0], out.node[1]);
      double k = mat.k;
      out.m[0] = out.m[1] = 0;
      if (block.type == ElementType::Bar) {
        STRATA_CHECK(L > 0, Input, "bar element {} has zero length", e);
        k = mat.E * mat.area / L;
        out.m[0] = out.m[1] = 0.5 * mat.rho * mat.area * L;
      }
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int i = 0; i < dim; ++i)
            for (int j = 0; j < dim; ++j)
              out.K[a * dim + i][b * dim + j] = (a == b ? 1 : -1) * k * n[i] * n[j];
      return;
    }
    case ElementType::Tri3:
    case ElementType::Tet4: {
      // Constant strain: K = t·A·Bᵀ D B and mass ρ·t·A/3 per node (Tri3, thickness t);
      // K = V·Bᵀ D B and mass ρ·V/4 per node (Tet4).
      const StrainDisplacement sd = strain_displacement(mesh, block.type, e, out.node);
      double D[36];
      elasticity_matrix(mat, block.type, D);
      const double t = block.type == ElementType::Tri3 ? mat.thickness : 1.0;
      btdb(sd, D, t * sd.measure, out);
      for (int a = 0; a < npe; ++a) out.m[a] = mat.rho * t * sd.measure / npe;
      return;
    }
  }
}

}  // namespace strata::fem
