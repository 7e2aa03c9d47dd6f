// The DEM model's storage: structure-of-arrays particles, ids and groups, the spatial order
// that keeps bond endpoints close in memory (Morton; row by row, and layer by layer, for a
// lattice whose bonds then sit in lattice slots), and read access for writers.
// Physics and design notes: docs/dem.md.
#include "model.hpp"

#include <strata/core/error.hpp>
#include <strata/dem/lattice_elastic.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

namespace strata::dem::detail {
namespace {

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

template <int D>
void Model<D>::reserve(std::size_t cap) {
  for (int a = 0; a < D; ++a) {
    x[a].reserve(cap);
    v[a].reserve(cap);
  }
  id.reserve(cap);
  grp.reserve(cap);
  mat.reserve(cap);
  flags.reserve(cap);
  bonds.off.reserve(cap + 1);
  contacts.off.reserve(cap + 1);
}

// The mass of a new particle of radius r and material m (the lattice cell's mass for
// mass <= 0), checked with the radius and the material.
template <int D>
double Model<D>::checked_mass(double r, int m, double mass) const {
  STRATA_CHECK(m >= 0 && m < static_cast<int>(materials.size()), Input,
               "add_particle: material {} does not exist ({} defined)", m, materials.size());
  STRATA_CHECK(r > 0 && std::isfinite(r), Input, "add_particle: radius {} must be > 0 (m)", r);
  STRATA_CHECK(materials.size() <= 255, Input, "at most 255 materials");
  if (mass <= 0) mass = lattice_particle_mass(D, materials[m].density, 2 * r);
  STRATA_CHECK(mass > 0 && std::isfinite(mass), Input,
               "add_particle: mass {} must be > 0 (kg); is the material's density set?", mass);
  return mass;
}

template <int D>
std::size_t Model<D>::add_particle(std::array<double, 3> p, double r, int m, double mass) {
  mass = checked_mass(r, m, mass);
  STRATA_CHECK(n() < 0xfffffff0u, Input, "add_particle: too many particles (uint32 indices)");
  slots_release();  // the slots are laid out over the particles there are
  for (int a = 0; a < D; ++a) {
    x[a].push_back(p[a]);
    v[a].push_back(0.0);
  }
  im.push_back(1.0 / mass);
  rad.push_back(r);
  if (nmat != static_cast<int>(materials.size())) refresh_laws();
  const std::size_t ident = n() - 1;
  id.push_back(static_cast<std::uint32_t>(ident));
  grp.push_back(0);  // no group yet
  mat.push_back(static_cast<std::uint8_t>(m));
  flags.push_back(0);
  bonds.off.push_back(static_cast<std::uint32_t>(bonds.size()));
  contacts.off.push_back(static_cast<std::uint32_t>(contacts.size()));
  if (initialised) {
    for (int a = 0; a < D; ++a) {
      x0[a].push_back(p[a]);
    }
    acc.resize(static_cast<std::size_t>((n() + kBlock - 1) / kBlock));
    plan_dirty = true;
    bcs_dirty = true;
  }
  sorted = sorted && initialised;  // appended at the end; no re-sort once running
  return ident;
}

// Particles at p (all of radius r and material m) at once, as add_particle one by one (the
// same arrays, the same bits), the arrays filled in parallel.
template <int D>
std::size_t Model<D>::add_particles(const std::vector<std::array<double, 3>>& p, double r, int m,
                                    double mass) {
  const std::size_t first = n(), count = p.size();
  if (initialised || count == 0) {  // a running model: one by one, with its extra arrays
    for (const auto& q : p) add_particle(q, r, m, mass);
    return first;
  }
  mass = checked_mass(r, m, mass);
  STRATA_CHECK(first + count <= 0xfffffff0u, Input, "add_particle: too many particles (uint32 indices)");
  slots_release();
  if (nmat != static_cast<int>(materials.size())) refresh_laws();
  const std::size_t n1 = first + count;
  // The arrays grow on all threads at once, one array each: their new pages are first
  // touched in parallel (on a large model the kernel's first touch is most of the time).
  constexpr int kArrays = 2 * D + 6;
  auto grow = [&](int k) {
    if (k < D) return x[k].resize(n1);
    if (k < 2 * D) return v[k - D].resize(n1, 0.0);
    switch (k - 2 * D) {
      case 0:
        return id.resize(n1);
      case 1:
        return grp.resize(n1, 0);
      case 2:
        return mat.resize(n1, static_cast<std::uint8_t>(m));
      case 3:
        return flags.resize(n1, 0);
      case 4:
        return bonds.off.resize(bonds.off.size() + count, static_cast<std::uint32_t>(bonds.size()));
      default:
        return contacts.off.resize(contacts.off.size() + count, static_cast<std::uint32_t>(contacts.size()));
    }
  };
  // (threads for the size the model will have: while the model is empty, small_model() would
  // say one)
  par::parallel_team(small_model(n1) ? 1 : par::threads(), [&](int t, int team) {
    for (int k = t; k < kArrays; k += team) grow(k);
  });
  im.append(count, 1.0 / mass);
  rad.append(count, r);
  for_range(static_cast<std::ptrdiff_t>(count), [&](std::ptrdiff_t i) {
    for (int a = 0; a < D; ++a) x[a][first + i] = p[i][a];
    id[first + i] = static_cast<std::uint32_t>(first + i);
  });
  sorted = false;
  return first;
}

// Inverse of id[]: internal index of each id.
template <int D>
std::vector<std::uint32_t> Model<D>::index_of_id() const {
  std::vector<std::uint32_t> inv;
  par::resize_paged(inv, n());
  // id is a permutation: each i writes its own entry
  for_range(static_cast<std::ptrdiff_t>(n()),
            [&](std::ptrdiff_t i) { inv[id[i]] = static_cast<std::uint32_t>(i); });
  return inv;
}

// Internal index of an id (the inverse permutation is cached on first use).
template <int D>
std::size_t Model<D>::index_of(std::size_t ident, const char* what) const {
  STRATA_CHECK(ident < n(), Input, "{}: no particle with id {}", what, ident);
  if (id[ident] == ident) return ident;
  if (inv_cache.size() != n()) inv_cache = index_of_id();
  return inv_cache[ident];
}

template <int D>
void Model<D>::set_velocity(std::size_t ident, std::array<double, 3> vel) {
  const std::size_t i = index_of(ident, "set_velocity");
  for (int a = 0; a < D; ++a) v[a][i] = vel[a];
  energy_valid = false;
  budget_dirty = initialised;
}

template <int D>
void Model<D>::add_to_group(const std::vector<std::uint32_t>& ids, std::uint32_t group) {
  const auto inv = index_of_id();
  // the new set of each old set, found once (particles share few sets)
  std::vector<std::uint32_t> moved(group_sets.size(), 0xffffffffu);
  for (const auto k : ids) {
    STRATA_CHECK(k < n(), Input, "group: no particle with id {}", k);
    std::uint32_t& s = grp[inv[k]];
    if (moved[s] == 0xffffffffu) moved[s] = set_with(s, group);
    s = moved[s];
  }
  bcs_dirty = true;
}

template <int D>
std::vector<std::uint32_t> Model<D>::members(std::uint32_t group) const {
  const auto in = sets_holding({group});
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < n(); ++i)
    if (in[grp[i]]) out.push_back(id[i]);
  std::sort(out.begin(), out.end());
  return out;
}

// Spatial sort (Morton order) so bond endpoints are close in memory; with rows_allowed, a 2D
// model added row by row keeps that order for now (keep_rows_if_lattice decides after
// bonding).
template <int D>
void Model<D>::sort_particles(bool rows_allowed) {
  const std::size_t N = n();
  if (rows_allowed && added_in_rows()) {
    rows_kept = true;
    sorted = true;
    return;
  }
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
  // (code, index) pairs: the index breaks ties, so the order is total and the same for any
  // thread count; the key sits beside its index, not behind it.
  struct Keyed {
    std::uint64_t code;
    std::uint32_t i;
  };
  std::unique_ptr<Keyed[]> key(new Keyed[N]);  // first written in parallel
  for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t i) {
    std::uint64_t c = 0;
    for (int a = 0; a < D; ++a) {
      const auto q = static_cast<std::uint64_t>((x[a][i] - lo[a]) / ext * bits);
      c |= (D == 2 ? spread_bits2(q) : spread_bits3(q)) << a;
    }
    key[static_cast<std::size_t>(i)] = {c, static_cast<std::uint32_t>(i)};
  });
  auto before = [](const Keyed& p, const Keyed& q) { return p.code != q.code ? p.code < q.code : p.i < q.i; };
  if (small_model())
    std::sort(key.get(), key.get() + N, before);
  else
    par::sort(key.get(), key.get() + N, before);
  std::vector<std::uint32_t> perm;
  par::resize_paged(perm, N);  // (first writes on all threads: par::page_in)
  for_range(static_cast<std::ptrdiff_t>(N), [&](std::ptrdiff_t i) { perm[i] = key[i].i; });
  key.reset();
  reorder(perm);
}

