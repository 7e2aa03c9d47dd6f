// Neighbour search of the DEM: the cell grid, bonding of touching pairs or of bonds given as
// data, the Verlet contact list, and the thread plan of the step (which pairs cross from one
// thread's range into a later one's).
#include "model.hpp"

#include <strata/core/error.hpp>
#include <strata/core/log.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>

#if defined(__GLIBC__)
#include <malloc.h>  // malloc_trim
#endif

namespace strata::dem::detail {

template <int D>
std::int64_t Model<D>::Grid::cell_of(const double* p) const {
  std::int64_t c = 0, mul = 1;
  for (int a = 0; a < D; ++a) {
    std::int64_t q = static_cast<std::int64_t>((p[a] - lo[a]) / h);
    q = std::clamp<std::int64_t>(q, 0, dims[a] - 1);
    c += q * mul;
    mul *= dims[a];
  }
  return c;
}

template <int D>
typename Model<D>::Grid Model<D>::build_grid(double h) const {
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
  std::vector<std::uint32_t> cell;
  par::resize_paged(cell, N);  // (first writes on all threads: par::page_in)
  for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t i) {
    double p[3];
    for (int a = 0; a < D; ++a) p[a] = x[a][i];
    cell[i] = static_cast<std::uint32_t>(g.cell_of(p));
  });
  g.start.assign(static_cast<std::size_t>(ncell) + 1, 0);
  for (std::size_t i = 0; i < N; ++i) g.start[cell[i] + 1]++;
  for (std::int64_t c = 0; c < ncell; ++c) g.start[c + 1] += g.start[c];
  par::resize_paged(g.list, N);
  std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t i = 0; i < N; ++i) g.list[fill[cell[i]]++] = static_cast<std::uint32_t>(i);
  g.at.reset(new std::array<double, D + 1>[N]);  // first written (and paged in) in parallel
  for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t k) {
    const std::uint32_t i = g.list[k];
    for (int a = 0; a < D; ++a) g.at[k][a] = x[a][i];
    g.at[k][D] = rad[i];
  });
  return g;
}

// The grid's list positions k of the particles q > p in the cells around p, into cand; returns
// their count. The cells of one row lie side by side in the list (one sweep each), and the
// test q > p, true for about half of them whatever the order, selects without a branch.
template <int D>
std::size_t Model<D>::neighbours_after(const Grid& g, std::size_t p, std::vector<std::uint32_t>& cand) const {
  std::int64_t c[3] = {0, 0, 0};
  for (int a = 0; a < D; ++a)
    c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>((x[a][p] - g.lo[a]) / g.h), 0, g.dims[a] - 1);
  const std::int64_t x0 = std::max<std::int64_t>(c[0] - 1, 0), x1 = std::min(c[0] + 1, g.dims[0] - 1);
  const std::uint32_t* start = g.start.data();
  const std::uint32_t* list = g.list.data();
  std::uint32_t lo[9], hi[9];
  int rows = 0;
  std::size_t total = 0;
  const int rz = D == 3 ? 1 : 0;
  for (int dz = -rz; dz <= rz; ++dz)
    for (int dy = -1; dy <= 1; ++dy) {
      const std::int64_t qy = c[1] + dy, qz = c[2] + dz;
      if (qy < 0 || qy >= g.dims[1] || (D == 3 && (qz < 0 || qz >= g.dims[2]))) continue;
      const std::int64_t row = g.dims[0] * (qy + (D == 3 ? g.dims[1] * qz : 0));
      lo[rows] = start[row + x0];
      hi[rows] = start[row + x1 + 1];
      total += hi[rows] - lo[rows];
      ++rows;
    }
  if (cand.size() < total) cand.resize(2 * total);
  std::uint32_t* out = cand.data();
  std::size_t m = 0;
  for (int r = 0; r < rows; ++r)
    for (std::uint32_t k = lo[r]; k < hi[r]; ++k) {
      out[m] = k;
      m += list[k] > p;
    }
  return m;
}

