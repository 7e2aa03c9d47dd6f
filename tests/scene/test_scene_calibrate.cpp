// A calibration file ([calibrate]): its keys and the checks between them; the cylinder shape of
// its 3D specimens; a run that stops once its specimen has failed ([probe] stop_after_peak).
#include <gtest/gtest.h>
#include <strata/cases/calibrate.hpp>
#include <strata/core/error.hpp>
#include <strata/dem/lattice_elastic.hpp>
#include <strata/scene/model.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "scene_test_util.hpp"

namespace fs = std::filesystem;
using strata::scene::test::error_of;

namespace {

const std::string kCalibration = R"toml([scene]
dimension = 2

[calibrate]
youngs_modulus = 60e9
poisson_ratio = 0.2
ucs = 200e6
tensile_strength = 12e6
density = 2650
diameter = 0.001
)toml";

}  // namespace

TEST(SceneCalibrate, TargetsAndDefaultsAreRead) {
  const auto sc = strata::scene::parse(kCalibration, "cal.toml");
  ASSERT_TRUE(sc.calibrate.has_value());
  EXPECT_FALSE(sc.coupled.has_value());
  EXPECT_DOUBLE_EQ(sc.calibrate->youngs_modulus, 60e9);
  EXPECT_DOUBLE_EQ(sc.calibrate->poisson_ratio, 0.2);
  EXPECT_DOUBLE_EQ(sc.calibrate->friction, 0.5);
  EXPECT_EQ(sc.calibrate->match.value, "ucs");
  EXPECT_EQ(sc.calibrate->iterations.value, 8);
  EXPECT_TRUE(sc.regions.empty());
  // a calibration is not a model: building one is refused, naming the command that runs it
  try {
    (void)strata::scene::build_model(sc, false);
    ADD_FAILURE() << "a calibration was built as a model";
  } catch (const strata::Error& e) {
    EXPECT_NE(std::string(e.what()).find("strata calibrate"), std::string::npos) << e.what();
  }
}

TEST(SceneCalibrate, ChecksBetweenKeysPointAtTheKey) {
  EXPECT_EQ(
      error_of(kCalibration, {"calibrate.poisson_ratio=0.4"}, "cal.toml"),
      "--set calibrate.poisson_ratio=0.4: poisson_ratio = 0.4 is above 1/3, the largest that bonds of normal "
      "and shear springs give a hexagonal lattice (with Ks = 0); allowed: -1 < poisson_ratio <= 1/3");
  EXPECT_EQ(error_of(kCalibration, {"scene.dimension=3"}, "cal.toml"), "no error")
      << "0.2 is the 3D limit itself (Ks = 0)";
  EXPECT_EQ(
      error_of(kCalibration, {"scene.dimension=3", "calibrate.poisson_ratio=0.25"}, "cal.toml"),
      "--set calibrate.poisson_ratio=0.25: poisson_ratio = 0.25 is above 1/5, the largest that bonds of "
      "normal and shear springs give a close packing along its stacking axis (with Ks = 0); allowed: -1 < "
      "poisson_ratio <= 0.2");
  EXPECT_EQ(
      error_of(kCalibration, {"calibrate.ucs=10e6"}, "cal.toml"),
      "--set calibrate.ucs=10e6: ucs = 10000000 Pa is not above tensile_strength = 12000000 Pa; rocks are "
      "several times stronger in compression than in tension");
  EXPECT_EQ(
      error_of(kCalibration, {"calibrate.lattice=\"hcp\""}, "cal.toml"),
      "--set calibrate.lattice=\"hcp\": lattice = \"hcp\" is for 3D calibrations; in 2D use hex (or auto)");
  EXPECT_EQ(error_of(kCalibration, {"calibrate.specimen_width=0.005"}, "cal.toml"),
            "--set calibrate.specimen_width=0.005: specimen_width = 0.005 m holds fewer than 10 particles of "
            "diameter 0.001 m across; allowed: 0 (40 diameters) or at least 10 diameters");
  EXPECT_EQ(
      error_of(kCalibration + "\n[solver]\ndt = 1e-8\n", {}, "cal.toml"),
      "cal.toml:12:1: [solver] cannot be mixed with [calibrate] (cal.toml:4:1): a calibration describes its "
      "targets and lattice in [calibrate] and builds its own specimens and may hold besides only [scene], "
      "[output] (keys directory, render); remove [solver] or [calibrate]");
  EXPECT_EQ(error_of(kCalibration + "\n[output]\nframes = 3\n", {}, "cal.toml"),
            "cal.toml:13:1: output.frames does not apply to a calibration ([calibrate] at cal.toml:4:1): its "
            "[output] takes only directory, render");
}

