#pragma once
/// What every pair law shares: the state byte of a pair, the outcome of the reference
/// kernel, and the bond as the batch form of the bond pass sees it (see laws.hpp).
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

/// What the reference kernel (`apply`) returns for one pair in one step.
template <int NS>
struct PairOutcome {
  double fn = 0;    ///< normal force, compression positive (N)
  double fs[NS]{};  ///< shear force components (N), in the frame the caller uses for us
  int broke = 0;    ///< 0: no break this step; 1: tension; 2: shear
};

/// Stiffnesses of a pair law (N/m): the largest normal and shear tangent stiffness a pair
/// can show, for the critical time step and its bounds.
struct PairStiffness {
  double kn = 0;
  double ks = 0;
};

/// The law of one intact bond given as data (Simulation::set_bonds): stiffnesses scaled by
/// its stiffness factor kf (`Law::scaled`) and, for a law with strengths to scale (a member
/// `strengthened`), strengths by its strength factor sf. A factor of 1 changes no bit.
template <class Law>
Law bond_law(const Law& law, double kf, double sf) {
  if constexpr (requires { law.strengthened(sf); })
    return law.scaled(kf).strengthened(sf);
  else
    return law.scaled(kf);
}

/// One bond as the batch form (`lane`) sees it: the bond pass has done the geometry.
template <int NS>
struct BondLane {
  std::int64_t st = 0;  ///< state byte, widened to 64 bits (vector lanes of doubles)
  double un = 0;        ///< normal overlap Un (m), compression positive
  double us[NS]{};      ///< stored Us plus this step's increment, turned into the current tangent plane
  double u2 = 0;        ///< |us|², summed over the components in order
  double kf = 1;        ///< stiffness factor of an intact bond given as data (1 otherwise)
  double sf = 1;        ///< strength factor of an intact bond given as data (1 otherwise)
};

/// What the batch form returns for one bond.
template <int NS>
struct BondLaneResult {
  double fn = 0;        ///< normal force (N), compression positive
  double fs[NS]{};      ///< shear force components (N)
  double us[NS]{};      ///< the bond's new Us
  std::int64_t st = 0;  ///< the bond's new state byte
  /// false: this bond needs the reference kernel (e.g. it breaks in this step); the bond
  /// pass then keeps its stored state and redoes it with `apply`.
  bool done = true;
  double energy = 0;  ///< stored energy (J), when asked for
};

}  // namespace strata::dem
