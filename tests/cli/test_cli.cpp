// The `strata` command as a user meets it: run the binary, check exit status, messages and
// the files left behind.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <vector>
#include "cli_test_util.hpp"
#include "series_check.hpp"

namespace fs = std::filesystem;
using namespace cli_test;

namespace {

/// A small valid 2D scene; `extra` is appended.
std::string small_scene(const std::string& extra = "", const std::string& material = kMaterial) {
  return "[scene]\ndimension = 2\n" + material + R"(
[[region]]
name = "block"
material = "rock"
diameter = 0.001
size = [0.010, 0.0105]
)" + platens("0.05") +
         R"(
[solver]
steps = 400
)" + extra;
}

}  // namespace

TEST(Cli, VersionAndHelp) {
  auto v = run_strata("--version");
  EXPECT_EQ(v.status, 0);
  EXPECT_NE(v.output.find("strata 0."), std::string::npos);
  EXPECT_NE(v.output.find("STRATA_WITH_GMSH"), std::string::npos);
  for (const char* sub : {"run", "check", "mesh", "bench dem", "render", "reference"}) {
    auto h = run_strata(std::string(sub) + " --help");
    EXPECT_EQ(h.status, 0) << sub;
    EXPECT_NE(h.output.find("Example"), std::string::npos) << sub << " --help shows no example";
  }
}

TEST(Cli, BadUsageExitsTwo) {
  EXPECT_EQ(run_strata("").status, 2);
  EXPECT_EQ(run_strata("frobnicate").status, 2);
  EXPECT_EQ(run_strata("run /no/such/scene.toml").status, 2);
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
    const auto r = run_strata("check " + f.string());
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
  const auto r = run_strata("check " + write(d, "ok.toml", small_scene()).string());
  EXPECT_EQ(r.status, 0) << r.output;
  for (const char* what : {"particles", "bonds", "memory", "dt_crit", "dt/dt_crit"})
    EXPECT_NE(r.output.find(what), std::string::npos) << what << "\n" << r.output;
  // The hexagonal lattice's elastic constants with Kn = 6.587e10, Ks = 2.371e10 N/m:
  // E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks) = 9.236e10 N/m and ν = (Kn−Ks)/(3Kn+Ks) = 0.1905 (to the 4
  // digits printed; the block's measured E is within 1 % of it, test_elastic).
  EXPECT_NE(r.output.find("E = 9.236e+10 N/m, nu = 0.1905 (per unit thickness, isotropic)"),
            std::string::npos)
      << r.output;
  // The same in 3D (HCP): along z E = 6√2·Kn(Kn+Ks)/(d(5Kn+Ks)) = 1.418e14 Pa and
  // ν = (Kn−Ks)/(5Kn+Ks) = 0.1194; isotropic average 2√2·Kn(2Kn+3Ks)/(d(4Kn+Ks)) = 1.316e14 Pa,
  // ν = (Kn−Ks)/(4Kn+Ks) = 0.1468 (d = 1 mm).
  const std::string three_d = "[scene]\ndimension = 3\n" + kMaterial +
                              "[[region]]\nname = \"block\"\nmaterial = \"rock\"\ndiameter = 0.001\n"
                              "size = [0.006, 0.006, 0.006]\n[solver]\nsteps = 10\n";
  const auto r3 = run_strata("check " + write(d, "ok3.toml", three_d).string());
  EXPECT_EQ(r3.status, 0) << r3.output;
  EXPECT_NE(r3.output.find(
                "along z E = 1.418e+14 Pa, nu = 0.1194; isotropic average E = 1.316e+14 Pa, nu = 0.1468"),
            std::string::npos)
      << r3.output;
  EXPECT_FALSE(fs::exists(d / "out")) << "check must not write output";
  fs::remove_all(d);
}

TEST(Cli, UnstableTimeStepIsRefusedBeforeTheRun) {
  const fs::path d = temp_dir("dt");
  const fs::path f = write(d, "fast.toml", small_scene("dt = 1e-6\n"));
  const auto r = run_strata("run " + f.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("exceeds the critical time step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(f.string() + ":"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out")) << "a refused scene must leave no output";
  fs::remove_all(d);
}

