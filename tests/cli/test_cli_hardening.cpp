// What a hostile or unlucky user meets: numbers beyond their type, empty options, damaged
// series files, geometry files for another gmsh. Each is refused with a message that says
// what is wrong, and nothing is drawn or written from it.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <regex>
#include <string>

#include "cli_test_util.hpp"
#include "series_check.hpp"

using namespace cli_test;

namespace {
const std::string kQuick = std::string(STRATA_SOURCE_DIR) + "/examples/01_uniaxial_compression/quick.toml";
const std::string kWave = std::string(STRATA_SOURCE_DIR) + "/examples/04_coupled_wave/quick.toml";
/// kQuick without frames or pictures: a scene any build (even without VTK) checks.
const std::string kQuickAnyBuild = kQuick + " --set output.vtk=false --set output.render=false";

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}
}  // namespace

// Integers in a scene end up in ints: beyond 2^31 - 1 they are refused, never wrapped round
// (η = 4294967297 once ran as η = 1).
TEST(CliHardening, IntegersBeyondTheirRangeAreRefusedAtTheirKey) {
  for (const std::string set : {"coupled.eta=[4294967297]", "coupled.repeats=4294967297",
                                "coupled.frames=2147483648", "coupled.series_eta=-4294967295"}) {
    const auto r = run_strata("check " + kWave + " --set " + set);
    EXPECT_EQ(r.status, 2) << set << ": " << r.output;
    EXPECT_TRUE(contains(r.output, "--set " + set + ": ")) << r.output;
  }
  const auto r = run_strata("check " + kQuick + " --set solver.min_particles_per_thread=4294967297");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "at most 2147483647")) << r.output;
  // threads has its own bound, the thread pool's size.
  const auto t = run_strata("check " + kQuick + " --set solver.threads=4294967297");
  EXPECT_EQ(t.status, 2) << t.output;
  EXPECT_TRUE(
      contains(t.output, "--set solver.threads=4294967297: threads = 4294967297 must be >= 0 and <= 1024"))
      << t.output;
  // The same numbers as options: refused by the option parser.
  EXPECT_EQ(run_strata("report wave --check --eta 4294967297").status, 2);
  EXPECT_EQ(run_strata("report chain6 --check --repeats 4294967297").status, 2);
}

// Option ranges read as numbers, not as the 309 digits of the largest double.
TEST(CliHardening, OptionRangesAreShortAndEmptyPathsAreRefused) {
  const auto r = run_strata("bench dem --particles 0");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "--particles: 0 must be a finite number > 0")) << r.output;
  EXPECT_LT(r.output.size(), 300u) << r.output;
  // -o "" (an unset shell variable, say) is not the scene's own folder.
  for (const std::string& cmd : {"run " + kQuick, "mesh " + kQuick, std::string("report chain6")}) {
    const auto e = run_strata(cmd + " -o \"\"");
    EXPECT_EQ(e.status, 2) << cmd << ": " << e.output;
    EXPECT_TRUE(contains(e.output, "an empty path")) << e.output;
  }
}

// A damaged .pvd or frame is an error (exit 1) naming the file, before anything is drawn;
// a series without frames has nothing to draw (exit 2).
TEST(CliHardening, RenderRefusesDamagedSeries) {
  if (!have_render() || !have_vtk()) GTEST_SKIP() << "needs STRATA_WITH_RENDER and STRATA_WITH_VTK";
  const fs::path d = temp_dir("damaged_series");
  const auto run = run_strata("run " + kQuick + " -o " + (d / "run").string() +
                              " --set solver.steps=400 --set output.frames=2 --set output.render=false");
  ASSERT_EQ(run.status, 0) << run.output;
  const fs::path pvd = d / "run" / "particles.pvd";
  {  // cut short
    fs::copy_file(pvd, d / "run" / "cut.pvd");
    fs::resize_file(d / "run" / "cut.pvd", fs::file_size(pvd) / 2);
    const auto r = run_strata("render " + (d / "run" / "cut.pvd").string() + " -o " + (d / "png1").string());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "cut.pvd is damaged")) << r.output;
    EXPECT_FALSE(fs::exists(d / "png1"));
  }
  {  // no frames
    std::ofstream(d / "run" / "empty.pvd")
        << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
           "  <Collection>\n  </Collection>\n</VTKFile>\n";
    const auto r =
        run_strata("render " + (d / "run" / "empty.pvd").string() + " -o " + (d / "png2").string());
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "lists no frames")) << r.output;
  }
  {  // a frame cut short
    const fs::path frame = d / "run" / "particles_000001.vtp";
    fs::resize_file(frame, fs::file_size(frame) / 2);
    const auto r = run_strata("render " + pvd.string() + " -o " + (d / "png3").string());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "particles_000001.vtp is damaged")) << r.output;
    EXPECT_FALSE(fs::exists(d / "png3" / "frame_000000.png")) << "nothing drawn from a damaged series";
  }
  fs::remove_all(d);
}

