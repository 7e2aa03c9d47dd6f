// Scenes with FEM and particle regions from one geometry file run through the one run path
// (scene::Run): both parts in one series, restart bit for bit, serial == parallel coupling.
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/core/parallel.hpp>
#include <strata/io/series.hpp>
#include <strata/io/vtk.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "scene_test_util.hpp"

namespace fs = std::filesystem;

using strata::scene::RunObserver;
using strata::scene::RunStatus;
using strata::scene::test::fresh_path;

namespace {

const fs::path kTunnel = fs::path(STRATA_SOURCE_DIR) / "examples" / "05_tunnel" / "quick.toml";

nlohmann::json summary(const fs::path& dir) {
  std::ifstream f(dir / "summary.json");
  return nlohmann::json::parse(f);
}

/// Runs the quick tunnel with `overrides` into `dir` (no pictures: this is about the state).
strata::scene::RunResult run_tunnel(const fs::path& dir, std::vector<std::string> overrides,
                                    const fs::path& restart = {}) {
  overrides.push_back("output.render=false");
  const auto sc = strata::scene::load(kTunnel, overrides);
  strata::scene::Run run(sc, {dir, false, restart});
  RunObserver quiet;
  return run.execute(quiet);
}

}  // namespace

TEST(CoupledRun, TunnelSceneWritesParticlesAndFemIntoOneSeries) {
  if (!STRATA_WITH_GMSH || !STRATA_WITH_VTK)
    GTEST_SKIP() << "the tunnel is a .geo file and the test reads its frames: needs STRATA_WITH_GMSH and "
                    "STRATA_WITH_VTK";
  const fs::path dir = fresh_path("coupled_run_series");
  const auto r = run_tunnel(dir, {"solver.steps=400", "output.frames=2"});
  EXPECT_EQ(r.status, RunStatus::Completed);
  EXPECT_EQ(r.step, 400);
  EXPECT_TRUE(fs::exists(dir / "particles.pvd"));
  EXPECT_TRUE(fs::exists(dir / "fem.pvd"));
  const auto j = summary(dir);
  EXPECT_EQ(j["status"], "completed");
  EXPECT_EQ(j["eta"], 2);
  EXPECT_GT(j["particles"].get<std::size_t>(), 700u);
  EXPECT_GT(j["fem_elements"].get<std::size_t>(), 1000u);
  // η·dt = 0.6·dt_crit is below the FEM's explicit limit, so "auto" chose central differences.
  EXPECT_EQ(j["fem_integrator"], "central-difference");
  // The FEM frames and the particle frames are at the same times (3 each: t = 0 and 2 more).
  std::ifstream pvd(dir / "fem.pvd");
  const std::string text((std::istreambuf_iterator<char>(pvd)), {});
  std::size_t frames = 0;
  for (std::size_t at = text.find("<DataSet"); at != std::string::npos; at = text.find("<DataSet", at + 1))
    ++frames;
  EXPECT_EQ(frames, 3u);
  // Both parts carry the overlap roles (0 internal, 1 boundary, 2 external): as many external
  // particles and nodes as the model has, and sources of each.
  const auto pe = strata::io::read_pvd(dir / "particles.pvd"), fe = strata::io::read_pvd(dir / "fem.pvd");
  ASSERT_EQ(pe.size(), 3u);
  ASSERT_EQ(fe.size(), 3u);
  const strata::io::PointCloud p = strata::io::read_vtp(dir / pe.back().file).points;
  const strata::io::MeshFrame mesh = strata::io::read_vtu(dir / fe.back().file);
  const strata::io::Array* ptag = p.find("overlap");
  const strata::io::Array* ntag = mesh.find_point("overlap");
  ASSERT_NE(ptag, nullptr);
  ASSERT_NE(ntag, nullptr);
  std::size_t count[2][3] = {};
  for (std::size_t i = 0; i < p.size(); ++i) ++count[0][std::size_t(ptag->at(i))];
  for (std::size_t n = 0; n < mesh.nodes(); ++n) ++count[1][std::size_t(ntag->at(n))];
  EXPECT_EQ(count[0][2], j["overlap_external_particles"].get<std::size_t>());
  EXPECT_EQ(count[1][2], j["overlap_external_nodes"].get<std::size_t>());
  EXPECT_GT(count[0][1], 0u);
  EXPECT_GT(count[1][1], 0u);
}