TEST(Cli, BadOverrideIsValidatedLikeTheFileAndWritesNothing) {
  const fs::path d = temp_dir("set");
  const fs::path f = write(d, "ok.toml", small_scene());
  const auto r = run_strata("run " + f.string() + " --set solver.dt=-1");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--set"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

TEST(Cli, RunWritesSeriesProbesAndSummary) {
  if (!have_vtk()) GTEST_SKIP() << "frames need STRATA_WITH_VTK";
  const fs::path d = temp_dir("run");
  const fs::path f = write(d, "ok.toml", small_scene("[output]\nframes = 2\nrender = false\n"));
  const auto r = run_strata("run " + f.string() + " -o " + (d / "res").string());
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
  if (!have_vtk()) GTEST_SKIP() << "frames need STRATA_WITH_VTK";
  const fs::path d = temp_dir("blowup");
  std::string text = small_scene("dt = 3e-7\n[output]\nframes = 200\nrender = false\n");
  text.replace(text.find("steps = 400"), 11, "steps = 20000");
  const fs::path f = write(d, "unstable.toml", text);
  const auto r = run_strata("run --force " + f.string() + " -o " + (d / "res").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("blow-up"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("last good frame kept"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(d / "res" / "particles.pvd"));
  fs::remove_all(d);
}

// The dt_DEM = 1e-4 s of Li et al. 2023 is unstable for the metamaterial chain; strata says
// so before running and names the stable limits.
TEST(Cli, ReportRefusesThePapersUnstableStep) {
  const auto bad = run_strata("report metamaterial --dt-dem 1e-4 --check");
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("7.68e-05 s for the whole chain"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("8.01e-05 s for the DEM partition alone"), std::string::npos) << bad.output;
  EXPECT_EQ(run_strata("report metamaterial --dt-dem 5e-5 --check").status, 0);
  EXPECT_EQ(run_strata("report chain6 --eta 0").status, 2);
}

TEST(Cli, ReportWritesTheSweepTables) {
  const fs::path d = temp_dir("report");
  const auto r =
      run_strata("report chain6 --eta 1 --eta 20 --modes serial --duration 2 --no-plot -o " + d.string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(d / "chain6_sweep.csv"));
  EXPECT_TRUE(fs::exists(d / "chain6_sweep.md"));
  fs::remove_all(d);
}

// ---- checkpoints, restart, interrupted and killed runs -------------------------------------

std::string check_series(const fs::path& pvd, std::size_t& frames);  // series_check.cpp
bool have_hdf5();                                                    // series_check.cpp
long long checkpoint_step(const fs::path& file);                     // series_check.cpp

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

/// A string field of summary.json (enough of a parser for the flat fields compared here).
std::string summary_field(const fs::path& dir, const std::string& key) {
  const std::string text = read_text(dir / "summary.json");
  const auto k = text.find("\"" + key + "\":");
  if (k == std::string::npos) return "<missing " + key + ">";
  const auto b = text.find_first_not_of(' ', k + key.size() + 3);
  const auto e = text.find_first_of(",\n}", b);
  return text.substr(b, e - b);
}

/// The small scene squeezed fast enough to break bonds within a few hundred steps.
std::string breaking_scene(const std::string& extra = "") {
  std::string t = small_scene(extra);
  t.replace(t.find("velocity = [0.0, -0.05]"), 23, "velocity = [0.0, -5.0]");
  return t;
}

/// Starts `strata ARGS...` with output to `log`; returns its process id.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::vector<char*> argv{const_cast<char*>(STRATA_EXE)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(STRATA_EXE, argv.data());
    _exit(127);
  }
  return pid;
}

/// Frames listed in a .pvd (0 when it does not exist yet).
int pvd_frames(const fs::path& pvd) {
  const std::string t = read_text(pvd);
  int n = 0;
  for (auto p = t.find("<DataSet"); p != std::string::npos; p = t.find("<DataSet", p + 1)) ++n;
  return n;
}

/// Waits until `pvd` lists at least `n` frames (true) or the process ends or 20 s pass.
bool wait_for_frames(pid_t pid, const fs::path& pvd, int n) {
  for (int i = 0; i < 2000; ++i) {
    if (pvd_frames(pvd) >= n) return true;
    int st = 0;
    if (waitpid(pid, &st, WNOHANG) == pid) return false;
    usleep(10000);
  }
  return false;
}

/// Waits for the process (at most 20 s, then SIGKILL); returns the raw wait status.
int wait_exit(pid_t pid) {
  int st = 0;
  for (int i = 0; i < 2000; ++i) {
    if (waitpid(pid, &st, WNOHANG) == pid) return st;
    usleep(10000);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &st, 0);
  return -1;
}

/// A run far too long to finish during a test, with a frame every 200 steps.
std::string endless_scene() {
  std::string t = breaking_scene("[output]\nframes = 100000\nrender = false\n");
  t.replace(t.find("steps = 400"), 11, "steps = 20000000");
  return t;
}

}  // namespace

