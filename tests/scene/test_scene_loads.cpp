// FEM scenes: a traction on a boundary (per = "boundary") applied with a smooth ramp stretches a
// bar as the uniaxial-stress solution says; the per keys that do not fit the group, a lattice's
// stiffnesses missing where a lattice is, and a mesh too fine for the machine are refused at
// their line.
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "scene_test_util.hpp"

namespace fs = std::filesystem;
using strata::scene::test::empty_dir;
using strata::scene::test::setup_error_of;

namespace {

// A bar of L x H = 0.1 x 0.02 m, rollers on its left (x) and bottom (y) sides, a traction of
// `traction` N/m on its right side, ramped smoothly from 0 at t = 0 to its value at t = ramp
// and held; the right side's mean displacement is a gauge.
std::string bar_scene(const fs::path& geo, const std::string& load_extra = "") {
  return "[scene]\ndimension = 2\n\n"
         "[[material]]\nname = \"rock\"\ndensity = 2650.0\nyoungs_modulus = 5e10\npoisson_ratio = 0.25\n\n"
         "[[region]]\nname = \"bar\"\nkind = \"fem\"\nmaterial = \"rock\"\nshape = \"file\"\nfile = \"" +
         geo.string() +
         "\"\nphysical = \"bar\"\nmesh_size = 0.005\n\n"
         "[[group]]\nname = \"left\"\nregion = \"bar\"\nselect = \"box\"\nbox_min = [-1, -1]\nbox_max = "
         "[1e-6, 1]\n\n"
         "[[group]]\nname = \"bottom\"\nregion = \"bar\"\nselect = \"box\"\nbox_min = [-1, -1]\nbox_max = "
         "[1, 1e-6]\n\n"
         "[[group]]\nname = \"right\"\nregion = \"bar\"\nselect = \"box\"\nbox_min = [0.099999, -1]\nbox_max "
         "= [1, 1]\n\n"
         "[[boundary]]\ngroup = \"left\"\ntype = \"fixed\"\naxes = [\"x\"]\n\n"
         "[[boundary]]\ngroup = \"bottom\"\ntype = \"fixed\"\naxes = [\"y\"]\n\n"
         "[[load]]\ngroup = \"right\"\ntimes = [0.0, 2e-3]\nforces = [[0.0, 0.0], [1e6, 0.0]]\nper = "
         "\"boundary\"\n"
         "ramp = \"smooth\"\n" +
         load_extra +
         "\n[probe]\ngauges = [\"right\"]\n\n"
         "[solver]\nduration = 2e-3\ndt_safety = 0.5\n\n"
         "[output]\nframes = 0\nrender = false\n";
}

fs::path bar_geometry(const fs::path& dir) {
  const fs::path geo = dir / "bar.geo";
  std::ofstream(geo) << "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 0.1, 0.02};\n"
                        "Physical Surface(\"bar\") = {1};\n";
  return geo;
}

std::map<std::string, double> last_probe_row(const fs::path& csv) {
  std::ifstream in(csv);
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::map<std::string, double> row;
  std::stringstream hs(header), ls(last);
  for (std::string h, v; std::getline(hs, h, ',') && std::getline(ls, v, ',');) row[h] = std::stod(v);
  return row;
}

}  // namespace

// Uniaxial stress σ = 1 MPa (1e6 N/m on a unit thickness) in plane stress with E = 50 GPa and
// ν = 0.25: u_x = σ·L/E = 2e-6 m on the right side, and its mean u_y = −ν·σ·(H/2)/E = −5e-8 m.
// The load is ramped over 2 ms, about 20 periods of the bar's first mode (4L/c = 93 µs), so
// what is left of the dynamic response is well under the 1 % tolerance.
TEST(SceneLoads, TractionOnAnFemSideStretchesABarAsUniaxialStress) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "the bar is meshed by gmsh: needs STRATA_WITH_GMSH";
  const fs::path dir = empty_dir("scene_loads_bar");
  const auto sc = strata::scene::parse(bar_scene(bar_geometry(dir)), (dir / "bar.toml").string(), {});
  strata::scene::Run run(sc, {dir / "out", false, {}});
  strata::scene::RunObserver quiet;
  const auto r = run.execute(quiet);
  EXPECT_EQ(r.status, strata::scene::RunStatus::Completed);
  const auto row = last_probe_row(dir / "out" / "probes.csv");
  ASSERT_TRUE(row.count("right_ux")) << "no gauge column right_ux";
  EXPECT_NEAR(row.at("right_ux"), 2e-6, 0.01 * 2e-6);
  EXPECT_NEAR(row.at("right_uy"), -5e-8, 0.02 * 5e-8);
}

