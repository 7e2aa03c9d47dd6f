// What a build of strata that leaves out optional parts does, through the `strata` command: a
// scene key or a command-line option that needs a missing part is refused before anything is
// written, at the key's file:line:col and naming the CMake option that turns the part on; a
// DEM scene at its defaults still runs and writes its probes and summary.
//
// A refusal test runs only in a build that leaves its part out (scripts/test builds one that
// leaves out all of them, labelled "parts") and is skipped in a build that has the part.
#include <gtest/gtest.h>
#include <strata/config.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_test_util.hpp"

namespace fs = std::filesystem;
using namespace cli_test;  // run_strata() runs the command

namespace {

/// A 2D block of 1 mm disks between platens, 200 steps, output in "out" beside the scene;
/// `output` holds the keys of [output] (one per line), `region` further keys of the block.
std::string block_scene(const std::string& output = "", const std::string& region = "") {
  return "[scene]\ndimension = 2\n" + kMaterial + R"(
[[region]]
name = "block"
material = "rock"
diameter = 0.001
size = [0.010, 0.0105]
)" + region +
         platens("0.05") +
         R"(
[solver]
steps = 200

[output]
directory = "out"
)" + output;
}

/// 1-based number of the first line of `text` that starts with `start` (0: none).
int line_of(const std::string& text, const std::string& start) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (line.rfind(start, 0) == 0) return n;
  }
  return 0;
}

/// `r` is a refusal of `scene` at `line` (exit status 2, "scene:line:col: ..." naming
/// -D<option>=ON) and `out` was not written.
void expect_refused_at(const Result& r, const fs::path& scene, int line, const std::string& option,
                       const fs::path& out) {
  EXPECT_EQ(r.status, 2) << r.output;
  const std::string at = scene.string() + ":" + std::to_string(line) + ":";
  const auto pos = r.output.find(at);
  ASSERT_NE(pos, std::string::npos) << "no " << at << " in:\n" << r.output;
  int col = 0;
  EXPECT_EQ(std::sscanf(r.output.c_str() + pos + at.size(), "%d:", &col), 1) << r.output;
  EXPECT_GT(col, 0) << r.output;
  EXPECT_NE(r.output.find("-D" + option + "=ON"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << out << " written by a refused run";
}

/// Writes `text` as `name` in `dir` and runs `strata run` on it with output in dir/out.
Result run_scene(const fs::path& dir, const std::string& name, const std::string& text,
                 const std::string& more = "") {
  const fs::path f = write(dir, name, text);
  return run_strata("run " + f.string() + " -o " + (dir / "out").string() + more);
}

}  // namespace

TEST(Parts, VersionNamesEveryOptionAndWhetherThisBuildHasIt) {
  const auto r = run_strata("--version");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const auto& f : strata::config::kFeatures) {
    const auto at = r.output.find(f.option);
    ASSERT_NE(at, std::string::npos) << f.option << "\n" << r.output;
    const std::string line = r.output.substr(at, r.output.find('\n', at) - at);
    EXPECT_NE(line.find(f.enabled ? " on " : " off "), std::string::npos) << line;
  }
}

// A DEM scene that leaves [output] at its defaults (frames, pictures) runs in any build: what
// the build cannot write is left out with a warning, the probes and the summary are written.
TEST(Parts, DemSceneAtItsDefaultsRunsAndWritesProbesAndSummary) {
  if (STRATA_WITH_RENDER)
    GTEST_SKIP() << "this build renders pictures: tests/cli and tests/examples run such scenes";
  const fs::path d = temp_dir("parts_defaults");
  const auto r = run_scene(d, "block.toml", block_scene());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"probes.csv", "summary.json", "breaks.csv"})
    EXPECT_TRUE(fs::exists(d / "out" / f)) << f;
  std::ifstream summary(d / "out" / "summary.json");
  const std::string s((std::istreambuf_iterator<char>(summary)), std::istreambuf_iterator<char>());
  EXPECT_NE(s.find("\"status\": \"completed\""), std::string::npos) << s;
  EXPECT_NE(s.find("\"steps_done\": 200"), std::string::npos) << s;
  std::ifstream probes(d / "out" / "probes.csv");
  int rows = 0;
  for (std::string line; std::getline(probes, line);) ++rows;
  EXPECT_GT(rows, 10);
  EXPECT_EQ(fs::exists(d / "out" / "particles.pvd"), STRATA_WITH_VTK != 0);
  EXPECT_EQ(fs::exists(d / "out" / "checkpoint.h5"), STRATA_WITH_HDF5 != 0);
  EXPECT_FALSE(fs::exists(d / "out" / "png"));
  if (!STRATA_WITH_VTK) {
    EXPECT_NE(r.output.find("VTK frames skipped"), std::string::npos) << r.output;
  }
  EXPECT_NE(r.output.find("pictures skipped"), std::string::npos) << r.output;
  fs::remove_all(d);
}