// Whether a model's particles were added row by row (and in 3D layer by layer): ascending in
// the last axis, then the one before, then x (a lattice region's generator adds them so).
// Such a model keeps that order through bonding, and afterwards if every bond then sits in
// lattice slots (keep_rows_if_lattice).
template <int D>
bool Model<D>::added_in_rows() const {
  auto before = [&](std::size_t a, std::size_t b) {
    for (int ax = D - 1; ax >= 0; --ax)
      if (x[ax][a] != x[ax][b]) return x[ax][a] < x[ax][b];
    return false;
  };
  for (std::size_t i = 1; i < n(); ++i)
    if (!before(i - 1, i)) return false;
  return n() > 1;
}

// After bonding a model kept in the order it was added row by row (and layer by layer): that
// order stays where it puts every bond in lattice slots (a lattice whose bond pass can then
// run direction by direction, LatticeSlots), else the Morton order replaces it (and the
// contact candidates found with the bonds are dropped: initialise() searches again).
template <int D>
void Model<D>::keep_rows_if_lattice() {
  if (!rows_kept) return;
  rows_kept = false;
  std::vector<std::uint32_t> offs;
  if (bonds.r0.empty() && slot_offsets<D>(bonds, n(), offs)) return;
  sort_particles();
  found_contacts = PairList{};
}

