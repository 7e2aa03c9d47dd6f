// Overlap of particle regions and FEM regions of a gmsh geometry along any interface: the
// general path of build_coupled_model (see overlap.hpp, docs/preprocess.md).
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/lattice.hpp>
#include <strata/preprocess/mesh_fill.hpp>
#include <strata/preprocess/overlap.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

// preprocess does not link Eigen3::Eigen (header-only); its headers are found either way.
#if __has_include(<Eigen/Dense>)
#include <Eigen/Dense>
#else
#include <eigen3/Eigen/Dense>
#endif

#include "gmsh_session.hpp"
#include "site_grid.hpp"

namespace strata::preprocess {

namespace {

constexpr std::uint32_t kNone = UINT32_MAX;

#if STRATA_WITH_GMSH  // the general construction meshes the geometry with gmsh
std::string quoted(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "\"" : ", \"") + n + "\"";
  return s.empty() ? "(none)" : s;
}

double dist2(const Vec3& a, const Vec3& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return dx * dx + dy * dy + dz * dz;
}

/// The conforming mesh of the named regions and which region each element belongs to.
struct Meshed {
  Geometry g;
  std::vector<std::int32_t> particle_of;  ///< per cell of g.mesh: particle region, -1 for none
  std::vector<std::int32_t> fem_of;       ///< per cell of g.mesh: FEM region, -1 for none
  std::size_t gamma_entities = 0;
};

/// Reads the geometry, finds Γ (boundary entities shared by a particle region's entity and
/// an FEM region's), meshes all regions at once with the size field of `opt`.
Meshed mesh_regions(const std::filesystem::path& file, const std::vector<std::string>& particle_regions,
                    const std::vector<std::string>& fem_regions, const OverlapOptions& opt, int want_dim) {
  const std::string what = file.string();
  STRATA_CHECK(std::filesystem::is_regular_file(file), Input,
               "coupled model: geometry file {} does not exist", what);
  detail::GmshSession gs;
  gs.run_checked(what, "read this file", [&] { gmsh::open(file.string()); });
  const int dim = gmsh::model::getDimension();
  STRATA_CHECK(dim == want_dim, Input,
               "{}: the geometry is {}D but the lattice ({}) is {}D; allowed: a hex lattice with a 2D "
               "geometry, hcp or fcc with a 3D one",
               what, dim, opt.kind == LatticeKind::Hex2D ? "hex" : "hcp/fcc", want_dim);

  // Regions: physical groups of the top dimension.
  std::map<std::string, std::vector<int>> regions;
  {
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups, dim);
    for (const auto& [d, tag] : groups) {
      std::string name;
      gmsh::model::getPhysicalName(d, tag, name);
      if (name.empty()) name = std::to_string(tag);
      std::vector<int> members;
      gmsh::model::getEntitiesForPhysicalGroup(d, tag, members);
      auto& v = regions[name];
      v.insert(v.end(), members.begin(), members.end());
    }
  }
  std::vector<std::string> names;
  for (const auto& [n, e] : regions) names.push_back(n);
  std::map<int, std::int32_t> particle_entity, fem_entity;  // entity -> region index
  std::set<std::string> seen;
  auto take = [&](const std::vector<std::string>& list, std::map<int, std::int32_t>& out, const char* kind) {
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::string& name = list[k];
      const auto it = regions.find(name);
      STRATA_CHECK(it != regions.end(), Input,
                   "{}: {} region \"{}\" is not a region of the geometry; allowed: the physical {} groups "
                   "{}",
                   what, kind, name, dim == 2 ? "surface" : "volume", quoted(names));
      STRATA_CHECK(seen.insert(name).second, Input,
                   "{}: region \"{}\" is listed twice; allowed: each region once, either as particles or as "
                   "FEM",
                   what, name);
      for (int e : it->second) out.emplace(e, static_cast<std::int32_t>(k));
    }
  };
  take(particle_regions, particle_entity, "particle");
  take(fem_regions, fem_entity, "FEM");
  for (const auto& [e, k] : particle_entity)
    STRATA_CHECK(!fem_entity.count(e), Input,
                 "{}: {} {} belongs to particle region \"{}\" and to FEM region \"{}\"; allowed: regions "
                 "without common entities",
                 what, dim == 2 ? "surface" : "volume", e, particle_regions[std::size_t(k)],
                 fem_regions[std::size_t(fem_entity.at(e))]);

  // The particle regions' bounding boxes bound their size: a diameter far too small for them
  // is refused here, before gmsh meshes down to it.
  double box_measure = 0;
  for (const auto& [e, k] : particle_entity) {
    double lo[3], hi[3];
    gmsh::model::getBoundingBox(dim, e, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    box_measure += (hi[0] - lo[0]) * (hi[1] - lo[1]) * (dim == 3 ? hi[2] - lo[2] : 1.0);
  }
  check_sites_fit(sites_in(box_measure, opt.d, dim), dim,
                  fmt::format("{}: the particle regions, with particles of diameter {} m,", what, opt.d));

  // Γ: boundary entities of a particle region that also bound an FEM region.
  auto boundary_of = [&](int entity) {
    gmsh::vectorpair out;
    gmsh::model::getBoundary({{dim, entity}}, out, false, false, false);
    std::set<int> b;
    for (const auto& [d, t] : out) b.insert(std::abs(t));
    return b;
  };
  std::set<int> fem_boundary, gamma;
  for (const auto& [e, k] : fem_entity) {
    const auto b = boundary_of(e);
    fem_boundary.insert(b.begin(), b.end());
  }
  std::vector<int> shared(particle_regions.size(), 0);
  for (const auto& [e, k] : particle_entity)
    for (int b : boundary_of(e))
      if (fem_boundary.count(b)) gamma.insert(b), ++shared[std::size_t(k)];
  for (std::size_t k = 0; k < particle_regions.size(); ++k)
    STRATA_CHECK(shared[k] > 0, Input,
                 "{}: particle region \"{}\" shares no boundary {} with any FEM region ({}); allowed: "
                 "particle regions that touch an FEM region along a common {} (build the geometry with "
                 "shared curves/surfaces, e.g. BooleanFragments)",
                 what, particle_regions[k], dim == 2 ? "curve" : "surface", quoted(fem_regions),
                 dim == 2 ? "curve" : "surface");

  // Mesh (unless the file brings one): size d on Γ, + growth per metre, at most far.
  std::vector<std::size_t> probe_tags, probe_nodes;
  gmsh::model::mesh::getElementsByType(dim == 2 ? 2 : 4, probe_tags, probe_nodes);
  if (probe_tags.empty()) {
    double far = opt.far_size;
    if (far <= 0) {
      far = opt.d;
      for (const auto& [e, k] : fem_entity) {
        double lo[3], hi[3];
        gmsh::model::getBoundingBox(dim, e, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
        for (int a = 0; a < dim; ++a) far = std::max(far, (hi[a] - lo[a]) / 4);
      }
    }
    std::vector<double> gamma_tags;
    double diag = 0;
    for (int t : gamma) {
      gamma_tags.push_back(t);
      double lo[3], hi[3];
      gmsh::model::getBoundingBox(dim - 1, t, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
      diag = std::max(diag, std::sqrt(dist2({lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]})));
    }
    // Γ is sampled by the Distance field: about 4 points per diameter along a curve's bounds
    // diagonal (2D); a surface is sampled on an n x n grid, capped for big surfaces (3D).
    const double n = std::ceil(4 * diag / opt.d) + 20;
    gs.run_checked(what, "mesh this geometry", [&] {
      namespace field = gmsh::model::mesh::field;
      const int fd = field::add("Distance");
      field::setNumbers(fd, dim == 2 ? "CurvesList" : "SurfacesList", gamma_tags);
      field::setNumber(fd, "NumPointsPerCurve", dim == 2 ? std::min(n, 1e5) : std::min(n, 400.0));
      const int fm = field::add("MathEval");
      field::setString(fm, "F",
                       fmt::format("min({:.17g}, {:.17g} + {:.17g} * F{})", far, opt.d, opt.growth, fd));
      field::setAsBackgroundMesh(fm);
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
      gmsh::model::mesh::generate(dim);
    });
  }

  Meshed m;
  m.g = detail::extract_gmsh_model(what, dim);
  m.gamma_entities = gamma.size();
  const std::size_t nc = m.g.mesh.cell_count();
  m.particle_of.assign(nc, -1);
  m.fem_of.assign(nc, -1);
  for (std::size_t i = 0; i < m.g.entity_tags.size(); ++i) {
    const int e = m.g.entity_tags[i];
    const auto p = particle_entity.find(e), f = fem_entity.find(e);
    for (std::size_t c = m.g.entity_first_cell[i]; c < m.g.entity_first_cell[i + 1]; ++c) {
      if (p != particle_entity.end()) m.particle_of[c] = p->second;
      if (f != fem_entity.end()) m.fem_of[c] = f->second;
    }
  }
  return m;
}

/// Facets (sorted node indices) of the named cells: Γ (one particle and one FEM cell) and
/// the outer boundary of their union (one cell only), as facet meshes on the cells' nodes.
void split_facets(const Meshed& m, SimplexMesh& gamma, SimplexMesh& outer) {
  const SimplexMesh& mesh = m.g.mesh;
  const int dim = mesh.dim, np = dim + 1;
  struct F {
    std::array<std::uint32_t, 3> key;
    char side;  // 'p' or 'f'
  };
  std::vector<F> facets;
  for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
    const char side = m.particle_of[c] >= 0 ? 'p' : m.fem_of[c] >= 0 ? 'f' : 0;
    if (!side) continue;
    const std::uint32_t* v = &mesh.cells[c * std::size_t(np)];
    for (int skip = 0; skip < np; ++skip) {
      // the facet's nodes, sorted (a 2D facet's unused third slot stays kNone, last)
      std::array<std::uint32_t, 3> k{kNone, kNone, kNone};
      std::size_t n = 0;
      for (int j = 0; j < np; ++j)
        if (j != skip) k[n++] = v[j];
      auto order = [&](std::size_t a, std::size_t b) {
        if (k[b] < k[a]) std::swap(k[a], k[b]);
      };
      order(0, 1), order(1, 2), order(0, 1);
      facets.push_back({k, side});
    }
  }
  std::sort(facets.begin(), facets.end(), [](const F& a, const F& b) { return a.key < b.key; });
  for (SimplexMesh* s : {&gamma, &outer}) {
    s->dim = dim - 1;
    s->x = mesh.x, s->y = mesh.y, s->z = mesh.z;
  }
  for (std::size_t i = 0; i < facets.size();) {
    std::size_t j = i + 1;
    bool p = facets[i].side == 'p', f = facets[i].side == 'f';
    while (j < facets.size() && facets[j].key == facets[i].key) {
      p = p || facets[j].side == 'p', f = f || facets[j].side == 'f';
      ++j;
    }
    SimplexMesh* to = j - i == 1 ? &outer : (p && f) ? &gamma : nullptr;
    if (to) to->cells.insert(to->cells.end(), facets[i].key.begin(), facets[i].key.begin() + dim);
    i = j;
  }
  gamma.cell_group.assign(gamma.cell_count(), -1);
  outer.cell_group.assign(outer.cell_count(), -1);
}

