#pragma once
/// The typed description of a scene: one struct per table of the scene file.
///
/// The loader (scene.hpp: load, parse) validates a scene file against the schema and turns
/// each table into its struct here; the keys of a table are declared, and read into its
/// struct, in one file (scene/src/tables/). Everything after the loader reads these fields,
/// never keys by name. Every field is a Located<T>: its value, where it was written (for
/// messages that point at the scene line) and whether the user wrote it. A key with a
/// default always has a value (given = false when defaulted); a key without one has
/// given = false and a value-initialised T when the scene leaves it out.
#include <strata/core/error.hpp>
#include <strata/core/ramp.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace strata::scene {

/// Where a value came from: a position in a scene file, or a `--set` override.
struct SourcePos {
  std::string file;     ///< scene file path as given, or "--set" for overrides
  int line = 0;         ///< 1-based; 0 when unknown
  int column = 0;       ///< 1-based; 0 when unknown
  std::string setting;  ///< for overrides: the "key=value" text as given to `--set`
  /// "scene.toml:42:17" (or "--set solver.dt=1" for an override)
  std::string str() const;
};

/// An error that names its place in a scene file ("file:line:col: message").
class SceneError : public Error {
 public:
  using Error::Error;
};

/// Throws an Input error "file:line:col: message" pointing at `pos` (a SceneError).
[[noreturn]] void fail_at(const SourcePos& pos, const std::string& message);

/// Runs f(). An Input or Unsupported error it throws that names no place in the scene gets
/// `pos` in front: what a key names (a geometry file, a physical group, a shape, a density)
/// is where an error of building from it comes from.
template <class F>
decltype(auto) blame_at(const SourcePos& pos, F&& f) {
  try {
    return std::forward<F>(f)();
  } catch (const SceneError&) {
    throw;
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Input && e.kind() != ErrorKind::Unsupported) throw;
    throw SceneError(e.kind(), pos.str() + ": " + e.what());
  }
}

/// A value of a scene key with its position: where the value was written, or the table's
/// header when the key was defaulted or left out.
template <class T>
struct Located {
  T value{};           ///< as written, or the declared default
  SourcePos pos;       ///< the value's position, or the table header's when not written
  bool given = false;  ///< the user wrote the key (in the file or with `--set`)

  operator const T&() const { return value; }  // NOLINT: reads as the value on purpose
  const T& operator*() const { return value; }
  const T* operator->() const { return &value; }
  /// Throws an Input error "file:line:col: message" pointing at this value.
  [[noreturn]] void fail(const std::string& message) const { fail_at(pos, message); }
  /// blame_at(pos, f): an unlocated Input error of f() points at this key.
  template <class F>
  decltype(auto) blame(F&& f) const {
    return blame_at(pos, std::forward<F>(f));
  }

  /// `region.name == "rock"`, `boundary.group != name` (numbers and enums compare through
  /// the conversion above).
  friend bool operator==(const Located& a,
                         const T& b) requires(!std::is_arithmetic_v<T> && !std::is_enum_v<T>) {
    return a.value == b;
  }
};

// ---- choices ---------------------------------------------------------------------------------

/// [[region]] kind: bonded particles or finite elements.
enum class RegionKind { Particles, Fem };
/// [[region]] shape: what the region fills.
enum class RegionShape { Box, Disk, Sphere, Cylinder, Polygon, File };
/// [[region]] eccentricity (ECC4D, Zhao et al. 2021): none, Type A (cube) or Type B (sphere).
enum class RegionEccentricity { None, Cube, Sphere };
/// [[region]] strength_spread: bond strengths all alike, or drawn per bond.
enum class StrengthSpread { None, Normal, Weibull };
/// [[region]] unit: the length unit of a geometry file's coordinates.
enum class LengthUnit { Metre, Centimetre, Millimetre, Kilometre };
/// Metres in one `unit`.
double metres(LengthUnit unit);
/// [[group]] select: which particles (or FEM nodes) of the region a group holds.
enum class GroupSelect {
  All,
  TopRow,
  BottomRow,
  LeftColumn,
  RightColumn,
  TopLayer,
  BottomLayer,
  Box,
  Physical,
  HoleRim,
};
/// [[boundary]] type: held, moved at a velocity, or moved in steps.
enum class BoundaryType { Fixed, Velocity, StepDisplacement };
/// [[load]] per: the force acts on each particle (or FEM node), is shared by the group, or
/// is a traction spread over the boundary of the group's FEM nodes.
enum class LoadPer { Particle, Group, Boundary };
/// [[load]] type: force vectors, or magnitudes pushing away from a centre.
enum class LoadType { ForceHistory, Radial };
/// [solver] damping.
enum class SolverDamping { None, Viscous, Local };
/// [solver] contact_detection.
enum class ContactDetection { Auto, On, Off };
/// [solver] coupling: how a model with particle and FEM regions runs its two sides.
enum class SolverCoupling { Serial, Parallel };

