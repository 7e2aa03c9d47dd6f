#pragma once
// Not API: the step kernel of the DEM, a template over the pair law: the scalar pair force,
// the bond pass (bond_pass.hpp), the two phases of a step, the damped leapfrog update, and
// the probes that evaluate pair forces. libdem compiles it for every built-in law
// (libdem/src/step.cpp); register_law() compiles it for a law added from outside.
//
// One step, per thread on a contiguous range [b, e) of whole blocks: phase A computes into
// slots the pairs whose partner lies in the range and whose owner lies in an earlier one;
// phase B gathers those slots, then block by block runs the bond pass and updates the
// particles, computing each contact on the way (a block owning pairs that a later thread
// computes waits until it has). Every particle's force is summed in the same order for any
// thread count (docs/dem.md, "Memory layout and the step loop"). A 2D lattice numbered row
// by row and without contacts takes the same steps with its bonds in lattice slots
// (bond_block_slots, then the pulled forces): the same sums in the same order (docs/dem.md,
// "Bonds in lattice slots").
#include <strata/core/parallel.hpp>
#include <strata/dem/detail/bond_pass.hpp>
#include <strata/dem/detail/law_engine.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>
#include <vector>

namespace strata::dem::detail {

/// Sum of three components (parallel_sum of forces).
struct V3 {
  double c[3]{};
  V3& operator+=(const V3& o) {
    for (int a = 0; a < 3; ++a) c[a] += o.c[a];
    return *this;
  }
};

template <int D, class Law>
class Engine final : public LawEngine<D> {
 public:
  static constexpr int kNs = kNsOf<D>;
  using Damping = Settings::Damping;
  /// The lattice-slot form is compiled for laws with a batch form (LatticeSlots).
  static constexpr bool kSlotsBuilt = HasLane<Law, kNs>;

  const char* name() const override { return Law::kName; }

  void set_materials(const std::vector<Material>& pair_materials, int nm) override {
    nmat = nm;
    laws.clear();
    for (const Material& pm : pair_materials) laws.push_back(Law::from_material(pm));
  }
  PairStiffness stiffness(int a, int b) const override {
    return laws[static_cast<std::size_t>(a) * nmat + b].stiffness();
  }

  void step(ModelData<D>& m, const StepCtx& c, bool energy) override {
    const bool in_slots = steps_in_slots(m, c.slots);
    if (in_slots) {
      if (!m.slots.held) m.slots_take_state();
      m.slots_let_go();
    } else if (m.slots.held) {
      m.slots_release();
    }
    if (energy)
      dispatch<true>(m, c, in_slots);
    else
      dispatch<false>(m, c, in_slots);
    if (!m.bond_us.empty()) m.bond_us.merge();  // bonds that became wide get their entries
    if (in_slots) ++m.slots_steps;
  }

  /// Whether a step runs in lattice slots: allowed by the settings, a law with a batch form,
  /// one material, the model held in slots (for the plan's threads) and no contacts now
  /// (their forces would come between the bonds' in each particle's sum).
  bool steps_in_slots(const ModelData<D>& m, bool allowed) const override {
    return kSlotsBuilt && allowed && m.slots.n > 0 && m.slots.threads == m.plan.nt &&
           m.contacts.size() == 0 && nmat == 1;
  }

  double shear_reach() const override {
    double r = 0;
    for (const Law& l : laws) r = std::max(r, shear_reach_of(l));
    return r;
  }

