// Eccentric lattices (ECC4D, Zhao et al. 2021) from a scene: `strata mesh` reports and plots
// the spread of bond lengths, and `strata run` simulates the model (per-bond rest lengths,
// so it starts unloaded).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>

#include "cli_test_util.hpp"
#include "series_check.hpp"

using namespace cli_test;
using nlohmann::json;

namespace {
std::string ecc_scene(double ra, const std::string& extra = "") {
  return R"([scene]
dimension = 2
seed = 11
)" + kMaterial +
         R"(
[[region]]
name = "block"
material = "rock"
diameter = 0.001
size = [0.012, 0.0125]
eccentricity = "sphere"
ra = )" + std::to_string(ra) +
         R"(
rc = 0.5
gamma = 0.001

[solver]
steps = 300
)" + extra;
}

json ecc_mesh_json(const fs::path& scene, const fs::path& out) {
  const auto r = run_strata("mesh " + scene.string() + " --json -o " + out.string());
  EXPECT_EQ(r.status, 0) << r.output;
  return json::parse(r.output.substr(r.output.find('{')));
}
}  // namespace

// Ra = 0 keeps one bond length (the class of 1.00 d); Ra = 0.5 spreads the lengths over
// classes from about 1 - Ra to 1 + Ra (offsets of up to Ra·R at each end), and the
// histograms are written as CSV (and PNG where the build renders).
TEST(CliEcc, MeshReportsTheSpreadOfBondLengths) {
  if (!have_vtk()) GTEST_SKIP() << "`strata mesh -o` writes VTK series: needs STRATA_WITH_VTK";
  const fs::path d = temp_dir("ecc_mesh");
  const json j0 = ecc_mesh_json(write(d, "ra0.toml", ecc_scene(0.0)), d / "m0");
  ASSERT_TRUE(j0.contains("bond_length_classes"));
  EXPECT_EQ(j0["bond_length_classes"].size(), 1u) << j0["bond_length_classes"].dump();
  const json j5 = ecc_mesh_json(write(d, "ra5.toml", ecc_scene(0.5)), d / "m5");
  EXPECT_EQ(j5["bonds"], j0["bonds"]) << "the offsets keep the regular lattice's bonds";
  std::size_t classes = 0;
  double lo = 9, hi = 0;
  for (const auto& [cls, n] : j5["bond_length_classes"].items()) {
    ++classes;
    lo = std::min(lo, std::stod(cls));
    hi = std::max(hi, std::stod(cls));
  }
  EXPECT_GT(classes, 20u);
  EXPECT_GE(lo, 0.5 - 0.02);  // |length - d| <= 2·Ra·R = Ra·d
  EXPECT_LE(hi, 1.5 + 0.02);
  EXPECT_TRUE(fs::exists(d / "m5" / "bond_lengths.csv"));
  EXPECT_TRUE(fs::exists(d / "m5" / "bond_directions.csv"));
  fs::remove_all(d);
}

// With no load the eccentric model stays exactly at rest (rest lengths are the initial
// distances); under platens it loads, and the weakened bonds make it softer than the
// regular lattice at the same strain.
TEST(CliEcc, RunStartsUnloadedAndIsSofterThanTheRegularLattice) {
  if (!have_vtk()) GTEST_SKIP() << "frames need STRATA_WITH_VTK";
  const fs::path d = temp_dir("ecc_run");
  {
    const fs::path f = write(d, "rest.toml", ecc_scene(0.9, "[output]\nframes = 1\nrender = false\n"));
    const auto r = run_strata("run " + f.string() + " -o " + (d / "rest").string());
    ASSERT_EQ(r.status, 0) << r.output;
    // probes.csv: kinetic and stored energy and broken bonds stay 0 in every row
    std::ifstream in(d / "rest" / "probes.csv");
    std::string line;
    std::getline(in, line);
    std::vector<std::string> names;
    {
      std::stringstream ss(line);
      for (std::string c; std::getline(ss, c, ',');) names.push_back(c);
    }
    int rows = 0;
    while (std::getline(in, line)) {
      std::stringstream ss(line);
      std::string cell;
      for (std::size_t c = 0; c < names.size() && std::getline(ss, cell, ','); ++c)
        if (names[c] == "kinetic_energy" || names[c] == "bond_energy" || names[c].rfind("broken_", 0) == 0) {
          EXPECT_EQ(std::stod(cell), 0.0) << names[c] << " in " << line;
        }
      ++rows;
    }
    EXPECT_GT(rows, 1);
  }
  const std::string load = platens("0.5") + R"(
[probe]
stress_strain = true
top_group = "top"
bottom_group = "bottom"
axis = "y"

[output]
frames = 1
render = false
)";
  auto final_stress = [&](double ra, const std::string& name) {
    std::string text = ecc_scene(ra, load);
    if (ra == 0) text.replace(text.find("eccentricity = \"sphere\""), 23, "eccentricity = \"none\"  ");
    const fs::path f = write(d, name + ".toml", text);
    const auto r = run_strata("run " + f.string() + " -o " + (d / name).string());
    EXPECT_EQ(r.status, 0) << r.output;
    std::ifstream in(d / name / "summary.json");
    const json s = json::parse(in);
    return s["peak_stress_pa"].get<double>();  // still rising: the stress at the end
  };
  const double regular = final_stress(0.0, "regular"), ecc = final_stress(0.9, "ecc");
  EXPECT_GT(regular, 0.0);
  EXPECT_GT(ecc, 0.0);
  EXPECT_LT(ecc, regular);
  fs::remove_all(d);
}
