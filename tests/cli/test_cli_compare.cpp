// `strata compare`: gauge error against run time of a scene over η against a reference scene.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_test_util.hpp"
#include "series_check.hpp"

namespace fs = std::filesystem;
using namespace cli_test;
using nlohmann::json;

namespace {

/// A bonded 2D block squeezed by its top row at `speed` (m/s), with gauges on the top row
/// and on a band across the middle. No damping, no breaking in 400 steps: a linear system
/// at rest at t = 0, so every displacement is proportional to the speed.
std::string block(const std::string& speed, bool gauges = true) {
  return "[scene]\ndimension = 2\n" + kMaterial + R"(
[[region]]
name = "block"
material = "rock"
diameter = 0.001
size = [0.010, 0.0105]

[[group]]
name = "mid"
select = "box"
box_min = [-1.0, 0.004]
box_max = [1.0, 0.0065]
)" + platens(speed) +
         (gauges ? "\n[probe]\ngauges = [\"mid\", \"top\"]\n" : "") + R"(
[solver]
steps = 400
)";
}

json summary_of(const fs::path& dir) { return json::parse(std::ifstream(dir / "summary.json")); }

}  // namespace

TEST(CliCompare, HelpShowsAnExample) {
  auto h = run_strata("compare --help");
  EXPECT_EQ(h.status, 0);
  EXPECT_NE(h.output.find("Example"), std::string::npos);
}

TEST(CliCompare, ASceneAgainstItselfHasNoError) {
  const fs::path d = temp_dir("compare_self");
  const fs::path sc = write(d, "block.toml", block("0.05"));
  auto r = run_strata("compare " + sc.string() + " --reference " + sc.string() + " --no-plot -o " +
                      (d / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const json j = summary_of(d / "out");
  ASSERT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["gauges"], json({"mid", "top"}));
  const json& row = j["rows"][1];
  EXPECT_EQ(row["status"], "completed");
  // strata is deterministic: the same scene gives the same bits, so the error is exactly 0
  EXPECT_EQ(row["error"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(d / "out" / "compare.csv"));
  EXPECT_TRUE(fs::exists(d / "out" / "compare.md"));
  EXPECT_TRUE(fs::exists(d / "out" / "runs" / "reference" / "probes.csv"));
  fs::remove_all(d);
}

TEST(CliCompare, ErrorOfAScaledLoadIsTheScale) {
  // Linear elasticity from rest: driving the top 10 % faster scales every displacement by
  // 1.1, so each gauge's error is 0.1 up to the lattice's geometric nonlinearity (strains
  // of 1e-4 here: a relative effect far below 1e-3).
  const fs::path d = temp_dir("compare_scaled");
  const fs::path ref = write(d, "ref.toml", block("0.05"));
  const fs::path sc = write(d, "fast.toml", block("0.055"));
  auto r = run_strata("compare " + sc.string() + " --reference " + ref.string() + " --no-plot -o " +
                      (d / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const json j = summary_of(d / "out");
  const json& row = j["rows"][1];
  EXPECT_NEAR(row["gauge_errors"]["top"].get<double>(), 0.1, 1e-9);  // prescribed: exactly 1.1x
  EXPECT_NEAR(row["gauge_errors"]["mid"].get<double>(), 0.1, 1e-3);
  EXPECT_NEAR(row["error"].get<double>(), 0.1, 1e-3);
  EXPECT_NE(r.output.find("| scene | 105 | 0 | 400 |"), std::string::npos) << r.output;
  fs::remove_all(d);
}

TEST(CliCompare, CoupledTunnelAgainstAllParticlesWithARefusedEta) {
  if (!have_gmsh()) GTEST_SKIP() << "the tunnel is a .geo file: needs STRATA_WITH_GMSH";
  const std::string ex = std::string(STRATA_SOURCE_DIR) + "/examples/05_tunnel/";
  const fs::path d = temp_dir("compare_tunnel");
  auto r = run_strata("compare " + ex + "scene.toml --reference " + ex +
                      "reference.toml --eta 2 3 --set solver.steps=2000 " + "--no-plot -o " + d.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const json j = summary_of(d);
  ASSERT_EQ(j["rows"].size(), 3u);
  EXPECT_EQ(j["rows"][1]["status"], "completed");
  EXPECT_GT(j["rows"][1]["fem_nodes"].get<int>(), 0);
  EXPECT_LT(j["rows"][1]["particles"].get<int>(), j["rows"][0]["particles"].get<int>());
  // The crown's settlement of the coupled model follows the all-particle one (12.6 % at
  // 2,000 steps, most of it the arrival of the first wave through the coarser FEM)
  EXPECT_LT(j["rows"][1]["gauge_errors"]["crown"].get<double>(), 0.2);
  // the exchange interval 3·dt is above the coupled stability limit: refused, not run
  EXPECT_EQ(j["rows"][2]["status"], "refused");
  EXPECT_NE(j["rows"][2]["note"].get<std::string>().find("solver.eta"), std::string::npos);
  std::ifstream csv(d / "compare.csv");
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 4);  // the header, the reference, eta = 2 and eta = 3
  fs::remove_all(d);
}

TEST(CliCompare, ScenesWithoutGaugesAreRefused) {
  const fs::path d = temp_dir("compare_nogauge");
  const fs::path sc = write(d, "block.toml", block("0.05", false));
  auto r =
      run_strata("compare " + sc.string() + " --reference " + sc.string() + " -o " + (d / "out").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("records no gauges"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out" / "compare.csv"));
  fs::remove_all(d);
}