// A re-run into the folder of a longer run leaves no frame its .pvd does not list.
TEST(CliHardening, ReRunIntoAnOldFolderLeavesNoStaleFrames) {
  if (!have_vtk()) GTEST_SKIP() << "needs STRATA_WITH_VTK";
  const fs::path d = temp_dir("rerun");
  const std::string base =
      "run " + kQuick + " -o " + d.string() + " --set solver.steps=400 --set output.render=false";
  ASSERT_EQ(run_strata(base + " --set output.frames=4").status, 0);
  std::ofstream(d / "particles_000002.vtp.tmp") << "killed while writing";
  const auto r = run_strata(base + " --set output.frames=1");
  ASSERT_EQ(r.status, 0) << r.output;
  std::size_t frames = 0;
  for (const auto& f : fs::directory_iterator(d))
    frames += f.path().filename().string().starts_with("particles_");
  EXPECT_EQ(frames, 2u) << "frames 0 and 1 of the new run only";
  EXPECT_TRUE(contains(r.output, "earlier 'particles' series")) << r.output;
  fs::remove_all(d);
}

// gmsh's version is named where files written for a newer gmsh fail, and by --version.
TEST(CliHardening, GmshVersionIsNamed) {
  if (!have_gmsh()) GTEST_SKIP() << "needs STRATA_WITH_GMSH";
  const auto v = run_strata("--version");
  EXPECT_EQ(v.status, 0);
  EXPECT_TRUE(contains(v.output, "gmsh 4.")) << v.output;
  const fs::path d = temp_dir("newer_gmsh");
  // a command of a later gmsh than this build may have
  std::ofstream(d / "newer.geo") << "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 1, 1};\n"
                                    "Physical Surface(\"rock\") = {1};\nMesh.Frobnicate[] = Unknown{ 1 };\n";
  std::ofstream(d / "scene.toml") << "[scene]\ndimension = 2\n"
                                  << kMaterial << R"(
[[region]]
name = "rock"
kind = "fem"
material = "rock"
shape = "file"
file = "newer.geo"
physical = "rock"

[solver]
steps = 2
)";
  const auto r = run_strata("check " + (d / "scene.toml").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "gmsh 4.")) << r.output;
  EXPECT_TRUE(contains(r.output, "newer gmsh")) << r.output;
  fs::remove_all(d);
}

namespace {
/// A 2D scene of one region from `geo` (kind "particles" or "fem") in folder `d`.
fs::path geo_scene(const fs::path& d, const std::string& geo, const std::string& kind) {
  std::ofstream(d / "shape.geo") << geo;
  std::ofstream(d / "scene.toml")
      << "[scene]\ndimension = 2\n"
      << kMaterial << "\n[[region]]\nname = \"rock\"\nkind = \"" << kind << "\"\nmaterial = \"rock\"\n"
      << (kind == "particles" ? "diameter = 0.001\n" : "")
      << "shape = \"file\"\nfile = \"shape.geo\"\nphysical = \"rock\"\n\n[solver]\nsteps = 2\n";
  return d / "scene.toml";
}
}  // namespace

// Models too large for the machine are refused from an estimate, at once, instead of
// hanging or running out of memory.
TEST(CliHardening, ModelsBeyondTheMachineAreRefusedFromAnEstimate) {
  const auto r = strata_within(60, "check " + kQuickAnyBuild + " --set region[0].diameter=1e-7");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "--set region[0].diameter=1e-7: ")) << r.output;
  EXPECT_TRUE(contains(r.output, "particles of diameter")) << r.output;
  if (!have_gmsh()) GTEST_SKIP() << "the mesh-size estimate needs STRATA_WITH_GMSH";
  // lc = 1e-6 m in a 3 cm plate: about 10^9 triangles
  const fs::path d = temp_dir("tiny_lc");
  const fs::path scene =
      geo_scene(d,
                "lc = 1e-6;\nPoint(1) = {0, 0, 0, lc};\nPoint(2) = {0.03, 0, 0, lc};\n"
                "Point(3) = {0.03, 0.03, 0, lc};\nPoint(4) = {0, 0.03, 0, lc};\n"
                "Line(1) = {1, 2};\nLine(2) = {2, 3};\nLine(3) = {3, 4};\nLine(4) = {4, 1};\n"
                "Curve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n"
                "Physical Surface(\"rock\") = {1};\n",
                "fem");
  const auto m = strata_within(60, "check " + scene.string());
  EXPECT_EQ(m.status, 2) << m.output;
  EXPECT_TRUE(contains(m.output, "scene.toml:")) << m.output;
  EXPECT_TRUE(contains(m.output, "triangles")) << m.output;
  fs::remove_all(d);
}

