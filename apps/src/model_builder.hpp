#pragma once
/// Builds a DEM model from a validated scene: regions filled with lattices, groups,
/// boundary conditions, loads and walls. Nothing is written to disk here.
#include <strata/dem/simulation.hpp>

#include <map>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace strata::app {

/// One particle region as built.
struct RegionInfo {
  std::string name;
  std::string lattice;  ///< "hex", "hcp" or "fcc"
  std::size_t particles = 0;
  double diameter = 0;
  double measure = 0;  ///< area (2D) or volume (3D) of the shape
  double packing = 0;  ///< particle area/volume over the shape's
};

/// Axial stress and strain between two platen groups (SPEC C1): compression positive.
struct PlatenProbe {
  bool enabled = false;
  std::string top, bottom;
  int axis = 1;
  double length0 = 0;  ///< initial distance between the platens' outer faces (m)
  double area = 0;     ///< loaded cross-section: width × thickness (2D) or area (3D), m²
  double radius = 0;   ///< particle radius of the platen rows
};

/// A model ready to run: the simulation (initialised, dt set) and what the reports need.
struct BuiltModel {
  int dim = 2;
  dem::Simulation sim;
  std::vector<RegionInfo> regions;
  std::map<std::string, std::size_t> groups;  ///< group name -> particle count
  double dt_crit = 0;
  double dt = 0;
  bool dt_automatic = false;
  std::int64_t steps = 0;
  double build_seconds = 0;
  PlatenProbe platens;
};

/// Builds and initialises the model. Throws strata::Error: Input (exit 2) for scenes that
/// cannot be built, including dt > dt_crit unless allowed (`force` or solver.allow_unstable).
BuiltModel build_model(const scene::Scene& sc, bool force);

/// Axial strain and stress between the platens at the simulation's current state.
struct AxialState {
  double strain = 0, stress = 0, force_top = 0, force_bottom = 0;
};
AxialState axial_state(const BuiltModel& m);

}  // namespace strata::app
