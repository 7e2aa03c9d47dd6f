// Geometry files through gmsh (.geo, .msh, .step, .brep) and CGAL (.stl, .off).
#include "strata/preprocess/geometry.hpp"

#include <strata/core/error.hpp>
#include <strata/core/memory.hpp>
#include <strata/core/parallel.hpp>

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "cgal_queries.hpp"
#include "gmsh_session.hpp"

namespace strata::preprocess {

namespace fs = std::filesystem;

// ---- gmsh session --------------------------------------------------------------------------
#if STRATA_WITH_GMSH
namespace detail {
namespace {
std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}
bool& gmsh_started() {
  static bool started = false;
  return started;
}
void start_gmsh() {
  gmsh::initialize();
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 1);
  gmsh::logger::start();
  gmsh_started() = true;
}
}  // namespace

GmshSession::GmshSession() : lock_(gmsh_mutex()), threads_(par::threads()) {
  // A fresh gmsh for every session (well under a millisecond): options and parser state
  // (e.g. a .geo file's SetFactory) do not leak from one file into the next.
  if (gmsh_started()) gmsh::finalize();
  start_gmsh();
  gmsh::option::setNumber("General.NumThreads", 1);
}

GmshSession::~GmshSession() {
  try {
    gmsh::clear();
  } catch (...) {
  }
  par::set_threads(threads_);
}

void GmshSession::restart() {
  try {
    gmsh::finalize();
  } catch (...) {
  }
  start_gmsh();
}

std::string GmshSession::last_error() {
  std::string e;
  gmsh::logger::getLastError(e);
  return e;
}

const std::string& GmshSession::version() {
  static const std::string v = [] {
    std::string s;
    gmsh::option::getString("General.Version", s);
    return s.empty() ? std::string(GMSH_API_VERSION) : s;
  }();
  return v;
}

std::string GmshSession::cannot(const std::string& file, const std::string& action) {
  return fmt::format("{}: gmsh {} cannot {}", file, version(), action);
}

std::string GmshSession::explain(const std::string& message) {
  if (message.find("syntax error") == std::string::npos) return message;
  return fmt::format(
      "{} (gmsh {} reads .geo files written for its own version and older ones; a file written for a "
      "newer gmsh, such as a newer gmsh tutorial, can use commands this version does not know)",
      message, version());
}
}  // namespace detail

std::string gmsh_version() {
  detail::GmshSession session;
  return detail::GmshSession::version();
}
#else
std::string gmsh_version() { return ""; }
#endif

// ---- GeometryRegion ------------------------------------------------------------------------

double GeometryRegion::measure() const {
  if (surface) return detail::surface_volume(*surface);
  return mesh.measure();
}

Bounds GeometryRegion::bounds() const {
  if (surface) return detail::surface_bounds(*surface);
  return mesh.bounds();
}

bool GeometryRegion::contains(const Vec3& p) const {
  if (surface) return detail::surface_contains(*surface, p);
  // Brute force over elements (tests and small meshes; fills enumerate sites per element).
  const int np = mesh.nodes_per_cell();
  for (std::size_t e = 0; e < mesh.cell_count(); ++e) {
    Vec3 v[4];
    for (int k = 0; k < np; ++k) v[k] = mesh.node(mesh.cells[e * np + k]);
    if (dim == 2) {
      auto o = [](const Vec3& a, const Vec3& b, const Vec3& c) {
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
      };
      const double s = o(v[0], v[1], v[2]), a = o(v[0], v[1], p), b = o(v[1], v[2], p), c = o(v[2], v[0], p);
      if (s > 0 ? (a >= 0 && b >= 0 && c >= 0) : (a <= 0 && b <= 0 && c <= 0)) return true;
    } else {
      const int face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
      bool in = true;
      for (int f = 0; f < 4 && in; ++f) {
        const int sv = detail::orient3d_exact(v[face[f][0]], v[face[f][1]], v[face[f][2]], v[f]);
        const int sp = detail::orient3d_exact(v[face[f][0]], v[face[f][1]], v[face[f][2]], p);
        in = sp == 0 || sp == sv;
      }
      if (in) return true;
    }
  }
  return false;
}

