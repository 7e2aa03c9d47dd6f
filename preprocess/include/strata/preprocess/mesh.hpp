#pragma once
/// Simplex meshes: triangles (2D) and tetrahedra (3D) for FEM regions and for the inside
/// tests of geometry regions, plus segments / triangles for region boundaries.
///
/// Layout (structure of arrays): node coordinates as three arrays (SoA), element connectivity
/// as one flat array of `dim + 1` node indices per element, element index last.
#include <strata/preprocess/shapes.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace strata::preprocess {

/// A mesh of simplices of one dimension: segments (dim 1), triangles (2), tetrahedra (3).
struct SimplexMesh {
  int dim = 2;                           ///< dimension of the simplices
  std::vector<double> x, y, z;           ///< node coordinates (m)
  std::vector<std::uint32_t> cells;      ///< dim + 1 node indices per element
  std::vector<std::int32_t> cell_group;  ///< per element: index into group_names, -1 for none
  std::vector<std::string> group_names;  ///< gmsh physical group (or entity) names

  std::size_t node_count() const { return x.size(); }
  int nodes_per_cell() const { return dim + 1; }
  std::size_t cell_count() const { return cells.size() / static_cast<std::size_t>(dim + 1); }
  Vec3 node(std::size_t i) const { return {x[i], y[i], z[i]}; }
  std::uint32_t add_node(const Vec3& p);
  /// Length, area or volume of element e (positive).
  double cell_measure(std::size_t e) const;
  /// Sum of the element measures: the length, area or volume the mesh covers.
  double measure() const;
  Bounds bounds() const;
  /// Index of a group name, -1 when the mesh has no group of that name.
  int group_index(const std::string& name) const;
};

/// Options of FEM meshing with gmsh.
struct FemMeshOptions {
  double size = 0;      ///< target element size (m); 0: the geometry file's own sizes
  double size_min = 0;  ///< smallest element size (m); 0: no bound
  int order = 1;        ///< element order (only linear elements are produced for now)
  double unit = 1;      ///< metres per unit of the geometry file's coordinates
};

/// Triangles (2D) or tetrahedra (3D) of the named physical group of a geometry file (all
/// regions of the top dimension when `physical` is empty), meshed by gmsh with the size
/// control of `opt`. cell_group holds the physical group of each element. Throws
/// strata::Error(Input) for unreadable files or unknown groups, Unsupported without gmsh.
SimplexMesh mesh_fem_region(const std::filesystem::path& file, const std::string& physical, int dim,
                            const FemMeshOptions& opt = {});

/// Triangles (2D) or tetrahedra (3D) filling a primitive shape (box, disk/cylinder, sphere,
/// polygon), meshed by gmsh with element size `size` (0: a tenth of the shape's extent).
SimplexMesh mesh_fem_shape(const Shape& shape, double size);

}  // namespace strata::preprocess
