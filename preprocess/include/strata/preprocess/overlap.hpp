#pragma once
/// Overlap layers between particle (DEM) regions and FEM regions, for the FEM–DEM coupling
/// of libcouple (overlapping domains, multi-time-step ratio η). Two constructions:
///
/// **Box path** (`build_overlap`): a particle box and one or two FEM boxes sharing whole
/// faces. The interface Γ is planar: a straight line in 2D, a plane z = const in 3D. One
/// lattice frame is laid so that one row (2D) or close-packed layer (3D) lies on Γ. The
/// overlap is two site layers and the lattice bonds / elements between them:
///
///   layer 0 (on Γ):              DEM boundary particles = FEM external nodes
///   layer 1 (one row/layer into the FEM region):
///                                DEM external particles = FEM boundary nodes
///
/// so that the coupling copies, node for particle and without interpolation,
/// X_E(DEM) = X_B(FEM) (layer 1) and X_E(FEM) = X_B(DEM) (layer 0). Every other particle
/// (the particle region's side of Γ) and every other FEM node is internal.
/// Particles are whole inside the union of the two regions (distance ≥ d/2 to its outer
/// boundary); the FEM mesh (gmsh) covers the FEM region exactly, has a node at every
/// overlap site (bit for bit the site's coordinates), no node strictly between the two
/// layers, element size d at Γ, and grows linearly away from it. A particle box may also
/// lie between two FEM boxes (FEM | DEM | FEM): one overlap per shared face, both normal to
/// the same axis.
///
/// **General path** (`build_coupled_model`, any interface between particle regions and FEM
/// regions of a gmsh geometry: curved, inclined, several, 2D or 3D). The copy becomes an
/// interpolation that reduces to the copy where a node coincides with a particle:
///
///  - Γ = the boundary entities (curves in 2D, surfaces in 3D) that a particle region and an
///    FEM region share. All regions are meshed as one conforming gmsh mesh, element size d
///    on Γ growing away from it. The FEM mesh is the FEM regions' elements plus the
///    *overlap ring*: the particle regions' elements with a node on Γ. FEM external nodes
///    are the ring's nodes off Γ (inside the particle regions).
///  - Particles: the particle regions filled with one lattice, plus a *band* of lattice
///    sites inside the FEM regions: every site that touches (centre distance d) a particle-
///    region site. Band sites are the DEM external particles.
///  - Links: a DEM external particle takes u_p = Σ N_k(x_p)·u_k over the nodes of the FEM
///    element that contains it (linear shape functions); an FEM external node takes the
///    value at x_n of a linear least-squares fit u ≈ a + B·(x − x_n) to the particle-region
///    particles around it (weights: the first row of the fit's pseudo-inverse). Both are
///    exact for affine fields (patch property), both sets of weights sum to 1.
///  - Roles: DEM boundary = the particles FEM externals read; FEM boundary = the nodes DEM
///    externals read; all others internal.
///
/// See docs/preprocess.md (overlap section) and libcouple/README.md.
#include <strata/preprocess/fill.hpp>
#include <strata/preprocess/mesh.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata::preprocess {

/// Role of a DEM particle or FEM node in the coupling.
enum class OverlapTag : std::uint8_t {
  Internal = 0,  ///< updated by its own model only, not copied
  Boundary = 1,  ///< updated by its own model, copied to the other model's external site
  External = 2,  ///< state copied from the other model's boundary site
};

/// How the overlap is built.
struct OverlapOptions {
  LatticeKind kind = LatticeKind::Hex2D;  ///< Hex2D in 2D; HCP or FCC in 3D
  double d = 0;                           ///< particle diameter (m)
  /// Largest FEM element size (m); 0: box path: a quarter of the FEM box's depth; general
  /// path: a quarter of the largest extent of the FEM regions' bounds (at least d).
  double far_size = 0;
  double growth = 0.5;  ///< FEM element size grows by this much per metre away from Γ (> 0)
  // ---- general path only ----
  /// A site of the lattice (regions meant to share one lattice take the same origin);
  /// default: the particle regions' lower bounds corner + d/2 on every axis (z = 0 in 2D).
  /// Setting it (or an orientation) selects the general path: the box path lays its own
  /// lattice with a row on Γ.
  std::optional<Vec3> origin;
  double orientation_deg = 0;  ///< lattice rotation about z (general path)
  bool force_general = false;  ///< use the general path even for boxes sharing faces
  /// Least-squares neighbourhood of an FEM external node: first radius, largest radius
  /// (in diameters), and the largest condition number of the scaled fit accepted before the
  /// radius grows (by d/4).
  double fit_radius = 1.5, fit_radius_max = 3.0, fit_condition = 20;
};

