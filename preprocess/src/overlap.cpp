// Overlap layers between a particle region and an FEM region (see overlap.hpp, SPEC C3).
#include "strata/preprocess/overlap.hpp"

#include <strata/core/error.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/mesh_fill.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>

#include "gmsh_session.hpp"

namespace strata::preprocess {

namespace {

/// Triangles (2D: 2) or tetrahedra (3D: 6, Kuhn split) of the box [lo, hi].
SimplexMesh box_simplices(int dim, const Vec3& lo, const Vec3& hi) {
  SimplexMesh m;
  m.dim = dim;
  if (dim == 2) {
    m.add_node({lo[0], lo[1], 0});
    m.add_node({hi[0], lo[1], 0});
    m.add_node({hi[0], hi[1], 0});
    m.add_node({lo[0], hi[1], 0});
    m.cells = {0, 1, 2, 0, 2, 3};
  } else {
    for (int k = 0; k < 8; ++k)
      m.add_node({(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]});
    // Kuhn (Freudenthal) split along the diagonal 0-7: one tetrahedron per axis order.
    const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& p : perm) {
      std::uint32_t v = 0;
      m.cells.push_back(v);
      for (int a : p) m.cells.push_back(v |= (1u << a));
    }
  }
  m.cell_group.assign(m.cell_count(), -1);
  return m;
}

/// Boundary facets of the box [lo, hi]: 4 segments (2D) or 12 triangles (3D).
SimplexMesh box_facets(int dim, const Vec3& lo, const Vec3& hi) {
  SimplexMesh f;
  f.dim = dim - 1;
  if (dim == 2) {
    f.add_node({lo[0], lo[1], 0});
    f.add_node({hi[0], lo[1], 0});
    f.add_node({hi[0], hi[1], 0});
    f.add_node({lo[0], hi[1], 0});
    f.cells = {0, 1, 1, 2, 2, 3, 3, 0};
  } else {
    for (int k = 0; k < 8; ++k)
      f.add_node({(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]});
    const std::uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                   {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& c : q) f.cells.insert(f.cells.end(), {c[0], c[1], c[2], c[0], c[2], c[3]});
  }
  f.cell_group.assign(f.cell_count(), -1);
  return f;
}

/// Bit pattern of a point, for exact coincidence.
std::array<std::uint64_t, 3> bits(const Vec3& p) {
  std::array<std::uint64_t, 3> b;
  for (int a = 0; a < 3; ++a) {
    const double v = p[a] == 0 ? 0.0 : p[a];  // -0 == +0
    std::memcpy(&b[a], &v, sizeof v);
  }
  return b;
}

}  // namespace

