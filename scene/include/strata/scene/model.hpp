#pragma once
/// Builds a model from a validated scene in two steps: describe_model fills the regions
/// (lattices, eccentric offsets, groups, FEM meshes) into a ModelDescription that holds
/// little more than the particles themselves; build_model turns a description into a DEM
/// model with boundary conditions, loads and walls. `strata mesh` uses the description
/// only. Nothing is written to disk here.
#include <strata/couple/coupler.hpp>
#include <strata/couple/dem_partition.hpp>
#include <strata/couple/fem_partition.hpp>
#include <strata/couple/spring_partition.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/ecc.hpp>
#include <strata/preprocess/lattice.hpp>
#include <strata/preprocess/mesh.hpp>
#include <strata/preprocess/overlap.hpp>

#include <map>
#include <memory>
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
  double measure = 0;      ///< area (2D) or volume (3D) of the shape
  double packing = 0;      ///< particle area/volume over the shape's
  std::string material;    ///< its [[material]]
  bool eccentric = false;  ///< centroids offset (the regular lattice's elastic constants do not hold)
  /// Eccentric regions: the bonds (the regular lattice's pairs), those weakened by γ (longer
  /// than Rc·L_max) and L_max, the longest bond (m).
  std::size_t bonds = 0, weakened_bonds = 0;
  double longest_bond = 0;
};

/// The particles of one region as filled: sites in id order (ids first_id, first_id + 1,
/// ...), eccentric offsets applied; rows and layers are dropped once groups are selected.
struct RegionSites {
  preprocess::Lattice sites;
  std::uint32_t first_id = 0;
  std::string material;
  bool eccentric = false;
  preprocess::BondList bonds;  ///< eccentric regions only: regular-lattice pairs, local indices
  /// A spread of bond strengths ([[region]] strength_spread): the distribution, its
  /// coefficient of variation and the seed its factors are drawn from.
  StrengthSpread strength_spread = StrengthSpread::None;
  double strength_cov = 0;
  std::uint64_t strength_seed = 0;
};

/// Strength factors of `count` bonds, drawn in order: mean 1, coefficient of variation
/// `cov`, normal (redrawn below 1e-3) or Weibull (modulus from cov), reproducible from `seed`.
std::vector<double> strength_factors(StrengthSpread spread, double cov, std::size_t count,
                                     std::uint64_t seed);

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
  /// A coupled model: the particle id of each particle of the overlap model (its particle
  /// regions, then the band of DEM external particles, region "overlap").
  std::vector<std::uint32_t> overlap_particle_id;

  std::size_t particle_count() const;
  std::size_t fem_nodes() const;
  std::size_t fem_elements() const;
  /// The regions' sites, in id order (global index = particle id).
  std::vector<const preprocess::Lattice*> lattices() const;
};

/// Fills the scene's regions. FEM regions (kind = "fem") are meshed when `allow_fem`, and
/// refused (Error Input, at the region's `kind`) otherwise. With `coupled` (the overlap model
/// of the scene's particle and FEM regions) the particle regions take their particles from
/// it, the band of DEM external particles becomes region "overlap", and FEM regions are not
/// meshed again.
ModelDescription describe_model(const scene::Scene& sc, bool allow_fem,
                                const preprocess::OverlapModel* coupled = nullptr);

/// Bond counts of the model build_model would make, by length class (classes 0.02·d_ref
/// wide, d_ref = the first region's diameter), without storing the bonds of regular
/// regions (preprocess::count_touching_pairs); eccentric regions count their BondList.
preprocess::PairCounts count_bonds(const ModelDescription& d);

/// Ids of the particles with fewer bonds than a particle inside the lattice (6 in 2D, 12
/// in 3D): the surface of the model, as FrameSelection::find_surface finds it on a model.
std::vector<std::uint32_t> surface_particles(const ModelDescription& d);

/// Axial stress and strain between two platen groups: compression positive.
struct PlatenProbe {
  bool enabled = false;
  std::string top, bottom;
  int axis = 1;
  double length0 = 0;  ///< initial distance between the platens' outer faces (m)
  double area = 0;     ///< loaded cross-section: width × thickness (2D) or area (3D), m²
  double radius = 0;   ///< particle radius of the platen rows
  /// The specimen's free sides, for the lateral strain: along each axis but the loaded one,
  /// the particles (ids) whose centres lie within 0.75 d of the outermost column's centre at
  /// the start, on the low and the high side, platen rows left out.
  struct Sides {
    int axis = 0;
    std::vector<std::uint32_t> low, high;
    double width0 = 0;  ///< distance between the two sides' mean centres at the start (m)
  };
  std::vector<Sides> sides;
};

/// One FEM region as built: its elements are block `block` of the FEM mesh.
struct FemRegionInfo {
  std::string name;
  std::size_t elements = 0;
  double youngs_modulus = 0, poisson_ratio = 0, density = 0;  ///< Pa, -, kg/m^3
};

/// A model ready to run: DEM particles, FEM elements or both coupled through overlap layers,
/// initialised with its time step set, and what the reports need.
///
/// Steps are counted in steps of `dt`: the DEM step of a model with particles, the FEM step
/// of an FEM-only model. A coupled model advances by whole system steps (η DEM steps and one
/// FEM step of η·dt), so its step counts are multiples of η.
struct BuiltModel {
  BuiltModel();
  ~BuiltModel();
  BuiltModel(BuiltModel&&) noexcept;
  BuiltModel& operator=(BuiltModel&&) noexcept;

