#pragma once
/// Builds a model from a validated scene in two steps: describe_model fills the regions
/// (lattices, eccentric offsets, groups, FEM meshes) into a ModelDescription that holds
/// little more than the particles themselves; build_model turns a description into a DEM
/// model with boundary conditions, loads and walls. `strata mesh` uses the description
/// only. Nothing is written to disk here.
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/ecc.hpp>
#include <strata/preprocess/lattice.hpp>
#include <strata/preprocess/mesh.hpp>

#include <map>
#include <string>
#include <vector>

#include <strata/scene/scene.hpp>

namespace strata::scene {

/// One particle region as built.
struct RegionInfo {
  std::string name;
  std::string lattice;  ///< "hex", "hcp" or "fcc"
  std::size_t particles = 0;
  double diameter = 0;
  double measure = 0;  ///< area (2D) or volume (3D) of the shape
  double packing = 0;  ///< particle area/volume over the shape's
};

/// The particles of one region as filled: sites in id order (ids first_id, first_id + 1,
/// ...), eccentric offsets applied; rows and layers are dropped once groups are selected.
struct RegionSites {
  preprocess::Lattice sites;
  std::uint32_t first_id = 0;
  std::string material;
  bool eccentric = false;
  preprocess::BondList bonds;  ///< eccentric regions only: regular-lattice pairs, local indices
};

/// One FEM region meshed (kind = "fem"): triangles (2D) or tetrahedra (3D).
struct FemRegion {
  std::string name;
  std::string material;
  preprocess::SimplexMesh mesh;
};

/// A scene's regions filled, without the DEM: what `strata mesh` reports and writes, and
/// what build_model builds the simulation from.
struct ModelDescription {
  int dim = 2;
  std::vector<RegionInfo> regions;  ///< particle regions, in scene order
  std::vector<RegionSites> sites;   ///< one per particle region
  /// Groups in the order they are made (each region, then each [[group]]): name and ids.
  /// A region's own group holds its ids [first_id, first_id + particles) and lists none.
  struct Group {
    std::string name;
    std::size_t count = 0;
    std::vector<std::uint32_t> ids;  ///< empty for a region's own group
    int region = -1;                 ///< the region whose own group this is, else -1
  };
  std::vector<Group> groups;
  std::vector<FemRegion> fem;
  /// True when every particle region is regular: the model's bonds are all touching pairs
  /// of all regions together; otherwise each region is bonded within itself.
  bool bonds_across_regions = true;
  double seconds = 0;  ///< time to fill

  std::size_t particle_count() const;
  std::size_t fem_nodes() const;
  std::size_t fem_elements() const;
  /// The regions' sites, in id order (global index = particle id).
  std::vector<const preprocess::Lattice*> lattices() const;
};

/// Fills the scene's regions. FEM regions (kind = "fem") are meshed when `allow_fem`, and
/// refused (Error Input, at the region's `kind`) otherwise.
ModelDescription describe_model(const scene::Scene& sc, bool allow_fem);

/// Bond counts of the model build_model would make, by length class (classes 0.02·d_ref
/// wide, d_ref = the first region's diameter), without storing the bonds of regular
/// regions (preprocess::count_touching_pairs); eccentric regions count their BondList.
preprocess::PairCounts count_bonds(const ModelDescription& d);

/// Ids of the particles with fewer bonds than a particle inside the lattice (6 in 2D, 12
/// in 3D): the surface of the model, as FrameSelection::find_surface finds it on a model.
std::vector<std::uint32_t> surface_particles(const ModelDescription& d);

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
/// cannot be built, including FEM regions (runs of FEM regions go through [coupled] scenes
/// and `strata report wave`) and dt > dt_crit unless allowed (`force` or
/// solver.allow_unstable).
BuiltModel build_model(const scene::Scene& sc, bool force);

/// Axial strain and stress between the platens at the simulation's current state.
struct AxialState {
  double strain = 0, stress = 0, force_top = 0, force_bottom = 0;
};
AxialState axial_state(const BuiltModel& m);

}  // namespace strata::scene
