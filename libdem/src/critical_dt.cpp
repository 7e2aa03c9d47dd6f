// Critical time step of the DEM: 2/√λ with λ the largest eigenvalue of M⁻¹K of the bonded
// lattice, from a rigorous node-local bound and a Lanczos estimate (docs/dem.md).
#include "model.hpp"

#include <strata/core/log.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace strata::dem::detail {
namespace {

// Deterministic pseudo-random number in [-1, 1) from an integer (splitmix64).
double hash_unit(std::uint64_t k) {
  k += 0x9e3779b97f4a7c15ull;
  k = (k ^ (k >> 30)) * 0xbf58476d1ce4e5b9ull;
  k = (k ^ (k >> 27)) * 0x94d049bb133111ebull;
  k ^= k >> 31;
  return static_cast<double>(k >> 11) * 0x1.0p-52 - 1.0;
}

// Margin of the time step over the Lanczos estimate: λ = min(bound, (1 + kMargin)·θ).
constexpr double kMargin = 0.01;
// Particles per chunk of the parallel set-up loops (the Lanczos products, the layer mode) and
// the fewest per chunk of the rigorous bound's pass.
constexpr std::size_t kChunkP = 1024;
// Chunks of the rigorous bound's pass: at most about this many (of at least kChunkP particles).
constexpr std::size_t kBoundChunks = 512;
// Fewest Lanczos steps before the residual may stop the iteration (large models).
constexpr int kMinSteps = 10;
// Models above this many particles are "large": the Lanczos iteration may stop early, and
// the layer mode may settle the step without it.
constexpr std::size_t kLargeModel = 200000;

// Largest eigenvalue θ of the Lanczos tridiagonal matrix (diagonal al, off-diagonal be, one
// shorter) and its residual |β_next·s_k| for the next off-diagonal β_next, s_k the last
// component of its unit eigenvector: some eigenvalue of the operator lies within the
// residual of θ.
std::pair<double, double> largest_ritz(const std::vector<double>& al, const std::vector<double>& be,
                                       double beta_next) {
  const int k = static_cast<int>(al.size());
  Eigen::VectorXd dg(k), sd(std::max(k - 1, 0));
  for (int i = 0; i < k; ++i) dg(i) = al[i];
  for (int i = 0; i + 1 < k; ++i) sd(i) = be[i];
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
  es.computeFromTridiagonal(dg, sd, beta_next > 0 ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
  const double theta = es.eigenvalues()(k - 1);
  return {theta, beta_next > 0 ? beta_next * std::abs(es.eigenvectors()(k - 1, k - 1)) : 0.0};
}

}  // namespace

// Stiffnesses of pair k of L: the materials' law, scaled by an intact eccentric-lattice
// bond's stiffness factor.
template <int D>
PairStiffness Model<D>::stiffness_of(const PairList& L, std::uint32_t k, std::size_t p, std::size_t j) const {
  PairStiffness s = stiff[static_cast<std::size_t>(mat[p]) * nmat + mat[j]];
  if (scaled(L, k)) {
    s.kn *= L.kf[k];
    s.ks *= L.kf[k];
  }
  return s;
}

// K·u over intact bonds and touching contacts: (K u)_i = Σ_b K_b (u_i - u_j),
// K_b = Kn·n nᵀ + Ks·(I - n nᵀ). The stiff pairs owned by particle p:
template <int D>
template <typename Fn>
void Model<D>::stiff_pairs_of(std::size_t p, Fn&& fn) const {
  for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) {
    const std::uint32_t j = bonds.j[k];
    const double r = rest_of(bonds, k, p, j);
    const bool on = (bonds.st[k] & pair_state::kKindMask) == pair_state::kIntact || dist2(p, j) < r * r;
    if (on) fn(p, j, stiffness_of(bonds, k, p, j));
  }
  for (std::uint32_t k = contacts.off[p]; k < contacts.off[p + 1]; ++k) {
    const std::uint32_t j = contacts.j[k];
    if (dist2(p, j) < (rad[p] + rad[j]) * (rad[p] + rad[j])) fn(p, j, stiffness_of(contacts, k, p, j));
  }
}

