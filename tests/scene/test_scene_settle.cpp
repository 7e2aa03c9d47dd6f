// [solver] settle: a settling stage under gravity before the run, through scene::Run; a
// restart continues the run and does not settle again; FEM scenes refuse the key at its line.
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/scene/model.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include "scene_test_util.hpp"

namespace fs = std::filesystem;
using strata::scene::RunObserver;
using strata::scene::RunResult;
using strata::scene::test::fresh_path;

namespace {

// A 20 × 20 mm block of rock on a held base row, under a strong gravity; its top row moves
// down at 0.1 m/s once loading starts. It settles for 2e-4 s (about 30 wave transits).
const std::string kSettling = R"toml([scene]
title = "settling block"
dimension = 2

[[material]]
name = "rock"
density = 2650
kn = 6.5e10
ks = 2.4e10

[[region]]
name = "block"
material = "rock"
diameter = 0.001
size = [0.02, 0.02]

[[group]]
name = "top"
select = "top_row"

[[group]]
name = "base"
select = "bottom_row"

[[boundary]]
group = "base"
type = "fixed"

[[boundary]]
group = "top"
type = "velocity"
axes = ["y"]
velocity = [0.0, -0.1]

[solver]
dt = 2e-8
steps = 400
settle = 2e-4
damping = "local"
gravity = [0.0, -1e4]

[output]
frames = 2
render = false
vtk = false
)toml";

class Settling : public RunObserver {
 public:
  void settling(std::int64_t step, std::int64_t steps) override {
    calls++;
    last = step;
    total = steps;
  }
  int calls = 0;
  std::int64_t last = -1, total = -1;
};

}  // namespace

TEST(SceneSettle, RunSettlesFirstAndARestartDoesNotSettleAgain) {
  if (!STRATA_WITH_HDF5) GTEST_SKIP() << "restart: needs STRATA_WITH_HDF5";
  const fs::path scene = fresh_path("settle_scene.toml");
  { std::ofstream(scene) << kSettling; }
  const fs::path a = fresh_path("settle_a"), b = fresh_path("settle_b");

  // 400 steps after settling; the settled start is step 0 at t = 0.
  const auto sc = strata::scene::load(scene, {});
  strata::scene::Run first(sc, {a, false, {}});
  Settling seen;
  const RunResult r = first.execute(seen);
  EXPECT_EQ(seen.total, 10000);
  EXPECT_EQ(seen.last, 10000);
  EXPECT_GE(seen.calls, 2);
  EXPECT_EQ(r.step, 400);
  EXPECT_NEAR(r.time, 400 * 2e-8, 1e-15);
  EXPECT_EQ(r.summary["settle_steps"], 10000);
  // The top row has moved by its velocity times the run's time, not the settling's.
  const auto& sim = first.model().sim();
  const auto u = sim.displacements();
  const auto ids = sim.ids();
  std::vector<std::size_t> where(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) where[ids[i]] = i;
  for (const auto id : sim.group_members("top")) EXPECT_NEAR(u[where[id]][1], -0.1 * 400 * 2e-8, 1e-15);

  // 800 steps in one go, and 400 more from the first run's checkpoint: the same state.
  const auto longer = strata::scene::load(scene, {"solver.steps=800"});
  strata::scene::Run straight(longer, {b, false, {}});
  RunObserver quiet;
  const RunResult s = straight.execute(quiet);
  strata::scene::Run resumed(longer, {a, false, a / "checkpoint.h5"});
  Settling again;
  const RunResult t = resumed.execute(again);
  EXPECT_EQ(again.calls, 0) << "a restart continues from the settled run";
  EXPECT_EQ(t.step, 800);
  EXPECT_EQ(t.summary["state_hash"], s.summary["state_hash"]);
  fs::remove_all(a), fs::remove_all(b), fs::remove(scene);
}

// A stop request while settling ends the run there: interrupted, at step 0, and summary.json
// says so.
TEST(SceneSettle, AStopRequestWhileSettlingEndsTheRun) {
  class StopAtOnce : public Settling {
   public:
    int stop_requested() override { return calls > 0 ? SIGINT : 0; }
  };
  const fs::path scene = fresh_path("settle_stop.toml");
  { std::ofstream(scene) << kSettling; }
  const fs::path dir = fresh_path("settle_stop");
  const auto sc = strata::scene::load(scene, {});  // the run keeps a reference to it
  strata::scene::Run run(sc, {dir, false, {}});
  StopAtOnce observer;
  const RunResult r = run.execute(observer);
  EXPECT_EQ(r.status, strata::scene::RunStatus::Interrupted);
  EXPECT_EQ(r.stop_reason, SIGINT);
  EXPECT_EQ(r.step, 0);
  EXPECT_EQ(observer.last, 0) << "stopped before the first chunk";
  EXPECT_EQ(r.summary["status"], "interrupted by SIGINT while settling, at step 0 of 10000");
  fs::remove_all(dir), fs::remove(scene);
}

TEST(SceneSettle, ScenesWithFemRegionsRefuseItAtItsLine) {
  std::string text = kSettling;
  text.replace(text.find("[[region]]"), 10, "[[region]]\nkind = \"fem\"");
  text.replace(text.find("diameter = 0.001\n"), 17, "");
  const auto sc = strata::scene::parse(text, "scene.toml", {});
  try {
    (void)strata::scene::build_model(sc, false);
    FAIL() << "no error";
  } catch (const strata::Error& e) {
    EXPECT_EQ(e.kind(), strata::ErrorKind::Input);
    EXPECT_NE(std::string(e.what()).find("scene.toml:38:10: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("settle = 0"), std::string::npos) << e.what();
  }
}
