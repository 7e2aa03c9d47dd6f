// Overlap layers between a particle box and an FEM box (SPEC C3, docs/preprocess.md).
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/preprocess/ecc.hpp>
#include <strata/preprocess/overlap.hpp>

#include "test_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>

namespace sp = strata::preprocess;
using sp::OverlapTag;

namespace {

sp::Shape box(int dim, sp::Vec3 lo, sp::Vec3 size) {
  sp::Shape s;
  s.kind = sp::Shape::Kind::Box;
  s.dim = dim;
  s.origin = lo;
  s.size = size;
  return s;
}

/// Signed length / area / volume of element e (positive for gmsh's orientation).
double signed_measure(const sp::SimplexMesh& m, std::size_t e) {
  const int np = m.nodes_per_cell();
  const std::uint32_t* c = &m.cells[e * np];
  const sp::Vec3 a = m.node(c[0]), b = m.node(c[1]), cc = m.node(c[2]);
  const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
               ac[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
  if (m.dim == 2) return 0.5 * (ab[0] * ac[1] - ab[1] * ac[0]);
  const sp::Vec3 dd = m.node(c[3]);
  const double ad[3] = {dd[0] - a[0], dd[1] - a[1], dd[2] - a[2]};
  return (ab[0] * (ac[1] * ad[2] - ac[2] * ad[1]) - ab[1] * (ac[0] * ad[2] - ac[2] * ad[0]) +
          ab[2] * (ac[0] * ad[1] - ac[1] * ad[0])) /
         6.0;
}

/// Every check of the brief on one overlap model. fem_box: the FEM region; union_box: both.
void check_overlap(const sp::OverlapModel& m, const sp::Shape& fem_box, const sp::Shape& union_box) {
  const int dim = m.dim;
  const double d = 2 * m.particles.radius, L = m.layer_spacing;
  const std::size_t np = m.particles.size(), nn = m.fem.node_count();
  ASSERT_EQ(m.particle_tag.size(), np);
  ASSERT_EQ(m.node_tag.size(), nn);
  ASSERT_EQ(m.pair_particle.size(), m.pair_node.size());

  // Particle tags follow the depth: < 0 internal, 0 boundary, one layer spacing external.
  std::size_t n_boundary = 0, n_external = 0;
  for (std::size_t i = 0; i < np; ++i) {
    const double dep = m.depth(m.particles.x[i]);
    switch (m.particle_tag[i]) {
      case OverlapTag::Internal:
        EXPECT_LT(dep, -0.5 * L);
        break;
      case OverlapTag::Boundary:
        EXPECT_NEAR(dep, 0.0, 1e-12 * d);
        ++n_boundary;
        break;
      case OverlapTag::External:
        EXPECT_NEAR(dep, L, 1e-12 * d);
        ++n_external;
        break;
    }
    // Whole particles inside the union of the two boxes.
    EXPECT_TRUE(union_box.contains(m.particles.x[i], m.particles.radius * (1 - 1e-9))) << i;
  }
  EXPECT_GT(n_boundary, 5u);
  EXPECT_GT(n_external, 5u);
  EXPECT_EQ(m.pair_particle.size(), n_boundary + n_external);

  // Coincidence: each overlap particle / FEM node in exactly one pair, at the same point;
  // tags swap (DEM boundary = FEM external, DEM external = FEM boundary).
  std::vector<int> in_pair_p(np, 0), in_pair_n(nn, 0);
  for (std::size_t k = 0; k < m.pair_particle.size(); ++k) {
    const auto i = m.pair_particle[k], n = m.pair_node[k];
    ASSERT_LT(i, np);
    ASSERT_LT(n, nn);
    ++in_pair_p[i], ++in_pair_n[n];
    const sp::Vec3 p = m.particles.x[i], q = m.fem.node(n);
    for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(p[a] - q[a]), 1e-12 * d);
    EXPECT_EQ(p, q) << "not bit for bit";
    EXPECT_NE(m.particle_tag[i], OverlapTag::Internal);
    EXPECT_EQ(m.node_tag[n],
              m.particle_tag[i] == OverlapTag::Boundary ? OverlapTag::External : OverlapTag::Boundary);
  }
  for (std::size_t i = 0; i < np; ++i)
    EXPECT_EQ(in_pair_p[i], m.particle_tag[i] == OverlapTag::Internal ? 0 : 1) << "particle " << i;
  for (std::size_t n = 0; n < nn; ++n)
    EXPECT_EQ(in_pair_n[n], m.node_tag[n] == OverlapTag::Internal ? 0 : 1) << "node " << n;

  // Internal FEM nodes coincide with no particle (within d/10: nothing else is close).
  std::map<std::array<long long, 3>, std::vector<std::uint32_t>> grid;
  auto cell = [&](const sp::Vec3& p) {
    return std::array<long long, 3>{std::llround(p[0] / d), std::llround(p[1] / d), std::llround(p[2] / d)};
  };
  for (std::uint32_t i = 0; i < np; ++i) grid[cell(m.particles.x[i])].push_back(i);
  for (std::size_t n = 0; n < nn; ++n) {
    if (m.node_tag[n] != OverlapTag::Internal) continue;
    const sp::Vec3 q = m.fem.node(n);
    const auto c = cell(q);
    for (long long a = -1; a <= 1; ++a)
      for (long long b = -1; b <= 1; ++b)
        for (long long e = -1; e <= 1; ++e) {
          const auto it = grid.find({c[0] + a, c[1] + b, c[2] + e});
          if (it == grid.end()) continue;
          for (auto i : it->second) {
            const sp::Vec3 p = m.particles.x[i];
            const double dist = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
            EXPECT_GT(dist, 0.1 * d) << "internal node " << n << " sits on particle " << i;
          }
        }
  }

  // Valid mesh covering the FEM box: positive measures, total = the box's, nodes inside.
  const std::size_t ne = m.fem.cell_count();
  ASSERT_GT(ne, 0u);
  double total = 0;
  for (std::size_t e = 0; e < ne; ++e) {
    const double v = signed_measure(m.fem, e);
    EXPECT_GT(v, 0) << "element " << e;
    total += v;
  }
  EXPECT_NEAR(total, fem_box.measure(), 1e-9 * fem_box.measure());
  for (std::size_t n = 0; n < nn; ++n) EXPECT_TRUE(fem_box.contains(m.fem.node(n), -1e-12 * d)) << n;

  // The overlap elements are the lattice's: every lattice bond between two overlap
  // particles is an FEM edge, and no FEM node lies strictly between the two layers away
  // from the side walls.
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t e = 0; e < ne; ++e)
    for (int a = 0; a <= dim; ++a)
      for (int b = a + 1; b <= dim; ++b) {
        const auto u = m.fem.cells[e * (dim + 1) + a], v = m.fem.cells[e * (dim + 1) + b];
        edges.insert(std::minmax(u, v));
      }
  std::vector<std::uint32_t> node_of(np, UINT32_MAX);
  for (std::size_t k = 0; k < m.pair_particle.size(); ++k) node_of[m.pair_particle[k]] = m.pair_node[k];
  const sp::BondList bonds = sp::touching_pairs(m.particles);
  const sp::Bounds fb = fem_box.bounds();
  // Lateral distance to the FEM box's side walls.
  auto wall_distance = [&](const sp::Vec3& p) {
    double w = INFINITY;
    for (int a = 0; a < dim; ++a)
      if (a != m.axis) w = std::min({w, p[a] - fb.lo[a], fb.hi[a] - p[a]});
    return w;
  };
  // Along the side walls (the outermost sites, half a diameter from a wall) gmsh's own wall
  // nodes join the lattice and may cut a bond there; at most 5 % of the bonds.
  std::size_t overlap_bonds = 0, cut_at_wall = 0;
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    const auto i = bonds.i[b], j = bonds.j[b];
    if (m.particle_tag[i] == OverlapTag::Internal || m.particle_tag[j] == OverlapTag::Internal) continue;
    ++overlap_bonds;
    if (edges.count(std::minmax(node_of[i], node_of[j]))) continue;
    const double w = std::min(wall_distance(m.particles.x[i]), wall_distance(m.particles.x[j]));
    EXPECT_LT(w, 0.75 * d) << "bond " << i << "-" << j << " is no FEM edge, " << w / d << " d from a wall";
    ++cut_at_wall;
  }
  EXPECT_LE(cut_at_wall, overlap_bonds / 20);
  EXPECT_GT(overlap_bonds, 2 * n_boundary);
  for (std::size_t n = 0; n < nn; ++n) {
    const sp::Vec3 q = m.fem.node(n);
    bool near_wall = false;
    for (int a = 0; a < dim; ++a)
      if (a != m.axis) near_wall = near_wall || q[a] < fb.lo[a] + d || q[a] > fb.hi[a] - d;
    const double dep = m.depth(q);
    if (!near_wall) {
      EXPECT_FALSE(dep > 1e-9 * d && dep < L - 1e-9 * d) << "node " << n << " in the band";
    }
  }

  // Coarsening: mean element size (measure^(1/dim)) in the far half > 2x that in the band.
  const double depth_fem = fem_box.size[m.axis];
  double near_sum = 0, far_sum = 0;
  std::size_t near_n = 0, far_n = 0;
  for (std::size_t e = 0; e < ne; ++e) {
    double c = 0;
    for (int a = 0; a <= dim; ++a) c += m.depth(m.fem.node(m.fem.cells[e * (dim + 1) + a])) / (dim + 1);
    const double h = std::pow(m.fem.cell_measure(e), 1.0 / dim);
    if (c < L) near_sum += h, ++near_n;
    if (c > depth_fem / 2) far_sum += h, ++far_n;
  }
  ASSERT_GT(near_n, 0u);
  ASSERT_GT(far_n, 0u);
  EXPECT_GT(far_sum / far_n, 2 * near_sum / near_n);
  if (std::getenv("STRATA_TEST_VERBOSE"))
    std::printf(
        "particles %zu (boundary %zu, external %zu), FEM nodes %zu, elements %zu, pairs %zu, "
        "overlap bonds %zu, mean size near %.3g far %.3g (d = %.3g)\n",
        np, n_boundary, n_external, nn, ne, m.pair_particle.size(), overlap_bonds, near_sum / near_n,
        far_sum / far_n, d);
}

