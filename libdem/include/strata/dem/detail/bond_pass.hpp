#pragma once
// Not API: the vectorised part of the bond pass (see step_kernel.hpp): one chunk of a
// block's bonds through the law's batch form (`lane`, laws.hpp).
#include <strata/dem/detail/model_data.hpp>
#include <strata/dem/laws/common.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <utility>

namespace strata::dem::detail {

/// Whether Law has a batch form for the bond pass (otherwise every bond takes `apply`).
template <class Law, int NS>
concept HasLane = requires(const Law& l, const BondLane<NS>& b) {
  { l.template lane<NS, true, true>(b) } -> std::same_as<BondLaneResult<NS>>;
};

/// The largest shear displacement an intact bond of law l holds (Law::intact_shear_reach,
/// m) where the law says and it is finite, else 0.
template <class Law>
double shear_reach_of(const Law& l) {
  if constexpr (requires { l.intact_shear_reach(); }) {
    const double r = l.intact_shear_reach();
    return std::isfinite(r) ? r : 0.0;
  } else {
    return 0.0;
  }
}

/// Whether a broken bond of Law that is open (not touching) carries nothing, keeps a zero
/// shear displacement and its state while its length exceeds its rest length, and touches
/// again only once it is shorter (Law::kOpenIsInert): the bond pass then takes such bonds
/// through the intact form (bond_span with kOpen).
template <class Law>
inline constexpr bool kOpenIsInert = requires {
  requires Law::kOpenIsInert;
};

/// x where mask is all ones, +0 where it is zero: a bond's value kept or zeroed by bit
/// operations. A select between x and 0 would do the same, but where x is a load GCC 12
/// makes it a masked load, and under the step kernel's no-gather tuning a loop holding
/// one does not vectorise.
inline double masked(double x, std::int64_t mask) {
  return std::bit_cast<double>(std::bit_cast<std::int64_t>(x) & mask);
}

/// The bits of a | b: of two values of which masked() zeroed one, the other one.
inline double either(double a, double b) {
  return std::bit_cast<double>(std::bit_cast<std::int64_t>(a) | std::bit_cast<std::int64_t>(b));
}

/// How the bond pass gets a bond's rest length.
enum Rest { kRadiusSum, kUniform, kPerBond };

/// Bonds per chunk of the bond pass (see bond_block).
inline constexpr std::size_t kChunk = 128;

/// Bond pass pointers of one block (indexed by the block's bond position q).
struct BondSpan {
  const double *X0, *X1, *X2, *V0, *V1, *V2, *R, *r0, *kf, *sf;
  double *F0, *F1, *F2, *en;
  /// The shear histories (BondShear): uq at the span's first bond, kNs per bond (in slots:
  /// component a of entry q at uq[a * us_n + q]); wide, the
  /// wide bonds' entries (at least one: the pass reads entry 0 for a bond held in steps);
  /// unit and its inverse. keep_us false: uq points at zeros the pass reads and must not
  /// write (no shear history; unit and inv are then 0).
  std::int32_t* uq;
  double* wide;
  double unit, inv;
  bool keep_us;
  bool intact_wide;        // an intact bond may be wide (BondShear::intact_wide)
  std::uint32_t k0, salt;  // the index of the span's first bond, and BondShear::salt_of(step)
  const std::uint8_t* own;
  const std::uint32_t* j;
  std::uint8_t *st, *slow;
  std::uint32_t p0, e;
  /// Bonds in lattice slots (bond_span with kInSlots): the span's entry q is owner pa + q's
  /// bond in direction dir, to partner pa + q + so, where bit dir of smask[q] says the owner
  /// has it; its index is soff[q] plus the owner's bonds in lower directions (dithering). The
  /// arrays indexed by q (st, uq, slow, the forces and energies) hold the span's entries, not
  /// the bonds'; an entry without a bond is computed and left as it was (slow 0).
  std::uint32_t pa = 0, so = 0;
  int dir = 0;
  std::size_t us_n = 0;  // in slots: the stride between the components of uq
  const std::uint32_t* soff = nullptr;
  const std::uint8_t* smask = nullptr;    // 2D
  const std::uint16_t* smask3 = nullptr;  // 3D (up to ten directions)
  bool* slow_seen = nullptr;              // set where an entry is left to the reference kernel
};

/// Where component a of entry q's shear history lies in BondSpan::uq: kNs per bond, or in
/// lattice slots one array per component, us_n apart.
template <int kNs, bool kInSlots>
[[gnu::always_inline]] inline std::size_t us_index(std::size_t q, int a, std::size_t us_n) {
  if constexpr (kInSlots)
    return static_cast<std::size_t>(a) * us_n + q;
  else
    return q * kNs + static_cast<std::size_t>(a);
}

/// The directions owner pa + q holds (BondSpan::smask, or smask3 in 3D).
template <int D>
[[gnu::always_inline]] inline std::uint32_t slot_mask(const BondSpan& sp, std::size_t q) {
  if constexpr (D == 2)
    return sp.smask[q];
  else
    return sp.smask3[q];
}

/// Bonds qa..qb-1 of a block: the geometry of each bond, then the law's batch form
/// (`Law::lane`) for both kinds of bond: intact and, when kBroken, broken (friction only).
/// Bitwise & and selects instead of branches, so the loop vectorises; a bond left for the
/// reference kernel (one breaking now, or a cross bond) keeps its stored state here.
/// Without kBroken every bond of the range must be intact and held in 32 bits: the
/// broken-bond law (a square root and a division per bond) and the wide entries are left
/// out; with kOpen (and without kBroken) a bond may also be broken, separated and not
/// touching (kOpenIsInert): its stored Us is zero, and while its length exceeds its rest
/// length it carries nothing (the broken-bond law's zero force; its state and Us stay as
/// they are); one that touches again is left to the reference kernel. Without kShear the
/// model keeps no shear history (every law's Ks is zero): Us is zero and nothing is rounded
/// or stored.
/// Everything it calls is inlined (flatten): GCC 12 left the law's batch form of the full
/// law (kBroken) as a call per bond, which kept the loop over the bonds from vectorising.
template <int D, class Law, bool kEnergy, Rest kRest, bool kBroken, bool kShear, bool kOpen = false,
          bool kInSlots = false>
[[gnu::flatten]] void bond_span(const BondSpan& sp, const Law& L, double dt, double d_uniform, std::size_t qa,
                                std::size_t qb) {
  using namespace pair_state;
  constexpr int kNs = kNsOf<D>;
  // in slots, the particle arrays from the span's first owner on: entry q's owner is q
  const std::size_t at = kInSlots ? sp.pa : 0;
  const double* __restrict X0 = sp.X0 + at, * __restrict X1 = sp.X1 + at, * __restrict X2 = sp.X2 + at;
  const double* __restrict V0 = sp.V0 + at, * __restrict V1 = sp.V1 + at, * __restrict V2 = sp.V2 + at;
  double* __restrict F0 = sp.F0, * __restrict F1 = sp.F1, * __restrict F2 = sp.F2;
  const double* __restrict R = sp.R ? sp.R + at : nullptr;
  const double* __restrict br0 = sp.r0;
  const double* __restrict bkf = sp.kf;
  const double* __restrict bsf = sp.sf;
  const std::uint8_t* __restrict own = sp.own;
  const std::uint32_t* __restrict bj = sp.j;
  std::uint8_t* __restrict bst = sp.st;
  std::uint8_t* __restrict slow = sp.slow;
  std::int32_t* __restrict buq = sp.uq;
  const std::size_t us_n = sp.us_n;
  // component a of bond q's history
  auto us_of = [buq, us_n](std::size_t q, int a) -> std::int32_t& {
    return buq[us_index<kNs, kInSlots>(q, a, us_n)];
  };
  double* __restrict bwide = sp.wide;
  const double unit = sp.unit, inv = sp.inv;
  const std::uint32_t k0 = sp.k0, salt = sp.salt;
  double* __restrict EN = sp.en;
  const std::uint32_t up0 = sp.p0, ee = sp.e;
  const Law law = L;  // a local copy: its parameters cannot alias the stores below
  // Endpoints, states and verdicts in 64-bit lanes: with a byte-sized type in the loop GCC
  // vectorises 64 bonds at a time (8 registers per double) and spills.
  const std::size_t len_q = qb - qa;
  alignas(64) std::int64_t P[kChunk], J[kChunk], ST[kChunk], SLOW[kChunk];
  // the entry of a wide bond's history in bwide, or -1 (with kBroken only: a chunk without
  // a broken or wide bond holds every history in 32 bits)
  alignas(64) std::int64_t WI[kChunk], WF[kChunk];               // WF: 1 for a wide bond (WI >= 0)
  alignas(64) std::int64_t OST[kChunk], DONE[kChunk];            // kBroken: the law's new state and verdict
  alignas(64) std::int64_t HAS[kInSlots ? kChunk : 1];           // kInSlots: 1 where the owner has the bond
  alignas(64) std::int64_t BI[kInSlots && kShear ? kChunk : 1];  // kInSlots: the bond's index
  // 1 where a fast bond's new Us goes to its 32-bit steps: in 32-bit lanes like the steps
  // and applied by masks (with a 64-bit flag or a select GCC 12 left the 3D store scalar)
  alignas(64) std::int32_t PUT32[kShear ? kChunk : 1];
  alignas(64) std::int32_t QN[kNs][kChunk];  // a new Us in 32-bit steps (BondShear::steps_of)
  alignas(64) double NU[kNs][kChunk];        // new shear displacements (stored for fast bonds only)
  auto ends = [&](std::size_t i, std::size_t q) {
    if constexpr (kInSlots)
      return std::pair<std::size_t, std::size_t>{q, q + sp.so};
    else
      return std::pair<std::int64_t, std::int64_t>{P[i], J[i]};
  };
  for (std::size_t i = 0; i < len_q; ++i) {
    if constexpr (kInSlots) {
      const std::uint32_t mask = slot_mask<D>(sp, qa + i);
      HAS[i] = mask >> sp.dir & 1;
      if constexpr (kShear) {  // LatticeSlots::bond
#if defined(__AVX512VPOPCNTDQ__)
        // a vector population count: one instruction per lane vector
        const std::uint32_t bond =
            LatticeSlots<D>::bond(sp.soff[qa + i], static_cast<typename LatticeSlots<D>::Mask>(mask), sp.dir);
#else
        // counted bit by bit, which vectorises without a vector population count
        const std::uint32_t lower = mask & ((1u << sp.dir) - 1u);
        std::uint32_t bond = sp.soff[qa + i] + (lower & 1u) + (lower >> 1 & 1u) + (lower >> 2 & 1u);
        static_assert(LatticeSlots<D>::kMax == (D == 2 ? 4 : 10), "one term per lower direction");
        if constexpr (D == 3)
          bond += (lower >> 3 & 1u) + (lower >> 4 & 1u) + (lower >> 5 & 1u) + (lower >> 6 & 1u) +
                  (lower >> 7 & 1u) + (lower >> 8 & 1u);
#endif
        BI[i] = bond;
      }
    } else {
      P[i] = up0 + own[qa + i];
      J[i] = bj[qa + i];
    }
    if constexpr (kBroken || kOpen) ST[i] = bst[qa + i];
    if constexpr (kBroken && kShear) {
      const std::int32_t h = us_of(qa + i, 0);
      WI[i] = BondShear<kNs>::is_wide(h) ? static_cast<std::int64_t>(BondShear<kNs>::index_of(h)) : -1;
      WF[i] = BondShear<kNs>::is_wide(h);
    }
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
    // in slots the owners and partners of consecutive entries are consecutive particles
    // (unsigned indices from the shifted arrays: the compiler then loads whole vectors)
    const auto [p, j] = ends(i, q);
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
    // shear displacement with this step's increment, and its square; the stored Us is in
    // 32-bit steps, or for a wide bond (kBroken only) in its entry. Without a shear history
    // every law's Ks is zero, and a law's force, verdict and energy then do not depend on Us
    // (laws.hpp): Us stays zero and the ends' velocities are not read.
    double us[3] = {0, 0, 0};  // the stored Us plus this step's increment, turned
    double u2 = 0;
    if constexpr (kShear) {
      double b[kNs];
      if constexpr (kBroken) {
        // both read (a wide bond's steps are its entry's code, a bond held in steps reads
        // entry 0) and the right one kept by masks: a select of the loads would be a masked
        // load
        const std::int64_t wide = -static_cast<std::int64_t>(WI[i] >= 0);  // all ones: wide
        const std::int64_t w = WI[i] & wide;
        for (int a = 0; a < kNs; ++a)
          b[a] = either(masked(bwide[w * kNs + a], wide), masked(us_of(q, a) * unit, ~wide));
      } else if constexpr (kOpen) {
        // broken and open: Us is zero (its wide entry holds zeros); the steps are read either
        // way and masked to +0
        const std::int64_t whole = -static_cast<std::int64_t>(ST[i] == kIntact);  // all ones: intact
        for (int a = 0; a < kNs; ++a) b[a] = masked(us_of(q, a) * unit, whole);
      } else {
        for (int a = 0; a < kNs; ++a) b[a] = us_of(q, a) * unit;
      }
      if constexpr (D == 2) {
        us[0] = b[0] + ((V1[j] - V1[p]) * n0 - (V0[j] - V0[p]) * n1) * dt;
      } else {
        // the stored Us plus the increment, its normal part projected out (as the reference
        // kernel, pair_force)
        const double w0 = b[0] + (V0[j] - V0[p]) * dt, w1 = b[1] + (V1[j] - V1[p]) * dt,
                     w2 = b[kNs - 1] + (V2[j] - V2[p]) * dt;
        const double wn = w0 * n0 + w1 * n1 + w2 * n2;
        us[0] = w0 - wn * n0;
        us[1] = w1 - wn * n1;
        us[2] = w2 - wn * n2;
      }
      // from the first square, not from 0 + it: a square is never -0, so the same bits, and
      // an addition fewer (GCC keeps 0 + x, which is not x for x = -0)
      u2 = us[0] * us[0];
      for (int a = 1; a < kNs; ++a) u2 += us[a] * us[a];
    }
    Geo g{{n0, n1, n2}, un, {us[0], us[1], us[2]}, u2};
    return g;
  };
  // The verdict on bond i of the chunk, whose new state is ost and whose new Us (in NU),
  // of square u2, the law is done with (done): fast, or left to the reference kernel
  // (SLOW) where the law is not done, the partner is another thread's, or the new Us needs
  // a wide entry the bond does not have yet (an intact bond beyond the reach: the reference
  // kernel asks for one); and a fast bond's Us in 32-bit steps (QN) where it is held so.
  // Integer lanes: with bools GCC branches.
  auto keep = [&](std::size_t i, double u2, std::int64_t ost, std::int64_t done) {
    // intact and within the reach (BondShear::within: an intact bond's new Us is the one of
    // square u2)
    std::int64_t in32 = 0, held = 1;  // without a shear history every bond is held
    if constexpr (kShear) {
      in32 = BondShear<kNs>::within(u2, inv);
      held = in32;
      if constexpr (kBroken) {
        in32 &= (ost & kKindMask) == kIntact;
        held = in32 | WF[i];
      }
      if constexpr (kOpen) {  // an open broken bond keeps its (zero) Us where it is
        const std::int64_t open = ST[i] != kIntact;
        in32 &= !open;
        held = in32 | open;
      }
      std::uint32_t bond = k0 + static_cast<std::uint32_t>(qa + i);
      if constexpr (kInSlots) bond = static_cast<std::uint32_t>(BI[i]);
      const std::uint32_t bits = BondShear<kNs>::dither_bits(bond, salt);
      // +0 where the bond is not held in steps, by a mask on the value: with a select GCC 12
      // rounded and converted both the value and 0 and chose between the two results
      const std::int64_t whole = -in32;  // all ones: held in steps
      for (int a = 0; a < kNs; ++a)
        QN[a][i] = BondShear<kNs>::steps_of(masked(NU[a][i] * inv, whole), bits, a);
    }
    // (in slots the pass takes only the entries whose partner is in range)
    std::int64_t fast = (kInSlots || J[i] < ee64) & done & held;
    if constexpr (kInSlots) {  // an entry without a bond is neither fast nor slow: nothing is kept
      fast &= HAS[i];
      SLOW[i] = (fast == 0) & HAS[i];
    } else {
      SLOW[i] = !fast;
    }
    if constexpr (kShear) PUT32[i] = static_cast<std::int32_t>(fast & in32);
    if constexpr (kBroken) ST[i] = ST[i] + fast * (ost - ST[i]);
  };
  auto apply_law = [&](std::size_t i, const Geo& g) {
    const std::size_t q = qa + i;
    BondLane<kNs> b;
    b.st = kBroken ? ST[i] : std::int64_t{kIntact};
    b.un = g.un;
    for (int a = 0; a < kNs; ++a) b.us[a] = g.us[a];
    b.u2 = g.u2;
    if constexpr (kRest == kPerBond) {  // 1 otherwise, which the compiler folds away
      b.kf = bkf[q];
      b.sf = bsf[q];
    }
    BondLaneResult<kNs> o = law.template lane<kNs, kBroken, kEnergy>(b);
    if constexpr (kOpen) {
      // a broken bond open before this step: while it stays open (Un <= 0) the broken-bond
      // law's zero force (+0 each: Fn = 0, Fs = Ks·0); once it touches, the reference kernel
      const std::int64_t whole = -static_cast<std::int64_t>(ST[i] == kIntact);  // all ones: intact
      o.fn = masked(o.fn, whole);
      for (int a = 0; a < kNs; ++a) o.fs[a] = masked(o.fs[a], whole);
      const std::int64_t apart = !(g.un > 0);
      o.done = (o.done & whole) | (apart & ~whole);
      if constexpr (kEnergy) o.energy = masked(o.energy, whole);
    }
    for (int a = 0; a < kNs; ++a) NU[a][i] = o.us[a];
    if constexpr (kBroken) {  // the verdict in a loop of its own (keep, below)
      OST[i] = o.st;
      DONE[i] = o.done;
    } else {
      keep(i, b.u2, o.st, o.done);
    }
    const double n0 = g.n[0], n1 = g.n[1], n2 = g.n[2];
    // −Fn·n + Fs as the reference kernel has it; in 3D written Fs − Fn·n, which is the same
    // operation (b − a is b + (−a), bit for bit) without negating Fn first
    if constexpr (D == 2) {
      F0[q] = -o.fn * n0 - o.fs[0] * n1;
      F1[q] = -o.fn * n1 + o.fs[0] * n0;
    } else {
      F0[q] = o.fs[0] - o.fn * n0;
      F1[q] = o.fs[1] - o.fn * n1;
      F2[q] = o.fs[2] - o.fn * n2;
    }
    if constexpr (kEnergy) EN[q] = o.energy;
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
      apply_law(i, g);
    }
#pragma omp simd
    for (std::size_t i = 0; i < len_q; ++i) keep(i, GU2[i], OST[i], DONE[i]);
  } else {
#pragma omp simd
    for (std::size_t i = 0; i < len_q; ++i) apply_law(i, geometry(i));
  }
  std::int64_t seen = 0;
  for (std::size_t i = 0; i < len_q; ++i) {
    slow[qa + i] = static_cast<std::uint8_t>(SLOW[i]);
    if constexpr (kBroken) bst[qa + i] = static_cast<std::uint8_t>(ST[i]);
    if constexpr (kInSlots) seen |= SLOW[i];
  }
  if constexpr (kInSlots)
    if (seen) *sp.slow_seen = true;
  if constexpr (kShear) {
    // fast bonds held in 32 bits: their new steps (by masks, not a branch or a select, so
    // that the loop vectorises in 2D and 3D); fast wide ones (broken, mostly): their entries
#pragma omp simd
    for (std::size_t i = 0; i < len_q; ++i) {
      const std::int32_t put = -PUT32[i];  // all ones: the new steps
      for (int a = 0; a < kNs; ++a) {
        std::int32_t& h = us_of(qa + i, a);
        h = (QN[a][i] & put) | (h & ~put);
      }
    }
    if constexpr (kBroken)
      for (std::size_t i = 0; i < len_q; ++i)  // left scalar by GCC in 3D (and 2D without AVX-512)
        if (!SLOW[i] && !PUT32[i] && (!kInSlots || HAS[i]))  // fast and not held in 32 bits: wide
          for (int a = 0; a < kNs; ++a) bwide[WI[i] * kNs + a] = NU[a][i];
  }
}