/// The words of the scene file for a choice ("hole_rim" for GroupSelect::HoleRim).
std::string_view to_string(RegionKind v);
std::string_view to_string(RegionShape v);
std::string_view to_string(RegionEccentricity v);
std::string_view to_string(StrengthSpread v);
std::string_view to_string(GroupSelect v);
std::string_view to_string(BoundaryType v);
std::string_view to_string(LoadPer v);
std::string_view to_string(LoadType v);
std::string_view to_string(Ramp v);
std::string_view to_string(SolverDamping v);
std::string_view to_string(ContactDetection v);
std::string_view to_string(SolverCoupling v);

// ---- the tables ------------------------------------------------------------------------------
// Units and meanings are those of docs/scene-reference.md (generated from the same
// declarations); each struct's `pos` is its table header (the file start for a table the
// scene leaves out).

/// [scene]: a title, 2D or 3D, and the random seed.
struct SceneTable {
  SourcePos pos;
  Located<std::string> title;
  Located<int> dimension;     ///< 2 or 3 (0 in a coupled scene, which has no [scene])
  Located<double> thickness;  ///< m, out-of-plane thickness of a 2D model
  Located<std::int64_t> seed;
};

/// [[material]]: a bonded-particle material of the solid-lattice law.
struct MaterialTable {
  SourcePos pos;
  Located<std::string> name;
  Located<std::string> law;
  Located<double> density;           ///< kg/m^2 in 2D, kg/m^3 in 3D
  Located<double> kn, ks;            ///< N/m
  Located<double> friction;          ///< μ
  Located<double> tensile_strength;  ///< N; inf: never breaks in tension
  Located<double> shear_strength;    ///< N; inf: never breaks in shear
  Located<bool> friction_strengthens_bonds;
  Located<double> youngs_modulus;  ///< Pa; optional (given with poisson_ratio)
  Located<double> poisson_ratio;   ///< optional (given with youngs_modulus)
};

/// [[region]]: a lattice of particles or a finite-element mesh filling a shape or a file.
struct RegionTable {
  SourcePos pos;
  Located<std::string> name;
  Located<RegionKind> kind;
  Located<std::string> material;  ///< a [[material]] name
  Located<std::string> lattice;   ///< "auto", "hex", "hcp" or "fcc"
  Located<double> diameter;       ///< m; given for kind = particles
  Located<RegionShape> shape;
  Located<std::vector<double>> origin;               ///< m, one component per axis
  Located<std::vector<double>> size;                 ///< m; given for shape = box
  Located<std::vector<double>> center;               ///< m; given for shape = disk or sphere
  Located<double> radius;                            ///< m; given for shape = disk, sphere or cylinder
  Located<double> height;                            ///< m; given for shape = cylinder (along z)
  Located<std::vector<std::vector<double>>> points;  ///< m, [[x, y], ...]; given for shape = polygon
  Located<std::filesystem::path> file;               ///< given for shape = file
  Located<LengthUnit> unit;                          ///< of the file's coordinates
  Located<double> orientation;                       ///< degrees
  Located<double> mesh_size;                         ///< m; 0: automatic
  Located<std::string> physical;          ///< gmsh physical group of shape = file; empty: the whole geometry
  Located<double> min_boundary_distance;  ///< m
  Located<RegionEccentricity> eccentricity;
  Located<double> ra, rc, gamma;
  Located<StrengthSpread> strength_spread;
  Located<double> strength_cov;  ///< coefficient of variation of the bond strength factors
};

/// [[group]]: a named set of particles (or FEM nodes) picked from a region.
struct GroupTable {
  SourcePos pos;
  Located<std::string> name;
  Located<std::string> region;  ///< a [[region]] name; empty: all regions
  Located<GroupSelect> select;
  Located<std::string> physical;                  ///< for select = physical
  Located<std::int64_t> hole;                     ///< for select = hole_rim, 1-based
  Located<double> width;                          ///< m; 0: one particle diameter
  Located<std::vector<double>> box_min, box_max;  ///< m; given for select = box
};