/// Weighted links in compressed rows: target[k] takes Σ_j weight[j]·value(source[j]) over
/// j in [first[k], first[k+1]), sources in the order listed. A target with a single source
/// of weight exactly 1 is a copy.
struct OverlapLinks {
  std::vector<std::uint32_t> target;  ///< ascending
  std::vector<std::uint32_t> first;   ///< target.size() + 1 offsets into source / weight
  std::vector<std::uint32_t> source;
  std::vector<double> weight;

  std::size_t size() const { return target.size(); }
  /// Appends a target with its sources and weights.
  void add(std::uint32_t to, const std::vector<std::uint32_t>& from, const std::vector<double>& w);
};

/// Which construction built an OverlapModel.
enum class OverlapMethod : std::uint8_t {
  Box = 0,      ///< coincident layers on a lattice row / layer (build_overlap)
  General = 1,  ///< band, ring and interpolated links (build_coupled_model, general path)
};

/// One interface Γ: the face a particle box shares with one FEM box.
struct OverlapInterface {
  int axis = 1;           ///< normal axis of Γ (0: x, 1: y, 2: z)
  double coordinate = 0;  ///< coordinate of Γ along `axis` (on a lattice row / layer)
  int fem_side = 1;       ///< +1 when this FEM box lies at larger `axis` coordinates, else -1
  int fem_group = 0;      ///< element group of this FEM box in OverlapModel::fem

  /// Signed distance of p from Γ, positive towards this interface's FEM box.
  double depth(const Vec3& p) const { return fem_side * (p[axis] - coordinate); }
};

/// Particles, FEM mesh, roles and links of a coupled model.
struct OverlapModel {
  int dim = 2;
  OverlapMethod method = OverlapMethod::Box;
  // ---- box path only (general path: interfaces empty, the members below unset) ----
  /// The first interface (interfaces[0]), kept as plain members for the one-interface case.
  int axis = 1;              ///< normal axis of Γ (0: x, 1: y, 2: z)
  double interface = 0;      ///< coordinate of Γ along `axis`
  int fem_side = 1;          ///< +1 when the FEM region lies at larger `axis` coordinates, else -1
  double layer_spacing = 0;  ///< distance between the two overlap layers: d·√3/2 or d·√(2/3)
  /// Every interface, in the order of the FEM boxes given (1 or 2; all normal to `axis`).
  std::vector<OverlapInterface> interfaces;

  /// Coincidence pairs, one per overlap site (both layers): particle pair_particle[k] sits
  /// exactly on FEM node pair_node[k], at interface pair_interface[k] (index into
  /// `interfaces`). Sorted by particle index.
  std::vector<std::uint32_t> pair_particle, pair_node;
  std::vector<std::uint8_t> pair_interface;

  // ---- both paths ----
  /// DEM particles. Box path: the particle region's side, layer 0, layer 1. General path:
  /// the particle regions' sites (region by region, in fill order), then the band.
  Lattice particles;
  std::vector<OverlapTag> particle_tag;  ///< per particle
  /// Per particle: index into particle_region_names, -1 for a site outside the particle
  /// regions (band sites; box path: layer 1). These are exactly the DEM external particles.
  std::vector<std::int32_t> particle_region;
  std::vector<std::string> particle_region_names;
  /// FEM mesh (triangles / tetrahedra). Groups: one per FEM region, in the order given
  /// (box path with FEM boxes: "fem" or "fem0", "fem1"), then, general path only, one overlap
  /// ring group per particle region, named "<particle region>:ring" (ring_group()).
  SimplexMesh fem;
  std::vector<OverlapTag> node_tag;  ///< per FEM node
  /// FEM boundary nodes → DEM external particles (targets: particles; sources: nodes).
  OverlapLinks fem_to_dem;
  /// DEM boundary particles → FEM external nodes (targets: nodes; sources: particles).
  OverlapLinks dem_to_fem;
  /// General path: Γ as the facets (segments in 2D, triangles in 3D) shared by particle-
  /// region and FEM-region elements, node indices into `fem`; box path: empty.
  SimplexMesh interface_facets;

  /// Element group of the overlap ring of particle region k (general path), -1 for none.
  int ring_group(std::size_t k) const {
    return method == OverlapMethod::General
               ? static_cast<int>(fem.group_names.size() - particle_region_names.size() + k)
               : -1;
  }

  /// Signed distance of p from the first Γ, positive towards its FEM region.
  double depth(const Vec3& p) const { return fem_side * (p[axis] - interface); }
};

/// Overlap of a particle box and an FEM box that share one face (2D: Shape::Kind::Box with
/// dim 2, the shared side normal to x or y; 3D: the shared face normal to z). Throws
/// Error(Input) for shapes that are not boxes, boxes that do not share a whole face, a
/// normal other than z in 3D, an FEM box thinner than three layer spacings, or a lattice
/// kind that does not match the dimension; Error(Unsupported) without gmsh.
/// The FEM mesh's elements are in one group, "fem".
OverlapModel build_overlap(const Shape& particle_box, const Shape& fem_box, const OverlapOptions& opt);

