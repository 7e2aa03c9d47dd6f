#pragma once
// Internal: the pieces of the model builder that its files share (model.cpp builds the
// particles, fem_model.cpp the FEM side and the coupling).
#include <strata/dem/simulation.hpp>
#include <strata/scene/model.hpp>
#include <strata/scene/scene.hpp>

#include <array>
#include <string>
#include <vector>

namespace strata::scene {

inline int axis_index(const std::string& a) { return a == "x" ? 0 : a == "y" ? 1 : 2; }

inline unsigned axes_mask(const std::vector<std::string>& axes, int dim) {
  unsigned m = 0;
  for (const auto& a : axes) m |= 1u << axis_index(a);
  return m & (dim == 2 ? dem::kXY : dem::kXYZ);
}

inline std::array<double, 3> vec3(const std::vector<double>& v) {
  std::array<double, 3> out{0, 0, 0};
  for (std::size_t a = 0; a < v.size() && a < 3; ++a) out[a] = v[a];
  return out;
}

/// The DEM settings of a scene's [solver] (dt as given; allow_unstable with `force`).
dem::Settings dem_settings(const Scene& sc, bool force);

/// Adds the described particles to `sim` with their materials, groups, bonds, boundary
/// conditions, loads and walls (those on particle groups), and records regions and groups
/// in `m`. `d` gives up its eccentric bond lists.
void populate_particles(const Scene& sc, ModelDescription& d, dem::Simulation& sim, BuiltModel& m);

/// Steps of dt that cover `seconds` (rounded up, a round-off short of a whole step ignored).
std::int64_t steps_in(double seconds, double dt);

/// solver.steps, or solver.duration / dt, rounded up to a multiple of `quantum`.
std::int64_t step_count_of(const SolverTable& solver, double dt, int quantum);

/// The FEM integrator of solver.fem_integrator at the FEM step `dt_fem`: auto is central
/// difference up to the explicit limit and implicit Newmark above it.
fem::Scheme scheme_of(const SolverTable& solver, double dt_fem, double explicit_limit);

/// A network scene ([network]): its FEM part and particle part coupled (network_model.cpp).
BuiltModel build_network_model(const Scene& sc, bool force);

/// A model with FEM regions: FEM alone, or coupled with the particle regions through the
/// overlap layers (fem_model.cpp).
BuiltModel build_fem_model(const Scene& sc, bool force);

}  // namespace strata::scene
