#pragma once
/// Filling meshes and geometry regions with lattice sites (large models from meshes, as ECC4D
/// builds them: Zhao, Qiao, Zhang, Sun & Chen 2021): the sites of each element are enumerated
/// directly (layer by layer, row by row, the column range of each row from the element's
/// faces), never by testing every site against every element. Two parallel passes (count per
/// element, prefix sum, write) give a deterministic order, the same for any number of threads,
/// and no memory beyond the sites and one counter per element.
///
/// Inside tests are exact: a site lies in an element when it is on the inner side of every
/// face, by CGAL's exact orientation predicates behind a floating-point filter. A site on a
/// face shared by two elements goes to exactly one of them: faces are oriented by their
/// sorted node indices, and a site on a face counts as lying on the side its symbolic
/// perturbation p + ε·(1, ε, ε²) falls on (simulation of simplicity). Sites on the outer
/// boundary follow the same rule, so about half of them are kept; use a minimum distance to
/// the boundary to keep whole particles.
#include <strata/preprocess/fill.hpp>
#include <strata/preprocess/geometry.hpp>

#include <optional>

namespace strata::preprocess {

/// A lattice in space: kind, diameter, rotation about z, and one site's position.
/// Site (i, j, k) is column i of row j of layer k (k = 0 in 2D). Rows run along the rotated
/// x axis, spaced d·√3/2, odd rows shifted by d/2; close-packed layers are spaced d·√(2/3)
/// along z, shifted in-plane by (d/2, d/(2√3)) per stacking position (HCP: A B A B, FCC:
/// A B C A B C), the same sites as lattice.hpp's box lattices.
class LatticeFrame {
 public:
  LatticeFrame(LatticeKind kind, double d, double orientation_deg = 0, Vec3 origin = {0, 0, 0});
  int dim() const { return kind_ == LatticeKind::Hex2D ? 2 : 3; }
  LatticeKind kind() const { return kind_; }
  double diameter() const { return d_; }
  const Vec3& origin() const { return origin_; }
  double row_spacing() const { return h_; }
  double layer_spacing() const { return c_; }
  /// Area (2D) or volume (3D) per site: d²·√3/2 or d³/√2.
  double cell_measure() const;
  /// Fraction of space the particles fill: π/(2√3) (hex) or π/(3√2) (close packing).
  double packing_fraction() const;
  /// In-plane shift of layer k (local coordinates).
  void layer_shift(std::int64_t k, double& sx, double& sy) const;
  /// Centre of site (i, j, k) in world coordinates. Always computed by this one function,
  /// compiled without floating-point contraction (-ffp-contract=off), so the same site seen
  /// from two elements, or from a test, has the same coordinates bit for bit.
  Vec3 site(std::int64_t i, std::int64_t j, std::int64_t k) const;
  /// World -> lattice-local coordinates (rotation undone, origin at 0).
  Vec3 to_local(const Vec3& p) const;

 private:
  LatticeKind kind_;
  double d_, h_, c_, cos_, sin_;
  Vec3 origin_;
};

/// Minimum distance to the boundary: sites closer than `distance` to `boundary` are dropped.
struct BoundaryFilter {
  const BoundaryDistance* boundary = nullptr;
  double distance = 0;
  const SimplexMesh& boundary_facets() const { return boundary->facets(); }
};

/// Statistics of a fill.
struct FillStats {
  std::size_t elements = 0;     ///< elements visited
  std::size_t candidates = 0;   ///< sites tested (after the per-row column ranges)
  std::size_t exact_tests = 0;  ///< sign tests the floating-point filter could not decide
  double seconds = 0;
};

/// Sites of `frame` inside the simplices of `mesh` (triangles in 2D, tetrahedra in 3D;
/// the frame's dimension must match), listed element by element in mesh order, within an
/// element by layer, row, column. When `first_site` is given it receives cell_count() + 1
/// offsets: the sites of element e are [first_site[e], first_site[e+1]).
Lattice fill_mesh(const SimplexMesh& mesh, const LatticeFrame& frame, const BoundaryFilter& filter = {},
                  std::vector<std::size_t>* first_site = nullptr, FillStats* stats = nullptr);

/// How a geometry region is filled.
struct FillOptions {
  LatticeKind kind = LatticeKind::Hex2D;
  double d = 0;                      ///< particle diameter (m)
  double orientation_deg = 0;        ///< lattice rotation about z
  double min_boundary_distance = 0;  ///< 0: centres inside; d/2: whole particles inside
  /// A site of the lattice; regions that should share one lattice (so that no two
  /// particles of neighbouring regions overlap) take the same origin. Default: the
  /// region's lower bounds corner + d/2 on every axis (z = 0 in 2D).
  std::optional<Vec3> origin;
};

/// A filled geometry region.
struct RegionFill {
  Lattice lattice;
  /// Sites of entity entity_tags[i] are [entity_first_site[i], entity_first_site[i+1])
  /// (empty for closed surfaces).
  std::vector<int> entity_tags;
  std::vector<std::size_t> entity_first_site;
  double measure = 0;  ///< area/volume of the region
  double packing = 0;  ///< particle area/volume over the region's
  FillStats stats;
};

/// Fills a region of a geometry file with a lattice: by element enumeration (gmsh
/// regions) or by CGAL inside tests on the lattice sites of the bounds (closed surfaces).
RegionFill fill_region(const GeometryRegion& region, const FillOptions& opt);

// ---- particle groups on filled regions (indices into the region's lattice, ascending) ----
/// Particles of a region physical group (a sub-region of the filled region, by its
/// entities), or within `width` of a boundary physical group (curves in 2D, surfaces in 3D).
std::vector<std::uint32_t> physical_group_members(const Geometry& g, const RegionFill& f,
                                                  const std::string& physical, double width);
/// Particles within `width` of the rim of hole `hole` (1-based; holes numbered left to
/// right by their centroid) of a 2D region.
std::vector<std::uint32_t> hole_rim(const GeometryRegion& r, const Lattice& l, int hole, double width);
/// Particles within `width` of any of `facets` (segments or triangles).
std::vector<std::uint32_t> near_facets(const SimplexMesh& facets, const Lattice& l, double width);

}  // namespace strata::preprocess
