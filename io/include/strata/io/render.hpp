#pragma once
/// Headless pictures of particle and FEM frames: PNG files rendered by VTK off-screen.
///
/// Particles are drawn as disks (2D, orthographic camera looking down -z, fitted to the
/// bounds) or spheres (3D, perspective camera along a given direction, optional clip
/// plane), coloured by a point array with a colour bar. Broken bonds are drawn on top as
/// thick lines (2D) or discs (3D) coloured by mode (tension, shear, closed again) with a
/// legend and counts; in 3D only those next to a particle the picture shows (on the surface,
/// or on the clip plane's cut), and particles are shaded by the face of the assembly they sit
/// on, so that the shape and its damage read in depth. Intact bonds and contacts only when asked. A FEM mesh
/// (MeshFrame) is drawn shaded by a point or cell array of the same name, alone or under the particles of a
/// coupled model, with the same colour bar, clip plane and camera. Rigid walls are drawn as dark lines (2D)
/// or translucent planes (3D). A label gives the time and step. Call ensure_display() first (render_frame
/// does it). Without STRATA_WITH_RENDER these functions throw strata::Error (Unsupported).
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "strata/io/frame.hpp"

namespace strata::io {

/// Colour maps for particle fields.
enum class Colormap {
  Viridis,   ///< perceptually uniform, colour-blind safe: magnitudes (displacement, stress)
  CoolWarm,  ///< diverging blue-white-red: signed fields centred on 0
  Greys,     ///< light greys: when only the cracks matter
};

/// How pictures look; shared by every frame of a series.
struct RenderStyle {
  int width = 1600;   ///< pixels
  int height = 1200;  ///< pixels
  std::string title;  ///< top line, e.g. "Uniaxial compression, 1033 disks" (may be empty)

  /// Array to colour by: a point array of the particles, and a point or cell array of a
  /// mesh (point data is preferred when both have it); empty or absent: one uniform colour.
  std::string field;
  /// Component of a multi-component field; -1 = magnitude.
  int component = -1;
  /// Values are multiplied by this before display (e.g. 1e3 for m -> mm).
  double field_scale = 1.0;
  /// Shown in the colour bar title as "<field label> [<unit>]" (unit after scaling).
  std::string field_label;  ///< defaults to the field name
  std::string unit;
  /// Fixed colour range (after scaling); default: the data range (render_series: the
  /// range over all frames, so colours mean the same in every frame).
  std::optional<std::array<double, 2>> range;
  Colormap colormap = Colormap::Viridis;
  /// Names of the values of an integer field drawn as categories (value k is named
  /// categories[k]; e.g. the layers of a sandbox): each value gets its own colour from a
  /// qualitative palette, and a legend lists the names of the values present instead of a
  /// colour bar. Empty: the field is drawn through `colormap`.
  std::vector<std::string> categories;
  /// Disks/spheres drawn at this fraction of their radius (slightly below 1 shows grains).
  double radius_factor = 0.96;

  /// Bonds: draw broken ones (state != Intact) unless switched off (pictures of the layers
  /// alone); intact ones only when asked.
  bool show_broken_bonds = true;
  bool show_intact_bonds = false;
  /// Contacts (BondState::Contact lines of the bond set) as thin lines, with a legend count.
  bool show_contacts = false;
  double bond_line_width = 0;  ///< pixels; 0 = chosen from the picture size

  /// 3D camera: direction from the camera towards the model, and the up vector.
  std::array<double, 3> view_direction{-1.0, -0.6, -0.45};
  std::array<double, 3> view_up{0.0, 0.0, 1.0};
  /// 3D clip plane (origin, normal): particles, bonds and mesh cells on the normal's side
  /// are removed (meshes are cut through, showing the field on the cut face).
  std::optional<std::array<double, 6>> clip_plane;
};

/// One picture: the data (not owned) and where to write it.
struct RenderRequest {
  /// Particles; needs a `radius` point array. May be null when `mesh` is given.
  const PointCloud* particles = nullptr;
  /// A FEM mesh drawn under the particles (or alone). May be null.
  const MeshFrame* mesh = nullptr;
  /// Bonds to draw, indexing `bond_points` (default: `particles`) and carrying a `state`
  /// cell array (BondState codes). May be null.
  const LineSet* bonds = nullptr;
  const PointCloud* bond_points = nullptr;
  /// Rigid walls: lines (2D) or triangles (3D), drawn as dark lines in 2D and as
  /// translucent planes with their outline in 3D. May be null.
  const MeshFrame* walls = nullptr;
  std::optional<double> time;        ///< seconds; default: particles->time, else mesh->time
  std::optional<std::int64_t> step;  ///< default: particles->step, else mesh->step
  std::filesystem::path png;         ///< output file
  RenderStyle style;
};

/// Renders one frame to `request.png` (parent folders created). Starts Xvfb if needed.
void render_frame(const RenderRequest& request);

/// The series of a run drawn together; an empty path: none.
struct SeriesPaths {
  /// A particle series (.vtp frames) or a FEM series (.vtu frames, recognised by the
  /// extension of its first frame): one picture per frame.
  std::filesystem::path main;
  std::filesystem::path bonds;  ///< bonds over the particles (.vtp line frames)
  std::filesystem::path mesh;   ///< a FEM mesh under the particles (.vtu)
  std::filesystem::path walls;  ///< rigid walls (.vtu: lines in 2D, triangles in 3D)
};

/// Renders every frame of `series.main` to `<out_dir>/frame_000000.png`, ... . The frames
/// of the other series are matched to the main frames by time. Returns the PNG paths in
/// order. `stop`, when given, is asked before each frame: true stops drawing, and the
/// pictures drawn so far are returned.
std::vector<std::filesystem::path> render_series(const SeriesPaths& series,
                                                 const std::filesystem::path& out_dir,
                                                 const RenderStyle& style,
                                                 const std::function<bool()>& stop = {});

/// Explicit lists of frame files, one entry per picture; each list empty or as long as the
/// longest (an empty path: none in that frame).
struct FrameFiles {
  std::vector<std::filesystem::path> particles;  ///< .vtp
  std::vector<std::filesystem::path> bonds;      ///< .vtp
  std::vector<std::filesystem::path> meshes;     ///< .vtu
  std::vector<std::filesystem::path> walls;      ///< .vtu
};

/// Same as render_series, from explicit lists of frame files.
std::vector<std::filesystem::path> render_frames(const FrameFiles& files,
                                                 const std::filesystem::path& out_dir,
                                                 const RenderStyle& style,
                                                 const std::function<bool()>& stop = {});

/// Joins `<png_dir>/frame_%06d.png` (frames of one size) into a movie of `fps` frames per
/// second: `<stem>.mp4` (H.264, yuv420p, padded to even size) when `ffmpeg` is on PATH,
/// otherwise `<stem>.ogv` (Ogg Theora, VTK's own encoder: every build with pictures can
/// make one; ParaView, VLC and web browsers play it). Written under a temporary name and
/// renamed when complete. Returns the movie's path; empty when ffmpeg failed (the PNGs
/// are kept and the failure is logged).
std::filesystem::path make_movie(const std::filesystem::path& png_dir, const std::filesystem::path& stem,
                                 int fps = 20);

/// "1.23 ms", "45.6 µs", "2.5 s": a time with an SI prefix and 3 significant digits.
std::string format_time(double seconds);

}  // namespace strata::io
