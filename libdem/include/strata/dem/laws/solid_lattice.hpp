#pragma once
/// The solid-lattice law: linear normal and shear springs, bonds that break in tension or in
/// shear, Coulomb friction after breaking (Liu, Pollard & Shi 2013, eqs. 1-5).
#include <strata/dem/laws/common.hpp>
#include <strata/dem/material.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace strata::dem {

/// The solid-lattice law (Liu, Pollard & Shi 2013, eqs. 1-5).
///  - intact: Fn = Kn·Un (Un = ri + rj - |xj - xi|, compression positive);
///    Fs = Ks·Us with Us accumulated from tangential displacement increments;
///    breaks in tension when Fn < -Fn_max, in shear when |Fs| > Fs0 or, with
///    `friction_strengthens_bonds`, |Fs| > Fs0 + mu·max(Fn, 0);
///  - broken bond or contact: no tension (Un <= 0: open, zero force, Us reset to 0);
///    touching: Fn = Kn·Un, |Fs| <= mu·Fn (Coulomb slip: Us is scaled back).
struct SolidLatticeLaw {
  static constexpr const char* kName = "solid_lattice";
  static constexpr const char* kDescription =
      "solid-lattice bonds (Liu, Pollard & Shi 2013): linear normal and shear springs, tension and "
      "shear breakage, Coulomb friction after breaking";
  double kn = 0, ks = 0, mu = 0, fn_max = 0, fs0 = 0;
  bool friction_strengthens_bonds = false;

  /// The law of a pair of particles of material m (for two materials, the pair rule's
  /// combined material).
  static SolidLatticeLaw from_material(const Material& m) {
    return {m.kn, m.ks, m.friction, m.tensile_strength, m.shear_strength, m.friction_strengthens_bonds};
  }
  /// The law with both stiffnesses multiplied by f (an intact bond of an eccentric lattice).
  inline SolidLatticeLaw scaled(double f) const {
    SolidLatticeLaw l = *this;
    l.kn *= f;
    l.ks *= f;
    return l;
  }
  /// The law with both bond strengths multiplied by f (a bond of a lattice with a spread of
  /// strengths).
  inline SolidLatticeLaw strengthened(double f) const {
    SolidLatticeLaw l = *this;
    l.fn_max *= f;
    l.fs0 *= f;
    return l;
  }
  /// Tangent stiffnesses, for the critical time step.
  inline PairStiffness stiffness() const { return {kn, ks}; }

  /// The largest shear displacement an intact bond holds without friction's help: Fs0/Ks
  /// (m; infinite for unbreakable bonds). strata sizes the 32-bit steps of intact bonds'
  /// shear histories on it (BondShear).
  inline double intact_shear_reach() const { return ks > 0 ? fs0 / ks : 0.0; }

  /// Shear strength of an intact bond carrying normal force fn.
  inline double intact_shear_limit(double fn) const {
    return friction_strengthens_bonds ? fs0 + mu * std::max(fn, 0.0) : fs0;
  }

  /// Reference kernel: advances one pair by one step. `st` state byte, `un` normal overlap
  /// now, `us` the NS shear displacement components: the stored ones plus this step's
  /// tangential displacement increment, turned into the current tangent plane by the
  /// caller. This law does not need the increment alone (`dus`).
  template <int NS>
  inline PairOutcome<NS> apply(std::uint8_t& st, double un, double* us, const double* /*dus*/) const {
    using namespace pair_state;
    PairOutcome<NS> o;
    if ((st & kKindMask) == kIntact) [[likely]] {
      double fs2 = 0;
      for (int a = 0; a < NS; ++a) fs2 += us[a] * us[a];
      fs2 *= ks * ks;
      const double fn = kn * un;
      const double lim = intact_shear_limit(fn);
      if (fn >= -fn_max && fs2 <= lim * lim) [[likely]] {
        o.fn = fn;
        for (int a = 0; a < NS; ++a) o.fs[a] = ks * us[a];
        return o;
      }
      // Tension is checked first: a bond over both limits breaks in tension.
      o.broke = fn < -fn_max ? 1 : 2;
      st = static_cast<std::uint8_t>((st & ~kKindMask) | (o.broke == 1 ? kBrokenTension : kBrokenShear));
      if (un > 0) st |= kTouching;
    }
    // Broken bond or contact: friction only.
    if (un <= 0) {
      for (int a = 0; a < NS; ++a) us[a] = 0;
      st = static_cast<std::uint8_t>(st & ~kTouching);
      if ((st & kKindMask) != kContact) st |= kSeparated;
      return o;
    }
    if (!(st & kTouching)) {
      st |= kTouching;
      if (st & kSeparated) st |= kReclosed;
    }
    double fs2 = 0;
    for (int a = 0; a < NS; ++a) fs2 += us[a] * us[a];
    fs2 *= ks * ks;
    o.fn = kn * un;
    const double cap = mu * o.fn;
    if (fs2 > cap * cap) {
      const double s = cap / std::sqrt(fs2);  // Coulomb slip: scale Us back onto the cap
      for (int a = 0; a < NS; ++a) us[a] *= s;
    }
    for (int a = 0; a < NS; ++a) o.fs[a] = ks * us[a];
    return o;
  }

