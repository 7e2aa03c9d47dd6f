// Bond counts without stored bonds (count_touching_pairs) and surface sites
// (undercoordinated_sites) against the listed pairs of touching_pairs, on lattices filled
// from geometry files. Counts are integers: they must agree exactly.
#include <gtest/gtest.h>
#include <strata/config.hpp>

#include <strata/core/parallel.hpp>
#include <strata/preprocess/ecc.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/mesh_fill.hpp>

#include <numeric>

#include "test_util.hpp"

using namespace strata;
using namespace strata::preprocess;
using strata::test::data;

namespace {
RegionFill fill(const Geometry& g, const std::string& region, LatticeKind kind, double d, double angle = 0) {
  FillOptions o;
  o.kind = kind;
  o.d = d;
  o.orientation_deg = angle;
  const Bounds b = g.mesh.bounds();  // one lattice for every region of the file
  o.origin = Vec3{b.lo[0] + d / 2, b.lo[1] + d / 2, g.dim == 3 ? b.lo[2] + d / 2 : 0.0};
  return fill_region(g.region(region), o);
}

/// Class k of the default width (0.02 d): a regular lattice's bonds all have length d.
constexpr std::size_t kClassOfD = 50;

void expect_count_equals_list(const Lattice& l) {
  const BondList listed = touching_pairs(l);
  ASSERT_GT(listed.size(), 0u);
  for (int threads : {1, 2}) {
    par::set_threads(threads);
    const PairCounts c = count_touching_pairs({&l}, 2 * l.radius);
    EXPECT_EQ(c.pairs, listed.size()) << threads << " threads";
    ASSERT_GT(c.by_class.size(), kClassOfD);
    EXPECT_EQ(c.by_class[kClassOfD], listed.size()) << "every bond in the class of length d";
  }
  par::set_threads(0);
}
}  // namespace

TEST(BondCount, EqualsTheListedPairsIn2D) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("plate_two_holes.geo"), {2});
  for (double angle : {0.0, 17.0})
    expect_count_equals_list(fill(g, "rock", LatticeKind::Hex2D, 1e-3, angle).lattice);
}

TEST(BondCount, EqualsTheListedPairsIn3D) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("cube.geo"), {3});
  for (auto kind : {LatticeKind::HCP, LatticeKind::FCC})
    for (double angle : {0.0, 23.0}) expect_count_equals_list(fill(g, "block", kind, 0.025, angle).lattice);
}

// Two regions of one file on one lattice, taken together: the count and the list over both
// include the pairs across their shared face, and equal those of the concatenated lattice.
TEST(BondCount, SeveralLatticesCountAsOneSet) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("two_blocks_3d.geo"), {3});
  const double d = 0.004;
  const Lattice a = fill(g, "fem", LatticeKind::HCP, d).lattice;
  const Lattice b = fill(g, "dem", LatticeKind::HCP, d).lattice;
  Lattice both = a;
  both.x.insert(both.x.end(), b.x.begin(), b.x.end());
  both.row.insert(both.row.end(), b.row.begin(), b.row.end());
  both.layer.insert(both.layer.end(), b.layer.begin(), b.layer.end());
  const std::size_t whole = touching_pairs(both).size();
  const PairCounts c = count_touching_pairs({&a, &b}, d);
  EXPECT_EQ(c.pairs, whole);
  EXPECT_GT(c.pairs, count_touching_pairs({&a}, d).pairs + count_touching_pairs({&b}, d).pairs)
      << "pairs across the shared face";
  const BondList listed = touching_pairs(std::vector<const Lattice*>{&a, &b});
  EXPECT_EQ(listed.size(), whole);
}

// Surface sites: fewer than 12 touching neighbours, as counted from the listed pairs.
TEST(BondCount, UndercoordinatedSitesAreTheSurface) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("cube.geo"), {3});
  const Lattice l = fill(g, "block", LatticeKind::HCP, 0.04).lattice;
  const BondList b = touching_pairs(l);
  std::vector<int> n(l.size(), 0);
  for (std::size_t k = 0; k < b.size(); ++k) ++n[b.i[k]], ++n[b.j[k]];
  std::vector<std::uint32_t> expected;
  for (std::size_t i = 0; i < n.size(); ++i)
    if (n[i] < 12) expected.push_back(std::uint32_t(i));
  const auto surface = undercoordinated_sites({&l}, 12);
  EXPECT_EQ(surface, expected);
  EXPECT_GT(surface.size(), 0u);
  EXPECT_LT(surface.size(), l.size());
}
