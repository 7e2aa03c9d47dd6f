#pragma once
// Internal: checkpoints of a run (HDF5) and the scene fingerprint that ties one to its scene.
#include <strata/io/checkpoint.hpp>
#include <strata/scene/model.hpp>
#include <strata/scene/scene.hpp>

#include <filesystem>
#include <memory>
#include <string>

#include "run_output.hpp"

namespace strata::scene {

/// Fingerprint of a validated scene: FNV-1a of a canonical text of every key (defaults
/// included, in schema order; referenced files by their contents), leaving out what a
/// restart may change without changing the model or its trajectory: the [output] table,
/// solver.steps, solver.duration and solver.threads.
std::string scene_fingerprint(const Scene& sc);

/// Opens a checkpoint for a restart and refuses one of another scene or another strata
/// version (Error Input; nothing has been written yet).
std::unique_ptr<io::CheckpointReader> open_checkpoint(const std::filesystem::path& file,
                                                      const std::string& fingerprint, const Scene& sc);

/// Writes `<dir>/checkpoint.h5` (through a temporary file and a rename).
std::filesystem::path write_checkpoint(const std::filesystem::path& dir, const BuiltModel& m,
                                       const std::string& fingerprint, const RunOutput& out,
                                       std::int64_t frame_breaks, double wall_seconds);

}  // namespace strata::scene