// Builds kLists CSR pair lists of owners p with partners q > p, in parallel and
// deterministically (rows sorted by partner): classify(p, rp, q, d2, rq), with rp and rq the
// radii and d2 = dist2(p, q) (the same bits), puts each neighbour q in list l - 1 for l in
// [1, kLists], or in none for 0.
template <int D>
template <int kLists, typename Classify>
std::array<PairList, kLists> Model<D>::build_pairs(const Grid& g, Classify&& classify) const {
  // One search: each chunk of particles lists its pairs apart, and the lists are joined in
  // chunk order.
  constexpr std::size_t kChunk = 1024;
  const std::size_t N = n(), nc = (N + kChunk - 1) / kChunk;
  std::array<PairList, kLists> L;
  for (PairList& l : L) {
    par::reserve_paged(l.off, N + 1);
    l.off.assign(N + 1, 0);
  }
  std::vector<std::array<std::vector<std::uint32_t>, kLists>> part(nc);
  const std::array<double, D + 1>* at = g.at.get();
  const std::uint32_t* list = g.list.data();
  for_chunks(static_cast<std::ptrdiff_t>(nc), [&](std::ptrdiff_t c) {
    auto& out = part[static_cast<std::size_t>(c)];
    std::vector<std::uint32_t> cand, hit[kLists];  // a particle's candidates and its pairs
    for (std::size_t p = static_cast<std::size_t>(c) * kChunk; p < std::min(N, (c + 1) * kChunk); ++p) {
      const std::size_t m = neighbours_after(g, p, cand);
      double xp[D];
      for (int a = 0; a < D; ++a) xp[a] = x[a][p];
      const double rp = rad[p];
      std::size_t found[kLists]{};
      for (auto& h : hit)
        if (h.size() < m) h.resize(cand.size());
      for (std::size_t i = 0; i < m; ++i) {
        const std::uint32_t k = cand[i], q = list[k];
        const std::array<double, D + 1>& s = at[k];
        double d2 = 0;
        for (int a = 0; a < D; ++a) {
          const double d = s[a] - xp[a];
          d2 += d * d;
        }
        const int l = classify(p, rp, q, d2, s[D]);
        for (int t = 0; t < kLists; ++t) {  // written always, kept where it belongs
          hit[t][found[t]] = q;
          found[t] += l == t + 1;
        }
      }
      for (int t = 0; t < kLists; ++t) {
        std::sort(hit[t].begin(), hit[t].begin() + static_cast<std::ptrdiff_t>(found[t]));
        out[t].insert(out[t].end(), hit[t].begin(), hit[t].begin() + static_cast<std::ptrdiff_t>(found[t]));
        L[t].off[p + 1] = static_cast<std::uint32_t>(found[t]);
      }
    }
  });
  for (PairList& l : L) {
    for (std::size_t i = 0; i < N; ++i) l.off[i + 1] += l.off[i];
    par::resize_paged(l.j, l.off[N]);
  }
  for_chunks(static_cast<std::ptrdiff_t>(nc), [&](std::ptrdiff_t c) {
    for (int l = 0; l < kLists; ++l) {
      auto& in = part[static_cast<std::size_t>(c)][l];
      std::copy(in.begin(), in.end(), L[l].j.begin() + L[l].off[static_cast<std::size_t>(c) * kChunk]);
      std::vector<std::uint32_t>().swap(in);
    }
  });
  return L;
}

template <int D>
void Model<D>::bond_touching_pairs(double tol) {
  STRATA_CHECK(tol >= 0 && tol < 1, Input, "bond_touching_pairs: tolerance {} must be in [0, 1)", tol);
  STRATA_CHECK(!initialised, Input, "bond_touching_pairs: call it before initialise()");
  if (n() == 0) return;
  log::Phases ph("DEM bonds");
  if (!sorted) {
    sort_particles(true);
    ph.lap("spatial order");
  }
  const double rmax = rad.max();
  // With contact detection, the same search also finds the contact candidates initialise()
  // needs (pairs within ri + rj + skin that are not bonded).
  const bool contacts_too = settings.contact_detection;
  const double skin0 = start_skin();
  const Grid g =
      build_grid(contacts_too ? std::max(2 * rmax * (1 + tol), 2 * rmax + skin0) : 2 * rmax * (1 + tol));
  ph.lap("cell grid");
  const double f1 = (1 + tol) * (1 + tol);
  // Touching pairs become bonds; with contact detection, the others within reach are the
  // contact candidates, listed in the same order.
  auto touching = [&](double rp, double d2, double rq) {
    const double r = rp + rq;
    return d2 <= r * r * f1;
  };
  PairList L;
  if (contacts_too) {
    auto found = build_pairs<2>(g, [&](std::size_t, double rp, std::uint32_t, double d2, double rq) {
      const double r = rp + rq + skin0;
      const int bond = touching(rp, d2, rq), near = d2 < r * r;
      return bond + 2 * (near & (bond ^ 1));  // 1: bond, 2: contact candidate (no branch)
    });
    L = std::move(found[0]);
    found_contacts = std::move(found[1]);
    found_contacts_skin = skin0;
  } else {
    auto found = build_pairs<1>(g, [&](std::size_t, double rp, std::uint32_t, double d2, double rq) {
      return int(touching(rp, d2, rq));
    });
    L = std::move(found[0]);
  }
  par::reserve_paged(L.st, L.size());
  L.st.assign(L.size(), pair_state::kIntact);
  bonds = std::move(L);
  bond_us.clear();  // zero histories: initialise() sizes them
  ph.lap("touching pairs");
#if defined(__GLIBC__)
  // The search's lists, one per chunk of particles, were freed in the threads' arenas, which
  // keep them (about 20 B per particle, fragmented): handed back, the run's resident memory
  // stays that of the model.
  malloc_trim(0);
#endif
  keep_rows_if_lattice();
}