// Issue 5 acceptance: 2N steps straight and N + N with a restart in between give the same
// final state (hash), break counts, probe rows and break list, bit for bit.
TEST(Cli, RestartFromTheFinalCheckpointEqualsAStraightRun) {
  if (!have_hdf5()) GTEST_SKIP() << "checkpoints need STRATA_WITH_HDF5";
  const fs::path d = temp_dir("restart");
  const fs::path f = write(d, "scene.toml", breaking_scene("[output]\nframes = 2\nrender = false\n"));
  const auto straight =
      run_strata("run " + f.string() + " -o " + (d / "a").string() + " --set solver.steps=800");
  ASSERT_EQ(straight.status, 0) << straight.output;
  const auto half = run_strata("run " + f.string() + " -o " + (d / "b").string());
  ASSERT_EQ(half.status, 0) << half.output;
  ASSERT_TRUE(fs::exists(d / "b" / "checkpoint.h5")) << half.output;
  const auto rest = run_strata("run " + f.string() + " -o " + (d / "b").string() +
                               " --set solver.steps=800 --restart " + (d / "b" / "checkpoint.h5").string());
  ASSERT_EQ(rest.status, 0) << rest.output;
  EXPECT_NE(rest.output.find("restart      step 400"), std::string::npos) << rest.output;
  for (const char* key : {"state_hash", "steps_done", "broken_tension", "broken_shear", "peak_stress_pa"})
    EXPECT_EQ(summary_field(d / "b", key), summary_field(d / "a", key)) << key;
  EXPECT_NE(summary_field(d / "a", "broken_tension"), "0") << "the test must break bonds";
  EXPECT_EQ(read_text(d / "b" / "probes.csv"), read_text(d / "a" / "probes.csv"));
  EXPECT_EQ(read_text(d / "b" / "breaks.csv"), read_text(d / "a" / "breaks.csv"));
  // frames of the first part are kept, the restart appends after them
  EXPECT_EQ(pvd_frames(d / "b" / "particles.pvd"), 4);  // steps 0, 200, 400 and 800
  fs::remove_all(d);
}

