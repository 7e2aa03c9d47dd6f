#pragma once
/// Pair laws of the DEM: small stateless kernels (STYLE.md §3).
///
/// A law is a struct of parameters with `inline` member functions; the per-pair state
/// (state byte and accumulated shear displacement) is passed in, so the law itself holds
/// nothing that changes during a run. The step loop is a template over the law, so there
/// is no virtual call per pair.
///
/// How to add a law:
///  1. Write a struct like `SolidLatticeLaw` below with the same member functions
///     (`apply<NS>`, `energy<NS>`, `max_stiffness`), and a `static constexpr const char* kName`.
///  2. Add an entry to `LawKind` and a row to `kLaws` (name + one-line description).
///  3. Add a `case` to the set-up switch in libdem/src/model.cpp (`Model<D>::run`) that
///     instantiates the step loop with the new struct, and a field to `Material` if the law
///     needs parameters the existing fields do not carry.
///  4. Add a unit test in tests/dem/test_bond_law.cpp (single pair, thresholds exact).
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace strata::dem {

/// State byte of a bond or contact: the low two bits are the kind, the others are flags.
namespace pair_state {
inline constexpr std::uint8_t kIntact = 0;         ///< bonded, carries tension and shear
inline constexpr std::uint8_t kBrokenTension = 1;  ///< bond broke in tension: friction only
inline constexpr std::uint8_t kBrokenShear = 2;    ///< bond broke in shear: friction only
inline constexpr std::uint8_t kContact = 3;        ///< never bonded: friction only
inline constexpr std::uint8_t kKindMask = 3;
inline constexpr std::uint8_t kTouching = 4;   ///< broken bond/contact currently in contact
inline constexpr std::uint8_t kSeparated = 8;  ///< broken bond has opened at least once
inline constexpr std::uint8_t kReclosed = 16;  ///< broken bond opened and touches again
}  // namespace pair_state

/// What the law returns for one pair in one step.
template <int NS>
struct PairOutcome {
  double fn = 0;    ///< normal force, compression positive (N)
  double fs[NS]{};  ///< shear force components (N), in the frame the caller uses for us
  int broke = 0;    ///< 0: no break this step; 1: tension; 2: shear
};

/// The solid-lattice law of SPEC C1 (Liu, Pollard & Shi 2013, eqs. 1-5).
///  - intact: Fn = Kn·Un (Un = ri + rj - |xj - xi|, compression positive);
///    Fs = Ks·Us with Us accumulated from tangential displacement increments;
///    breaks in tension when Fn < -Fn_max, in shear when |Fs| > Fs0 (default) or
///    |Fs| > Fs0 + mu·max(Fn, 0) (`friction_strengthens_bonds`);
///  - broken bond or contact: no tension (Un <= 0: open, zero force, Us reset to 0);
///    touching: Fn = Kn·Un, |Fs| <= mu·Fn (Coulomb slip: Us is scaled back).
struct SolidLatticeLaw {
  static constexpr const char* kName = "solid_lattice";
  double kn = 0, ks = 0, mu = 0, fn_max = 0, fs0 = 0;
  bool friction_strengthens_bonds = false;

  /// Shear strength of an intact bond carrying normal force fn.
  inline double intact_shear_limit(double fn) const {
    return friction_strengthens_bonds ? fs0 + mu * std::max(fn, 0.0) : fs0;
  }

  /// Advances one pair by one step: `st` state byte, `un` normal overlap now, `us` the NS
  /// shear displacement components (already rotated into the current tangent plane by the
  /// caller), `dus` this step's tangential displacement increment.
  template <int NS>
  inline PairOutcome<NS> apply(std::uint8_t& st, double un, double* us, const double* dus) const {
    using namespace pair_state;
    PairOutcome<NS> o;
    bool added = false;
    if ((st & kKindMask) == kIntact) [[likely]] {
      double fs2 = 0;
      for (int a = 0; a < NS; ++a) {
        us[a] += dus[a];
        fs2 += us[a] * us[a];
      }
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
      added = true;
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
    for (int a = 0; a < NS; ++a) {
      if (!added) us[a] += dus[a];
      fs2 += us[a] * us[a];
    }
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

  /// Largest of the pair's stiffnesses (N/m), for time-step bounds.
  inline double max_stiffness() const { return std::max(kn, ks); }
};

/// The registry of pair laws (see the header comment for how to add one).
enum class LawKind { SolidLattice };
struct LawInfo {
  LawKind kind;
  const char* name;
  const char* description;
};
inline constexpr LawInfo kLaws[] = {
    {LawKind::SolidLattice, SolidLatticeLaw::kName,
     "solid-lattice bonds (Liu et al. 2013): linear normal/shear springs, tension and shear "
     "breakage, Coulomb friction after breaking"},
};

}  // namespace strata::dem