TEST(Parts, GeometryFileNeedsGmsh) {
  if (STRATA_WITH_GMSH) GTEST_SKIP() << "this build has STRATA_WITH_GMSH: nothing to refuse";
  const fs::path d = temp_dir("parts_gmsh");
  std::ofstream(d / "block.geo") << "Rectangle(1) = {0, 0, 0, 0.01, 0.01};\n";
  const std::string text = block_scene("", "shape = \"file\"\nfile = \"block.geo\"\n");
  const auto r = run_scene(d, "geo.toml", text);
  expect_refused_at(r, d / "geo.toml", line_of(text, "file = "), "STRATA_WITH_GMSH", d / "out");
  EXPECT_NE(r.output.find("block.geo"), std::string::npos) << r.output;
  // `strata mesh`, which builds the regions only, refuses it at the same line.
  expect_refused_at(run_strata("mesh " + (d / "geo.toml").string()), d / "geo.toml", line_of(text, "file = "),
                    "STRATA_WITH_GMSH", d / "out");
  fs::remove_all(d);
}

TEST(Parts, FemRegionNeedsGmsh) {
  if (STRATA_WITH_GMSH) GTEST_SKIP() << "this build has STRATA_WITH_GMSH: nothing to refuse";
  const fs::path d = temp_dir("parts_fem");
  const std::string text = R"([scene]
dimension = 2

[[material]]
name = "steel"
density = 7850.0
kn = 1e10
ks = 1e10
youngs_modulus = 2e11
poisson_ratio = 0.3

[[region]]
name = "plate"
kind = "fem"
material = "steel"
size = [0.01, 0.01]

[solver]
steps = 10
)";
  const auto r = run_scene(d, "fem.toml", text);
  expect_refused_at(r, d / "fem.toml", line_of(text, "kind = "), "STRATA_WITH_GMSH", d / "out");
  fs::remove_all(d);
}

TEST(Parts, ClosedSurfaceNeedsCgal) {
  if (STRATA_WITH_CGAL) GTEST_SKIP() << "this build has STRATA_WITH_CGAL: nothing to refuse";
  const fs::path d = temp_dir("parts_cgal");
  std::ofstream(d / "ball.stl") << "solid ball\nendsolid ball\n";
  const std::string text = "[scene]\ndimension = 3\n" + kMaterial + R"(
[[region]]
name = "ball"
material = "rock"
diameter = 0.001
shape = "file"
file = "ball.stl"

[solver]
steps = 10
)";
  const auto r = run_scene(d, "stl.toml", text);
  expect_refused_at(r, d / "stl.toml", line_of(text, "file = "), "STRATA_WITH_CGAL", d / "out");
  fs::remove_all(d);
}