TEST(Cli, RestartWithACheckpointOfAnotherSceneIsRefused) {
  if (!have_hdf5()) GTEST_SKIP() << "checkpoints need STRATA_WITH_HDF5";
  const fs::path d = temp_dir("refuse");
  const fs::path f = write(d, "scene.toml", small_scene("[output]\nframes = 0\nrender = false\n"));
  ASSERT_EQ(run_strata("run " + f.string() + " -o " + (d / "a").string()).status, 0);
  const auto r =
      run_strata("run " + f.string() + " -o " + (d / "b").string() + " --set material.rock.kn=5e10" +
                 " --restart " + (d / "a" / "checkpoint.h5").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("belongs to another scene"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fingerprint"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "b")) << "a refused restart must write nothing";
  const auto junk =
      run_strata("run " + f.string() + " -o " + (d / "c").string() + " --restart " + f.string());
  EXPECT_EQ(junk.status, 2) << junk.output;
  EXPECT_NE(junk.output.find("not a strata checkpoint"), std::string::npos) << junk.output;
  fs::remove_all(d);
}

// Issue 5 acceptance: a run killed with SIGKILL mid-way leaves a .pvd that lists only
// complete frames (every listed file exists and reads back).
TEST(Cli, KilledRunLeavesAPvdOfCompleteFrames) {
  if (!have_vtk()) GTEST_SKIP() << "frames need STRATA_WITH_VTK";
  const fs::path d = temp_dir("kill");
  const fs::path f = write(d, "scene.toml", endless_scene());
  const pid_t pid = spawn({"run", f.string(), "-o", (d / "res").string()}, d / "log.txt");
  ASSERT_GT(pid, 0);
  const bool started = wait_for_frames(pid, d / "res" / "particles.pvd", 3);
  kill(pid, SIGKILL);
  int st = 0;
  waitpid(pid, &st, 0);
  ASSERT_TRUE(started) << read_text(d / "log.txt");
  ASSERT_TRUE(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
  for (const char* series : {"particles.pvd", "bonds.pvd"}) {
    std::size_t frames = 0;
    EXPECT_EQ(check_series(d / "res" / series, frames), "") << series;
    EXPECT_GE(frames, series[0] == 'p' ? 3u : 2u) << series;  // bonds follow particles
  }
  fs::remove_all(d);
}

// SIGINT stops a run between chunks with status 130, the current frame and a checkpoint;
// the restart from it reaches the same state as a run that was never interrupted.
TEST(Cli, InterruptedRunWritesACheckpointAndRestartsExactly) {
  if (!have_hdf5()) GTEST_SKIP() << "checkpoints need STRATA_WITH_HDF5";
  const fs::path d = temp_dir("sigint");
  const fs::path f = write(d, "scene.toml", endless_scene());
  const pid_t pid = spawn({"run", f.string(), "-o", (d / "res").string()}, d / "log.txt");
  ASSERT_GT(pid, 0);
  const bool started = wait_for_frames(pid, d / "res" / "particles.pvd", 2);
  kill(pid, SIGINT);
  const int st = wait_exit(pid);
  ASSERT_TRUE(started) << read_text(d / "log.txt");
  const std::string log = read_text(d / "log.txt");
  ASSERT_TRUE(WIFEXITED(st)) << log;
  EXPECT_EQ(WEXITSTATUS(st), 130) << log;
  EXPECT_NE(log.find("interrupted by SIGINT"), std::string::npos) << log;
  ASSERT_TRUE(fs::exists(d / "res" / "checkpoint.h5")) << log;
  EXPECT_NE(summary_field(d / "res", "status").find("interrupted"), std::string::npos);

  const std::string at = summary_field(d / "res", "steps_done");
  const std::string steps = std::to_string(std::stoll(at) + 300);
  const std::string quiet = " --set output.vtk=false --set solver.steps=" + steps;
  const auto rest = run_strata("run " + f.string() + " -o " + (d / "res").string() + quiet + " --restart " +
                               (d / "res" / "checkpoint.h5").string());
  ASSERT_EQ(rest.status, 0) << rest.output;
  const auto straight = run_strata("run " + f.string() + " -o " + (d / "straight").string() + quiet);
  ASSERT_EQ(straight.status, 0) << straight.output;
  EXPECT_EQ(summary_field(d / "res", "steps_done"), steps);
  EXPECT_EQ(summary_field(d / "res", "state_hash"), summary_field(d / "straight", "state_hash"));
  EXPECT_EQ(summary_field(d / "res", "broken_tension"), summary_field(d / "straight", "broken_tension"));
  fs::remove_all(d);
}

// Issue 5: frames by simulated time (at the nearest step, plus the first and the last) and
// by events (every N more broken bonds, checked at probe rows).
TEST(Cli, FramesBySimulatedTimeAndByBrokenBonds) {
  if (!have_vtk()) GTEST_SKIP() << "frames need STRATA_WITH_VTK";
  const fs::path d = temp_dir("cadence");
  const fs::path f = write(d, "scene.toml", breaking_scene("dt = 2e-8\n[output]\nrender = false\n"));
  const auto by_time =
      run_strata("run " + f.string() + " -o " + (d / "t").string() + " --set output.frame_every_time=3e-6");
  ASSERT_EQ(by_time.status, 0) << by_time.output;
  const std::string pvd = read_text(d / "t" / "particles.pvd");
  std::vector<double> times;
  for (auto p = pvd.find("timestep=\""); p != std::string::npos; p = pvd.find("timestep=\"", p + 1))
    times.push_back(std::stod(pvd.substr(p + 10)));
  const std::vector<double> expected{0, 3e-6, 6e-6, 8e-6};  // steps 0, 150, 300 and the last, 400
  ASSERT_EQ(times.size(), expected.size()) << pvd;
  for (std::size_t k = 0; k < times.size(); ++k) EXPECT_NEAR(times[k], expected[k], 1e-12) << pvd;

  const auto by_breaks = run_strata("run " + f.string() + " -o " + (d / "b").string() +
                                    " --set output.frame_every_breaks=25 --set output.probe_every=10");
  ASSERT_EQ(by_breaks.status, 0) << by_breaks.output;
  const long broken =
      std::stol(summary_field(d / "b", "broken_tension")) + std::stol(summary_field(d / "b", "broken_shear"));
  const int frames = pvd_frames(d / "b" / "particles.pvd");
  EXPECT_GE(broken, 50) << "the test must break bonds";
  EXPECT_GE(frames, 3);
  EXPECT_LE(frames, 2 + broken / 25);
  fs::remove_all(d);
}

// The case checkpoints are for: a run killed (SIGKILL) after a periodic checkpoint is
// continued from it; frames and probe rows written after the checkpoint are replaced, and
// the result equals a run that was never killed.
TEST(Cli, KilledRunContinuesFromItsLastPeriodicCheckpoint) {
  if (!have_hdf5()) GTEST_SKIP() << "checkpoints need STRATA_WITH_HDF5";
  const fs::path d = temp_dir("resume");
  std::string text = endless_scene();
  text.replace(text.find("frames = 100000"), 15,
               "frames = 100000\ncheckpoint_every = 300\nprobe_every = 100");
  const fs::path f = write(d, "scene.toml", text);
  const pid_t pid = spawn({"run", f.string(), "-o", (d / "res").string()}, d / "log.txt");
  ASSERT_GT(pid, 0);
  bool ready = false;  // a checkpoint and at least one frame after it
  for (int i = 0; i < 2000 && !ready; ++i) {
    ready = checkpoint_step(d / "res" / "checkpoint.h5") > 0 && pvd_frames(d / "res" / "particles.pvd") >= 5;
    if (!ready) usleep(10000);
  }
  kill(pid, SIGKILL);
  int st = 0;
  waitpid(pid, &st, 0);
  ASSERT_TRUE(ready) << read_text(d / "log.txt");
  const long long at = checkpoint_step(d / "res" / "checkpoint.h5");
  ASSERT_EQ(at % 300, 0);

  const std::string steps = std::to_string(at + 500);
  const auto rest =
      run_strata("run " + f.string() + " -o " + (d / "res").string() + " --set solver.steps=" + steps +
                 " --set output.frames=5 --restart " + (d / "res" / "checkpoint.h5").string());
  ASSERT_EQ(rest.status, 0) << rest.output;
  const auto straight = run_strata("run " + f.string() + " -o " + (d / "straight").string() +
                                   " --set output.vtk=false --set solver.steps=" + steps);
  ASSERT_EQ(straight.status, 0) << straight.output;
  EXPECT_EQ(summary_field(d / "res", "state_hash"), summary_field(d / "straight", "state_hash"));

  std::size_t frames = 0;
  EXPECT_EQ(check_series(d / "res" / "particles.pvd", frames), "");
  const std::string pvd = read_text(d / "res" / "particles.pvd");
  std::vector<double> times;
  for (auto p = pvd.find("timestep=\""); p != std::string::npos; p = pvd.find("timestep=\"", p + 1))
    times.push_back(std::stod(pvd.substr(p + 10)));
  for (std::size_t k = 1; k < times.size(); ++k) EXPECT_LT(times[k - 1], times[k]) << pvd;
  std::istringstream probes(read_text(d / "res" / "probes.csv"));
  std::string line;
  std::getline(probes, line);
  long long prev = -1;
  while (std::getline(probes, line)) {
    const long long step = std::stoll(line);
    EXPECT_LT(prev, step) << "probe rows must not repeat or go back";
    prev = step;
  }
  EXPECT_EQ(prev, at + 500);
  fs::remove_all(d);
}

// [output] selections: surface particles only, a group, a slice, all bonds, and the force
// field; read the frames back and count.
TEST(Cli, SelectiveOutputWritesOnlyWhatIsAsked) {
  if (!have_vtk()) GTEST_SKIP() << "frames need STRATA_WITH_VTK";
  const fs::path d = temp_dir("select");
  const std::string base = small_scene("[output]\nframes = 1\nrender = false\n");
  const fs::path f = write(d, "sel.toml", base);
  // The 10 x 11-row block: 10 + 10 disks in the end rows, 2 per inner row (9 rows) = 38 surface.
  auto run = [&](const std::string& sets, const std::string& name) {
    const auto r = run_strata("run " + f.string() + " -o " + (d / name).string() + " " + sets);
    EXPECT_EQ(r.status, 0) << r.output;
    return frame_counts(d / name / "particles_000001.vtp");
  };
  const FrameCounts all = run("", "all");
  const FrameCounts surface = run("--set output.particles=surface", "surface");
  const FrameCounts top = run("--set 'output.groups=[\"top\"]'", "top");
  const FrameCounts slice =
      run("--set output.slice_thickness=0.001 --set 'output.slice_point=[0.0, 0.005]' "
          "--set 'output.slice_normal=[0.0, 1.0]'",
          "slice");
  const FrameCounts forces = run("--set 'output.fields=[\"force\"]' --set output.bonds=all", "forces");
  // a 1 mm slice across the rows through x = 4.5 mm: the surface and, besides, the slice's
  // inner disks, one or two per inner row
  const FrameCounts both =
      run("--set output.particles=surface_and_slice --set output.slice_thickness=0.001 "
          "--set 'output.slice_point=[0.0045, 0.0]' --set 'output.slice_normal=[1.0, 0.0]'",
          "both");
  const FrameCounts cut =
      run("--set output.slice_thickness=0.001 --set 'output.slice_point=[0.0045, 0.0]' "
          "--set 'output.slice_normal=[1.0, 0.0]'",
          "cut");
  const FrameCounts cut_surface =
      run("--set output.particles=surface --set output.slice_thickness=0.001 "
          "--set 'output.slice_point=[0.0045, 0.0]' --set 'output.slice_normal=[1.0, 0.0]'",
          "cut_surface");
  EXPECT_EQ(both.points, surface.points + cut.points - cut_surface.points);
  EXPECT_GT(both.points, surface.points);
  // without a slice, surface_and_slice is refused at its key, before anything is written
  const auto refused = run_strata("run " + f.string() + " -o " + (d / "refused").string() +
                                  " --set output.particles=surface_and_slice");
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find("slice_thickness is 0"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(d / "refused" / "summary.json"));
  EXPECT_EQ(all.points, 105u);
  EXPECT_EQ(surface.points, 38u);
  EXPECT_EQ(top.points, 10u);
  EXPECT_GT(slice.points, 0u);
  EXPECT_LE(slice.points, 20u) << "a 1 mm slice holds at most two rows of 1 mm disks";
  // every bond of the block: 94 along the rows (6 x 9 + 5 x 8) and 180 between them (10 x 18)
  EXPECT_EQ(frame_counts(d / "forces" / "bonds_000001.vtp").lines, 274u);
  EXPECT_NE(std::find(forces.arrays.begin(), forces.arrays.end(), "force"), forces.arrays.end());
  EXPECT_EQ(std::find(forces.arrays.begin(), forces.arrays.end(), "velocity"), forces.arrays.end());
  fs::remove_all(d);
}

// A scene with walls writes a `walls` series beside the particles (ParaView shows it): one
// line per wall in 2D, where the wall is at each frame's time; the pictures of the run and
// `strata render` of the particle series (which finds walls.pvd beside it) draw it.
TEST(Cli, WallsAreWrittenBesideTheParticles) {
  if (!have_vtk()) GTEST_SKIP() << "frames need STRATA_WITH_VTK";
  const fs::path d = temp_dir("walls");
  const fs::path f =
      write(d, "walls.toml",
            small_scene("[output]\nframes = 2\nmovie = false\nrender = " +
                        std::string(have_render() ? "true" : "false") +
                        "\n[[wall]]\nname = \"lid\"\npoint = [0.0, 0.02]\nnormal = [0.0, -1.0]\n"
                        "velocity = [0.0, -1.0]\n"));
  const auto run = run_strata("run " + f.string() + " -o " + (d / "run").string());
  ASSERT_EQ(run.status, 0) << run.output;
  const auto frames = wall_frames(d / "run" / "walls.pvd");
  ASSERT_EQ(frames.size(), 3u);  // the start and two frames
  for (const auto& w : frames) {
    ASSERT_EQ(w.cells, 1u);
    ASSERT_EQ(w.xyz.size(), 6u);
    for (const double y : {w.xyz[1], w.xyz[4]})
      EXPECT_NEAR(y, 0.02 - 1.0 * w.time, 1e-15) << "t = " << w.time;
    EXPECT_LT(std::min(w.xyz[0], w.xyz[3]), 0.0) << "the wall spans the block (x from 0 to 10 mm)";
    EXPECT_GT(std::max(w.xyz[0], w.xyz[3]), 0.010);
  }
  EXPECT_GT(frames.back().time, 0.0);
  if (have_render()) {
    EXPECT_TRUE(fs::exists(d / "run" / "png" / "frame_000002.png")) << run.output;
    const auto r = run_strata("render " + (d / "run" / "particles.pvd").string() + " -o " +
                              (d / "png").string() + " --size 200 150 --no-movie");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(d / "png" / "frame_000002.png")) << r.output;
  }
  fs::remove_all(d);
}

// `strata render --view/--up/--clip` are checked when parsed: a wrong count, a word or a
// zero direction exits with status 2 and names the option and what it expects.
TEST(Cli, RenderViewAndClipOptionsAreValidated) {
  const fs::path d = temp_dir("render_opts");
  const fs::path pvd = write(d, "particles.pvd", "<?xml version=\"1.0\"?>\n");
  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"--clip 1,2,3", "clip plane OX,OY,OZ,NX,NY,NZ"},
      {"--clip 0,0,0,0,0,0", "normal must not be zero"},
      {"--clip 1,2,3,4,5,x", "6 comma-separated numbers"},
      {"--view 1,2", "view direction X,Y,Z"},
      {"--view 0,0,0", "must not be zero"},
      {"--up 0,0,inf", "an up vector X,Y,Z"},
  };
  for (const auto& c : cases) {
    const auto r = run_strata("render " + pvd.string() + " " + c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.args.substr(0, c.args.find(' '))), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(d / "png"));
  fs::remove_all(d);
}