/// The same for two regions of a geometry file (physical groups of the top dimension, e.g.
/// tests/preprocess/data/two_blocks_2d.geo) that are axis-aligned boxes sharing a face;
/// the FEM mesh's elements are in one group named `fem_region`. Throws Error(Input) for a
/// region that is not a box (its measure differs from its bounds' by more than 1e-9
/// relative), besides the errors above and those of read_geometry.
OverlapModel build_overlap(const std::filesystem::path& file, const std::string& particle_region,
                           const std::string& fem_region, const OverlapOptions& opt);

/// Overlaps of a particle box with one or two FEM boxes (FEM | DEM | FEM), each sharing a
/// whole face with the particle box, all these faces normal to one axis (z in 3D) and on
/// opposite sides of the particle box. The lattice has a row / layer on the first
/// interface; with two, the particle box's depth between them must be a whole number n >= 2
/// of layer spacings (within 1e-6·d; the second FEM box's face is then moved onto the
/// lattice row, by at most that much). The FEM mesh has one element group per FEM box, in
/// the order given ("fem" for a single box, else "fem0", "fem1"); interfaces[k] belongs to
/// fem_boxes[k]. Throws Error(Input) for no FEM box or more than two, two FEM boxes on the
/// same side or on different axes, a depth that is not a whole number of layer spacings,
/// besides the errors of the one-box form.
OverlapModel build_overlap(const Shape& particle_box, const std::vector<Shape>& fem_boxes,
                           const OverlapOptions& opt);

/// The same for regions of a geometry file: the particle region and one or two FEM regions
/// (e.g. examples/04_coupled_wave/wave_embedded.geo: "fem" | "dem" | "fem_exit"); the FEM
/// mesh's element groups are named after the FEM regions.
OverlapModel build_overlap(const std::filesystem::path& file, const std::string& particle_region,
                           const std::vector<std::string>& fem_regions, const OverlapOptions& opt);

/// The coupled model of a geometry file: particle regions and FEM regions (physical groups
/// of the top dimension, by name). Uses the box path (build_overlap; links are the
/// coincidence pairs as single-source copies of weight 1) when there is one particle region,
/// one or two FEM regions that are axis-aligned boxes sharing whole faces with it and
/// build_overlap accepts them, and no origin, orientation or force_general is asked for;
/// otherwise the general path:
///
///  - Γ: the boundary entities shared by a particle region's entities and an FEM region's
///    (gmsh getBoundary); every particle region must share at least one with an FEM region.
///  - One conforming gmsh mesh of all named regions with the size field
///    min(far_size, d + growth·dist(Γ)) (gmsh Distance + MathEval fields); a file that
///    already holds a mesh of the top dimension is used as it is.
///  - Particles: the lattice of `opt` (kind, d, origin, orientation) in the particle
///    regions' elements and in the FEM elements within 1.5 d of Γ (fill_mesh), whole inside
///    the union of all named regions (centre ≥ d/2 from its outer boundary; Γ is not an
///    outer boundary). Sites in particle regions are kept; sites in FEM regions only when
///    they touch a particle-region site (the band, DEM external). A site on Γ belongs to
///    the element fill_mesh gives it to (one side exactly).
///  - FEM mesh: the FEM regions' elements (a group per FEM region) and the overlap ring (a
///    group per particle region). Nodes used only by ring elements are FEM external.
///  - fem_to_dem: a band site takes the linear shape functions of the FEM-region element
///    that contains it (the mesh defines the regions, so there is always one). dem_to_fem:
///    an FEM external node takes the first row of the pseudo-inverse of the least-squares
///    fit u ≈ a + B·(x − x_n) over the particle-region particles within fit_radius·d, the
///    radius growing by d/4 up to fit_radius_max·d until the scaled fit's condition number
///    is at most fit_condition. A node or particle that coincides with a source (within
///    1e-9·d) takes that source alone, weight 1 (a copy).
///  - node_tag / particle_tag: External as above, Boundary for every source of a link,
///    Internal otherwise.
///
/// Throws Error(Input) naming the file and region for: a name that is not a region
/// (physical group of the top dimension; the message lists them), a name listed as both
/// particle and FEM region or twice, no particle or no FEM region, a particle region that
/// shares no boundary entity with any FEM region, a lattice kind that does not match the
/// geometry's dimension, d <= 0, growth <= 0, an FEM external node with too few particles
/// around it (d too large for the region); Error(Unsupported) without gmsh.
OverlapModel build_coupled_model(const std::filesystem::path& geometry,
                                 const std::vector<std::string>& particle_regions,
                                 const std::vector<std::string>& fem_regions, const OverlapOptions& opt);

}  // namespace strata::preprocess