/// Least-squares weights at x over the particles `near` (indices into x_of): the first row
/// of the pseudo-inverse of A = [1, (x_j − x)/R]. Returns the condition number of A.
double fit_weights(const std::vector<std::uint32_t>& near, const std::vector<Vec3>& x_of, const Vec3& x,
                   double R, int dim, std::vector<double>& w) {
  const auto m = static_cast<Eigen::Index>(near.size());
  Eigen::MatrixXd A(m, dim + 1);
  for (Eigen::Index j = 0; j < m; ++j) {
    const Vec3& p = x_of[near[std::size_t(j)]];
    A(j, 0) = 1;
    for (int a = 0; a < dim; ++a) A(j, a + 1) = (p[std::size_t(a)] - x[std::size_t(a)]) / R;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double smin = s(s.size() - 1);
  if (!(smin > 0)) return HUGE_VAL;
  const Eigen::VectorXd row = svd.matrixV().row(0).transpose().cwiseQuotient(s);
  const Eigen::VectorXd wv = svd.matrixU() * row;
  w.assign(wv.data(), wv.data() + wv.size());
  return s(0) / smin;
}

/// Linear shape functions (barycentric coordinates) of the simplex v[0..dim] at p.
std::vector<double> shape_functions(const Vec3* v, int dim, const Vec3& p) {
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int a = 0; a < dim; ++a) {
    for (int k = 0; k < dim; ++k) J(a, k) = v[k + 1][std::size_t(a)] - v[0][std::size_t(a)];
    b(a) = p[std::size_t(a)] - v[0][std::size_t(a)];
  }
  const Eigen::Vector3d l = J.fullPivLu().solve(b);
  std::vector<double> n(std::size_t(dim) + 1);
  double rest = 1;
  for (int k = 0; k < dim; ++k) n[std::size_t(k) + 1] = l(k), rest -= l(k);
  n[0] = rest;
  return n;
}
#endif

