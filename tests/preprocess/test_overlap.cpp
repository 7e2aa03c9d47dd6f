// Overlap layers between a particle box and an FEM box: the box path (docs/preprocess.md).
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

/// Every check of the brief on one overlap model. fem_boxes: the FEM regions, in the order
/// of the interfaces (fem_boxes[k] is group k of the mesh); union_box: all regions.
void check_overlap(const sp::OverlapModel& m, const std::vector<sp::Shape>& fem_boxes,
                   const sp::Shape& union_box) {
  const int dim = m.dim;
  const double d = 2 * m.particles.radius, L = m.layer_spacing;
  const std::size_t np = m.particles.size(), nn = m.fem.node_count(), nf = fem_boxes.size();
  ASSERT_EQ(m.particle_tag.size(), np);
  ASSERT_EQ(m.node_tag.size(), nn);
  ASSERT_EQ(m.pair_particle.size(), m.pair_node.size());
  ASSERT_EQ(m.pair_interface.size(), m.pair_node.size());
  ASSERT_EQ(m.interfaces.size(), nf);
  EXPECT_EQ(m.interfaces[0].axis, m.axis);
  EXPECT_EQ(m.interfaces[0].fem_side, m.fem_side);
  EXPECT_EQ(m.interfaces[0].coordinate, m.interface);
  ASSERT_EQ(m.fem.group_names.size(), nf);
  for (std::size_t k = 0; k < nf; ++k) EXPECT_EQ(m.interfaces[k].fem_group, int(k));

  // The interface of each overlap particle (from the pairs).
  std::vector<int> gamma(np, -1);
  for (std::size_t k = 0; k < m.pair_particle.size(); ++k) {
    ASSERT_LT(m.pair_particle[k], np);
    ASSERT_LT(m.pair_interface[k], nf);
    gamma[m.pair_particle[k]] = m.pair_interface[k];
  }

  // Particle tags follow the depth from their Γ: boundary on it, external one layer spacing
  // into its FEM box; internal particles are behind every Γ.
  std::vector<std::size_t> n_boundary(nf, 0), n_external(nf, 0);
  for (std::size_t i = 0; i < np; ++i) {
    switch (m.particle_tag[i]) {
      case OverlapTag::Internal:
        EXPECT_EQ(gamma[i], -1);
        for (const auto& g : m.interfaces) EXPECT_LT(g.depth(m.particles.x[i]), -0.5 * L);
        break;
      case OverlapTag::Boundary:
        ASSERT_GE(gamma[i], 0) << i;
        EXPECT_NEAR(m.interfaces[gamma[i]].depth(m.particles.x[i]), 0.0, 1e-12 * d);
        ++n_boundary[gamma[i]];
        break;
      case OverlapTag::External:
        ASSERT_GE(gamma[i], 0) << i;
        EXPECT_NEAR(m.interfaces[gamma[i]].depth(m.particles.x[i]), L, 1e-12 * d);
        ++n_external[gamma[i]];
        break;
    }
    // Whole particles inside the union of the boxes.
    EXPECT_TRUE(union_box.contains(m.particles.x[i], m.particles.radius * (1 - 1e-9))) << i;
  }
  std::size_t n_overlap = 0;
  for (std::size_t k = 0; k < nf; ++k) {
    EXPECT_GT(n_boundary[k], 5u) << "interface " << k;
    EXPECT_GT(n_external[k], 5u) << "interface " << k;
    n_overlap += n_boundary[k] + n_external[k];
  }
  EXPECT_EQ(m.pair_particle.size(), n_overlap);

  // Coincidence: each overlap particle / FEM node in exactly one pair, at the same point;
  // tags swap (DEM boundary = FEM external, DEM external = FEM boundary).
  std::vector<int> in_pair_p(np, 0), in_pair_n(nn, 0);
  for (std::size_t k = 0; k < m.pair_particle.size(); ++k) {
    const auto i = m.pair_particle[k], n = m.pair_node[k];
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

  // Valid mesh covering each FEM box with its own element group: positive measures, the
  // group's total = its box's, its nodes inside its box.
  const std::size_t ne = m.fem.cell_count();
  ASSERT_GT(ne, 0u);
  ASSERT_EQ(m.fem.cell_group.size(), ne);
  std::vector<double> total(nf, 0.0);
  const int npc = dim + 1;
  for (std::size_t e = 0; e < ne; ++e) {
    const double v = signed_measure(m.fem, e);
    EXPECT_GT(v, 0) << "element " << e;
    const int grp = m.fem.cell_group[e];
    ASSERT_TRUE(grp >= 0 && std::size_t(grp) < nf) << "element " << e;
    total[std::size_t(grp)] += v;
    for (int a = 0; a < npc; ++a)
      EXPECT_TRUE(fem_boxes[std::size_t(grp)].contains(m.fem.node(m.fem.cells[e * npc + a]), -1e-12 * d))
          << e;
  }
  for (std::size_t k = 0; k < nf; ++k)
    EXPECT_NEAR(total[k], fem_boxes[k].measure(), 1e-9 * fem_boxes[k].measure()) << "FEM box " << k;

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
  const sp::Bounds fb = fem_boxes[0].bounds();  // all FEM boxes have the particle box's lateral extent
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
    if (gamma[i] != gamma[j]) continue;  // a strip one spacing thick would bond the two interfaces
    ++overlap_bonds;
    if (edges.count(std::minmax(node_of[i], node_of[j]))) continue;
    const double w = std::min(wall_distance(m.particles.x[i]), wall_distance(m.particles.x[j]));
    EXPECT_LT(w, 0.75 * d) << "bond " << i << "-" << j << " is no FEM edge, " << w / d << " d from a wall";
    ++cut_at_wall;
  }
  EXPECT_LE(cut_at_wall, overlap_bonds / 20);
  std::size_t all_boundary = 0;
  for (auto c : n_boundary) all_boundary += c;
  EXPECT_GT(overlap_bonds, 2 * all_boundary);
  for (std::size_t n = 0; n < nn; ++n) {
    const sp::Vec3 q = m.fem.node(n);
    bool near_wall = false;
    for (int a = 0; a < dim; ++a)
      if (a != m.axis) near_wall = near_wall || q[a] < fb.lo[a] + d || q[a] > fb.hi[a] - d;
    if (near_wall) continue;
    for (const auto& g : m.interfaces) {
      const double dep = g.depth(q);
      EXPECT_FALSE(dep > 1e-9 * d && dep < L - 1e-9 * d) << "node " << n << " in the band";
    }
  }

  // Coarsening, per FEM box: mean element size (measure^(1/dim)) in its far half > 2x that
  // in its band.
  for (std::size_t k = 0; k < nf; ++k) {
    const auto& g = m.interfaces[k];
    const double depth_fem = fem_boxes[k].size[m.axis];
    double near_sum = 0, far_sum = 0;
    std::size_t near_n = 0, far_n = 0;
    for (std::size_t e = 0; e < ne; ++e) {
      if (m.fem.cell_group[e] != g.fem_group) continue;
      double c = 0;
      for (int a = 0; a <= dim; ++a) c += g.depth(m.fem.node(m.fem.cells[e * (dim + 1) + a])) / (dim + 1);
      const double h = std::pow(m.fem.cell_measure(e), 1.0 / dim);
      if (c < L) near_sum += h, ++near_n;
      if (c > depth_fem / 2) far_sum += h, ++far_n;
    }
    ASSERT_GT(near_n, 0u);
    ASSERT_GT(far_n, 0u);
    EXPECT_GT(far_sum / far_n, 2 * near_sum / near_n) << "FEM box " << k;
    if (std::getenv("STRATA_TEST_VERBOSE"))
      std::printf("FEM box %zu: mean size near %.3g far %.3g (d = %.3g)\n", k, near_sum / near_n,
                  far_sum / far_n, d);
  }
  if (std::getenv("STRATA_TEST_VERBOSE"))
    std::printf("particles %zu, FEM nodes %zu, elements %zu, pairs %zu, overlap bonds %zu\n", np, nn, ne,
                m.pair_particle.size(), overlap_bonds);
}