// Particles and bonds renumbered as new index i = old index perm[i]; contacts cleared.
template <int D>
void Model<D>::reorder(const std::vector<std::uint32_t>& perm) {
  slots_release();
  const std::size_t N = n();
  // Bonds: remember them by pairs of new indices and rebuild the CSR.
  std::vector<std::uint32_t> inv;
  std::vector<std::array<std::uint32_t, 2>> pairs;
  std::vector<std::uint8_t> pst;
  std::vector<double> pus, pr0, pkf, psf;
  if (!bond_us.empty()) bonds.us = bond_us.expanded();  // carried as doubles, taken back below
  if (bonds.size() > 0) {
    inv.assign(N, 0);
    for (std::size_t i = 0; i < N; ++i) inv[perm[i]] = static_cast<std::uint32_t>(i);
    for (std::size_t p = 0; p < N; ++p)
      for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) {
        pairs.push_back({inv[p], inv[bonds.j[k]]});
        pst.push_back(bonds.st[k]);
        if (!bonds.us.empty())
          for (int s = 0; s < kNs; ++s) pus.push_back(bonds.us[k * kNs + s]);
        if (!bonds.r0.empty()) {
          pr0.push_back(bonds.r0[k]);
          pkf.push_back(bonds.kf[k]);
          psf.push_back(bonds.sf[k]);
        }
      }
  }
  // a[i] = a[perm[i]], gathered in parallel into `spare`, which then holds the array replaced
  // (the next gather's target: the arrays of one type share one new allocation)
  auto permute = [&](auto& a, auto& spare) {
    par::resize_paged(spare, a.size());
    for_range(static_cast<std::ptrdiff_t>(perm.size()), [&](std::ptrdiff_t i) { spare[i] = a[perm[i]]; });
    a.swap(spare);
  };
  aligned_vector<double> spare;
  for (int a = 0; a < D; ++a) {
    permute(x[a], spare);
    permute(v[a], spare);
  }
  spare = {};
  im.permute(perm);
  rad.permute(perm);
  std::vector<std::uint32_t> spare32;
  permute(id, spare32);
  permute(grp, spare32);
  spare32 = {};
  std::vector<std::uint8_t> spare8;
  permute(mat, spare8);
  spare8 = {};
  aligned_vector<std::uint8_t> spare_flags;
  permute(flags, spare_flags);
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
    nb.us.resize(pus.size());
    nb.r0.resize(pr0.size());
    nb.kf.resize(pkf.size());
    nb.sf.resize(psf.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
      const auto o = order[k];
      nb.off[pairs[o][0] + 1]++;
      nb.j[k] = pairs[o][1];
      nb.st[k] = pst[o];
      if (!pus.empty())
        for (int s = 0; s < kNs; ++s) nb.us[k * kNs + s] = pus[o * kNs + s];
      if (!pr0.empty()) {
        nb.r0[k] = pr0[o];
        nb.kf[k] = pkf[o];
        nb.sf[k] = psf[o];
      }
    }
    for (std::size_t i = 0; i < N; ++i) nb.off[i + 1] += nb.off[i];
    bonds = std::move(nb);
    if (!bonds.us.empty()) {
      bond_us.take(bonds.us, bonds.st, bond_us.unit);
      bonds.us = {};
    }
  } else {
    bonds.off.assign(N + 1, 0);
  }
  contacts = PairList{};
  contacts.off.assign(N + 1, 0);
  sorted = true;
}