// Unit vector from p to j.
template <int D>
void Model<D>::unit_normal(std::size_t p, std::uint32_t j, double nv[D]) const {
  double l2 = 0;
  for (int a = 0; a < D; ++a) {
    nv[a] = x[a][j] - x[a][p];
    l2 += nv[a] * nv[a];
  }
  const double l = std::sqrt(l2);
  for (int a = 0; a < D; ++a) nv[a] /= l;
}

template <int D>
void Model<D>::pair_matrix(std::size_t p, std::uint32_t j, const PairStiffness& k, double K[D][D]) const {
  double nv[D];
  unit_normal(p, j, nv);
  for (int a = 0; a < D; ++a)
    for (int b2 = 0; b2 < D; ++b2) K[a][b2] = (k.kn - k.ks) * nv[a] * nv[b2] + (a == b2 ? k.ks : 0.0);
}

// Largest stiffness of the model's pair laws.
template <int D>
double Model<D>::max_stiffness() const {
  double kmax = 0;
  for (const PairStiffness& s : stiff) kmax = std::max(kmax, std::max(s.kn, s.ks));
  return kmax;
}

template <int D>
void Model<D>::compute_critical_dt() {
  bonds_current();
  const std::size_t N = n();
  log::Phases ph("critical time step");
  // rigorous bound: uᵀKu <= Σ_b 2(u_iᵀK_b u_i + u_jᵀK_b u_j) => λ <= max_i λmax(2ΣK_b)/m_i
  // (ΣK_b kept in float, upper triangle only, to keep the set-up's memory peak low; the
  // result is raised by 1e-5 to cover the float round-off). In parallel over chunks of
  // particles with the sums of a serial pass over owners in order, so the same bits for any
  // thread count: each entry first gets the terms of pairs owned in earlier chunks (formed
  // in a first pass and handed over in owner order), then those of its own chunk.
  constexpr int kSym = D * (D + 1) / 2;
  struct Term {
    std::uint32_t j;
    float k[kSym];
  };
  auto upper = [&](std::size_t p, std::uint32_t j, const PairStiffness& k, Term& t) {
    double K[D][D];
    pair_matrix(p, j, k, K);
    int e = 0;
    for (int a = 0; a < D; ++a)
      for (int b2 = a; b2 < D; ++b2, ++e) t.k[e] = static_cast<float>(K[a][b2]);
  };
  // The sums come out the same for any chunk size, so large models take large chunks: fewer
  // pairs then cross into a later chunk and have their terms stored (6 % of them in a
  // close-packed cube of 1.3e7 spheres, against 19 % with chunks of kChunkP).
  const std::size_t chunk = std::max(kChunkP, (N + kBoundChunks - 1) / kBoundChunks);
  const std::size_t nc = (N + chunk - 1) / chunk;
  auto chunk_end = [&](std::size_t c) { return std::min(N, (c + 1) * chunk); };
  std::vector<std::vector<Term>> later(nc);  // terms of each chunk's pairs that reach later chunks
  std::vector<std::size_t> pairs_in(nc, 0);
  // (each chunk's count, largest values and sums in locals, stored once at its end)
  for_chunks(static_cast<std::ptrdiff_t>(nc), [&](std::ptrdiff_t c) {
    const auto cu = static_cast<std::size_t>(c);
    const std::size_t hi = chunk_end(cu);
    std::size_t count = 0;
    for (std::size_t p = cu * chunk; p < hi; ++p)
      stiff_pairs_of(p, [&](std::size_t pp, std::uint32_t j, const PairStiffness& k) {
        ++count;
        if (j < hi) return;
        Term t{j, {}};
        upper(pp, j, k, t);
        later[cu].push_back(t);
      });
    pairs_in[cu] = count;
  });
  std::vector<std::vector<Term>> incoming(nc);  // by receiving chunk, in owner order
  for (const auto& terms : later)
    for (const Term& t : terms) incoming[t.j / chunk].push_back(t);
  // Each chunk's pass reads and writes only its own particles' sums, and clears them first
  // (on its own thread: the pages are first touched there, in parallel).
  std::unique_ptr<float[]> S(new float[N * kSym]);
  std::vector<double> chunk_bound(nc, 0.0);
  // A rigorous lower bound of λmax for each pair: the Rayleigh quotient of the two particles
  // moving apart along an axis a, u_i = e_a = −u_j, is 4·K_aa/(m_i + m_j) plus the (positive)
  // terms of their other pairs. A Lanczos estimate below it has missed a mode (a stiff pair
  // alone in a soft network, as eccentric lattices with weakened bonds have).
  std::vector<double> chunk_pair(nc, 0.0);
  for_chunks(static_cast<std::ptrdiff_t>(nc), [&](std::ptrdiff_t c) {
    const auto cu = static_cast<std::size_t>(c);
    const std::size_t lo = cu * chunk, hi = chunk_end(cu);
    std::fill(S.get() + lo * kSym, S.get() + hi * kSym, 0.0f);
    for (const Term& t : incoming[cu])
      for (int e = 0; e < kSym; ++e) S[std::size_t{t.j} * kSym + e] += t.k[e];
    std::size_t next_later = 0;  // the terms the first pass formed, in the same pair order
    double pair_max = 0, bound_max = 0;
    double mp = 0;  // the owner's mass, 1 / im[p]
    auto pair_lower = [&](std::uint32_t j, const Term& t) {
      float kd = 0;
      for (int a = 0, e = 0; a < D; e += D - a, ++a) kd = std::max(kd, t.k[e]);  // diagonal: e = a(2D−a+1)/2
      pair_max = std::max(pair_max, 4.0 * double(kd) / (mp + 1.0 / im[j]));
    };
    for (std::size_t p = lo; p < hi; ++p) {
      mp = 1.0 / im[p];
      stiff_pairs_of(p, [&](std::size_t pp, std::uint32_t j, const PairStiffness& k) {
        if (j >= hi) {
          const Term& t = later[cu][next_later++];
          for (int e = 0; e < kSym; ++e) S[pp * kSym + e] += t.k[e];
          pair_lower(j, t);
          return;
        }
        Term t{j, {}};
        upper(pp, j, k, t);
        pair_lower(j, t);
        for (int e = 0; e < kSym; ++e) {
          S[pp * kSym + e] += t.k[e];
          S[std::size_t{j} * kSym + e] += t.k[e];
        }
      });
    }
    for (std::size_t i = lo; i < hi; ++i) {
      Eigen::Matrix<double, D, D> M;
      int e = 0;
      for (int a = 0; a < D; ++a)
        for (int b2 = a; b2 < D; ++b2, ++e) M(a, b2) = M(b2, a) = S[i * kSym + e];
      const double lm = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>>(M, Eigen::EigenvaluesOnly)
                            .eigenvalues()(D - 1);
      bound_max = std::max(bound_max, 2 * lm * im[i] * (1 + 1e-5));
    }
    chunk_pair[cu] = pair_max;
    chunk_bound[cu] = bound_max;
  });
  std::size_t npairs = 0, stored = 0;
  for (std::size_t c = 0; c < nc; ++c) npairs += pairs_in[c], stored += later[c].size();
  log::debug("critical time step: {} chunks of {} particles; {} of {} pairs cross into a later chunk", nc,
             chunk, stored, npairs);
  const double bound = nc > 0 ? *std::max_element(chunk_bound.begin(), chunk_bound.end()) : 0.0;
  const double pair_bound = nc > 0 ? *std::max_element(chunk_pair.begin(), chunk_pair.end()) : 0.0;
  later.clear();
  incoming.clear();
  S.reset();
  const double kmax = max_stiffness();
  const double imax = im.max();
  // contacts may form later: a particle touching z neighbours (6 in 2D, 12 in 3D)
  // through contacts of stiffness <= kmax has λ <= 2·z·kmax/m (same bound)
  const double contact_bound = contacts_on ? 2.0 * (D == 2 ? 6 : 12) * kmax * imax : 0.0;
  // rigid walls: a particle pressed against walls adds k_w·n nᵀ to its diagonal block, a
  // positive semi-definite term, which raises λ by at most Σ_w k_w / m_min (Weyl's
  // inequality); any particle may meet a wall later, so every wall counts from the start
  double wall_lambda = 0;
  for (const Wall& w : walls) wall_lambda += w.k * imax;
  lam_bound = bound;
  ph.lap("rigorous bound");
  // A large model: the Rayleigh quotient of its lattice layers moving against each other is a
  // lower bound of λmax. When it shows (1 + margin)·λmax above the bound (a close-packed or
  // hexagonal lattice of normal springs), the bound sets the step whatever the Lanczos
  // estimate would say; otherwise the estimate is at least this quotient (the iteration,
  // stopped early, may lie below it).
  const double layers = npairs > 0 && N > kLargeModel ? layer_mode_quotient() : 0.0;
  if (layers > 0)
    log::debug("critical time step: layer mode {:.17g}, {:.6f} of the bound", layers, layers / bound);
  if ((1 + kMargin) * layers >= bound && layers > 0) {
    lam_est = layers;
    ph.lap("layer mode (the bound holds within the margin; no Lanczos estimate)");
  } else {
    lam_est = npairs > 0 ? std::max(lanczos(), layers) : 0.0;
    ph.lap("Lanczos estimate");
  }
  log::debug("critical time step: largest eigenvalue {:.17g} (estimate), {:.17g} (bound)", lam_est,
             lam_bound);
  double lam = npairs > 0 ? std::min(bound, (1 + kMargin) * lam_est) : contact_bound;
  if (npairs > 0 && lam_est < (1 - 1e-5) * pair_bound) {
    // The estimate lies below what one pair alone shows (float sums: 1e-5 of room): the
    // iteration has not seen the stiffest mode; the rigorous bound is safe.
    log::info(
        "critical time step: the Lanczos estimate {:.4g} is below a single pair's mode {:.4g} (a "
        "stiff pair in a soft network); the step follows the rigorous bound {:.4g}",
        lam_est, pair_bound, bound);
    lam = bound;
  }
  if (npairs == 0) lam_bound = contact_bound;
  lam += wall_lambda;
  lam_bound += wall_lambda;
  dt_crit = lam > 0 ? 2.0 / std::sqrt(lam) : std::numeric_limits<double>::infinity();
}