  int dim = 2;
  std::vector<RegionInfo> regions;                               ///< particle regions
  std::vector<FemRegionInfo> fem_regions;                        ///< FEM regions
  std::map<std::string, std::size_t> groups;                     ///< group name -> particle count
  std::map<std::string, std::vector<std::uint32_t>> fem_groups;  ///< group name -> FEM nodes
  double dt_crit = 0;      ///< the limit dt is checked against (coupled: the DEM side's)
  double fem_dt_crit = 0;  ///< limit of the FEM integrator in use (+inf: implicit)
  double fem_explicit_dt_crit = 0;
  double dt = 0;
  bool dt_automatic = false;
  std::int64_t steps = 0;
  std::int64_t settle_steps = 0;  ///< steps of the settling stage before the run ([solver] settle)
  int eta = 1;                    ///< FEM step / DEM step of a coupled model
  couple::Execution execution_mode = couple::Execution::Serial;
  double build_seconds = 0;
  PlatenProbe platens;
  std::size_t overlap_particles = 0, overlap_nodes = 0;  ///< externals of the coupling (each side)

  bool has_particles() const { return dem_ != nullptr || dem_partition_ != nullptr; }
  bool has_fem() const { return fem_partition_ != nullptr; }
  /// A network scene ([network]): its particle part is a spring network (network()), its FEM
  /// part spring elements; it has no particles and no FEM regions.
  bool has_network() const { return network_ != nullptr; }
  bool coupled() const { return coupler_ != nullptr; }
  /// The particles (has_particles()).
  dem::Simulation& sim();
  const dem::Simulation& sim() const;
  /// The coupler of particles and FEM (coupled()): its observers see every FEM step and
  /// every DEM step.
  couple::Coupler& coupler();
  const couple::Coupler& coupler() const;
  /// The particle part of a network scene (has_network()).
  couple::SpringNetworkPartition& network();
  const couple::SpringNetworkPartition& network() const;
  /// A probe node of a network scene, read on the part that computes it.
  struct NetworkProbe {
    std::int64_t node = 0;
    bool fem = false;     ///< read on the FEM part (else on the particle part)
    std::size_t dof = 0;  ///< its degree of freedom there
  };
  std::vector<NetworkProbe> network_probes;
  /// Displacement and velocity of a probe node now.
  std::pair<double, double> network_probe(const NetworkProbe& p) const;
  /// The FEM solver (has_fem()).
  fem::Solver& fem();
  const fem::Solver& fem() const;
  /// Integrator of the FEM side in words ("" without FEM).
  std::string fem_integrator() const;
  /// "serial" or "parallel" (coupled models).
  std::string execution() const;

  /// Steps done (in steps of dt) and the simulated time.
  std::int64_t step_count() const;
  double time() const;
  /// Advances `steps` steps of dt (coupled: a multiple of eta).
  void advance(std::int64_t steps);
  /// Last step whose state passed the health checks of every part.
  std::int64_t last_good_step() const;
  /// The coupled model's own health check, besides each part's: the energy of particles and
  /// FEM together may not exceed 10 × (its value at the start + the work of loads and
  /// boundary conditions), the work passed between the parts left out (inside one part it
  /// counts as work, so a runaway exchange would raise that part's allowance with it), and
  /// the work of loads and boundaries taken with its sign (the growing swings of a reaction
  /// do no net work, but summed as |work| they would raise the allowance too).
  /// advance() runs it every kCoupledCheckEvery system steps and at its end; throws
  /// strata::Error (Numerical) on failure. take_initial_energy() records the start (once;
  /// before a restart's state is loaded, so a continued run checks against the same start).
  void check_coupled_energy();
  void take_initial_energy();
  static constexpr std::int64_t kCoupledCheckEvery = 50;
  /// A hash of the whole state (particles, bonds, FEM displacements and velocities).
  std::uint64_t state_hash() const;

  double coupled_energy0 = -1;         ///< energy at the start (J); < 0: not taken yet
  std::int64_t coupled_last_good = 0;  ///< last step that passed check_coupled_energy()

  // The parts (set by build_model).
  std::unique_ptr<dem::Simulation> dem_;
  std::unique_ptr<couple::DemPartition> dem_partition_;
  std::unique_ptr<couple::FemPartition> fem_partition_;
  std::unique_ptr<couple::SpringNetworkPartition> network_;
  std::unique_ptr<couple::Coupler> coupler_;
};

/// Builds and initialises the model: particle regions, FEM regions, and the overlap layers
/// where a particle region meets an FEM region of the same geometry file. Throws
/// strata::Error: Input (exit 2, at the scene key) for keys that need an optional part this
/// build leaves out (require_build_parts, checked first), for scenes that cannot be built, and for
/// dt above the critical step of any part unless allowed (`force` or solver.allow_unstable).
BuiltModel build_model(const scene::Scene& sc, bool force);

/// Axial strain and stress between the platens at the simulation's current state, and the
/// lateral strain of the free sides (positive in expansion; in 3D the mean of both lateral
/// axes).
struct AxialState {
  double strain = 0, stress = 0, force_top = 0, force_bottom = 0;
  double lateral_strain = 0;
};
AxialState axial_state(const BuiltModel& m);

}  // namespace strata::scene
