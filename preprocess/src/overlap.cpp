// Overlap layers between a particle box and FEM boxes: the box path (see overlap.hpp).
#include "strata/preprocess/overlap.hpp"

#include <strata/core/error.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/lattice.hpp>
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

/// The coincidence pairs as single-source copies of weight 1, and the particles' regions
/// (0 on the particle side, -1 for layer 1, which lies in an FEM box).
void add_copy_links(OverlapModel& m) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> to_dem, to_fem;  // (target, source)
  for (std::size_t k = 0; k < m.pair_particle.size(); ++k) {
    const std::uint32_t i = m.pair_particle[k], n = m.pair_node[k];
    if (m.particle_tag[i] == OverlapTag::External)
      to_dem.emplace_back(i, n);
    else
      to_fem.emplace_back(n, i);
  }
  std::sort(to_dem.begin(), to_dem.end());
  std::sort(to_fem.begin(), to_fem.end());
  for (const auto& [t, f] : to_dem) m.fem_to_dem.add(t, {f}, {1.0});
  for (const auto& [t, f] : to_fem) m.dem_to_fem.add(t, {f}, {1.0});
  m.particle_region.resize(m.particles.size());
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    m.particle_region[i] = m.particle_tag[i] == OverlapTag::External ? -1 : 0;
  m.particle_region_names = {"particles"};
}

}  // namespace

void OverlapLinks::add(std::uint32_t to, const std::vector<std::uint32_t>& from,
                       const std::vector<double>& w) {
  STRATA_CHECK(from.size() == w.size() && !from.empty(), Internal,
               "overlap links: target {} has {} sources and {} weights", to, from.size(), w.size());
  if (first.empty()) first.push_back(0);
  target.push_back(to);
  source.insert(source.end(), from.begin(), from.end());
  weight.insert(weight.end(), w.begin(), w.end());
  first.push_back(static_cast<std::uint32_t>(source.size()));
}

OverlapModel build_overlap(const Shape& pb, const Shape& fb, const OverlapOptions& opt) {
  return build_overlap(pb, std::vector<Shape>{fb}, opt);
}