sp::Shape union_of(const sp::Shape& a, const sp::Shape& b) {
  sp::Vec3 lo, hi;
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::min(a.origin[k], b.origin[k]);
    hi[k] = std::max(a.origin[k] + a.size[k], b.origin[k] + b.size[k]);
  }
  return box(a.dim, lo, {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
}

}  // namespace

#if STRATA_WITH_GMSH

TEST(Overlap, Boxes2DVerticalInterface) {
  // DEM [0, 0.02] x [0, 0.02], FEM [0.02, 0.06] x [0, 0.02], d = 1 mm: Γ is x = 0.02.
  const auto dem = box(2, {0, 0, 0}, {0.02, 0.02, 0}), fem = box(2, {0.02, 0, 0}, {0.04, 0.02, 0});
  sp::OverlapOptions o;
  o.d = 0.001;
  const auto m = sp::build_overlap(dem, fem, o);
  EXPECT_EQ(m.axis, 0);
  EXPECT_EQ(m.fem_side, 1);
  check_overlap(m, fem, union_of(dem, fem));
}

TEST(Overlap, Boxes2DFemBelow) {
  // FEM below the particles: Γ is y = 0.03, the FEM region at smaller y.
  const auto dem = box(2, {0, 0.03, 0}, {0.025, 0.012, 0}), fem = box(2, {0, -0.01, 0}, {0.025, 0.04, 0});
  sp::OverlapOptions o;
  o.d = 0.001;
  const auto m = sp::build_overlap(dem, fem, o);
  EXPECT_EQ(m.axis, 1);
  EXPECT_EQ(m.fem_side, -1);
  check_overlap(m, fem, union_of(dem, fem));
}

