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

/// Particles, FEM mesh and the coincidence of their overlap sites.
struct OverlapModel {
  int dim = 2;
  int axis = 1;              ///< normal axis of Γ (0: x, 1: y, 2: z)
  double interface = 0;      ///< coordinate of Γ along `axis`
  int fem_side = 1;          ///< +1 when the FEM region lies at larger `axis` coordinates, else -1
  double layer_spacing = 0;  ///< distance between the two overlap layers: d·√3/2 or d·√(2/3)

  Lattice particles;                     ///< DEM particles: the particle region's side, layer 0, layer 1
  std::vector<OverlapTag> particle_tag;  ///< per particle
  SimplexMesh fem;                       ///< FEM mesh of the FEM region (triangles / tetrahedra)
  std::vector<OverlapTag> node_tag;      ///< per FEM node

  /// Coincidence pairs, one per overlap site (both layers): particle pair_particle[k] sits
  /// exactly on FEM node pair_node[k]. Sorted by particle index.
  std::vector<std::uint32_t> pair_particle, pair_node;

  /// Signed distance of p from Γ, positive towards the FEM region.
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

}  // namespace strata::preprocess