OverlapModel build_overlap(const Shape& pb, const std::vector<Shape>& fem_boxes, const OverlapOptions& opt) {
  const int dim = pb.dim;
  STRATA_CHECK(!fem_boxes.empty() && fem_boxes.size() <= 2, Input,
               "overlap: {} FEM boxes given; allowed: one, or two on opposite sides of the particle box",
               fem_boxes.size());
  STRATA_CHECK(pb.kind == Shape::Kind::Box, Input,
               "overlap: the particle and FEM regions must be boxes (Shape::Kind::Box)");
  check_sites_fit(sites_in(pb.measure(), opt.d, dim), dim,
                  fmt::format("the particle region with particles of diameter {} m", opt.d));
  for (const Shape& fb : fem_boxes) {
    STRATA_CHECK(fb.kind == Shape::Kind::Box, Input,
                 "overlap: the particle and FEM regions must be boxes (Shape::Kind::Box)");
    STRATA_CHECK(fb.dim == dim && (dim == 2 || dim == 3), Input,
                 "overlap: the particle region is {}D and the FEM region {}D; allowed: both 2D or both 3D",
                 dim, fb.dim);
  }
  STRATA_CHECK((dim == 2) == (opt.kind == LatticeKind::Hex2D), Input,
               "overlap: lattice kind does not match dimension {}; allowed: Hex2D in 2D, HCP or FCC in 3D",
               dim);
  STRATA_CHECK(opt.d > 0 && std::isfinite(opt.d), Input, "overlap: particle diameter {} must be > 0", opt.d);
  STRATA_CHECK(opt.growth > 0, Input, "overlap: element size growth {} must be > 0", opt.growth);
  const double d = opt.d, r = d / 2;
  const std::size_t nf = fem_boxes.size();

  OverlapModel m;
  m.dim = dim;
  Vec3 plo = pb.origin, phi{};
  for (int a = 0; a < 3; ++a) phi[a] = plo[a] + pb.size[a];
  if (dim == 2) phi[2] = plo[2] = 0;
  std::vector<Vec3> flo(nf), fhi(nf);  // FEM boxes (z = 0 in 2D)
  for (std::size_t f = 0; f < nf; ++f) {
    flo[f] = fem_boxes[f].origin;
    for (int a = 0; a < 3; ++a) fhi[f][a] = flo[f][a] + fem_boxes[f].size[a];
    if (dim == 2) flo[f][2] = fhi[f][2] = 0;
  }

  // The shared faces: each FEM box touches the particle box along one axis and agrees with
  // it on the others.
  const double tol = 1e-12 * std::max({std::abs(phi[0] - plo[0]), std::abs(phi[1] - plo[1]),
                                       std::abs(phi[2] - plo[2]), std::abs(fhi[0][0] - flo[0][0]), 1.0});
  auto same = [&](double u, double v) { return std::abs(u - v) <= tol; };
  for (std::size_t f = 0; f < nf; ++f) {
    OverlapInterface gi;
    gi.axis = -1;
    gi.fem_group = static_cast<int>(f);
    for (int a = 0; a < dim; ++a) {
      bool lateral_ok = true;
      for (int b = 0; b < dim; ++b)
        if (b != a) lateral_ok = lateral_ok && same(plo[b], flo[f][b]) && same(phi[b], fhi[f][b]);
      if (!lateral_ok) continue;
      if (same(phi[a], flo[f][a])) gi.axis = a, gi.fem_side = 1, gi.coordinate = phi[a];
      if (same(fhi[f][a], plo[a])) gi.axis = a, gi.fem_side = -1, gi.coordinate = plo[a];
    }
    STRATA_CHECK(gi.axis >= 0, Input,
                 "overlap: the particle box and the FEM box{} must share one whole face (same extent on the "
                 "other axes, touching on one)",
                 nf > 1 ? fmt::format(" {}", f) : std::string());
    STRATA_CHECK(
        dim == 2 || gi.axis == 2, Input,
        "overlap: in 3D the interface must be normal to z (close-packed layers are planes z = const); "
        "it is normal to {}",
        gi.axis == 0 ? "x" : "y");
    m.interfaces.push_back(gi);
  }
  if (nf == 2)
    STRATA_CHECK(
        m.interfaces[0].axis == m.interfaces[1].axis && m.interfaces[0].fem_side != m.interfaces[1].fem_side,
        Input,
        "overlap: the two FEM boxes must lie on opposite sides of the particle box across one axis "
        "(FEM | DEM | FEM: the lattice has rows along one direction only); they touch it across {} "
        "(side {:+d}) and {} (side {:+d})",
        "xyz"[m.interfaces[0].axis], m.interfaces[0].fem_side, "xyz"[m.interfaces[1].axis],
        m.interfaces[1].fem_side);
  m.axis = m.interfaces[0].axis;
  m.fem_side = m.interfaces[0].fem_side;
  m.interface = m.interfaces[0].coordinate;
  const int ax = m.axis;
  const double g = m.interface;

  // Lattice frame with row/layer 0 on the first Γ: rows along Γ (2D: rotated by 90° for a
  // vertical Γ).
  Vec3 ulo = plo, uhi = phi;
  for (std::size_t f = 0; f < nf; ++f)
    for (int a = 0; a < 3; ++a) ulo[a] = std::min(ulo[a], flo[f][a]), uhi[a] = std::max(uhi[a], fhi[f][a]);
  Vec3 origin{ulo[0] + r, ulo[1] + r, dim == 3 ? ulo[2] + r : 0.0};
  origin[ax] = g;
  const LatticeFrame frame(opt.kind, d, dim == 2 && ax == 0 ? 90.0 : 0.0, origin);
  const double L = dim == 2 ? frame.row_spacing() : frame.layer_spacing();
  m.layer_spacing = L;
  for (std::size_t f = 0; f < nf; ++f)
    STRATA_CHECK(fem_boxes[f].size[ax] >= 3 * L, Input,
                 "overlap: the FEM box{} is {} m deep across the interface; it must be at least 3 layer "
                 "spacings ({} m) deep",
                 nf > 1 ? fmt::format(" {}", f) : std::string(), fem_boxes[f].size[ax], 3 * L);
  STRATA_CHECK(pb.size[ax] >= L, Input,
               "overlap: the particle box is {} m deep across the interface; it must be at least one layer "
               "spacing ({} m)",
               pb.size[ax], L);
  if (nf == 2) {
    // The second Γ must be a lattice row / layer too: move it (and its FEM box's face) onto
    // the row the lattice frame computes, bit for bit.
    const double depth = pb.size[ax];
    const double n = std::round(depth / L);
    STRATA_CHECK(
        n >= 2 && std::abs(depth - n * L) <= 1e-6 * d, Input,
        "overlap: the particle box is {} m deep between its two FEM boxes; it must be a whole number "
        ">= 2 of layer spacings L = {} m (within 1e-6 d), e.g. {} m or {} m",
        depth, L, std::max(2.0, std::floor(depth / L)) * L, std::max(3.0, std::ceil(depth / L)) * L);
    // Row index of the second Γ: the lattice's local row axis runs along +axis, except for
    // the 90° rotation (2D, Γ normal to x), where local y runs along -x.
    const double sign = dim == 2 && ax == 0 ? -1.0 : 1.0;
    const auto j = static_cast<std::int64_t>(-m.fem_side * sign * n);
    const Vec3 on_row = dim == 2 ? frame.site(0, j, 0) : frame.site(0, 0, j);
    OverlapInterface& g2 = m.interfaces[1];
    g2.coordinate = on_row[ax];
    STRATA_CHECK(std::abs(g2.coordinate - (m.fem_side > 0 ? plo[ax] : phi[ax])) <= 1e-6 * d, Internal,
                 "overlap: lattice row {} at {} is not on the second interface", j, g2.coordinate);
    (g2.fem_side > 0 ? flo[1] : fhi[1])[ax] = g2.coordinate;
    (g2.fem_side > 0 ? phi : plo)[ax] = g2.coordinate;
  }

  // Particles: the sites of the particle box extended 1.5 layers into each FEM box, whole
  // inside the union of the boxes (fill_mesh with a distance r to the union's boundary).
  Vec3 blo = plo, bhi = phi;
  for (const auto& gi : m.interfaces)
    if (gi.fem_side > 0)
      bhi[ax] = gi.coordinate + 1.5 * L;
    else
      blo[ax] = gi.coordinate - 1.5 * L;
  const SimplexMesh fill_box = box_simplices(dim, blo, bhi);
  const SimplexMesh union_facets = box_facets(dim, ulo, uhi);
  const BoundaryDistance dist(union_facets);
  const Lattice sites = fill_mesh(fill_box, frame, BoundaryFilter{&dist, r});

  // Tags by depth from each Γ: layer 0 (on a Γ) boundary, layer 1 (one spacing into that
  // Γ's FEM box) external, every other site (behind all Γ) internal.
  const double ltol = 1e-9 * d;
  std::vector<int> cls(sites.size(), -1), site_gamma(sites.size(), -1);
  for (std::size_t i = 0; i < sites.size(); ++i) {
    bool behind_all = true;
    for (std::size_t k = 0; k < nf; ++k) {
      const double dep = m.interfaces[k].depth(sites.x[i]);
      if (std::abs(dep) <= ltol)
        cls[i] = 1, site_gamma[i] = static_cast<int>(k);
      else if (std::abs(dep - L) <= ltol)
        cls[i] = 2, site_gamma[i] = static_cast<int>(k);
      behind_all = behind_all && dep < -ltol;
    }
    if (cls[i] < 0 && behind_all) cls[i] = 0;
    STRATA_CHECK(cls[i] >= 0, Internal,
                 "overlap: site ({}, {}, {}) is neither behind, on nor one layer past an "
                 "interface",
                 sites.x[i][0], sites.x[i][1], sites.x[i][2]);
  }
  std::vector<std::size_t> order;  // particle order: by depth class, then fill order
  for (int pass = 0; pass < 3; ++pass)
    for (std::size_t i = 0; i < sites.size(); ++i)
      if (cls[i] == pass) order.push_back(i);
  m.particles.dim = dim;
  m.particles.radius = r;
  std::vector<int> gamma_of;  // per particle: its interface, -1 for internal ones
  for (std::size_t i : order) {
    m.particles.x.push_back(sites.x[i]);
    m.particles.row.push_back(sites.row[i]);
    m.particles.layer.push_back(sites.layer.empty() ? 0 : sites.layer[i]);
    m.particle_tag.push_back(OverlapTag(cls[i]));
    gamma_of.push_back(site_gamma[i]);
  }

  std::vector<std::vector<std::uint32_t>> layer0(nf), layer1(nf);
  for (std::uint32_t i = 0; i < m.particles.size(); ++i) {
    if (m.particle_tag[i] == OverlapTag::Boundary) layer0[std::size_t(gamma_of[i])].push_back(i);
    if (m.particle_tag[i] == OverlapTag::External) layer1[std::size_t(gamma_of[i])].push_back(i);
  }
  for (std::size_t f = 0; f < nf; ++f)
    STRATA_CHECK(!layer0[f].empty() && !layer1[f].empty(), Input,
                 "overlap: no lattice site on the interface (d = {} m is too large for the boxes)", d);

#if STRATA_WITH_GMSH
  // FEM mesh (gmsh, built-in kernel): each FEM box with its layer-0 sites as points of its
  // Γ's curve/surface and its layer-1 sites embedded as mesh points; element size d at the
  // nearest Γ, growing linearly away from it.
  double far = opt.far_size;
  if (far <= 0) {
    far = d;
    for (const Shape& fb : fem_boxes) far = std::max(far, fb.size[ax] / 4);
  }
  detail::GmshSession gs;
  m.fem = gs.run("overlap FEM mesh", [&] {
    namespace geo = gmsh::model::geo;
    gmsh::model::add("overlap");
    auto point = [&](const Vec3& p) { return geo::addPoint(p[0], p[1], p[2], 0); };
    std::map<int, int> box_of_entity;  // gmsh surface (2D) / volume (3D) -> FEM box
    for (std::size_t f = 0; f < nf; ++f) {
      const Vec3 lo = flo[f], hi = fhi[f];
      const int s = m.interfaces[f].fem_side;
      int entity = 0;
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
            for (auto i : layer0[f]) pts.push_back(m.particles.x[i]);
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
        for (const auto& fq : q)
          faces.push_back(geo::addPlaneSurface({geo::addCurveLoop(
              {line(fq[0], fq[1]), line(fq[1], fq[2]), line(fq[2], fq[3]), line(fq[3], fq[0])})}));
        entity = geo::addVolume({geo::addSurfaceLoop(faces)});
        const int gamma_face = faces[s > 0 ? 0 : 1];  // z = lo or z = hi
        std::vector<int> on_gamma;
        for (auto i : layer0[f]) on_gamma.push_back(point(m.particles.x[i]));
        geo::synchronize();
        gmsh::model::mesh::embed(0, on_gamma, 2, gamma_face);
      }
      std::vector<int> embedded;
      for (auto i : layer1[f]) embedded.push_back(point(m.particles.x[i]));
      geo::synchronize();
      gmsh::model::mesh::embed(0, embedded, dim, entity);
      box_of_entity[entity] = static_cast<int>(f);
    }

    // Size: d at the nearest Γ, + growth per metre, at most `far`.
    const char* var = ax == 0 ? "x" : ax == 1 ? "y" : "z";
    std::string size = fmt::format("{:.17g}", far);
    for (const auto& gi : m.interfaces)
      size = fmt::format("min({}, {:.17g} + {:.17g} * abs({} - ({:.17g})))", size, d, opt.growth, var,
                         gi.coordinate);
    const int field = gmsh::model::mesh::field::add("MathEval");
    gmsh::model::mesh::field::setString(field, "F", size);
    gmsh::model::mesh::field::setAsBackgroundMesh(field);
    gmsh::option::setNumber("Mesh.Algorithm", 5);  // Delaunay: keeps the lattice triangles at the walls
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
    gmsh::model::mesh::generate(dim);
    Geometry geom = detail::extract_gmsh_model("overlap FEM mesh", dim);
    SimplexMesh mesh = std::move(geom.mesh);
    if (nf == 1)
      mesh.group_names = {"fem"};
    else
      mesh.group_names = {"fem0", "fem1"};
    for (std::size_t e = 0; e < geom.entity_tags.size(); ++e) {
      const auto it = box_of_entity.find(geom.entity_tags[e]);
      STRATA_CHECK(it != box_of_entity.end(), Internal, "overlap: gmsh entity {} is no FEM box",
                   geom.entity_tags[e]);
      for (std::size_t c = geom.entity_first_cell[e]; c < geom.entity_first_cell[e + 1]; ++c)
        mesh.cell_group[c] = it->second;
    }
    return mesh;
  });
