#pragma once
/// FEM mesh data: node coordinates as a structure of arrays, elements in blocks of one type
/// and one material with flat connectivity (element index last: nodes of element e are
/// conn[e*npe .. e*npe+npe-1]).
///
/// DOF numbering: node i, component a (0 <= a < dim) is DOF i*dim + a.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace strata::fem {

/// Element kinds libfem knows. All are linear elastic, small strain.
enum class ElementType {
  Spring,  ///< 2 nodes, axial stiffness k (N/m), no mass of its own; along the node-to-node line
           ///< (in 1D always along +x, so coincident nodes are allowed there)
  Bar,     ///< 2 nodes, axial stiffness E·A/L, lumped mass ρ·A·L/2 per node
  Tri3,    ///< linear triangle (2D), plane stress or plane strain, thickness t
  Tet4,    ///< linear tetrahedron (3D)
};

/// Plane-stress or plane-strain interpretation of a 2D triangle.
enum class PlaneMode { Stress, Strain };

/// Nodes per element of a type.
constexpr int nodes_per_element(ElementType t) {
  return t == ElementType::Tri3 ? 3 : t == ElementType::Tet4 ? 4 : 2;
}
std::string to_string(ElementType t);

/// Material and section data of a block. Unused fields are ignored.
struct Material {
  double k = 0;          ///< Spring: stiffness (N/m)
  double E = 0;          ///< Young's modulus (Pa)
  double nu = 0;         ///< Poisson's ratio (-)
  double rho = 0;        ///< density (kg/m^3)
  double area = 1;       ///< Bar: cross-section (m^2)
  double thickness = 1;  ///< Tri3: thickness (m)
  PlaneMode plane = PlaneMode::Stress;
};

/// Elements of one type and one material.
struct ElementBlock {
  ElementType type = ElementType::Spring;
  Material material;
  std::vector<std::int32_t> conn;  ///< flat: nodes_per_element(type) node ids per element

  std::size_t size() const { return conn.size() / static_cast<std::size_t>(nodes_per_element(type)); }
};

/// Nodes (SoA), optional point masses and element blocks.
struct Mesh {
  int dim = 2;                           ///< 1, 2 or 3 displacement components per node
  std::array<std::vector<double>, 3> x;  ///< x[a][i]: coordinate a of node i (a < dim used)
  std::vector<double> point_mass;        ///< extra lumped mass per node (kg); empty = none
  std::vector<ElementBlock> blocks;

  std::size_t nodes() const { return x[0].size(); }
  std::size_t dofs() const { return nodes() * static_cast<std::size_t>(dim); }
  /// Appends a node and returns its id.
  std::int32_t add_node(double x0, double x1 = 0, double x2 = 0);
  /// Adds `m` kg at node `i` (resizes point_mass as needed).
  void add_point_mass(std::int32_t i, double m);
  /// Checks ids, dimensions and material values; throws strata::Error(Input).
  void validate() const;
};

/// A 1D chain of point masses joined by springs (used by the coupled chain cases):
/// nodes at x = 0, 1, 2, ... (only for numbering; springs act along +x in 1D).
/// `spring_i[s]`, `spring_j[s]`, `spring_k[s]` list the springs; masses[i] the point masses.
Mesh spring_mass_mesh(const std::vector<double>& masses, const std::vector<std::int32_t>& spring_i,
                      const std::vector<std::int32_t>& spring_j, const std::vector<double>& spring_k);

/// Structured meshes for tests and examples.
/// A bar along x of `n` Bar elements, length L, in `dim` dimensions (nodes on the x axis).
Mesh bar_mesh(int n, double L, const Material& m, int dim = 1);
/// A rectangle [0,Lx]x[0,Ly] of nx*ny squares, each split into two triangles.
Mesh rectangle_tri_mesh(int nx, int ny, double Lx, double Ly, const Material& m);
/// A box [0,Lx]x[0,Ly]x[0,Lz] of nx*ny*nz cubes, each split into six tetrahedra (Kuhn split,
/// conforming across faces).
Mesh box_tet_mesh(int nx, int ny, int nz, double Lx, double Ly, double Lz, const Material& m);

}  // namespace strata::fem