  /// One pair: geometry (normal, tangential increment, the stored shear displacement plus
  /// the increment turned into the current tangent plane), then the law's reference kernel. F
  /// receives the force on the owner p; returns the pair's energy when kEnergy.
  /// Out of line, as are the other rare paths of the step (law_for, record, bond_force,
  /// ModelData::pending_advance): GCC's inlining of them changes with their number of
  /// callers, and inlined into phase_b or bond_block they cost the step loop registers (6 %
  /// on one thread, 10^6 disks, when phase A's calls were rearranged).
  template <bool kEnergy>
  [[gnu::noinline]] static double pair_force(const double* const* X, const double* const* V, double rest,
                                             std::size_t p, std::uint32_t j, std::uint8_t& st, double* us,
                                             const Law& law, double dt, double* F, int& broke) {
    return pair_force_inline<kEnergy>(X, V, rest, p, j, st, us, law, dt, F, broke);
  }
  /// pair_force inlined, for the loops over every pair outside the step (dry_pairs: the
  /// stored energy at set-up and in probes, forces on groups, the writers' pair views),
  /// where a call per pair (and per pair's law) nearly doubles the time: the stored energy
  /// of 1.3e7 spheres and 7.8e7 bonds on two threads took 1.5 s through the calls, 0.8 s
  /// inlined. The same operations, so the same bits (libdem compiles without FMA
  /// contraction).
  template <bool kEnergy>
  [[gnu::always_inline]] static inline double pair_force_inline(const double* const* X,
                                                                const double* const* V, double rest,
                                                                std::size_t p, std::uint32_t j,
                                                                std::uint8_t& st, double* us, const Law& law,
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
    // us becomes the stored Us plus this step's increment, in the current tangent plane;
    // dus is the increment alone, for a law that asks for it
    double dus[kNs];
    if constexpr (D == 2) {
      // tangent t = (-n_y, n_x); the scalar Us turns with the normal
      dus[0] = ((V[1][j] - V[1][p]) * n[0] - (V[0][j] - V[0][p]) * n[1]) * dt;
      us[0] += dus[0];
    } else {
      double du[3], dun = 0, wn = 0;
      for (int a = 0; a < 3; ++a) {
        du[a] = (V[a][j] - V[a][p]) * dt;
        us[a] += du[a];
        dun += du[a] * n[a];
        wn += us[a] * n[a];
      }
      // keep Us in the current tangent plane: project out the normal part of the sum (one
      // projection, not one of the stored Us and one of the increment: the same value,
      // 11 operations fewer per bond). Its length shrinks by a factor cos(θ) for the
      // per-step rotation θ of the normal (θ ~ 1e-6 in a loaded lattice, a relative change
      // of 1e-12 per step), which is not restored.
      for (int a = 0; a < 3; ++a) us[a] -= wn * n[a];
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

  // ---- probes ---------------------------------------------------------------------------
  double stored_energy(const ModelData<D>& m, const Wall* walls, std::size_t nwalls,
                       double dt) const override {
    return par::parallel_sum<double>(static_cast<std::ptrdiff_t>(m.n()), [&](std::ptrdiff_t p) {
      double e = 0;
      dry_pairs(m, dt, static_cast<std::size_t>(p),
                [&](std::uint32_t, const double*, double en, std::uint8_t, const double*, bool) { e += en; });
      double F[D] = {};
      return e + m.wall_energy_and_force(walls, nwalls, static_cast<std::size_t>(p), F);
    });
  }

  std::array<double, 3> group_force(const ModelData<D>& m, const Wall* walls, std::size_t nwalls, double dt,
                                    const std::uint8_t* set_in_group) const override {
    const V3 r = par::parallel_sum<V3>(static_cast<std::ptrdiff_t>(m.n()), [&](std::ptrdiff_t pp) {
      const auto p = static_cast<std::size_t>(pp);
      V3 s;
      const bool gp = set_in_group[m.grp[p]];
      dry_pairs(m, dt, p, [&](std::uint32_t j, const double* F, double, std::uint8_t, const double*, bool) {
        const bool gj = set_in_group[m.grp[j]];
        for (int a = 0; a < D; ++a) s.c[a] += (gp ? F[a] : 0.0) - (gj ? F[a] : 0.0);
      });
      if (gp) {
        double F[D] = {};
        m.wall_energy_and_force(walls, nwalls, p, F);
        for (int a = 0; a < D; ++a) s.c[a] += F[a];
      }
      return s;
    });
    return {r.c[0], r.c[1], r.c[2]};
  }

  std::vector<PairView> pairs(const ModelData<D>& m, PairSet which) const override {
    std::vector<PairView> out;
    const PairList& L = which == PairSet::Contacts ? m.contacts : m.bonds;
    const bool broken_only = which == PairSet::BrokenBonds;
    const double* X[D];
    const double* V[D];
    for (int a = 0; a < D; ++a) {
      X[a] = m.x[a].data();
      V[a] = m.v[a].data();
    }
    if (!broken_only) out.reserve(L.size());
    for (std::size_t p = 0; p < m.n(); ++p)
      for (std::uint32_t k = L.off[p]; k < L.off[p + 1]; ++k) {
        if (broken_only && (L.st[k] & pair_state::kKindMask) == pair_state::kIntact) continue;
        const std::uint32_t j = L.j[k];
        std::uint8_t st = L.st[k];
        double us[kNs];
        m.load_us(L, k, us);
        double F[D];
        int broke = 0;
        // forces at the current state without the pending increment (dt = 0)
        pair_force<false>(X, V, m.rest_of(L, k, p, j), p, j, st, us, law_for(m, L, k, p, j), 0.0, F, broke);
        const std::uint8_t s0 = L.st[k];
        double fn = 0, fs2 = 0;
        double nv[D], l2 = 0;
        for (int a = 0; a < D; ++a) {
          nv[a] = m.x[a][j] - m.x[a][p];
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

 private:
  std::vector<Law> laws;  // nmat × nmat
  int nmat = 0;

  /// The law of the pair (p, q).
  const Law& law_of(const ModelData<D>& m, std::size_t p, std::size_t q) const {
    return laws[static_cast<std::size_t>(m.mat[p]) * nmat + m.mat[q]];
  }
  /// The law of pair k of L: the materials' law, for an intact bond given as data with its
  /// stiffness factor (eccentric lattices: k -> γ·k) and its strength factor.
  [[gnu::noinline]] Law law_for(const ModelData<D>& m, const PairList& L, std::uint32_t k, std::size_t p,
                                std::size_t j) const {
    return law_for_inline(m, L, k, p, j);
  }
  /// law_for inlined, for dry_pairs (as pair_force_inline).
  [[gnu::always_inline]] Law law_for_inline(const ModelData<D>& m, const PairList& L, std::uint32_t k,
                                            std::size_t p, std::size_t j) const {
    return m.scaled(L, k) ? bond_law(law_of(m, p, j), L.kf[k], L.sf[k]) : law_of(m, p, j);
  }

  /// Probes: fn(j, F, energy, state, us, is_contact) for every pair owned by p, evaluated
  /// on copies of the pair state with the pending shear increment (v·dt) the next step
  /// would add.
  /// Where a list keeps no shear history its pairs start from Us = 0 known at compile time
  /// (kHist false), as load_us would give them: the same bits, and the law's shear terms of
  /// a model of normal springs fold away (read through load_us for every pair, the stored
  /// energy of the block above took 1.35 s instead of 0.8 s).
  template <typename Fn>
  void dry_pairs(const ModelData<D>& m, double dt, std::size_t p, Fn&& fn) const {
    const double* X[D];
    const double* V[D];
    for (int a = 0; a < D; ++a) {
      X[a] = m.x[a].data();
      V[a] = m.v[a].data();
    }
    auto one = [&]<bool kHist>(const PairList& L, std::uint32_t k) {
      const std::uint32_t j = L.j[k];
      std::uint8_t st = L.st[k];
      double us[kNs] = {};
      if constexpr (kHist) m.load_us(L, k, us);
      double F[D];
      int broke = 0;
      const double e = pair_force_inline<true>(X, V, m.rest_of(L, k, p, j), p, j, st, us,
                                               law_for_inline(m, L, k, p, j), dt, F, broke);
      fn(j, F, e, st, us, &L == &m.contacts);
    };
    auto all = [&](const PairList& L, bool hist) {
      if (hist)
        for (std::uint32_t k = L.off[p]; k < L.off[p + 1]; ++k) one.template operator()<true>(L, k);
      else
        for (std::uint32_t k = L.off[p]; k < L.off[p + 1]; ++k) one.template operator()<false>(L, k);
    };
    all(m.bonds, !m.bond_us.empty());
    all(m.contacts, !m.contacts.us.empty());
  }

  [[gnu::noinline, gnu::cold]] static void record(ModelData<D>& m, int t, std::int64_t step, std::size_t p,
                                                  std::uint32_t j, int mode) {
    RawEvent ev{step, {0, 0, 0}, static_cast<std::uint8_t>(mode), static_cast<std::uint32_t>(p), j};
    for (int a = 0; a < D; ++a) ev.pos[a] = 0.5 * (m.x[a][p] + m.x[a][j]);
    m.evbuf[t].push_back(ev);
  }

  /// pair_force on bond k of thread t's step, with its shear history taken from the bonds'
  /// store and put back.
  template <bool kEnergy>
  double bond_force(ModelData<D>& m, int t, const StepCtx& c, const double* const* X, const double* const* V,
                    std::size_t p, std::uint32_t k, double* F, int& broke) const {
    return bond_force_at<kEnergy>(m, t, c, X, V, p, k, m.bonds.j[k], m.bonds.st[k],
                                  m.bond_us.empty() ? nullptr : m.bond_us.q.data() + std::size_t{k} * kNs, F,
                                  broke);
  }
  /// The same for bond k to partner j whose state st and shear history h (nullptr: none kept)
  /// are held where the caller says (in the bonds' arrays, or in lattice slots); code_at as
  /// BondShear::store_at.
  template <bool kEnergy>
  [[gnu::noinline]] double bond_force_at(ModelData<D>& m, int t, const StepCtx& c, const double* const* X,
                                         const double* const* V, std::size_t p, std::uint32_t k,
                                         std::uint32_t j, std::uint8_t& st, std::int32_t* h, double* F,
                                         int& broke, std::int32_t* code_at = nullptr) const {
    double us[kNs] = {};
    if (h) m.bond_us.load_at(h, us);
    const double e = pair_force<kEnergy>(X, V, m.rest_of(m.bonds, k, p, j), p, j, st, us,
                                         law_for(m, m.bonds, k, p, j), c.dt, F, broke);
    if (h)
      m.bond_us.store_at(t, k, h, c.salt, (st & pair_state::kKindMask) == pair_state::kIntact, us, code_at);
    return e;
  }

  // Phase A: the cross pairs whose partner lies in this thread's range (their owners lie in
  // earlier threads' ranges, which do not move them before this thread's count says so).
  // With kSlots (the model in lattice slots, no contacts) they are bonds whose state the
  // slots hold: phase_a_slots takes them through the bond pass where the ranges allow it
  // (slots_cross_in_batch); else the reference kernel takes each here, and its force and
  // energy also go to this thread's ring, where its partner pulls them.
  template <bool kEnergy, bool kSlots = false>
  void phase_a(ModelData<D>& m, int t, const StepCtx& c) const {
    if constexpr (kSlots) {
      if (slots_cross_in_batch(m, t)) {
        phase_a_slots<kEnergy>(m, t, c);
        return;
      }
    }
    const double* X[D];
    const double* V[D];
    for (int a = 0; a < D; ++a) {
      X[a] = m.x[a].data();
      V[a] = m.v[a].data();
    }
    const std::vector<CrossPair>& calc = m.plan.calc[t];
    std::atomic_ref<std::int64_t> count = m.plan.counter(t);
    std::int64_t n = m.plan.counted_before_step(t);
    for (const CrossPair& x : calc) {
      const std::uint32_t p = x.owner, k = x.pair;
      double F[D], none[kNs];
      int broke = 0;
      double e;
      if constexpr (kSlots) {
        LatticeSlots<D>& L = m.slots;  // the bonds' partners are let go: the slots say them
        const int d = L.direction(m.bonds.off[p], L.mask[p], k);
        const std::uint32_t j = p + L.off[d];
        e = slot_bond_force<kEnergy>(m, t, c, X, V, p, k, j, d, F, broke);
        if (broke) [[unlikely]]
          record(m, t, c.step, p, j, broke);
        const std::size_t r = L.slot(d, p);
        for (int a = 0; a < D; ++a) L.force(t, d, a)[r] = F[a];
        L.energy(t, d)[r] = e;
      } else if (!x.contact) {
        e = bond_force<kEnergy>(m, t, c, X, V, p, k, F, broke);
      } else {
        PairList& L = m.contacts;
        const std::uint32_t j = L.j[k];
        e = pair_force<kEnergy>(X, V, m.rest_of(L, k, p, j), p, j, L.st[k], ModelData<D>::us_of(L, k, none),
                                law_for(m, L, k, p, j), c.dt, F, broke);
      }
      if (!kSlots && broke) [[unlikely]]
        record(m, t, c.step, p, x.contact ? m.contacts.j[k] : m.bonds.j[k], broke);
      double* out = &(x.contact ? m.cross_c : m.cross_b)[std::size_t{x.slot} * (D + 1)];
      for (int a = 0; a < D; ++a) out[a] = F[a];
      out[D] = e;
      count.store(++n, std::memory_order_release);
    }
  }

  /// Whether thread t's cross bonds in lattice slots may go through the bond pass
  /// (phase_a_slots): its range and the one before are each longer than the longest partner
  /// offset and a block. Their owners then lie in the range before, whose thread waits for
  /// this one at their blocks, and none of them bonds into a later range, so no other
  /// thread's phase A reads or writes their state. Otherwise (short ranges: a small model on
  /// many threads) the reference kernel takes them one by one, as the plan lists them.
  static bool slots_cross_in_batch(const ModelData<D>& m, int t) {
    const std::vector<std::ptrdiff_t>& b = m.plan.begin;
    const std::ptrdiff_t need = std::ptrdiff_t{m.slots.off[m.slots.n - 1]} + kBlock;
    return t > 0 && b[t] - b[t - 1] >= need && b[t + 1] - b[t] >= need;
  }

  // Phase A in lattice slots: the cross bonds into this thread's range [lo, e) go through
  // the bond pass of the blocks that own them (bond_block_slots from lo), into this
  // thread's ring, where their partners pull them; then into their slots of cross_b, where
  // the owners' thread takes them (slots_cross_in). The count says all of them at once.
  template <bool kEnergy>
  void phase_a_slots(ModelData<D>& m, int t, const StepCtx& c) const {
    const std::vector<CrossPair>& calc = m.plan.calc[t];
    if (calc.empty()) return;
    LatticeSlots<D>& L = m.slots;
    const std::ptrdiff_t lo = m.plan.begin[t], e = m.plan.begin[t + 1];
    const std::ptrdiff_t from = std::max<std::ptrdiff_t>(0, lo - L.off[L.n - 1]);
    for (std::ptrdiff_t blk = from / kBlock; blk * kBlock < lo; ++blk) {
      const std::ptrdiff_t p0 = blk * kBlock, pe = std::min(lo, p0 + kBlock);
      if (m.uniform_diameter > 0)
        bond_block_slots<kEnergy, kUniform>(m, t, c, p0, pe, e, lo);
      else
        bond_block_slots<kEnergy, kRadiusSum>(m, t, c, p0, pe, e, lo);
    }
    for (const CrossPair& x : calc) {
      const int d = L.direction(m.bonds.off[x.owner], L.mask[x.owner], x.pair);
      const std::size_t r = L.slot(d, x.owner);
      double* out = &m.cross_b[std::size_t{x.slot} * (D + 1)];
      for (int a = 0; a < D; ++a) out[a] = L.force(t, d, a)[r];
      out[D] = L.energy(t, d)[r];
    }
    m.plan.counter(t).store(m.plan.counted_before_step(t) + static_cast<std::int64_t>(calc.size()),
                            std::memory_order_release);
  }

  /// Waits until the threads that compute the cross pairs owned in block blk of thread t's
  /// range have done so in this step, from t's wait w on; returns the next wait. Out of line:
  /// a few blocks of a range have any, and the step loop keeps its registers.
  [[gnu::noinline]] static std::size_t wait_for_cross_pairs(ModelData<D>& m, int t, std::ptrdiff_t blk,
                                                            std::size_t w) {
    const std::vector<CrossWait>& waits = m.plan.waits[t];
    for (; w < waits.size() && waits[w].blk == blk; ++w) {
      const CrossWait& cw = waits[w];
      const std::int64_t goal = m.plan.counted_before_step(cw.by) + static_cast<std::int64_t>(cw.count);
      std::atomic_ref<std::int64_t> count = m.plan.counter(cw.by);
      for (int spins = 0; count.load(std::memory_order_acquire) < goal; ++spins)
        if (spins >= 256) std::this_thread::yield();  // the other thread is not running now
    }
    return w;
  }

  /// One velocity component through the damped leapfrog update; returns v(n+½).
  template <Damping DK>
  static inline double integrate(double vo, double F, double imass, double g, double dt, double c_visc,
                                 double alpha, double& diss) {
    if constexpr (DK == Damping::None) {
      return vo + dt * (F * imass + g);
    } else if constexpr (DK == Damping::Viscous) {
      // F - c·v(n), v(n) = ½(v(n-½) + v(n+½)): solved for v(n+½) (artificial viscosity)
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
  // partner lies in this thread's range (j < e), before any of them moves. Bonds of a model
  // with one material go through the law's batch form in a branch-free loop the compiler
  // vectorises (bond_span: gathers of the endpoints' positions and velocities); the others
  // (bonds breaking now, pairs of two materials, every bond of a law without a batch form)
  // are redone by the reference kernel. Both evaluate the same expressions in the same
  // order, so the results do not depend on which path a bond takes.
  template <bool kEnergy, Rest kRest>
  void bond_block(ModelData<D>& m, int t, const StepCtx& c, std::ptrdiff_t p0, std::ptrdiff_t pe,
                  std::ptrdiff_t e) const {
    const std::uint32_t k0 = m.bonds.off[p0], k1 = m.bonds.off[pe];
    const std::size_t mq = k1 - k0;
    Scratch<D>& S = m.scratch[t];
    S.fit(mq);
    // owner - p0: kept per bond, or expanded from the offsets here (BondShear models)
    const std::uint8_t* own = m.bond_owner.empty() ? S.own.data() : m.bond_owner.data() + k0;
    if (m.bond_owner.empty()) {
      std::uint8_t* ex = S.own.data();
      const std::uint32_t* off = m.bonds.off.data();
      // eight bytes per owner at once, each owner overwriting what the one before wrote past
      // its own bonds (a loop per owner becomes a call to memset per owner); an owner of
      // more than eight bonds (rare: a lattice has at most six per owner) fills the rest
      for (std::ptrdiff_t p = p0; p < pe; ++p) {
        const std::uint32_t a = off[p] - k0, b = off[p + 1] - k0;
        const std::uint64_t v = 0x0101010101010101ull * static_cast<std::uint64_t>(p - p0);
        std::memcpy(ex + a, &v, 8);
        for (std::uint32_t k = a + 8; k < b; ++k) ex[k] = static_cast<std::uint8_t>(p - p0);
      }
    }
    const std::uint32_t up0 = static_cast<std::uint32_t>(p0);
    const double* X[D];
    const double* V[D];
    double* FB[D];
    for (int a = 0; a < D; ++a) {
      X[a] = m.x[a].data();
      V[a] = m.v[a].data();
      FB[a] = S.fb[a].data();
    }
    const std::uint32_t* bj = m.bonds.j.data() + k0;
    double* EN = S.en.data();
    std::uint8_t* slow = S.slow.data();
    const double dt = c.dt;
    const std::uint32_t ee = static_cast<std::uint32_t>(e);
    const bool keep_us = !m.bond_us.empty();
    if (!keep_us && S.no_us.size() < mq * kNs) S.no_us.assign(mq * kNs, 0);
    static double no_wide[kNs] = {};  // read (and discarded) where no bond is wide
    if constexpr (HasLane<Law, kNs>) {
      if (nmat == 1) {
        // one pointer per axis (arrays of pointers keep GCC from vectorising the 3D loop)
        const BondSpan sp{X[0],
                          X[1],
                          X[D - 1],
                          V[0],
                          V[1],
                          V[D - 1],
                          m.rad.per_particle(),  // read only for kRadiusSum: sizes differ
                          kRest == kPerBond ? m.bonds.r0.data() + k0 : nullptr,
                          kRest == kPerBond ? m.bonds.kf.data() + k0 : nullptr,
                          kRest == kPerBond ? m.bonds.sf.data() + k0 : nullptr,
                          FB[0],
                          FB[1],
                          FB[D - 1],
                          EN,
                          keep_us ? m.bond_us.q.data() + std::size_t{k0} * kNs : S.no_us.data(),
                          m.bond_us.wide.empty() ? no_wide : m.bond_us.wide.data(),
                          keep_us ? m.bond_us.unit : 0.0,
                          keep_us ? m.bond_us.inv : 0.0,
                          keep_us,
                          m.bond_us.intact_wide,
                          k0,
                          c.salt,
                          own,
                          bj,
                          m.bonds.st.data() + k0,
                          slow,
                          up0,
                          ee};
        bond_chunks<D, Law, kEnergy, kRest>(sp, laws[0], dt, m.uniform_diameter, mq);
      } else {
        std::fill(slow, slow + mq, std::uint8_t{1});
      }
    } else {
      std::fill(slow, slow + mq, std::uint8_t{1});
    }
    // the reference kernel for the rest (cross bonds, j >= e, are phase A's)
    for (std::size_t q = 0; q < mq; ++q) {
      if (q % 8 == 0 && q + 8 <= mq) {  // skip 8 fast bonds at a time
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
      EN[q] = bond_force<kEnergy>(m, t, c, X, V, p, k, F, broke);
      for (int a = 0; a < D; ++a) FB[a][q] = F[a];
      if (broke) [[unlikely]]
        record(m, t, c.step, p, j, broke);
    }
  }

  /// The bond pass's lanes in a vector at most (16 bonds in 512 bits: its shear steps are
  /// 32-bit), and the gap between two runs is at least as wide (LatticeSlots::kGap).
  static constexpr std::uint32_t kRunLanes = 16;
  static_assert(LatticeSlots<D>::kGap >= kRunLanes, "a run's early start stays in the gap before it");

  // The bond pass of one block in lattice slots (LatticeSlots): direction by direction, the
  // entries of the block's owners whose partner lies in [lo, e) go through bond_chunks with
  // kInSlots; forces and energies land in the thread's ring. In phase B the partners are
  // those of this thread's range before e (lo = 0: the others are phase A's of a later
  // thread); in phase A, with lo its range's start, the cross bonds into it. The bonds the
  // batch form leaves are then redone by the reference kernel in bond order, as bond_block
  // does, on their state in the slots.
  template <bool kEnergy, Rest kRest>
  void bond_block_slots(ModelData<D>& m, int t, const StepCtx& c, std::ptrdiff_t p0, std::ptrdiff_t pe,
                        std::ptrdiff_t e, std::ptrdiff_t lo = 0) const {
    LatticeSlots<D>& L = m.slots;
    Scratch<D>& S = m.scratch[t];
    const std::size_t nb = static_cast<std::size_t>(pe - p0);
    if (S.slow.size() < nb) S.slow.resize(nb);
    if (S.no_us.size() < nb * kNs) S.no_us.assign(nb * kNs, 0);
    S.sref.clear();
    const bool keep_us = !m.bond_us.empty();
    std::uint8_t* __restrict sslow = S.slow.data();  // one direction's verdicts at a time
    static double no_wide[kNs] = {};
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(m.n());
    for (int d = 0; d < L.n; ++d) {
      // owners from pl to pb have their partner in range
      const std::ptrdiff_t pb = std::min<std::ptrdiff_t>(pe, e - L.off[d]);
      const std::ptrdiff_t pl = std::max<std::ptrdiff_t>(p0, lo - L.off[d]);
      if (pb <= pl) continue;
      const std::size_t r0 = L.slot(d, static_cast<std::size_t>(p0));
      const std::size_t len = static_cast<std::size_t>(pb - p0);
      const std::size_t s0 = L.entry(d, static_cast<std::size_t>(p0), m.n());
      BondSpan sp{m.x[0].data(),
                  m.x[1].data(),
                  m.x[D - 1].data(),
                  m.v[0].data(),
                  m.v[1].data(),
                  m.v[D - 1].data(),
                  m.rad.per_particle(),
                  nullptr,
                  nullptr,
                  nullptr,
                  L.force(t, d, 0) + r0,
                  L.force(t, d, 1) + r0,
                  L.force(t, d, D - 1) + r0,
                  L.energy(t, d) + r0,
                  keep_us ? L.uq.data() + L.us_at(d, 0, static_cast<std::size_t>(p0), m.n()) : S.no_us.data(),
                  m.bond_us.wide.empty() ? no_wide : m.bond_us.wide.data(),
                  keep_us ? m.bond_us.unit : 0.0,
                  keep_us ? m.bond_us.inv : 0.0,
                  keep_us,
                  m.bond_us.intact_wide,
                  0,
                  c.salt,
                  nullptr,
                  nullptr,
                  L.st.data() + s0,
                  sslow,
                  static_cast<std::uint32_t>(p0),
                  static_cast<std::uint32_t>(n)};
      sp.us_n = keep_us ? m.n() : nb;
      sp.pa = static_cast<std::uint32_t>(p0);
      sp.so = L.off[d];
      sp.dir = d;
      sp.soff = m.bonds.off.data() + p0;
      if constexpr (D == 2)
        sp.smask = L.mask.data() + p0;
      else
        sp.smask3 = L.mask.data() + p0;
      bool any_slow = false;
      sp.slow_seen = &any_slow;
      // the runs of owners with a bond in this direction (LatticeSlots::run); the entries
      // between them are not computed, as a stand-in's would be dropped
      const auto ua = static_cast<std::uint32_t>(p0), ul = static_cast<std::uint32_t>(pl),
                 ub = static_cast<std::uint32_t>(pb);
      const auto [rf, rend] = L.runs_from(d, ul);  // from the first run that ends past pl
      std::uint32_t done = ul - ua;                // the entries up to the end of the last run
      const bool cross = lo > 0;
      if (cross) std::fill_n(sslow, len, std::uint8_t{0});  // verdicts of the entries left out
      for (const std::uint32_t* rr = rf; rr < rend && rr[0] < ub; rr += 2) {
        std::uint32_t qa = std::max(rr[0], ul) - ua;
        std::uint32_t qb = std::min(rr[1], ub) - ua;
        if (cross) {
          // phase A: from the first owner with the bond to the last, so that every entry lies
          // in a block whose thread waits for this one (phase_a_slots); no early start
          while (qa < qb && !(L.mask[p0 + qa] >> d & 1u)) ++qa;
          while (qb > qa && !(L.mask[p0 + qb - 1] >> d & 1u)) --qb;
          if (qa == qb) continue;
        } else {
          // a whole number of vectors: the run starts up to kRunLanes - 1 entries early, in
          // the gap before it (owners without the bond: stand-ins, dropped), where it has
          // one; the compiler's shorter loops for the last few entries run at a fraction of
          // the rate
          const std::uint32_t pad = (kRunLanes - (qb - qa) % kRunLanes) % kRunLanes;
          qa = std::max(done, qa >= pad ? qa - pad : 0u);
          if (rr == rf && (qa > 0 || qb < len))
            std::fill_n(sslow, len, std::uint8_t{0});  // verdicts of the entries left out
        }
        done = qb;
        bond_chunks<D, Law, kEnergy, kRest, true>(sp, laws[0], c.dt, m.uniform_diameter, qb, qa);
      }
      if (any_slow) [[unlikely]]
        for (std::size_t q = 0; q < len; ++q)
          if (sslow[q]) {
            const auto p = static_cast<std::size_t>(p0) + q;
            S.sref.push_back({L.bond(m.bonds.off[p], L.mask[p], d), static_cast<std::uint32_t>(p),
                              static_cast<std::uint32_t>(d)});
          }
    }
    if (S.sref.empty()) [[likely]]
      return;
    std::sort(S.sref.begin(), S.sref.end());  // bond order
    const double* X[D];
    const double* V[D];
    for (int a = 0; a < D; ++a) {
      X[a] = m.x[a].data();
      V[a] = m.v[a].data();
    }
    for (const auto& [k, p, d] : S.sref) {
      double F[D];
      int broke = 0;
      const std::uint32_t j = p + L.off[d];
      const double e = slot_bond_force<kEnergy>(m, t, c, X, V, p, k, j, static_cast<int>(d), F, broke);
      const std::size_t r = L.slot(static_cast<int>(d), p);
      for (int a = 0; a < D; ++a) L.force(t, static_cast<int>(d), a)[r] = F[a];
      L.energy(t, static_cast<int>(d))[r] = e;
      if (broke) [[unlikely]]
        record(m, t, c.step, p, j, broke);
    }
  }

  /// bond_force_at on bond k (owner p, partner j, direction d) held in lattice slots.
  template <bool kEnergy>
  double slot_bond_force(ModelData<D>& m, int t, const StepCtx& c, const double* const* X,
                         const double* const* V, std::size_t p, std::uint32_t k, std::uint32_t j, int d,
                         double* F, int& broke) const {
    LatticeSlots<D>& L = m.slots;
    const std::size_t s = L.entry(d, p, m.n());
    if (m.bond_us.empty()) return bond_force_at<kEnergy>(m, t, c, X, V, p, k, j, L.st[s], nullptr, F, broke);
    // the history's components, together for the reference kernel; a bond that becomes wide
    // gets its entry's code in its slot
    std::int32_t h[kNs];
    for (int a = 0; a < kNs; ++a) h[a] = L.uq[L.us_at(d, a, p, m.n())];
    const double e =
        bond_force_at<kEnergy>(m, t, c, X, V, p, k, j, L.st[s], h, F, broke, &L.uq[L.us_at(d, 0, p, m.n())]);
    for (int a = 0; a < kNs; ++a) L.uq[L.us_at(d, a, p, m.n())] = h[a];
    return e;
  }

  /// One particle with a boundary condition through the update: its free axes by the damped
  /// leapfrog, its driven ones by their mode, with the work of the applied load and of the
  /// reactions booked; v2 and vv gain its new speed squared and vo·vn.
  template <Damping DK>
  [[gnu::always_inline]] static inline void bc_update(BcParticle& bc, const StepCtx& c, const double* F,
                                                      double imass, std::ptrdiff_t p,
                                                      double* __restrict const* X,
                                                      double* __restrict const* V, double& work,
                                                      double& work_ex, double& diss, double& vfree2,
                                                      double& v2, double& vv) {
    const double dt = c.dt, cv = c.viscous_c, alpha = c.local_alpha;
    double fapp[3] = {0, 0, 0};
    if (bc.history >= 0)  // load_dir: 1 for a force vector, the unit direction of a radial load
      for (int a = 0; a < D; ++a) fapp[a] = c.hist[bc.history][a] * bc.load_dir[a];
    bc.w_ahead = 0;
    bc.w_ahead_ex = 0;
    double v2f = 0;  // over the free axes
    double vv_driven = 0;
    for (int a = 0; a < D; ++a) {
      bc.f_int[a] = F[a];
      const double vo = V[a][p];
      double vn;
      if (bc.mode[a] == 0) {
        vn = integrate<DK>(vo, F[a] + fapp[a], imass, c.g[a], dt, cv, alpha, diss);
        work += fapp[a] * vn * dt;
        v2f += vn * vn;
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
        if (bc.exchange >> a & 1u) {  // booked apart: energy passed between partitions
          work_ex -= 0.5 * fr * (bc.dx_prev[a] + dx);
          bc.w_ahead_ex -= 0.5 * fr * dx;
        }
        bc.dx_prev[a] = dx;
        vv_driven += vo * vn;
      }
      V[a][p] = vn;
      X[a][p] += vn * dt;
      v2 += vn * vn;
      vv += vo * vn;
    }
    vfree2 = std::max(vfree2, v2f);
    bc.ke_driven = 0.5 * vv_driven / imass;
  }

  /// Into thread t's ring: the forces and energies of the bonds owned by particles p0..pe-1
  /// whose partner lies in a later thread's range (at or beyond e), from the slots phase A
  /// of that thread computed them into (cross_b from `cur` on, in ascending owner and
  /// direction, as the plan numbers them). Out of line: a few blocks of a range have any.
  [[gnu::noinline]] static void slots_cross_in(ModelData<D>& m, int t, std::ptrdiff_t p0, std::ptrdiff_t pe,
                                               std::ptrdiff_t e, std::size_t& cur) {
    LatticeSlots<D>& L = m.slots;
    for (std::ptrdiff_t p = std::max<std::ptrdiff_t>(p0, e - L.off[L.n - 1]); p < pe; ++p)
      for (int d = 0; d < L.n; ++d)
        if ((L.mask[p] >> d & 1u) && p + static_cast<std::ptrdiff_t>(L.off[d]) >= e) {
          const double* s = &m.cross_b[cur++ * (D + 1)];
          const std::size_t r = L.slot(d, static_cast<std::size_t>(p));
          for (int a = 0; a < D; ++a) L.force(t, d, a)[r] = s[a];
          L.energy(t, d)[r] = s[D];
        }
  }

  /// The bond forces of particles p0..pe-1 from thread t's ring into F[a][p - p0], in vector
  /// lanes: direction by direction, minus the bonds they are the partner of (descending
  /// direction: ascending owner), then plus their own (ascending partner), each where the
  /// bond exists. Every particle's sum takes the terms in pull_slots' order.
  static void pull_block(LatticeSlots<D>& L, int t, std::ptrdiff_t p0, std::ptrdiff_t pe,
                         double (*F)[kBlock]) {
    const std::size_t nb = static_cast<std::size_t>(pe - p0);
    const auto* __restrict mk = L.mask.data();
    for (int a = 0; a < D; ++a) std::fill_n(F[a], nb, 0.0);
    // entries q in [qa, qb) whose ring entries are R + q (no wrap), mask bytes M + q
    auto apply = [&](int d, std::size_t qa, std::size_t qb, std::ptrdiff_t shift, bool own) {
      const auto* __restrict M = mk + p0 - shift;
      const std::size_t r = L.slot(d, static_cast<std::size_t>(p0 - shift + static_cast<std::ptrdiff_t>(qa)));
      const double* __restrict R0 = L.force(t, d, 0) + r - qa;
      const double* __restrict R1 = L.force(t, d, 1) + r - qa;
      const double* __restrict R2 = L.force(t, d, D - 1) + r - qa;
      double* __restrict F0 = F[0];
      double* __restrict F1 = F[1];
      double* __restrict F2 = F[D - 1];
      const unsigned sh = static_cast<unsigned>(d);
      const double sign = own ? 1.0 : -1.0;  // exact: R or -R
      // R[q] where the bond exists, else +0 (F is never -0: F + 0 is F)
#pragma omp simd
      for (std::size_t q = qa; q < qb; ++q) {
        const std::int64_t on = -static_cast<std::int64_t>(M[q] >> sh & 1u);
        F0[q] += masked(sign * R0[q], on);
        F1[q] += masked(sign * R1[q], on);
        if constexpr (D == 3) F2[q] += masked(sign * R2[q], on);
      }
    };
    // entries q in [qa, qe), split where their owners' ring entries wrap (at most once over
    // a block)
    auto span = [&](int d, std::size_t qa, std::size_t qe, std::ptrdiff_t shift, bool own) {
      while (qa < qe) {
        const std::size_t r =
            L.slot(d, static_cast<std::size_t>(p0 - shift + static_cast<std::ptrdiff_t>(qa)));
        const std::size_t qb = std::min(qe, qa + (L.ring[d] - r));
        apply(d, qa, qb, shift, own);
        qa = qb;
      }
    };
    // the owners p - shift (>= 0); in 3D only those within direction d's runs
    // (LatticeSlots::run): an owner outside them has no bond in d, whose term would be +0. A
    // block lies in one layer, so about half the directions into the next layer (the other
    // kind of layer's) have no run in it. In 2D, where every direction has runs in nearly
    // every block, finding them cost more than the entries it skipped.
    auto pass = [&](int d, std::ptrdiff_t shift, bool own) {
      const std::ptrdiff_t olo = std::max<std::ptrdiff_t>(0, p0 - shift), ohi = pe - shift;
      if (ohi <= olo) return;
      if constexpr (D == 2) {
        span(d, static_cast<std::size_t>(olo + shift - p0), nb, shift, own);
      } else {
        const auto [rf, rend] = L.runs_from(d, static_cast<std::uint32_t>(olo));
        for (const std::uint32_t* rr = rf; rr < rend && std::ptrdiff_t{rr[0]} < ohi; rr += 2) {
          const std::ptrdiff_t a = std::max<std::ptrdiff_t>(rr[0], olo),
                               b = std::min<std::ptrdiff_t>(rr[1], ohi);
          span(d, static_cast<std::size_t>(a + shift - p0), static_cast<std::size_t>(b + shift - p0), shift,
               own);
        }
      }
    };
    for (int d = L.n - 1; d >= 0; --d) pass(d, static_cast<std::ptrdiff_t>(L.off[d]), false);
    for (int d = 0; d < L.n; ++d) pass(d, 0, true);
  }

  /// The damped update of particles p0..pe-1 without a boundary condition (flags 0), in
  /// vector lanes, from forces F[a][p - p0]; V2 and DP receive each one's new speed squared
  /// and damping loss (for the block's sums, which take them in particle order). Particles
  /// with a boundary condition are left as they are.
  template <Damping DK>
  static void update_free_block(ModelData<D>& m, const StepCtx& c, std::ptrdiff_t p0, std::ptrdiff_t pe,
                                const double (*F)[kBlock], double* __restrict V2, double* __restrict DP) {
    const std::size_t nb = static_cast<std::size_t>(pe - p0);
    const std::uint8_t* __restrict FL = m.flags.data() + p0;
    const double* __restrict IMb = m.im.block(static_cast<std::size_t>(p0));
    double* __restrict X0 = m.x[0].data() + p0;
    double* __restrict X1 = m.x[1].data() + p0;
    double* __restrict X2 = m.x[D - 1].data() + p0;
    double* __restrict V0 = m.v[0].data() + p0;
    double* __restrict V1 = m.v[1].data() + p0;
    double* __restrict W2 = m.v[D - 1].data() + p0;
    const double* __restrict F0 = F[0];
    const double* __restrict F1 = F[1];
    const double* __restrict F2 = F[D - 1];
    const double dt = c.dt, cv = c.viscous_c, alpha = c.local_alpha, g0 = c.g[0], g1 = c.g[1],
                 g2 = c.g[D - 1];
#pragma omp simd
    for (std::size_t q = 0; q < nb; ++q) {
      const double imass = IMb[q];
      const bool free = FL[q] == 0;
      double dp = 0, v2 = 0;
      const double vo0 = V0[q], vo1 = V1[q];
      const double vn0 = integrate<DK>(vo0, F0[q], imass, g0, dt, cv, alpha, dp);
      const double vn1 = integrate<DK>(vo1, F1[q], imass, g1, dt, cv, alpha, dp);
      V0[q] = free ? vn0 : vo0;
      X0[q] = free ? X0[q] + vn0 * dt : X0[q];
      v2 += vn0 * vn0;
      V1[q] = free ? vn1 : vo1;
      X1[q] = free ? X1[q] + vn1 * dt : X1[q];
      v2 += vn1 * vn1;
      if constexpr (D == 3) {
        const double vo2 = W2[q];
        const double vn2 = integrate<DK>(vo2, F2[q], imass, g2, dt, cv, alpha, dp);
        W2[q] = free ? vn2 : vo2;
        X2[q] = free ? X2[q] + vn2 * dt : X2[q];
        v2 += vn2 * vn2;
      }
      V2[q] = free ? v2 : 0.0;  // a particle with a boundary condition: its own update (bc_update)
      DP[q] = free ? dp : 0.0;
    }
  }

  /// The free particles' damping losses of a block are summed in kLossLanes lanes, particle
  /// q of the block (from its first) in lane q mod kLossLanes, and the lanes then added in
  /// pairs (loss_total): the vector form has one chain of additions per lane instead of one
  /// through the block (a tenth of the step of a model of 10^3 disks), and both forms of the
  /// particle update, in lanes and particle by particle, give the same bits at any vector
  /// width.
  static constexpr int kLossLanes = 8;
  static double loss_total(const double* l) {
    static_assert(kLossLanes == 8, "pairs of pairs of pairs");
    return ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]));
  }

  /// Particle p's bond forces from thread t's ring: minus those of the bonds it is the
  /// partner of, by ascending owner (descending direction), then plus its own, by ascending
  /// partner; eb gains its own bonds' energies in the same order (kEnergy).
  template <bool kEnergy>
  static inline void pull_slots(LatticeSlots<D>& L, int t, std::ptrdiff_t p, double* F, double& eb) {
    const auto* mk = L.mask.data();
    for (int a = 0; a < D; ++a) F[a] = 0.0;
    for (int d = L.n - 1; d >= 0; --d) {
      const std::ptrdiff_t o = p - static_cast<std::ptrdiff_t>(L.off[d]);
      if (o >= 0 && (mk[o] >> d & 1u)) {
        const std::size_t r = L.slot(d, static_cast<std::size_t>(o));
        for (int a = 0; a < D; ++a) F[a] -= L.force(t, d, a)[r];
      }
    }
    const auto mp = mk[p];
    for (int d = 0; d < L.n; ++d)
      if (mp >> d & 1u) {
        const std::size_t r = L.slot(d, static_cast<std::size_t>(p));
        for (int a = 0; a < D; ++a) F[a] += L.force(t, d, a)[r];
        if constexpr (kEnergy) eb += L.energy(t, d)[r];
      }
  }

  // With kSlots (no contacts, the model in lattice slots) the bond pass runs by direction
  // (bond_block_slots) and each particle pulls its bonds' forces from its thread's ring in
  // the order the other form pushes them: the bonds of its owners by ascending owner, then
  // its own by ascending partner. The bonds crossing into a later thread's range come from
  // its phase A: into that thread's ring there, into this one's (slots_cross_in) here.
  template <Damping DK, bool kEnergy, bool kSlots = false>
  void phase_b(ModelData<D>& m, int t, const StepCtx& c) const {
    const std::ptrdiff_t b = m.plan.begin[t], e = m.plan.begin[t + 1];
    if (b >= e) return;
    double* __restrict X[D];
    double* __restrict V[D];
    for (int a = 0; a < D; ++a) {
      X[a] = m.x[a].data();
      V[a] = m.v[a].data();
    }
    const ParticleConst& R = m.rad;  // R[j]: a contact's partner (a block's own: Rb below)
    const std::uint8_t* __restrict FL = m.flags.data();
    const std::uint32_t* __restrict boff = m.bonds.off.data();
    const std::uint32_t* __restrict bj = m.bonds.j.data();
    const std::uint32_t* __restrict coff = m.contacts.off.data();
    const std::uint32_t* __restrict cj = m.contacts.j.data();
    std::uint8_t* __restrict cst = m.contacts.st.data();
    const double dt = c.dt, cv = c.viscous_c, alpha = c.local_alpha;
    const bool one_law = nmat == 1;
    const Law law0 = laws[0];
    const std::size_t nwalls = c.nwalls;
    const Wall* W = c.walls;
    const double* XC[D];
    const double* VC[D];
    for (int a = 0; a < D; ++a) {
      XC[a] = X[a];
      VC[a] = V[a];
    }

    // pending forces: the ring for partners before ring_end, a slot of their block's further on
    double* __restrict RG = m.pend[t].ring.data();
    constexpr std::uint32_t kRingMask = ModelData<D>::kRing - 1;
    static_assert((ModelData<D>::kRing & kRingMask) == 0, "the ring's size is a power of two");
    std::uint32_t ring_end =
        static_cast<std::uint32_t>(std::min<std::ptrdiff_t>(e, b + kRingBlocks * kBlock));
    auto pend_sub = [&](std::uint32_t j, const double* Fp) {
      if (j < ring_end) [[likely]] {
        for (int a = 0; a < D; ++a) RG[a * ModelData<D>::kRingStride + (j & kRingMask)] -= Fp[a];
      } else {
        m.pending_far_sub(t, j, Fp);
      }
    };
    // incoming cross contributions, ascending owner (in slots: phase A put them in the ring)
    if constexpr (!kSlots)
      for (const Incoming& in : m.plan.in[t]) {
        const double* s = in.contact ? &m.cross_c[in.slot * (D + 1)] : &m.cross_b[in.slot * (D + 1)];
        pend_sub(in.target, s);
      }
    std::size_t cur_b = m.plan.base_b[t], cur_c = m.plan.base_c[t];
    std::size_t next_wait = 0;  // the next of the waits for cross pairs, and its block (-1: none)
    std::ptrdiff_t next_wait_blk = m.plan.waits[t].empty() ? -1 : m.plan.waits[t][0].blk;
    auto bc_it = std::lower_bound(m.bcp.begin(), m.bcp.end(), static_cast<std::uint32_t>(b),
                                  [](const BcParticle& q, std::uint32_t i) { return q.index < i; });

    for (std::ptrdiff_t blk = b / kBlock; blk * kBlock < e; ++blk) {
      const std::ptrdiff_t pe = std::min(e, (blk + 1) * kBlock);
      // the block's cross pairs computed by later threads, before they are read and their owners move
      if (blk == next_wait_blk) [[unlikely]] {
        next_wait = wait_for_cross_pairs(m, t, blk, next_wait);
        next_wait_blk = next_wait < m.plan.waits[t].size() ? m.plan.waits[t][next_wait].blk : -1;
      }
      // diss: the losses of the particles with a boundary condition, in particle order; the
      // free particles' in loss (loss_total)
      double work = 0, work_ex = 0, diss = 0, ke = 0, eb = 0, vmax2 = 0, vfree2 = 0;
      alignas(64) double loss[kLossLanes] = {};
      if constexpr (kSlots) {
        if (m.uniform_diameter > 0)
          bond_block_slots<kEnergy, kUniform>(m, t, c, blk * kBlock, pe, e);
        else
          bond_block_slots<kEnergy, kRadiusSum>(m, t, c, blk * kBlock, pe, e);
        if (pe + static_cast<std::ptrdiff_t>(m.slots.off[m.slots.n - 1]) > e &&
            e < static_cast<std::ptrdiff_t>(m.n())) [[unlikely]]
          slots_cross_in(m, t, blk * kBlock, pe, e, cur_b);
      } else if (!m.bonds.r0.empty())
        bond_block<kEnergy, kPerBond>(m, t, c, blk * kBlock, pe, e);
      else if (m.uniform_diameter > 0)
        bond_block<kEnergy, kUniform>(m, t, c, blk * kBlock, pe, e);
      else
        bond_block<kEnergy, kRadiusSum>(m, t, c, blk * kBlock, pe, e);
      // the block's bond forces and energies (pointers hoisted: the stores of pending forces below
      // would otherwise make the compiler reload them for every bond)
      const std::uint32_t kb0 = boff[blk * kBlock];
      const double* __restrict SF[D] = {};
      const double* __restrict SE = nullptr;
      if constexpr (!kSlots) {
        for (int a = 0; a < D; ++a) SF[a] = m.scratch[t].fb[a].data() - kb0;
        SE = m.scratch[t].en.data() - kb0;
      }
      const std::ptrdiff_t p0 = blk * kBlock;
      // a block whose bonds all reach partners in this thread's range and in the ring (nearly
      // every block of a lattice) passes their reactions on without the checks below
      std::uint32_t jmax = 0;
      if constexpr (!kSlots)
        for (std::uint32_t k = kb0; k < boff[pe]; ++k) jmax = std::max(jmax, bj[k]);
      const bool near = jmax < std::min(static_cast<std::uint32_t>(e), ring_end);
      const double* __restrict Rb = m.rad.block(static_cast<std::size_t>(p0));
      const double* __restrict IMb = m.im.block(static_cast<std::size_t>(p0));
      bool in_lanes = false;  // the block's particles updated below in vector lanes
      if constexpr (kSlots && !kEnergy) {
        // forces and the free particles' update in vector lanes; the sums, and the particles
        // with a boundary condition, in particle order
        if (nwalls == 0) {
          alignas(64) double FX[D][kBlock], V2[kBlock], DP[kBlock];
          pull_block(m.slots, t, p0, pe, FX);
          update_free_block<DK>(m, c, p0, pe, FX, V2, DP);
          // the free particles' losses and largest speed in lanes (V2 and DP are 0 for the
          // others, and for the lanes past the block's end): maxima and sums with no chain
          // through the block
          const std::size_t nb = static_cast<std::size_t>(pe - p0);
          for (std::size_t q = nb; q % kLossLanes != 0; ++q) V2[q] = DP[q] = 0.0;
          alignas(64) double vl[kLossLanes] = {};
          for (std::size_t q0 = 0; q0 < nb; q0 += kLossLanes)
            for (int l = 0; l < kLossLanes; ++l) {
              loss[l] += DP[q0 + l];
              vl[l] = std::max(vl[l], V2[q0 + l]);
            }
          for (int l = 0; l < kLossLanes; ++l) vfree2 = std::max(vfree2, vl[l]);
          vmax2 = vfree2;
          // the particles with a boundary condition (m.bcp, by index), in particle order
          for (; bc_it != m.bcp.end() && bc_it->index < static_cast<std::uint32_t>(pe); ++bc_it) {
            const std::ptrdiff_t p = bc_it->index;
            const std::size_t q = static_cast<std::size_t>(p - p0);
            double F[D], vv = 0, v2 = 0;
            for (int a = 0; a < D; ++a) F[a] = FX[a][q];
            bc_update<DK>(*bc_it, c, F, IMb[q], p, X, V, work, work_ex, diss, vfree2, v2, vv);
            vmax2 = std::max(vmax2, v2);
          }
          in_lanes = true;
        }
      }
      for (std::ptrdiff_t p = p0; p < (in_lanes ? p0 : pe); ++p) {
        double F[D];  // the forces of earlier particles' pairs and of the incoming cross pairs
        if constexpr (kSlots) {
          pull_slots<kEnergy>(m.slots, t, p, F, eb);
        } else {
          for (int a = 0; a < D; ++a)
            F[a] = RG[a * ModelData<D>::kRingStride + (static_cast<std::uint32_t>(p) & kRingMask)];
        }
        // bonds owned by p, then contacts owned by p (fixed order)
        if constexpr (kSlots) {
          // its own bonds are in F already (pull_slots)
        } else if (near) {
          for (std::uint32_t k = boff[p]; k < boff[p + 1]; ++k) {
            const std::uint32_t jr = bj[k] & kRingMask;
            for (int a = 0; a < D; ++a) {
              RG[a * ModelData<D>::kRingStride + jr] -= SF[a][k];
              F[a] += SF[a][k];
            }
            if constexpr (kEnergy) eb += SE[k];
          }
        } else {
          for (std::uint32_t k = boff[p]; k < boff[p + 1]; ++k) {
            const std::uint32_t j = bj[k];
            double Fb[D];
            if (j >= static_cast<std::uint32_t>(e)) [[unlikely]] {
              const double* s = &m.cross_b[cur_b++ * (D + 1)];
              for (int a = 0; a < D; ++a) Fb[a] = s[a];
              if constexpr (kEnergy) eb += s[D];
            } else {
              for (int a = 0; a < D; ++a) Fb[a] = SF[a][k];
              pend_sub(j, Fb);
              if constexpr (kEnergy) eb += SE[k];
            }
            for (int a = 0; a < D; ++a) F[a] += Fb[a];
          }
        }
        for (std::uint32_t k = coff[p]; k < coff[p + 1]; ++k) {
          const std::uint32_t j = cj[k];
          double Fb[D];
          if (j >= static_cast<std::uint32_t>(e)) {
            const double* s = &m.cross_c[cur_c++ * (D + 1)];
            for (int a = 0; a < D; ++a) Fb[a] = s[a];
            if constexpr (kEnergy) eb += s[D];
          } else {
            int broke = 0;
            double none[kNs];
            const Law& law = one_law ? law0 : law_of(m, p, j);
            const double en =
                pair_force<kEnergy>(XC, VC, R[p] + R[j], p, j, cst[k],
                                    ModelData<D>::us_of(m.contacts, k, none), law, dt, Fb, broke);
            if constexpr (kEnergy) eb += en;
            pend_sub(j, Fb);
          }
          for (int a = 0; a < D; ++a) F[a] += Fb[a];
        }
        // rigid walls (penalty springs)
        for (std::size_t w = 0; w < nwalls; ++w) {
          double s = 0;
          for (int a = 0; a < D; ++a) s += (X[a][p] - W[w].p[a]) * W[w].n[a];
          const double delta = Rb[p - p0] - s;
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
        const double imass = IMb[p - p0];
        double v2 = 0, vv = 0;
        if (!FL[p]) [[likely]] {
          double dp = 0;  // this particle's damping loss, added to its lane of loss
          for (int a = 0; a < D; ++a) {
            const double vo = V[a][p];
            const double vn = integrate<DK>(vo, F[a], imass, c.g[a], dt, cv, alpha, dp);
            V[a][p] = vn;
            X[a][p] += vn * dt;
            v2 += vn * vn;
            vv += vo * vn;
          }
          vfree2 = std::max(vfree2, v2);
          loss[static_cast<std::size_t>(p - p0) % kLossLanes] += dp;
        } else {
          bc_update<DK>(*bc_it++, c, F, imass, p, X, V, work, work_ex, diss, vfree2, v2, vv);
        }
        vmax2 = std::max(vmax2, v2);
        if constexpr (kEnergy) ke += 0.5 * vv / imass;
      }
      if constexpr (!kSlots) m.pending_advance(t, blk, e);  // may move a slot into the ring
      ring_end = static_cast<std::uint32_t>(std::min<std::ptrdiff_t>(e, (blk + 1 + kRingBlocks) * kBlock));
      BlockAcc& A = m.acc[blk];
      A.work += work;
      A.work_ex += work_ex;
      A.dissipated += diss + loss_total(loss);
      A.vmax2 = vmax2;
      A.vfree2 = vfree2;
      if constexpr (kEnergy) {
        A.ke = ke;
        A.eb = eb;
      }
    }
  }

  template <Damping DK, bool kEnergy>
  void step_once(ModelData<D>& m, const StepCtx& c, bool in_slots) const {
    const int nt = m.plan.nt;
    ++m.plan.epoch;
    if constexpr (kSlotsBuilt) {
      if (in_slots) {
        run_plan<DK, kEnergy, true>(m, c, nt);
        return;
      }
    }
    run_plan<DK, kEnergy, false>(m, c, nt);
  }

  /// Both phases on the plan's threads (one thread: no team is started).
  template <Damping DK, bool kEnergy, bool kSlots>
  void run_plan(ModelData<D>& m, const StepCtx& c, int nt) const {
    par::parallel_team(nt, [&](int t, int team) {
      if (team != nt) {  // fewer threads than planned: run the plan serially on thread 0
        if (t == 0) {
          for (int s = 0; s < nt; ++s) phase_a<kEnergy, kSlots>(m, s, c);
          for (int s = 0; s < nt; ++s) phase_b<DK, kEnergy, kSlots>(m, s, c);
        }
        return;
      }
      phase_a<kEnergy, kSlots>(m, t, c);
      phase_b<DK, kEnergy, kSlots>(m, t, c);
    });
  }

  template <bool kEnergy>
  void dispatch(ModelData<D>& m, const StepCtx& c, bool in_slots) const {
    switch (c.damping) {
      case Damping::None:
        step_once<Damping::None, kEnergy>(m, c, in_slots);
        break;
      case Damping::Viscous:
        step_once<Damping::Viscous, kEnergy>(m, c, in_slots);
        break;
      case Damping::Local:
        step_once<Damping::Local, kEnergy>(m, c, in_slots);
        break;
    }
  }
};

}  // namespace strata::dem::detail
