// Parameter studies: the runs a study plans (every combination, the last [[vary]] key fastest,
// values written as the scene takes them) and the mean and sample standard deviation of its
// measures over the spread key.
#include <gtest/gtest.h>
#include <strata/cases/study.hpp>
#include <strata/scene/scene.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace strata::cases;

namespace {

strata::scene::Scene study_of(const std::string& extra = "") {
  const fs::path d = fs::temp_directory_path() / "strata_test_study";
  fs::create_directories(d);
  std::ofstream(d / "base.toml") << "[scene]\ndimension = 2\n";  // read only as a file here
  return strata::scene::parse(
      "[study]\nscene = \"base.toml\"\nset = [\"solver.steps=10\"]\nspread = \"scene.seed\"\n"
      "\n[[vary]]\nkey = \"region.box.size\"\nvalues = [0.01, 0.02]\ncomponents = 2\n"
      "\n[[vary]]\nkey = \"scene.seed\"\nvalues = [1, 2, 3]\n"
      "\n[[measure]]\nname = \"nu\"\nvalue = \"/measured_elastic/poisson_ratio\"\n" +
          extra,
      d / "study.toml", {});
}

}  // namespace

TEST(Study, PlansEveryCombinationLastKeyFastest) {
  const auto st = study_of();
  const StudyPlan p = plan_study(st);
  ASSERT_EQ(p.overrides.size(), 6u);
  EXPECT_EQ(p.overrides[0],
            (std::vector<std::string>{"solver.steps=10", "region.box.size=[0.01, 0.01]", "scene.seed=1"}));
  EXPECT_EQ(p.overrides[2][2], "scene.seed=3");
  EXPECT_EQ(p.overrides[3][1], "region.box.size=[0.02, 0.02]");
  EXPECT_EQ(p.values[5], (std::vector<double>{0.02, 3}));
}

// Groups over the seeds: mean and sample standard deviation of the runs whose measures are all
// finite (a run without the number counts in `runs`, not in `counted`).
TEST(Study, GroupsTakeMeanAndSpreadOverTheSpreadKey) {
  const auto st = study_of();
  const double nan = std::nan("");
  std::vector<StudyPoint> pts = {{{0.01, 1}, {0.2}, "completed", 0},  {{0.01, 2}, {0.4}, "completed", 0},
                                 {{0.01, 3}, {0.3}, "completed", 0},  {{0.02, 1}, {0.5}, "completed", 0},
                                 {{0.02, 2}, {nan}, "blew up: x", 0}, {{0.02, 3}, {0.7}, "completed", 0}};
  const auto g = group_points(st, pts);
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0].values[0], 0.01);
  EXPECT_TRUE(std::isnan(g[0].values[1]));
  EXPECT_EQ(g[0].runs, 3u);
  EXPECT_EQ(g[0].counted, 3u);
  EXPECT_NEAR(g[0].mean[0], 0.3, 1e-15);
  EXPECT_NEAR(g[0].std[0], 0.1, 1e-15);
  EXPECT_EQ(g[1].runs, 3u);
  EXPECT_EQ(g[1].counted, 2u);
  EXPECT_NEAR(g[1].mean[0], 0.6, 1e-15);
  EXPECT_NEAR(g[1].std[0], std::sqrt(0.02), 1e-15);
}

// A study names [[vary]] keys in its roles, and a measure is a JSON pointer; [[vary]] belongs to
// a study file.
TEST(Study, RolesAndPointersAreChecked) {
  auto error_of = [](auto&& f) {
    try {
      f();
    } catch (const strata::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string x =
      error_of([] { study_of("\n[[measure]]\nname = \"E\"\nvalue = \"measured_elastic\"\n"); });
  EXPECT_NE(x.find("is not a JSON pointer into summary.json"), std::string::npos) << x;
  const fs::path d = fs::temp_directory_path() / "strata_test_study";
  const fs::path quick = fs::path(STRATA_SOURCE_DIR) / "examples" / "01_uniaxial_compression" / "quick.toml";
  std::ifstream in(quick);
  const std::string scene_text((std::istreambuf_iterator<char>(in)), {});
  const std::string stray = error_of([&] {
    strata::scene::parse(scene_text + "\n[[vary]]\nkey = \"scene.seed\"\nvalues = [1]\n", quick, {});
  });
  EXPECT_NE(stray.find("[[vary]] belongs to a study file"), std::string::npos) << stray;
  const std::string role = error_of([&] {
    strata::scene::parse(
        "[study]\nscene = \"base.toml\"\nx = \"scene.dimension\"\n\n[[vary]]\nkey = \"scene.seed\"\n"
        "values = [1]\n\n[[measure]]\nname = \"nu\"\nvalue = \"/a\"\n",
        d / "s.toml", {});
  });
  EXPECT_NE(role.find("study.x = \"scene.dimension\" is not a [[vary]] key (varied: scene.seed)"),
            std::string::npos)
      << role;
}