OverlapModel build_general(const std::filesystem::path& file,
                           const std::vector<std::string>& particle_regions,
                           const std::vector<std::string>& fem_regions, const OverlapOptions& opt) {
#if STRATA_WITH_GMSH
  const int dim = opt.kind == LatticeKind::Hex2D ? 2 : 3;
  const double d = opt.d, r = d / 2, tol = 1e-9 * d;
  const std::string what = file.string();
  Meshed M = mesh_regions(file, particle_regions, fem_regions, opt, dim);
  const SimplexMesh& mesh = M.g.mesh;
  const std::size_t nc = mesh.cell_count(), nn = mesh.node_count(), np = std::size_t(dim) + 1;
  const std::size_t npr = particle_regions.size(), nfr = fem_regions.size();
  auto cell_node = [&](std::size_t c, std::size_t k) { return mesh.cells[c * np + k]; };

  SimplexMesh gamma, outer;
  split_facets(M, gamma, outer);
  STRATA_CHECK(gamma.cell_count() > 0, Input,
               "{}: the particle and FEM regions share {} boundary entities but no mesh facet; allowed: "
               "regions meshed conformingly along their common boundary",
               what, M.gamma_entities);

  // Γ nodes: used by particle and FEM cells. The ring: particle cells with a Γ node.
  std::vector<char> in_p(nn, 0), in_f(nn, 0);
  for (std::size_t c = 0; c < nc; ++c)
    for (std::size_t k = 0; k < np; ++k) {
      if (M.particle_of[c] >= 0) in_p[cell_node(c, k)] = 1;
      if (M.fem_of[c] >= 0) in_f[cell_node(c, k)] = 1;
    }
  std::vector<std::size_t> ring;
  for (std::size_t c = 0; c < nc; ++c) {
    if (M.particle_of[c] < 0) continue;
    bool touches = false;
    for (std::size_t k = 0; k < np; ++k)
      touches = touches || (in_p[cell_node(c, k)] && in_f[cell_node(c, k)]);
    if (touches) ring.push_back(c);
  }

  // ---- lattice ----
  Vec3 origin{};
  if (opt.origin) {
    origin = *opt.origin;
  } else {
    Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL};
    for (std::size_t n = 0; n < nn; ++n)
      if (in_p[n])
        for (int a = 0; a < 3; ++a)
          lo[std::size_t(a)] = std::min(lo[std::size_t(a)], mesh.node(n)[std::size_t(a)]);
    for (int a = 0; a < 3; ++a) origin[std::size_t(a)] = lo[std::size_t(a)] + r;
  }
  if (dim == 2) origin[2] = 0;
  const LatticeFrame frame(opt.kind, d, opt.orientation_deg, origin);

  // Cells to fill: the particle regions' (region by region), then the FEM cells within 1.5 d
  // of Γ (a band site is within d of Γ). Whole particles inside the union of all regions.
  SimplexMesh fill;
  fill.dim = dim;
  fill.x = mesh.x, fill.y = mesh.y, fill.z = mesh.z;
  std::vector<std::size_t> fill_cell;  // fill cell -> mesh cell
  for (std::size_t k = 0; k < npr; ++k)
    for (std::size_t c = 0; c < nc; ++c)
      if (M.particle_of[c] == std::int32_t(k)) fill_cell.push_back(c);
  const std::size_t n_particle_cells = fill_cell.size();
  {
    const BoundaryDistance near_gamma(gamma);
    for (std::size_t c = 0; c < nc; ++c) {
      if (M.fem_of[c] < 0) continue;
      Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
      for (std::size_t k = 0; k < np; ++k) {
        const Vec3 p = mesh.node(cell_node(c, k));
        for (std::size_t a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
      }
      if (near_gamma.near_box(lo, hi, 1.5 * d)) fill_cell.push_back(c);
    }
  }
  for (std::size_t c : fill_cell)
    fill.cells.insert(fill.cells.end(), &mesh.cells[c * np], &mesh.cells[c * np] + np);
  fill.cell_group.assign(fill_cell.size(), -1);
  const BoundaryDistance outer_dist(outer);
  std::vector<std::size_t> first_site;
  const Lattice sites = fill_mesh(fill, frame, BoundaryFilter{&outer_dist, r}, &first_site);

  // Particle-region sites, in fill order; the candidates of the band with their FEM cell.
  OverlapModel m;
  m.dim = dim;
  m.method = OverlapMethod::General;
  m.particle_region_names = particle_regions;
  Lattice& P = m.particles;
  P.dim = dim;
  P.radius = r;
  std::vector<std::uint32_t> candidates;
  std::vector<std::size_t> site_cell(sites.size());  // mesh cell of each site
  std::vector<std::size_t> per_region(npr, 0);
  for (std::size_t f = 0; f < fill_cell.size(); ++f)
    for (std::size_t s = first_site[f]; s < first_site[f + 1]; ++s) {
      site_cell[s] = fill_cell[f];
      if (f < n_particle_cells) {
        P.x.push_back(sites.x[s]);
        P.row.push_back(sites.row[s]);
        P.layer.push_back(sites.layer[s]);
        m.particle_region.push_back(M.particle_of[fill_cell[f]]);
        ++per_region[std::size_t(M.particle_of[fill_cell[f]])];
      } else {
        candidates.push_back(static_cast<std::uint32_t>(s));
      }
    }
  for (std::size_t k = 0; k < npr; ++k)
    STRATA_CHECK(per_region[k] > 0, Input,
                 "{}: particle region \"{}\" holds no whole particle of diameter {} m; allowed: d smaller "
                 "than the region",
                 what, particle_regions[k], d);
  const std::size_t n_inner = P.size();

  // One grid over the particle-region sites serves the band (radius d) and the fits
  // (radius up to fit_radius_max·d): cells of the larger radius.
  const double r_max = std::max(opt.fit_radius_max, 1.0) * d;
  Lattice inner_sites;  // the same sites, for the grid (the grid keeps a pointer)
  inner_sites.dim = dim;
  inner_sites.radius = r;
  inner_sites.x = P.x;
  const detail::SiteGrid grid({&inner_sites}, r_max * (1 + 1e-9));
  const double touch2 = (d * (1 + 1e-6)) * (d * (1 + 1e-6));
  std::vector<std::size_t> band_cell;
  for (std::uint32_t s : candidates) {
    const Vec3& q = sites.x[s];
    bool touches = false;
    grid.for_each_near(q, [&](std::uint32_t j) { touches = touches || dist2(grid.x(j), q) <= touch2; });
    if (!touches) continue;
    P.x.push_back(q);
    P.row.push_back(sites.row[s]);
    P.layer.push_back(sites.layer[s]);
    m.particle_region.push_back(-1);
    band_cell.push_back(site_cell[s]);
  }

  // ---- FEM mesh: FEM cells (grouped by FEM region, mesh order), then the ring ----
  std::vector<std::size_t> fem_cells;
  std::vector<std::int32_t> fem_group;
  for (std::size_t c = 0; c < nc; ++c)
    if (M.fem_of[c] >= 0) fem_cells.push_back(c), fem_group.push_back(M.fem_of[c]);
  for (std::size_t c : ring)
    fem_cells.push_back(c), fem_group.push_back(std::int32_t(nfr) + M.particle_of[c]);
  std::vector<std::uint32_t> node_of(nn, kNone);  // mesh node -> FEM node
  {
    std::vector<char> used(nn, 0);
    for (std::size_t c : fem_cells)
      for (std::size_t k = 0; k < np; ++k) used[cell_node(c, k)] = 1;
    m.fem.dim = dim;
    for (std::size_t n = 0; n < nn; ++n)
      if (used[n]) node_of[n] = m.fem.add_node(mesh.node(n));
  }
  for (std::size_t c : fem_cells)
    for (std::size_t k = 0; k < np; ++k) m.fem.cells.push_back(node_of[cell_node(c, k)]);
  m.fem.cell_group = fem_group;
  m.fem.group_names = fem_regions;
  for (const auto& n : particle_regions) m.fem.group_names.push_back(n + ":ring");
  m.interface_facets = SimplexMesh{};
  m.interface_facets.dim = dim - 1;
  m.interface_facets.x = m.fem.x, m.interface_facets.y = m.fem.y, m.interface_facets.z = m.fem.z;
  for (std::uint32_t v : gamma.cells) m.interface_facets.cells.push_back(node_of[v]);
  m.interface_facets.cell_group.assign(m.interface_facets.cell_count(), -1);

  const std::size_t nfem = m.fem.node_count();
  m.node_tag.assign(nfem, OverlapTag::Internal);
  m.particle_tag.assign(P.size(), OverlapTag::Internal);
  for (std::size_t n = 0; n < nn; ++n)
    if (node_of[n] != kNone && !in_f[n]) m.node_tag[node_of[n]] = OverlapTag::External;

  // ---- FEM → DEM: band sites by the shape functions of their FEM cell ----
  for (std::size_t b = 0; b < band_cell.size(); ++b) {
    const auto i = static_cast<std::uint32_t>(n_inner + b);
    m.particle_tag[i] = OverlapTag::External;
    const Vec3& p = P.x[i];
    Vec3 v[4];
    std::vector<std::uint32_t> src(np);
    for (std::size_t k = 0; k < np; ++k)
      src[k] = node_of[cell_node(band_cell[b], k)], v[k] = m.fem.node(src[k]);
    std::uint32_t same = kNone;
    for (std::size_t k = 0; k < np; ++k)
      if (dist2(v[k], p) <= tol * tol) same = src[k];
    if (same != kNone)
      m.fem_to_dem.add(i, {same}, {1.0});
    else
      m.fem_to_dem.add(i, src, shape_functions(v, dim, p));
    for (std::uint32_t j = m.fem_to_dem.first[b]; j < m.fem_to_dem.first[b + 1]; ++j)
      m.node_tag[m.fem_to_dem.source[j]] = OverlapTag::Boundary;
  }

  // ---- DEM → FEM: FEM external nodes by a least-squares fit to the particles around ----
  std::vector<std::uint32_t> near;
  std::vector<double> w;
  for (std::uint32_t n = 0; n < nfem; ++n) {
    if (m.node_tag[n] != OverlapTag::External) continue;
    const Vec3 x = m.fem.node(n);
    std::uint32_t same = kNone;
    grid.for_each_near(x, [&](std::uint32_t j) {
      if (same == kNone && dist2(grid.x(j), x) <= tol * tol) same = j;
    });
    if (same != kNone) {
      m.dem_to_fem.add(n, {same}, {1.0});
      m.particle_tag[same] = OverlapTag::Boundary;
      continue;
    }
    double R = opt.fit_radius * d, cond = HUGE_VAL;
    for (;; R += 0.25 * d) {
      near.clear();
      grid.for_each_near(x, [&](std::uint32_t j) {
        if (dist2(grid.x(j), x) <= R * R) near.push_back(j);
      });
      std::sort(near.begin(), near.end());
      cond = near.size() >= 2 * np ? fit_weights(near, P.x, x, R, dim, w) : HUGE_VAL;
      if (cond <= opt.fit_condition || R + 0.25 * d > r_max * (1 + 1e-12)) break;
    }
    STRATA_CHECK(
        cond < 1e6, Input,
        "{}: FEM external node ({:.6g}, {:.6g}, {:.6g}) of the overlap ring has {} particles within "
        "{:.4g} m (condition {:.3g}): too few for a linear fit; allowed: particle regions at least a "
        "few diameters (d = {} m) wide along their interface",
        what, x[0], x[1], x[2], near.size(), R, cond, d);
    m.dem_to_fem.add(n, near, w);
    for (std::uint32_t j : near) m.particle_tag[j] = OverlapTag::Boundary;
  }
  return m;
#else
  (void)file, (void)particle_regions, (void)fem_regions, (void)opt;
  fail_missing_feature("STRATA_WITH_GMSH", "coupled models from geometry files");
#endif
}

