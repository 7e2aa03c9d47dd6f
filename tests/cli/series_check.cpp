// Reads a written series back with strata::io (see series_check.hpp).
#include <strata/config.hpp>
#include <strata/io/series.hpp>
#include <strata/io/vtk.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "series_check.hpp"
#include "tet_box.hpp"

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

/// Whether this build draws pictures (STRATA_WITH_RENDER).
bool have_render() { return STRATA_WITH_RENDER != 0; }
bool have_vtk() { return STRATA_WITH_VTK != 0; }
bool have_gmsh() { return STRATA_WITH_GMSH != 0; }

/// Writes `<dir>/fem.pvd` with two frames of tet_box(2) (tests/common: a 2 x 2 x 2 box of
/// unit cubes, six tetrahedra each, cell array "cx" = centroid x) with a point array
/// "displacement".
void write_mesh_series(const std::filesystem::path& dir) {
  using namespace strata::io;
  MeshFrame m = fixtures::tet_box(2, ArrayType::Float64);
  Array disp{"displacement", 3, {}, ArrayType::Float64};
  for (std::size_t a = 0; a < m.nodes(); ++a)
    disp.values.insert(disp.values.end(), {1e-3 * m.xyz[3 * a], 0.0, -1e-3 * m.xyz[3 * a + 2]});
  m.point_data = {disp};
  Series fem(dir, "fem");
  for (int f = 0; f < 2; ++f) {
    m.time = 0.5 * f;
    fem.add_mesh(0.5 * f, m);
  }
}

std::vector<WallFrame> wall_frames(const std::filesystem::path& pvd) {
  std::vector<WallFrame> out;
  for (const auto& e : strata::io::read_pvd(pvd)) {
    const auto mesh = strata::io::read_vtu(pvd.parent_path() / e.file);
    out.push_back({e.time, mesh.cells(), mesh.xyz});
  }
  return out;
}