// ---- read access ---------------------------------------------------------------------------
template <int D>
std::vector<std::array<double, 3>> Model<D>::pack(const std::array<aligned_vector<double>, D>& a,
                                                  Rows rows) const {
  std::vector<std::array<double, 3>> out(rows.count(n()), {0, 0, 0});
  for (std::size_t k = 0; k < out.size(); ++k)
    for (int c = 0; c < D; ++c) out[k][c] = a[c][rows[k]];
  return out;
}

template <int D>
std::vector<std::array<double, 3>> Model<D>::displacements(Rows rows) const {
  std::vector<std::array<double, 3>> out(rows.count(n()), {0, 0, 0});
  if (!initialised) return out;
  for (std::size_t k = 0; k < out.size(); ++k)
    for (int c = 0; c < D; ++c) out[k][c] = x[c][rows[k]] - x0[c][rows[k]];
  return out;
}

template <int D>
std::vector<double> Model<D>::radii(Rows rows) const {
  if (rows.all) return rad.values();
  std::vector<double> out(rows.list.size());
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = rad[rows[k]];
  return out;
}

template <int D>
std::vector<std::uint32_t> Model<D>::ids(Rows rows) const {
  if (rows.all) return id;
  std::vector<std::uint32_t> out(rows.list.size());
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = id[rows[k]];
  return out;
}

