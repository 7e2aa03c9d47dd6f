// [probe] wedge_group: summary.json reports the cover's taper, faults and critical taper
// through scene::Run; bad wedge keys are refused at their line.
#include <gtest/gtest.h>
#include <strata/core/error.hpp>
#include <strata/dem/wedge.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "scene_test_util.hpp"

namespace fs = std::filesystem;
using strata::scene::test::fresh_path;

namespace {

// A cover 40 × 10 mm of 1 mm disks on a fixed wall below, pushed from the right by a wall
// moving at 0.05 m/s, under gravity; 600 steps barely move it: the report's start top, wall
// and theory are what is checked.
const std::string kCover = R"toml([scene]
title = "cover"
dimension = 2

[[material]]
name = "rock"
density = 2650
kn = 6.5e10
ks = 2.4e10
friction = 0.5

[[region]]
name = "cover"
material = "rock"
diameter = 0.001
size = [0.04, 0.01]

[[wall]]
name = "floor"
point = [0.0, 0.0]
normal = [0.0, 1.0]

[[wall]]
name = "piston"
point = [0.0405, 0.0]
normal = [-1.0, 0.0]
velocity = [-0.05, 0.0]

[solver]
dt = 2e-8
steps = 600
gravity = [0.0, -9.81]

[probe]
wedge_group = "cover"
wedge_friction = [0.6, 0.3]

[output]
frames = 1
render = false
vtk = false
)toml";

std::string with(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

}  // namespace

TEST(SceneWedge, SummaryReportsTheWedgeAndItsCriticalTaper) {
  const fs::path scene = fresh_path("wedge_scene.toml"), dir = fresh_path("wedge_out");
  { std::ofstream(scene) << kCover; }
  const auto sc = strata::scene::load(scene, {});
  strata::scene::Run run(sc, {dir, false, {}});
  strata::scene::RunObserver quiet;
  const auto r = run.execute(quiet);
  ASSERT_TRUE(r.summary.contains("wedge"));
  const auto& w = r.summary["wedge"];
  EXPECT_EQ(w["group"], "cover");
  EXPECT_DOUBLE_EQ(w["spacing_m"].get<double>(), 0.001);
  // the hex rows of 1 mm disks stand 0.866 mm apart: the top lies within a diameter of 10 mm
  EXPECT_NEAR(w["initial_top_m"].get<double>(), 0.01, 0.001);
  // the piston has moved 600 steps at 0.05 m/s
  EXPECT_NEAR(w["backstop_x_m"].get<double>(), 0.0405 - 0.05 * 600 * 2e-8, 1e-12);
  EXPECT_LT(w["max_uplift_m"].get<double>(), 0.001);  // no wedge yet
  const auto t = strata::dem::critical_taper(0.6, 0.3);
  EXPECT_DOUBLE_EQ(w["critical_taper"]["taper_deg"].get<double>(), t.taper_deg);
  EXPECT_DOUBLE_EQ(w["critical_taper"]["forethrust_dip_deg"].get<double>(), t.forethrust_dip_deg);
  fs::remove_all(dir), fs::remove(scene);
}

TEST(SceneWedge, BadKeysAreRefusedAtTheirLine) {
  auto refused = [&](const std::string& text, const std::string& where, const std::string& what) {
    const fs::path scene = fresh_path("wedge_bad.toml");
    { std::ofstream(scene) << text; }
    try {
      const auto sc = strata::scene::load(scene, {});
      ADD_FAILURE() << "accepted: " << what;
    } catch (const strata::Error& e) {
      EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
    fs::remove(scene);
  };
  refused(with(kCover, "wedge_friction = [0.6, 0.3]", "wedge_friction = [0.3, 0.6]"),
          "bad.toml:36:", "must be below the internal friction");
  refused(with(kCover, "wedge_group = \"cover\"", "wedge_group = \"layers\""),
          "bad.toml:35:", "wedge_group = \"layers\" names no [[group]] or [[region]]");
  refused(with(kCover, "wedge_group = \"cover\"", "wedge_group = \"cover\"\nwedge_backstop = \"ram\""),
          "bad.toml:36:", "wedge_backstop = \"ram\" names no [[group]] or [[region]]");
}