TEST(CoupledRun, SerialAndParallelCouplingGiveTheSameBits) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "the tunnel is a .geo file: needs STRATA_WITH_GMSH";
  strata::par::set_threads(1);
  const fs::path a = fresh_path("coupled_run_serial"), b = fresh_path("coupled_run_parallel");
  run_tunnel(a, {"solver.steps=200", "output.frames=0", "solver.coupling=\"serial\""});
  run_tunnel(b, {"solver.steps=200", "output.frames=0", "solver.coupling=\"parallel\""});
  EXPECT_EQ(summary(a)["state_hash"], summary(b)["state_hash"]);
  EXPECT_EQ(summary(b)["coupling"], "parallel");
}

TEST(CoupledRun, RestartFromACheckpointContinuesBitForBit) {
  if (!STRATA_WITH_HDF5) GTEST_SKIP() << "checkpoints need STRATA_WITH_HDF5";
  const fs::path straight = fresh_path("coupled_run_straight"), split = fresh_path("coupled_run_split");
  run_tunnel(straight, {"solver.steps=400", "output.frames=0"});
  run_tunnel(split, {"solver.steps=200", "output.frames=0"});
  const auto r = run_tunnel(split, {"solver.steps=400", "output.frames=0"}, split / "checkpoint.h5");
  EXPECT_EQ(r.first_step, 200);
  EXPECT_EQ(r.step, 400);
  EXPECT_EQ(summary(split)["state_hash"], summary(straight)["state_hash"]);
}

TEST(CoupledRun, FemOnlySceneMovesItsLoadedSideAtTheGivenVelocity) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "its FEM region is meshed by gmsh: needs STRATA_WITH_GMSH";
  // The far field alone (the tunnel's FEM region, the hole now an empty disk of radius Rp):
  // the top nodes move at the prescribed velocity, everything stays finite.
  const fs::path dir = fresh_path("coupled_run_fem_only");
  const fs::path scene = dir.string() + ".toml";
  {
    std::ifstream in(kTunnel);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const auto a = text.find("[[region]]\nname = \"near\"");
    const auto b = text.find("[[region]]\nname = \"far\"");
    ASSERT_NE(a, std::string::npos);
    ASSERT_NE(b, std::string::npos);
    text.erase(a, b - a);
    const auto g = text.find("[[group]]");
    text.insert(g, "[probe]\ngauges = [\"top\"]\n\n");
    std::string geo = (kTunnel.parent_path() / "tunnel.geo").string();
    for (std::size_t at = text.find("\"tunnel.geo\""); at != std::string::npos;
         at = text.find("\"tunnel.geo\"", at))
      text.replace(at, 12, "\"" + geo + "\""), at += geo.size() + 2;
    std::ofstream(scene) << text;
  }
  const auto sc = strata::scene::load(scene, {"solver.steps=50", "output.frames=0", "output.render=false"});
  strata::scene::Run run(sc, {dir, false, {}});
  RunObserver quiet;
  const auto r = run.execute(quiet);
  EXPECT_EQ(r.status, RunStatus::Completed);
  ASSERT_TRUE(run.model().has_fem());
  EXPECT_FALSE(run.model().has_particles());
  // Last probe row: the top gauge's uy is -0.05 m/s × t (prescribed exactly).
  std::ifstream probes(dir / "probes.csv");
  std::string line, last;
  while (std::getline(probes, line))
    if (!line.empty()) last = line;
  std::vector<double> v;
  std::stringstream ss(last);
  for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
  ASSERT_GE(v.size(), 2u);
  EXPECT_NEAR(v.back(), -0.05 * v[1], 1e-12 * 0.05 * v[1] + 1e-18);
}
