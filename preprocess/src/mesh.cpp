// Simplex meshes and FEM meshing with gmsh.
#include "strata/preprocess/mesh.hpp"

#include <strata/core/error.hpp>
#include <strata/core/memory.hpp>
#include <strata/preprocess/geometry.hpp>

#include <algorithm>
#include <cmath>

#include "gmsh_session.hpp"

namespace strata::preprocess {

std::uint32_t SimplexMesh::add_node(const Vec3& p) {
  x.push_back(p[0]);
  y.push_back(p[1]);
  z.push_back(p[2]);
  return static_cast<std::uint32_t>(x.size() - 1);
}

double SimplexMesh::cell_measure(std::size_t e) const {
  const int np = nodes_per_cell();
  const std::uint32_t* c = &cells[e * static_cast<std::size_t>(np)];
  const Vec3 a = node(c[0]), b = node(c[1]);
  const Vec3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  if (dim == 1) return std::sqrt(ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
  const Vec3 cc = node(c[2]);
  const Vec3 ac{cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
  const Vec3 n{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
  if (dim == 2) return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const Vec3 d = node(c[3]);
  return std::abs(n[0] * (d[0] - a[0]) + n[1] * (d[1] - a[1]) + n[2] * (d[2] - a[2])) / 6.0;
}

double SimplexMesh::measure() const {
  double s = 0;
  for (std::size_t e = 0; e < cell_count(); ++e) s += cell_measure(e);
  return s;
}

Bounds SimplexMesh::bounds() const {
  Bounds b;
  b.lo = {INFINITY, INFINITY, INFINITY};
  b.hi = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < node_count(); ++i) {
    const Vec3 p = node(i);
    for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], p[a]), b.hi[a] = std::max(b.hi[a], p[a]);
  }
  return b;
}

int SimplexMesh::group_index(const std::string& name) const {
  const auto it = std::find(group_names.begin(), group_names.end(), name);
  return it == group_names.end() ? -1 : static_cast<int>(it - group_names.begin());
}

namespace {
/// The region's mesh with one group per region physical group the elements belong to.
SimplexMesh tagged_mesh(const Geometry& g, const std::string& physical) {
  GeometryRegion r = g.region(physical);
  SimplexMesh m = std::move(r.mesh);
  // cell_group: the physical region each element's entity belongs to (first by name).
  m.group_names.clear();
  std::vector<std::int32_t> group_of_entity(r.entity_tags.size(), -1);
  for (const auto& [name, ents] : g.regions) {
    for (std::size_t i = 0; i < r.entity_tags.size(); ++i) {
      if (group_of_entity[i] >= 0 || std::find(ents.begin(), ents.end(), r.entity_tags[i]) == ents.end())
        continue;
      int gi = m.group_index(name);
      if (gi < 0) {
        m.group_names.push_back(name);
        gi = int(m.group_names.size() - 1);
      }
      group_of_entity[i] = gi;
    }
  }
  for (std::size_t i = 0; i < r.entity_tags.size(); ++i)
    for (std::size_t e = r.entity_first_cell[i]; e < r.entity_first_cell[i + 1]; ++e)
      m.cell_group[e] = group_of_entity[i];
  return m;
}
}  // namespace

namespace detail {
void refuse_huge_mesh(const std::string& what, int dim, const double lo[3], const double hi[3], double h,
                      const std::string& allowed) {
  const double box =
      dim == 2 ? (hi[0] - lo[0]) * (hi[1] - lo[1]) : (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  const double elements =
      dim == 2 ? box / (std::sqrt(3.0) / 4 * h * h) : box / (std::sqrt(2.0) / 12 * h * h * h);
  const double bytes = elements * (dim == 2 ? 500.0 : 1000.0), memory = double(sys::physical_memory_bytes());
  STRATA_CHECK(!(h > 0) || memory <= 0 || bytes <= memory / 2, Input,
               "{}: gmsh would make about {:.3g} {} (elements about {:.3g} m long, a geometry {:.3g} m "
               "across): about {:.3g} GB, more than half this machine's {:.3g} GB of memory; allowed: {}",
               what, elements, dim == 2 ? "triangles" : "tetrahedra", h,
               std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}), bytes / 1e9, memory / 1e9, allowed);
}

}  // namespace detail

