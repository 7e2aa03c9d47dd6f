// `strata check|run` of coupled wave scenes ([coupled] case = "wave", examples/04_coupled_wave):
// exit status, the stability block, what is (not) written, and the same files as
// `strata report wave`.
#include <gtest/gtest.h>

#include <strata/io/csv.hpp>

#include <filesystem>
#include <string>

#include "cli_test_util.hpp"
#include "series_check.hpp"

namespace fs = std::filesystem;
using namespace cli_test;

namespace {

const fs::path kWaveExample = fs::path(STRATA_SOURCE_DIR) / "examples" / "04_coupled_wave";

/// A wave scene outside the example folder (the geometry by absolute path): one pulse length,
/// η = 1 and 5, serial, no series, no plots: about a second.
std::string small_wave(const std::string& geometry = (kWaveExample / "wave.geo").string()) {
  return "[coupled]\ncase = \"wave\"\ngeometry = \"" + geometry +
         "\"\nwavelengths = [20]\neta = [1, 5]\nmodes = \"serial\"\nframes = 0\n\n[output]\n"
         "directory = \"res\"\nrender = false\n";
}

/// Only the scene files are left in `d` (no output folder, no staging folder).
void expect_nothing_written(const fs::path& d) {
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().extension(), ".toml") << "left behind: " << e.path();
}

}  // namespace

TEST(CliWave, CheckOfTheQuickScenePrintsTheStabilityBlock) {
  if (!have_gmsh()) GTEST_SKIP() << "the wave's geometry is a .geo file: needs STRATA_WITH_GMSH";
  const fs::path quick = kWaveExample / "quick.toml";
  const auto r = run_strata("check " + quick.string());
  EXPECT_EQ(r.status, 0) << r.output;
  for (const char* what : {"(coupled wave)", "2D coupled wave", "coupled steps: DEM leapfrog at dt_DEM =",
                           "DEM partition: limit", "FEM partition: explicit limit",
                           "eta =  1: dt_FEM =", "eta =  5: dt_FEM =", "central-difference -> ok",
                           "implicit-newmark -> ok", "sweep: wavelengths 20 d; eta = 1, 5; modes both"})
    EXPECT_NE(r.output.find(what), std::string::npos) << what << "\n" << r.output;
  EXPECT_FALSE(fs::exists(kWaveExample / "out")) << "check must not write output";

  // η = 12 puts dt_FEM = 1.8 x the lattice's limit: the coupler's note on the copy step.
  const auto n = run_strata("check " + quick.string() + " --set coupled.eta=[12]");
  EXPECT_EQ(n.status, 0) << n.output;
  EXPECT_NE(n.output.find("note: dt_FEM = "), std::string::npos) << n.output;
  EXPECT_NE(n.output.find("the overlap exchange may be unstable"), std::string::npos) << n.output;

  const auto j = run_strata("check --json " + quick.string());
  EXPECT_EQ(j.status, 0) << j.output;
  EXPECT_NE(j.output.find("\"per_eta\""), std::string::npos) << j.output;
  EXPECT_NE(j.output.find("\"case\": \"wave\""), std::string::npos) << j.output;
}

// An explicit FEM above its limit (central difference at η = 5, 0.75 x the lattice's limit while
// the FEM's explicit limit is below 0.6 x) is refused before anything runs, at the key.
TEST(CliWave, CheckRefusesAnExplicitFemAboveItsLimit) {
  if (!have_gmsh()) GTEST_SKIP() << "the wave's geometry is a .geo file: needs STRATA_WITH_GMSH";
  const fs::path d = temp_dir("wave_refused");
  std::string text = small_wave();
  text.replace(text.find("modes"), 0, "fem_scheme = \"central-difference\"\n");
  const fs::path cd = write(d, "cd.toml", text);
  const auto r = run_strata("check " + cd.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find(cd.string() + ":6:14: eta = 5 cannot run with fem_scheme = \"central-difference\""),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("eta =  5: dt_FEM ="), std::string::npos) << "the numbers come first\n" << r.output;
  // run: the same refusal, and nothing written.
  const auto run = run_strata("run " + cd.string() + " -o " + (d / "res").string());
  EXPECT_EQ(run.status, 2) << run.output;
  expect_nothing_written(d);
  fs::remove_all(d);
}