namespace {
/// Calls f(particle, broken) for both ends of every bond.
template <typename F>
void for_each_bond_end(const PairList& bonds, std::size_t n, F&& f) {
  for (std::size_t p = 0; p < n; ++p)
    for (std::uint32_t k = bonds.off[p]; k < bonds.off[p + 1]; ++k) {
      const bool broken = (bonds.st[k] & pair_state::kKindMask) != pair_state::kIntact;
      f(p, broken);
      f(std::size_t{bonds.j[k]}, broken);
    }
}
}  // namespace

template <int D>
std::vector<std::uint8_t> Model<D>::bond_counts() const {
  bonds_current();
  std::vector<std::uint8_t> count(n(), 0);
  for_each_bond_end(bonds, n(),
                    [&](std::size_t i, bool) { count[i] = std::uint8_t(count[i] + (count[i] < 255)); });
  return count;
}

template <int D>
std::vector<float> Model<D>::damage(Rows rows) const {
  bonds_current();
  std::vector<std::uint32_t> tot(n(), 0), brk(n(), 0);
  for_each_bond_end(bonds, n(), [&](std::size_t i, bool broken) {
    ++tot[i];
    brk[i] += broken;
  });
  std::vector<float> out(rows.count(n()), 0.f);
  for (std::size_t k = 0; k < out.size(); ++k)
    if (const std::size_t i = rows[k]; tot[i])
      out[k] = static_cast<float>(brk[i]) / static_cast<float>(tot[i]);
  return out;
}

template <int D>
std::size_t Model<D>::memory_bytes() const {
  std::size_t b = 0;
  for (int a = 0; a < D; ++a) b += (x[a].capacity() + v[a].capacity() + x0[a].capacity()) * sizeof(double);
  b += im.bytes() + rad.bytes();
  b += (id.capacity() + grp.capacity()) * 4 + mat.capacity() + flags.capacity();
  b += bonds.bytes() + contacts.bytes() + bond_us.bytes();
  b += bcp.capacity() * sizeof(BcParticle) + acc.capacity() * sizeof(BlockAcc);
  b += (cross_b.capacity() + cross_c.capacity()) * sizeof(double);
  b += bond_owner.capacity() + pend_slot.capacity() * 4;
  for (const PendingPool& P : pend)
    b += (P.ring.capacity() + P.buf.capacity()) * sizeof(double) + P.spare.capacity() * 4;
  b += events.capacity() * sizeof(BreakEvent);
  b += slots.mask.capacity() * sizeof(slots.mask[0]) + slots.run.capacity() * 4 + slots.st.capacity() +
       slots.uq.capacity() * 4 + (slots.f.capacity() + slots.en.capacity()) * sizeof(double);
  return b;
}

template <int D>
std::size_t Model<D>::streamed_bytes_per_step() const {
  // The bytes a step reads and writes in memory, as the model last stepped.
  if (slots.held) {
    // stepping in lattice slots: per particle its positions and velocities, flags, first
    // bond's index (the shear history's rounding) and mask of directions (a byte in 2D, two
    // in 3D); per column of slots a state byte and shear history read and written, whether
    // or not the particle has that bond
    const std::size_t column = 2 + (bond_us.empty() ? 0 : 2 * kNs * 4);
    return n() * (2 * D * 2 * sizeof(double) + 1 + 4 + sizeof(slots.mask[0]) +
                  static_cast<std::size_t>(slots.cols) * column);
  }
  // Per particle: positions and
  // velocities read and written; inverse mass and radius read where they differ between particles; the flags
  // byte and both pair lists' offsets read (the pending forces stay in cache: a ring of a few blocks and the
  // front's slots)
  const std::size_t particle = 2 * D * 2 * sizeof(double) + (im.uniform() ? 0 : sizeof(double)) +
                               (rad.uniform() ? 0 : sizeof(double)) + 1 + 2 * 4;
  // per pair: partner index read, state byte and shear history read and written (a bond's
  // in 32 bits, a contact's in 64)
  const std::size_t pair = 4 + 2;
  std::size_t b = n() * particle + contacts.size() * (pair + (contacts.us.empty() ? 0 : 2 * kNs * 8));
  b += bonds.size() * (pair + (bond_us.empty() ? 0 : 2 * kNs * 4) + 1);  // and the bond pass's owner byte,
                                                                         // written and read in cache
  if (!bonds.r0.empty()) b += bonds.size() * 3 * sizeof(double);         // rest length, factors
  return b;
}

