// Static answers of the linear elements against closed-form values, and the assembly's
// determinism. Linear elements reproduce uniform strain exactly (patch test), so these
// tolerances are round-off level (1e-9 relative).
#include <gtest/gtest.h>
#include <strata/core/error.hpp>
#include <strata/core/parallel.hpp>
#include <strata/fem/assembly.hpp>
#include <strata/fem/solver.hpp>

#include <cmath>

using namespace strata::fem;

namespace {
std::vector<char> none(const Assembled& s) {
  return std::vector<char>(static_cast<std::size_t>(s.K.rows()), 0);
}
}  // namespace

// Bar fixed at x = 0 with an axial tip load P: tip displacement P L / (E A).
TEST(FemStatic, BarTipDisplacementIsPLOverEA) {
  const Material mat{.E = 2e11, .rho = 7800, .area = 1e-4};
  const double L = 3.0, P = 1e4;
  for (int dim : {1, 2, 3}) {
    const Mesh mesh = bar_mesh(10, L, mat, dim);
    const Assembled sys = assemble(mesh);
    auto fixed = none(sys);
    for (int c = 0; c < dim; ++c) fixed[static_cast<std::size_t>(c)] = 1;  // node 0
    for (std::size_t i = 1; i < mesh.nodes(); ++i)
      for (int c = 1; c < dim; ++c) fixed[i * dim + c] = 1;  // no transverse stiffness: hold it
    Eigen::VectorXd f = Eigen::VectorXd::Zero(sys.K.rows());
    f[10 * dim] = P;
    const Eigen::VectorXd u = static_solve(sys, fixed, Eigen::VectorXd::Zero(sys.K.rows()), f);
    EXPECT_NEAR(u[10 * dim], P * L / (mat.E * mat.area), 1e-9 * P * L / (mat.E * mat.area)) << "dim " << dim;
    EXPECT_NEAR(sys.mass.sum() / dim, mat.rho * mat.area * L, 1e-9);
  }
}

// Plate in uniform tension σ along x (triangles), symmetry supports on x = 0 and y = 0:
// plane stress ε_xx = σ/E, ε_yy = −ν σ/E; plane strain ε_xx = σ(1−ν²)/E, ε_yy = −ν(1+ν)σ/E.
TEST(FemStatic, TrianglePlateUniformTension) {
  const double Lx = 2.0, Ly = 1.0, t = 0.1, sigma = 5e6;
  for (PlaneMode mode : {PlaneMode::Stress, PlaneMode::Strain}) {
    const Material mat{.E = 3e10, .nu = 0.25, .rho = 2500, .thickness = t, .plane = mode};
    const int nx = 8, ny = 5;
    const Mesh mesh = rectangle_tri_mesh(nx, ny, Lx, Ly, mat);
    const Assembled sys = assemble(mesh);
    auto pre = none(sys);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(sys.K.rows());
    const double h = Ly / ny;
    for (std::size_t i = 0; i < mesh.nodes(); ++i) {
      if (mesh.x[0][i] == 0) pre[2 * i] = 1;
      if (mesh.x[1][i] == 0) pre[2 * i + 1] = 1;
      if (std::abs(mesh.x[0][i] - Lx) < 1e-12) {  // consistent edge load σ t h (h/2 at the corners)
        const bool corner = mesh.x[1][i] == 0 || std::abs(mesh.x[1][i] - Ly) < 1e-12;
        f[static_cast<Eigen::Index>(2 * i)] = sigma * t * h * (corner ? 0.5 : 1.0);
      }
    }
    const Eigen::VectorXd u = static_solve(sys, pre, Eigen::VectorXd::Zero(sys.K.rows()), f);
    const double nu = mat.nu, E = mat.E;
    const double exx = mode == PlaneMode::Stress ? sigma / E : sigma * (1 - nu * nu) / E;
    const double eyy = mode == PlaneMode::Stress ? -nu * sigma / E : -nu * (1 + nu) * sigma / E;
    for (std::size_t i = 0; i < mesh.nodes(); ++i) {
      EXPECT_NEAR(u[2 * i], exx * mesh.x[0][i], 1e-9 * exx * Lx);
      EXPECT_NEAR(u[2 * i + 1], eyy * mesh.x[1][i], 1e-9 * std::abs(eyy) * Lx);
    }
    EXPECT_NEAR(sys.mass.sum() / 2, mat.rho * t * Lx * Ly, 1e-9 * mat.rho * t * Lx * Ly);
  }
}