SimplexMesh mesh_fem_region(const std::filesystem::path& file, const std::string& physical, int dim,
                            const FemMeshOptions& opt) {
  STRATA_CHECK(opt.order == 1, Input, "FEM mesh of {}: element order {} is not available; allowed: 1",
               file.string(), opt.order);
  GeometryOptions go;
  go.dim = dim;
  go.mesh_size = opt.size;
  go.mesh_size_min = opt.size_min;
  go.curvature_points = 0;
  go.unit = opt.unit;
  const Geometry g = read_geometry(file, go);
  STRATA_CHECK(
      !g.surface, Input,
      "{}: an FEM region needs a geometry gmsh can mesh (.geo, .msh, .step, .brep); a closed STL/OFF "
      "surface can only be filled with particles",
      file.string());
  return tagged_mesh(g, physical);
}

SimplexMesh mesh_fem_shape(const Shape& s, double size) {
#if STRATA_WITH_GMSH
  const Bounds b = s.bounds();
  double extent = 0;
  for (int a = 0; a < s.dim; ++a) extent = std::max(extent, b.hi[a] - b.lo[a]);
  if (size <= 0) size = extent / 10;
  STRATA_CHECK(size > 0, Input, "FEM mesh of a shape: element size {} must be > 0", size);
  {
    const double lo[3] = {b.lo[0], b.lo[1], b.lo[2]}, hi[3] = {b.hi[0], b.hi[1], b.hi[2]};
    detail::refuse_huge_mesh(fmt::format("FEM mesh of a primitive shape with elements of {} m", size), s.dim,
                             lo, hi, size, "a larger mesh_size (0: a tenth of the shape's extent)");
  }
  detail::GmshSession gs;
  return gs.run("FEM mesh of a primitive shape", [&] {
    namespace occ = gmsh::model::occ;
    gmsh::model::add("shape");
    const bool three = s.dim == 3;
    switch (s.kind) {
      case Shape::Kind::Box:
        if (three)
          occ::addBox(s.origin[0], s.origin[1], s.origin[2], s.size[0], s.size[1], s.size[2]);
        else
          occ::addRectangle(s.origin[0], s.origin[1], 0, s.size[0], s.size[1]);
        break;
      case Shape::Kind::Disk:
        if (three)
          occ::addCylinder(s.center[0], s.center[1], s.z_min, 0, 0, s.z_max - s.z_min, s.radius);
        else
          occ::addDisk(s.center[0], s.center[1], 0, s.radius, s.radius);
        break;
      case Shape::Kind::Sphere:
        if (three)
          occ::addSphere(s.center[0], s.center[1], s.center[2], s.radius);
        else
          occ::addDisk(s.center[0], s.center[1], 0, s.radius, s.radius);
        break;
      case Shape::Kind::Polygon: {
        std::vector<int> pts, lines;
        for (const auto& v : s.polygon) pts.push_back(occ::addPoint(v[0], v[1], three ? s.z_min : 0));
        for (std::size_t i = 0; i < pts.size(); ++i)
          lines.push_back(occ::addLine(pts[i], pts[(i + 1) % pts.size()]));
        const int surf = occ::addPlaneSurface({occ::addCurveLoop(lines)});
        if (three) {
          gmsh::vectorpair out;
          occ::extrude({{2, surf}}, 0, 0, s.z_max - s.z_min, out);
        }
        break;
      }
    }
    occ::synchronize();
    gmsh::option::setNumber("Mesh.MeshSizeMax", size);
    gmsh::option::setNumber("Mesh.MeshSizeMin", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::model::mesh::generate(s.dim);
    Geometry g = detail::extract_gmsh_model("FEM mesh of a primitive shape", s.dim);
    return tagged_mesh(g, "");
  });
#else
  (void)s;
  (void)size;
  fail_missing_feature("STRATA_WITH_GMSH", "FEM meshes");
#endif
}

}  // namespace strata::preprocess
