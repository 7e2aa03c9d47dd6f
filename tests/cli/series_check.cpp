// Reads a written series back with strata::io. In its own file: test_cli.cpp's `strata()`
// helper (run the command) would clash with the namespace of the strata headers.
#include <strata/config.hpp>
#include <strata/io/series.hpp>
#include <strata/io/vtk.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "series_check.hpp"

/// Checks that every frame a .pvd lists exists and reads back as VTK PolyData; returns ""
/// or what is wrong, and the number of frames listed in `frames`.
std::string check_series(const std::filesystem::path& pvd, std::size_t& frames) {
  try {
    const auto entries = strata::io::read_pvd(pvd);
    frames = entries.size();
    for (const auto& e : entries) {
      const auto file = pvd.parent_path() / e.file;
      if (!std::filesystem::exists(file)) return file.string() + " is listed but does not exist";
      strata::io::read_vtp(file);
    }
  } catch (const std::exception& ex) {
    return ex.what();
  }
  return {};
}

/// Whether this build writes checkpoints (STRATA_WITH_HDF5).
bool have_hdf5() { return STRATA_WITH_HDF5 != 0; }

#include <strata/io/checkpoint.hpp>

/// Step of a checkpoint file (-1 when it cannot be read).
long long checkpoint_step(const std::filesystem::path& file) {
  try {
    return strata::io::CheckpointReader(file).info().step;
  } catch (const std::exception&) {
    return -1;
  }
}

/// Points, lines and point-array names of one written frame.
FrameCounts frame_counts(const std::filesystem::path& vtp) {
  const auto c = strata::io::read_vtp(vtp);
  FrameCounts f{c.points.size(), c.lines.size(), {}};
  for (const auto& a : c.points.point_data) f.arrays.push_back(a.name);
  return f;
}