TEST(CliWave, InvalidSceneWritesNothing) {
  if (!have_gmsh()) GTEST_SKIP() << "the wave's geometry is a .geo file: needs STRATA_WITH_GMSH";
  const fs::path d = temp_dir("wave_invalid");
  // A chain-only key in a wave scene.
  std::string text = small_wave();
  text.replace(text.find("wavelengths"), 0, "dt_dem = 1e-4\n");
  const fs::path bad = write(d, "bad.toml", text);
  const auto r = run_strata("run " + bad.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(
      r.output.find(bad.string() + ":4:10: dt_dem applies only to case = \"chain6\" or \"metamaterial\""),
      std::string::npos)
      << r.output;
  // A pulse too long for the geometry: refused at wavelengths, after the model is built.
  const fs::path lng = write(d, "long.toml", small_wave());
  const auto l = run_strata("run " + lng.string() + " --set coupled.wavelengths=[20,400]");
  EXPECT_EQ(l.status, 2) << l.output;
  EXPECT_NE(l.output.find("--set coupled.wavelengths=[20,400]: wave: a pulse of 400 particle diameters"),
            std::string::npos)
      << l.output;
  expect_nothing_written(d);
  fs::remove_all(d);
}

TEST(CliWave, MissingGeometryFileNamesThePath) {
  const fs::path d = temp_dir("wave_geo");
  const fs::path f = write(d, "nogeo.toml", small_wave("no_such_wave.geo"));
  for (const char* cmd : {"check ", "run "}) {
    const auto r = run_strata(cmd + f.string());
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(f.string() + ":3:12: geometry 'no_such_wave.geo' not found (looked for " +
                            (d / "no_such_wave.geo").lexically_normal().string()),
              std::string::npos)
        << r.output;
  }
  expect_nothing_written(d);
  fs::remove_all(d);
}

// `strata run SCENE` and `strata report wave` share one path: the same files, the same numbers.
TEST(CliWave, RunWritesTheSameFilesAsTheReport) {
  if (!have_gmsh()) GTEST_SKIP() << "the wave's geometry is a .geo file: needs STRATA_WITH_GMSH";
  const fs::path d = temp_dir("wave_run");
  const fs::path f = write(d, "wave.toml", small_wave());
  const auto r = run_strata("run " + f.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("wrote:"), std::string::npos) << r.output;
  const auto rep = run_strata("report wave --geometry " + (kWaveExample / "wave.geo").string() +
                              " --wavelengths 20 --eta 1 5 --modes serial --frames 0 --no-plot -o " +
                              (d / "rep").string());
  ASSERT_EQ(rep.status, 0) << rep.output;
  for (const char* file : {"wave_sweep.csv", "wave_sweep.md", "summary.json"}) {
    EXPECT_TRUE(fs::exists(d / "res" / file)) << file << "\n" << r.output;
    EXPECT_TRUE(fs::exists(d / "rep" / file)) << file << "\n" << rep.output;
  }
  EXPECT_FALSE(fs::exists(d / "res" / "wave_sweep.png")) << "output.render = false";
  const auto a = strata::io::read_csv(d / "res" / "wave_sweep.csv");
  const auto b = strata::io::read_csv(d / "rep" / "wave_sweep.csv");
  ASSERT_EQ(a.rows(), 2u);
  ASSERT_EQ(b.rows(), 2u);
  for (const char* col : {"eta", "ok", "dt_fem_s", "R_peak", "T_peak", "R_energy", "T_energy"})
    EXPECT_EQ(a.column(col), b.column(col)) << col << ": the scene and the report differ";
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++entries;
  EXPECT_EQ(entries, 3) << "a staging folder was left behind";
  fs::remove_all(d);
}
