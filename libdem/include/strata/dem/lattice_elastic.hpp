#pragma once
/// Elastic constants of regular lattices of equal particles bonded to their touching
/// neighbours by normal and shear springs Kn and Ks (the elastic part of the solid-lattice
/// law), from the homogenisation of the bonds' energy under a uniform strain (Liu, Pollard &
/// Shi 2013; see docs/dem.md). A finite block approaches them as 1/n with its size n in
/// particles (its surface bonds are fewer); eccentric offsets and weakened bonds lower E.
#include <numbers>

namespace strata::dem {

/// Young's modulus and Poisson's ratio of a lattice.
struct LatticeElastic {
  double E = 0;   ///< Pa in 3D; N/m in 2D (E times the thickness: the 2D lattice is per unit thickness)
  double nu = 0;  ///< Poisson's ratio
};

/// 2D hexagonal lattice (isotropic, plane stress): E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks) and
/// ν = (Kn−Ks)/(3Kn+Ks), at most 1/3 (Ks = 0).
inline LatticeElastic hex_elastic(double kn, double ks) {
  return {2 * std::numbers::sqrt3 * kn * (kn + ks) / (3 * kn + ks), (kn - ks) / (3 * kn + ks)};
}

/// 3D close packing of spheres of diameter d (volume d³/√2 per sphere) loaded along its
/// stacking axis, z in strata's lattices (the HCP c-axis, FCC [111]):
/// E = 6√2·Kn(Kn+Ks)/(d(5Kn+Ks)), ν = (Kn−Ks)/(5Kn+Ks).
inline LatticeElastic close_packed_stacking_axis_elastic(double kn, double ks, double d) {
  return {6 * std::numbers::sqrt2 * kn * (kn + ks) / (d * (5 * kn + ks)), (kn - ks) / (5 * kn + ks)};
}

/// FCC loaded along a cube axis [100] (not an axis of strata's FCC lattices, whose z is
/// [111]): E = 2√2·Kn(Kn+3Ks)/(d(3Kn+Ks)), ν = (Kn−Ks)/(3Kn+Ks).
inline LatticeElastic fcc_cube_axis_elastic(double kn, double ks, double d) {
  return {2 * std::numbers::sqrt2 * kn * (kn + 3 * ks) / (d * (3 * kn + ks)), (kn - ks) / (3 * kn + ks)};
}

/// Isotropic (Voigt) average of the close-packed lattices: E = 2√2·Kn(2Kn+3Ks)/(d(4Kn+Ks)),
/// ν = (Kn−Ks)/(4Kn+Ks), at most 1/4 (Ks = 0).
inline LatticeElastic close_packed_isotropic_elastic(double kn, double ks, double d) {
  return {2 * std::numbers::sqrt2 * kn * (2 * kn + 3 * ks) / (d * (4 * kn + ks)), (kn - ks) / (4 * kn + ks)};
}

}  // namespace strata::dem