// Tetrahedral block stretched by a prescribed end displacement (symmetry supports on three
// faces): lateral contraction −ν ε and end reaction E ε A.
TEST(FemStatic, TetBlockUniaxialStretch) {
  const Material mat{.E = 5e10, .nu = 0.3, .rho = 2700};
  const double Lx = 2, Ly = 1, Lz = 1.5, eps = 1e-4;
  const Mesh mesh = box_tet_mesh(4, 3, 3, Lx, Ly, Lz, mat);
  const Assembled sys = assemble(mesh);
  auto pre = none(sys);
  Eigen::VectorXd up = Eigen::VectorXd::Zero(sys.K.rows());
  for (std::size_t i = 0; i < mesh.nodes(); ++i) {
    for (int c = 0; c < 3; ++c)
      if (mesh.x[c][i] == 0) pre[3 * i + c] = 1;
    if (std::abs(mesh.x[0][i] - Lx) < 1e-12) {
      pre[3 * i] = 1;
      up[static_cast<Eigen::Index>(3 * i)] = eps * Lx;
    }
  }
  const Eigen::VectorXd u = static_solve(sys, pre, up, Eigen::VectorXd::Zero(sys.K.rows()));
  const Eigen::VectorXd r = sys.K * u;
  double reaction = 0;
  for (std::size_t i = 0; i < mesh.nodes(); ++i) {
    EXPECT_NEAR(u[3 * i], eps * mesh.x[0][i], 1e-9 * eps * Lx);
    EXPECT_NEAR(u[3 * i + 1], -mat.nu * eps * mesh.x[1][i], 1e-9 * eps * Lx);
    EXPECT_NEAR(u[3 * i + 2], -mat.nu * eps * mesh.x[2][i], 1e-9 * eps * Lx);
    if (std::abs(mesh.x[0][i] - Lx) < 1e-12) reaction += r[3 * i];
  }
  EXPECT_NEAR(reaction, mat.E * eps * Ly * Lz, 1e-9 * mat.E * eps * Ly * Lz);
  EXPECT_NEAR(sys.mass.sum() / 3, mat.rho * Lx * Ly * Lz, 1e-9 * mat.rho * Lx * Ly * Lz);
}

// Element assembly in parallel gives the same matrix bit for bit as with one thread.
TEST(FemStatic, ParallelAssemblyIsDeterministic) {
  const Material mat{.E = 5e10, .nu = 0.3, .rho = 2700};
  const Mesh mesh = box_tet_mesh(6, 5, 5, 1, 1, 1, mat);
  const int before = strata::par::threads();
  strata::par::set_threads(1);
  const Assembled a1 = assemble(mesh);
  strata::par::set_threads(2);
  const Assembled a2 = assemble(mesh);
  strata::par::set_threads(before);
  ASSERT_EQ(a1.K.nonZeros(), a2.K.nonZeros());
  for (Eigen::Index k = 0; k < a1.K.nonZeros(); ++k) {
    ASSERT_EQ(a1.K.valuePtr()[k], a2.K.valuePtr()[k]);
    ASSERT_EQ(a1.K.innerIndexPtr()[k], a2.K.innerIndexPtr()[k]);
  }
  EXPECT_TRUE((a1.mass.array() == a2.mass.array()).all());
  // K is symmetric and annihilates rigid translations
  EXPECT_LT((Eigen::SparseMatrix<double>(a1.K.transpose()) - Eigen::SparseMatrix<double>(a1.K)).norm(),
            1e-12 * a1.K.norm());
  Eigen::VectorXd tx = Eigen::VectorXd::Zero(a1.K.rows());
  for (Eigen::Index i = 0; i < tx.size(); i += 3) tx[i] = 1;
  EXPECT_LT((a1.K * tx).norm(), 1e-9 * a1.K.norm());
}

TEST(FemStatic, BadInputIsRefused) {
  Mesh m = rectangle_tri_mesh(1, 1, 1, 1, Material{.E = 1, .nu = 0.6, .rho = 1});
  EXPECT_THROW(assemble(m), strata::Error);
  Mesh d = rectangle_tri_mesh(1, 1, 1, 1, Material{.E = 1, .nu = 0.2, .rho = 1});
  d.x[0][1] = 0;  // collapse a triangle
  d.x[1][1] = 0;
  EXPECT_THROW(assemble(d), strata::Error);
}
