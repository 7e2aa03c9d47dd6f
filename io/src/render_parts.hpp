#pragma once
// Internal: the building blocks of a picture (colours, colour tables, field values, crack
// glyphs, cameras, the shading of 3D assemblies, mesh and wall actors, PNG output), shared by
// render.cpp, which composes them into frames and series. Only with STRATA_WITH_RENDER.
#include "strata/config.hpp"
#include "strata/io/render.hpp"

#if STRATA_WITH_RENDER
#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkGlyph3DMapper.h>
#include <vtkLookupTable.h>
#include <vtkPolyData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace strata::io::render_parts {

namespace fs = std::filesystem;

using Rgb = std::array<double, 3>;

/// Colours of broken-bond modes (BondState codes 1..3) and their legend names.
struct ModeStyle {
  BondState state;
  Rgb colour;
  const char* label;
};

inline constexpr ModeStyle kModes[] = {
    {BondState::BrokenTension, {0.84, 0.10, 0.11}, "tensile crack"},
    {BondState::BrokenShear, {0.13, 0.40, 0.90}, "shear crack"},
    {BondState::Closed, {0.10, 0.10, 0.10}, "closed again"},
};

inline constexpr ModeStyle kContactMode{BondState::Contact, {0.05, 0.55, 0.25}, "contact"};

inline constexpr Rgb kIntactColour{0.55, 0.55, 0.55};

inline constexpr Rgb kUniformMeshColour{0.74, 0.80, 0.87};  // pale steel blue

inline constexpr Rgb kMeshEdgeColour{0.35, 0.38, 0.42};

inline constexpr Rgb kWallColour{0.20, 0.24, 0.32};  // dark slate: 2D walls, 3D outlines

inline constexpr Rgb kWallFill{0.55, 0.62, 0.75};  // light slate: 3D planes, translucent

/// Meshes with at most this many cells are drawn with their element edges.
inline constexpr std::size_t kMaxCellsWithEdges = 5000;

inline constexpr Rgb kUniformParticleColour{0.86, 0.82, 0.72};  // sandstone beige

inline constexpr Rgb kText{0.08, 0.08, 0.08};

inline Rgb hex(unsigned v) {
  return {((v >> 16) & 255) / 255.0, ((v >> 8) & 255) / 255.0, (v & 255) / 255.0};
}

vtkSmartPointer<vtkLookupTable> make_lut(Colormap map, double lo, double hi);

/// A table of one colour per category, value k in [k - 0.5, k + 0.5): Tableau's ten
/// qualitative colours, repeated past ten, so neighbouring layers always differ.
vtkSmartPointer<vtkLookupTable> make_categorical_lut(std::size_t n);

/// The displayed value of array `a` at each tuple (component or magnitude, times scale).
std::vector<double> field_values(const Array* a, const RenderStyle& s);

std::vector<double> field_values(const PointCloud& cloud, const RenderStyle& s);

/// The displayed values of a mesh: from its point array `field` if it has one, else from
/// its cell array; empty when it has neither.
struct MeshValues {
  std::vector<double> values;
  bool on_cells = false;
};

MeshValues field_values(const MeshFrame& mesh, const RenderStyle& s);

std::array<double, 2> finite_range(const std::vector<double>& v);

std::array<double, 2> merge(std::array<double, 2> a, std::array<double, 2> b);

/// A usable colour range: finite, non-empty.
std::array<double, 2> widen(std::array<double, 2> r);

bool clipped(const RenderStyle& s, int dim, const double* p);

vtkSmartPointer<vtkTextActor> text(const std::string& s, double x, double y, int size, bool bold,
                                   const Rgb& colour, int justify = VTK_TEXT_LEFT,
                                   int vjustify = VTK_TEXT_TOP);

/// A short horizontal line in normalized window coordinates (legend sample).
vtkSmartPointer<vtkActor2D> legend_line(double x0, double x1, double y, const Rgb& colour, double width);

/// Says whether the picture shows the bond particle of this index (3D); null in 2D, where
/// every bond is drawn.
using SeenTest = std::function<bool(std::size_t)>;