/// The bond pass of one block's bonds q0..mq-1, chunk by chunk: chunks with no broken bond
/// (nearly all of an unbroken lattice) skip the broken-bond law; the others take the full one.
template <int D, class Law, bool kEnergy, Rest kRest, bool kInSlots = false>
void bond_chunks(const BondSpan& sp, const Law& L, double dt, double d_uniform, std::size_t mq,
                 std::size_t q0 = 0) {
  constexpr int kNs = kNsOf<D>;
  const std::uint8_t* stq = sp.st;
  const std::int32_t* uq = sp.uq;
  static_assert(pair_state::kIntact == 0, "a chunk of intact bonds ORs to kIntact");
  for (std::size_t qa = q0; qa < mq; qa += kChunk) {  // left scalar: a chunk at a time
    const std::size_t qb = std::min(mq, qa + kChunk);
    // shut: a broken bond that touches, or one that has not been found open yet (its state
    // and Us are the law's to settle)
    std::uint8_t any = 0, shut = 0;
    for (std::size_t q = qa; q < qb; ++q) any |= stq[q];  // kIntact is 0: nonzero where one is not
    if (any != pair_state::kIntact)
      for (std::size_t q = qa; q < qb; ++q)
        shut |= (stq[q] & pair_state::kTouching) |
                (stq[q] != pair_state::kIntact && !(stq[q] & pair_state::kSeparated));
    // an intact bond that is wide (a broken one is, and sets `any`); it matters where no bond
    // is broken (the intact form is then out) or where the open form may apply
    constexpr bool kMayOpen = kOpenIsInert<Law>;
    bool wide = false;
    if (sp.intact_wide && !shut && (any == pair_state::kIntact || (kMayOpen && sp.keep_us)))
      for (std::size_t q = qa; q < qb; ++q)  // left scalar: only where intact bonds may be wide
        wide |= stq[q] == pair_state::kIntact &&
                BondShear<kNs>::is_wide(uq[us_index<kNs, kInSlots>(q, 0, sp.us_n)]);
    const bool broken = any != pair_state::kIntact || wide;
    // broken bonds, all open, among intact ones held in 32 bits: the intact form with kOpen
    // (with a shear history only: GCC 12 does not vectorise that form without)
    const bool open = kMayOpen && sp.keep_us && broken && !shut && !wide;
    if (!sp.keep_us) {  // no shear history: nothing of BondShear is read or written
      if (broken)
        bond_span<D, Law, kEnergy, kRest, true, false, false, kInSlots>(sp, L, dt, d_uniform, qa, qb);
      else
        bond_span<D, Law, kEnergy, kRest, false, false, false, kInSlots>(sp, L, dt, d_uniform, qa, qb);
    } else if (open) {
      bond_span<D, Law, kEnergy, kRest, false, true, true, kInSlots>(sp, L, dt, d_uniform, qa, qb);
    } else if (broken) {
      bond_span<D, Law, kEnergy, kRest, true, true, false, kInSlots>(sp, L, dt, d_uniform, qa, qb);
    } else {
      bond_span<D, Law, kEnergy, kRest, false, true, false, kInSlots>(sp, L, dt, d_uniform, qa, qb);
    }
  }
}

}  // namespace strata::dem::detail