/// Whether the regions are one particle box and one or two FEM boxes that share whole faces
/// with it (the box path's rules; build_overlap checks the rest).
bool boxes_sharing_faces(const std::filesystem::path& file, const std::string& particle_region,
                         const std::vector<std::string>& fem_regions, int dim) {
  if (fem_regions.empty() || fem_regions.size() > 2) return false;
  GeometryOptions go;
  go.dim = dim;
  const Geometry g = read_geometry(file, go);
  auto box_of = [&](const std::string& name, Bounds& b) {
    const GeometryRegion r = g.region(name);
    b = r.bounds();
    double box = 1;
    for (int a = 0; a < dim; ++a) box *= b.hi[std::size_t(a)] - b.lo[std::size_t(a)];
    return std::abs(r.measure() - box) <= 1e-9 * box;
  };
  Bounds pb;
  if (!box_of(particle_region, pb)) return false;
  for (const auto& name : fem_regions) {
    Bounds fb;
    if (!box_of(name, fb)) return false;
    double scale = 1;
    for (int a = 0; a < dim; ++a)
      scale = std::max({scale, std::abs(pb.lo[std::size_t(a)]), std::abs(pb.hi[std::size_t(a)])});
    const double t = 1e-12 * scale;
    bool face = false;
    for (int a = 0; a < dim; ++a) {
      bool lateral = true;
      for (int b = 0; b < dim; ++b)
        if (b != a)
          lateral = lateral && std::abs(pb.lo[std::size_t(b)] - fb.lo[std::size_t(b)]) <= t &&
                    std::abs(pb.hi[std::size_t(b)] - fb.hi[std::size_t(b)]) <= t;
      face = face || (lateral && (std::abs(pb.hi[std::size_t(a)] - fb.lo[std::size_t(a)]) <= t ||
                                  std::abs(fb.hi[std::size_t(a)] - pb.lo[std::size_t(a)]) <= t));
    }
    if (!face) return false;
  }
  return true;
}

}  // namespace