/// Crack glyphs of one mode: a segment (2D) or disc (3D) at each bond's midpoint,
/// perpendicular to the bond. With a `seen` test, only cracks next to a particle that is
/// seen are drawn. `count` counts the cracks the clip plane leaves, drawn or hidden.
struct CrackSet {
  vtkSmartPointer<vtkPolyData> centres;
  std::size_t count = 0;
  std::size_t drawn = 0;
};

CrackSet crack_set(const PointCloud& pts, const LineSet& bonds, const Array* state, const Array* radius,
                   int code, const RenderStyle& s, int dim, const SeenTest& seen);

vtkSmartPointer<vtkGlyph3DMapper> crack_mapper(vtkPolyData* centres, int dim);

/// Fits an orthographic camera looking down -z so that `b` fills the region
/// [x0, x1] x [y0, y1] (normalized window coordinates) of a w x h window.
void fit_2d_camera(vtkCamera* cam, const double b[6], int w, int h, double x0, double x1, double y0,
                   double y1);

/// Projected extent (display pixels) of the corners of `b`: {xmin, xmax, ymin, ymax}.
std::array<double, 4> projected_box(vtkRenderer* ren, const double b[6]);

/// After ResetCamera: zooms and shifts the projection so that the projected bounding box
/// fills the region [x0, x1] x [y0, y1] (normalized window coordinates), centred in it.
void fit_3d_camera(vtkRenderer* ren, const double b[6], int w, int h, double x0, double x1, double y0,
                   double y1);

/// Outward directions of a 3D particle assembly at each of its centres (3 values per point
/// in `xyz`): the mean offset from the neighbours within `reach` to the point, in units of
/// `reach`, then averaged half and half with its neighbours' mean, so that the grains of
/// one face of the assembly agree. A point on a flat face gets about 0.3 along the face's
/// outward normal, a point deep inside about 0. `alone` marks the points without neighbours.
struct Outward {
  std::vector<double> dir;
  std::vector<bool> alone;
};

Outward outward_directions(const std::vector<double>& xyz, double reach);

/// Direction of the key light of 3D pictures in the camera's frame: from the upper left
/// and in front (x right, y up, z towards the viewer).
inline constexpr double kKeyLight[3] = {-0.45, 0.75, 1.0};

/// Brightness of faces turned away from the key light, and of particles inside.
inline constexpr double kFaceDark = 0.4, kInsideDark = 0.4;

/// Brightness factors (0.4 .. 1) that shade a 3D particle assembly like a solid: each
/// particle is lit by the key light as the face of the assembly it lies on (its outward
/// direction), so the faces of a block, of a notch cut into it and of a clip plane's cut
/// each get their own brightness. Particles inside (seen through the gaps between the
/// surface grains) are dark; particles alone are lit as if facing the camera.
std::vector<double> face_shading(const std::vector<double>& xyz, double mean_r, vtkCamera* cam);

void write_png(vtkRenderWindow* win, const fs::path& png);

inline std::string thousands(std::int64_t n) { return std::to_string(n); }

/// A mesh ready to draw: its actor (null when nothing is left after clipping) and the
/// bounds of what is drawn.
struct MeshActor {
  vtkSmartPointer<vtkActor> actor;
  double bounds[6] = {1e300, -1e300, 1e300, -1e300, 1e300, -1e300};
};

/// The mesh as a VTK grid, clipped by the style's plane in 3D (cells cut through, so the
/// cut face shows the field), coloured by `values` (display values, on points or cells)
/// through `lut`, or in one colour when `values` is empty.
MeshActor mesh_actor(const MeshFrame& mesh, const MeshValues& mv, const RenderStyle& s, int dim,
                     vtkLookupTable* lut, const std::array<double, 2>& range);

/// Rigid walls: dark lines in 2D; in 3D translucent planes with a dark outline (their
/// boundary edges, not the diagonal between a rectangle's two triangles), so that the
/// particles behind them stay readable.
std::vector<vtkSmartPointer<vtkActor>> wall_actors(const MeshFrame& walls, int dim, int height);

}  // namespace strata::io::render_parts
#endif
