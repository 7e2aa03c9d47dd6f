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

/// Mass of a particle of diameter d filling its site of the lattice: ρ·(√3/2)·d² in 2D (ρ per
/// unit thickness, the hexagonal cell), ρ·d³/√2 in 3D (the close-packed cell).
inline double lattice_particle_mass(int dim, double density, double d) {
  return density * (dim == 2 ? std::numbers::sqrt3 / 2 * d * d : d * d * d / std::numbers::sqrt2);
}

/// Bond stiffnesses of a lattice.
struct LatticeSprings {
  double kn = 0, ks = 0;  ///< N/m
};

/// The inverse of hex_elastic: the Kn and Ks that give a 2D hexagonal lattice E·t (N/m) and
/// ν, from Ks/Kn = (1−3ν)/(1+ν) and Kn = E·t·(3+Ks/Kn)/(2√3·(1+Ks/Kn)). Needs −1 < ν ≤ 1/3.
inline LatticeSprings hex_springs(double e_t, double nu) {
  const double r = (1 - 3 * nu) / (1 + nu);
  const double kn = e_t * (3 + r) / (2 * std::numbers::sqrt3 * (1 + r));
  return {kn, r * kn};
}

/// The inverse of close_packed_stacking_axis_elastic: the Kn and Ks that give a close packing
/// of diameter d the E (Pa) and ν along its stacking axis, from Ks/Kn = (1−5ν)/(1+ν) and
/// Kn = E·d·(5+Ks/Kn)/(6√2·(1+Ks/Kn)). Needs −1 < ν ≤ 1/5.
inline LatticeSprings close_packed_stacking_axis_springs(double e, double nu, double d) {
  const double r = (1 - 5 * nu) / (1 + nu);
  const double kn = e * d * (5 + r) / (6 * std::numbers::sqrt2 * (1 + r));
  return {kn, r * kn};
}

}  // namespace strata::dem