TEST(SceneCalibrate, AnalyticalInversionGivesBackTheLattice) {
  // hex_springs and close_packed_stacking_axis_springs invert the lattices' elastic constants
  for (const double ratio : {0.0, 0.3, 1.0, 2.5}) {
    const double kn = 6.5e10, ks = ratio * kn, d = 1e-3;
    const auto e2 = strata::dem::hex_elastic(kn, ks);
    const auto k2 = strata::dem::hex_springs(e2.E, e2.nu);
    EXPECT_NEAR(k2.kn / kn, 1.0, 1e-12);
    EXPECT_NEAR(k2.ks, ks, 1e-12 * kn);
    const auto e3 = strata::dem::close_packed_stacking_axis_elastic(kn, ks, d);
    const auto k3 = strata::dem::close_packed_stacking_axis_springs(e3.E, e3.nu, d);
    EXPECT_NEAR(k3.kn / kn, 1.0, 1e-12);
    EXPECT_NEAR(k3.ks, ks, 1e-12 * kn);
  }
}

// The specimens a calibration writes load and hold what they should: the 3D disc is a
// cylinder of the right volume, loaded on two lines of particles along its thickness.
TEST(SceneCalibrate, SpecimenScenesAreValidModels) {
  const auto sc = strata::scene::parse(
      kCalibration, "cal.toml",
      {"scene.dimension=3", "calibrate.poisson_ratio=0.15", "calibrate.specimen_width=0.012"});
  strata::cases::LatticeParameters p;
  p.kn = 4e7, p.ks = 1e7, p.fn_max = 2, p.fs0 = 4;
  const auto uni =
      strata::scene::parse(strata::cases::specimen_scene(sc, "uniaxial", p, 1.0, 1e-3, false), "u.toml");
  ASSERT_EQ(uni.regions.size(), 1u);
  EXPECT_EQ(uni.regions[0].shape.value, strata::scene::RegionShape::Cylinder);
  const auto m = strata::scene::build_model(uni, false);
  // HCP: one sphere per d³/√2; a cylinder of diameter 12 d and height 24 d, with whole
  // spheres inside (the radius and height shrink by d/2 and d): within 15 %
  const double d = 1e-3, r = 0.006 - d / 2, h = 0.024 - d;
  const double expected = std::numbers::pi * r * r * h / (d * d * d / std::numbers::sqrt2);
  EXPECT_NEAR(double(m.sim().particle_count()) / expected, 1.0, 0.15);
  EXPECT_GT(m.groups.at("top"), 50u) << "the top layer of a 12 d cylinder";
  const auto disc =
      strata::scene::parse(strata::cases::specimen_scene(sc, "brazilian", p, 1.0, 1e-3, false), "b.toml");
  const auto md = strata::scene::build_model(disc, false);
  const std::size_t line = md.groups.at("top");
  EXPECT_GE(line, 3u);
  EXPECT_LE(line, 12u) << "a line of particles along the 6 mm thickness, not a face";
  EXPECT_EQ(md.groups.at("bottom"), line) << "the disc is symmetric";
}

