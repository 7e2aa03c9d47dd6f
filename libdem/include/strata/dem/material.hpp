#pragma once
/// Material of DEM particles: density and the parameters of the pair law.
#include <limits>
#include <string>

namespace strata::dem {

/// Material of a particle; bonds and contacts between two materials use the pair rule in
/// docs/dem.md (series stiffness, weaker strength, smaller friction).
struct Material {
  double density = 0;   ///< kg/m² in 2D (per unit thickness), kg/m³ in 3D
  double kn = 0;        ///< normal stiffness Kn (N/m)
  double ks = 0;        ///< shear stiffness Ks (N/m)
  double friction = 0;  ///< friction coefficient μ of broken bonds and contacts
  double tensile_strength = std::numeric_limits<double>::infinity();  ///< Fn_max (N)
  double shear_strength = std::numeric_limits<double>::infinity();    ///< Fs0 (N)
  /// true (default, criterion (5) of Liu, Pollard & Shi 2013): an intact bond breaks in
  /// shear when |Fs| > Fs0 + μ·max(Fn, 0); false: when |Fs| > Fs0. With the rock of
  /// liu2013_rock() true gives the published curve (peak strain 3.06e-3 against 2.8e-3;
  /// false: 1.80e-3).
  bool friction_strengthens_bonds = true;
  /// Pair law by name: a row of kLaws (laws.hpp) or a law added with register_law()
  /// (register_law.hpp). All materials of one model must name the same law.
  std::string law = "solid_lattice";
};

}  // namespace strata::dem
