#pragma once
// The scene commands of `strata`: run, check and mesh. Each loads the scene, calls the scene
// library and prints what it did; errors propagate as strata::Error to main().
#include <filesystem>
#include <string>
#include <vector>

namespace strata::app {

/// What `strata run/check/mesh` were asked to do.
struct SceneOptions {
  std::filesystem::path scene;
  std::filesystem::path output;        // empty: the scene's [output] directory
  int threads = -1;                    // -1: the scene's [solver] threads
  std::vector<std::string> overrides;  // --set KEY=VALUE
  bool force = false;                  // run even when dt > dt_crit
  std::filesystem::path restart;       // `strata run --restart`: checkpoint to continue from
  bool no_checkpoint = false;          // `strata run --no-checkpoint`: none at the end of a completed run
};

/// `strata run`: the exit status (0; 128 + signal after SIGINT or SIGTERM, with a checkpoint
/// and the current frame written).
int run_scene(const SceneOptions& opt);
/// `strata calibrate`: the calibration of a file with a [calibrate] table (exit status as run).
int calibrate_scene(const SceneOptions& opt);
/// `strata check`: validate, build and print what would run and the derived numbers.
int check_scene(const SceneOptions& opt, bool json);
/// `strata mesh`: fill the regions only and report.
int mesh_scene(const SceneOptions& opt, bool json);

}  // namespace strata::app