template <int D>
void Model<D>::set_bonds(const std::vector<std::uint32_t>& bi, const std::vector<std::uint32_t>& bj,
                         const std::vector<double>& factor, const std::vector<double>& strength) {
  STRATA_CHECK(!initialised, Input, "set_bonds: call it before initialise()");
  STRATA_CHECK(bi.size() == bj.size() && (factor.empty() || factor.size() == bi.size()) &&
                   (strength.empty() || strength.size() == bi.size()),
               Input,
               "set_bonds: {} first ends, {} second ends, {} stiffness and {} strength factors (need equal "
               "counts; factors may be omitted)",
               bi.size(), bj.size(), factor.size(), strength.size());
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
    STRATA_CHECK(f > 0 && f <= 1, Input, "set_bonds: stiffness factor {} of bond {} must be in (0, 1]", f, b);
    const double g = strength.empty() ? 1.0 : strength[b];
    STRATA_CHECK(g > 0 && std::isfinite(g), Input, "set_bonds: strength factor {} of bond {} must be > 0", g,
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
  L.sf.resize(pairs.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto o = order[k];
    STRATA_CHECK(k == 0 || pairs[o] != pairs[order[k - 1]], Input,
                 "set_bonds: particles {} and {} are bonded twice", id[pairs[o][0]], id[pairs[o][1]]);
    L.off[pairs[o][0] + 1]++;
    L.j[k] = pairs[o][1];
    L.r0[k] = std::sqrt(dist2(pairs[o][0], pairs[o][1]));  // rest length: the initial distance
    L.kf[k] = factor.empty() ? 1.0 : factor[o];
    L.sf[k] = strength.empty() ? 1.0 : strength[o];
  }
  for (std::size_t i = 0; i < N; ++i) L.off[i + 1] += L.off[i];
  par::reserve_paged(L.st, L.size());
  L.st.assign(L.size(), pair_state::kIntact);
  bonds = std::move(L);
  bond_us.clear();  // zero histories: initialise() sizes them
}

template <int D>
bool Model<D>::bonded(std::size_t p, std::uint32_t q) const {
  if (bonds_let_go()) return slots.bonds_to(p, q);  // stepping in slots
  for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k)
    if (bonds.j[k] == q) return true;
  return false;
}

// Rebuilds the contact candidate list (pairs within ri + rj + skin, not bonded) and
// carries each surviving pair's state and shear displacement by matching (i, j).
template <int D>
void Model<D>::rebuild_contacts() {
  const double rmax = rad.max();
  const Grid g = build_grid(2 * rmax + skin);
  auto found = build_pairs<1>(g, [&](std::size_t p, double rp, std::uint32_t q, double d2, double rq) {
    const double r = rp + rq + skin;
    return d2 < r * r && !bonded(p, q) ? 1 : 0;
  });
  take_contacts(std::move(found[0]));
}

