// Lattices filling geometry regions: counts against area/volume, exactness of the inside
// tests (each site in exactly one element), whole-particle filters, selections and
// thread-independence.
#include <gtest/gtest.h>
#include <strata/config.hpp>

#include <strata/core/error.hpp>
#include <strata/core/parallel.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/lattice.hpp>
#include <strata/preprocess/mesh_fill.hpp>

#include <algorithm>
#include <cmath>
#include <set>

#include "test_util.hpp"

using namespace strata;
using namespace strata::preprocess;
using strata::test::data;

namespace {
constexpr double kHexCell = 0.8660254037844386;  // √3/2: area per site / d²
constexpr double kCpCell = 0.7071067811865476;   // 1/√2: volume per site / d³

/// No two sites at the same place (sites are lattice points: compare exactly).
bool all_distinct(const Lattice& l) {
  std::vector<Vec3> x = l.x;
  std::sort(x.begin(), x.end());
  return std::adjacent_find(x.begin(), x.end()) == x.end();
}

/// Counting centres inside: the count is measure / (area or volume per site) up to the
/// sites near the boundary, whose share falls as 1/size; we compare within 1 % for regions of
/// 2e4 or more sites.
void expect_count_matches_measure(const RegionFill& f, double cell, double tol = 0.01) {
  const double expected = f.measure / cell;
  EXPECT_NEAR(double(f.lattice.size()), expected, tol * expected)
      << "sites " << f.lattice.size() << ", measure/cell " << expected;
}
}  // namespace

TEST(Fill, PlateWithHolesCountMatchesArea) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("plate_two_holes.geo"), {2});
  const GeometryRegion r = g.region("rock");
  const double d = 1e-3;
  for (double angle : {0.0, 30.0, 17.0}) {
    FillOptions o;
    o.kind = LatticeKind::Hex2D;
    o.d = d;
    o.orientation_deg = angle;
    const RegionFill f = fill_region(r, o);
    expect_count_matches_measure(f, kHexCell * d * d);
    EXPECT_NEAR(f.packing, M_PI / (2 * std::sqrt(3.0)), 0.01 * f.packing);
    EXPECT_TRUE(all_distinct(f.lattice));
    for (std::size_t i = 0; i < f.lattice.size(); i += 97) EXPECT_TRUE(r.contains(f.lattice.x[i]));
  }
}

TEST(Fill, WholeParticlesStayInside) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("plate_two_holes.geo"), {2});
  const GeometryRegion r = g.region("rock");
  const double d = 1e-3, rad = d / 2;
  FillOptions o;
  o.d = d;
  o.min_boundary_distance = rad;
  const RegionFill f = fill_region(r, o);
  const BoundaryDistance dist(r.boundary);
  for (const auto& p : f.lattice.x) EXPECT_GE(dist(p), rad - 1e-9 * d);
  // Centres lie in the region shrunk by r: (W - 2r)(H - 2r) - 2π(R + r)².
  const double shrunk = (0.2 - d) * (0.1 - d) - 2 * M_PI * (0.01 + rad) * (0.01 + rad);
  EXPECT_NEAR(double(f.lattice.size()), shrunk / (kHexCell * d * d), 0.01 * shrunk / (kHexCell * d * d));
}

TEST(Fill, SameSitesAsTheBoxLatticesForRectangles) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads .geo files: needs STRATA_WITH_GMSH";
  // A rectangle and a slab from files, filled with whole particles from the corner + d/2,
  // hold exactly the sites of lattice.hpp's box lattices.
  const double d = 2e-3;
  FillOptions o;
  o.d = d;
  o.min_boundary_distance = d / 2;
  const RegionFill f2 = fill_region(read_geometry(data("t1_rectangle.geo")).region("My surface"), o);
  EXPECT_EQ(f2.lattice.size(), hex2d_box(0, 0, 0.1, 0.3, d).size());
  const double d3 = 5e-3;
  for (auto [kind, packing] :
       {std::pair{LatticeKind::HCP, Packing::HCP}, std::pair{LatticeKind::FCC, Packing::FCC}}) {
    o.kind = kind;
    o.d = d3;
    o.min_boundary_distance = d3 / 2;
    const RegionFill f3 = fill_region(read_geometry(data("t2_extruded.geo")).region("slab"), o);
    EXPECT_EQ(f3.lattice.size(), close_packed_box(packing, {0, 0, 0}, {0.1, 0.3, 0.05}, d3).size());
    EXPECT_TRUE(all_distinct(f3.lattice));
  }
}