// ---- boundaries of a region ----------------------------------------------------------------
namespace {

/// Facets that belong to one element only, oriented with the element on their left (2D) /
/// outward (3D); node indices into `mesh`.
SimplexMesh boundary_facets(const SimplexMesh& mesh) {
  SimplexMesh b;
  b.dim = mesh.dim - 1;
  b.x = mesh.x, b.y = mesh.y, b.z = mesh.z;
  const int np = mesh.nodes_per_cell(), nf = mesh.dim + 1, fn = mesh.dim;
  struct Facet {
    std::array<std::uint32_t, 3> key;  // sorted nodes
    std::array<std::uint32_t, 3> oriented;
  };
  std::vector<Facet> facets;
  facets.reserve(mesh.cell_count() * nf);
  for (std::size_t e = 0; e < mesh.cell_count(); ++e) {
    const std::uint32_t* c = &mesh.cells[e * np];
    if (mesh.dim == 2) {
      const Vec3 a = mesh.node(c[0]), bb = mesh.node(c[1]), cc = mesh.node(c[2]);
      const bool ccw = (bb[0] - a[0]) * (cc[1] - a[1]) - (bb[1] - a[1]) * (cc[0] - a[0]) > 0;
      for (int k = 0; k < 3; ++k) {
        std::uint32_t u = c[k], v = c[(k + 1) % 3];
        if (!ccw) std::swap(u, v);
        facets.push_back({{std::min(u, v), std::max(u, v), 0}, {u, v, 0}});
      }
    } else {
      // faces opposite each vertex, oriented outward for a positively oriented tet
      const Vec3 p0 = mesh.node(c[0]), p1 = mesh.node(c[1]), p2 = mesh.node(c[2]), p3 = mesh.node(c[3]);
      const bool pos = detail::orient3d_exact(p0, p1, p2, p3) > 0;
      const int face[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
      for (int f = 0; f < 4; ++f) {
        std::array<std::uint32_t, 3> o{c[face[f][0]], c[face[f][1]], c[face[f][2]]};
        if (!pos) std::swap(o[1], o[2]);
        auto k = o;
        std::sort(k.begin(), k.end());
        facets.push_back({k, o});
      }
    }
  }
  std::sort(facets.begin(), facets.end(), [](const Facet& a, const Facet& b) { return a.key < b.key; });
  for (std::size_t i = 0; i < facets.size();) {
    std::size_t j = i + 1;
    while (j < facets.size() && facets[j].key == facets[i].key) ++j;
    if (j - i == 1)
      for (int k = 0; k < fn; ++k) b.cells.push_back(facets[i].oriented[k]);
    i = j;
  }
  b.cell_group.assign(b.cell_count(), -1);
  return b;
}

/// 2D: splits boundary segments into loops; 0 for outer loops (counter-clockwise), k >= 1
/// for holes (clockwise), numbered by centroid x then y.
int number_loops(const SimplexMesh& b, std::vector<int>& loop_of) {
  const std::size_t n = b.cell_count();
  loop_of.assign(n, -1);
  std::unordered_multimap<std::uint32_t, std::size_t> from;
  for (std::size_t s = 0; s < n; ++s) from.emplace(b.cells[2 * s], s);
  struct Loop {
    double area = 0, cx = 0, cy = 0;
    std::vector<std::size_t> segs;
  };
  std::vector<Loop> loops;
  std::vector<char> used(n, 0);
  for (std::size_t s0 = 0; s0 < n; ++s0) {
    if (used[s0]) continue;
    Loop l;
    std::size_t s = s0;
    while (!used[s]) {
      used[s] = 1;
      l.segs.push_back(s);
      const std::uint32_t a = b.cells[2 * s], e = b.cells[2 * s + 1];
      l.area += 0.5 * (b.x[a] * b.y[e] - b.x[e] * b.y[a]);
      l.cx += b.x[a], l.cy += b.y[a];
      auto [it, end] = from.equal_range(e);
      for (; it != end; ++it)
        if (!used[it->second]) break;
      if (it == end) break;
      s = it->second;
    }
    l.cx /= double(l.segs.size()), l.cy /= double(l.segs.size());
    loops.push_back(std::move(l));
  }
  std::vector<std::size_t> holes;
  for (std::size_t i = 0; i < loops.size(); ++i)
    if (loops[i].area < 0) holes.push_back(i);
  std::sort(holes.begin(), holes.end(), [&](std::size_t a, std::size_t c) {
    return loops[a].cx != loops[c].cx ? loops[a].cx < loops[c].cx : loops[a].cy < loops[c].cy;
  });
  for (const auto& l : loops)
    for (auto s : l.segs) loop_of[s] = 0;
  for (std::size_t h = 0; h < holes.size(); ++h)
    for (auto s : loops[holes[h]].segs) loop_of[s] = int(h + 1);
  return int(holes.size());
}

/// Keeps only the nodes the cells use, renumbered in order of first use.
void compact_nodes(SimplexMesh& m) {
  std::vector<std::uint32_t> map(m.node_count(), UINT32_MAX);
  SimplexMesh out;
  out.dim = m.dim;
  for (auto& c : m.cells) {
    if (map[c] == UINT32_MAX) map[c] = out.add_node(m.node(c));
    c = map[c];
  }
  m.x = std::move(out.x), m.y = std::move(out.y), m.z = std::move(out.z);
}

}  // namespace

// ---- Geometry --------------------------------------------------------------------------------

std::vector<std::string> Geometry::region_names() const {
  std::vector<std::string> out;
  for (const auto& [n, e] : regions) out.push_back(n);
  return out;
}

std::vector<std::string> Geometry::boundary_names() const {
  std::vector<std::string> out;
  for (const auto& [n, e] : boundaries) out.push_back(n);
  return out;
}

const std::vector<int>* Geometry::region_entities(const std::string& name) const {
  auto it = regions.find(name);
  return it == regions.end() ? nullptr : &it->second;
}

namespace {
std::string quoted_list(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "\"" : ", \"") + n + "\"";
  return s.empty() ? "(none)" : s;
}
}  // namespace