template <int D>
void Model<D>::take_contacts(PairList L) {
  const std::size_t N = n();
  L.st.assign(L.size(), pair_state::kContact);
  if (keeps_shear()) L.us.assign(L.size() * kNs, 0.0);
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
          if (!L.us.empty() && !contacts.us.empty())
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

// Thread plan: contiguous ranges of whole blocks; pairs whose partner lies in a later
// thread's range ("cross pairs") are computed first (phase A), stored in slots, and
// gathered by both ends in the same order as in a one-thread run.
template <int D>
int Model<D>::effective_threads(int nt) const {
  const std::ptrdiff_t nb = static_cast<std::ptrdiff_t>((n() + kBlock - 1) / kBlock);
  const std::ptrdiff_t by_size =
      static_cast<std::ptrdiff_t>(n()) / std::max(1, settings.min_particles_per_thread);
  return static_cast<int>(
      std::max<std::ptrdiff_t>(1, std::min<std::ptrdiff_t>({nt, nb, std::max<std::ptrdiff_t>(by_size, 1)})));
}

namespace {
/// The thread whose range holds particle i, for ranges starting at begin (nt + 1 entries).
int thread_holding(const std::vector<std::ptrdiff_t>& begin, std::ptrdiff_t i) {
  return static_cast<int>(std::upper_bound(begin.begin(), begin.end(), i) - begin.begin()) - 1;
}
}  // namespace

template <int D>
std::vector<std::ptrdiff_t> Model<D>::thread_ranges(int nt, double cross_cost) const {
  const std::ptrdiff_t N = static_cast<std::ptrdiff_t>(n());
  const std::ptrdiff_t nb = (N + kBlock - 1) / kBlock;
  std::vector<std::ptrdiff_t> begin(nt + 1);
  for (int t = 0; t <= nt; ++t) begin[t] = std::min(N, nb * t / nt * kBlock);
  if (nt == 1) return begin;
  // The work of a block: its particles' updates and its pairs, alike each (in units of a bond
  // through the batch form). A cross pair costs cross_cost such units (phase A) on the thread
  // of its partner; with the ranges of equal blocks the later threads would compute them on
  // top of an equal share.
  std::vector<double> sum(static_cast<std::size_t>(nb) + 1, 0.0);  // the work of blocks 0..b-1
  for (std::ptrdiff_t blk = 0; blk < nb; ++blk) {
    const std::ptrdiff_t p0 = blk * kBlock, pe = std::min(N, p0 + kBlock);
    sum[blk + 1] = sum[blk] + static_cast<double>(pe - p0) + (bonds.off[pe] - bonds.off[p0]) +
                   (contacts.off[pe] - contacts.off[p0]);
  }
  std::vector<double> cross(nt, 0.0);  // the cross pairs each thread computes
  for (int t = 0; t + 1 < nt; ++t) {
    const auto e = static_cast<std::uint32_t>(begin[t + 1]);
    for (const PairList* L : {&bonds, &contacts})
      for (std::uint32_t k = L->off[begin[t]]; k < L->off[e]; ++k)
        if (L->j[k] >= e) [[unlikely]]
          cross[thread_holding(begin, L->j[k])] += 1;
  }
  double total = sum[nb];
  for (const double x : cross) total += cross_cost * x;
  // each thread's blocks: an equal share of the work, less the cross pairs it computes
  double share = 0;
  std::ptrdiff_t prev = 0;
  for (int t = 0; t + 1 < nt; ++t) {
    share += total / nt - cross_cost * cross[t];
    std::ptrdiff_t b = std::lower_bound(sum.begin(), sum.end(), share) - sum.begin();
    if (b > nb || (b > 0 && share - sum[b - 1] < sum[b] - share)) --b;
    b = std::clamp(b, prev, nb);
    begin[t + 1] = std::min(N, b * kBlock);
    prev = b;
  }
  return begin;
}

template <int D>
bool slot_offsets(const PairList& bonds, std::size_t n, std::vector<std::uint32_t>& offs) {
  offs.clear();
  if (bonds.size() == 0) return false;
  for (std::size_t p = 0; p < n; ++p)
    for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) {
      const std::uint32_t o = bonds.j[k] - static_cast<std::uint32_t>(p);
      if (std::find(offs.begin(), offs.end(), o) != offs.end()) continue;
      if (offs.size() == LatticeSlots<D>::kMax) return false;  // too many directions
      offs.push_back(o);
    }
  std::sort(offs.begin(), offs.end());
  return std::bit_ceil(std::size_t{offs.back()} + kBlock) <= kMaxSlotRing;  // else rows too long for a ring
}

