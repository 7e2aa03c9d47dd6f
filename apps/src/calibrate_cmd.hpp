#pragma once
// `strata calibrate`: choose the solid-lattice parameters that give a rock's E, ν, UCS and
// tensile strength (the work is in strata::cases::calibrate).
#include <strata/scene/scene.hpp>

#include <filesystem>

namespace strata::app {

/// Runs the calibration of `sc` into `output` (empty: the file's output.directory), prints the
/// table and the files written; returns the exit status (130/143 when stopped by SIGINT/SIGTERM).
int calibrate_cmd(const scene::Scene& sc, const std::filesystem::path& output);

/// `strata check` of a calibration: the analytical starting point and the specimens.
int check_calibration(const scene::Scene& sc);

}  // namespace strata::app