[[maybe_unused]] void check_overlap(const sp::OverlapModel& m, const sp::Shape& fem_box,
                                    const sp::Shape& union_box) {
  check_overlap(m, std::vector<sp::Shape>{fem_box}, union_box);
}

[[maybe_unused]] sp::Shape union_of(const sp::Shape& a, const sp::Shape& b) {
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

// FEM | DEM | FEM: a particle strip 20 row spacings wide between two FEM blocks (Γ normal
// to x). One lattice, one FEM mesh with a group per block, tags and coincidence exact at
// both interfaces (check_overlap: bit-for-bit pairs, lattice edges in the mesh).
TEST(Overlap, Embedded2DStripBetweenTwoFemBoxes) {
  const double d = 0.001, L = d * std::sqrt(3.0) / 2, w = 20 * L;
  const auto fem0 = box(2, {0, 0, 0}, {0.03, 0.015, 0}), dem = box(2, {0.03, 0, 0}, {w, 0.015, 0}),
             fem1 = box(2, {0.03 + w, 0, 0}, {0.025, 0.015, 0});
  sp::OverlapOptions o;
  o.d = d;
  const auto m = sp::build_overlap(dem, {fem0, fem1}, o);
  ASSERT_EQ(m.interfaces.size(), 2u);
  EXPECT_EQ(m.axis, 0);
  EXPECT_EQ(m.interfaces[0].fem_side, -1);
  EXPECT_EQ(m.interfaces[1].fem_side, 1);
  EXPECT_EQ(m.interfaces[0].coordinate, 0.03);
  EXPECT_NEAR(m.interfaces[1].coordinate, 0.03 + w, 1e-12 * d);
  EXPECT_EQ(m.fem.group_names, (std::vector<std::string>{"fem0", "fem1"}));
  check_overlap(m, {fem0, fem1}, union_of(union_of(fem0, dem), fem1));
  // Every lattice row of the strip, both interfaces' rows included, and one external row
  // on each side: 21 + 2 columns of particles.
  std::set<long> columns;
  for (const auto& p : m.particles.x) columns.insert(std::lround((p[0] - 0.03) / L));
  EXPECT_EQ(columns.size(), 23u);
  EXPECT_EQ(*columns.begin(), -1);
  EXPECT_EQ(*columns.rbegin(), 21);
}

// The same from a geometry file, Γ normal to y, the first FEM region above the particles;
// the element groups take the regions' names.
TEST(Overlap, EmbeddedGeometryFemAboveAndBelow) {
  const auto geo = strata::test::scratch("embedded_2d.geo");
  std::ofstream(geo) << "L = 0.002*Sqrt(3)/2; y1 = 0.03; y2 = y1 + 12*L; y3 = y2 + 0.03;\n"
                        "Point(1) = {0, 0, 0}; Point(2) = {0.04, 0, 0}; Point(3) = {0.04, y1, 0};\n"
                        "Point(4) = {0, y1, 0}; Point(5) = {0.04, y2, 0}; Point(6) = {0, y2, 0};\n"
                        "Point(7) = {0.04, y3, 0}; Point(8) = {0, y3, 0};\n"
                        "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
                        "Line(5) = {3, 5}; Line(6) = {5, 6}; Line(7) = {6, 4};\n"
                        "Line(8) = {5, 7}; Line(9) = {7, 8}; Line(10) = {8, 6};\n"
                        "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
                        "Curve Loop(2) = {5, 6, 7, -3}; Plane Surface(2) = {2};\n"
                        "Curve Loop(3) = {8, 9, 10, -6}; Plane Surface(3) = {3};\n"
                        "Physical Surface(\"below\") = {1}; Physical Surface(\"strip\") = {2};\n"
                        "Physical Surface(\"above\") = {3};\n";
  const double d = 0.002, L = d * std::sqrt(3.0) / 2, y2 = 0.03 + 12 * L;
  sp::OverlapOptions o;
  o.d = d;
  const std::vector<std::string> regions{"above", "below"};
  const auto m = sp::build_overlap(geo, "strip", regions, o);
  ASSERT_EQ(m.interfaces.size(), 2u);
  EXPECT_EQ(m.axis, 1);
  EXPECT_EQ(m.interfaces[0].fem_side, 1);
  EXPECT_EQ(m.interfaces[1].fem_side, -1);
  EXPECT_NEAR(m.interface, y2, 1e-12);
  EXPECT_NEAR(m.interfaces[1].coordinate, 0.03, 1e-12);
  EXPECT_EQ(m.fem.group_names, regions);
  const auto above = box(2, {0, y2, 0}, {0.04, 0.03, 0}), below = box(2, {0, 0, 0}, {0.04, 0.03, 0});
  check_overlap(m, {above, below}, box(2, {0, 0, 0}, {0.04, y2 + 0.03, 0}));
}

// 3D: an HCP particle slab 6 layer spacings thick between FEM blocks below and above.
TEST(Overlap, Embedded3DHcpSlab) {
  const double d = 0.01, c = d * std::sqrt(2.0 / 3.0), t = 6 * c;
  const auto below = box(3, {0, 0, 0}, {0.08, 0.07, 0.08}), dem = box(3, {0, 0, 0.08}, {0.08, 0.07, t}),
             above = box(3, {0, 0, 0.08 + t}, {0.08, 0.07, 0.07});
  sp::OverlapOptions o;
  o.kind = sp::LatticeKind::HCP;
  o.d = d;
  o.growth = 1.0;
  o.far_size = 0.03;
  const auto m = sp::build_overlap(dem, {below, above}, o);
  ASSERT_EQ(m.interfaces.size(), 2u);
  EXPECT_EQ(m.axis, 2);
  check_overlap(m, {below, above}, union_of(union_of(below, dem), above));
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

TEST(Overlap, RejectsFemBoxesThatDoNotEmbedTheParticles) {
  sp::OverlapOptions o;
  o.d = 0.001;
  const double L = 0.001 * std::sqrt(3.0) / 2;
  const auto dem = box(2, {0.02, 0, 0}, {20 * L, 0.02, 0});
  const auto left = box(2, {0, 0, 0}, {0.02, 0.02, 0}),
             right = box(2, {0.02 + 20 * L, 0, 0}, {0.02, 0.02, 0});
  EXPECT_THROW(sp::build_overlap(dem, std::vector<sp::Shape>{}, o), strata::Error);
  EXPECT_THROW(sp::build_overlap(dem, {left, right, right}, o), strata::Error);
  EXPECT_THROW(sp::build_overlap(dem, {left, left}, o), strata::Error);  // same side
  // a strip that is not a whole number of row spacings wide
  const auto dem_odd = box(2, {0.02, 0, 0}, {20.5 * L, 0.02, 0});
  EXPECT_THROW(sp::build_overlap(dem_odd, {left, box(2, {0.02 + 20.5 * L, 0, 0}, {0.02, 0.02, 0})}, o),
               strata::Error);
  // FEM boxes across different axes: the hex lattice has rows along one direction only
  const auto sq = box(2, {0.02, 0, 0}, {0.02, 0.02, 0});
  EXPECT_THROW(sp::build_overlap(sq, {left, box(2, {0.02, 0.02, 0}, {0.02, 0.02, 0})}, o), strata::Error);
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
