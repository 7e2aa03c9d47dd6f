#pragma once
// Read-back helpers for test_cli: what the `strata` command wrote, read with strata::io (the
// cli tests run the command through cli_test::run_strata()).
#include <filesystem>
#include <string>
#include <vector>

/// What one written .vtp frame holds.
struct FrameCounts {
  std::size_t points = 0, lines = 0;
  std::vector<std::string> arrays;  ///< point-array names
};
FrameCounts frame_counts(const std::filesystem::path& vtp);

/// Whether this build draws pictures (STRATA_WITH_RENDER).
bool have_render();
/// Whether this build writes VTK frames (STRATA_WITH_VTK).
bool have_vtk();
/// Whether this build reads geometry files and meshes FEM regions (STRATA_WITH_GMSH).
bool have_gmsh();
/// Writes `<dir>/fem.pvd` with two frames of a small tetrahedral box (point array
/// "displacement", cell array "cx").
void write_mesh_series(const std::filesystem::path& dir);

/// One frame of a walls series: its time, cells and node coordinates (3 per node).
struct WallFrame {
  double time = 0;
  std::size_t cells = 0;
  std::vector<double> xyz;
};
/// Every frame a walls .pvd lists, read back with VTK's reader.
std::vector<WallFrame> wall_frames(const std::filesystem::path& pvd);
