#pragma once
/// Time series of VTK frames with a ParaView collection (.pvd) index.
///
/// A Series owns `<dir>/<name>.pvd` and frames `<dir>/<name>_<NNNNNN>.vtp` (particles,
/// bonds) or `.vtu` (FEM meshes). After each
/// completed frame the .pvd is rewritten to `<name>.pvd.tmp` and renamed onto `<name>.pvd`,
/// so a run killed at any moment leaves a .pvd listing only complete frames. Particles and
/// bonds go in two series (e.g. `particles.pvd`, `bonds.pvd`) that ParaView opens together;
/// a FEM mesh in a third (e.g. `fem.pvd`).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "strata/io/frame.hpp"

namespace strata::io {

/// One entry of a .pvd collection.
struct PvdEntry {
  double time = 0;
  std::filesystem::path file;  ///< as written in the .pvd: relative to the .pvd's folder
  int part = 0;
};

/// Reads a .pvd collection (strata's or ParaView's). Files are returned as written
/// (relative paths stay relative to the .pvd's folder).
std::vector<PvdEntry> read_pvd(const std::filesystem::path& pvd);

/// Whether a .pvd collection lists FEM frames: its first frame is a .vtu file.
bool is_mesh_series(const std::filesystem::path& pvd);

/// Writes a .pvd collection atomically (through `<pvd>.tmp` and a rename).
void write_pvd(const std::filesystem::path& pvd, const std::vector<PvdEntry>& entries);

class Series {
 public:
  /// How a Series treats an existing `<name>.pvd`.
  enum class Mode {
    Fresh,   ///< start empty (an old .pvd is replaced at the first frame)
    Resume,  ///< keep the frames listed in the old .pvd (restart); see truncate_after
  };

  /// Creates `dir` if needed. Files of this series that the series will not list are removed
  /// with a warning naming how many: unfinished `.tmp` files a killed run left; frames (and
  /// the .pvd) of an earlier run in the same folder (Fresh); frames the old .pvd does not list
  /// (Resume). A folder never holds frames that its .pvd leaves out.
  Series(std::filesystem::path dir, std::string name, Mode mode = Mode::Fresh);

  /// Writes the next frame's particles (write_particles) and updates the .pvd.
  /// Returns the frame's path.
  std::filesystem::path add_particles(double time, const PointCloud& particles);

  /// Writes the next frame's bonds (write_lines) and updates the .pvd.
  std::filesystem::path add_lines(double time, const PointCloud& points, const LineSet& lines);

  /// Writes the next frame's mesh (write_mesh, a .vtu file) and updates the .pvd.
  std::filesystem::path add_mesh(double time, const MeshFrame& mesh);

  /// Generic form: calls `write(path)` for the next frame's path (with extension `ext`;
  /// the callback must leave a complete file there, e.g. through write-to-temp-and-rename),
  /// then lists it in the .pvd. If `write` throws, nothing is listed and the frame number
  /// is not used up.
  std::filesystem::path add_frame(double time, const std::function<void(const std::filesystem::path&)>& write,
                                  const std::string& ext = ".vtp");

  /// Drops frames with time > `time` from the index and their files (for a restart from a
  /// checkpoint at `time`); the .pvd is rewritten at once. The next frame number follows the
  /// last kept frame.
  void truncate_after(double time);

  /// Path the next frame will get: `<dir>/<name>_<NNNNNN><ext>`.
  std::filesystem::path next_frame_path(const std::string& ext = ".vtp") const;
  std::filesystem::path pvd_path() const { return dir_ / (name_ + ".pvd"); }
  const std::filesystem::path& dir() const { return dir_; }
  const std::string& name() const { return name_; }
  /// Frames listed in the .pvd, oldest first.
  const std::vector<PvdEntry>& frames() const { return entries_; }

 private:
  void renumber();
  /// Removes the files of this series in dir_ that entries_ does not list (frames and
  /// `.tmp` files; the .pvd too when `pvd_too`); returns how many.
  std::size_t remove_unlisted(bool pvd_too);

  std::filesystem::path dir_;
  std::string name_;
  std::vector<PvdEntry> entries_;
  std::int64_t next_index_ = 0;
};

}  // namespace strata::io