GeometryRegion Geometry::region(const std::string& name) const {
  GeometryRegion r;
  r.name = name;
  r.file = file;
  r.dim = dim;
  if (surface) {
    STRATA_CHECK(name.empty() || regions.count(name), Input,
                 "{}: no region named \"{}\": a closed surface has one region, \"{}\" (or leave `physical` "
                 "empty)",
                 file, name, regions.begin()->first);
    r.surface = surface;
    r.boundary = detail::surface_triangles(*surface);
    return r;
  }
  std::vector<int> wanted;
  if (name.empty()) {
    wanted = entity_tags;
  } else {
    const auto* e = region_entities(name);
    STRATA_CHECK(e != nullptr, Input,
                 "{}: no region (physical {} group) named \"{}\"; the {}D regions are: {}", file,
                 dim == 2 ? "surface" : "volume", name, dim, quoted_list(region_names()));
    wanted = *e;
  }
  r.mesh.dim = dim;
  r.mesh.x = mesh.x, r.mesh.y = mesh.y, r.mesh.z = mesh.z;
  r.mesh.group_names = mesh.group_names;
  const int np = dim + 1;
  r.entity_first_cell.push_back(0);
  for (std::size_t i = 0; i < entity_tags.size(); ++i) {
    if (std::find(wanted.begin(), wanted.end(), entity_tags[i]) == wanted.end()) continue;
    for (std::size_t e = entity_first_cell[i]; e < entity_first_cell[i + 1]; ++e) {
      r.mesh.cells.insert(r.mesh.cells.end(), &mesh.cells[e * np], &mesh.cells[e * np] + np);
      r.mesh.cell_group.push_back(mesh.cell_group[e]);
    }
    r.entity_tags.push_back(entity_tags[i]);
    r.entity_first_cell.push_back(r.mesh.cell_count());
  }
  STRATA_CHECK(r.mesh.cell_count() > 0, Input, "{}: region \"{}\" has no {} after meshing", file, name,
               dim == 2 ? "triangles" : "tetrahedra");
  compact_nodes(r.mesh);
  r.boundary = boundary_facets(r.mesh);
  if (dim == 2) r.hole_count = number_loops(r.boundary, r.facet_loop);
  return r;
}

