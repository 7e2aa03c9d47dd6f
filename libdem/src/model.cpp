// The DEM model: structure-of-arrays particles, CSR bonds/contacts, the fused
// force-gather-update step loop, contact search, time-step estimate and probes.
// Physics and design notes: docs/dem.md.
#include "model.hpp"

#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

namespace strata::dem::detail {
namespace {

using Damping = Settings::Damping;

template <int D>
constexpr int kNsOf = D == 2 ? 1 : 3;

/// Bond/contact law between two materials: the same material gives its own law; two
/// different ones give harmonic-mean stiffnesses (springs in series, scaled so that equal
/// materials give back their own), the weaker strengths and the smaller friction.
SolidLatticeLaw pair_law(const Material& a, const Material& b) {
  SolidLatticeLaw l;
  auto hm = [](double p, double q) { return p + q > 0 ? 2 * p * q / (p + q) : 0.0; };
  l.kn = &a == &b ? a.kn : hm(a.kn, b.kn);
  l.ks = &a == &b ? a.ks : hm(a.ks, b.ks);
  l.mu = std::min(a.friction, b.friction);
  l.fn_max = std::min(a.tensile_strength, b.tensile_strength);
  l.fs0 = std::min(a.shear_strength, b.shear_strength);
  l.friction_strengthens_bonds = a.friction_strengthens_bonds && b.friction_strengthens_bonds;
  return l;
}

struct V3 {
  double c[3]{};
  V3& operator+=(const V3& o) {
    for (int a = 0; a < 3; ++a) c[a] += o.c[a];
    return *this;
  }
};

std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

/// Deterministic pseudo-random number in [-1, 1) from an integer (splitmix64).
double hash_unit(std::uint64_t k) {
  k += 0x9e3779b97f4a7c15ull;
  k = (k ^ (k >> 30)) * 0xbf58476d1ce4e5b9ull;
  k = (k ^ (k >> 27)) * 0x94d049bb133111ebull;
  k ^= k >> 31;
  return static_cast<double>(k >> 11) * 0x1.0p-52 - 1.0;
}

std::uint64_t spread_bits2(std::uint64_t v) {  // 32 bits -> every other bit of 64
  v &= 0xffffffffull;
  v = (v | (v << 16)) & 0x0000ffff0000ffffull;
  v = (v | (v << 8)) & 0x00ff00ff00ff00ffull;
  v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0full;
  v = (v | (v << 2)) & 0x3333333333333333ull;
  v = (v | (v << 1)) & 0x5555555555555555ull;
  return v;
}
std::uint64_t spread_bits3(std::uint64_t v) {  // 21 bits -> every third bit of 63
  v &= 0x1fffffull;
  v = (v | (v << 32)) & 0x1f00000000ffffull;
  v = (v | (v << 16)) & 0x1f0000ff0000ffull;
  v = (v | (v << 8)) & 0x100f00f00f00f00full;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3ull;
  v = (v | (v << 2)) & 0x1249249249249249ull;
  return v;
}

}  // namespace

std::array<double, 3> ForceHistory::at(double time) const {
  if (t.empty()) return {};
  if (time <= t.front()) return f.front();
  if (time >= t.back()) return f.back();
  const auto it = std::upper_bound(t.begin(), t.end(), time);
  const std::size_t k = static_cast<std::size_t>(it - t.begin());
  const double w = (time - t[k - 1]) / (t[k] - t[k - 1]);
  std::array<double, 3> r{};
  for (int a = 0; a < 3; ++a) r[a] = (1 - w) * f[k - 1][a] + w * f[k][a];
  return r;
}

template <int D>
class Model final : public ModelBase {
 public:
  static constexpr int kNs = kNsOf<D>;

  explicit Model(const Settings& s) { settings = s; }

  // ---- particle arrays (structure of arrays, internal order) ---------------------------
  std::array<std::vector<double>, D> x, v, x0, f;
  std::vector<double> im, rad;
  std::vector<std::uint32_t> id, grp;
  std::vector<std::uint8_t> mat, flags;          // flags bit 0: particle has a boundary condition
  mutable std::vector<std::uint32_t> inv_cache;  // id -> internal index (built on demand)
  PairList bonds, contacts;

  // ---- set-up state --------------------------------------------------------------------
  std::vector<SolidLatticeLaw> laws;  // nmat × nmat
  int nmat = 0;
  std::vector<BcParticle> bcp;  // sorted by index
  bool sorted = false, initialised = false, bcs_dirty = true;
  double dt_crit = 0, lam_est = 0, lam_bound = 0;

  // ---- run state -------------------------------------------------------------------------
  std::int64_t step_ = 0, last_good = 0;
  double time_ = 0;
  std::vector<BlockAcc> acc;
  bool energy_valid = false;  // acc[].ke/eb are from the last step
  double energy_budget0 = 0, energy_tiny = 0;
  bool budget_dirty = false;  // velocities were set after initialise()
  bool contacts_on = false;
  double skin = 0, disp_bound = 0;

  struct RawEvent {
    std::int64_t step;
    double pos[3];
    std::uint8_t mode;
    std::uint32_t i, j;
  };
  std::vector<std::vector<RawEvent>> evbuf;

  /// Per-thread scratch of the bond pass of one block (see bond_block): each bond's force on
  /// its owner, its energy, and whether the scalar law must redo it.
  struct Scratch {
    std::array<std::vector<double>, D> fb;
    std::vector<double> en;
    std::vector<std::uint8_t> slow;
    void fit(std::size_t m) {
      if (en.size() >= m) return;
      for (auto& a : fb) a.resize(m);
      en.resize(m);
      slow.resize(m);
    }
  };
  std::vector<Scratch> scratch;
  std::vector<BreakEvent> events;

  // ---- thread plan (rebuilt when the thread count or the contact lists change) ---------
  struct Incoming {
    std::uint32_t slot, target;
    bool contact;
  };
  struct Plan {
    int nt = 0;
    std::vector<std::ptrdiff_t> begin;
    std::vector<std::vector<std::array<std::uint32_t, 2>>> own_b, own_c;  // (owner, pair)
    std::vector<std::size_t> base_b, base_c;
    std::vector<std::vector<Incoming>> in;
  } plan;
  bool plan_dirty = true;
  double uniform_diameter = 0;  // 2r when every particle has radius r, else 0 (set by build_plan)
  /// Owner of each bond relative to the start of its block (one byte per bond: kBlock =
  /// 256; the bond pass reads owners from it instead of walking the CSR offsets every step).
  std::vector<std::uint8_t> bond_owner;
  static_assert(kBlock <= 256, "bond_owner holds owner offsets in one byte");
  std::vector<double> cross_b, cross_c;  // D forces + 1 energy per slot

  // ---- per-step context ------------------------------------------------------------------
  struct Ctx {
    double dt, t, g[3];
    std::int64_t step;
    std::vector<std::array<double, 3>> hist;
  };

  // =========================================================================================
  int dim() const override { return D; }
  std::size_t n() const { return im.size(); }

  /// Small models stay on one thread in set-up loops (a parallel region costs more than it
  /// saves there, and much more on a loaded machine).
  bool small_model() const {
    return static_cast<std::ptrdiff_t>(n()) < 2 * std::max(1, settings.min_particles_per_thread);
  }

  /// parallel_for for set-up loops (one thread for small models).
  template <typename F>
  void for_range(std::ptrdiff_t count, F&& f) const {
    if (small_model()) {
      for (std::ptrdiff_t i = 0; i < count; ++i) f(i);
    } else {
      par::parallel_for(count, std::forward<F>(f));
    }
  }

  void reserve(std::size_t cap) override {
    for (int a = 0; a < D; ++a) {
      x[a].reserve(cap);
      v[a].reserve(cap);
    }
    im.reserve(cap);
    rad.reserve(cap);
    id.reserve(cap);
    grp.reserve(cap);
    mat.reserve(cap);
    flags.reserve(cap);
  }

  std::size_t add_particle(std::array<double, 3> p, double r, int m, std::uint32_t g, double mass) override {
    STRATA_CHECK(m >= 0 && m < static_cast<int>(materials.size()), Input,
                 "add_particle: material {} does not exist ({} defined)", m, materials.size());
    STRATA_CHECK(r > 0 && std::isfinite(r), Input, "add_particle: radius {} must be > 0 (m)", r);
    STRATA_CHECK(n() < 0xfffffff0u, Input, "add_particle: too many particles (uint32 indices)");
    STRATA_CHECK(materials.size() <= 255, Input, "at most 255 materials");
    const double d = 2 * r;
    if (mass <= 0)
      mass = materials[m].density * (D == 2 ? std::sqrt(3.0) / 2 * d * d : d * d * d / std::sqrt(2.0));
    STRATA_CHECK(mass > 0 && std::isfinite(mass), Input,
                 "add_particle: mass {} must be > 0 (kg); is the material's density set?", mass);
    for (int a = 0; a < D; ++a) {
      x[a].push_back(p[a]);
      v[a].push_back(0.0);
    }
    im.push_back(1.0 / mass);
    rad.push_back(r);
    if (nmat != static_cast<int>(materials.size())) refresh_laws();
    const std::size_t ident = n() - 1;
    id.push_back(static_cast<std::uint32_t>(ident));
    grp.push_back(g);
    mat.push_back(static_cast<std::uint8_t>(m));
    flags.push_back(0);
    bonds.off.push_back(static_cast<std::uint32_t>(bonds.size()));
    contacts.off.push_back(static_cast<std::uint32_t>(contacts.size()));
    if (initialised) {
      for (int a = 0; a < D; ++a) {
        x0[a].push_back(p[a]);
        f[a].push_back(0.0);
      }
      acc.resize(static_cast<std::size_t>((n() + kBlock - 1) / kBlock));
      plan_dirty = true;
      bcs_dirty = true;
    }
    sorted = sorted && initialised;  // appended at the end; no re-sort once running
    return ident;
  }
  std::size_t particle_count() const override { return n(); }

  /// The nmat × nmat table of pair laws.
  void refresh_laws() {
    nmat = static_cast<int>(materials.size());
    laws.clear();
    for (int a = 0; a < nmat; ++a)
      for (int b = 0; b < nmat; ++b)
        laws.push_back(a == b ? pair_law(materials[a], materials[a]) : pair_law(materials[a], materials[b]));
  }

  /// Inverse of id[]: internal index of each id.
  std::vector<std::uint32_t> index_of_id() const {
    std::vector<std::uint32_t> inv(n());
    for (std::size_t i = 0; i < n(); ++i) inv[id[i]] = static_cast<std::uint32_t>(i);
    return inv;
  }

  void set_velocity(std::size_t ident, std::array<double, 3> vel) override {
    const std::size_t i = index_of(ident, "set_velocity");
    for (int a = 0; a < D; ++a) v[a][i] = vel[a];
    energy_valid = false;
    budget_dirty = initialised;
  }

  /// Internal index of an id (the inverse permutation is cached on first use).
  std::size_t index_of(std::size_t ident, const char* what) const {
    STRATA_CHECK(ident < n(), Input, "{}: no particle with id {}", what, ident);
    if (id[ident] == ident) return ident;
    if (inv_cache.size() != n()) inv_cache = index_of_id();
    return inv_cache[ident];
  }

