// `strata mesh`: the model as a description only (no DEM model), FEM regions meshed and
// written as .vtu, bonds counted without storing them; `strata run` and `check` refuse FEM
// regions.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>

#include "cli_test_util.hpp"
#include "series_check.hpp"

using namespace cli_test;
using nlohmann::json;

namespace {
const std::string kElasticRock = R"([[material]]
name = "rock"
density = 2650.0
kn = 6.587e10
ks = 2.371e10
friction = 0.239
)";

/// tests/preprocess/data/two_blocks_3d.geo: particles in "dem" (above z = 0.05), an FEM
/// mesh of "fem" (below).
std::string mixed_scene() {
  const std::string geo = std::string(STRATA_SOURCE_DIR) + "/tests/preprocess/data/two_blocks_3d.geo";
  return "[scene]\ndimension = 3\n\n" + kElasticRock + R"(
[[region]]
name = "particles"
material = "rock"
diameter = 0.005
shape = "file"
file = ")" +
         geo + R"("
physical = "dem"

[[region]]
name = "elastic"
kind = "fem"
material = "rock"
shape = "file"
file = ")" +
         geo + R"("
physical = "fem"
mesh_size = 0.02

[solver]
steps = 2
)";
}

/// Line (1-based) of the first occurrence of `needle` in `text`.
[[maybe_unused]] int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
}

json mesh_json(const std::string& args) {
  const auto r = run_strata("mesh " + args + " --json");
  EXPECT_EQ(r.status, 0) << r.output;
  const auto brace = r.output.find('{');
  if (brace == std::string::npos) return json::object();
  return json::parse(r.output.substr(brace));
}

/// A string field of summary.json.
json summary(const fs::path& dir) {
  std::ifstream f(dir / "summary.json");
  return json::parse(f);
}
}  // namespace

TEST(CliMesh, MeshesFemRegionsAndWritesThem) {
  if (!have_gmsh() || !have_vtk())
    GTEST_SKIP() << "a .geo scene whose VTK files are checked: needs STRATA_WITH_GMSH and STRATA_WITH_VTK";
  const fs::path d = temp_dir("mesh_fem");
  const fs::path scene = write(d, "mixed.toml", mixed_scene());
  const json j = mesh_json(scene.string() + " -o " + (d / "out").string());
  for (const char* key :
       {"particles", "bonds", "fem_nodes", "fem_elements", "seconds", "particles_per_s", "peak_rss_bytes"})
    EXPECT_TRUE(j.contains(key)) << key << "\n" << j.dump(2);
  EXPECT_GT(j["particles"].get<std::size_t>(), 1000u);
  EXPECT_GT(j["bonds"].get<std::size_t>(), 5 * j["particles"].get<std::size_t>() / 2);
  EXPECT_GT(j["fem_nodes"].get<std::size_t>(), 0u);
  EXPECT_GT(j["fem_elements"].get<std::size_t>(), 0u);
  EXPECT_GT(j["peak_rss_bytes"].get<double>(), 0.0);
  EXPECT_FALSE(j.contains("dt_crit_s")) << "mesh builds no DEM model";
  EXPECT_EQ(j["written_particles"]["selection"], "all");
  EXPECT_TRUE(fs::exists(d / "out" / "fem_000000.vtu"));
  EXPECT_TRUE(fs::exists(d / "out" / "fem.pvd"));
  EXPECT_TRUE(fs::exists(d / "out" / "model_000000.vtp"));
  // The .vtu holds the mesh's elements (tetrahedra: VTK type 10).
  std::stringstream vtu;
  vtu << std::ifstream(d / "out" / "fem_000000.vtu").rdbuf();
  EXPECT_NE(vtu.str().find("NumberOfCells=\"" + std::to_string(j["fem_elements"].get<std::size_t>()) + "\""),
            std::string::npos);
  fs::remove_all(d);
}