TEST(Fill, CubeCountsMatchVolumeForHcpAndFcc) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("cube.geo"), {3});
  const GeometryRegion r = g.region("block");
  const double d = 0.025;
  for (auto kind : {LatticeKind::HCP, LatticeKind::FCC}) {
    for (double angle : {0.0, 23.0}) {
      FillOptions o;
      o.kind = kind;
      o.d = d;
      o.orientation_deg = angle;
      const RegionFill f = fill_region(r, o);
      expect_count_matches_measure(f, kCpCell * d * d * d);
      EXPECT_NEAR(f.packing, M_PI / (3 * std::sqrt(2.0)), 0.01 * f.packing);
      EXPECT_TRUE(all_distinct(f.lattice));
    }
  }
}

TEST(Fill, ClosedStlSurfaces) {
  if (!STRATA_WITH_CGAL) GTEST_SKIP() << "reads closed STL surfaces: needs STRATA_WITH_CGAL";
  const auto box = test::scratch("fill_box.stl");
  test::write_stl(box, test::box_triangles({0, 0, 0}, {1, 0.5, 0.4}));
  const auto ball = test::scratch("fill_ball.stl");
  test::write_stl(ball, test::icosphere({0, 0, 0}, 0.5, 4));
  const double d = 0.02;
  FillOptions o;
  o.kind = LatticeKind::FCC;
  o.d = d;
  // A box: exactly the sites of the lattice in the closed box (those on the surface count
  // as inside). Its count is not within 1 % of volume/cell: 24 layers of 0.0163 m fill
  // 0.392 m of the 0.4 m height (a boundary effect of up to one layer per axis).
  const RegionFill fb = fill_region(read_geometry(box).region(""), o);
  const LatticeFrame fr(LatticeKind::FCC, d, 0, {d / 2, d / 2, d / 2});
  std::size_t in_box = 0;
  for (int k = -5; k < 40; ++k)
    for (int j = -5; j < 40; ++j)
      for (int i = -5; i < 60; ++i) {
        const Vec3 p = fr.site(i, j, k);
        in_box += p[0] >= 0 && p[0] <= 1 && p[1] >= 0 && p[1] <= 0.5 && p[2] >= 0 && p[2] <= 0.4;
      }
  EXPECT_EQ(fb.lattice.size(), in_box);
  const RegionFill fs = fill_region(read_geometry(ball).region(""), o);
  expect_count_matches_measure(fs, kCpCell * d * d * d);
  // Whole particles: every centre at least d/2 from the surface.
  o.min_boundary_distance = d / 2;
  const GeometryRegion rs = read_geometry(ball).region("");
  const RegionFill fw = fill_region(rs, o);
  for (const auto& p : fw.lattice.x)
    EXPECT_LE(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), 0.5 - d / 2 + 1e-9);
  EXPECT_LT(fw.lattice.size(), fs.lattice.size());
}

TEST(MeshFill, EverySiteInExactlyOneElement2D) {
  // A mesh whose nodes are lattice sites: the hexagonal lattice's own triangles. Every
  // site is a vertex of six triangles, yet must be listed once.
  const LatticeFrame fr(LatticeKind::Hex2D, 1.0, 12.0, {0.3, -0.2, 0});
  const int n = 20;
  SimplexMesh m;
  m.dim = 2;
  auto id = [&](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.add_node(fr.site(i - j / 2, j, 0));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // node (i, j) sits at x = (i - j/2)·d: (i, j + 1) is up-left, (i + 1, j + 1) up-right
      const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), e = id(i, j + 1);
      m.cells.insert(m.cells.end(), {a, b, c, a, c, e});
    }
  m.cell_group.assign(m.cell_count(), -1);
  const Lattice l = fill_mesh(m, fr);
  EXPECT_TRUE(all_distinct(l));
  // Every node not on the outer boundary of the mesh appears.
  std::set<Vec3> got(l.x.begin(), l.x.end());
  std::size_t interior = 0;
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i) {
      ++interior;
      EXPECT_TRUE(got.count(m.node(id(i, j)))) << i << ' ' << j;
    }
  EXPECT_GE(l.size(), interior);
}

