// The `strata` command as a user meets it: run the binary, check exit status, messages and
// the files left behind.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace fs = std::filesystem;

namespace {

struct Result {
  int status = -1;
  std::string output;  // stdout and stderr together
};

Result strata(const std::string& args) {
  const std::string cmd = std::string(STRATA_EXE) + " " + args + " 2>&1";
  Result r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.output.append(buf.data(), n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

/// A fresh directory for one test.
fs::path temp_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("strata_cli_" + name + "_" + std::to_string(std::random_device{}()));
  fs::create_directories(d);
  return d;
}

const std::string kMaterial = R"(
[[material]]
name = "rock"
density = 2650.0
kn = 6.587e10
ks = 2.371e10
friction = 0.239
tensile_strength = 1.252e4
shear_strength = 3.690e4
)";

/// A small valid 2D scene; `extra` is appended.
std::string small_scene(const std::string& extra = "", const std::string& material = kMaterial) {
  return "[scene]\ndimension = 2\n" + material + R"(
[[region]]
name = "block"
material = "rock"
diameter = 0.001
size = [0.010, 0.0105]

[[group]]
name = "top"
select = "top_row"

[[group]]
name = "bottom"
select = "bottom_row"

[[boundary]]
group = "bottom"
type = "fixed"

[[boundary]]
group = "top"
type = "velocity"
axes = ["y"]
velocity = [0.0, -0.05]

[solver]
steps = 400
)" + extra;
}

fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << text;
  return dir / name;
}

}  // namespace

TEST(Cli, VersionAndHelp) {
  auto v = strata("--version");
  EXPECT_EQ(v.status, 0);
  EXPECT_NE(v.output.find("strata 0."), std::string::npos);
  EXPECT_NE(v.output.find("STRATA_WITH_GMSH"), std::string::npos);
  for (const char* sub : {"run", "check", "mesh", "bench dem", "render", "reference"}) {
    auto h = strata(std::string(sub) + " --help");
    EXPECT_EQ(h.status, 0) << sub;
    EXPECT_NE(h.output.find("Example"), std::string::npos) << sub << " --help shows no example";
  }
}

TEST(Cli, BadUsageExitsTwo) {
  EXPECT_EQ(strata("").status, 2);
  EXPECT_EQ(strata("frobnicate").status, 2);
  EXPECT_EQ(strata("run /no/such/scene.toml").status, 2);
}

// The acceptance test of the scene validation: four different mistakes, four precise
// file:line:col messages, exit status 2 each time.
TEST(Cli, FourBadScenesGiveFourPreciseMessages) {
  const fs::path d = temp_dir("four");
  std::string misspelt = small_scene();
  misspelt.replace(misspelt.find("friction ="), 10, "fricton =");
  std::string negative = small_scene();
  negative.replace(negative.find("kn = 6.587e10"), 13, "kn = -6.587e10");
  std::string wrong_type = small_scene("dt = \"fast\"\n");
  std::string missing_file = small_scene();
  missing_file.replace(missing_file.find("size = [0.010, 0.0105]"), 22,
                       "shape = \"file\"\nfile = \"nowhere.geo\"");

  const std::array<std::pair<std::string, std::string>, 4> cases{{
      {misspelt, "fricton"},
      {negative, "kn"},
      {wrong_type, "dt"},
      {missing_file, "nowhere.geo"},
  }};
  std::vector<std::string> messages;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const fs::path f = write(d, "bad" + std::to_string(k) + ".toml", cases[k].first);
    const auto r = strata("check " + f.string());
    EXPECT_EQ(r.status, 2) << r.output;
    // file:line:col: at the start of the message
    const std::string prefix = f.string() + ":";
    const auto at = r.output.find(prefix);
    ASSERT_NE(at, std::string::npos) << r.output;
    int line = 0, col = 0;
    ASSERT_EQ(std::sscanf(r.output.c_str() + at + prefix.size(), "%d:%d:", &line, &col), 2) << r.output;
    EXPECT_GT(line, 0);
    EXPECT_GT(col, 0);
    EXPECT_NE(r.output.find(cases[k].second), std::string::npos) << r.output;
    messages.push_back(r.output);
  }
  EXPECT_NE(messages[0].find("did you mean 'friction'"), std::string::npos) << messages[0];
  EXPECT_NE(messages[1].find("must be > 0"), std::string::npos) << messages[1];
  for (std::size_t a = 0; a < messages.size(); ++a)
    for (std::size_t b = a + 1; b < messages.size(); ++b) EXPECT_NE(messages[a], messages[b]);
  fs::remove_all(d);
}