// λmax(M^-½ K M^-½) by Lanczos without reorthogonalisation (the largest Ritz value
// converges first and stays below λmax), deterministic start vector.
template <int D>
double Model<D>::lanczos() const {
  bonds_current();
  // up to 600 unknowns: full reorthogonalisation and as many steps as unknowns (exact
  // extreme eigenvalue); otherwise 120 steps, with float vectors above 20,000 unknowns to
  // keep the set-up's memory peak low. Above 200,000 particles the iteration stops as soon
  // as the largest Ritz value θ is known to within the margin the time step keeps over it:
  // some eigenvalue lies within the residual β·|s_k| of θ (s the Ritz vector in the Lanczos
  // basis; Parlett 1998), and once that residual is at most 1 % of θ, 1.01·θ covers the
  // interval; at most 60 steps (a 10 M-disk block needs about 20, each a product K·u over
  // every bond). It also stops once (1 + margin)·θ reaches the rigorous bound (lam_bound, set
  // before), which then gives the time step: a regular lattice gets there after about 16 steps.
  return n() * D <= 20000 ? lanczos_impl<double>() : lanczos_impl<float>();
}

// uᵀKu / uᵀMu for u = ±e_z (±e_y in 2D), the sign alternating from one lattice layer to the
// next (layers d·√(2/3) apart along z in a close-packed lattice stacked along z, rows d·√3/2
// apart along y in the hexagonal one): each particle pushes against its neighbours in the
// layers above and below. In a regular lattice of normal springs this is its highest mode,
// with the quotient of the rigorous bound less the missing neighbours at the surface; in any
// model it is a lower bound of λmax. Sums per chunk, added in chunk order: the same for any
// thread count.
template <int D>
double Model<D>::layer_mode_quotient() const {
  bonds_current();
  const std::size_t N = n();
  const double d = 2 * rad.max();
  const double h = D == 3 ? d * std::sqrt(2.0 / 3.0) : d * std::sqrt(3.0) / 2;
  double lo[D], len[D];
  for (int a = 0; a < D; ++a) {
    const auto [mn, mx] = std::minmax_element(x[a].begin(), x[a].end());
    lo[a] = *mn - d;
    len[a] = *mx - *mn + 2 * d;
  }
  // u_i: the sign of the layer, times a sine envelope over the model's box that fades the
  // mode out towards its surface, where particles miss neighbours (in single precision: any
  // vector gives a lower bound; the sums are in double)
  const std::size_t nc = (N + kChunkP - 1) / kChunkP;
  std::vector<float> u;
  par::resize_paged(u, N);  // (first writes on all threads: par::page_in)
  for_chunks(static_cast<std::ptrdiff_t>(nc), [&](std::ptrdiff_t c) {
    for (std::size_t i = std::size_t(c) * kChunkP; i < std::min(N, std::size_t(c + 1) * kChunkP); ++i) {
      double w = std::llround((x[D - 1][i] - lo[D - 1] - d) / h) % 2 == 0 ? 1.0 : -1.0;
      for (int a = 0; a < D; ++a) w *= std::sin(M_PI * (x[a][i] - lo[a]) / len[a]);
      u[i] = static_cast<float>(w);
    }
  });
  std::vector<double> energy(nc, 0.0), mass(nc, 0.0);
  for_chunks(static_cast<std::ptrdiff_t>(nc), [&](std::ptrdiff_t c) {
    const auto cu = static_cast<std::size_t>(c);
    double e = 0, m = 0;  // the chunk's sums, in the same order
    for (std::size_t p = cu * kChunkP; p < std::min(N, (cu + 1) * kChunkP); ++p) {
      m += double(u[p]) * u[p] / im[p];
      stiff_pairs_of(p, [&](std::size_t pp, std::uint32_t j, const PairStiffness& k) {
        const double du = double(u[pp]) - u[j];  // along the last axis
        if (du == 0) return;
        double nv[D];
        unit_normal(pp, j, nv);
        e += k.ks * du * du + (k.kn - k.ks) * nv[D - 1] * nv[D - 1] * du * du;
      });
    }
    energy[cu] = e;
    mass[cu] = m;
  });
  double e = 0, m = 0;
  for (std::size_t c = 0; c < nc; ++c) e += energy[c], m += mass[c];
  return m > 0 ? e / m : 0.0;
}

