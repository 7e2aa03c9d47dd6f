// Probes of the DEM: kinetic and stored energy, external work, damping losses, forces on
// groups, break and contact counts, touching pairs and the pair views of writers. Pair
// forces are evaluated by the law's engine ("dry": on copies of the pair state, with the
// pending shear increment v·dt the next step would add).
#include "model.hpp"

#include <algorithm>
#include <cmath>

namespace strata::dem::detail {

template <int D>
double Model<D>::dry_bond_energy() const {
  bonds_current();
  if (!engine) return 0.0;  // no particle yet
  return engine->stored_energy(*this, walls.data(), walls.size(), settings.dt);
}

template <int D>
double Model<D>::dry_kinetic() const {
  return par::parallel_sum<double>(static_cast<std::ptrdiff_t>(n()), [&](std::ptrdiff_t p) {
    double s = 0;
    for (int a = 0; a < D; ++a) s += v[a][p] * v[a][p];
    return 0.5 * s / im[p];
  });
}

template <int D>
std::array<double, 3> Model<D>::group_force(std::uint32_t group) const {
  bonds_current();
  if (!engine) return {0, 0, 0};
  const auto in = sets_holding({group});
  return engine->group_force(*this, walls.data(), walls.size(), settings.dt, in.data());
}

template <int D>
double Model<D>::kinetic_energy() const {
  if (!energy_valid) return dry_kinetic();
  double s = 0;
  for (const BlockAcc& A : acc) s += A.ke;
  return s;
}

template <int D>
double Model<D>::bond_energy() const {
  if (!energy_valid) return dry_bond_energy();
  double s = 0;
  for (const BlockAcc& A : acc) s += A.eb;
  return s;
}

template <int D>
double Model<D>::external_work() const {
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

template <int D>
double Model<D>::exchange_work() const {
  double s = 0;
  for (const BlockAcc& A : acc) s += A.work_ex;
  for (const BcParticle& b : bcp) s -= b.w_ahead_ex;
  return s;
}

template <int D>
double Model<D>::damping_dissipation() const {
  double s = 0;
  for (const BlockAcc& A : acc) s += A.dissipated;
  return s;
}

template <int D>
std::size_t Model<D>::broken_count(int mode) const {
  std::size_t c = 0;
  for (const auto& e : events)
    if (mode == 0 || static_cast<int>(e.mode) == mode) ++c;
  return c;
}

template <int D>
std::size_t Model<D>::contact_count() const {
  bonds_current();
  std::size_t c = 0;
  for (const auto* L : {&bonds, &contacts})
    for (std::size_t k = 0; k < L->size(); ++k)
      if ((L->st[k] & pair_state::kKindMask) != pair_state::kIntact && (L->st[k] & pair_state::kTouching))
        ++c;
  return c;
}

template <int D>
std::vector<std::array<std::uint32_t, 2>> Model<D>::touching_pairs() const {
  bonds_current();
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

template <int D>
std::vector<PairView> Model<D>::pairs(PairSet which) const {
  bonds_current();
  if (!engine) return {};
  return engine->pairs(*this, which);
}

#define STRATA_DEM_INSTANTIATE(D)                                                      \
  template double Model<D>::dry_bond_energy() const;                                   \
  template double Model<D>::dry_kinetic() const;                                       \
  template std::array<double, 3> Model<D>::group_force(std::uint32_t) const;           \
  template double Model<D>::kinetic_energy() const;                                    \
  template double Model<D>::bond_energy() const;                                       \
  template double Model<D>::external_work() const;                                     \
  template double Model<D>::exchange_work() const;                                     \
  template double Model<D>::damping_dissipation() const;                               \
  template std::size_t Model<D>::broken_count(int) const;                              \
  template std::size_t Model<D>::contact_count() const;                                \
  template std::vector<std::array<std::uint32_t, 2>> Model<D>::touching_pairs() const; \
  template std::vector<PairView> Model<D>::pairs(PairSet) const;
STRATA_DEM_INSTANTIATE(2)
STRATA_DEM_INSTANTIATE(3)
#undef STRATA_DEM_INSTANTIATE

}  // namespace strata::dem::detail