  /// Stored energy of a pair (J): ½·Kn·Un² + ½·Ks·|Us|² for an intact bond, and for a
  /// broken bond or contact while it touches (Un > 0); zero otherwise.
  template <int NS>
  inline double energy(std::uint8_t st, double un, const double* us) const {
    using namespace pair_state;
    if ((st & kKindMask) != kIntact && un <= 0) return 0.0;
    double u2 = 0;
    for (int a = 0; a < NS; ++a) u2 += us[a] * us[a];
    return 0.5 * kn * un * un + 0.5 * ks * u2;
  }

  /// A broken bond that is open (Un <= 0 when last computed) carries nothing, holds Us = 0
  /// and keeps its state until it touches again (Un > 0): the bond pass may take it with the
  /// intact bonds (bond_pass.hpp, kOpenIsInert).
  static constexpr bool kOpenIsInert = true;

  /// Batch form of `apply` and `energy` for one bond (intact or broken; never a contact),
  /// written with selects and bitwise & instead of branches so that the bond pass's
  /// `omp simd` loop vectorises it. The same expressions in the same order as `apply`, so
  /// a bond gives the same bits on either path (tests/dem/test_law_conformance.cpp). A
  /// bond that breaks now is left to `apply` (done = false). kBroken = false: the caller
  /// promises an intact bond and the broken-bond law (a square root and a division) is
  /// left out. The stiffness factor b.kf scales Kn and Ks of an intact bond only. The loops
  /// over the NS components are unrolled by pragma: GCC 12 otherwise leaves some of them
  /// as loops inside the bond pass's loop, which then does not vectorise.
  template <int NS, bool kBroken, bool kEnergy>
  inline BondLaneResult<NS> lane(const BondLane<NS>& b) const {
    using namespace pair_state;
    const std::int64_t st0 = kBroken ? b.st : std::int64_t{kIntact};
    const double un = b.un, u2 = b.u2;
    const double kni = kn * b.kf, ksi = ks * b.kf;              // intact bond
    const double fn_maxi = fn_max * b.sf, fs0i = fs0 * b.sf;    // its strengths
    const double mu_b = friction_strengthens_bonds ? mu : 0.0;  // intact-bond friction term
    // intact: Fn = Kn·Un, Fs = Ks·Us, and the two limits
    const bool intact = !kBroken || st0 == kIntact;
    const double fn_i = kni * un;
    const double lim = fs0i + mu_b * std::max(fn_i, 0.0);  // = fs0i exactly when mu_b = 0
    const bool holds = (fn_i >= -fn_maxi) & (u2 * (ksi * ksi) <= lim * lim);
    BondLaneResult<NS> o;
    o.fn = fn_i;
    double kss = ksi;
#pragma GCC unroll 3
    for (int a = 0; a < NS; ++a) o.us[a] = b.us[a];
    o.st = st0;
    double e_b = 0;
    if constexpr (kBroken) {
      // broken: open (Un <= 0) carries nothing and forgets Us; touching: Coulomb slip
      const bool touch = un > 0;
      const double fn_t = kn * un;
      const double cap = mu * fn_t;
      const double fs2 = u2 * (ks * ks);
      const double sc = cap / std::sqrt(fs2);
      const bool slip = fs2 > cap * cap;
      const double fslip = slip ? sc : 1.0;  // us·1.0 is us exactly
      double ub[NS], ub2 = 0;
#pragma GCC unroll 3
      for (int a = 0; a < NS; ++a) {
        ub[a] = touch ? b.us[a] * fslip : 0.0;
        ub2 += ub[a] * ub[a];
      }
      // reclosed: touching again after having separated
      const std::int64_t reclosed = ((st0 & kSeparated) != 0) & ((st0 & kTouching) == 0);
      const std::int64_t st_b = touch ? (st0 | kTouching | (reclosed * kReclosed))
                                      : ((st0 & ~std::int64_t{kTouching}) | kSeparated);
      o.fn = intact ? fn_i : (touch ? fn_t : 0.0);
      kss = intact ? ksi : ks;
#pragma GCC unroll 3
      for (int a = 0; a < NS; ++a) o.us[a] = intact ? b.us[a] : ub[a];
      o.st = intact ? st0 : st_b;
      if constexpr (kEnergy) e_b = touch ? 0.5 * kn * un * un + 0.5 * ks * ub2 : 0.0;
    }
    o.done = !intact | holds;
#pragma GCC unroll 3
    for (int a = 0; a < NS; ++a) o.fs[a] = kss * o.us[a];
    if constexpr (kEnergy) {
      const double e_i = 0.5 * kni * un * un + 0.5 * ksi * u2;
      o.energy = intact ? e_i : e_b;
    }
    return o;
  }
};

}  // namespace strata::dem
