#include <strata/core/error.hpp>
#include <strata/fem/mesh.hpp>

#include <cmath>

namespace strata::fem {

std::string to_string(ElementType t) {
  switch (t) {
    case ElementType::Spring:
      return "spring";
    case ElementType::Bar:
      return "bar";
    case ElementType::Tri3:
      return "tri3";
    case ElementType::Tet4:
      return "tet4";
  }
  return "?";
}

std::int32_t Mesh::add_node(double x0, double x1, double x2) {
  x[0].push_back(x0);
  x[1].push_back(x1);
  x[2].push_back(x2);
  return static_cast<std::int32_t>(x[0].size() - 1);
}

void Mesh::add_point_mass(std::int32_t i, double m) {
  if (point_mass.size() < nodes()) point_mass.resize(nodes(), 0.0);
  point_mass.at(static_cast<std::size_t>(i)) += m;
}

void Mesh::validate() const {
  STRATA_CHECK(dim >= 1 && dim <= 3, Input, "mesh: dim = {} must be 1, 2 or 3", dim);
  STRATA_CHECK(x[0].size() == x[1].size() && x[0].size() == x[2].size(), Input,
               "mesh: coordinate arrays have different lengths");
  STRATA_CHECK(point_mass.empty() || point_mass.size() == nodes(), Input,
               "mesh: {} point masses for {} nodes", point_mass.size(), nodes());
  for (double m : point_mass)
    STRATA_CHECK(m >= 0 && std::isfinite(m), Input, "mesh: point mass {} kg < 0", m);
  for (const ElementBlock& b : blocks) {
    const int npe = nodes_per_element(b.type);
    STRATA_CHECK(b.conn.size() % static_cast<std::size_t>(npe) == 0, Input,
                 "mesh: {} block connectivity of length {} is not a multiple of {}", to_string(b.type),
                 b.conn.size(), npe);
    for (std::int32_t n : b.conn)
      STRATA_CHECK(n >= 0 && static_cast<std::size_t>(n) < nodes(), Input,
                   "mesh: {} element refers to node {} (mesh has {} nodes)", to_string(b.type), n, nodes());
    const Material& m = b.material;
    switch (b.type) {
      case ElementType::Spring:
        STRATA_CHECK(m.k > 0, Input, "mesh: spring k = {} must be > 0 (N/m)", m.k);
        break;
      case ElementType::Bar:
        STRATA_CHECK(m.E > 0 && m.area > 0 && m.rho >= 0, Input,
                     "mesh: bar needs E > 0 (Pa), area > 0 (m^2), rho >= 0 (kg/m^3); got {}, {}, {}", m.E,
                     m.area, m.rho);
        break;
      case ElementType::Tri3:
        STRATA_CHECK(dim == 2, Input, "mesh: tri3 elements need dim = 2 (mesh has dim = {})", dim);
        [[fallthrough]];
      case ElementType::Tet4:
        if (b.type == ElementType::Tet4)
          STRATA_CHECK(dim == 3, Input, "mesh: tet4 elements need dim = 3 (mesh has dim = {})", dim);
        STRATA_CHECK(m.E > 0 && m.rho >= 0 && m.thickness > 0, Input,
                     "mesh: {} needs E > 0 (Pa), rho >= 0, thickness > 0; got {}, {}, {}", to_string(b.type),
                     m.E, m.rho, m.thickness);
        STRATA_CHECK(m.nu > -1 && m.nu < 0.5, Input, "mesh: nu = {} must be in (-1, 0.5)", m.nu);
        break;
    }
  }
}

Mesh spring_mass_mesh(const std::vector<double>& masses, const std::vector<std::int32_t>& spring_i,
                      const std::vector<std::int32_t>& spring_j, const std::vector<double>& spring_k) {
  STRATA_CHECK(spring_i.size() == spring_j.size() && spring_i.size() == spring_k.size(), Input,
               "spring_mass_mesh: {} / {} / {} spring ends and stiffnesses", spring_i.size(), spring_j.size(),
               spring_k.size());
  Mesh m;
  m.dim = 1;
  for (std::size_t i = 0; i < masses.size(); ++i) m.add_node(static_cast<double>(i));
  m.point_mass = masses;
  // one block per distinct stiffness keeps the data flat and the blocks few
  for (std::size_t s = 0; s < spring_k.size(); ++s) {
    ElementBlock* blk = nullptr;
    for (ElementBlock& b : m.blocks)
      if (b.material.k == spring_k[s]) blk = &b;
    if (!blk) {
      m.blocks.push_back({ElementType::Spring, Material{.k = spring_k[s]}, {}});
      blk = &m.blocks.back();
    }
    blk->conn.push_back(spring_i[s]);
    blk->conn.push_back(spring_j[s]);
  }
  return m;
}

Mesh bar_mesh(int n, double L, const Material& mat, int dim) {
  Mesh m;
  m.dim = dim;
  for (int i = 0; i <= n; ++i) m.add_node(L * i / n);
  ElementBlock b{ElementType::Bar, mat, {}};
  for (int i = 0; i < n; ++i) {
    b.conn.push_back(i);
    b.conn.push_back(i + 1);
  }
  m.blocks.push_back(std::move(b));
  return m;
}

Mesh rectangle_tri_mesh(int nx, int ny, double Lx, double Ly, const Material& mat) {
  Mesh m;
  m.dim = 2;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.add_node(Lx * i / nx, Ly * j / ny);
  ElementBlock b{ElementType::Tri3, mat, {}};
  auto id = [&](int i, int j) { return static_cast<std::int32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::int32_t n00 = id(i, j), n10 = id(i + 1, j), n11 = id(i + 1, j + 1), n01 = id(i, j + 1);
      b.conn.insert(b.conn.end(), {n00, n10, n11, n00, n11, n01});
    }
  m.blocks.push_back(std::move(b));
  return m;
}

Mesh box_tet_mesh(int nx, int ny, int nz, double Lx, double Ly, double Lz, const Material& mat) {
  Mesh m;
  m.dim = 3;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.add_node(Lx * i / nx, Ly * j / ny, Lz * k / nz);
  auto id = [&](int i, int j, int k) { return static_cast<std::int32_t>((k * (ny + 1) + j) * (nx + 1) + i); };
  ElementBlock b{ElementType::Tet4, mat, {}};
  // Kuhn split: one tetrahedron per path 0 -> e_p0 -> e_p0+e_p1 -> (1,1,1) along the cube's
  // main diagonal; the same diagonal in every cube makes the split conforming.
  static constexpr int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : kPerm) {
          int c[3] = {0, 0, 0};
          std::int32_t t[4];
          t[0] = id(i, j, k);
          for (int s = 0; s < 3; ++s) {
            c[p[s]] = 1;
            t[s + 1] = id(i + c[0], j + c[1], k + c[2]);
          }
          b.conn.insert(b.conn.end(), t, t + 4);
        }
  m.blocks.push_back(std::move(b));
  return m;
}

}  // namespace strata::fem