OverlapModel build_coupled_model(const std::filesystem::path& geometry,
                                 const std::vector<std::string>& particle_regions,
                                 const std::vector<std::string>& fem_regions, const OverlapOptions& opt) {
  STRATA_CHECK(!particle_regions.empty() && !fem_regions.empty(), Input,
               "{}: coupled model with {} particle and {} FEM regions; allowed: at least one of each",
               geometry.string(), particle_regions.size(), fem_regions.size());
  STRATA_CHECK(opt.d > 0 && std::isfinite(opt.d), Input, "coupled model: particle diameter {} must be > 0",
               opt.d);
  STRATA_CHECK(opt.growth > 0, Input, "coupled model: element size growth {} must be > 0", opt.growth);
  STRATA_CHECK(
      opt.fit_radius > 0 && opt.fit_radius_max >= opt.fit_radius && opt.fit_condition > 1, Input,
      "coupled model: fit radius {} .. {} diameters and condition {}; allowed: 0 < first <= largest, "
      "condition > 1",
      opt.fit_radius, opt.fit_radius_max, opt.fit_condition);
  const int dim = opt.kind == LatticeKind::Hex2D ? 2 : 3;
  if (!opt.force_general && !opt.origin && opt.orientation_deg == 0 && particle_regions.size() == 1 &&
      boxes_sharing_faces(geometry, particle_regions[0], fem_regions, dim)) {
    try {
      return build_overlap(geometry, particle_regions[0], fem_regions, opt);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Input) throw;
      log::info("{}: the box overlap does not apply ({}); using the general construction", geometry.string(),
                e.what());
    }
  }
  return build_general(geometry, particle_regions, fem_regions, opt);
}

}  // namespace strata::preprocess