template <int D>
template <typename Real>
double Model<D>::lanczos_impl() const {
  const std::size_t N = n(), nd = N * D;
  const bool full = nd <= 600;
  const bool large = !full && N > kLargeModel;
  const int kmax = static_cast<int>(full ? nd : std::min<std::size_t>(nd, large ? 60 : 120));
  std::vector<Real> q(nd), qp(nd, Real(0)), w(nd);
  double nrm = 0;
  for (std::size_t i = 0; i < nd; ++i) {
    const double h = hash_unit(i);
    nrm += h * h;
  }
  nrm = std::sqrt(nrm);
  for (std::size_t i = 0; i < nd; ++i) q[i] = static_cast<Real>(hash_unit(i) / nrm);
  // w = M^-½ K M^-½ q in parallel, the same for any thread count: each chunk of particles
  // sums its pairs into its own entries in pair order; the parts that land in later
  // chunks are kept per chunk and subtracted afterwards, in chunk order.
  struct Cross {
    std::uint32_t j;
    Real t[D];
  };
  const std::size_t nc = (N + kChunkP - 1) / kChunkP;
  std::vector<std::vector<Cross>> cross(nc);
  auto matvec = [&] {
    for_chunks(static_cast<std::ptrdiff_t>(nc), [&](std::ptrdiff_t c) {
      const std::size_t lo = static_cast<std::size_t>(c) * kChunkP, hi = std::min(N, lo + kChunkP);
      std::fill(w.begin() + static_cast<std::ptrdiff_t>(lo * D),
                w.begin() + static_cast<std::ptrdiff_t>(hi * D), Real(0));
      auto& out = cross[static_cast<std::size_t>(c)];
      out.clear();
      for (std::size_t p = lo; p < hi; ++p)
        stiff_pairs_of(p, [&](std::size_t pp, std::uint32_t j, const PairStiffness& k) {
          // K_b du = Ks·du + (Kn - Ks)·n (n·du)
          double nv[D];
          unit_normal(pp, j, nv);
          const double sp = std::sqrt(im[pp]), sj = std::sqrt(im[j]);
          double du[D], ndu = 0;
          for (int a = 0; a < D; ++a) {
            du[a] = q[pp * D + a] * sp - q[std::size_t{j} * D + a] * sj;
            ndu += nv[a] * du[a];
          }
          Cross cr{j, {}};
          for (int a = 0; a < D; ++a) {
            const double t = k.ks * du[a] + (k.kn - k.ks) * ndu * nv[a];
            w[pp * D + a] += static_cast<Real>(t * sp);
            cr.t[a] = static_cast<Real>(t * sj);
          }
          if (j < hi) {
            for (int a = 0; a < D; ++a) w[std::size_t{j} * D + a] -= cr.t[a];
          } else {
            out.push_back(cr);
          }
        });
    });
    for (const auto& out : cross)
      for (const Cross& cr : out)
        for (int a = 0; a < D; ++a) w[std::size_t{cr.j} * D + a] -= cr.t[a];
  };
  const auto ndi = static_cast<std::ptrdiff_t>(nd);
  std::vector<double> al, be, basis;
  double beta = 0;
  for (int it = 0; it < kmax; ++it) {
    if (full) basis.insert(basis.end(), q.begin(), q.end());
    matvec();
    const double alpha =
        par::parallel_sum<double>(ndi, [&](std::ptrdiff_t i) { return static_cast<double>(w[i]) * q[i]; });
    par::parallel_for(
        ndi, [&](std::ptrdiff_t i) { w[i] = static_cast<Real>(w[i] - alpha * q[i] - beta * qp[i]); });
    double b2 =
        par::parallel_sum<double>(ndi, [&](std::ptrdiff_t i) { return static_cast<double>(w[i]) * w[i]; });
    if (full) {
      for (int pass = 0; pass < 2; ++pass)
        for (int c = 0; c <= it; ++c) {
          const double* qc = &basis[static_cast<std::size_t>(c) * nd];
          double dot = 0;
          for (std::size_t i = 0; i < nd; ++i) dot += w[i] * qc[i];
          for (std::size_t i = 0; i < nd; ++i) w[i] = static_cast<Real>(w[i] - dot * qc[i]);
        }
      b2 = 0;
      for (std::size_t i = 0; i < nd; ++i) b2 += static_cast<double>(w[i]) * w[i];
    }
    al.push_back(alpha);
    beta = std::sqrt(b2);
    if (beta < 1e-12 * std::abs(alpha) || it == kmax - 1) break;
    if (large && it + 1 >= kMinSteps) {
      // θ only grows with the steps (each tridiagonal matrix holds the last), so once
      // (1 + margin)·θ reaches the rigorous bound, λ = min(bound, (1 + margin)·θ) is the bound
      // whatever more steps give
      const auto [theta, residual] = largest_ritz(al, be, beta);
      if (residual <= kMargin * theta || (1 + kMargin) * theta >= lam_bound) break;
    }
    be.push_back(beta);
    par::parallel_for(ndi, [&](std::ptrdiff_t i) {
      qp[i] = q[i];
      q[i] = static_cast<Real>(w[i] / beta);
    });
  }
  return largest_ritz(al, be, 0.0).first;
}

#define STRATA_DEM_INSTANTIATE(D)                                                                            \
  template PairStiffness Model<D>::stiffness_of(const PairList&, std::uint32_t, std::size_t, std::size_t)    \
      const;                                                                                                 \
  template void Model<D>::unit_normal(std::size_t, std::uint32_t, double*) const;                            \
  template void Model<D>::pair_matrix(std::size_t, std::uint32_t, const PairStiffness&, double(*)[D]) const; \
  template double Model<D>::max_stiffness() const;                                                           \
  template void Model<D>::compute_critical_dt();                                                             \
  template double Model<D>::lanczos() const;                                                                 \
  template double Model<D>::layer_mode_quotient() const;
STRATA_DEM_INSTANTIATE(2)
STRATA_DEM_INSTANTIATE(3)
#undef STRATA_DEM_INSTANTIATE

}  // namespace strata::dem::detail