TEST(Overlap, Boxes3DHcp) {
  // DEM z in [0, 0.06], FEM z in [0.06, 0.26], 0.1 m square, d = 1 cm.
  const auto dem = box(3, {0, 0, 0}, {0.1, 0.1, 0.06}), fem = box(3, {0, 0, 0.06}, {0.1, 0.1, 0.2});
  sp::OverlapOptions o;
  o.kind = sp::LatticeKind::HCP;
  o.d = 0.01;
  const auto m = sp::build_overlap(dem, fem, o);
  EXPECT_EQ(m.axis, 2);
  check_overlap(m, fem, union_of(dem, fem));
}

TEST(Overlap, Boxes3DFccFemBelow) {
  const auto dem = box(3, {0, 0, 0.1}, {0.08, 0.09, 0.05}), fem = box(3, {0, 0, -0.05}, {0.08, 0.09, 0.15});
  sp::OverlapOptions o;
  o.kind = sp::LatticeKind::FCC;
  o.d = 0.01;
  const auto m = sp::build_overlap(dem, fem, o);
  EXPECT_EQ(m.fem_side, -1);
  check_overlap(m, fem, union_of(dem, fem));
}

TEST(Overlap, TwoBlocksGeometry2D) {
  // two_blocks_2d.geo: "fem" y in [0, 0.05], "dem" y in [0.05, 0.1], 0.1 m wide.
  sp::OverlapOptions o;
  o.d = 0.002;
  const auto m = sp::build_overlap(strata::test::data("two_blocks_2d.geo"), "dem", "fem", o);
  EXPECT_EQ(m.axis, 1);
  EXPECT_EQ(m.fem_side, -1);
  EXPECT_DOUBLE_EQ(m.interface, 0.05);
  EXPECT_EQ(m.fem.group_names, std::vector<std::string>{"fem"});
  check_overlap(m, box(2, {0, 0, 0}, {0.1, 0.05, 0}), box(2, {0, 0, 0}, {0.1, 0.1, 0}));
}

