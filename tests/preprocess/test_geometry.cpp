// Geometry files: gmsh (.geo) and closed surfaces (.stl), their regions, boundaries and
// the errors a user sees for files that cannot be used.
#include <gtest/gtest.h>
#include <strata/config.hpp>

#include <strata/core/error.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/mesh.hpp>

#include <cmath>

#include "test_util.hpp"

using namespace strata;
using namespace strata::preprocess;
using strata::test::data;

namespace {
/// Runs f, expects Error of `kind` whose message contains every one of `parts`.
template <typename F>
void expect_error(F&& f, ErrorKind kind, std::vector<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no error thrown";
  } catch (const Error& e) {
    EXPECT_EQ(int(e.kind()), int(kind)) << e.what();
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what() << "\n  lacks: " << p;
  }
}
}  // namespace

TEST(Geometry, PlateWithTwoHolesFromGeo) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads a .geo file: needs STRATA_WITH_GMSH";
  const Geometry g = read_geometry(data("plate_two_holes.geo"), {2, 0, 0, 36});
  EXPECT_EQ(g.dim, 2);
  EXPECT_EQ(g.region_names(), std::vector<std::string>{"rock"});
  EXPECT_EQ(g.boundary_names(), (std::vector<std::string>{"bottom", "hole1", "hole2", "top"}));
  const GeometryRegion r = g.region("rock");
  // The mesh approximates the holes by 36-gons at least: area within 0.1 % of the exact one.
  const double exact = 0.2 * 0.1 - 2 * M_PI * 0.01 * 0.01;
  EXPECT_NEAR(r.measure(), exact, 1e-3 * exact);
  EXPECT_EQ(r.hole_count, 2);
  // Hole 1 is the left one: its boundary segments lie at distance R from (0.05, 0.05).
  for (std::size_t s = 0; s < r.boundary.cell_count(); ++s) {
    if (r.facet_loop[s] != 1) continue;
    const auto p = r.boundary.node(r.boundary.cells[2 * s]);
    EXPECT_NEAR(std::hypot(p[0] - 0.05, p[1] - 0.05), 0.01, 1e-9);
  }
  EXPECT_TRUE(r.contains({0.01, 0.01, 0}));
  EXPECT_FALSE(r.contains({0.05, 0.05, 0}));  // in hole 1
  EXPECT_FALSE(r.contains({0.25, 0.05, 0}));
  EXPECT_GT(g.boundary("hole2").cell_count(), 10u);
}

TEST(Geometry, TutorialStyleFiles2DAnd3D) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "reads .geo files: needs STRATA_WITH_GMSH";
  const Geometry t1 = read_geometry(data("t1_rectangle.geo"));
  EXPECT_EQ(t1.dim, 2);
  EXPECT_NEAR(t1.region("My surface").measure(), 0.03, 1e-12);
  EXPECT_EQ(t1.boundary_names(), std::vector<std::string>{"My boundary"});
  const Geometry t2 = read_geometry(data("t2_extruded.geo"));
  EXPECT_EQ(t2.dim, 3);
  EXPECT_NEAR(t2.region("slab").measure(), 1.5e-3, 1e-12);
  EXPECT_EQ(t2.boundary_names(), (std::vector<std::string>{"base", "lid"}));
  // The whole geometry ("") is the union of its regions.
  const Geometry two = read_geometry(data("two_blocks_3d.geo"));
  EXPECT_NEAR(two.region("").measure(), 1e-3, 1e-12);
  EXPECT_NEAR(two.region("dem").measure(), 5e-4, 1e-12);
}

TEST(Geometry, ClosedStlSurface) {
  if (!STRATA_WITH_CGAL) GTEST_SKIP() << "reads a closed STL surface: needs STRATA_WITH_CGAL";
  const auto stl = test::scratch("box.stl");
  test::write_stl(stl, test::box_triangles({0, 0, 0}, {2, 1, 0.5}));
  const Geometry g = read_geometry(stl, {3});
  ASSERT_TRUE(g.surface != nullptr);
  const GeometryRegion r = g.region("");
  EXPECT_NEAR(r.measure(), 1.0, 1e-12);
  EXPECT_TRUE(r.contains({1, 0.5, 0.25}));
  EXPECT_FALSE(r.contains({3, 0.5, 0.25}));
  EXPECT_EQ(r.boundary.cell_count(), 12u);
}