/// [[boundary]]: a prescribed motion of a group.
struct BoundaryTable {
  SourcePos pos;
  Located<std::string> group;
  Located<BoundaryType> type;
  Located<std::vector<std::string>> axes;  ///< "x", "y", "z": the prescribed components
  Located<std::vector<double>> velocity;   ///< m/s; given for type = velocity
  Located<std::vector<double>> increment;  ///< m; given for type = step_displacement
  Located<std::int64_t> every;             ///< steps between two increments
};

/// [[load]]: a force history applied to a group.
struct LoadTable {
  SourcePos pos;
  Located<std::string> group;
  Located<LoadType> type;
  Located<std::vector<double>> times;                ///< s, increasing
  Located<std::vector<std::vector<double>>> forces;  ///< N, one row per time, one component per axis
  Located<std::vector<double>> magnitudes;           ///< N, one per time (radial)
  Located<std::vector<double>> center;               ///< m (radial; empty: the group's mean position)
  Located<std::vector<double>> axis;                 ///< 3D radial: a borehole's axis (empty: none)
  Located<LoadPer> per;
  Located<Ramp> ramp;  ///< from one listed value to the next
};

/// [[wall]]: a rigid flat wall.
struct WallTable {
  SourcePos pos;
  Located<std::string> name;
  Located<std::vector<double>> point;     ///< m
  Located<std::vector<double>> normal;    ///< into the particles, not zero
  Located<std::vector<double>> velocity;  ///< m/s
  Located<double> stiffness;              ///< N/m; 0: the largest material kn
};

/// [solver]: time stepping and damping.
struct SolverTable {
  SourcePos pos;
  Located<double> dt;  ///< s; 0: dt_safety × dt_crit
  Located<double> dt_safety;
  Located<std::int64_t> steps;  ///< 0: the run lasts `duration`
  Located<double> duration;     ///< s
  Located<double> settle;       ///< s of settling before the run; 0: none
  Located<SolverDamping> damping;
  Located<double> viscous_c;  ///< N·s/m
  Located<double> local_damping;
  Located<std::vector<double>> gravity;  ///< m/s^2
  Located<ContactDetection> contact_detection;
  Located<bool> allow_unstable;
  Located<bool> lattice_slots;
  Located<std::int64_t> threads;  ///< 0: all cores
  Located<std::int64_t> min_particles_per_thread;
  Located<std::string> fem_integrator;  ///< "auto" or a libfem scheme name
  Located<std::int64_t> eta;            ///< FEM step over particle step
  Located<SolverCoupling> coupling;
};

/// [output]: what a run writes, and how often.
struct OutputTable {
  SourcePos pos;
  Located<std::filesystem::path> directory;
  Located<std::int64_t> frames;
  Located<double> frame_every_time;  ///< s
  Located<std::int64_t> frame_every_breaks;
  Located<std::int64_t> checkpoint_every;  ///< steps
  Located<std::int64_t> probe_every;       ///< steps
  Located<bool> vtk, render;
  Located<std::string> render_field;  ///< "displacement", "velocity", "damage", "group", "shear_strain"
  Located<std::vector<std::string>> fields;  ///< per-particle fields of the VTK frames
  Located<bool> movie, render_while_running, render_contacts, render_cracks;
  Located<std::vector<std::int64_t>> render_size;        ///< pixels: width, height
  Located<std::vector<double>> view_direction, view_up;  ///< 3 components each
  Located<std::vector<double>> clip_plane;               ///< [ox, oy, oz, nx, ny, nz]; optional
  Located<std::string> particles;                        ///< "all", "surface" or "none"
  Located<std::vector<std::string>> groups;
  Located<std::vector<double>> slice_point, slice_normal;  ///< one component per axis
  Located<double> slice_thickness;                         ///< m; 0: no slice
  Located<std::string> bonds;                              ///< "broken", "all" or "none"
  Located<bool> contacts;
};

/// [probe]: measurements written as CSV rows during the run.
struct ProbeTable {
  SourcePos pos;
  Located<bool> stress_strain;
  Located<std::string> top_group, bottom_group;
  Located<std::string> axis;        ///< "x", "y" or "z"
  Located<double> stop_after_peak;  ///< fraction of the peak stress; 0: never
  Located<bool> energy, broken_bonds;
  Located<std::vector<std::string>> gauges;
  Located<std::string> wedge_group, wedge_backstop;
  Located<std::vector<double>> wedge_friction;  ///< internal, basal; optional
};