// Errors of what a scene key names point at that key: the density behind a mass that
// underflows, the diameter of a shape too small for one particle, an unknown physical group,
// a 2D surface outside the xy plane.
TEST(CliHardening, ErrorsOfWhatAKeyNamesPointAtTheKey) {
  const std::regex located(R"(\.toml:[0-9]+:[0-9]+: |--set [^:]+: )");
  auto refused_at = [&](const Result& r, const std::string& what) {
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_TRUE(std::regex_search(r.output, located)) << r.output;
    EXPECT_TRUE(contains(r.output, what)) << r.output;
  };
  refused_at(run_strata("check " + kQuickAnyBuild + " --set material[0].density=1e-320"),
             "--set material[0].density=1e-320: ");
  refused_at(run_strata("check " + kQuickAnyBuild + " --set region[0].size=[0.0001,0.0001]"),
             "quick.toml:24:");
  if (!have_gmsh()) GTEST_SKIP() << "geometry files need STRATA_WITH_GMSH";
  const std::string plate = std::string(STRATA_SOURCE_DIR) + "/examples/03_plate_with_holes/quick.toml";
  refused_at(run_strata("check " + plate + " --set 'region[0].physical=\"nope\"'"), "no region");
  const fs::path d = temp_dir("xz_plane");
  const fs::path scene = geo_scene(d,
                                   "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 0.03, 0.03};\n"
                                   "Rotate {{1, 0, 0}, {0, 0, 0}, Pi/2} { Surface{1}; }\n"
                                   "Physical Surface(\"rock\") = {1};\n",
                                   "particles");
  refused_at(run_strata("check " + scene.string()), "xy plane");
  fs::remove_all(d);
}

namespace {
/// Volume of the geometry mesh a particle region was filled from, from `strata mesh --json`:
/// particles · (π/6)d³ / packing density.
double filled_volume(const std::string& scene, double d) {
  const auto r = run_strata("mesh " + scene + " --json");
  EXPECT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  const auto& region = j["regions"][0];
  return region["particles"].get<double>() * M_PI / 6 * d * d * d / region["packing_density"].get<double>();
}
}  // namespace

// A CAD sphere written in millimetres: `unit` scales it to metres, and `mesh_size` on the
// particle region sets the geometry mesh that decides what is inside (gmsh's default mesh of a
// curved CAD surface makes the sphere 3.5 % too small; one particle diameter: within 0.5 %).
TEST(CliHardening, CadFilesInMillimetresAndTheirCurvedSurfaces) {
  if (!have_gmsh()) GTEST_SKIP() << "needs STRATA_WITH_GMSH";
  const fs::path d = temp_dir("cad_mm");
  std::ofstream(d / "sphere.geo") << "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0, 0, 0, 20};\n"
                                     "Physical Volume(\"rock\") = {1};\n";
  auto scene = [&](const std::string& extra) {
    const fs::path f = d / "scene.toml";
    std::ofstream(f)
        << "[scene]\ndimension = 3\n"
        << kMaterial
        << "\n[[region]]\nname = \"rock\"\nmaterial = \"rock\"\ndiameter = 0.002\nshape = \"file\"\n"
           "file = \"sphere.geo\"\nphysical = \"rock\"\nunit = \"mm\"\n"
        << extra << "\n[solver]\nsteps = 2\n";
    return f.string();
  };
  const double exact = 4.0 / 3.0 * M_PI * 0.02 * 0.02 * 0.02;  // m³: 20 mm read as 0.02 m
  const double coarse = filled_volume(scene(""), 0.002) / exact - 1;
  const double fine = filled_volume(scene("mesh_size = 0.002"), 0.002) / exact - 1;
  EXPECT_LT(coarse, -0.01) << "gmsh's default mesh of the sphere (the reason for mesh_size)";
  EXPECT_LT(std::abs(fine), 0.005) << "mesh_size = one diameter: volume error " << fine;
  fs::remove_all(d);
}

// Geometry extensions: one list for the readers and the scene checks (.brep and .stp are
// gmsh's); mesh_size on a particle shape that has no mesh is refused, not ignored.
TEST(CliHardening, GeometryExtensionsAndMeshSizeWhereItMeansSomething) {
  const fs::path d = temp_dir("extensions");
  for (const std::string ext : {".brep", ".stp", ".step", ".brp", ".dxf"})
    std::ofstream(d / ("part" + ext)) << "\n";
  for (const std::string ext : {".brep", ".stp", ".step", ".brp"}) {
    const auto r = run_strata("check " + kQuick + " --set region[0].shape=\"file\" --set region[0].file=\"" +
                              (d / ("part" + ext)).string() + "\"");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_FALSE(contains(r.output, "not a geometry file strata reads")) << ext << ": " << r.output;
  }
  const auto bad = run_strata("check " + kQuick + " --set region[0].shape=\"file\" --set region[0].file=\"" +
                              (d / "part.dxf").string() + "\"");
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_TRUE(contains(bad.output, ".brep")) << bad.output;
  const auto box = run_strata("check " + kQuick + " --set region[0].mesh_size=0.001");
  EXPECT_EQ(box.status, 2) << box.output;
  EXPECT_TRUE(contains(box.output, "--set region[0].mesh_size=0.001: mesh_size sets")) << box.output;
  fs::remove_all(d);
}