TEST(Geometry, ErrorsNameTheFileAndWhatIsAllowed) {
  if (!STRATA_WITH_GMSH || !STRATA_WITH_CGAL)
    GTEST_SKIP() << "reads .geo and .stl files: needs STRATA_WITH_GMSH and STRATA_WITH_CGAL";
  expect_error([] { read_geometry(data("nowhere.geo")); }, ErrorKind::Input,
               {"nowhere.geo", "does not exist"});
  expect_error([] { read_geometry(data("CMakeLists.txt")); }, ErrorKind::Input, {"does not exist"});
  expect_error(
      [] { read_geometry(std::filesystem::path(STRATA_SOURCE_DIR) / "tests/preprocess/CMakeLists.txt"); },
      ErrorKind::Input, {"unknown extension", ".txt", "allowed: .geo"});
  expect_error([] { read_geometry(data("bad_syntax.geo")); }, ErrorKind::Input,
               {"bad_syntax.geo", "cannot read this file", "syntax error", "newer gmsh"});
  // gmsh recovers after a syntax error:
  EXPECT_EQ(read_geometry(data("t1_rectangle.geo")).dim, 2);
  expect_error([] { read_geometry(data("cube.geo"), {2}); }, ErrorKind::Input,
               {"cube.geo", "3D", "scene is 2D"});
  expect_error([] { read_geometry(data("cube.geo")).region("rock"); }, ErrorKind::Input,
               {"no region", "\"rock\"", "\"block\""});
  expect_error([] { read_geometry(data("cube.geo")).boundary("side"); }, ErrorKind::Input,
               {"no boundary group", "\"bottom\", \"top\""});
  // An STL with one triangle missing is not closed.
  auto tris = test::box_triangles({0, 0, 0}, {1, 1, 1});
  tris.pop_back();
  const auto open = test::scratch("open_box.stl");
  test::write_stl(open, tris);
  expect_error([&] { read_geometry(open); }, ErrorKind::Input, {"open_box.stl", "not closed", "3 edges"});
  const auto stl = test::scratch("closed_box.stl");
  test::write_stl(stl, test::box_triangles({0, 0, 0}, {1, 1, 1}));
  expect_error([&] { read_geometry(stl, {2}); }, ErrorKind::Input, {"scene is 2D"});
  const auto junk = test::scratch("junk.stl");
  { std::ofstream(junk) << "this is not an stl file\n"; }
  expect_error([&] { read_geometry(junk); }, ErrorKind::Input, {"junk.stl", "cannot read"});
}

TEST(FemMesh, TrianglesAndTetrahedraWithSizeControl) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "meshes with gmsh: needs STRATA_WITH_GMSH";
  const SimplexMesh coarse = mesh_fem_region(data("plate_two_holes.geo"), "rock", 2, {0.01});
  const SimplexMesh fine = mesh_fem_region(data("plate_two_holes.geo"), "rock", 2, {0.004});
  EXPECT_EQ(coarse.dim, 2);
  EXPECT_GT(fine.cell_count(),
            2.5 * double(coarse.cell_count()));  // (0.01/0.004)² = 6.25 away from the holes
  EXPECT_NEAR(fine.measure(), 0.2 * 0.1 - 2 * M_PI * 1e-4, 2e-3 * 0.02);
  ASSERT_EQ(fine.group_names, std::vector<std::string>{"rock"});
  for (auto gidx : fine.cell_group) EXPECT_EQ(gidx, 0);
  const SimplexMesh tets = mesh_fem_region(data("two_blocks_3d.geo"), "", 3, {0.02});
  EXPECT_EQ(tets.dim, 3);
  EXPECT_NEAR(tets.measure(), 1e-3, 1e-12);
  EXPECT_EQ(tets.group_names.size(), 2u);
  Shape box;
  box.kind = Shape::Kind::Box;
  box.dim = 3;
  box.size = {1, 2, 3};
  const SimplexMesh b = mesh_fem_shape(box, 0.5);
  EXPECT_NEAR(b.measure(), 6.0, 1e-9);
  Shape disk;
  disk.kind = Shape::Kind::Disk;
  disk.radius = 1;
  const SimplexMesh dm = mesh_fem_shape(disk, 0.1);
  EXPECT_NEAR(dm.measure(), M_PI, 0.01);
}
