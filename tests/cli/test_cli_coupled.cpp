// `strata check|run|mesh` of coupled-chain scenes ([coupled], the chains of Li et al. 2023):
// exit status, the stability numbers, and what is (not) written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_test_util.hpp"
#include "scene_fixtures.hpp"

namespace fs = std::filesystem;
using namespace cli_test;

namespace {

const fs::path kMetamaterialExample = fs::path(STRATA_SOURCE_DIR) / "examples" / "02_metamaterial_chain";

/// A chain6 sweep small enough for a test (2 s simulated, two η, serial, no plot).
const std::string kChain6 = fixtures::chain_scene("chain6", "1e-4", "1, 20", "duration = 2.0\nrepeats = 1\n");

}  // namespace

// The dt_DEM = 1e-4 s of Li et al. 2023 is unstable for the metamaterial chain. `strata check`
// refuses it (exit 2) at the scene's dt_dem, naming the whole chain's limit 7.68e-5 s and the
// DEM partition's 8.0e-5 s (8.006e-5, printed as 8.01e-05 with three digits).
TEST(CliCoupled, CheckRefusesThePapersStepNamingBothLimits) {
  const fs::path paper = kMetamaterialExample / "paper.toml";
  const auto r = run_strata("check " + paper.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find(paper.string() + ":12:10: dt_DEM = 0.0001 s is unstable"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("7.68e-05 s for the whole chain"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("8.01e-05 s for the DEM partition alone"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(kMetamaterialExample / "out" / "paper")) << "check must not write output";
}

TEST(CliCoupled, CheckPrintsTheStabilityNumbersOfAStableScene) {
  const auto r = run_strata("check " + (kMetamaterialExample / "scene.toml").string());
  EXPECT_EQ(r.status, 0) << r.output;
  for (const char* what :
       {"whole chain: omega_max = 2.603e+04 rad/s", "explicit limit 7.683e-05 s",
        "DEM partition: limit 8.006e-05 s", "eta = 20: dt_FEM = 8e-05 s",
        "exchange interval 0.999 x the DEM limit", "an explicit FEM step would be unstable here",
        "reference: monolithic implicit Newmark"})
    EXPECT_NE(r.output.find(what), std::string::npos) << what << "\n" << r.output;
  const auto j = run_strata("check --json " + (kMetamaterialExample / "scene.toml").string());
  EXPECT_EQ(j.status, 0) << j.output;
  EXPECT_NE(j.output.find("\"per_eta\""), std::string::npos) << j.output;
}

TEST(CliCoupled, UnstableOrInvalidSceneWritesNothing) {
  const fs::path d = temp_dir("refused");
  // The paper's step, through --set on a copy of the stable scene.
  std::string text = kChain6;
  text.replace(text.find("case = \"chain6\""), 15, "case = \"metamaterial\"");
  const fs::path meta = write(d, "meta.toml", text);
  const auto r = run_strata("run " + meta.string() + " --set coupled.dt_dem=1e-4 -o " + (d / "res").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("7.68e-05 s for the whole chain"), std::string::npos) << r.output;
  // An explicit FEM step above its limit at eta = 20 (chain6 at dt_DEM = 0.2 s: the DEM and the
  // FEM explicit limits are both 1 s, so eta = 20 gives dt_FEM = 4 s): refused before the run.
  const fs::path fem = write(d, "fem.toml", kChain6);
  const auto f = run_strata("run " + fem.string() + " --set coupled.dt_dem=0.2 --set coupled.duration=20");
  EXPECT_EQ(f.status, 2) << f.output;
  EXPECT_NE(f.output.find(fem.string() + ":4:7: eta = 20 cannot run"), std::string::npos) << f.output;
  // A mixed scene.
  const fs::path mixed = write(d, "mixed.toml", kChain6 + "\n[solver]\ndt = 1e-4\n");
  const auto m = run_strata("run " + mixed.string());
  EXPECT_EQ(m.status, 2) << m.output;
  EXPECT_NE(m.output.find(mixed.string() + ":13:1: [solver] cannot be mixed with [coupled]"),
            std::string::npos)
      << m.output;
  // Nothing written: no output folder, no staging folder.
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().extension(), ".toml") << "left behind: " << e.path();
  EXPECT_EQ(run_strata("mesh " + fem.string()).status, 2);
  fs::remove_all(d);
}

TEST(CliCoupled, RunWritesTheSweepFilesAllAtOnce) {
  const fs::path d = temp_dir("run");
  const fs::path f = write(d, "chain6.toml", kChain6);
  const auto r = run_strata("run " + f.string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* file : {"chain6_sweep.csv", "chain6_sweep.md", "summary.json"})
    EXPECT_TRUE(fs::exists(d / "res" / file)) << file << "\n" << r.output;
  EXPECT_FALSE(fs::exists(d / "res" / "chain6_sweep.png")) << "output.render = false";
  EXPECT_NE(r.output.find("| 20 | serial |"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("wrote:"), std::string::npos) << r.output;
  // -o wins over output.directory; only the scene and the two output folders are left.
  ASSERT_EQ(run_strata("run " + f.string() + " -o " + (d / "other").string()).status, 0);
  EXPECT_TRUE(fs::exists(d / "other" / "chain6_sweep.csv"));
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++entries;
  EXPECT_EQ(entries, 3) << "a staging folder was left behind";
  fs::remove_all(d);
}
