#include <strata/core/error.hpp>
#include <strata/core/parallel.hpp>
#include <strata/fem/critical_step.hpp>
#include <strata/fem/element.hpp>
#include <strata/fem/stability.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace strata::fem {

double explicit_dt_crit(double omega_max, double alpha, double beta) {
  if (!(omega_max > 0)) return std::numeric_limits<double>::infinity();
  return central_difference_dt_crit(omega_max, rayleigh_damping_ratio(omega_max, alpha, beta));
}

double element_omega2_bound(const Mesh& mesh, const Eigen::VectorXd& mass,
                            const std::vector<char>& constrained) {
  const int dim = mesh.dim;
  const std::size_t nn = mesh.nodes();
  // Pass 1 (serial, element order): per node, the sums that define each element's share.
  std::vector<double> own_sum(nn, 0.0), trace_sum(nn, 0.0);
  std::vector<char> massless_element(nn, 0);
  for (const ElementBlock& blk : mesh.blocks) {
    const int npe = nodes_per_element(blk.type);
    for (std::size_t e = 0; e < blk.size(); ++e) {
      ElementMatrices em;
      element_matrices(mesh, blk, e, em);
      for (int a = 0; a < npe; ++a) {
        const auto i = static_cast<std::size_t>(em.node[a]);
        double tr = 0;
        for (int c = 0; c < dim; ++c) tr += em.K[a * dim + c][a * dim + c];
        own_sum[i] += em.m[a];
        trace_sum[i] += tr;
        if (!(em.m[a] > 0)) massless_element[i] = 1;
      }
    }
  }
  // Pass 2 (parallel): λmax of each element's K_e with its mass share, then a serial max.
  double bound = 0;
  for (const ElementBlock& blk : mesh.blocks) {
    const int npe = nodes_per_element(blk.type);
    std::vector<double> lam(blk.size(), 0.0);
    par::parallel_for(static_cast<std::ptrdiff_t>(blk.size()), [&](std::ptrdiff_t ei) {
      ElementMatrices em;
      element_matrices(mesh, blk, static_cast<std::size_t>(ei), em);
      const int nd = em.nd;
      double s[kMaxElementDofs];
      for (int a = 0; a < npe; ++a) {
        const auto i = static_cast<std::size_t>(em.node[a]);
        double tr = 0;
        for (int c = 0; c < dim; ++c) tr += em.K[a * dim + c][a * dim + c];
        const double Mi = mass[static_cast<Eigen::Index>(i * dim)];
        const double share = !massless_element[i] && own_sum[i] > 0 ? Mi * em.m[a] / own_sum[i]
                             : trace_sum[i] > 0                     ? Mi * tr / trace_sum[i]
                                                                    : 0.0;
        const double inv = share > 0 ? 1 / std::sqrt(share) : (tr > 0 ? INFINITY : 0.0);
        for (int c = 0; c < dim; ++c) {
          const std::size_t d = i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(c);
          s[a * dim + c] = !constrained.empty() && constrained[d] ? 0.0 : inv;
        }
      }
      Eigen::MatrixXd A(nd, nd);
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j)
          A(i, j) = em.K[i][j] == 0 || s[i] == 0 || s[j] == 0 ? 0.0 : s[i] * em.K[i][j] * s[j];
      if (!A.allFinite()) {
        lam[static_cast<std::size_t>(ei)] = INFINITY;
        return;
      }
      lam[static_cast<std::size_t>(ei)] =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues()(nd - 1);
    });
    for (double l : lam) bound = std::max(bound, l);
  }
  STRATA_CHECK(std::isfinite(bound), Input,
               "FEM critical step: a node with stiffness has no mass (add element density or point masses)");
  return bound;
}

LanczosResult omega_max_lanczos(const SparseMatrix& K, const Eigen::VectorXd& mass,
                                const std::vector<char>& constrained, int max_iterations, double tolerance) {
  const Eigen::Index n = K.rows();
  Eigen::VectorXd d(n);  // M^{-1/2} on free DOFs, 0 on constrained ones
  Eigen::Index nfree = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool fixed = !constrained.empty() && constrained[static_cast<std::size_t>(i)];
    if (!fixed) STRATA_CHECK(mass[i] > 0, Input, "Lanczos: free DOF {} has no mass", i);
    d[i] = fixed ? 0.0 : 1 / std::sqrt(mass[i]);
    nfree += fixed ? 0 : 1;
  }
  LanczosResult res;
  if (nfree == 0) return res;
  const int m = static_cast<int>(std::min<Eigen::Index>(max_iterations, nfree));
  Eigen::MatrixXd Q(n, m + 1);
  std::vector<double> alpha, beta;
  // deterministic start vector (a fixed linear congruential sequence)
  std::uint64_t st = 0x9E3779B97F4A7C15ull;
  Eigen::VectorXd q(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    q[i] = d[i] == 0 ? 0.0 : 0.5 + static_cast<double>(st >> 11) * 0x1.0p-53;
  }
  q.normalize();
  Q.col(0) = q;
  Eigen::VectorXd w(n);
  for (int j = 0; j < m; ++j) {
    w = d.cwiseProduct(K * d.cwiseProduct(Q.col(j)));
    const double a = Q.col(j).dot(w);
    alpha.push_back(a);
    // full reorthogonalisation, twice (classical Gram–Schmidt)
    for (int pass = 0; pass < 2; ++pass) w -= Q.leftCols(j + 1) * (Q.leftCols(j + 1).transpose() * w);
    const double b = w.norm();
    const bool last = j + 1 == m || b <= 1e-14 * std::abs(a);
    if ((j + 1) % 10 == 0 || last) {
      const int k = j + 1;
      Eigen::MatrixXd T = Eigen::MatrixXd::Zero(k, k);
      for (int i = 0; i < k; ++i) {
        T(i, i) = alpha[static_cast<std::size_t>(i)];
        if (i + 1 < k) T(i, i + 1) = T(i + 1, i) = beta[static_cast<std::size_t>(i)];
      }
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(T);
      const double theta = es.eigenvalues()(k - 1);
      res.omega_max = std::sqrt(std::max(theta, 0.0));
      res.residual = std::abs(b * es.eigenvectors()(k - 1, k - 1));
      res.iterations = k;
      if (last || res.residual <= tolerance * std::abs(theta)) break;
    }
    beta.push_back(b);
    Q.col(j + 1) = w / b;
  }
  return res;
}

double h_over_c_dt(const Mesh& mesh) {
  double dt = INFINITY;
  for (const ElementBlock& blk : mesh.blocks) {
    if (blk.type == ElementType::Spring) continue;
    const int npe = nodes_per_element(blk.type);
    const double c = p_wave_speed(blk.material, blk.type);
    for (std::size_t e = 0; e < blk.size(); ++e) {
      double hmin = INFINITY;
      for (int a = 0; a < npe; ++a)
        for (int b = a + 1; b < npe; ++b) {
          double l2 = 0;
          for (int k = 0; k < mesh.dim; ++k) {
            const double dx = mesh.x[k][blk.conn[e * npe + b]] - mesh.x[k][blk.conn[e * npe + a]];
            l2 += dx * dx;
          }
          hmin = std::min(hmin, std::sqrt(l2));
        }
      dt = std::min(dt, hmin / c);
    }
  }
  return dt;
}

}  // namespace strata::fem