template <int D>
LatticeSlots<D> lattice_slots(const PairList& bonds, std::size_t n, int threads) {
  using Slots = LatticeSlots<D>;
  Slots s;
  std::vector<std::uint32_t> offs;  // the distinct offsets of partners from owners, ascending
  if (!slot_offsets<D>(bonds, n, offs)) return s;
  s.mask.assign(n, 0);
  for (std::size_t p = 0; p < n; ++p)
    for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) {
      const auto d =
          std::find(offs.begin(), offs.end(), bonds.j[k] - static_cast<std::uint32_t>(p)) - offs.begin();
      s.mask[p] |= static_cast<typename Slots::Mask>(1u << d);
    }
  s.n = static_cast<int>(offs.size());
  std::copy(offs.begin(), offs.end(), s.off);
  // columns of the bonds' state: each direction joins the first column none of whose
  // directions a particle owns together with it
  std::vector<char> seen(1u << Slots::kMax, 0);
  for (const auto m : s.mask) seen[m] = 1;
  unsigned members[Slots::kMax] = {};  // each column's directions, bit d
  for (int d = 0; d < s.n; ++d) {
    int c = 0;
    for (;; ++c) {
      bool apart = true;
      for (unsigned m = 0; m < (1u << Slots::kMax); ++m)
        apart = apart && !(seen[m] && (m >> d & 1u) && (m & members[c]));
      if (apart) break;
    }
    members[c] |= 1u << d;
    s.col[d] = c;
    s.cols = std::max(s.cols, c + 1);
  }
  for (int d = 0; d < s.n; ++d) {
    s.ring[d] = std::bit_ceil(std::size_t{s.off[d]} + kBlock);
    s.at[d] = s.per;
    s.per += s.ring[d];
  }
  for (int d = 0; d < s.n; ++d) {
    s.run_at[d] = s.run.size();
    for (std::uint32_t p = 0; p < n;) {
      while (p < n && !(s.mask[p] >> d & 1u)) ++p;
      if (p == n) break;
      std::uint32_t q = p, last = p;
      for (; q < n && q - last < Slots::kGap; ++q)
        if (s.mask[q] >> d & 1u) last = q;
      s.run.push_back(p);
      s.run.push_back(last + 1);
      p = q;
    }
  }
  s.run_at[s.n] = s.run.size();
  s.threads = threads;
  s.f.assign(static_cast<std::size_t>(threads) * s.per * D, 0.0);
  s.en.assign(static_cast<std::size_t>(threads) * s.per, 0.0);
  return s;
}

