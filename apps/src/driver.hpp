#pragma once
/// The run driver: scene file -> validated scene -> model -> simulation -> outputs.
#include <filesystem>
#include <string>
#include <vector>

namespace strata::app {

/// What `strata run/check/mesh` were asked to do.
struct SceneOptions {
  std::filesystem::path scene;
  std::filesystem::path output;        ///< empty: the scene's [output] directory
  int threads = -1;                    ///< -1: the scene's [solver] threads
  std::vector<std::string> overrides;  ///< --set KEY=VALUE
  bool force = false;                  ///< run even when dt > dt_crit
  std::filesystem::path restart;       ///< `strata run --restart`: checkpoint to continue from
};

/// `strata run`: returns the exit status (0; 130 or 143 after SIGINT or SIGTERM, with a
/// checkpoint and the current frame written); throws strata::Error on bad input or a failed
/// run. With `opt.restart` the run continues from that checkpoint to the scene's steps.
int run_scene(const SceneOptions& opt);
/// `strata check`: validate and print what would be built and the derived numbers.
int check_scene(const SceneOptions& opt, bool json);
/// `strata mesh`: build the model only and report.
int mesh_scene(const SceneOptions& opt, bool json);

/// Writes `text` to `path` through a temporary file and a rename, so readers never see a
/// half-written file.
void write_file_atomic(const std::filesystem::path& path, const std::string& text);

}  // namespace strata::app
