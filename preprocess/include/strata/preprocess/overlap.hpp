#pragma once
/// Overlap layers between a particle (DEM) region and an FEM region (SPEC C3).
///
/// The two regions meet on a planar interface Γ: a straight line in 2D, a plane z = const
/// in 3D. One lattice frame is laid so that one row (2D) or close-packed layer (3D) lies on
/// Γ. The overlap is two site layers and the lattice bonds / elements between them:
///
///   layer 0 (on Γ):              DEM boundary particles = FEM external nodes
///   layer 1 (one row/layer into the FEM region):
///                                DEM external particles = FEM boundary nodes
///
/// so that the coupling copies, node for particle and without interpolation,
/// X_E(DEM) = X_B(FEM) (layer 1) and X_E(FEM) = X_B(DEM) (layer 0). Every other particle
/// (the particle region's side of Γ) and every other FEM node is internal.
///
/// Particles are whole inside the union of the two regions (distance ≥ d/2 to its outer
/// boundary); the FEM mesh (gmsh) covers the FEM region exactly, has a node at every
/// overlap site (bit for bit the site's coordinates), no node strictly between the two
/// layers, element size d at Γ, and grows linearly away from it. See docs/preprocess.md.
///
/// A particle box may also lie between two FEM boxes (FEM | DEM | FEM: a particle strip
/// embedded in an FEM block): one overlap per shared face, both interfaces normal to the
/// same axis, on opposite sides of the particle box. The result is still one lattice, one
/// FEM mesh (one element group per FEM box) and one set of tags and coincidence pairs, so
/// the coupling needs a single FEM and a single DEM partition.
#include <strata/preprocess/fill.hpp>
#include <strata/preprocess/mesh.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace strata::preprocess {

/// Role of a DEM particle or FEM node in the coupling (SPEC C3).
enum class OverlapTag : std::uint8_t {
  Internal = 0,  ///< updated by its own model only, not copied
  Boundary = 1,  ///< updated by its own model, copied to the other model's external site
  External = 2,  ///< state copied from the other model's boundary site
};

/// How the overlap is built.
struct OverlapOptions {
  LatticeKind kind = LatticeKind::Hex2D;  ///< Hex2D in 2D; HCP or FCC in 3D
  double d = 0;                           ///< particle diameter (m)
  double far_size = 0;  ///< largest FEM element size (m); 0: a quarter of the FEM region's depth
  double growth = 0.5;  ///< FEM element size grows by this much per metre away from Γ (> 0)
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

/// Particles, FEM mesh and the coincidence of their overlap sites.
struct OverlapModel {
  int dim = 2;
  /// The first interface (interfaces[0]), kept as plain members for the one-interface case.
  int axis = 1;              ///< normal axis of Γ (0: x, 1: y, 2: z)
  double interface = 0;      ///< coordinate of Γ along `axis`
  int fem_side = 1;          ///< +1 when the FEM region lies at larger `axis` coordinates, else -1
  double layer_spacing = 0;  ///< distance between the two overlap layers: d·√3/2 or d·√(2/3)
  /// Every interface, in the order of the FEM boxes given (1 or 2; all normal to `axis`).
  std::vector<OverlapInterface> interfaces;

  Lattice particles;                     ///< DEM particles: the particle region's side, layer 0, layer 1
  std::vector<OverlapTag> particle_tag;  ///< per particle
  SimplexMesh fem;                       ///< FEM mesh of the FEM region (triangles / tetrahedra)
  std::vector<OverlapTag> node_tag;      ///< per FEM node

  /// Coincidence pairs, one per overlap site (both layers): particle pair_particle[k] sits
  /// exactly on FEM node pair_node[k], at interface pair_interface[k] (index into
  /// `interfaces`). Sorted by particle index.
  std::vector<std::uint32_t> pair_particle, pair_node;
  std::vector<std::uint8_t> pair_interface;

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

}  // namespace strata::preprocess