template <int D>
void Model<D>::build_plan(int nt) {
  slots_release();  // the slots are rebuilt below
  const std::size_t N = n();
  const std::ptrdiff_t nb = static_cast<std::ptrdiff_t>((N + kBlock - 1) / kBlock);
  nt = effective_threads(nt);
  plan = Plan{};
  plan.nt = nt;
  slots = LatticeSlots<D>{};
  if (bonds.r0.empty()) slots = lattice_slots<D>(bonds, N, nt);
  // a cross pair through the reference kernel and a slot costs about three bonds of the batch
  // form; in lattice slots (one batch bond and two copies) about one and a half
  const bool slotted = engine && engine->steps_in_slots(*this, settings.lattice_slots);
  plan.begin = thread_ranges(nt, slotted ? 1.5 : 3.0);
  plan.in.assign(nt, {});
  plan.base_b.assign(nt + 1, 0);
  plan.base_c.assign(nt + 1, 0);
  plan.calc.assign(nt, {});
  plan.waits.assign(nt, {});
  plan.done.assign(static_cast<std::size_t>(nt) * Plan::kFlagStride, 0);
  evbuf.resize(nt);
  bond_us.fresh.resize(static_cast<std::size_t>(nt));
  scratch.resize(nt);
  if (nt > 1) {
    // the cross pairs each thread owns, (owner, pair) in ascending owner; their slots follow
    // one another thread by thread from base_b[t] and base_c[t]
    std::vector<std::vector<std::array<std::uint32_t, 2>>> own_b(nt), own_c(nt);
    for (int t = 0; t < nt; ++t) {
      const auto b = plan.begin[t], e = plan.begin[t + 1];
      for (std::ptrdiff_t p = b; p < e; ++p) {
        for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k)
          if (bonds.j[k] >= e) own_b[t].push_back({static_cast<std::uint32_t>(p), k});
        for (std::uint32_t k = contacts.off[p]; k < contacts.off[p + 1]; ++k)
          if (contacts.j[k] >= e) own_c[t].push_back({static_cast<std::uint32_t>(p), k});
      }
      plan.base_b[t + 1] = plan.base_b[t] + own_b[t].size();
      plan.base_c[t + 1] = plan.base_c[t] + own_c[t].size();
    }
    auto thread_of = [&](std::ptrdiff_t i) { return thread_holding(plan.begin, i); };
    // each cross pair, in ascending owner (bonds before contacts of the same owner), goes to
    // its partner's thread twice: to compute it (calc) and to gather it (in)
    for (int t = 0; t < nt; ++t) {
      std::size_t ib = 0, ic = 0;
      const auto& ob = own_b[t];
      const auto& oc = own_c[t];
      while (ib < ob.size() || ic < oc.size()) {
        const bool take_b = ic >= oc.size() || (ib < ob.size() && ob[ib][0] <= oc[ic][0]);
        const auto [p, k] = take_b ? ob[ib] : oc[ic];
        const std::uint32_t j = (take_b ? bonds : contacts).j[k];
        const auto slot = static_cast<std::uint32_t>(take_b ? plan.base_b[t] + ib++ : plan.base_c[t] + ic++);
        plan.calc[thread_of(j)].push_back({p, k, slot, !take_b});
        plan.in[thread_of(j)].push_back({slot, j, !take_b});
      }
    }
    // each owner's thread waits, before a block holding owners of cross pairs computed by a
    // later thread, until that thread has computed its list up to the block's end
    for (int u = 0; u < nt; ++u) {
      const auto& calc = plan.calc[u];
      for (std::size_t i = 0; i < calc.size(); ++i) {
        const std::ptrdiff_t blk = calc[i].owner / kBlock;
        if (i + 1 < calc.size() && calc[i + 1].owner / kBlock == blk) continue;  // the block's last
        plan.waits[thread_of(calc[i].owner)].push_back({blk, u, i + 1});
      }
    }
    for (auto& w : plan.waits)
      std::sort(w.begin(), w.end(), [](const CrossWait& a, const CrossWait& b) {
        return a.blk != b.blk ? a.blk < b.blk : a.by < b.by;
      });
  }
  uniform_diameter = N > 0 && rad.uniform() ? 2 * rad[0] : 0.0;
  bond_owner.clear();
  if (bond_us.empty()) {  // no shear history: owners kept (ModelData::bond_owner)
    par::resize_paged(bond_owner, bonds.size());
    for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t p) {
      for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k)
        bond_owner[k] = static_cast<std::uint8_t>(p % kBlock);
    });
  }
  bond_owner.shrink_to_fit();
  pend_slot.assign(static_cast<std::size_t>(nb * (kBlock / kSlot)), -1);
  pend.assign(nt, PendingPool{std::vector<double>(D * Data::kRingStride, 0.0), {}, {}});
  cross_b.assign(plan.base_b[nt] * (D + 1), 0.0);
  cross_c.assign(plan.base_c[nt] * (D + 1), 0.0);
  plan_dirty = false;
}

#define STRATA_DEM_INSTANTIATE(D)                                                                         \
  template typename Model<D>::Grid Model<D>::build_grid(double) const;                                    \
  template void Model<D>::bond_touching_pairs(double);                                                    \
  template void Model<D>::set_bonds(const std::vector<std::uint32_t>&, const std::vector<std::uint32_t>&, \
                                    const std::vector<double>&, const std::vector<double>&);              \
  template bool Model<D>::bonded(std::size_t, std::uint32_t) const;                                       \
  template void Model<D>::rebuild_contacts();                                                             \
  template void Model<D>::take_contacts(PairList);                                                        \
  template int Model<D>::effective_threads(int) const;                                                    \
  template void Model<D>::build_plan(int);                                                                \
  template LatticeSlots<D> lattice_slots<D>(const PairList&, std::size_t, int);                           \
  template bool slot_offsets<D>(const PairList&, std::size_t, std::vector<std::uint32_t>&);               \
  template std::vector<std::ptrdiff_t> Model<D>::thread_ranges(int, double) const;
STRATA_DEM_INSTANTIATE(2)
STRATA_DEM_INSTANTIATE(3)
#undef STRATA_DEM_INSTANTIATE

}  // namespace strata::dem::detail