const SimplexMesh& Geometry::boundary(const std::string& name) const {
  auto it = boundaries.find(name);
  STRATA_CHECK(it != boundaries.end(), Input,
               "{}: no boundary group (physical {} group) named \"{}\"; the boundary groups are: {}", file,
               dim == 2 ? "curve" : "surface", name, quoted_list(boundary_names()));
  return it->second;
}

// ---- reading -----------------------------------------------------------------------------------
namespace {

std::string lower(std::string s) {
  for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

#if STRATA_WITH_GMSH
/// Corner-node count of gmsh's simplex element types of dimension dim (-1: not a simplex).
int simplex_corners(int type, int dim) {
  std::string name;
  int d = 0, order = 0, nn = 0, nprim = 0;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(type, name, d, order, nn, local, nprim);
  if (d != dim) return -2;  // another dimension: ignore
  const std::string n = lower(name);
  if ((dim == 1 && n.rfind("line", 0) == 0) || (dim == 2 && n.rfind("triangle", 0) == 0) ||
      (dim == 3 && n.rfind("tetrahedron", 0) == 0))
    return nn;
  return -1;
}

/// Appends the simplices of entity (dim, tag) to `cells` (corner nodes, gmsh node tags).
void entity_simplices(int dim, int tag, const std::string& file, std::vector<std::size_t>& cells) {
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> etags, ntags;
  gmsh::model::mesh::getElements(types, etags, ntags, dim, tag);
  for (std::size_t t = 0; t < types.size(); ++t) {
    const int nn = simplex_corners(types[t], dim);
    if (nn == -2) continue;
    if (nn < 0) {
      std::string name;
      int d = 0, order = 0, n = 0, np = 0;
      std::vector<double> local;
      gmsh::model::mesh::getElementProperties(types[t], name, d, order, n, local, np);
      const bool meshed_here = !fs::path(file).extension().string().ends_with("msh");
      fail(ErrorKind::Input,
           "{}: entity {} of dimension {} has {} elements; allowed: triangles (2D) and tetrahedra (3D) {}",
           file, tag, dim, name,
           meshed_here
               ? "(the geometry asks gmsh for them, e.g. Recombine in an Extrude's Layers: strata splits "
                 "quadrangles into triangles itself, but not hexahedra or prisms; remove Recombine)"
               : "(remesh with gmsh, or use a .geo/.step so strata meshes it)");
    }
    const std::size_t ne = etags[t].size();
    for (std::size_t e = 0; e < ne; ++e)
      for (int k = 0; k <= dim; ++k) cells.push_back(ntags[t][e * std::size_t(nn) + std::size_t(k)]);
  }
}

/// gmsh meshes what a file asks for, however fine: a characteristic length of 1e-6 m in a
/// plate of centimetres means some 10^9 triangles and hours of meshing. The curves are meshed
/// first (quick), and their mean element length h gives the count the surfaces (bounding
/// box area / (√3/4·h²)) or volumes (box volume / (√2/12·h³)) would get; a mesh that would
/// need more than half this machine's memory (about 500 bytes per triangle and 1000 per
/// tetrahedron in gmsh and strata) is refused with the estimate before it is made.
void refuse_huge_mesh(const std::string& what, int dim) {
  gmsh::model::mesh::generate(1);
  std::vector<std::size_t> node_tags, line_tags, line_nodes;
  std::vector<double> xyz, param;
  gmsh::model::mesh::getNodes(node_tags, xyz, param, -1, -1, false, false);
  gmsh::model::mesh::getElementsByType(1, line_tags, line_nodes);
  if (line_tags.empty()) return;
  std::unordered_map<std::size_t, std::size_t> index;
  for (std::size_t k = 0; k < node_tags.size(); ++k) index[node_tags[k]] = k;
  double length = 0;
  for (std::size_t e = 0; e < line_tags.size(); ++e) {
    const std::size_t a = index.at(line_nodes[2 * e]), b = index.at(line_nodes[2 * e + 1]);
    length +=
        std::hypot(xyz[3 * a] - xyz[3 * b], xyz[3 * a + 1] - xyz[3 * b + 1], xyz[3 * a + 2] - xyz[3 * b + 2]);
  }
  const double h = length / double(line_tags.size());
  double lo[3], hi[3];
  gmsh::model::getBoundingBox(-1, -1, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  detail::refuse_huge_mesh(what, dim, lo, hi, h,
                           "larger characteristic lengths (lc) in the file, or a mesh_size on the region");
}

Geometry read_gmsh(const fs::path& file, const GeometryOptions& opt) {
  detail::GmshSession gs;
  const std::string what = file.string();
  Geometry g;
  g.file = what;
  gs.run_checked(what, "read this file", [&] { gmsh::open(file.string()); });
  const int dim = gmsh::model::getDimension();
  STRATA_CHECK(
      dim >= 2, Input,
      "{}: the geometry has no surface or volume (its highest dimension is {}); allowed: a 2D geometry "
      "with surfaces or a 3D one with volumes",
      what, dim);
  STRATA_CHECK(opt.dim == 0 || opt.dim == dim, Input,
               "{}: the geometry is {}D but the scene is {}D; allowed: a geometry of the scene's dimension",
               what, dim, opt.dim);
  g.dim = dim;

  // Mesh the geometry unless the file brings a mesh of the top dimension.
  std::vector<std::size_t> probe_tags, probe_nodes;
  gmsh::model::mesh::getElementsByType(dim == 2 ? 2 : 4, probe_tags, probe_nodes);
  if (probe_tags.empty()) {
    // sizes in the file's own unit
    if (opt.mesh_size > 0) gmsh::option::setNumber("Mesh.MeshSizeMax", opt.mesh_size / opt.unit);
    if (opt.mesh_size_min > 0) gmsh::option::setNumber("Mesh.MeshSizeMin", opt.mesh_size_min / opt.unit);
    if (opt.curvature_points > 0) gmsh::option::setNumber("Mesh.MinimumCirclePoints", opt.curvature_points);
    gs.run_checked(what, "mesh this geometry", [&] {
      refuse_huge_mesh(what, dim);
      gmsh::model::mesh::generate(dim);
      // Recombined surfaces (Recombine, structured extrusions of lines) come out as
      // quadrangles: each is split into two triangles.
      if (dim == 2) gmsh::model::mesh::splitQuadrangles();
    });
  }

  g = detail::extract_gmsh_model(what, dim);
  if (opt.unit != 1.0) {  // to metres
    auto scale = [&](SimplexMesh& m) {
      for (auto* c : {&m.x, &m.y, &m.z})
        for (double& v : *c) v *= opt.unit;
    };
    scale(g.mesh);
    for (auto& [name, b] : g.boundaries) scale(b);
  }
  if (dim == 2 && g.mesh.node_count() > 0) {
    // strata's 2D models lie in the xy plane (z = 0): a surface elsewhere would be read by
    // its x and y only, flattened, and filled with nothing.
    const Bounds b = g.mesh.bounds();
    const double span = std::max(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1]);
    STRATA_CHECK(
        std::max(std::abs(b.lo[2]), std::abs(b.hi[2])) <= 1e-9 * std::max(span, 1e-300), Input,
        "{}: the 2D geometry does not lie in the xy plane (z from {:.6g} to {:.6g} m); allowed: surfaces "
        "at z = 0 (2D models are in the xy plane: rotate or move the geometry)",
        what, b.lo[2], b.hi[2]);
  }
  return g;
}
#endif

}  // namespace

#if STRATA_WITH_GMSH
Geometry detail::extract_gmsh_model(const std::string& what, int dim) {
  Geometry g;
  g.file = what;
  g.dim = dim;
  // Nodes (gmsh tags -> compact indices).
  std::vector<std::size_t> tags;
  std::vector<double> xyz, param;
  gmsh::model::mesh::getNodes(tags, xyz, param, -1, -1, false, false);
  std::size_t max_tag = 0;
  for (auto t : tags) max_tag = std::max(max_tag, t);
  std::vector<std::uint32_t> index(max_tag + 1, UINT32_MAX);
  for (std::size_t i = 0; i < tags.size(); ++i) {
    index[tags[i]] = std::uint32_t(i);
    g.mesh.add_node({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
  }
  auto to_index = [&](std::vector<std::size_t>& c) {
    std::vector<std::uint32_t> out(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) out[i] = index[c[i]];
    return out;
  };

  // Elements of the top dimension, entity by entity.
  g.mesh.dim = dim;
  gmsh::vectorpair ents;
  gmsh::model::getEntities(ents, dim);
  g.entity_first_cell.push_back(0);
  for (const auto& [d, tag] : ents) {
    std::vector<std::size_t> cells;
    entity_simplices(dim, tag, what, cells);
    if (cells.empty()) continue;
    const auto c = to_index(cells);
    g.mesh.cells.insert(g.mesh.cells.end(), c.begin(), c.end());
    g.mesh.group_names.push_back(fmt::format("{} {}", dim == 2 ? "surface" : "volume", tag));
    g.mesh.cell_group.resize(g.mesh.cell_count(), std::int32_t(g.mesh.group_names.size() - 1));
    g.entity_tags.push_back(tag);
    g.entity_first_cell.push_back(g.mesh.cell_count());
  }
  STRATA_CHECK(!g.entity_tags.empty(), Input,
               "{}: the geometry has no {} after meshing; allowed: a geometry with "
               "at least one {}",
               what, dim == 2 ? "triangles" : "tetrahedra", dim == 2 ? "surface" : "volume");

  // Physical groups: regions (top dimension) and boundaries (dim - 1).
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups);
  for (const auto& [d, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(d, tag, name);
    if (name.empty()) name = std::to_string(tag);
    std::vector<int> members;
    gmsh::model::getEntitiesForPhysicalGroup(d, tag, members);
    std::sort(members.begin(), members.end());
    if (d == dim) {
      g.regions[name] = members;
    } else if (d == dim - 1) {
      SimplexMesh f;
      f.dim = dim - 1;
      f.x = g.mesh.x, f.y = g.mesh.y, f.z = g.mesh.z;
      for (int m : members) {
        std::vector<std::size_t> cells;
        entity_simplices(dim - 1, m, what, cells);
        const auto c = to_index(cells);
        f.cells.insert(f.cells.end(), c.begin(), c.end());
      }
      f.cell_group.assign(f.cell_count(), -1);
      compact_nodes(f);
      g.boundaries[name] = std::move(f);
    }
  }
  if (g.regions.empty())
    for (std::size_t i = 0; i < g.entity_tags.size(); ++i)
      g.regions[g.mesh.group_names[i]] = {g.entity_tags[i]};
  return g;
}
#endif

Geometry read_geometry(const fs::path& file, const GeometryOptions& opt) {
  const std::string ext = lower(file.extension().string());
  STRATA_CHECK(fs::exists(file), Input, "geometry file {} does not exist", file.string());
  STRATA_CHECK(opt.unit > 0 && std::isfinite(opt.unit), Input, "geometry file {}: unit {} m must be > 0",
               file.string(), opt.unit);
  STRATA_CHECK(fs::is_regular_file(file), Input, "geometry file {} is not a regular file", file.string());
  if (is_surface_file(file)) {
    STRATA_CHECK(opt.dim == 0 || opt.dim == 3, Input,
                 "{}: a closed surface bounds a 3D region but the scene is {}D; allowed in 2D: .geo, .msh, "
                 ".step, .brep",
                 file.string(), opt.dim);
    Geometry g;
    g.file = file.string();
    g.dim = 3;
    g.surface = detail::read_closed_surface(file, opt.unit);
    g.regions[file.stem().string()] = {};
    return g;
  }
  STRATA_CHECK(is_gmsh_file(file), Input, "geometry file {}: unknown extension \"{}\"; {}", file.string(),
               ext, geometry_extensions_text());
#if STRATA_WITH_GMSH
  return read_gmsh(file, opt);
#else
  fail_missing_feature("STRATA_WITH_GMSH", fmt::format("gmsh geometry files such as {}", file.string()));
#endif
}

namespace {
template <std::size_t N>
bool listed(const char* const (&list)[N], const std::string& ext) {
  return std::any_of(std::begin(list), std::end(list), [&](const char* e) { return ext == e; });
}
}  // namespace

bool is_gmsh_file(const fs::path& file) { return listed(kGmshExtensions, lower(file.extension().string())); }
bool is_surface_file(const fs::path& file) {
  return listed(kSurfaceExtensions, lower(file.extension().string()));
}

std::string geometry_extensions_text() {
  return fmt::format("allowed: {} (gmsh) and {} (closed surfaces)", fmt::join(kGmshExtensions, ", "),
                     fmt::join(kSurfaceExtensions, ", "));
}

double distance_to_facet(const SimplexMesh& f, std::size_t e, const Vec3& p) {
  const int np = f.nodes_per_cell();
  auto sub = [](const Vec3& a, const Vec3& b) { return Vec3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  auto dot = [](const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  {
    const Vec3 a = f.node(f.cells[e * np]), b = f.node(f.cells[e * np + 1]);
    if (f.dim == 1) {
      const Vec3 ab = sub(b, a), ap = sub(p, a);
      const double t = std::clamp(dot(ap, ab) / std::max(dot(ab, ab), 1e-300), 0.0, 1.0);
      const Vec3 q{a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
      return std::sqrt(dot(sub(p, q), sub(p, q)));
    }
    // Closest point on triangle (Ericson, Real-Time Collision Detection, 5.1.5).
    const Vec3 c = f.node(f.cells[e * np + 2]);
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    Vec3 q;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    const Vec3 bp = sub(p, b), cp = sub(p, c);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp), d5 = dot(ab, cp), d6 = dot(ac, cp);
    const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (d1 <= 0 && d2 <= 0) {
      q = a;
    } else if (d3 >= 0 && d4 <= d3) {
      q = b;
    } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
      const double v = d1 / (d1 - d3);
      q = {a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2]};
    } else if (d6 >= 0 && d5 <= d6) {
      q = c;
    } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
      const double w = d2 / (d2 - d6);
      q = {a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2]};
    } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
      const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      q = {b[0] + w * (c[0] - b[0]), b[1] + w * (c[1] - b[1]), b[2] + w * (c[2] - b[2])};
    } else {
      const double den = 1 / (va + vb + vc), v = vb * den, w = vc * den;
      q = {a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w};
    }
    return std::sqrt(dot(sub(p, q), sub(p, q)));
  }
}

double distance_to_facets(const SimplexMesh& f, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < f.cell_count(); ++e) best = std::min(best, distance_to_facet(f, e, p));
  return best;
}

}  // namespace strata::preprocess
