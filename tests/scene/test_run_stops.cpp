// How a run stops on request (Ctrl-C, SIGTERM) through scene::Run's observer, wherever it is:
// while stepping it leaves a frame and a checkpoint; while the pictures are drawn it stops
// drawing, keeps what is drawn and says so (it never ends as if nothing had happened).
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace fs = std::filesystem;
using strata::scene::RunObserver;
using strata::scene::RunResult;
using strata::scene::RunStatus;

namespace {

const fs::path kQuick = fs::path(STRATA_SOURCE_DIR) / "examples" / "01_uniaxial_compression" / "quick.toml";

/// Asks to stop (SIGINT) at its `after`-th poll once every step is done: while pictures are drawn.
class StopWhileDrawing : public RunObserver {
 public:
  explicit StopWhileDrawing(int after) : after_(after) {}
  void stepped(const RunResult&) override { stepped_ = true; }
  int stop_requested() override { return stepped_ && ++polls_ >= after_ ? SIGINT : 0; }

 private:
  int after_, polls_ = 0;
  bool stepped_ = false;
};

std::size_t count_png(const fs::path& dir) {
  std::size_t n = 0;
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().extension() == ".png";
  return n;
}

}  // namespace

TEST(RunStops, CtrlCWhileDrawingStopsTheDrawingAndSaysSo) {
  if (!STRATA_WITH_RENDER || !STRATA_WITH_VTK)
    GTEST_SKIP() << "pictures of a series: needs STRATA_WITH_RENDER and STRATA_WITH_VTK";
  const fs::path dir = fs::temp_directory_path() / "strata_run_stops_drawing";
  fs::remove_all(dir);
  const auto sc = strata::scene::load(kQuick, {"solver.steps=400", "output.frames=4", "output.render=true"});
  strata::scene::Run run(sc, {dir, false, {}});
  // Polls while drawing: before the plots, before frame 0, before frame 1 (stop there).
  StopWhileDrawing observer(3);
  const RunResult r = run.execute(observer);
  EXPECT_EQ(r.status, RunStatus::PicturesInterrupted);
  EXPECT_EQ(r.stop_reason, SIGINT);
  EXPECT_EQ(r.step, 400) << "every step was done before the pictures";
  EXPECT_EQ(count_png(dir / "png"), 1u) << "frame 0 drawn, frames 1 to 4 not";
  EXPECT_FALSE(fs::exists(dir / "movie.mp4"));
  EXPECT_FALSE(fs::exists(dir / "movie.ogv"));
  std::ifstream f(dir / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(f)["status"], "completed") << "the run itself completed";
  fs::remove_all(dir);
}
