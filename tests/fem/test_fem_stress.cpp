// Element stress against analytical constant-strain states: a displacement field
// u = G·x (G constant) gives ε = sym(G) exactly in every linear element (patch test), so
// the stress must equal Hooke's law of that strain to round-off (1e-9 relative to the
// largest stress component, far above the ~1e-15 of double arithmetic on O(1) gradients).
#include <gtest/gtest.h>
#include <strata/core/error.hpp>
#include <strata/fem/stress.hpp>

#include <algorithm>
#include <array>
#include <cmath>

using namespace strata::fem;

namespace {
/// u = G·x at every node (rows of G: displacement components).
Eigen::VectorXd affine(const Mesh& mesh, const double (&G)[3][3]) {
  Eigen::VectorXd u(static_cast<Eigen::Index>(mesh.dofs()));
  for (std::size_t i = 0; i < mesh.nodes(); ++i)
    for (int a = 0; a < mesh.dim; ++a) {
      double v = 0;
      for (int b = 0; b < mesh.dim; ++b) v += G[a][b] * mesh.x[static_cast<std::size_t>(b)][i];
      u[static_cast<Eigen::Index>(i) * mesh.dim + a] = v;
    }
  return u;
}

void expect_all_elements(const Mesh& mesh, const Eigen::VectorXd& u, const std::array<double, 6>& want) {
  double scale = 0;
  for (double s : want) scale = std::max(scale, std::abs(s));
  const double tol = 1e-9 * std::max(scale, 1.0);
  for (const auto& block : mesh.blocks)
    for (std::size_t e = 0; e < block.size(); ++e) {
      const auto got = element_stress(mesh, block, e, u);
      for (int k = 0; k < 6; ++k) EXPECT_NEAR(got[k], want[k], tol) << "element " << e << ", component " << k;
    }
}
}  // namespace

// 3D: σ = λ tr(ε) I + 2μ ε for a general strain (normal and shear parts).
TEST(FemStress, Tet4ConstantStrainGivesHookesLaw) {
  const Material mat{.E = 50e9, .nu = 0.25, .rho = 2650};
  const Mesh mesh = box_tet_mesh(2, 3, 2, 1.0, 1.5, 0.8, mat);
  const double G[3][3] = {{1e-4, 2e-5, -1e-5}, {4e-5, -3e-5, 6e-5}, {0, 2e-5, 5e-5}};
  const double lam = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu)), mu = mat.E / (2 * (1 + mat.nu));
  const double exx = 1e-4, eyy = -3e-5, ezz = 5e-5, eyz = 0.5 * (6e-5 + 2e-5), exz = 0.5 * (-1e-5 + 0),
               exy = 0.5 * (2e-5 + 4e-5);
  const double tr = exx + eyy + ezz;
  expect_all_elements(mesh, affine(mesh, G),
                      {lam * tr + 2 * mu * exx, lam * tr + 2 * mu * eyy, lam * tr + 2 * mu * ezz,
                       2 * mu * eyz, 2 * mu * exz, 2 * mu * exy});
}

// 2D uniaxial strain εxx with simple shear γxy: plane stress and plane strain closed forms.
TEST(FemStress, Tri3PlaneStressAndPlaneStrain) {
  const double E = 30e9, nu = 0.2, exx = 2e-4, gxy = 1e-4;
  const double G[3][3] = {{exx, gxy, 0}, {0, 0, 0}, {0, 0, 0}};  // u = (exx x + gxy y, 0)
  Material mat{.E = E, .nu = nu, .rho = 2500, .thickness = 0.1};
  {
    const Mesh mesh = rectangle_tri_mesh(4, 3, 2.0, 1.0, mat);
    const double c = E / (1 - nu * nu);
    expect_all_elements(mesh, affine(mesh, G),
                        {c * exx, c * nu * exx, 0.0, 0.0, 0.0, E / (2 * (1 + nu)) * gxy});
  }
  mat.plane = PlaneMode::Strain;
  {
    const Mesh mesh = rectangle_tri_mesh(4, 3, 2.0, 1.0, mat);
    const double c = E / ((1 + nu) * (1 - 2 * nu));
    const double sxx = c * (1 - nu) * exx, syy = c * nu * exx;
    expect_all_elements(mesh, affine(mesh, G),
                        {sxx, syy, nu * (sxx + syy), 0.0, 0.0, E / (2 * (1 + nu)) * gxy});
  }
}

// An infinitesimal rigid rotation (skew G) strains nothing: zero stress.
TEST(FemStress, RigidRotationIsStressFree) {
  const Material mat{.E = 50e9, .nu = 0.3, .rho = 2650};
  const Mesh mesh = box_tet_mesh(2, 2, 2, 1.0, 1.0, 1.0, mat);
  const double G[3][3] = {{0, -3e-4, 2e-4}, {3e-4, 0, -1e-4}, {-2e-4, 1e-4, 0}};
  const auto u = affine(mesh, G);
  for (std::size_t e = 0; e < mesh.blocks[0].size(); ++e)
    for (double s : element_stress(mesh, mesh.blocks[0], e, u)) EXPECT_NEAR(s, 0.0, 1e-9 * mat.E * 3e-4);
}

// A bar along a diagonal stretched by ε: axial stress Eε, as the tensor σ n⊗n.
TEST(FemStress, BarAxialStressAlongItsDirection) {
  const Material mat{.E = 2e11, .rho = 7800, .area = 1e-4};
  Mesh mesh;
  mesh.dim = 2;
  mesh.add_node(0, 0);
  mesh.add_node(3, 4);  // length 5, n = (0.6, 0.8)
  mesh.blocks.push_back({ElementType::Bar, mat, {0, 1}});
  const double eps = 1e-4;
  Eigen::VectorXd u(4);
  u << 0, 0, 0.6 * 5 * eps, 0.8 * 5 * eps;
  const auto s = element_stress(mesh, mesh.blocks[0], 0, u);
  const double sa = mat.E * eps;
  const double tol = 1e-9 * sa;
  EXPECT_NEAR(s[0], sa * 0.36, tol);
  EXPECT_NEAR(s[1], sa * 0.64, tol);
  EXPECT_NEAR(s[2], 0.0, tol);
  EXPECT_NEAR(s[5], sa * 0.48, tol);
  EXPECT_THROW(element_stress(mesh, mesh.blocks[0], 0, Eigen::VectorXd::Zero(3)), strata::Error);
}