// The same settings as [output] keys are validated before a run writes anything.
TEST(Cli, RenderSceneKeysAreValidated) {
  if (!have_vtk()) GTEST_SKIP() << "frames need STRATA_WITH_VTK";
  const fs::path d = temp_dir("render_keys");
  const fs::path f = write(d, "s.toml", small_scene("[output]\nframes = 1\n"));
  const auto bad_len = run_strata("run " + f.string() + " -o " + (d / "a").string() +
                                  " --set 'output.clip_plane=[0.0, 0.0, 1.0]'");
  EXPECT_EQ(bad_len.status, 2) << bad_len.output;
  EXPECT_NE(bad_len.output.find("clip_plane must have 6"), std::string::npos) << bad_len.output;
  const auto zero = run_strata("run " + f.string() + " -o " + (d / "b").string() +
                               " --set 'output.clip_plane=[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]'");
  EXPECT_EQ(zero.status, 2) << zero.output;
  EXPECT_NE(zero.output.find("normal (the last three numbers) must not be zero"), std::string::npos)
      << zero.output;
  const auto parallel = run_strata("run " + f.string() + " -o " + (d / "c").string() +
                                   " --set 'output.view_up=[2.0, 1.2, 0.9]'");
  EXPECT_EQ(parallel.status, 2) << parallel.output;
  EXPECT_NE(parallel.output.find("parallel to view_direction"), std::string::npos) << parallel.output;
  EXPECT_FALSE(fs::exists(d / "a" / "particles.pvd"));
  EXPECT_FALSE(fs::exists(d / "c" / "particles.pvd"));
  fs::remove_all(d);
}