  void set_kinematics(std::size_t ident, const std::array<double, 3>& u,
                      const std::array<double, 3>& vel) override {
    STRATA_CHECK(initialised, Input, "set_kinematics: call initialise() first");
    if (bcs_dirty) resolve_bcs();
    const std::size_t i = index_of(ident, "set_kinematics");
    auto it = std::lower_bound(bcp.begin(), bcp.end(), static_cast<std::uint32_t>(i),
                               [](const BcParticle& q, std::uint32_t k) { return q.index < k; });
    STRATA_CHECK(it != bcp.end() && it->index == i, Input,
                 "set_kinematics: particle {} is not driven (put it in a group passed to drive())", ident);
    for (int a = 0; a < D; ++a) {
      if (it->mode[a] != 2) continue;
      x[a][i] = x0[a][i] + u[a];
      v[a][i] = vel[a];
      it->value[a] = vel[a];
    }
    energy_valid = false;
  }

  void kinematics(std::size_t ident, std::array<double, 3>& u, std::array<double, 3>& vel) const override {
    const std::size_t i = index_of(ident, "kinematics");
    u = {0, 0, 0};
    vel = {0, 0, 0};
    for (int a = 0; a < D; ++a) {
      u[a] = initialised ? x[a][i] - x0[a][i] : 0.0;
      vel[a] = v[a][i];
    }
  }

  void add_group_bits(const std::vector<std::uint32_t>& ids, std::uint32_t mask) override {
    const auto inv = index_of_id();
    for (const auto k : ids) {
      STRATA_CHECK(k < n(), Input, "group: no particle with id {}", k);
      grp[inv[k]] |= mask;
    }
    bcs_dirty = true;
  }

  std::vector<std::uint32_t> members(std::uint32_t mask) const override {
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < n(); ++i)
      if (grp[i] & mask) out.push_back(id[i]);
    std::sort(out.begin(), out.end());
    return out;
  }

  void bcs_changed() override { bcs_dirty = true; }

  // =========================================================================================
  // Spatial sort (Morton order) so bond endpoints are close in memory.
  template <typename T>
  static void permute(std::vector<T>& a, const std::vector<std::uint32_t>& perm) {
    std::vector<T> tmp(a.size());
    for (std::size_t i = 0; i < perm.size(); ++i) tmp[i] = a[perm[i]];
    a.swap(tmp);
  }