// [calibrate] strength_spread reaches the specimens: the region of each specimen scene holds
// the spread and its coefficient of variation. A spread without its coefficient is refused at
// the key.
TEST(SceneCalibrate, SpecimensCarryTheStrengthSpread) {
  const auto sc = strata::scene::parse(
      kCalibration, "cal.toml", {"calibrate.strength_spread=\"weibull\"", "calibrate.strength_cov=0.2"});
  strata::cases::LatticeParameters p;
  p.kn = 6.5e10, p.ks = 2.3e10, p.fn_max = 1.2e4, p.fs0 = 3.7e4;
  for (const char* specimen : {"uniaxial", "brazilian"}) {
    const auto s =
        strata::scene::parse(strata::cases::specimen_scene(sc, specimen, p, 1.0, 1e-3, false), "s.toml");
    ASSERT_EQ(s.regions.size(), 1u);
    EXPECT_EQ(s.regions[0].strength_spread.value, strata::scene::StrengthSpread::Weibull) << specimen;
    EXPECT_EQ(s.regions[0].strength_cov.value, 0.2) << specimen;
  }
  EXPECT_EQ(error_of(kCalibration, {"calibrate.strength_spread=\"normal\""}, "cal.toml"),
            "--set calibrate.strength_spread=\"normal\": strength_spread = \"normal\" needs strength_cov > 0 "
            "(the coefficient of variation of the bond strengths, e.g. 0.2)");
}

// A 2D uniaxial specimen that stops once it has failed: the stress fell below the fraction of
// its peak, with a bond broken; summary.json gives the step and the run ends "completed".
TEST(SceneCalibrate, RunStopsAfterThePeak) {
  const fs::path quick = fs::path(STRATA_SOURCE_DIR) / "examples" / "01_uniaxial_compression" / "quick.toml";
  const fs::path dir = fs::temp_directory_path() / "strata_stop_after_peak";
  fs::remove_all(dir);
  const auto sc =
      strata::scene::load(quick, {"probe.stop_after_peak=0.5", "output.render=false", "output.vtk=false"});
  strata::scene::Run run(sc, {dir, false, {}});
  strata::scene::RunObserver quiet;
  const auto r = run.execute(quiet);
  std::ifstream f(dir / "summary.json");
  const auto j = nlohmann::json::parse(f);
  EXPECT_EQ(j["status"], "completed");
  ASSERT_TRUE(j.contains("stopped_after_peak_at_step"));
  EXPECT_EQ(j["stopped_after_peak_at_step"].get<std::int64_t>(), r.step);
  EXPECT_LT(r.step, 48000) << "the quick example runs 48000 steps to strain 6e-3, well past the peak";
  EXPECT_GT(j["peak_stress_pa"].get<double>(), 2e8) << "its peak (2.4e8 Pa) comes before the stop";
  fs::remove_all(dir);
  // a 2D scene of one region, with `shape` lines and `tail` tables
  auto small = [](const std::string& shape, const std::string& tail) {
    return "[scene]\ndimension = 2\n[[material]]\nname = \"rock\"\ndensity = 2650\nkn = 6.5e10\nks = 2.4e10\n"
           "[[region]]\nname = \"s\"\nmaterial = \"rock\"\ndiameter = 0.001\n" +
           shape + "[solver]\nsteps = 10\n" + tail;
  };
  EXPECT_NE(error_of(small("size = [0.01, 0.01]\n", "[probe]\nstop_after_peak = 0.5\n"), {}, "cal.toml")
                .find("stop_after_peak needs the specimen's stress"),
            std::string::npos);
  EXPECT_NE(error_of(small("shape = \"cylinder\"\ncenter = [0.0, 0.0]\nradius = 0.01\nheight = 0.01\n", ""),
                     {}, "cal.toml")
                .find("shape = \"cylinder\" is for 3D scenes; in 2D use \"disk\""),
            std::string::npos);
}