TEST(CliMesh, RunAndCheckBuildBothPartsOfAMixedScene) {
  if (!have_gmsh() || !have_vtk())
    GTEST_SKIP() << "a .geo scene whose VTK files are checked: needs STRATA_WITH_GMSH and STRATA_WITH_VTK";
  // A particle box and an FEM box sharing a face of one geometry file: coupled through the
  // overlap layer, one series with both parts.
  const fs::path d = temp_dir("mesh_fem_run");
  const fs::path scene = write(d, "mixed.toml", mixed_scene());
  const auto c = run_strata("check " + scene.string());
  EXPECT_EQ(c.status, 0) << c.output;
  EXPECT_NE(c.output.find("coupling     eta = 1 (serial)"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("FEM region   elastic"), std::string::npos) << c.output;
  const auto r = run_strata("run " + scene.string() + " -o " + (d / "out").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(d / "out" / "particles.pvd"));
  EXPECT_TRUE(fs::exists(d / "out" / "fem.pvd"));
  fs::remove_all(d);
}

// The counted bonds are the bonds `strata run` makes: two boxes stacked on one hex lattice
// (bonds across their shared side) and a disk, 2D.
TEST(CliMesh, CountedBondsEqualTheRunsBonds) {
  const fs::path d = temp_dir("mesh_bonds");
  const fs::path scene = write(d, "boxes.toml", "[scene]\ndimension = 2\n\n" + kElasticRock + R"(
[[region]]
name = "lower"
material = "rock"
diameter = 0.001
size = [0.02, 0.01]

[[region]]
name = "upper"
material = "rock"
diameter = 0.001
origin = [0.0005, 0.009526]  # first row one row spacing above the lower box's top row, shifted d/2
size = [0.02, 0.01]

[[region]]
name = "disk"
material = "rock"
diameter = 0.001
shape = "disk"
center = [0.04, 0.01]
radius = 0.008

[solver]
steps = 2
)");
  const json j = mesh_json(scene.string());
  const auto r = run_strata("run " + scene.string() + " -o " + (d / "run").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const json s = summary(d / "run");
  ASSERT_TRUE(s.contains("bonds")) << s.dump(2);
  EXPECT_EQ(j["bonds"], s["bonds"]);
  EXPECT_EQ(j["particles"], s["particles"]);
  EXPECT_GT(j["bonds"].get<std::size_t>(), 0u);
  fs::remove_all(d);
}

// gmsh's structured extrusions (Extrude { ... Layers{...}; }, with and without Recombine) are
// meshed by gmsh's extruded-mesh code, which once crashed calling Eigen kernels that the
// `strata` program exported in place of gmsh's own.
TEST(CliMesh, StructuredExtrusionsAreMeshedIn2DAnd3D) {
  if (!have_gmsh()) GTEST_SKIP() << "a .geo file: needs STRATA_WITH_GMSH";
  const fs::path d = temp_dir("mesh_extruded");
  write(d, "strip.geo", R"(lc = 0.1;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Line(1) = {1, 2};
out[] = Extrude {0, 0.5, 0} { Line{1}; Layers{5}; Recombine; };
Physical Surface("rock") = {out[1]};
)");
  write(d, "slab.geo", R"(lc = 0.25;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 1, 0, lc};
Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
out[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{4}; };
Physical Volume("rock") = {out[1]};
)");
  for (const auto& [dim, geo] : {std::pair{2, "strip.geo"}, std::pair{3, "slab.geo"}}) {
    const fs::path scene = write(d, "scene" + std::to_string(dim) + ".toml",
                                 "[scene]\ndimension = " + std::to_string(dim) + "\n" + kElasticRock + R"(
[[region]]
name = "rock"
kind = "fem"
material = "rock"
shape = "file"
file = ")" + (d / geo).string() + R"("
physical = "rock"
mesh_size = 0.1

[solver]
steps = 2
)");
    const json j = mesh_json(scene.string() + " -o " + (d / ("out" + std::to_string(dim))).string());
    ASSERT_TRUE(j.contains("fem_elements")) << geo << ": " << j.dump();
    EXPECT_GT(j["fem_elements"].get<std::size_t>(), 10u) << geo;
    EXPECT_GT(j["fem_nodes"].get<std::size_t>(), 10u) << geo;
  }
  fs::remove_all(d);
}