  void sort_particles() {
    const std::size_t N = n();
    double lo[3], hi[3];
    for (int a = 0; a < D; ++a) {
      const auto [mn, mx] = std::minmax_element(x[a].begin(), x[a].end());
      lo[a] = *mn;
      hi[a] = *mx;
    }
    double ext = 0;
    for (int a = 0; a < D; ++a) ext = std::max(ext, hi[a] - lo[a]);
    if (ext <= 0) ext = 1;
    const double bits = D == 2 ? 4294967295.0 : 2097151.0;
    std::vector<std::uint64_t> code(N);
    for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t i) {
      std::uint64_t c = 0;
      for (int a = 0; a < D; ++a) {
        const auto q = static_cast<std::uint64_t>((x[a][i] - lo[a]) / ext * bits);
        c |= (D == 2 ? spread_bits2(q) : spread_bits3(q)) << a;
      }
      code[i] = c;
    });
    std::vector<std::uint32_t> perm(N);
    std::iota(perm.begin(), perm.end(), 0u);
    std::sort(perm.begin(), perm.end(), [&](std::uint32_t p, std::uint32_t q) {
      return code[p] != code[q] ? code[p] < code[q] : p < q;
    });
    code.clear();
    code.shrink_to_fit();
    // Bonds: remember them by pairs of new indices and rebuild the CSR.
    std::vector<std::uint32_t> inv;
    std::vector<std::array<std::uint32_t, 2>> pairs;
    std::vector<std::uint8_t> pst;
    std::vector<double> pus, pr0, pkf;
    if (bonds.size() > 0) {
      inv.assign(N, 0);
      for (std::size_t i = 0; i < N; ++i) inv[perm[i]] = static_cast<std::uint32_t>(i);
      for (std::size_t p = 0; p < N; ++p)
        for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) {
          pairs.push_back({inv[p], inv[bonds.j[k]]});
          pst.push_back(bonds.st[k]);
          for (int s = 0; s < kNs; ++s) pus.push_back(bonds.us[k * kNs + s]);
          if (!bonds.r0.empty()) {
            pr0.push_back(bonds.r0[k]);
            pkf.push_back(bonds.kf[k]);
          }
        }
    }
    for (int a = 0; a < D; ++a) {
      permute(x[a], perm);
      permute(v[a], perm);
    }
    permute(im, perm);
    permute(rad, perm);
    permute(id, perm);
    permute(grp, perm);
    permute(mat, perm);
    permute(flags, perm);
    inv_cache.clear();
    if (!pairs.empty()) {
      for (auto& p : pairs)
        if (p[0] > p[1]) std::swap(p[0], p[1]);
      std::vector<std::uint32_t> order(pairs.size());
      std::iota(order.begin(), order.end(), 0u);
      std::sort(order.begin(), order.end(),
                [&](std::uint32_t a, std::uint32_t b) { return pairs[a] < pairs[b]; });
      PairList nb;
      nb.off.assign(N + 1, 0);
      nb.j.resize(pairs.size());
      nb.st.resize(pairs.size());
      nb.us.resize(pairs.size() * kNs);
      nb.r0.resize(pr0.size());
      nb.kf.resize(pkf.size());
      for (std::size_t k = 0; k < order.size(); ++k) {
        const auto o = order[k];
        nb.off[pairs[o][0] + 1]++;
        nb.j[k] = pairs[o][1];
        nb.st[k] = pst[o];
        for (int s = 0; s < kNs; ++s) nb.us[k * kNs + s] = pus[o * kNs + s];
        if (!pr0.empty()) {
          nb.r0[k] = pr0[o];
          nb.kf[k] = pkf[o];
        }
      }
      for (std::size_t i = 0; i < N; ++i) nb.off[i + 1] += nb.off[i];
      bonds = std::move(nb);
    } else {
      bonds.off.assign(N + 1, 0);
    }
    contacts = PairList{};
    contacts.off.assign(N + 1, 0);
    sorted = true;
  }

  // =========================================================================================
  // Cell grid over the particles: cell side h >= the largest search distance.
  struct Grid {
    double lo[3]{}, h = 1;
    std::int64_t dims[3]{1, 1, 1};
    std::vector<std::uint32_t> start, list;
    std::int64_t cell_of(const double* p) const {
      std::int64_t c = 0, mul = 1;
      for (int a = 0; a < D; ++a) {
        std::int64_t q = static_cast<std::int64_t>((p[a] - lo[a]) / h);
        q = std::clamp<std::int64_t>(q, 0, dims[a] - 1);
        c += q * mul;
        mul *= dims[a];
      }
      return c;
    }
  };

  Grid build_grid(double h) const {
    Grid g;
    const std::size_t N = n();
    double hi[3];
    for (int a = 0; a < D; ++a) {
      const auto [mn, mx] = std::minmax_element(x[a].begin(), x[a].end());
      g.lo[a] = *mn;
      hi[a] = *mx;
    }
    g.h = h;
    for (;;) {  // keep the number of cells O(N)
      double cells = 1;
      for (int a = 0; a < D; ++a) {
        g.dims[a] = static_cast<std::int64_t>((hi[a] - g.lo[a]) / g.h) + 1;
        cells *= static_cast<double>(g.dims[a]);
      }
      if (cells <= 4.0 * static_cast<double>(N) + 64) break;
      g.h *= 1.5;
    }
    std::int64_t ncell = 1;
    for (int a = 0; a < D; ++a) ncell *= g.dims[a];
    std::vector<std::uint32_t> cell(N);
    for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t i) {
      double p[3];
      for (int a = 0; a < D; ++a) p[a] = x[a][i];
      cell[i] = static_cast<std::uint32_t>(g.cell_of(p));
    });
    g.start.assign(static_cast<std::size_t>(ncell) + 1, 0);
    for (std::size_t i = 0; i < N; ++i) g.start[cell[i] + 1]++;
    for (std::int64_t c = 0; c < ncell; ++c) g.start[c + 1] += g.start[c];
    g.list.resize(N);
    std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
    for (std::size_t i = 0; i < N; ++i) g.list[fill[cell[i]]++] = static_cast<std::uint32_t>(i);
    return g;
  }

  /// Calls fn(q) for every particle q > p in the cells around p.
  template <typename Fn>
  void for_neighbours(const Grid& g, std::size_t p, Fn&& fn) const {
    std::int64_t c[3] = {0, 0, 0};
    for (int a = 0; a < D; ++a)
      c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>((x[a][p] - g.lo[a]) / g.h), 0, g.dims[a] - 1);
    const int rz = D == 3 ? 1 : 0;
    for (int dz = -rz; dz <= rz; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::int64_t q[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
          bool ok = true;
          for (int a = 0; a < D; ++a) ok = ok && q[a] >= 0 && q[a] < g.dims[a];
          if (!ok) continue;
          const std::int64_t cell = q[0] + g.dims[0] * (q[1] + (D == 3 ? g.dims[1] * q[2] : 0));
          for (std::uint32_t k = g.start[cell]; k < g.start[cell + 1]; ++k) {
            const std::uint32_t o = g.list[k];
            if (o > p) fn(o);
          }
        }
  }

  double dist2(std::size_t p, std::size_t q) const {
    double s = 0;
    for (int a = 0; a < D; ++a) {
      const double d = x[a][q] - x[a][p];
      s += d * d;
    }
    return s;
  }

  /// Builds a CSR pair list of owners p with partners q > p passing accept(p, q), in
  /// parallel and deterministically (rows sorted by partner).
  template <typename Accept>
  PairList build_pairs(const Grid& g, Accept&& accept) const {
    const std::size_t N = n();
    PairList L;
    L.off.assign(N + 1, 0);
    for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t p) {
      std::uint32_t c = 0;
      for_neighbours(g, static_cast<std::size_t>(p), [&](std::uint32_t q) { c += accept(p, q) ? 1 : 0; });
      L.off[p + 1] = c;
    });
    for (std::size_t i = 0; i < N; ++i) L.off[i + 1] += L.off[i];
    L.j.resize(L.off[N]);
    for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t p) {
      std::uint32_t k = L.off[p];
      for_neighbours(g, static_cast<std::size_t>(p), [&](std::uint32_t q) {
        if (accept(p, q)) L.j[k++] = q;
      });
      std::sort(L.j.begin() + L.off[p], L.j.begin() + L.off[p + 1]);
    });
    return L;
  }

  void bond_touching_pairs(double tol) override {
    STRATA_CHECK(tol >= 0 && tol < 1, Input, "bond_touching_pairs: tolerance {} must be in [0, 1)", tol);
    STRATA_CHECK(!initialised, Input, "bond_touching_pairs: call it before initialise()");
    if (n() == 0) return;
    if (!sorted) sort_particles();
    const double rmax = *std::max_element(rad.begin(), rad.end());
    const Grid g = build_grid(2 * rmax * (1 + tol));
    const double f1 = (1 + tol) * (1 + tol);
    PairList L = build_pairs(g, [&](std::size_t p, std::uint32_t q) {
      const double r = rad[p] + rad[q];
      return dist2(p, q) <= r * r * f1;
    });
    L.st.assign(L.size(), pair_state::kIntact);
    L.us.assign(L.size() * kNs, 0.0);
    bonds = std::move(L);
  }

  void set_bonds(const std::vector<std::uint32_t>& bi, const std::vector<std::uint32_t>& bj,
                 const std::vector<double>& factor) override {
    STRATA_CHECK(!initialised, Input, "set_bonds: call it before initialise()");
    STRATA_CHECK(bi.size() == bj.size() && (factor.empty() || factor.size() == bi.size()), Input,
                 "set_bonds: {} first ends, {} second ends and {} factors (need equal counts; factors may be "
                 "omitted)",
                 bi.size(), bj.size(), factor.size());
    STRATA_CHECK(bonds.size() == 0, Input,
                 "set_bonds: the model has bonds already (call it once, instead of "
                 "bond_touching_pairs)");
    if (n() == 0) return;
    const std::size_t N = n();
    if (!sorted) sort_particles();
    const auto inv = index_of_id();
    // bonds by (owner, partner) in internal indices, checked
    std::vector<std::array<std::uint32_t, 2>> pairs(bi.size());
    for (std::size_t b = 0; b < bi.size(); ++b) {
      STRATA_CHECK(bi[b] < N && bj[b] < N && bi[b] != bj[b], Input,
                   "set_bonds: bond {} joins particles {} and {} (ids must differ and be < {})", b, bi[b],
                   bj[b], N);
      const double f = factor.empty() ? 1.0 : factor[b];
      STRATA_CHECK(f > 0 && f <= 1, Input, "set_bonds: stiffness factor {} of bond {} must be in (0, 1]", f,
                   b);
      std::uint32_t p = inv[bi[b]], q = inv[bj[b]];
      if (p > q) std::swap(p, q);
      pairs[b] = {p, q};
    }
    std::vector<std::uint32_t> order(pairs.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return pairs[a] < pairs[b]; });
    PairList L;
    L.off.assign(N + 1, 0);
    L.j.resize(pairs.size());
    L.r0.resize(pairs.size());
    L.kf.resize(pairs.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
      const auto o = order[k];
      STRATA_CHECK(k == 0 || pairs[o] != pairs[order[k - 1]], Input,
                   "set_bonds: particles {} and {} are bonded twice", id[pairs[o][0]], id[pairs[o][1]]);
      L.off[pairs[o][0] + 1]++;
      L.j[k] = pairs[o][1];
      L.r0[k] = std::sqrt(dist2(pairs[o][0], pairs[o][1]));  // rest length: the initial distance
      L.kf[k] = factor.empty() ? 1.0 : factor[o];
    }
    for (std::size_t i = 0; i < N; ++i) L.off[i + 1] += L.off[i];
    L.st.assign(L.size(), pair_state::kIntact);
    L.us.assign(L.size() * kNs, 0.0);
    bonds = std::move(L);
  }

  bool bonded(std::size_t p, std::uint32_t q) const {
    for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k)
      if (bonds.j[k] == q) return true;
    return false;
  }

  /// Rebuilds the contact candidate list (pairs within ri + rj + skin, not bonded) and
  /// carries each surviving pair's state and shear displacement by matching (i, j).
  void rebuild_contacts() {
    const std::size_t N = n();
    const double rmax = *std::max_element(rad.begin(), rad.end());
    const Grid g = build_grid(2 * rmax + skin);
    PairList L = build_pairs(g, [&](std::size_t p, std::uint32_t q) {
      const double r = rad[p] + rad[q] + skin;
      return dist2(p, q) < r * r && !bonded(p, q);
    });
    L.st.assign(L.size(), pair_state::kContact);
    L.us.assign(L.size() * kNs, 0.0);
    if (contacts.size() > 0) {
      for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t p) {
        std::uint32_t a = contacts.off[p], b = L.off[p];
        const std::uint32_t ae = contacts.off[p + 1], be = L.off[p + 1];
        while (a < ae && b < be) {
          if (contacts.j[a] < L.j[b]) {
            ++a;
          } else if (L.j[b] < contacts.j[a]) {
            ++b;
          } else {
            L.st[b] = contacts.st[a];
            for (int s = 0; s < kNs; ++s) L.us[b * kNs + s] = contacts.us[a * kNs + s];
            ++a;
            ++b;
          }
        }
      });
    }
    contacts = std::move(L);
    disp_bound = 0;
    plan_dirty = true;
  }

  // =========================================================================================
  // Boundary conditions: resolve group specs into per-particle records.
  void resolve_bcs() {
    std::vector<BcParticle> out;
    const std::size_t N = n();
    for (std::size_t p = 0; p < N; ++p) {
      flags[p] = 0;
      if (grp[p] == 0) continue;
      BcParticle b;
      b.index = static_cast<std::uint32_t>(p);
      bool any = false;
      for (const auto& s : bc_specs) {
        if (!(grp[p] & s.mask)) continue;
        any = true;
        if (s.kind == BcSpec::Force) {
          b.history = s.history;
          continue;
        }
        for (int a = 0; a < D; ++a) {
          if (!(s.axes & (1u << a))) continue;
          if (s.kind == BcSpec::Fix) {
            b.mode[a] = 1;
            b.value[a] = 0;
          } else if (s.kind == BcSpec::Velocity) {
            b.mode[a] = 2;
            b.value[a] = s.value[a];
          } else {
            b.mode[a] = 3;
            b.value[a] = s.value[a];
            b.every[a] = s.every;
          }
        }
      }
      if (!any) continue;
      // keep the trapezoid history of particles that already had a condition
      auto old = std::lower_bound(bcp.begin(), bcp.end(), b.index,
                                  [](const BcParticle& q, std::uint32_t i) { return q.index < i; });
      if (old != bcp.end() && old->index == b.index) {
        std::copy(old->dx_prev, old->dx_prev + 3, b.dx_prev);
        std::copy(old->f_int, old->f_int + 3, b.f_int);
      }
      flags[p] = 1;
      out.push_back(b);
    }
    bcp = std::move(out);
    bcs_dirty = false;
  }

  // =========================================================================================
  // The law of the pair (p, q).
  const SolidLatticeLaw& law_of(std::size_t p, std::size_t q) const {
    return laws[static_cast<std::size_t>(mat[p]) * nmat + mat[q]];
  }

  /// Length at which pair k of L (between p and j) carries no normal force: ri + rj (the
  /// disks/spheres touch), or an eccentric-lattice bond's initial length (intact or broken:
  /// a broken one pushes back once shorter than that, as two touching grains would).
  double rest_of(const PairList& L, std::uint32_t k, std::size_t p, std::size_t j) const {
    return L.r0.empty() ? rad[p] + rad[j] : L.r0[k];
  }
  /// The law of pair k of L: the materials' law, with Kn and Ks scaled by an intact
  /// eccentric-lattice bond's stiffness factor (SPEC C4: k -> γ·k).
  SolidLatticeLaw law_for(const PairList& L, std::uint32_t k, std::size_t p, std::size_t j) const {
    SolidLatticeLaw l = law_of(p, j);
    if (!L.kf.empty() && (L.st[k] & pair_state::kKindMask) == pair_state::kIntact) {
      l.kn *= L.kf[k];
      l.ks *= L.kf[k];
    }
    return l;
  }

  /// One pair: geometry (normal, tangential increment, rotation of the stored shear
  /// displacement into the current tangent plane), then the law. F receives the force on
  /// the owner p; returns the pair's energy when kEnergy. Commit=false works on copies.
  template <bool kEnergy>
  static inline double pair_force(const double* const* X, const double* const* V, double rest, std::size_t p,
                                  std::uint32_t j, std::uint8_t& st, double* us, const SolidLatticeLaw& law,
                                  double dt, double* F, int& broke) {
    double n[D], len2 = 0;
    for (int a = 0; a < D; ++a) {
      n[a] = X[a][j] - X[a][p];
      len2 += n[a] * n[a];
    }
    const double len = std::sqrt(len2);
    const double inv = 1.0 / len;
    for (int a = 0; a < D; ++a) n[a] *= inv;
    const double un = rest - len;
    double dus[kNs];
    if constexpr (D == 2) {
      // tangent t = (-n_y, n_x); the scalar Us rotates with the normal
      dus[0] = ((V[1][j] - V[1][p]) * n[0] - (V[0][j] - V[0][p]) * n[1]) * dt;
    } else {
      double du[3], dun = 0, usn = 0;
      for (int a = 0; a < 3; ++a) {
        du[a] = (V[a][j] - V[a][p]) * dt;
        dun += du[a] * n[a];
        usn += us[a] * n[a];
      }
      // keep Us in the current tangent plane: project out its normal part. Its length
      // shrinks by a factor cos(θ) for the per-step rotation θ of the normal (θ ~ 1e-6 in
      // a loaded lattice, a relative change of 1e-12 per step), which is not restored.
      for (int a = 0; a < 3; ++a) us[a] -= usn * n[a];
      for (int a = 0; a < 3; ++a) dus[a] = du[a] - dun * n[a];
    }
    const PairOutcome<kNs> o = law.template apply<kNs>(st, un, us, dus);
    broke = o.broke;
    if constexpr (D == 2) {
      F[0] = -o.fn * n[0] - o.fs[0] * n[1];
      F[1] = -o.fn * n[1] + o.fs[0] * n[0];
    } else {
      for (int a = 0; a < 3; ++a) F[a] = -o.fn * n[a] + o.fs[a];
    }
    if constexpr (kEnergy) return law.template energy<kNs>(st, un, us);
    return 0.0;
  }

  // =========================================================================================
  // Thread plan: contiguous ranges of whole blocks; pairs whose partner lies in a later
  // thread's range ("cross pairs") are computed first (phase A), stored in slots, and
  // gathered by both ends in the same order as in a one-thread run.
  int effective_threads(int nt) const {
    const std::ptrdiff_t nb = static_cast<std::ptrdiff_t>((n() + kBlock - 1) / kBlock);
    const std::ptrdiff_t by_size =
        static_cast<std::ptrdiff_t>(n()) / std::max(1, settings.min_particles_per_thread);
    return static_cast<int>(std::max<std::ptrdiff_t>(
        1, std::min<std::ptrdiff_t>({nt, nb, std::max<std::ptrdiff_t>(by_size, 1)})));
  }

  void build_plan(int nt) {
    const std::size_t N = n();
    const std::ptrdiff_t nb = static_cast<std::ptrdiff_t>((N + kBlock - 1) / kBlock);
    nt = effective_threads(nt);
    plan = Plan{};
    plan.nt = nt;
    plan.begin.resize(nt + 1);
    for (int t = 0; t <= nt; ++t)
      plan.begin[t] = std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(N), nb * t / nt * kBlock);
    plan.own_b.assign(nt, {});
    plan.own_c.assign(nt, {});
    plan.in.assign(nt, {});
    plan.base_b.assign(nt + 1, 0);
    plan.base_c.assign(nt + 1, 0);
    evbuf.resize(nt);
    scratch.resize(nt);
    if (nt > 1) {
      for (int t = 0; t < nt; ++t) {
        const auto b = plan.begin[t], e = plan.begin[t + 1];
        for (std::ptrdiff_t p = b; p < e; ++p) {
          for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k)
            if (bonds.j[k] >= e) plan.own_b[t].push_back({static_cast<std::uint32_t>(p), k});
          for (std::uint32_t k = contacts.off[p]; k < contacts.off[p + 1]; ++k)
            if (contacts.j[k] >= e) plan.own_c[t].push_back({static_cast<std::uint32_t>(p), k});
        }
        plan.base_b[t + 1] = plan.base_b[t] + plan.own_b[t].size();
        plan.base_c[t + 1] = plan.base_c[t] + plan.own_c[t].size();
      }
      auto thread_of = [&](std::uint32_t j) {
        return static_cast<int>(
                   std::upper_bound(plan.begin.begin(), plan.begin.end(), static_cast<std::ptrdiff_t>(j)) -
                   plan.begin.begin()) -
               1;
      };
      // incoming lists in ascending owner order (bonds before contacts of the same owner)
      for (int t = 0; t < nt; ++t) {
        std::size_t ib = 0, ic = 0;
        const auto& ob = plan.own_b[t];
        const auto& oc = plan.own_c[t];
        while (ib < ob.size() || ic < oc.size()) {
          const bool take_b = ic >= oc.size() || (ib < ob.size() && ob[ib][0] <= oc[ic][0]);
          if (take_b) {
            const std::uint32_t j = bonds.j[ob[ib][1]];
            plan.in[thread_of(j)].push_back({static_cast<std::uint32_t>(plan.base_b[t] + ib), j, false});
            ++ib;
          } else {
            const std::uint32_t j = contacts.j[oc[ic][1]];
            plan.in[thread_of(j)].push_back({static_cast<std::uint32_t>(plan.base_c[t] + ic), j, true});
            ++ic;
          }
        }
      }
    }
    bond_owner.resize(bonds.size());
    for (std::size_t p = 0; p < N; ++p)
      for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k)
        bond_owner[k] = static_cast<std::uint8_t>(p % kBlock);
    uniform_diameter = N > 0 && std::all_of(rad.begin(), rad.end(), [&](double r) { return r == rad[0]; })
                           ? 2 * rad[0]
                           : 0.0;
    cross_b.assign(plan.base_b[nt] * (D + 1), 0.0);
    cross_c.assign(plan.base_c[nt] * (D + 1), 0.0);
    plan_dirty = false;
  }

  // =========================================================================================
  // Phase A: the cross pairs this thread owns.
  template <bool kEnergy>
  void phase_a(int t, const Ctx& c) {
    const double* X[D];
    const double* V[D];
    for (int a = 0; a < D; ++a) {
      X[a] = x[a].data();
      V[a] = v[a].data();
    }
    auto run_list = [&](const std::vector<std::array<std::uint32_t, 2>>& own, std::size_t base, PairList& L,
                        std::vector<double>& slots) {
      for (std::size_t s = 0; s < own.size(); ++s) {
        const std::uint32_t p = own[s][0], k = own[s][1], j = L.j[k];
        double F[D];
        int broke = 0;
        const double e =
            pair_force<kEnergy>(X, V, rest_of(L, k, p, j), p, j, L.st[k], &L.us[std::size_t{k} * kNs],
                                law_for(L, k, p, j), c.dt, F, broke);
        if (broke) [[unlikely]]
          record(t, c.step, p, j, broke);
        double* out = &slots[(base + s) * (D + 1)];
        for (int a = 0; a < D; ++a) out[a] = F[a];
        out[D] = e;
      }
    };
    run_list(plan.own_b[t], plan.base_b[t], bonds, cross_b);
    run_list(plan.own_c[t], plan.base_c[t], contacts, cross_c);
  }

  void record(int t, std::int64_t step, std::size_t p, std::uint32_t j, int mode) {
    RawEvent ev{step, {0, 0, 0}, static_cast<std::uint8_t>(mode), static_cast<std::uint32_t>(p), j};
    for (int a = 0; a < D; ++a) ev.pos[a] = 0.5 * (x[a][p] + x[a][j]);
    evbuf[t].push_back(ev);
  }

  /// One velocity component through the damped leapfrog update; returns v(n+½).
  template <Damping DK>
  static inline double integrate(double vo, double F, double imass, double g, double dt, double c_visc,
                                 double alpha, double& diss) {
    if constexpr (DK == Damping::None) {
      return vo + dt * (F * imass + g);
    } else if constexpr (DK == Damping::Viscous) {
      // F - c·v(n), v(n) = ½(v(n-½) + v(n+½)): solved for v(n+½) (SPEC C1 damping)
      const double h = 0.5 * c_visc * dt * imass;
      const double vn = (vo * (1 - h) + dt * (F * imass + g)) / (1 + h);
      const double vm = 0.5 * (vo + vn);
      diss += c_visc * vm * vm * dt;
      return vn;
    } else {
      // local non-viscous damping (PFC/Yade): F_d = -α·|F|·sign(v)
      const double ft = F + g / imass;
      const double sgn = static_cast<double>((vo > 0) - (vo < 0));
      const double fd = -alpha * std::abs(ft) * sgn;
      const double vn = vo + dt * (ft + fd) * imass;
      diss -= fd * vn * dt;
      return vn;
    }
  }

  // Bond pass of one block: the forces of the bonds owned by particles p0..pe-1 whose
  // partner lies in this thread's range (j < e), before any of them moves. Intact bonds that
  // stay intact (nearly all) go through a branch-free loop the compiler vectorises (gathers
  // of the endpoints' positions and velocities); the others (broken bonds, bonds breaking
  // now, pairs of two materials) are redone by the scalar law. Both evaluate the same
  // expressions in the same order, so the results do not depend on which path a bond takes.
  /// How the bond pass gets a bond's rest length.
  enum Rest { kRadiusSum, kUniform, kPerBond };

  /// Bonds per chunk of the bond pass (see bond_block).
  static constexpr std::size_t kChunk = 128;

  /// Bond pass pointers of one block (indexed by the block's bond position q).
  struct BondSpan {
    const double *X0, *X1, *X2, *V0, *V1, *V2, *R, *r0, *kf;
    double *F0, *F1, *F2, *en, *us;
    const std::uint8_t* own;
    const std::uint32_t* j;
    std::uint8_t *st, *slow;
    std::uint32_t p0, e;
  };

  /// Bonds qa..qb-1 of a block through SolidLatticeLaw::apply written out for both kinds
  /// of bond: intact (that stays intact) and, when kBroken, broken (friction only). Bitwise
  /// & and selects instead of branches, so the loop vectorises; a bond left for the scalar
  /// law (one breaking now, or a cross bond) keeps its stored state here. Without kBroken
  /// every bond of the range must be intact: the broken-bond law (a square root and a
  /// division per bond) is left out.
  template <bool kEnergy, Rest kRest, bool kBroken>
  void bond_span(const BondSpan& sp, const SolidLatticeLaw& L, double dt, double d_uniform, std::size_t qa,
                 std::size_t qb) {
    using namespace pair_state;
    const double* __restrict X0 = sp.X0, * __restrict X1 = sp.X1, * __restrict X2 = sp.X2;
    const double* __restrict V0 = sp.V0, * __restrict V1 = sp.V1, * __restrict V2 = sp.V2;
    double* __restrict F0 = sp.F0, * __restrict F1 = sp.F1, * __restrict F2 = sp.F2;
    const double* __restrict R = sp.R;
    const double* __restrict br0 = sp.r0;
    const double* __restrict bkf = sp.kf;
    const std::uint8_t* __restrict own = sp.own;
    const std::uint32_t* __restrict bj = sp.j;
    std::uint8_t* __restrict bst = sp.st;
    std::uint8_t* __restrict slow = sp.slow;
    double* __restrict bus = sp.us;
    double* __restrict EN = sp.en;
    const std::uint32_t up0 = sp.p0, ee = sp.e;
    const double kn0 = L.kn, ks0 = L.ks, mu = L.mu, fn_max = L.fn_max, fs0 = L.fs0;
    const double mu_b = L.friction_strengthens_bonds ? mu : 0.0;  // intact-bond friction term
    const double ksb2 = ks0 * ks0;                                // broken bonds: the material's stiffness
    // Endpoints, states and verdicts in 64-bit lanes: with a byte-sized type in the loop GCC
    // vectorises 64 bonds at a time (8 registers per double) and spills.
    const std::size_t len_q = qb - qa;
    alignas(64) std::int64_t P[kChunk], J[kChunk], ST[kChunk], SLOW[kChunk];
    alignas(64) double NU[kNs][kChunk];  // new shear displacements (stored for fast bonds only)
    for (std::size_t i = 0; i < len_q; ++i) {
      P[i] = up0 + own[qa + i];
      J[i] = bj[qa + i];
      if constexpr (kBroken) ST[i] = bst[qa + i];
    }
    const std::int64_t ee64 = ee;
    // The geometry of a bond (gathers, length, normal, Us) and its law. Where broken bonds
    // take the friction law as well, they run as two loops: each is short enough for the
    // core to overlap several bonds' square roots and divisions, which in one long loop run
    // back to back; the intact law alone runs best in one loop.
    struct Geo {
      double n[3], un, us[3], u2;
    };
    auto geometry = [&](std::size_t i) {
      const std::size_t q = qa + i;
      const std::int64_t p = P[i], j = J[i];
      double n0 = X0[j] - X0[p], n1 = X1[j] - X1[p], n2 = 0;
      double len2 = n0 * n0 + n1 * n1;
      if constexpr (D == 3) {
        n2 = X2[j] - X2[p];
        len2 += n2 * n2;
      }
      const double len = std::sqrt(len2);
      const double inv = 1.0 / len;
      n0 *= inv;
      n1 *= inv;
      if constexpr (D == 3) n2 *= inv;
      double un;
      if constexpr (kRest == kPerBond) {
        un = br0[q] - len;
      } else if constexpr (kRest == kUniform) {
        un = d_uniform - len;  // two gathers fewer
      } else {
        un = R[p] + R[j] - len;
      }
      // shear displacement with this step's increment, and its square
      double us[3] = {0, 0, 0};  // the stored Us, rotated, plus this step's increment
      if constexpr (D == 2) {
        us[0] = bus[q] + ((V1[j] - V1[p]) * n0 - (V0[j] - V0[p]) * n1) * dt;
      } else {
        const double du0 = (V0[j] - V0[p]) * dt, du1 = (V1[j] - V1[p]) * dt, du2 = (V2[j] - V2[p]) * dt;
        const double dun = du0 * n0 + du1 * n1 + du2 * n2;
        const double b0 = bus[3 * q], b1 = bus[3 * q + 1], b2 = bus[3 * q + 2];
        const double usn = b0 * n0 + b1 * n1 + b2 * n2;
        us[0] = (b0 - usn * n0) + (du0 - dun * n0);
        us[1] = (b1 - usn * n1) + (du1 - dun * n1);
        us[2] = (b2 - usn * n2) + (du2 - dun * n2);
      }
      double u2 = 0;
      for (int a = 0; a < kNs; ++a) u2 += us[a] * us[a];
      Geo g{{n0, n1, n2}, un, {us[0], us[1], us[2]}, u2};
      return g;
    };
    auto law = [&](std::size_t i, const Geo& g) {
      const std::size_t q = qa + i;
      const std::int64_t j = J[i];
      const std::int64_t st0 = kBroken ? ST[i] : std::int64_t{kIntact};
      const double n0 = g.n[0], n1 = g.n[1], n2 = g.n[2], un = g.un, u2 = g.u2;
      const double us[3] = {g.us[0], g.us[1], g.us[2]};
      double kn = kn0, ks = ks0;
      if constexpr (kRest == kPerBond) {
        kn = kn0 * bkf[q];  // intact only
        ks = ks0 * bkf[q];
      }
      // intact: Fn = Kn·Un, Fs = Ks·Us, limits (SPEC C1 eqs. 1-5)
      const bool intact = !kBroken || st0 == kIntact;
      const double fn_i = kn * un;
      const double lim = fs0 + mu_b * std::max(fn_i, 0.0);  // = fs0 exactly when mu_b = 0
      const bool holds = (fn_i >= -fn_max) & (u2 * (ks * ks) <= lim * lim);
      double fn = fn_i, kss = ks, uo[3] = {us[0], us[1], us[2]}, e_b = 0;
      std::int64_t st_b = st0;
      if constexpr (kBroken) {
        // broken: open (Un <= 0) carries nothing and forgets Us; touching: Coulomb slip
        const bool touch = un > 0;
        const double fn_t = kn0 * un;
        const double cap = mu * fn_t;
        const double fs2 = u2 * ksb2;
        const double sc = cap / std::sqrt(fs2);
        const bool slip = fs2 > cap * cap;
        const double fslip = slip ? sc : 1.0;  // us·1.0 is us exactly
        double ub[3], ub2 = 0;
        for (int a = 0; a < kNs; ++a) {
          ub[a] = touch ? us[a] * fslip : 0.0;
          ub2 += ub[a] * ub[a];
        }
        // reclosed: touching again after having separated
        const std::int64_t reclosed = ((st0 & kSeparated) != 0) & ((st0 & kTouching) == 0);
        st_b = touch ? (st0 | kTouching | (reclosed * kReclosed))
                     : ((st0 & ~std::int64_t{kTouching}) | kSeparated);
        fn = intact ? fn_i : (touch ? fn_t : 0.0);
        kss = intact ? ks : ks0;
        for (int a = 0; a < kNs; ++a) uo[a] = intact ? us[a] : ub[a];
        if constexpr (kEnergy) e_b = touch ? 0.5 * kn0 * un * un + 0.5 * ks0 * ub2 : 0.0;
      }
      const bool fast = (j < ee64) & (!intact | holds);
      SLOW[i] = !fast;
      for (int a = 0; a < kNs; ++a) NU[a][i] = uo[a];
      if constexpr (kBroken) ST[i] = st0 + static_cast<std::int64_t>(fast & !intact) * (st_b - st0);
      if constexpr (D == 2) {
        F0[q] = -fn * n0 - kss * uo[0] * n1;
        F1[q] = -fn * n1 + kss * uo[0] * n0;
      } else {
        F0[q] = -fn * n0 + kss * uo[0];
        F1[q] = -fn * n1 + kss * uo[1];
        F2[q] = -fn * n2 + kss * uo[2];
      }
      if constexpr (kEnergy) EN[q] = intact ? 0.5 * kn * un * un + 0.5 * ks * u2 : e_b;
    };
    if constexpr (kBroken) {
      alignas(64) double GN[D][kChunk], GUN[kChunk], GUS[kNs][kChunk], GU2[kChunk];
#pragma omp simd
      for (std::size_t i = 0; i < len_q; ++i) {
        const Geo g = geometry(i);
        for (int a = 0; a < D; ++a) GN[a][i] = g.n[a];
        GUN[i] = g.un;
        for (int a = 0; a < kNs; ++a) GUS[a][i] = g.us[a];
        GU2[i] = g.u2;
      }
#pragma omp simd
      for (std::size_t i = 0; i < len_q; ++i) {
        Geo g{{0, 0, 0}, GUN[i], {0, 0, 0}, GU2[i]};
        for (int a = 0; a < D; ++a) g.n[a] = GN[a][i];
        for (int a = 0; a < kNs; ++a) g.us[a] = GUS[a][i];
        law(i, g);
      }
    } else {
#pragma omp simd
      for (std::size_t i = 0; i < len_q; ++i) law(i, geometry(i));
    }
    for (std::size_t i = 0; i < len_q; ++i) {
      slow[qa + i] = static_cast<std::uint8_t>(SLOW[i]);
      if constexpr (kBroken) bst[qa + i] = static_cast<std::uint8_t>(ST[i]);
      if (!SLOW[i])
        for (int a = 0; a < kNs; ++a) bus[(qa + i) * kNs + a] = NU[a][i];
    }
  }

  template <bool kEnergy, Rest kRest>
  void bond_block(int t, const Ctx& c, std::ptrdiff_t p0, std::ptrdiff_t pe, std::ptrdiff_t e) {
    const std::uint32_t k0 = bonds.off[p0], k1 = bonds.off[pe];
    const std::size_t m = k1 - k0;
    Scratch& S = scratch[t];
    S.fit(m);
    const std::uint8_t* own = bond_owner.data() + k0;  // owner - p0
    const std::uint32_t up0 = static_cast<std::uint32_t>(p0);
    const double* X[D];
    const double* V[D];
    double* FB[D];
    for (int a = 0; a < D; ++a) {
      X[a] = x[a].data();
      V[a] = v[a].data();
      FB[a] = S.fb[a].data();
    }
    const std::uint32_t* bj = bonds.j.data() + k0;
    double* EN = S.en.data();
    std::uint8_t* slow = S.slow.data();
    const double dt = c.dt;
    const std::uint32_t ee = static_cast<std::uint32_t>(e);
    if (nmat == 1) {
      // one pointer per axis (arrays of pointers keep GCC from vectorising the 3D loop)
      const BondSpan sp{X[0],
                        X[1],
                        X[D - 1],
                        V[0],
                        V[1],
                        V[D - 1],
                        rad.data(),
                        kRest == kPerBond ? bonds.r0.data() + k0 : nullptr,
                        kRest == kPerBond ? bonds.kf.data() + k0 : nullptr,
                        FB[0],
                        FB[1],
                        FB[D - 1],
                        EN,
                        bonds.us.data() + std::size_t{k0} * kNs,
                        own,
                        bj,
                        bonds.st.data() + k0,
                        slow,
                        up0,
                        ee};
      // chunks of bonds with no broken bond (nearly all of an unbroken lattice) skip the
      // broken-bond law; the others take the full one
      const std::uint8_t* stq = sp.st;
      for (std::size_t qa = 0; qa < m; qa += kChunk) {
        const std::size_t qb = std::min(m, qa + kChunk);
        std::uint8_t any = 0;
        for (std::size_t q = qa; q < qb; ++q) any |= stq[q];
        if (any == pair_state::kIntact)
          bond_span<kEnergy, kRest, false>(sp, laws[0], dt, uniform_diameter, qa, qb);
        else
          bond_span<kEnergy, kRest, true>(sp, laws[0], dt, uniform_diameter, qa, qb);
      }
    } else {
      std::fill(slow, slow + m, std::uint8_t{1});
    }
    // the scalar law for the rest (cross bonds, j >= e, are phase A's)
    for (std::size_t q = 0; q < m; ++q) {
      if (q % 8 == 0 && q + 8 <= m) {  // skip 8 fast bonds at a time
        std::uint64_t w;
        std::memcpy(&w, slow + q, 8);
        if (w == 0) {
          q += 7;
          continue;
        }
      }
      if (!slow[q] || bj[q] >= ee) [[likely]]
        continue;
      const std::uint32_t p = up0 + own[q], j = bj[q], k = k0 + static_cast<std::uint32_t>(q);
      double F[D];
      int broke = 0;
      EN[q] = pair_force<kEnergy>(X, V, rest_of(bonds, k, p, j), p, j, bonds.st[k],
                                  &bonds.us[std::size_t{k} * kNs], law_for(bonds, k, p, j), dt, F, broke);
      for (int a = 0; a < D; ++a) FB[a][q] = F[a];
      if (broke) [[unlikely]]
        record(t, c.step, p, j, broke);
    }
  }

  // Phase B: gather + update of this thread's particles, computing its internal pairs on
  // the way (a pair (p, j) with j in range is computed when p is reached; j > p has not
  // moved yet, and p's own force is complete once its own pairs are done).
  template <Damping DK, bool kEnergy>
  void phase_b(int t, const Ctx& c) {
    const std::ptrdiff_t b = plan.begin[t], e = plan.begin[t + 1];
    if (b >= e) return;
    double* __restrict X[D];
    double* __restrict V[D];
    double* __restrict FA[D];
    for (int a = 0; a < D; ++a) {
      X[a] = x[a].data();
      V[a] = v[a].data();
      FA[a] = f[a].data();
    }
    const double* __restrict R = rad.data();
    const double* __restrict IM = im.data();
    const std::uint8_t* __restrict FL = flags.data();
    const std::uint32_t* __restrict boff = bonds.off.data();
    const std::uint32_t* __restrict bj = bonds.j.data();
    const std::uint32_t* __restrict coff = contacts.off.data();
    const std::uint32_t* __restrict cj = contacts.j.data();
    std::uint8_t* __restrict cst = contacts.st.data();
    double* __restrict cus = contacts.us.data();
    const double dt = c.dt, cv = settings.viscous_c, alpha = settings.local_alpha;
    const bool one_law = nmat == 1;
    const SolidLatticeLaw law0 = laws[0];
    const std::size_t nwalls = walls.size();
    const Wall* W = walls.data();
    const double* XC[D];
    const double* VC[D];
    for (int a = 0; a < D; ++a) {
      XC[a] = X[a];
      VC[a] = V[a];
    }

    // incoming cross contributions, ascending owner
    for (const Incoming& in : plan.in[t]) {
      const double* s = in.contact ? &cross_c[in.slot * (D + 1)] : &cross_b[in.slot * (D + 1)];
      for (int a = 0; a < D; ++a) FA[a][in.target] -= s[a];
    }
    std::size_t cur_b = plan.base_b[t], cur_c = plan.base_c[t];
    auto bc_it = std::lower_bound(bcp.begin(), bcp.end(), static_cast<std::uint32_t>(b),
                                  [](const BcParticle& q, std::uint32_t i) { return q.index < i; });

    for (std::ptrdiff_t blk = b / kBlock; blk * kBlock < e; ++blk) {
      const std::ptrdiff_t pe = std::min(e, (blk + 1) * kBlock);
      double work = 0, diss = 0, ke = 0, eb = 0, vmax2 = 0;
      if (!bonds.r0.empty())
        bond_block<kEnergy, kPerBond>(t, c, blk * kBlock, pe, e);
      else if (uniform_diameter > 0)
        bond_block<kEnergy, kUniform>(t, c, blk * kBlock, pe, e);
      else
        bond_block<kEnergy, kRadiusSum>(t, c, blk * kBlock, pe, e);
      // the block's bond forces and energies (pointers hoisted: the stores to f[] below
      // would otherwise make the compiler reload them for every bond)
      const std::uint32_t kb0 = boff[blk * kBlock];
      const double* __restrict SF[D];
      for (int a = 0; a < D; ++a) SF[a] = scratch[t].fb[a].data() - kb0;
      const double* __restrict SE = scratch[t].en.data() - kb0;
      for (std::ptrdiff_t p = blk * kBlock; p < pe; ++p) {
        double F[D];
        for (int a = 0; a < D; ++a) {
          F[a] = FA[a][p];
          FA[a][p] = 0.0;
        }
        // bonds owned by p, then contacts owned by p (fixed order)
        for (std::uint32_t k = boff[p]; k < boff[p + 1]; ++k) {
          const std::uint32_t j = bj[k];
          double Fb[D];
          if (j >= static_cast<std::uint32_t>(e)) [[unlikely]] {
            const double* s = &cross_b[cur_b++ * (D + 1)];
            for (int a = 0; a < D; ++a) Fb[a] = s[a];
            if constexpr (kEnergy) eb += s[D];
          } else {
            for (int a = 0; a < D; ++a) {
              Fb[a] = SF[a][k];
              FA[a][j] -= Fb[a];
            }
            if constexpr (kEnergy) eb += SE[k];
          }
          for (int a = 0; a < D; ++a) F[a] += Fb[a];
        }
        for (std::uint32_t k = coff[p]; k < coff[p + 1]; ++k) {
          const std::uint32_t j = cj[k];
          double Fb[D];
          if (j >= static_cast<std::uint32_t>(e)) {
            const double* s = &cross_c[cur_c++ * (D + 1)];
            for (int a = 0; a < D; ++a) Fb[a] = s[a];
            if constexpr (kEnergy) eb += s[D];
          } else {
            int broke = 0;
            const SolidLatticeLaw& law = one_law ? law0 : law_of(p, j);
            const double en = pair_force<kEnergy>(XC, VC, R[p] + R[j], p, j, cst[k],
                                                  &cus[std::size_t{k} * kNs], law, dt, Fb, broke);
            if constexpr (kEnergy) eb += en;
            for (int a = 0; a < D; ++a) FA[a][j] -= Fb[a];
          }
          for (int a = 0; a < D; ++a) F[a] += Fb[a];
        }
        // rigid walls (penalty springs)
        for (std::size_t w = 0; w < nwalls; ++w) {
          double s = 0;
          for (int a = 0; a < D; ++a) s += (X[a][p] - W[w].p[a]) * W[w].n[a];
          const double delta = R[p] - s;
          if (delta > 0) {
            double pw = 0;
            for (int a = 0; a < D; ++a) {
              const double fw = W[w].k * delta * W[w].n[a];
              F[a] += fw;
              pw += fw * W[w].v[a];
            }
            work += pw * dt;  // the moving wall does work F·v_wall·dt
            if constexpr (kEnergy) eb += 0.5 * W[w].k * delta * delta;
          }
        }
        const double imass = IM[p];
        double v2 = 0, vv = 0;
        if (!FL[p]) [[likely]] {
          double dp = 0;  // this particle's damping loss: one add per particle on the block's chain
          for (int a = 0; a < D; ++a) {
            const double vo = V[a][p];
            const double vn = integrate<DK>(vo, F[a], imass, c.g[a], dt, cv, alpha, dp);
            V[a][p] = vn;
            X[a][p] += vn * dt;
            v2 += vn * vn;
            vv += vo * vn;
          }
          diss += dp;
        } else {
          BcParticle& bc = *bc_it++;
          double fapp[3] = {0, 0, 0};
          if (bc.history >= 0)
            for (int a = 0; a < D; ++a) fapp[a] = c.hist[bc.history][a];
          bc.w_ahead = 0;
          for (int a = 0; a < D; ++a) {
            bc.f_int[a] = F[a];
            const double vo = V[a][p];
            double vn;
            if (bc.mode[a] == 0) {
              vn = integrate<DK>(vo, F[a] + fapp[a], imass, c.g[a], dt, cv, alpha, diss);
              work += fapp[a] * vn * dt;
            } else {
              if (bc.mode[a] == 1)
                vn = 0;
              else if (bc.mode[a] == 2)
                vn = bc.value[a];
              else
                vn = (c.step + 1) % bc.every[a] == 0 ? bc.value[a] / dt : 0.0;
              // reaction work, trapezoid rule: -½·F(n)·(Δx(n-½) + Δx(n+½))
              const double dx = vn * dt;
              const double fr = F[a] + fapp[a] + c.g[a] / imass;
              work -= 0.5 * fr * (bc.dx_prev[a] + dx);
              bc.w_ahead -= 0.5 * fr * dx;
              bc.dx_prev[a] = dx;
            }
            V[a][p] = vn;
            X[a][p] += vn * dt;
            v2 += vn * vn;
            vv += vo * vn;
          }
        }
        vmax2 = std::max(vmax2, v2);
        if constexpr (kEnergy) ke += 0.5 * vv / imass;
      }
      BlockAcc& A = acc[blk];
      A.work += work;
      A.dissipated += diss;
      A.vmax2 = vmax2;
      if constexpr (kEnergy) {
        A.ke = ke;
        A.eb = eb;
      }
    }
  }

  template <Damping DK, bool kEnergy>
  void step_once(const Ctx& c) {
    const int nt = plan.nt;
    par::parallel_team(nt, [&](int t, int team) {
      if (team != nt) {  // fewer threads than planned: run the plan serially on thread 0
        if (t == 0) {
          for (int s = 0; s < nt; ++s) phase_a<kEnergy>(s, c);
          for (int s = 0; s < nt; ++s) phase_b<DK, kEnergy>(s, c);
        }
        return;
      }
      if (nt > 1) {
        phase_a<kEnergy>(t, c);
        par::team_barrier();
      }
      phase_b<DK, kEnergy>(t, c);
    });
  }

  template <bool kEnergy>
  void dispatch(const Ctx& c) {
    switch (settings.damping) {
      case Damping::None:
        step_once<Damping::None, kEnergy>(c);
        break;
      case Damping::Viscous:
        step_once<Damping::Viscous, kEnergy>(c);
        break;
      case Damping::Local:
        step_once<Damping::Local, kEnergy>(c);
        break;
    }
  }

  void merge_events() {
    std::vector<BreakEvent> fresh;
    for (auto& buf : evbuf) {
      for (const RawEvent& r : buf)
        fresh.push_back(
            {r.step, {r.pos[0], r.pos[1], r.pos[2]}, static_cast<BreakMode>(r.mode), id[r.i], id[r.j]});
      buf.clear();
    }
    std::sort(fresh.begin(), fresh.end(), [](const BreakEvent& a, const BreakEvent& b) {
      if (a.step != b.step) return a.step < b.step;
      if (a.id_i != b.id_i) return a.id_i < b.id_i;
      return a.id_j < b.id_j;
    });
    events.insert(events.end(), fresh.begin(), fresh.end());
  }

  void run(std::int64_t steps, bool energies_at_end) override {
    STRATA_CHECK(initialised, Input, "run: call initialise() first");
    STRATA_CHECK(steps >= 0, Input, "run: steps = {} must be >= 0", steps);
    if (steps == 0) return;
    if (bcs_dirty) resolve_bcs();
    if (budget_dirty) {  // initial conditions changed: the energy budget grows with them
      energy_budget0 = std::max(energy_budget0, dry_kinetic() + dry_bond_energy());
      budget_dirty = false;
    }
    const int nt = par::threads();
    if (plan_dirty || plan.nt != effective_threads(nt)) build_plan(nt);
    Ctx c;
    c.dt = settings.dt;
    for (int a = 0; a < 3; ++a) c.g[a] = settings.gravity[a];
    c.hist.resize(histories.size());
    const int check = settings.energy_check_every;
    for (std::int64_t s = 0; s < steps; ++s) {
      c.step = step_;
      c.t = time_;
      for (std::size_t h = 0; h < histories.size(); ++h) c.hist[h] = histories[h].at(time_);
      const bool check_now = check > 0 && (step_ + 1) % check == 0;
      const bool energy = (energies_at_end && s == steps - 1) || check_now;
      if (energy)
        dispatch<true>(c);
      else
        dispatch<false>(c);
      double vmax2 = 0;
      for (const BlockAcc& A : acc) vmax2 = std::max(vmax2, A.vmax2);
      for (Wall& w : walls)
        for (int a = 0; a < 3; ++a) w.p[a] += w.v[a] * c.dt;
      ++step_;
      time_ += c.dt;
      energy_valid = energy;
      if (contacts_on) {
        disp_bound += std::sqrt(vmax2) * c.dt;
        if (!(disp_bound < 0.5 * skin)) {  // Verlet-skin rule (also catches NaN)
          if (!std::isfinite(disp_bound)) check_blowup(true);
          rebuild_contacts();
          build_plan(nt);
        }
      }
      if (check_now) check_blowup(false);
    }
    merge_events();
  }

  void check_blowup(bool nan_seen) {
    double ke = 0, eb = 0;
    for (const BlockAcc& A : acc) {
      ke += A.ke;
      eb += A.eb;
    }
    const double w = std::abs(external_work());
    const double budget = 10 * (energy_budget0 + w) + energy_tiny;
    if (nan_seen || !std::isfinite(ke) || !std::isfinite(eb) || (energy_valid && ke > budget)) {
      merge_events();
      fail(ErrorKind::Numerical,
           "blow-up at step {}, t={:.6g} s: kinetic energy {:.4g} J, stored energy {:.4g} J, work input "
           "{:.4g} J "
           "(dt = {:.4g} s, critical dt = {:.4g} s); last good step {}",
           step_, time_, ke, eb, w, settings.dt, dt_crit, last_good);
    }
    last_good = step_;
  }

  // =========================================================================================
  void initialise() override {
    STRATA_CHECK(n() > 0, Input, "initialise: the model has no particles");
    STRATA_CHECK(!materials.empty(), Input, "initialise: no material");
    STRATA_CHECK(settings.dt > 0 && std::isfinite(settings.dt), Input, "dt = {} must be > 0 (s)",
                 settings.dt);
    STRATA_CHECK(settings.local_alpha >= 0 && settings.local_alpha < 1, Input,
                 "local_alpha = {} must be in [0, 1)", settings.local_alpha);
    STRATA_CHECK(settings.viscous_c >= 0, Input, "viscous_c = {} must be >= 0 (N·s/m)", settings.viscous_c);
    if (!sorted) sort_particles();
    refresh_laws();
    resolve_bcs();
    acc.assign(static_cast<std::size_t>((n() + kBlock - 1) / kBlock), BlockAcc{});
    const double rmax = *std::max_element(rad.begin(), rad.end());
    skin = settings.skin > 0 ? settings.skin : 0.5 * rmax;
    contacts_on = settings.contact_detection;
    if (contacts_on) rebuild_contacts();
    compute_critical_dt();
    check_dt();
    for (int a = 0; a < D; ++a) {  // allocated after the time-step estimate's temporaries
      x0[a] = x[a];
      f[a].assign(n(), 0.0);
    }
    // energy budget of the blow-up check: initial kinetic + stored energy
    energy_budget0 = dry_kinetic() + dry_bond_energy();
    double kmax = 0;
    for (const auto& l : laws) kmax = std::max(kmax, l.max_stiffness());
    energy_tiny = static_cast<double>(n()) * 0.5 * kmax * std::pow(1e-6 * 2 * rmax, 2);
    build_plan(par::threads());
    initialised = true;
    last_good = step_;
  }

  void check_dt() override {
    if (!initialised && dt_crit == 0) return;  // checked by initialise()
    if (settings.dt > dt_crit) {
      if (!settings.allow_unstable)
        fail(ErrorKind::Numerical,
             "dt = {:.4g} s exceeds the critical time step {:.4g} s (ratio {:.3f}); lower dt or set "
             "allow_unstable",
             settings.dt, dt_crit, settings.dt / dt_crit);
      log::warn("dt = {:.4g} s exceeds the critical time step {:.4g} s (ratio {:.3f}): the run may blow up",
                settings.dt, dt_crit, settings.dt / dt_crit);
    }
  }

  // K·u over intact bonds and touching contacts: (K u)_i = Σ_b K_b (u_i - u_j),
  // K_b = Kn·n nᵀ + Ks·(I - n nᵀ). The stiff pairs owned by particle p:
  template <typename Fn>
  void stiff_pairs_of(std::size_t p, Fn&& fn) const {
    for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) {
      const std::uint32_t j = bonds.j[k];
      const double r = rest_of(bonds, k, p, j);
      const bool on = (bonds.st[k] & pair_state::kKindMask) == pair_state::kIntact || dist2(p, j) < r * r;
      if (on) fn(p, j, law_for(bonds, k, p, j));
    }
    for (std::uint32_t k = contacts.off[p]; k < contacts.off[p + 1]; ++k) {
      const std::uint32_t j = contacts.j[k];
      if (dist2(p, j) < (rad[p] + rad[j]) * (rad[p] + rad[j])) fn(p, j, law_of(p, j));
    }
  }
  template <typename Fn>
  void for_each_stiff_pair(Fn&& fn) const {
    for (std::size_t p = 0; p < n(); ++p) stiff_pairs_of(p, fn);
  }

  /// Unit vector from p to j.
  void unit_normal(std::size_t p, std::uint32_t j, double nv[D]) const {
    double l2 = 0;
    for (int a = 0; a < D; ++a) {
      nv[a] = x[a][j] - x[a][p];
      l2 += nv[a] * nv[a];
    }
    const double l = std::sqrt(l2);
    for (int a = 0; a < D; ++a) nv[a] /= l;
  }

  void pair_matrix(std::size_t p, std::uint32_t j, const SolidLatticeLaw& law, double K[D][D]) const {
    double nv[D];
    unit_normal(p, j, nv);
    for (int a = 0; a < D; ++a)
      for (int b2 = 0; b2 < D; ++b2) K[a][b2] = (law.kn - law.ks) * nv[a] * nv[b2] + (a == b2 ? law.ks : 0.0);
  }

  void compute_critical_dt() {
    const std::size_t N = n();
    // rigorous bound: uᵀKu <= Σ_b 2(u_iᵀK_b u_i + u_jᵀK_b u_j) => λ <= max_i λmax(2ΣK_b)/m_i
    // (ΣK_b kept in float, upper triangle only, to keep the set-up's memory peak low; the
    // result is raised by 1e-5 to cover the float round-off)
    constexpr int kSym = D * (D + 1) / 2;
    std::vector<float> S(N * kSym, 0.0f);
    std::size_t npairs = 0;
    for_each_stiff_pair([&](std::size_t p, std::uint32_t j, const SolidLatticeLaw& law) {
      double K[D][D];
      pair_matrix(p, j, law, K);
      int e = 0;
      for (int a = 0; a < D; ++a)
        for (int b2 = a; b2 < D; ++b2, ++e) {
          S[p * kSym + e] += static_cast<float>(K[a][b2]);
          S[std::size_t{j} * kSym + e] += static_cast<float>(K[a][b2]);
        }
      ++npairs;
    });
    double bound = 0;
    for (std::size_t i = 0; i < N; ++i) {
      Eigen::Matrix<double, D, D> M;
      int e = 0;
      for (int a = 0; a < D; ++a)
        for (int b2 = a; b2 < D; ++b2, ++e) M(a, b2) = M(b2, a) = S[i * kSym + e];
      const double lm = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>>(M, Eigen::EigenvaluesOnly)
                            .eigenvalues()(D - 1);
      bound = std::max(bound, 2 * lm * im[i] * (1 + 1e-5));
    }
    S.clear();
    S.shrink_to_fit();
    double kmax = 0;
    for (const auto& l : laws) kmax = std::max(kmax, l.max_stiffness());
    // contacts may form later: a particle touching z neighbours (6 in 2D, 12 in 3D)
    // through contacts of stiffness <= kmax has λ <= 2·z·kmax/m (same bound)
    double contact_bound = 0;
    if (contacts_on) {
      const double imax = *std::max_element(im.begin(), im.end());
      contact_bound = 2.0 * (D == 2 ? 6 : 12) * kmax * imax;
    }
    lam_bound = bound;
    lam_est = npairs > 0 ? lanczos() : 0.0;
    double lam = npairs > 0 ? std::min(bound, 1.01 * lam_est) : contact_bound;
    if (npairs == 0) lam_bound = contact_bound;
    dt_crit = lam > 0 ? 2.0 / std::sqrt(lam) : std::numeric_limits<double>::infinity();
  }

  /// λmax(M^-½ K M^-½) by Lanczos without reorthogonalisation (the largest Ritz value
  /// converges first and stays below λmax), deterministic start vector.
  double lanczos() const {
    // up to 600 unknowns: full reorthogonalisation and as many steps as unknowns (exact
    // extreme eigenvalue); otherwise 120 steps (60 above 200,000 particles), with float
    // vectors above 20,000 unknowns to keep the set-up's memory peak low
    return n() * D <= 20000 ? lanczos_impl<double>() : lanczos_impl<float>();
  }

  /// Set-up loops over fixed chunks of particles: f(c) for c in [0, nc), the chunks split
  /// evenly over the threads (one thread for small models, as for_range).
  template <typename F>
  void for_chunks(std::ptrdiff_t nc, F&& f) const {
    const int nt = small_model() ? 1 : static_cast<int>(std::min<std::ptrdiff_t>(par::threads(), nc));
    par::parallel_team(nt, [&](int t, int team) {
      for (std::ptrdiff_t c = nc * t / team; c < nc * (t + 1) / team; ++c) f(c);
    });
  }

  template <typename Real>
  double lanczos_impl() const {
    const std::size_t N = n(), nd = N * D;
    const bool full = nd <= 600;
    const int kmax = static_cast<int>(full ? nd : std::min<std::size_t>(nd, N > 200000 ? 60 : 120));
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
    constexpr std::size_t kChunk = 1024;
    struct Cross {
      std::uint32_t j;
      Real t[D];
    };
    const std::size_t nc = (N + kChunk - 1) / kChunk;
    std::vector<std::vector<Cross>> cross(nc);
    auto matvec = [&] {
      for_chunks(static_cast<std::ptrdiff_t>(nc), [&](std::ptrdiff_t c) {
        const std::size_t lo = static_cast<std::size_t>(c) * kChunk, hi = std::min(N, lo + kChunk);
        std::fill(w.begin() + static_cast<std::ptrdiff_t>(lo * D),
                  w.begin() + static_cast<std::ptrdiff_t>(hi * D), Real(0));
        auto& out = cross[static_cast<std::size_t>(c)];
        out.clear();
        for (std::size_t p = lo; p < hi; ++p)
          stiff_pairs_of(p, [&](std::size_t pp, std::uint32_t j, const SolidLatticeLaw& law) {
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
              const double t = law.ks * du[a] + (law.kn - law.ks) * ndu * nv[a];
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
      be.push_back(beta);
      par::parallel_for(ndi, [&](std::ptrdiff_t i) {
        qp[i] = q[i];
        q[i] = static_cast<Real>(w[i] / beta);
      });
    }
    const int k = static_cast<int>(al.size());
    Eigen::VectorXd dg(k), sd(std::max(k - 1, 0));
    for (int i = 0; i < k; ++i) dg(i) = al[i];
    for (int i = 0; i + 1 < k; ++i) sd(i) = be[i];
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
    es.computeFromTridiagonal(dg, sd, Eigen::EigenvaluesOnly);
    return es.eigenvalues()(k - 1);
  }

  double critical_dt() const override { return dt_crit; }
  double lambda_bound() const override { return lam_bound; }
  double lambda_estimate() const override { return lam_est; }
  std::int64_t step_count() const override { return step_; }
  double time() const override { return time_; }
  std::int64_t last_good_step() const override { return last_good; }

  // =========================================================================================
  // Probes. "Dry" evaluations work on copies of the pair state, with the pending shear
  // increment (v·dt) the next step would add.
  template <typename Fn>
  void dry_pairs(std::size_t p, Fn&& fn) const {
    const double* X[D];
    const double* V[D];
    for (int a = 0; a < D; ++a) {
      X[a] = x[a].data();
      V[a] = v[a].data();
    }
    auto one = [&](const PairList& L, std::uint32_t k) {
      const std::uint32_t j = L.j[k];
      std::uint8_t st = L.st[k];
      double us[kNs];
      for (int s = 0; s < kNs; ++s) us[s] = L.us[std::size_t{k} * kNs + s];
      double F[D];
      int broke = 0;
      const double e = pair_force<true>(X, V, rest_of(L, k, p, j), p, j, st, us, law_for(L, k, p, j),
                                        settings.dt, F, broke);
      fn(j, F, e, st, us, &L == &contacts);
    };
    for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) one(bonds, k);
    for (std::uint32_t k = contacts.off[p]; k < contacts.off[p + 1]; ++k) one(contacts, k);
  }

  double wall_energy_and_force(std::size_t p, double* F) const {
    double e = 0;
    for (const Wall& w : walls) {
      double s = 0;
      for (int a = 0; a < D; ++a) s += (x[a][p] - w.p[a]) * w.n[a];
      const double delta = rad[p] - s;
      if (delta > 0) {
        for (int a = 0; a < D; ++a) F[a] += w.k * delta * w.n[a];
        e += 0.5 * w.k * delta * delta;
      }
    }
    return e;
  }

  double dry_bond_energy() const {
    return par::parallel_sum<double>(static_cast<std::ptrdiff_t>(n()), [&](std::ptrdiff_t p) {
      double e = 0;
      dry_pairs(static_cast<std::size_t>(p),
                [&](std::uint32_t, const double*, double en, std::uint8_t, const double*, bool) { e += en; });
      double F[D] = {};
      return e + wall_energy_and_force(static_cast<std::size_t>(p), F);
    });
  }
  double dry_kinetic() const {
    return par::parallel_sum<double>(static_cast<std::ptrdiff_t>(n()), [&](std::ptrdiff_t p) {
      double s = 0;
      for (int a = 0; a < D; ++a) s += v[a][p] * v[a][p];
      return 0.5 * s / im[p];
    });
  }

  std::array<double, 3> group_force(std::uint32_t mask) const override {
    const V3 r = par::parallel_sum<V3>(static_cast<std::ptrdiff_t>(n()), [&](std::ptrdiff_t pp) {
      const auto p = static_cast<std::size_t>(pp);
      V3 s;
      const bool gp = grp[p] & mask;
      dry_pairs(p, [&](std::uint32_t j, const double* F, double, std::uint8_t, const double*, bool) {
        const bool gj = grp[j] & mask;
        for (int a = 0; a < D; ++a) s.c[a] += (gp ? F[a] : 0.0) - (gj ? F[a] : 0.0);
      });
      if (gp) {
        double F[D] = {};
        wall_energy_and_force(p, F);
        for (int a = 0; a < D; ++a) s.c[a] += F[a];
      }
      return s;
    });
    return {r.c[0], r.c[1], r.c[2]};
  }

  double kinetic_energy() const override {
    if (!energy_valid) return dry_kinetic();
    double s = 0;
    for (const BlockAcc& A : acc) s += A.ke;
    return s;
  }
  double bond_energy() const override {
    if (!energy_valid) return dry_bond_energy();
    double s = 0;
    for (const BlockAcc& A : acc) s += A.eb;
    return s;
  }
  double external_work() const override {
    double s = 0;
    for (const BlockAcc& A : acc) s += A.work;
    // the energies are those of the last step's time level: leave out the half interval
    // of reaction work already booked beyond it
    for (const BcParticle& b : bcp) s -= b.w_ahead;
    const auto& g = settings.gravity;
    if (g[0] != 0 || g[1] != 0 || g[2] != 0) {  // gravity: Σ m g·(x - x0)
      s += par::parallel_sum<double>(static_cast<std::ptrdiff_t>(n()), [&](std::ptrdiff_t p) {
        double d = 0;
        for (int a = 0; a < D; ++a) d += g[a] * (x[a][p] - x0[a][p]);
        return d / im[p];
      });
    }
    return s;
  }
  double damping_dissipation() const override {
    double s = 0;
    for (const BlockAcc& A : acc) s += A.dissipated;
    return s;
  }
  std::size_t broken_count(int mode) const override {
    std::size_t c = 0;
    for (const auto& e : events)
      if (mode == 0 || static_cast<int>(e.mode) == mode) ++c;
    return c;
  }
  std::size_t bond_count() const override { return bonds.size(); }
  std::size_t contact_count() const override {
    std::size_t c = 0;
    for (const auto* L : {&bonds, &contacts})
      for (std::size_t k = 0; k < L->size(); ++k)
        if ((L->st[k] & pair_state::kKindMask) != pair_state::kIntact && (L->st[k] & pair_state::kTouching))
          ++c;
    return c;
  }
  const std::vector<BreakEvent>& breaks() const override { return events; }

  std::vector<std::array<std::uint32_t, 2>> touching_pairs() const override {
    std::vector<std::array<std::uint32_t, 2>> out;
    for (std::size_t p = 0; p < n(); ++p)
      for (const auto* L : {&bonds, &contacts})
        for (std::uint32_t k = L->off[p]; k < L->off[p + 1]; ++k) {
          const std::uint32_t j = L->j[k];
          const double r = rest_of(*L, k, p, j);
          if (dist2(p, j) < r * r) out.push_back({std::min(id[p], id[j]), std::max(id[p], id[j])});
        }
    std::sort(out.begin(), out.end());
    return out;
  }

  // ---- read access -----------------------------------------------------------------------
  std::vector<std::array<double, 3>> pack(const std::array<std::vector<double>, D>& a) const {
    std::vector<std::array<double, 3>> out(n(), {0, 0, 0});
    for (std::size_t i = 0; i < n(); ++i)
      for (int c = 0; c < D; ++c) out[i][c] = a[c][i];
    return out;
  }
  std::vector<std::array<double, 3>> positions() const override { return pack(x); }
  std::vector<std::array<double, 3>> velocities() const override { return pack(v); }
  std::vector<std::array<double, 3>> displacements() const override {
    std::vector<std::array<double, 3>> out(n(), {0, 0, 0});
    if (!initialised) return out;
    for (std::size_t i = 0; i < n(); ++i)
      for (int c = 0; c < D; ++c) out[i][c] = x[c][i] - x0[c][i];
    return out;
  }
  std::vector<double> radii() const override { return rad; }
  std::vector<std::uint32_t> ids() const override { return id; }
  std::vector<std::uint32_t> group_bits() const override { return grp; }
  std::vector<float> damage() const override {
    std::vector<std::uint32_t> tot(n(), 0), brk(n(), 0);
    for (std::size_t p = 0; p < n(); ++p)
      for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) {
        const std::uint32_t j = bonds.j[k];
        ++tot[p];
        ++tot[j];
        if ((bonds.st[k] & pair_state::kKindMask) != pair_state::kIntact) {
          ++brk[p];
          ++brk[j];
        }
      }
    std::vector<float> out(n(), 0.f);
    for (std::size_t i = 0; i < n(); ++i)
      if (tot[i]) out[i] = static_cast<float>(brk[i]) / static_cast<float>(tot[i]);
    return out;
  }
  std::vector<PairView> pairs(bool want_bonds) const override {
    std::vector<PairView> out;
    const PairList& L = want_bonds ? bonds : contacts;
    const double* X[D];
    const double* V[D];
    for (int a = 0; a < D; ++a) {
      X[a] = x[a].data();
      V[a] = v[a].data();
    }
    out.reserve(L.size());
    for (std::size_t p = 0; p < n(); ++p)
      for (std::uint32_t k = L.off[p]; k < L.off[p + 1]; ++k) {
        const std::uint32_t j = L.j[k];
        std::uint8_t st = L.st[k];
        double us[kNs];
        for (int s = 0; s < kNs; ++s) us[s] = L.us[std::size_t{k} * kNs + s];
        double F[D];
        int broke = 0;
        // forces at the current state without the pending increment (dt = 0)
        pair_force<false>(X, V, rest_of(L, k, p, j), p, j, st, us, law_for(L, k, p, j), 0.0, F, broke);
        const std::uint8_t s0 = L.st[k];
        double fn = 0, fs2 = 0;
        double nv[D], l2 = 0;
        for (int a = 0; a < D; ++a) {
          nv[a] = x[a][j] - x[a][p];
          l2 += nv[a] * nv[a];
        }
        const double l = std::sqrt(l2);
        for (int a = 0; a < D; ++a) fn -= F[a] * nv[a] / l;
        for (int a = 0; a < D; ++a) {
          const double ft = F[a] + fn * nv[a] / l;
          fs2 += ft * ft;
        }
        out.push_back({static_cast<std::uint32_t>(p),
                       j,
                       static_cast<PairKind>(s0 & pair_state::kKindMask),
                       (s0 & pair_state::kTouching) != 0,
                       (s0 & pair_state::kReclosed) != 0,
                       fn,
                       std::sqrt(fs2),
                       {F[0], F[1], D == 3 ? F[D - 1] : 0.0}});
      }
    return out;
  }

  std::size_t memory_bytes() const override {
    std::size_t b = 0;
    for (int a = 0; a < D; ++a)
      b += (x[a].capacity() + v[a].capacity() + x0[a].capacity() + f[a].capacity()) * sizeof(double);
    b += (im.capacity() + rad.capacity()) * sizeof(double);
    b += (id.capacity() + grp.capacity()) * 4 + mat.capacity() + flags.capacity();
    b += bonds.bytes() + contacts.bytes();
    b += bcp.capacity() * sizeof(BcParticle) + acc.capacity() * sizeof(BlockAcc);
    b += (cross_b.capacity() + cross_c.capacity()) * sizeof(double);
    b += bond_owner.capacity();
    b += events.capacity() * sizeof(BreakEvent);
    return b;
  }

  std::uint64_t state_hash() const override {
    std::uint64_t h = 1469598103934665603ull;
    for (int a = 0; a < D; ++a) {
      h = fnv(h, x[a].data(), x[a].size() * sizeof(double));
      h = fnv(h, v[a].data(), v[a].size() * sizeof(double));
    }
    for (const auto* L : {&bonds, &contacts}) {
      h = fnv(h, L->j.data(), L->j.size() * 4);
      h = fnv(h, L->st.data(), L->st.size());
      h = fnv(h, L->us.data(), L->us.size() * sizeof(double));
    }
    return h;
  }

  // ---- checkpoints (state.cpp) -------------------------------------------------------------
  StateRefs state_refs() override {
    StateRefs r;
    r.dim = D;
    for (int a = 0; a < D; ++a) {
      r.x[a] = &x[a];
      r.v[a] = &v[a];
      r.x0[a] = &x0[a];
      r.f[a] = &f[a];
    }
    r.im = &im;
    r.rad = &rad;
    r.id = &id;
    r.grp = &grp;
    r.mat = &mat;
    r.flags = &flags;
    r.bonds = &bonds;
    r.contacts = &contacts;
    r.bcp = &bcp;
    r.acc = &acc;
    r.events = &events;
    r.step = &step_;
    r.last_good = &last_good;
    r.time = &time_;
    r.dt_crit = &dt_crit;
    r.lam_est = &lam_est;
    r.lam_bound = &lam_bound;
    r.energy_budget0 = &energy_budget0;
    r.energy_tiny = &energy_tiny;
    r.skin = &skin;
    r.disp_bound = &disp_bound;
    r.initialised = &initialised;
    r.bcs_dirty = &bcs_dirty;
    r.energy_valid = &energy_valid;
    r.budget_dirty = &budget_dirty;
    r.contacts_on = &contacts_on;
    return r;
  }

  /// After a load: the particles are in their saved (sorted) order; rebuild what derives
  /// from the state. The thread plan is a function of the pair lists and the thread count
  /// only, so rebuilding it does not change the floating-point path.
  void state_loaded() override {
    refresh_laws();
    inv_cache.clear();
    sorted = true;
    plan_dirty = true;
    for (auto& b : evbuf) b.clear();
  }
};

template <int D>
std::unique_ptr<ModelBase> make_model(const Settings& s) {
  return std::make_unique<Model<D>>(s);
}
template std::unique_ptr<ModelBase> make_model<2>(const Settings&);
template std::unique_ptr<ModelBase> make_model<3>(const Settings&);

}  // namespace strata::dem::detail