OverlapModel build_overlap(const Shape& pb, const Shape& fb, const OverlapOptions& opt) {
  const int dim = pb.dim;
  STRATA_CHECK(pb.kind == Shape::Kind::Box && fb.kind == Shape::Kind::Box, Input,
               "overlap: the particle and FEM regions must be boxes (Shape::Kind::Box)");
  STRATA_CHECK(fb.dim == dim && (dim == 2 || dim == 3), Input,
               "overlap: the particle region is {}D and the FEM region {}D; allowed: both 2D or both 3D", dim,
               fb.dim);
  STRATA_CHECK((dim == 2) == (opt.kind == LatticeKind::Hex2D), Input,
               "overlap: lattice kind does not match dimension {}; allowed: Hex2D in 2D, HCP or FCC in 3D",
               dim);
  STRATA_CHECK(opt.d > 0 && std::isfinite(opt.d), Input, "overlap: particle diameter {} must be > 0", opt.d);
  STRATA_CHECK(opt.growth > 0, Input, "overlap: element size growth {} must be > 0", opt.growth);
  const double d = opt.d, r = d / 2;

  OverlapModel m;
  m.dim = dim;
  Vec3 plo = pb.origin;
  const Vec3 flo = fb.origin;
  Vec3 phi{}, fhi{};
  for (int a = 0; a < 3; ++a) phi[a] = plo[a] + pb.size[a], fhi[a] = flo[a] + fb.size[a];
  if (dim == 2) phi[2] = fhi[2] = plo[2] = 0;
  Vec3 flo2 = flo;
  if (dim == 2) flo2[2] = 0;

  // The shared face: the boxes touch along one axis and agree on the others.
  const double tol = 1e-12 * std::max({std::abs(phi[0] - plo[0]), std::abs(phi[1] - plo[1]),
                                       std::abs(phi[2] - plo[2]), std::abs(fhi[0] - flo2[0]), 1.0});
  auto same = [&](double u, double v) { return std::abs(u - v) <= tol; };
  m.axis = -1;
  for (int a = 0; a < dim; ++a) {
    bool lateral_ok = true;
    for (int b = 0; b < dim; ++b)
      if (b != a) lateral_ok = lateral_ok && same(plo[b], flo2[b]) && same(phi[b], fhi[b]);
    if (!lateral_ok) continue;
    if (same(phi[a], flo2[a])) m.axis = a, m.fem_side = 1, m.interface = phi[a];
    if (same(fhi[a], plo[a])) m.axis = a, m.fem_side = -1, m.interface = plo[a];
  }
  STRATA_CHECK(m.axis >= 0, Input,
               "overlap: the particle box and the FEM box must share one whole face (same extent on the "
               "other axes, touching on one)");
  STRATA_CHECK(dim == 2 || m.axis == 2, Input,
               "overlap: in 3D the interface must be normal to z (close-packed layers are planes z = const); "
               "it is normal to {}",
               m.axis == 0 ? "x" : "y");
  const int ax = m.axis, s = m.fem_side;
  const double g = m.interface;

  // Lattice frame with row/layer 0 on Γ: rows along Γ (2D: rotated by 90° for a vertical Γ).
  Vec3 ulo, uhi;
  for (int a = 0; a < 3; ++a) ulo[a] = std::min(plo[a], flo2[a]), uhi[a] = std::max(phi[a], fhi[a]);
  Vec3 origin{ulo[0] + r, ulo[1] + r, dim == 3 ? ulo[2] + r : 0.0};
  origin[ax] = g;
  const LatticeFrame frame(opt.kind, d, dim == 2 && ax == 0 ? 90.0 : 0.0, origin);
  const double L = dim == 2 ? frame.row_spacing() : frame.layer_spacing();
  m.layer_spacing = L;
  const double fem_depth = fb.size[ax];
  STRATA_CHECK(fem_depth >= 3 * L, Input,
               "overlap: the FEM box is {} m deep across the interface; it must be at least 3 layer spacings "
               "({} m) deep",
               fem_depth, 3 * L);
  STRATA_CHECK(pb.size[ax] >= L, Input,
               "overlap: the particle box is {} m deep across the interface; it must be at least one layer "
               "spacing ({} m)",
               pb.size[ax], L);

  // Particles: the sites of the particle box extended 1.5 layers into the FEM box, whole
  // inside the union of the boxes (fill_mesh with a distance r to the union's boundary).
  Vec3 blo = plo, bhi = phi;
  if (s > 0)
    bhi[ax] = g + 1.5 * L;
  else
    blo[ax] = g - 1.5 * L;
  const SimplexMesh fill_box = box_simplices(dim, blo, bhi);
  const SimplexMesh union_facets = box_facets(dim, ulo, uhi);
  const BoundaryDistance dist(union_facets);
  const Lattice sites = fill_mesh(fill_box, frame, BoundaryFilter{&dist, r});

  // Tags by depth: < 0 internal, layer 0 (on Γ) boundary, layer 1 external (SPEC C3).
  const double ltol = 1e-9 * d;
  std::vector<OverlapTag> tags;
  std::vector<std::size_t> order;  // particle order: by depth class, then fill order
  for (int pass = 0; pass < 3; ++pass) {
    for (std::size_t i = 0; i < sites.size(); ++i) {
      const double dep = m.depth(sites.x[i]);
      int cls = -1;
      if (dep < -ltol)
        cls = 0;
      else if (std::abs(dep) <= ltol)
        cls = 1;
      else if (std::abs(dep - L) <= ltol)
        cls = 2;
      if (cls == pass) order.push_back(i), tags.push_back(OverlapTag(cls));
    }
  }
  m.particles.dim = dim;
  m.particles.radius = r;
  for (std::size_t i : order) {
    m.particles.x.push_back(sites.x[i]);
    m.particles.row.push_back(sites.row[i]);
    m.particles.layer.push_back(sites.layer.empty() ? 0 : sites.layer[i]);
  }
  m.particle_tag = std::move(tags);

  std::vector<std::uint32_t> layer0, layer1;
  for (std::uint32_t i = 0; i < m.particles.size(); ++i) {
    if (m.particle_tag[i] == OverlapTag::Boundary) layer0.push_back(i);
    if (m.particle_tag[i] == OverlapTag::External) layer1.push_back(i);
  }
  STRATA_CHECK(!layer0.empty() && !layer1.empty(), Input,
               "overlap: no lattice site on the interface (d = {} m is too large for the boxes)", d);

#if STRATA_WITH_GMSH
  // FEM mesh (gmsh, built-in kernel): the FEM box with the layer-0 sites as points of Γ's
  // curve/surface and the layer-1 sites embedded as mesh points; element size d at Γ,
  // growing linearly away from it.
  const double far = opt.far_size > 0 ? opt.far_size : std::max(d, fem_depth / 4);
  detail::GmshSession gs;
  m.fem = gs.run("overlap FEM mesh", [&] {
    namespace geo = gmsh::model::geo;
    gmsh::model::add("overlap");
    auto point = [&](const Vec3& p) { return geo::addPoint(p[0], p[1], p[2], 0); };
    std::vector<int> embedded;
    const Vec3 lo = flo2, hi = fhi;
    int entity = 0;  // the surface (2D) / volume (3D)
    if (dim == 2) {
      // Corners counter-clockwise; Γ's side is split at the layer-0 sites.
      const Vec3 c[4] = {{lo[0], lo[1], 0}, {hi[0], lo[1], 0}, {hi[0], hi[1], 0}, {lo[0], hi[1], 0}};
      // side k goes from c[k] to c[k+1]; Γ is side 0 (y = lo), 1 (x = hi), 2 (y = hi) or 3 (x = lo)
      const int gamma_side = ax == 1 ? (s > 0 ? 0 : 2) : (s > 0 ? 3 : 1);
      std::vector<int> loop;
      int first = point(c[0]), prev = first;
      for (int k = 0; k < 4; ++k) {
        if (k == gamma_side) {
          std::vector<Vec3> pts;
          for (auto i : layer0) pts.push_back(m.particles.x[i]);
          const int along = 1 - ax;
          const bool up = c[(k + 1) % 4][along] > c[k][along];
          std::sort(pts.begin(), pts.end(), [&](const Vec3& a, const Vec3& b) {
            return up ? a[along] < b[along] : a[along] > b[along];
          });
          for (const auto& p : pts) {
            const int q = point(p);
            loop.push_back(geo::addLine(prev, q));
            prev = q;
          }
        }
        const int next = k == 3 ? first : point(c[k + 1]);
        loop.push_back(geo::addLine(prev, next));
        prev = next;
      }
      entity = geo::addPlaneSurface({geo::addCurveLoop(loop)});
    } else {
      int v[8];
      for (int k = 0; k < 8; ++k)
        v[k] = point({(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]});
      std::map<std::pair<int, int>, int> lines;
      auto line = [&](int a, int b) {
        auto it = lines.find({b, a});
        if (it != lines.end()) return -it->second;
        return lines[{a, b}] = geo::addLine(v[a], v[b]);
      };
      const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
      std::vector<int> faces;
      for (const auto& f : q)
        faces.push_back(geo::addPlaneSurface(
            {geo::addCurveLoop({line(f[0], f[1]), line(f[1], f[2]), line(f[2], f[3]), line(f[3], f[0])})}));
      entity = geo::addVolume({geo::addSurfaceLoop(faces)});
      const int gamma_face = faces[s > 0 ? 0 : 1];  // z = lo or z = hi
      std::vector<int> on_gamma;
      for (auto i : layer0) on_gamma.push_back(point(m.particles.x[i]));
      geo::synchronize();
      gmsh::model::mesh::embed(0, on_gamma, 2, gamma_face);
    }
    for (auto i : layer1) embedded.push_back(point(m.particles.x[i]));
    geo::synchronize();
    gmsh::model::mesh::embed(0, embedded, dim, entity);

    // Size: d at Γ, + growth per metre, at most `far`.
    const char* var = ax == 0 ? "x" : ax == 1 ? "y" : "z";
    const int field = gmsh::model::mesh::field::add("MathEval");
    gmsh::model::mesh::field::setString(
        field, "F",
        fmt::format("min({:.17g}, {:.17g} + {:.17g} * abs({} - ({:.17g})))", far, d, opt.growth, var, g));
    gmsh::model::mesh::field::setAsBackgroundMesh(field);
    gmsh::option::setNumber("Mesh.Algorithm", 5);  // Delaunay: keeps the lattice triangles at the walls
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
    gmsh::model::mesh::generate(dim);
    Geometry geom = detail::extract_gmsh_model("overlap FEM mesh", dim);
    SimplexMesh mesh = std::move(geom.mesh);
    mesh.group_names = {"fem"};
    mesh.cell_group.assign(mesh.cell_count(), 0);
    return mesh;
  });
#else
  fail_missing_feature("STRATA_WITH_GMSH", "overlap FEM meshes");
#endif

  // Coincidence: FEM nodes at overlap sites, bit for bit.
  std::map<std::array<std::uint64_t, 3>, std::uint32_t> site_of;
  for (auto i : layer0) site_of[bits(m.particles.x[i])] = i;
  for (auto i : layer1) site_of[bits(m.particles.x[i])] = i;
  const std::size_t nn = m.fem.node_count();
  m.node_tag.assign(nn, OverlapTag::Internal);
  std::vector<std::uint32_t> node_of(m.particles.size(), UINT32_MAX);
  std::size_t between = 0;
  for (std::uint32_t n = 0; n < nn; ++n) {
    const Vec3 p = m.fem.node(n);
    const auto it = site_of.find(bits(p));
    if (it != site_of.end()) {
      STRATA_CHECK(node_of[it->second] == UINT32_MAX, Internal, "overlap: two FEM nodes at site ({}, {}, {})",
                   p[0], p[1], p[2]);
      node_of[it->second] = n;
      m.node_tag[n] =
          m.particle_tag[it->second] == OverlapTag::Boundary ? OverlapTag::External : OverlapTag::Boundary;
    } else {
      // Away from the side walls (where gmsh's own nodes join the lattice), no node may lie
      // strictly between the two layers.
      bool near_wall = false;
      for (int a = 0; a < dim; ++a)
        if (a != ax) near_wall = near_wall || p[a] < flo2[a] + d || p[a] > fhi[a] - d;
      const double dep = m.depth(p);
      if (!near_wall && dep > ltol && dep < L - ltol) ++between;
    }
  }
  std::size_t missing = 0;
  for (const auto& [key, i] : site_of) {
    if (node_of[i] == UINT32_MAX) {
      ++missing;
      continue;
    }
    m.pair_particle.push_back(i);
  }
  STRATA_CHECK(missing == 0, Internal, "overlap: {} of {} overlap sites have no FEM node at their centre",
               missing, site_of.size());
  STRATA_CHECK(between == 0, Internal,
               "overlap: gmsh put {} FEM nodes strictly between the two overlap layers; the overlap elements "
               "would not be the lattice's",
               between);
  std::sort(m.pair_particle.begin(), m.pair_particle.end());
  for (auto i : m.pair_particle) m.pair_node.push_back(node_of[i]);
  return m;
}

OverlapModel build_overlap(const std::filesystem::path& file, const std::string& particle_region,
                           const std::string& fem_region, const OverlapOptions& opt) {
  GeometryOptions go;
  go.dim = opt.kind == LatticeKind::Hex2D ? 2 : 3;
  const Geometry g = read_geometry(file, go);
  auto as_box = [&](const std::string& name) {
    const GeometryRegion r = g.region(name);
    const Bounds b = r.bounds();
    Shape s;
    s.kind = Shape::Kind::Box;
    s.dim = g.dim;
    s.origin = b.lo;
    for (int a = 0; a < g.dim; ++a) s.size[a] = b.hi[a] - b.lo[a];
    if (g.dim == 2) s.origin[2] = 0;
    const double box = s.measure(), meas = r.measure();
    STRATA_CHECK(std::abs(meas - box) <= 1e-9 * box, Input,
                 "{}: region \"{}\" is not an axis-aligned box (area/volume {} against {} of its bounds); an "
                 "overlap needs two boxes sharing a face",
                 file.string(), name, meas, box);
    return s;
  };
  OverlapModel m = build_overlap(as_box(particle_region), as_box(fem_region), opt);
  m.fem.group_names = {fem_region};
  return m;
}

}  // namespace strata::preprocess