TEST(Parts, CheckpointsNeedHdf5) {
  if (STRATA_WITH_HDF5) GTEST_SKIP() << "this build has STRATA_WITH_HDF5: nothing to refuse";
  const fs::path d = temp_dir("parts_hdf5");
  const std::string text = block_scene("checkpoint_every = 100\nvtk = false\nrender = false\n");
  expect_refused_at(run_scene(d, "ck.toml", text), d / "ck.toml", line_of(text, "checkpoint_every"),
                    "STRATA_WITH_HDF5", d / "out");
  // --restart is refused when the command line is read.
  std::ofstream(d / "checkpoint.h5") << "not a checkpoint\n";
  const auto r = run_scene(d, "ok.toml", block_scene("vtk = false\nrender = false\n"),
                           " --restart " + (d / "checkpoint.h5").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--restart"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("-DSTRATA_WITH_HDF5=ON"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

// Frames asked for by the scene, in the file or with --set, are refused; output.vtk = false in
// the scene turns them off.
TEST(Parts, FramesNeedVtk) {
  if (STRATA_WITH_VTK) GTEST_SKIP() << "this build has STRATA_WITH_VTK: nothing to refuse";
  const fs::path d = temp_dir("parts_vtk");
  for (const std::string key :
       {"frames = 5", "vtk = true", "frame_every_time = 1e-6", "frame_every_breaks = 10"}) {
    const std::string text = block_scene(key + "\nrender = false\n");
    SCOPED_TRACE(key);
    expect_refused_at(run_scene(d, "frames.toml", text), d / "frames.toml", line_of(text, key),
                      "STRATA_WITH_VTK", d / "out");
  }
  const auto r = run_scene(d, "set.toml", block_scene("render = false\n"), " --set output.frames=3");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--set output.frames=3: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("-DSTRATA_WITH_VTK=ON"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out"));

  const auto off = run_scene(d, "off.toml", block_scene("frames = 5\nvtk = false\nrender = false\n"));
  EXPECT_EQ(off.status, 0) << off.output;
  EXPECT_TRUE(fs::exists(d / "out" / "summary.json"));
  EXPECT_FALSE(fs::exists(d / "out" / "particles.pvd"));
  fs::remove_all(d);
}

// Pictures asked for by the scene are refused; output.render = false turns them off, with
// the keys that only style them.
TEST(Parts, PicturesNeedRendering) {
  if (STRATA_WITH_RENDER) GTEST_SKIP() << "this build has STRATA_WITH_RENDER: nothing to refuse";
  const fs::path d = temp_dir("parts_render");
  const std::string vtk = STRATA_WITH_VTK ? "frames = 2\n" : "vtk = false\n";
  for (const std::string key : {"render = true", "movie = true", "render_while_running = true"}) {
    const std::string text = block_scene(vtk + key + "\n");
    SCOPED_TRACE(key);
    expect_refused_at(run_scene(d, "pictures.toml", text), d / "pictures.toml", line_of(text, key),
                      "STRATA_WITH_RENDER", d / "out");
  }
  const auto off = run_scene(d, "off.toml", block_scene(vtk + "render = false\nmovie = true\n"));
  EXPECT_EQ(off.status, 0) << off.output;
  EXPECT_FALSE(fs::exists(d / "out" / "png"));
  fs::remove_all(d);
}

// Commands and options that need a missing part stop before they read or write anything.
TEST(Parts, CommandsThatNeedAMissingPartStopFirst) {
  const fs::path d = temp_dir("parts_commands");
  const fs::path scene = write(d, "block.toml", block_scene("vtk = false\nrender = false\n"));
  if (!STRATA_WITH_RENDER) {
    std::ofstream(d / "particles.pvd") << "<VTKFile/>\n";
    const auto r = run_strata("render " + (d / "particles.pvd").string() + " -o " + (d / "png").string());
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("-DSTRATA_WITH_RENDER=ON"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "png"));
  }
  if (!STRATA_WITH_VTK) {
    const auto r = run_strata("mesh " + scene.string() + " -o " + (d / "model").string());
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("-o"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("-DSTRATA_WITH_VTK=ON"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "model"));
    EXPECT_EQ(run_strata("mesh " + scene.string()).status, 0) << "without -o `strata mesh` writes nothing";
    const auto w = run_strata("report wave --quick --no-plot --frames 2 -o " + (d / "wave").string());
    EXPECT_EQ(w.status, 2) << w.output;
    EXPECT_NE(w.output.find("--frames"), std::string::npos) << w.output;
    EXPECT_NE(w.output.find("-DSTRATA_WITH_VTK=ON"), std::string::npos) << w.output;
    EXPECT_FALSE(fs::exists(d / "wave"));
  }
  if (!STRATA_WITH_GMSH) {
    const auto w = run_strata("report wave --quick --no-plot --frames 0 -o " + (d / "wave").string());
    EXPECT_EQ(w.status, 2) << w.output;
    EXPECT_NE(w.output.find("-DSTRATA_WITH_GMSH=ON"), std::string::npos) << w.output;
  }
  fs::remove_all(d);
}

TEST(Parts, CoupledWaveGeometryNeedsGmshForCheckAndRun) {
  if (STRATA_WITH_GMSH) GTEST_SKIP() << "this build has STRATA_WITH_GMSH: nothing to refuse";
  const fs::path d = temp_dir("parts_wave");
  std::ofstream(d / "wave.geo") << "Rectangle(1) = {0, 0, 0, 0.01, 0.01};\n";
  const std::string text = R"([coupled]
case = "wave"
geometry = "wave.geo"
wavelengths = [20]
eta = [1]

[output]
directory = "out"
)";
  const fs::path f = write(d, "wave.toml", text);
  expect_refused_at(run_strata("check " + f.string()), f, line_of(text, "geometry = "), "STRATA_WITH_GMSH",
                    d / "out");
  expect_refused_at(run_strata("run " + f.string() + " -o " + (d / "out").string()), f,
                    line_of(text, "geometry = "), "STRATA_WITH_GMSH", d / "out");
  fs::remove_all(d);
}

TEST(Parts, CheckRefusesAGeometryFileAtItsLine) {
  if (STRATA_WITH_GMSH) GTEST_SKIP() << "this build has STRATA_WITH_GMSH: nothing to refuse";
  const fs::path d = temp_dir("parts_check");
  std::ofstream(d / "block.geo") << "Rectangle(1) = {0, 0, 0, 0.01, 0.01};\n";
  const std::string text = block_scene("", "shape = \"file\"\nfile = \"block.geo\"\n");
  const fs::path f = write(d, "geo.toml", text);
  expect_refused_at(run_strata("check " + f.string()), f, line_of(text, "file = "), "STRATA_WITH_GMSH",
                    d / "out");
  fs::remove_all(d);
}