TEST(Overlap, TwoBlocksGeometry3D) {
  // two_blocks_3d.geo: "fem" z in [0, 0.05], "dem" z in [0.05, 0.1], 0.1 m x 0.1 m.
  sp::OverlapOptions o;
  o.kind = sp::LatticeKind::FCC;
  o.d = 0.005;
  o.far_size = 0.02;  // the FEM block is only 10 d deep: grow fast to show coarsening
  o.growth = 1.0;
  const auto m = sp::build_overlap(strata::test::data("two_blocks_3d.geo"), "dem", "fem", o);
  EXPECT_EQ(m.axis, 2);
  EXPECT_EQ(m.fem_side, -1);
  check_overlap(m, box(3, {0, 0, 0}, {0.1, 0.1, 0.05}), box(3, {0, 0, 0}, {0.1, 0.1, 0.1}));
}

TEST(Overlap, RejectsRegionsThatAreNotBoxes) {
  sp::OverlapOptions o;
  o.d = 0.002;
  EXPECT_THROW(sp::build_overlap(strata::test::data("plate_two_holes.geo"), "rock", "rock", o),
               strata::Error);
  EXPECT_THROW(sp::build_overlap(strata::test::data("two_blocks_2d.geo"), "dem", "nope", o), strata::Error);
}

#endif

TEST(Overlap, RejectsBoxesThatDoNotShareAFace) {
  sp::OverlapOptions o;
  o.d = 0.001;
  const auto dem = box(2, {0, 0, 0}, {0.02, 0.02, 0});
  EXPECT_THROW(sp::build_overlap(dem, box(2, {0.021, 0, 0}, {0.04, 0.02, 0}), o), strata::Error);
  EXPECT_THROW(sp::build_overlap(dem, box(2, {0.02, 0.001, 0}, {0.04, 0.02, 0}), o), strata::Error);
  o.kind = sp::LatticeKind::HCP;  // wrong dimension
  EXPECT_THROW(sp::build_overlap(dem, box(2, {0.02, 0, 0}, {0.04, 0.02, 0}), o), strata::Error);
  o.kind = sp::LatticeKind::FCC;  // 3D interface normal to x
  EXPECT_THROW(sp::build_overlap(box(3, {0, 0, 0}, {0.1, 0.1, 0.1}), box(3, {0.1, 0, 0}, {0.1, 0.1, 0.1}), o),
               strata::Error);
}

#if STRATA_WITH_GMSH
// Robustness sweep over diameters, box sizes and size gradings (slow: run with
// --gtest_also_run_disabled_tests).
TEST(Overlap, DISABLED_Sweep) {
  for (double d : {1e-3, 0.73e-3, 0.41e-3})
    for (double growth : {0.2, 0.5, 1.5})
      for (int ax : {0, 1}) {
        SCOPED_TRACE(::testing::Message() << "2D d " << d << " growth " << growth << " axis " << ax);
        sp::Vec3 ds{0.0213, 0.0177, 0}, fs{0.0213, 0.0177, 0}, fo{0, 0, 0};
        fs[ax] = 0.0391, fo[ax] = ds[ax];
        const auto dem = box(2, {0, 0, 0}, ds), fem = box(2, fo, fs);
        sp::OverlapOptions o;
        o.d = d;
        o.growth = growth;
        check_overlap(sp::build_overlap(dem, fem, o), fem, union_of(dem, fem));
      }
  for (auto kind : {sp::LatticeKind::HCP, sp::LatticeKind::FCC})
    for (double d : {0.01, 0.0071})
      for (double growth : {0.3, 1.0}) {
        SCOPED_TRACE(::testing::Message() << "3D d " << d << " growth " << growth);
        const auto dem = box(3, {0, 0, 0}, {0.093, 0.081, 0.05}),
                   fem = box(3, {0, 0, 0.05}, {0.093, 0.081, 0.17});
        sp::OverlapOptions o;
        o.kind = kind;
        o.d = d;
        o.growth = growth;
        check_overlap(sp::build_overlap(dem, fem, o), fem, union_of(dem, fem));
      }
}
#endif