TEST(Cli, CheckPrintsDerivedNumbers) {
  const fs::path d = temp_dir("check");
  const auto r = strata("check " + write(d, "ok.toml", small_scene()).string());
  EXPECT_EQ(r.status, 0) << r.output;
  for (const char* what : {"particles", "bonds", "memory", "dt_crit", "dt/dt_crit"})
    EXPECT_NE(r.output.find(what), std::string::npos) << what << "\n" << r.output;
  EXPECT_FALSE(fs::exists(d / "out")) << "check must not write output";
  fs::remove_all(d);
}

TEST(Cli, UnstableTimeStepIsRefusedBeforeTheRun) {
  const fs::path d = temp_dir("dt");
  const fs::path f = write(d, "fast.toml", small_scene("dt = 1e-6\n"));
  const auto r = strata("run " + f.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("exceeds the critical time step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(f.string() + ":"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out")) << "a refused scene must leave no output";
  fs::remove_all(d);
}

TEST(Cli, BadOverrideIsValidatedLikeTheFileAndWritesNothing) {
  const fs::path d = temp_dir("set");
  const fs::path f = write(d, "ok.toml", small_scene());
  const auto r = strata("run " + f.string() + " --set solver.dt=-1");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--set"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

TEST(Cli, RunWritesSeriesProbesAndSummary) {
  const fs::path d = temp_dir("run");
  const fs::path f = write(d, "ok.toml", small_scene("[output]\nframes = 2\nrender = false\n"));
  const auto r = strata("run " + f.string() + " -o " + (d / "res").string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* file : {"particles.pvd", "bonds.pvd", "probes.csv", "breaks.csv", "summary.json"})
    EXPECT_TRUE(fs::exists(d / "res" / file)) << file;
  EXPECT_TRUE(fs::exists(d / "res" / "particles_000002.vtp"));
  EXPECT_NE(r.output.find("wrote:"), std::string::npos);
  fs::remove_all(d);
}

// A run that blows up (dt far above the limit, forced) stops with status 1, says so, and
// keeps the frames written before the blow-up listed in the .pvd.
TEST(Cli, BlowUpStopsTheRunAndKeepsTheLastGoodFrame) {
  const fs::path d = temp_dir("blowup");
  std::string text = small_scene("dt = 3e-7\n[output]\nframes = 200\nrender = false\n");
  text.replace(text.find("steps = 400"), 11, "steps = 20000");
  const fs::path f = write(d, "unstable.toml", text);
  const auto r = strata("run --force " + f.string() + " -o " + (d / "res").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("blow-up"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("last good frame kept"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(d / "res" / "particles.pvd"));
  fs::remove_all(d);
}

// SPEC C3: the paper's dt_DEM = 1e-4 s is unstable for the metamaterial chain; strata says
// so before running and names the stable limits.
TEST(Cli, ReportRefusesThePapersUnstableStep) {
  const auto bad = strata("report metamaterial --dt-dem 1e-4 --check");
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("7.68e-05 s for the whole chain"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("8.01e-05 s for the DEM partition alone"), std::string::npos) << bad.output;
  EXPECT_EQ(strata("report metamaterial --dt-dem 5e-5 --check").status, 0);
  EXPECT_EQ(strata("report chain6 --eta 0").status, 2);
}

TEST(Cli, ReportWritesTheSweepTables) {
  const fs::path d = temp_dir("report");
  const auto r = strata("report chain6 --eta 1 --eta 20 --modes serial --duration 2 --no-plot -o " + d.string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(d / "chain6_sweep.csv"));
  EXPECT_TRUE(fs::exists(d / "chain6_sweep.md"));
  fs::remove_all(d);
}
