#pragma once
/// Published parameter sets, for examples, tests and benchmarks.
#include <strata/dem/simulation.hpp>

namespace strata::dem {

/// The rock of Liu, Pollard & Shi (2013) for 1 mm disks:
/// Kn = 6.587e10 N/m, Ks = 2.371e10 N/m, μ = 0.239, ρ = 2.65e3 kg/m² (per unit thickness;
/// used as kg/m³ in 3D), Fn_max = 1.252e4 N, Fs0 = 3.690e4 N, default shear criterion.
inline Material liu2013_rock() {
  Material m;
  m.density = 2.65e3;
  m.kn = 6.587e10;
  m.ks = 2.371e10;
  m.friction = 0.239;
  m.tensile_strength = 1.252e4;
  m.shear_strength = 3.690e4;
  return m;
}

}  // namespace strata::dem
