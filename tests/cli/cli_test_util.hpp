#pragma once
// Running the `strata` binary from tests: exit status and output, fresh directories, files.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "scene_fixtures.hpp"

namespace cli_test {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string output;  // stdout and stderr together
};

/// Runs a shell command and returns its exit status and output (stdout and stderr together).
inline Result strata_command(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  Result r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.output.append(buf.data(), n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

/// Runs `strata ARGS` (the binary under test) and returns its exit status and output.
inline Result run_strata(const std::string& args) {
  return strata_command(std::string(STRATA_EXE) + " " + args);
}

/// `strata ARGS` stopped after `seconds` (exit status 124, or 137 when it ignores SIGTERM).
inline Result strata_within(int seconds, const std::string& args) {
  return strata_command("timeout -k 5 " + std::to_string(seconds) + " " + std::string(STRATA_EXE) + " " +
                        args);
}

/// A fresh directory for one test.
inline fs::path temp_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("strata_cli_" + name + "_" + std::to_string(std::random_device{}()));
  fs::create_directories(d);
  return d;
}

/// The rock of Liu, Pollard & Shi 2013 (1 mm disks) as a scene [[material]] named "rock".
inline const std::string kMaterial = R"(
[[material]]
name = "rock"
density = 2650.0
kn = 6.587e10
ks = 2.371e10
friction = 0.239
tensile_strength = 1.252e4
shear_strength = 3.690e4
)";

/// Platens of a 2D block: groups "top" and "bottom" (rows), the bottom fixed, the top
/// moving down at `speed` (m/s).
inline std::string platens(const std::string& speed) {
  return "\n" + fixtures::kPlatenGroups + R"(
[[boundary]]
group = "top"
type = "velocity"
axes = ["y"]
velocity = [0.0, -)" +
         speed + "]\n";
}

inline fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << text;
  return dir / name;
}

}  // namespace cli_test