// A run that renders while running with the render keys set, and `strata render` of a FEM
// series (.vtu frames) with a 3D view and a clip plane.
TEST(Cli, RenderWithViewClipAndFemSeries) {
  if (!have_render()) GTEST_SKIP() << "pictures need STRATA_WITH_RENDER";
  const fs::path d = temp_dir("render_fem");
  const fs::path f = write(d, "s.toml",
                           small_scene("[output]\nframes = 1\nmovie = false\nrender_while_running = true\n"
                                       "render_contacts = true\nview_direction = [0.0, -1.0, -1.0]\n"
                                       "clip_plane = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0]\n"));
  const auto run = run_strata("run " + f.string() + " -o " + (d / "run").string());
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(fs::exists(d / "run" / "png" / "frame_000001.png")) << run.output;

  write_mesh_series(d / "fem");
  const auto r =
      run_strata("render " + (d / "fem" / "fem.pvd").string() + " -o " + (d / "png").string() +
                 " --size 200 150 --no-movie --field cx --view -1,-0.5,-0.5 --up 0,0,1 --clip 1,1,1,1,0,0");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(d / "png" / "frame_000000.png")) << r.output;
  EXPECT_TRUE(fs::exists(d / "png" / "frame_000001.png")) << r.output;
  fs::remove_all(d);
}
