#pragma once
/// Geometry files: gmsh `.geo`, `.msh`, `.step`/`.stp`, `.brep` (through the gmsh C++ API)
/// and closed `.stl`/`.off` triangle surfaces (through CGAL).
///
/// A gmsh geometry is meshed once (triangles in 2D, tetrahedra in 3D); that mesh is what
/// lattices fill (mesh_fill.hpp) and what inside tests use, so a site is inside a region
/// exactly when it lies in one of the region's elements. Curved boundaries are therefore
/// approximated by the mesh (GeometryOptions::curvature_points elements per 2π).
///
/// Regions are gmsh physical groups of the top dimension (physical surfaces in 2D, physical
/// volumes in 3D) by name; a file without such groups has one region per entity, named
/// "surface 3" / "volume 2", and the empty name stands for all of them together.
/// Physical groups of dimension dim − 1 (curves in 2D, surfaces in 3D) name boundaries, for
/// particle groups ("particles on the rim of hole 1").
#include <strata/preprocess/mesh.hpp>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace strata::preprocess {

/// A closed, oriented triangle surface (STL/OFF) with its inside test and distance queries.
/// Defined in geometry.cpp (CGAL types stay out of the headers).
struct ClosedSurface;

/// How geometry files are read.
struct GeometryOptions {
  int dim = 0;                ///< 2 or 3: the dimension the scene needs; 0 accepts the file's
  double mesh_size = 0;       ///< largest element of the inside-test mesh (m); 0: the file's sizes
  double mesh_size_min = 0;   ///< smallest element (m); 0: no bound
  int curvature_points = 36;  ///< at least this many elements on a full circle (gmsh MinimumCirclePoints)
  double unit = 1;            ///< metres per unit of the file's coordinates (1e-3: a file in mm)
};

/// One region of a geometry: what a lattice fills.
struct GeometryRegion {
  std::string name;  ///< physical group name ("" for the whole geometry)
  std::string file;  ///< the file it came from, for messages
  int dim = 3;
  /// Triangles (2D) or tetrahedra (3D) of the region, grouped by gmsh entity: the elements
  /// of entity entity_tags[i] are [entity_first_cell[i], entity_first_cell[i+1]).
  /// Empty for a closed surface (STL/OFF).
  SimplexMesh mesh;
  std::vector<int> entity_tags;
  std::vector<std::size_t> entity_first_cell;
  /// Boundary of the region: segments (2D) or triangles (3D), the element facets that
  /// belong to one element only. For a closed surface, its triangles.
  SimplexMesh boundary;
  /// 2D: boundary loop of each boundary segment: 0 for the outer loop(s), k >= 1 for the
  /// k-th hole, holes numbered by the x (then y) of their centroid, left to right.
  std::vector<int> facet_loop;
  int hole_count = 0;
  std::shared_ptr<const ClosedSurface> surface;  ///< STL/OFF only

  /// Area (2D) or volume (3D) of the region (of its mesh, or enclosed by its surface).
  double measure() const;
  Bounds bounds() const;
  /// Whether p lies inside the region (in one of its elements, or inside its surface).
  bool contains(const Vec3& p) const;
};

/// A geometry file read and meshed.
class Geometry {
 public:
  std::string file;
  int dim = 3;
  /// All elements of the top dimension, grouped by entity; cell_group indexes entity_names.
  SimplexMesh mesh;
  std::vector<int> entity_tags;                     ///< top-dimension entities, in mesh order
  std::vector<std::size_t> entity_first_cell;       ///< entity_tags.size() + 1 offsets
  std::map<std::string, std::vector<int>> regions;  ///< top-dim physical name -> entity tags
  std::map<std::string, SimplexMesh> boundaries;    ///< (dim-1) physical name -> facets
  std::shared_ptr<const ClosedSurface> surface;     ///< STL/OFF only

  /// Names of the regions (top-dimension physical groups, or entities).
  std::vector<std::string> region_names() const;
  /// Names of the boundary groups (physical groups of dimension dim - 1).
  std::vector<std::string> boundary_names() const;
  /// The named region; "" for all regions together. Throws Error(Input) listing the
  /// region names when there is none of that name.
  GeometryRegion region(const std::string& name) const;
  /// Facets (segments in 2D, triangles in 3D) of a boundary group; throws Error(Input)
  /// listing the names when there is none of that name.
  const SimplexMesh& boundary(const std::string& name) const;
  /// Entity tags of the region with this name (empty when there is none).
  const std::vector<int>* region_entities(const std::string& name) const;
};

/// Reads a geometry file. Errors (strata::Error, kind Input) name the file, what is wrong
/// and what is allowed: a missing file, an unknown extension, a file gmsh or CGAL cannot
/// read (with gmsh's message), a surface that is not closed, a geometry of the wrong
/// dimension, or one with no region of the top dimension. Without gmsh (CGAL) in this build,
/// gmsh (STL/OFF) files give Error(Unsupported).
Geometry read_geometry(const std::filesystem::path& file, const GeometryOptions& opt = {});

/// Extensions (lower case) of the geometry files strata reads: gmsh's, and the closed
/// triangle surfaces CGAL reads. One list for the readers, the scene checks and the messages.
inline constexpr const char* kGmshExtensions[] = {".geo", ".msh", ".step", ".stp", ".brep", ".brp"};
inline constexpr const char* kSurfaceExtensions[] = {".stl", ".off"};
/// Which reader takes `file` (by its extension, in any case): gmsh, CGAL, or neither.
bool is_gmsh_file(const std::filesystem::path& file);
bool is_surface_file(const std::filesystem::path& file);
/// "allowed: .geo, .msh, .step, .stp, .brep, .brp (gmsh) and .stl, .off (closed surfaces)".
std::string geometry_extensions_text();

/// The version of the gmsh library this build reads geometry files with (e.g. "4.8.4"); empty
/// in a build without gmsh.
std::string gmsh_version();

/// Distance from p to the nearest facet of `facets` (segments or triangles), brute force;
/// for many queries use BoundaryDistance.
double distance_to_facets(const SimplexMesh& facets, const Vec3& p);
/// Distance from p to facet e of `facets` (a segment or a triangle).
double distance_to_facet(const SimplexMesh& facets, std::size_t e, const Vec3& p);

/// Distance queries to a set of facets (segments or triangles), with an AABB tree when CGAL
/// is available. Safe to call from several threads after construction.
class BoundaryDistance {
 public:
  explicit BoundaryDistance(const SimplexMesh& facets);
  ~BoundaryDistance();
  BoundaryDistance(const BoundaryDistance&) = delete;
  BoundaryDistance& operator=(const BoundaryDistance&) = delete;
  double operator()(const Vec3& p) const;
  /// Whether some facet comes within `r` of the box [lo, hi].
  bool near_box(const Vec3& lo, const Vec3& hi, double r) const;
  /// Indices of the facets that come within `r` of the box [lo, hi] (replaces `out`).
  void facets_near_box(const Vec3& lo, const Vec3& hi, double r, std::vector<std::uint32_t>& out) const;
  /// The facets queried.
  const SimplexMesh& facets() const;
  /// Distance from p to the nearest of the listed facets (infinity for none).
  double distance_to(const std::vector<std::uint32_t>& facets, const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace strata::preprocess