std::uint32_t ModelBase::set_with(std::uint32_t set, std::uint32_t group) {
  std::vector<std::uint32_t> want = group_sets[set];
  const auto at = std::lower_bound(want.begin(), want.end(), group);
  if (at != want.end() && *at == group) return set;
  want.insert(at, group);
  const auto found = std::find(group_sets.begin(), group_sets.end(), want);
  if (found != group_sets.end()) return static_cast<std::uint32_t>(found - group_sets.begin());
  STRATA_CHECK(group_sets.size() < 0xffffffffu, Input, "group: too many combinations of groups");
  group_sets.push_back(std::move(want));
  return static_cast<std::uint32_t>(group_sets.size() - 1);
}

std::vector<std::uint8_t> ModelBase::sets_holding(const std::vector<std::uint32_t>& groups) const {
  std::vector<std::uint8_t> out(group_sets.size(), 0);
  for (std::size_t s = 0; s < group_sets.size(); ++s)
    for (const std::uint32_t g : groups)
      if (std::binary_search(group_sets[s].begin(), group_sets[s].end(), g)) out[s] = 1;
  return out;
}

template <int D>
std::unique_ptr<ModelBase> make_model(const Settings& s) {
  return std::make_unique<Model<D>>(s);
}
template std::unique_ptr<ModelBase> make_model<2>(const Settings&);
template std::unique_ptr<ModelBase> make_model<3>(const Settings&);

#define STRATA_DEM_INSTANTIATE(D)                                                                          \
  template void Model<D>::reserve(std::size_t);                                                            \
  template std::size_t Model<D>::add_particle(std::array<double, 3>, double, int, double);                 \
  template std::size_t Model<D>::add_particles(const std::vector<std::array<double, 3>>&, double, int,     \
                                               double);                                                    \
  template double Model<D>::checked_mass(double, int, double) const;                                       \
  template std::vector<std::uint32_t> Model<D>::index_of_id() const;                                       \
  template std::size_t Model<D>::index_of(std::size_t, const char*) const;                                 \
  template void Model<D>::set_velocity(std::size_t, std::array<double, 3>);                                \
  template void Model<D>::add_to_group(const std::vector<std::uint32_t>&, std::uint32_t);                  \
  template std::vector<std::uint32_t> Model<D>::members(std::uint32_t) const;                              \
  template void Model<D>::sort_particles(bool);                                                            \
  template void Model<D>::keep_rows_if_lattice();                                                          \
  template bool Model<D>::added_in_rows() const;                                                           \
  template void Model<D>::reorder(const std::vector<std::uint32_t>&);                                      \
  template std::vector<std::array<double, 3>> Model<D>::pack(const std::array<aligned_vector<double>, D>&, \
                                                             Rows) const;                                  \
  template std::vector<std::array<double, 3>> Model<D>::displacements(Rows) const;                         \
  template std::vector<double> Model<D>::radii(Rows) const;                                                \
  template std::vector<std::uint32_t> Model<D>::ids(Rows) const;                                           \
  template std::vector<std::uint8_t> Model<D>::bond_counts() const;                                        \
  template std::vector<float> Model<D>::damage(Rows) const;                                                \
  template std::size_t Model<D>::memory_bytes() const;                                                     \
  template std::size_t Model<D>::streamed_bytes_per_step() const;
STRATA_DEM_INSTANTIATE(2)
STRATA_DEM_INSTANTIATE(3)
#undef STRATA_DEM_INSTANTIATE

}  // namespace strata::dem::detail