TEST(MeshFill, EverySiteInExactlyOneElement3D) {
  // A grid of cubes split into six tetrahedra each (all sharing the cube's main diagonal),
  // filled with an FCC lattice commensurate with the grid: many sites lie on shared faces,
  // edges and nodes. Each site strictly inside the box must appear exactly once.
  const int n = 4;
  const double a = 1.0;
  SimplexMesh m;
  m.dim = 3;
  auto id = [&](int i, int j, int k) { return std::uint32_t((k * (n + 1) + j) * (n + 1) + i); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m.add_node({i * a, j * a, k * a});
  const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& p : perm) {
          int c[3] = {i, j, k};
          std::uint32_t t[4];
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          m.cells.insert(m.cells.end(), t, t + 4);
        }
  m.cell_group.assign(m.cell_count(), -1);
  EXPECT_NEAR(m.measure(), n * n * n, 1e-9);
  const LatticeFrame fr(LatticeKind::FCC, 0.25, 0.0, {0, 0, 0});
  FillStats stats;
  const Lattice l = fill_mesh(m, fr, {}, nullptr, &stats);
  EXPECT_TRUE(all_distinct(l));
  EXPECT_GT(stats.exact_tests, 0u);  // sites on faces went through the exact predicates
  std::set<Vec3> got(l.x.begin(), l.x.end());
  std::size_t inside = 0, missing = 0;
  for (int k = -2; k <= 40; ++k)
    for (int j = -4; j <= 40; ++j)
      for (int i = -4; i <= 40; ++i) {
        const Vec3 p = fr.site(i, j, k);
        bool in = true;
        for (int c = 0; c < 3; ++c) in = in && p[c] > 1e-9 && p[c] < n * a - 1e-9;
        if (!in) continue;
        ++inside;
        missing += got.count(p) ? 0 : 1;
      }
  EXPECT_EQ(missing, 0u) << "of " << inside;
  EXPECT_GE(l.size(), inside);
}

TEST(MeshFill, SameResultForAnyNumberOfThreads) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("cube.geo"), {3});
  const GeometryRegion r = g.region("block");
  FillOptions o;
  o.kind = LatticeKind::HCP;
  o.d = 0.04;
  o.orientation_deg = 10;
  o.min_boundary_distance = 0.02;
  const int before = par::threads();
  par::set_threads(1);
  const RegionFill a = fill_region(r, o);
  par::set_threads(2);
  const RegionFill b = fill_region(r, o);
  par::set_threads(before);
  EXPECT_EQ(a.lattice.x, b.lattice.x);
  EXPECT_EQ(a.lattice.row, b.lattice.row);
  EXPECT_EQ(a.lattice.layer, b.lattice.layer);
}

TEST(Selections, HoleRimsAndPhysicalGroups) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("plate_two_holes.geo"), {2});
  const GeometryRegion r = g.region("rock");
  const double d = 1e-3;
  FillOptions o;
  o.d = d;
  o.min_boundary_distance = d / 2;
  const RegionFill f = fill_region(r, o);
  for (int hole : {1, 2}) {
    const auto rim = hole_rim(r, f.lattice, hole, d);
    const double cx = hole == 1 ? 0.05 : 0.15;
    // A ring of particles around the hole (centres within d of the rim, at least d/2 from it).
    EXPECT_GT(rim.size(), 30u);
    EXPECT_LT(rim.size(), 200u);
    for (auto i : rim) {
      const auto& p = f.lattice.x[i];
      EXPECT_LE(std::hypot(p[0] - cx, p[1] - 0.05), 0.01 + d + 1e-6);
    }
    const auto by_name = physical_group_members(g, f, hole == 1 ? "hole1" : "hole2", d);
    EXPECT_EQ(by_name.size(), rim.size());
  }
  EXPECT_THROW(hole_rim(r, f.lattice, 3, d), Error);
  EXPECT_THROW(physical_group_members(g, f, "nothing", d), Error);
  // Region physical groups: the two blocks of a geometry partition the whole.
  const Geometry two = read_geometry(data("two_blocks_3d.geo"), {3});
  FillOptions o3;
  o3.kind = LatticeKind::FCC;
  o3.d = 0.004;
  o3.origin = Vec3{0.002, 0.002, 0.002};
  const RegionFill all = fill_region(two.region(""), o3);
  const auto dem = physical_group_members(two, all, "dem", 0);
  const auto fem = physical_group_members(two, all, "fem", 0);
  EXPECT_EQ(dem.size() + fem.size(), all.lattice.size());
  for (auto i : dem) EXPECT_GE(all.lattice.x[i][2], 0.05 - 1e-12);
  for (auto i : fem) EXPECT_LE(all.lattice.x[i][2], 0.05 + 1e-12);
  // Filling the regions on their own with the same origin gives the same sites.
  EXPECT_EQ(fill_region(two.region("dem"), o3).lattice.size(), dem.size());
}
