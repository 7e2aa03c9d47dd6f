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

/// Whether this build draws pictures (STRATA_WITH_RENDER).
bool have_render() { return STRATA_WITH_RENDER != 0; }

/// Writes `<dir>/fem.pvd` with two frames of a 2 x 2 x 2 box of unit cubes, six
/// tetrahedra each, with a point array "displacement" and a cell array "cx" (centroid x).
void write_mesh_series(const std::filesystem::path& dir) {
  using namespace strata::io;
  MeshFrame m;
  m.dim = 3;
  const int n = 2;
  auto node = [](int i, int j, int k) { return static_cast<std::int64_t>((k * (n + 1) + j) * (n + 1) + i); };
  Array disp{"displacement", 3, {}, ArrayType::Float64};
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        m.xyz.insert(m.xyz.end(), {double(i), double(j), double(k)});
        disp.values.insert(disp.values.end(), {1e-3 * i, 0.0, -1e-3 * k});
      }
  Array cx{"cx", 1, {}, ArrayType::Float64};
  static constexpr int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& p : kPerm) {
          int c[3] = {i, j, k};
          std::int64_t v[4] = {node(i, j, k), 0, 0, 0};
          double sx = i;
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            v[s + 1] = node(c[0], c[1], c[2]);
            sx += c[0];
          }
          m.add_cell(CellType::Tetra, {v[0], v[1], v[2], v[3]});
          cx.values.push_back(sx / 4);
        }
  m.point_data = {disp};
  m.cell_data = {cx};
  Series fem(dir, "fem");
  for (int f = 0; f < 2; ++f) {
    m.time = 0.5 * f;
    fem.add_mesh(0.5 * f, m);
  }
}