/// [coupled]: a coupled FEM–DEM model run as a sweep over η (chain6, metamaterial, wave).
struct CoupledTable {
  SourcePos pos;
  Located<std::string> case_name;  ///< the `case` key: "chain6", "metamaterial" or "wave"
  Located<std::string> title;
  Located<double> dt_dem;                  ///< s; given for the chains
  Located<std::vector<std::int64_t>> eta;  ///< optional: the default depends on the case
  Located<std::string> modes;              ///< "serial", "parallel" or "both"
  Located<double> duration;                ///< s; 0: the case's
  Located<std::string> fem_scheme;
  Located<double> dt_ref;                   ///< s
  Located<double> pulse_amplitude;          ///< N
  Located<double> pulse_duration;           ///< s
  Located<std::filesystem::path> geometry;  ///< given for the wave
  Located<std::string> particle_region, fem_region, exit_region;
  Located<bool> embedded;
  Located<std::vector<double>>
      wavelengths;           ///< particle diameters; optional: the default depends on `embedded`
  Located<double> diameter;  ///< m
  Located<double> dt_fraction;
  Located<double> fem_far_size;   ///< particle diameters
  Located<double> fem_growth;     ///< m/m
  Located<double> peak_velocity;  ///< m/s
  Located<std::int64_t> frames;
  Located<std::int64_t> series_eta;
  Located<std::int64_t> repeats;  ///< optional: the default depends on the case
  Located<std::int64_t> threads;  ///< optional: the default depends on the case
};

/// [network]: point masses and springs with one degree of freedom per node, split into an
/// FEM part and a particle part that share one layer of nodes.
struct NetworkTable {
  SourcePos pos;
  Located<std::string> title;
  Located<std::vector<double>> mass;                  ///< kg per node
  Located<std::vector<std::vector<double>>> springs;  ///< rows [i, j, k (N/m)]
  Located<std::vector<std::vector<double>>> walls;    ///< rows [i, k (N/m)]
  Located<std::vector<std::int64_t>> fem_nodes, particle_nodes;
  Located<std::vector<std::vector<double>>> sine_loads;  ///< rows [i, P (N), period (s), end (s)]
  Located<std::vector<std::int64_t>> probe_nodes;
};

/// [study]: a scene run over the combinations of its [[vary]] values.
struct StudyTable {
  SourcePos pos;
  Located<std::string> title;
  Located<std::filesystem::path> scene;   ///< the scene to run
  Located<std::vector<std::string>> set;  ///< overrides of every run ("key=value")
  Located<std::string> spread;            ///< a [[vary]] key: mean and spread over it; "" none
  Located<std::string> x;                 ///< a [[vary]] key: the plots' abscissa; "" the first
};

/// [[vary]]: one key of a study's scene and its values.
struct VaryTable {
  SourcePos pos;
  Located<std::string> key;  ///< as `--set` names it
  Located<std::vector<double>> values;
  Located<std::int64_t> components;  ///< 0: a number; 2, 3: the list [v, v(, v)]
  Located<std::string> label;
};

/// [[measure]]: one number of each run's summary.json.
struct MeasureTable {
  SourcePos pos;
  Located<std::string> name;
  Located<std::string> value;      ///< JSON pointer
  Located<std::string> divide_by;  ///< JSON pointer, or ""
};

/// [calibrate]: targets and lattice of `strata calibrate`.
struct CalibrateTable {
  SourcePos pos;
  Located<double> youngs_modulus;  ///< Pa
  Located<double> poisson_ratio;
  Located<double> ucs;               ///< Pa
  Located<double> tensile_strength;  ///< Pa (Brazilian)
  Located<double> density;           ///< kg/m^2 in 2D, kg/m^3 in 3D
  Located<double> diameter;          ///< m
  Located<std::string> lattice;      ///< "auto", "hex", "hcp" or "fcc"
  Located<double> friction;
  Located<bool> friction_strengthens_bonds;
  Located<double> specimen_width;  ///< m; 0: 40 diameters
  Located<double> damping_ratio;
  Located<double> transits_to_peak;
  Located<std::int64_t> iterations;
  Located<double> tolerance;
  Located<std::string> match;               ///< "ucs" or "tensile_strength"
  Located<StrengthSpread> strength_spread;  ///< of the specimens' bond strengths
  Located<double> strength_cov;
};

}  // namespace strata::scene