#else
  fail_missing_feature("STRATA_WITH_GMSH", "overlap FEM meshes");
#endif

  // Coincidence: FEM nodes at overlap sites, bit for bit.
  std::map<std::array<std::uint64_t, 3>, std::uint32_t> site_of;
  for (std::size_t f = 0; f < nf; ++f) {
    for (auto i : layer0[f]) site_of[bits(m.particles.x[i])] = i;
    for (auto i : layer1[f]) site_of[bits(m.particles.x[i])] = i;
  }
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
      // strictly between the two layers of any interface.
      bool near_wall = false;
      for (int a = 0; a < dim; ++a)
        if (a != ax) near_wall = near_wall || p[a] < ulo[a] + d || p[a] > uhi[a] - d;
      for (const auto& gi : m.interfaces) {
        const double dep = gi.depth(p);
        if (!near_wall && dep > ltol && dep < L - ltol) ++between;
      }
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
  for (auto i : m.pair_particle) {
    m.pair_node.push_back(node_of[i]);
    m.pair_interface.push_back(static_cast<std::uint8_t>(gamma_of[i]));
  }
  add_copy_links(m);
  return m;
}

OverlapModel build_overlap(const std::filesystem::path& file, const std::string& particle_region,
                           const std::string& fem_region, const OverlapOptions& opt) {
  return build_overlap(file, particle_region, std::vector<std::string>{fem_region}, opt);
}

OverlapModel build_overlap(const std::filesystem::path& file, const std::string& particle_region,
                           const std::vector<std::string>& fem_regions, const OverlapOptions& opt) {
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
                 "overlap needs boxes sharing faces",
                 file.string(), name, meas, box);
    return s;
  };
  std::vector<Shape> fem_boxes;
  for (const auto& name : fem_regions) fem_boxes.push_back(as_box(name));
  OverlapModel m = build_overlap(as_box(particle_region), fem_boxes, opt);
  m.fem.group_names = fem_regions;
  m.particle_region_names = {particle_region};
  return m;
}

}  // namespace strata::preprocess