TEST(SceneLoads, BoundaryTractionNeedsFemNodesOnTheBoundary) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "the bar is meshed by gmsh: needs STRATA_WITH_GMSH";
  const fs::path dir = empty_dir("scene_loads_inner");
  std::string text = bar_scene(bar_geometry(dir));
  // a group of inner nodes only: no boundary edge between them
  const std::string from = "box_min = [0.099999, -1]\nbox_max = [1, 1]";
  text.replace(text.find(from), from.size(), "box_min = [0.04, 0.004]\nbox_max = [0.06, 0.016]");
  const std::string e = setup_error_of(text, "scene.toml", empty_dir("scene_loads_refused"));
  EXPECT_NE(e.find("scene.toml:54:7: group 'right': no boundary edge of the FEM mesh has all its corners in "
                   "the group"),
            std::string::npos)
      << e;
}

TEST(SceneLoads, BoundaryTractionIsForFemNodesOnly) {
  const std::string text =
      "[scene]\ndimension = 2\n\n"
      "[[material]]\nname = \"rock\"\ndensity = 2650.0\nkn = 1e10\nks = 1e9\n\n"
      "[[region]]\nname = \"block\"\nmaterial = \"rock\"\nshape = \"box\"\norigin = [0, 0]\nsize = [0.01, "
      "0.01]\n"
      "diameter = 0.001\n\n"
      "[[group]]\nname = \"top\"\nselect = \"top_row\"\n\n"
      "[[load]]\ngroup = \"top\"\ntimes = [0.0]\nforces = [[0.0, -1.0]]\nper = \"boundary\"\n\n"
      "[solver]\nsteps = 10\n\n[output]\nframes = 0\nrender = false\n";
  EXPECT_EQ(
      setup_error_of(text, "scene.toml", empty_dir("scene_loads_refused")),
      "scene.toml:26:7: group 'top' holds particles: per = \"boundary\" spreads a traction over the boundary "
      "of FEM nodes (allowed for particles: \"particle\" or \"group\")");
}

// An FEM region whose material gives E and ν needs no bond stiffnesses (the bar scenes above
// have none); particles do, and so does an FEM region that takes the lattice's continuum.
TEST(SceneLoads, BondStiffnessesAreNeededWhereALatticeIs) {
  const std::string particles =
      "[scene]\ndimension = 2\n\n"
      "[[material]]\nname = \"rock\"\ndensity = 2650.0\nyoungs_modulus = 5e10\npoisson_ratio = 0.25\n\n"
      "[[region]]\nname = \"block\"\nmaterial = \"rock\"\nshape = \"box\"\norigin = [0, 0]\nsize = [0.01, "
      "0.01]\n"
      "diameter = 0.001\n\n[solver]\nsteps = 10\n";
  auto error_of_parse = [](const std::string& text) -> std::string {
    try {
      strata::scene::parse(text, "scene.toml", {});
    } catch (const strata::Error& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(error_of_parse(particles).find("scene.toml:4:1: [[material]] 'rock' is missing required key 'kn' "
                                           "(Kn: normal stiffness"),
            std::string::npos)
      << error_of_parse(particles);
  std::string with_kn = particles;
  with_kn.replace(with_kn.find("youngs_modulus"), 0, "kn = 1e10\n");
  EXPECT_NE(error_of_parse(with_kn).find("scene.toml:4:1: [[material]] 'rock' is missing required key 'ks'"),
            std::string::npos)
      << error_of_parse(with_kn);
}

// An FEM region of a primitive shape with elements far too small for the machine is refused
// at its mesh_size, with the estimate, before gmsh starts (a 1 m square of 1 µm triangles:
// some 2e12 of them).
TEST(SceneFemMesh, ATinyMeshSizeIsRefusedBeforeMeshing) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "FEM regions are meshed by gmsh: needs STRATA_WITH_GMSH";
  const std::string text =
      "[scene]\ndimension = 2\n\n"
      "[[material]]\nname = \"rock\"\ndensity = 2650.0\nyoungs_modulus = 5e10\npoisson_ratio = 0.25\n\n"
      "[[region]]\nname = \"slab\"\nkind = \"fem\"\nmaterial = \"rock\"\nshape = \"box\"\norigin = [0, 0]\n"
      "size = [1.0, 1.0]\nmesh_size = 1e-6\n\n"
      "[solver]\nsteps = 10\n\n[output]\nframes = 0\nrender = false\n";
  const std::string e = setup_error_of(text, "scene.toml", empty_dir("scene_loads_refused"));
  EXPECT_EQ(
      e.rfind("scene.toml:17:13: FEM mesh of a primitive shape with elements of 1e-06 m: gmsh would make "
              "about 2.31e+12 triangles",
              0),
      0u)
      << e;
  EXPECT_NE(e.find("allowed: a larger mesh_size"), std::string::npos) << e;
}
