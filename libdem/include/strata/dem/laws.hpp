#pragma once
/// Pair laws of the DEM and their registry.
///
/// A law is a small stateless struct: its parameters, with `inline` member functions; the
/// per-pair state (state byte and shear displacement Us) is passed in, so nothing in the
/// law changes during a run. The model picks its law once, when it is set up, by the name
/// that Material::law holds (the scene's `law` key); the step loop is a template over the
/// law (detail/step_kernel.hpp), so there is no virtual call per pair.
///
/// What a law provides (the concept PairLaw below checks it; laws/solid_lattice.hpp is the
/// worked example):
///  - `kName` (the name materials use) and `kDescription` (one line);
///  - `static Law from_material(const Material&)`: the law of a pair of that material (for
///    two materials the model passes their combined material: harmonic-mean stiffnesses,
///    smaller friction and strengths, see docs/dem.md);
///  - `Law scaled(double f) const`: the law with its stiffnesses times f (intact bonds of
///    eccentric lattices); `PairStiffness stiffness() const` (critical time step; a law
///    whose shear stiffness `ks` is zero for every pair of the model must give a shear
///    force of zero, and take its verdict and energy from Un alone, whatever Us holds: such
///    a model keeps no shear history, and its bond pass passes Us = 0 without computing the
///    shear increment);
///  - the reference kernel `template <int NS> PairOutcome<NS> apply(st, un, us, dus) const`
///    and `template <int NS> double energy(st, un, us) const`, NS = 1 in 2D, 3 in 3D; it
///    handles every kind of pair (intact and broken bonds, never-bonded contacts). `us`
///    arrives as the stored shear displacement plus this step's increment, turned into the
///    current tangent plane (as the batch form's BondLane::us); `dus` is the increment
///    alone, for a law that needs it (a law that forgets Us sets `us` to zero);
///  - optionally the batch form `template <int NS, bool kBroken, bool kEnergy>
///    BondLaneResult<NS> lane(const BondLane<NS>&) const` for the bond pass: `apply` and
///    `energy` for one bond without branches (selects), giving the same bits; without it
///    every bond takes `apply` (correct, slower). Check that the bond pass still vectorises
///    (GCC: -fopt-info-vec on libdem/src/step.cpp); `#pragma GCC unroll` on its loops over
///    the NS components helps;
///  - optionally `static constexpr bool kOpenIsInert = true` where a broken bond that is
///    open (not touching) carries nothing and keeps Us = 0 and its state until it touches
///    again: the bond pass then takes chunks whose broken bonds are all open through the
///    intact form (bond_pass.hpp).
///
/// How to add a law to strata:
///  1. Write libdem/include/strata/dem/laws/<name>.hpp with the struct (copy
///     laws/solid_lattice.hpp); cite the source of its equations.
///  2. Include it below and add the struct to `BuiltinLaws` (one row); libdem then compiles
///     the step kernel for it (libdem/src/step.cpp) and `kLaws` lists it.
///  3. If it needs parameters Material does not carry, add fields to Material
///     (material.hpp), to the checkpoint (libdem/src/state.cpp) and to the scene schema.
///  4. Run test_dem: tests/dem/test_law_conformance.cpp checks the batch form against the
///     reference kernel for every row; add single-pair tests of its thresholds next to
///     tests/dem/test_bond_law.cpp and a section to docs/dem.md.
/// A program can also add a law of its own without changing strata: register_law<Law>()
/// (register_law.hpp) compiles the step kernel for it in the program.
#include <strata/dem/laws/common.hpp>
#include <strata/dem/laws/solid_lattice.hpp>
#include <strata/dem/material.hpp>

#include <array>
#include <concepts>
#include <cstdint>
#include <vector>

namespace strata::dem {

/// What the model needs of a pair law (see the header comment).
template <class L>
concept PairLaw = requires(const L& l, const Material& m, std::uint8_t& st, double un, double* us,
                           const double* dus) {
  { L::kName } -> std::convertible_to<const char*>;
  { L::kDescription } -> std::convertible_to<const char*>;
  { L::from_material(m) } -> std::same_as<L>;
  { l.scaled(1.0) } -> std::same_as<L>;
  { l.stiffness() } -> std::same_as<PairStiffness>;
  { l.template apply<1>(st, un, us, dus) } -> std::same_as<PairOutcome<1>>;
  { l.template apply<3>(st, un, us, dus) } -> std::same_as<PairOutcome<3>>;
  { l.template energy<1>(st, un, us) } -> std::same_as<double>;
  { l.template energy<3>(st, un, us) } -> std::same_as<double>;
};

/// A list of law types.
template <PairLaw... L>
struct LawList {};

/// The registry: the laws built into strata, one row each.
using BuiltinLaws = LawList<SolidLatticeLaw>;

/// Name and description of a law.
struct LawInfo {
  const char* name;
  const char* description;
};

namespace detail {
template <class... L>
constexpr std::array<LawInfo, sizeof...(L)> law_table(LawList<L...>) {
  return {LawInfo{L::kName, L::kDescription}...};
}
}  // namespace detail

/// The built-in laws (from BuiltinLaws), in order.
inline constexpr auto kLaws = detail::law_table(BuiltinLaws{});

/// Every law a Material may name: the built-in ones, then those added with register_law().
std::vector<LawInfo> available_laws();

}  // namespace strata::dem
