#include "strata/io/render.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "atomic_file.hpp"
#include "strata/config.hpp"
#include "strata/core/error.hpp"
#include "strata/core/log.hpp"
#include "strata/io/display.hpp"
#include "strata/io/series.hpp"
#include "strata/io/vtk.hpp"
#include "vtk_grid.hpp"

#if STRATA_WITH_RENDER
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkCell.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkCoordinate.h>
#include <vtkDataSetMapper.h>
#include <vtkDoubleArray.h>
#include <vtkFeatureEdges.h>
#include <vtkFloatArray.h>
#include <vtkGlyph3DMapper.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkLight.h>
#include <vtkLineSource.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkOggTheoraWriter.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRegularPolygonSource.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkStaticPointLocator.h>
#include <vtkTableBasedClipDataSet.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkWindowToImageFilter.h>

#include <cstdlib>
#include <sstream>
#endif

namespace strata::io {
namespace fs = std::filesystem;

std::string format_time(double t) {
  if (t == 0 || !std::isfinite(t)) return fmt::format("{} s", t);
  struct Prefix {
    double scale;
    const char* unit;
  };
  static constexpr Prefix kPrefixes[] = {{1, "s"}, {1e-3, "ms"}, {1e-6, "\u00b5s"}, {1e-9, "ns"}};
  for (const auto& p : kPrefixes)
    if (std::abs(t) >= p.scale * 0.99995 || p.scale == 1e-9) {
      const double v = t / p.scale;
      const int digits = std::abs(v) >= 100 ? 0 : std::abs(v) >= 10 ? 1 : 2;
      return fmt::format("{:.{}f} {}", v, digits, p.unit);
    }
  return fmt::format("{} s", t);
}

#if STRATA_WITH_RENDER
namespace {

using Rgb = std::array<double, 3>;

/// Colours of broken-bond modes (BondState codes 1..3) and their legend names.
struct ModeStyle {
  BondState state;
  Rgb colour;
  const char* label;
};
constexpr ModeStyle kModes[] = {
    {BondState::BrokenTension, {0.84, 0.10, 0.11}, "tensile crack"},
    {BondState::BrokenShear, {0.13, 0.40, 0.90}, "shear crack"},
    {BondState::Closed, {0.10, 0.10, 0.10}, "closed again"},
};
constexpr ModeStyle kContactMode{BondState::Contact, {0.05, 0.55, 0.25}, "contact"};
constexpr Rgb kIntactColour{0.55, 0.55, 0.55};
constexpr Rgb kUniformMeshColour{0.74, 0.80, 0.87};  // pale steel blue
constexpr Rgb kMeshEdgeColour{0.35, 0.38, 0.42};
constexpr Rgb kWallColour{0.20, 0.24, 0.32};  // dark slate: 2D walls, 3D outlines
constexpr Rgb kWallFill{0.55, 0.62, 0.75};    // light slate: 3D planes, translucent
/// Meshes with at most this many cells are drawn with their element edges.
constexpr std::size_t kMaxCellsWithEdges = 5000;
constexpr Rgb kUniformParticleColour{0.86, 0.82, 0.72};  // sandstone beige
constexpr Rgb kText{0.08, 0.08, 0.08};

Rgb hex(unsigned v) { return {((v >> 16) & 255) / 255.0, ((v >> 8) & 255) / 255.0, (v & 255) / 255.0}; }

vtkSmartPointer<vtkLookupTable> make_lut(Colormap map, double lo, double hi) {
  vtkNew<vtkColorTransferFunction> ctf;
  switch (map) {
    case Colormap::Viridis: {
      // matplotlib's viridis at 10 evenly spaced points.
      static constexpr unsigned kViridis[] = {0x440154, 0x482878, 0x3E4A89, 0x31688E, 0x26828E,
                                              0x1F9E89, 0x35B779, 0x6DCD59, 0xB4DE2C, 0xFDE725};
      for (int i = 0; i < 10; ++i) {
        const Rgb c = hex(kViridis[i]);
        ctf->AddRGBPoint(i / 9.0, c[0], c[1], c[2]);
      }
      break;
    }
    case Colormap::CoolWarm:
      ctf->SetColorSpaceToDiverging();
      ctf->AddRGBPoint(0.0, 0.230, 0.299, 0.754);
      ctf->AddRGBPoint(1.0, 0.706, 0.016, 0.150);
      break;
    case Colormap::Greys:
      ctf->AddRGBPoint(0.0, 0.92, 0.92, 0.92);
      ctf->AddRGBPoint(1.0, 0.45, 0.45, 0.45);
      break;
  }
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  constexpr int kColours = 256;
  lut->SetNumberOfTableValues(kColours);
  for (int i = 0; i < kColours; ++i) {
    double c[3];
    ctf->GetColor(i / (kColours - 1.0), c);
    lut->SetTableValue(i, c[0], c[1], c[2], 1.0);
  }
  lut->SetTableRange(lo, hi);
  lut->Build();
  return lut;
}

/// A table of one colour per category, value k in [k - 0.5, k + 0.5): Tableau's ten
/// qualitative colours, repeated past ten, so neighbouring layers always differ.
vtkSmartPointer<vtkLookupTable> make_categorical_lut(std::size_t n) {
  static constexpr unsigned kPalette[] = {0x4E79A7, 0xF28E2B, 0xE15759, 0x76B7B2, 0x59A14F,
                                          0xEDC948, 0xB07AA1, 0xFF9DA7, 0x9C755F, 0xBAB0AC};
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  const auto count = static_cast<vtkIdType>(std::max<std::size_t>(n, 1));
  lut->SetNumberOfTableValues(count);
  for (vtkIdType k = 0; k < count; ++k) {
    const Rgb c = hex(kPalette[k % 10]);
    lut->SetTableValue(k, c[0], c[1], c[2], 1.0);
  }
  lut->SetTableRange(-0.5, static_cast<double>(count) - 0.5);
  return lut;
}

/// The displayed value of array `a` at each tuple (component or magnitude, times scale).
std::vector<double> field_values(const Array* a, const RenderStyle& s) {
  if (!a) return {};
  STRATA_CHECK(s.component < a->components, Input,
               "render: field '{}' has {} components, asked for component {}", s.field, a->components,
               s.component);
  std::vector<double> v(a->tuples());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (s.component >= 0 || a->components == 1) {
      v[i] = a->at(i, std::max(s.component, 0));
    } else {
      double m = 0;
      for (int c = 0; c < a->components; ++c) m += a->at(i, c) * a->at(i, c);
      v[i] = std::sqrt(m);
    }
    v[i] *= s.field_scale;
  }
  return v;
}

std::vector<double> field_values(const PointCloud& cloud, const RenderStyle& s) {
  return field_values(cloud.find(s.field), s);
}

/// The displayed values of a mesh: from its point array `field` if it has one, else from
/// its cell array; empty when it has neither.
struct MeshValues {
  std::vector<double> values;
  bool on_cells = false;
};
MeshValues field_values(const MeshFrame& mesh, const RenderStyle& s) {
  if (s.field.empty()) return {};
  if (const Array* a = mesh.find_point(s.field)) return {field_values(a, s), false};
  if (const Array* a = mesh.find_cell(s.field)) return {field_values(a, s), true};
  return {};
}

std::array<double, 2> finite_range(const std::vector<double>& v) {
  std::array<double, 2> r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (double x : v)
    if (std::isfinite(x)) r = {std::min(r[0], x), std::max(r[1], x)};
  return r;
}

std::array<double, 2> merge(std::array<double, 2> a, std::array<double, 2> b) {
  return {std::min(a[0], b[0]), std::max(a[1], b[1])};
}

/// A usable colour range: finite, non-empty.
std::array<double, 2> widen(std::array<double, 2> r) {
  if (!(r[0] <= r[1])) return {0.0, 1.0};
  if (r[1] - r[0] <= 1e-12 * std::max(std::abs(r[0]), std::abs(r[1]))) {
    const double pad = r[0] == 0 ? 1.0 : 0.05 * std::abs(r[0]);
    return {r[0] - pad, r[1] + pad};
  }
  return r;
}

bool clipped(const RenderStyle& s, int dim, const double* p) {
  if (dim != 3 || !s.clip_plane) return false;
  const auto& c = *s.clip_plane;
  return (p[0] - c[0]) * c[3] + (p[1] - c[1]) * c[4] + (p[2] - c[2]) * c[5] > 0;
}

vtkSmartPointer<vtkTextActor> text(const std::string& s, double x, double y, int size, bool bold,
                                   const Rgb& colour, int justify = VTK_TEXT_LEFT,
                                   int vjustify = VTK_TEXT_TOP) {
  auto t = vtkSmartPointer<vtkTextActor>::New();
  t->SetInput(s.c_str());
  t->GetPositionCoordinate()->SetCoordinateSystemToNormalizedDisplay();
  t->GetPositionCoordinate()->SetValue(x, y);
  auto* p = t->GetTextProperty();
  p->SetFontFamilyToArial();
  p->SetFontSize(size);
  p->SetBold(bold);
  p->SetColor(colour[0], colour[1], colour[2]);
  p->SetJustification(justify);
  p->SetVerticalJustification(vjustify);
  return t;
}

/// A short horizontal line in normalized window coordinates (legend sample).
vtkSmartPointer<vtkActor2D> legend_line(double x0, double x1, double y, const Rgb& colour, double width) {
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(x0, y, 0);
  pts->InsertNextPoint(x1, y, 0);
  vtkNew<vtkCellArray> lines;
  const vtkIdType ids[2] = {0, 1};
  lines->InsertNextCell(2, ids);
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(pts);
  pd->SetLines(lines);
  vtkNew<vtkCoordinate> coord;
  coord->SetCoordinateSystemToNormalizedDisplay();
  vtkNew<vtkPolyDataMapper2D> m;
  m->SetInputData(pd);
  m->SetTransformCoordinate(coord);
  auto a = vtkSmartPointer<vtkActor2D>::New();
  a->SetMapper(m);
  a->GetProperty()->SetColor(colour[0], colour[1], colour[2]);
  a->GetProperty()->SetLineWidth(static_cast<float>(width));
  return a;
}

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
                   int code, const RenderStyle& s, int dim, const SeenTest& seen) {
  vtkNew<vtkPoints> p;
  p->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> dir, size;
  dir->SetName("dir");
  dir->SetNumberOfComponents(3);
  size->SetName("size");
  CrackSet out;
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    const int st = state ? static_cast<int>(std::lround(state->at(b))) : 1;
    if (st != code) continue;
    const auto i = static_cast<std::size_t>(bonds.ends[2 * b]),
               j = static_cast<std::size_t>(bonds.ends[2 * b + 1]);
    const double* a = &pts.xyz[3 * i];
    const double* c = &pts.xyz[3 * j];
    const double mid[3] = {0.5 * (a[0] + c[0]), 0.5 * (a[1] + c[1]), 0.5 * (a[2] + c[2])};
    if (clipped(s, dim, mid)) continue;
    double d[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len == 0) continue;
    // 2D: face of the Voronoi cell between two touching equal disks in a hexagonal packing,
    // d/sqrt(3) long, so cracks of neighbouring bonds join into continuous lines. 3D: a disc
    // as wide as the particles' mean radius, so the cracks crossing a surface read as a
    // dashed line.
    const double ri = radius ? radius->at(i) : 0.5 * len, rj = radius ? radius->at(j) : 0.5 * len;
    const double face = dim == 2 ? (ri + rj) / std::sqrt(3.0) : 0.5 * (ri + rj);
    ++out.count;
    if (seen && !seen(i) && !seen(j)) continue;
    p->InsertNextPoint(mid);
    dir->InsertNextTuple3(d[0] / len, d[1] / len, d[2] / len);
    size->InsertNextValue(face);
    ++out.drawn;
  }
  out.centres = vtkSmartPointer<vtkPolyData>::New();
  out.centres->SetPoints(p);
  out.centres->GetPointData()->AddArray(dir);
  out.centres->GetPointData()->AddArray(size);
  return out;
}

vtkSmartPointer<vtkGlyph3DMapper> crack_mapper(vtkPolyData* centres, int dim) {
  auto m = vtkSmartPointer<vtkGlyph3DMapper>::New();
  m->SetInputData(centres);
  if (dim == 2) {
    // Unit segment along y; the glyph's x axis is turned onto the bond direction.
    vtkNew<vtkLineSource> seg;
    seg->SetPoint1(0, -0.5, 0);
    seg->SetPoint2(0, 0.5, 0);
    m->SetSourceConnection(seg->GetOutputPort());
  } else {
    vtkNew<vtkRegularPolygonSource> disc;
    disc->SetNumberOfSides(6);
    disc->SetRadius(0.5);
    disc->SetNormal(1, 0, 0);
    m->SetSourceConnection(disc->GetOutputPort());
  }
  m->SetOrientationArray("dir");
  m->SetOrientationModeToDirection();
  m->SetScaleArray("size");
  m->SetScaleModeToScaleByMagnitude();
  m->SetScaling(true);
  m->ScalarVisibilityOff();
  return m;
}

/// Fits an orthographic camera looking down -z so that `b` fills the region
/// [x0, x1] x [y0, y1] (normalized window coordinates) of a w x h window.
void fit_2d_camera(vtkCamera* cam, const double b[6], int w, int h, double x0, double x1, double y0,
                   double y1) {
  const double bw = std::max(b[1] - b[0], 1e-30), bh = std::max(b[3] - b[2], 1e-30);
  const double s = std::max(bw / ((x1 - x0) * w), bh / ((y1 - y0) * h));  // world units per pixel
  const double cx = 0.5 * (b[0] + b[1]), cy = 0.5 * (b[2] + b[3]);
  const double fx = cx + (0.5 - 0.5 * (x0 + x1)) * w * s;  // window centre in world units
  const double fy = cy + (0.5 - 0.5 * (y0 + y1)) * h * s;
  // The camera stands 10 model sizes above the plane; the depth range it draws must follow,
  // whatever the model's size (micrometres to hundreds of kilometres): VTK's default range
  // (0.01 to 1000.01) would leave anything beyond 100 m undrawn.
  const double dist = 10 * std::max(bw, bh);
  const double zmin = std::max(std::abs(b[4]), std::abs(b[5]));  // disks and halo layers near z = 0
  cam->ParallelProjectionOn();
  cam->SetFocalPoint(fx, fy, 0);
  cam->SetPosition(fx, fy, dist);
  cam->SetViewUp(0, 1, 0);
  cam->SetParallelScale(0.5 * h * s);
  cam->SetClippingRange(std::max(1e-3 * dist, 0.5 * dist - zmin), 1.5 * dist + zmin);
}

/// Projected extent (display pixels) of the corners of `b`: {xmin, xmax, ymin, ymax}.
std::array<double, 4> projected_box(vtkRenderer* ren, const double b[6]) {
  std::array<double, 4> e{1e300, -1e300, 1e300, -1e300};
  for (int k = 0; k < 8; ++k) {
    ren->SetWorldPoint(b[k & 1], b[2 + ((k >> 1) & 1)], b[4 + ((k >> 2) & 1)], 1.0);
    ren->WorldToDisplay();
    double d[3];
    ren->GetDisplayPoint(d);
    e = {std::min(e[0], d[0]), std::max(e[1], d[0]), std::min(e[2], d[1]), std::max(e[3], d[1])};
  }
  return e;
}

/// After ResetCamera: zooms and shifts the projection so that the projected bounding box
/// fills the region [x0, x1] x [y0, y1] (normalized window coordinates), centred in it.
void fit_3d_camera(vtkRenderer* ren, const double b[6], int w, int h, double x0, double x1, double y0,
                   double y1) {
  vtkCamera* cam = ren->GetActiveCamera();
  auto e = projected_box(ren, b);
  const double zoom =
      std::min((x1 - x0) * w / std::max(e[1] - e[0], 1.0), (y1 - y0) * h / std::max(e[3] - e[2], 1.0));
  cam->Zoom(0.97 * zoom);
  // The window centre shifts the picture linearly: measure how much, then aim.
  cam->SetWindowCenter(0, 0);
  e = projected_box(ren, b);
  const double c0x = 0.5 * (e[0] + e[1]), c0y = 0.5 * (e[2] + e[3]);
  cam->SetWindowCenter(0.1, 0.1);
  e = projected_box(ren, b);
  const double kx = (0.5 * (e[0] + e[1]) - c0x) / 0.1, ky = (0.5 * (e[2] + e[3]) - c0y) / 0.1;
  const double ax = 0.5 * (x0 + x1) * w, ay = 0.5 * (y0 + y1) * h;
  cam->SetWindowCenter(std::abs(kx) > 1e-9 ? (ax - c0x) / kx : 0.0,
                       std::abs(ky) > 1e-9 ? (ay - c0y) / ky : 0.0);
}

/// Outward directions of a 3D particle assembly at each of its centres (3 values per point
/// in `xyz`): the mean offset from the neighbours within `reach` to the point, in units of
/// `reach`, then averaged half and half with its neighbours' mean, so that the grains of
/// one face of the assembly agree. A point on a flat face gets about 0.3 along the face's
/// outward normal, a point deep inside about 0. `alone` marks the points without neighbours.
struct Outward {
  std::vector<double> dir;
  std::vector<bool> alone;
};
Outward outward_directions(const std::vector<double>& xyz, double reach) {
  const std::size_t n = xyz.size() / 3;
  Outward res{std::vector<double>(3 * n, 0.0), std::vector<bool>(n, true)};
  auto& out = res.dir;
  if (n == 0 || !(reach > 0)) return res;
  // A point locator over the points with finite coordinates (the others have no neighbours).
  auto finite = [&](std::size_t i) {
    return std::isfinite(xyz[3 * i]) && std::isfinite(xyz[3 * i + 1]) && std::isfinite(xyz[3 * i + 2]);
  };
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::vector<std::size_t> point_of;  // locator id -> index into xyz
  for (std::size_t i = 0; i < n; ++i)
    if (finite(i)) {
      points->InsertNextPoint(&xyz[3 * i]);
      point_of.push_back(i);
    }
  if (point_of.empty()) return res;
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(points);
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(cloud);
  locator->BuildLocator();
  vtkNew<vtkIdList> found;
  // f(j, p_i - p_j) for each other point j closer than `reach` (strictly), in index order
  auto for_neighbours = [&](std::size_t i, auto&& f) {
    if (!finite(i)) return;
    const double* p = &xyz[3 * i];
    locator->FindPointsWithinRadius(reach, p, found);
    std::vector<std::size_t> near;
    for (vtkIdType k = 0; k < found->GetNumberOfIds(); ++k)
      near.push_back(point_of[std::size_t(found->GetId(k))]);
    std::sort(near.begin(), near.end());
    for (const std::size_t j : near) {
      const double* q = &xyz[3 * j];
      const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
      if (j != i && d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < reach * reach) f(j, d);
    }
  };
  std::vector<double> raw(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double sum[3] = {0, 0, 0};
    std::size_t count = 0;
    for_neighbours(i, [&](std::size_t, const double* d) {
      for (int k = 0; k < 3; ++k) sum[k] += d[k];
      ++count;
    });
    res.alone[i] = count == 0;
    if (count > 0)
      for (int k = 0; k < 3; ++k) raw[3 * i + k] = sum[k] / (reach * static_cast<double>(count));
  }
  for (std::size_t i = 0; i < n; ++i) {
    double sum[3] = {0, 0, 0};
    std::size_t count = 0;
    for_neighbours(i, [&](std::size_t j, const double*) {
      for (int k = 0; k < 3; ++k) sum[k] += raw[3 * j + k];
      ++count;
    });
    for (int k = 0; k < 3; ++k)
      out[3 * i + k] = count > 0 ? 0.5 * raw[3 * i + k] + 0.5 * sum[k] / static_cast<double>(count) : 0.0;
  }
  return res;
}

/// Direction of the key light of 3D pictures in the camera's frame: from the upper left
/// and in front (x right, y up, z towards the viewer).
constexpr double kKeyLight[3] = {-0.45, 0.75, 1.0};
/// Brightness of faces turned away from the key light, and of particles inside.
constexpr double kFaceDark = 0.4, kInsideDark = 0.4;

/// Brightness factors (0.4 .. 1) that shade a 3D particle assembly like a solid: each
/// particle is lit by the key light as the face of the assembly it lies on (its outward
/// direction), so the faces of a block, of a notch cut into it and of a clip plane's cut
/// each get their own brightness. Particles inside (seen through the gaps between the
/// surface grains) are dark; particles alone are lit as if facing the camera.
std::vector<double> face_shading(const std::vector<double>& xyz, double mean_r, vtkCamera* cam) {
  const std::size_t n = xyz.size() / 3;
  double view[3], up[3], right[3];
  {
    double pos[3], focal[3];
    cam->GetPosition(pos);
    cam->GetFocalPoint(focal);
    cam->GetViewUp(up);
    for (int k = 0; k < 3; ++k) view[k] = pos[k] - focal[k];  // towards the viewer
  }
  auto normalise = [](double* v) {
    const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
      for (int k = 0; k < 3; ++k) v[k] /= l;
    return l;
  };
  normalise(view);
  const double uv = up[0] * view[0] + up[1] * view[1] + up[2] * view[2];
  for (int k = 0; k < 3; ++k) up[k] -= uv * view[k];
  normalise(up);
  right[0] = up[1] * view[2] - up[2] * view[1];
  right[1] = up[2] * view[0] - up[0] * view[2];
  right[2] = up[0] * view[1] - up[1] * view[0];
  double light[3];
  for (int k = 0; k < 3; ++k)
    light[k] = kKeyLight[0] * right[k] + kKeyLight[1] * up[k] + kKeyLight[2] * view[k];
  normalise(light);
  // A flat face's outward direction is about 0.3 long; 0.15 and longer count fully.
  const Outward out = outward_directions(xyz, 3.5 * mean_r);
  auto lit = [&](const double* d) {
    return kFaceDark + (1 - kFaceDark) * std::max(0.0, d[0] * light[0] + d[1] * light[1] + d[2] * light[2]);
  };
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) {
    double d[3] = {out.dir[3 * i], out.dir[3 * i + 1], out.dir[3 * i + 2]};
    const double w = std::min(1.0, normalise(d) / 0.15);
    f[i] = out.alone[i] ? lit(view) : w * lit(d) + (1 - w) * kInsideDark;
  }
  return f;
}

void write_png(vtkRenderWindow* win, const fs::path& png) {
  detail::make_parent(png);
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(win);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  const auto tmp = fs::path(png.string() + ".tmp");
  vtkNew<vtkPNGWriter> w;
  w->SetFileName(tmp.c_str());
  w->SetInputConnection(grab->GetOutputPort());
  w->Write();
  STRATA_CHECK(w->GetErrorCode() == 0 && fs::exists(tmp), IO, "could not write PNG {}", png.string());
  detail::commit(tmp, png);
}

std::string thousands(std::int64_t n) { return std::to_string(n); }

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
                     vtkLookupTable* lut, const std::array<double, 2>& range) {
  const vtkSmartPointer<vtkUnstructuredGrid> ug = detail::mesh_grid(mesh);
  const bool coloured = !mv.values.empty();
  if (coloured) {
    vtkNew<vtkFloatArray> c;
    c->SetName("c");
    for (double v : mv.values) c->InsertNextValue(static_cast<float>(v));
    if (mv.on_cells)
      ug->GetCellData()->AddArray(c);
    else
      ug->GetPointData()->AddArray(c);
  }

  vtkSmartPointer<vtkDataSet> shown = ug.Get();
  if (dim == 3 && s.clip_plane) {
    const auto& p = *s.clip_plane;
    vtkNew<vtkPlane> plane;
    plane->SetOrigin(p[0], p[1], p[2]);
    plane->SetNormal(p[3], p[4], p[5]);
    vtkNew<vtkTableBasedClipDataSet> clip;
    clip->SetInputData(ug);
    clip->SetClipFunction(plane);
    clip->InsideOutOn();  // keep the side the normal points away from
    clip->Update();
    shown = clip->GetOutput();
  }
  MeshActor out;
  if (shown->GetNumberOfCells() == 0) return out;
  shown->GetBounds(out.bounds);

  vtkNew<vtkDataSetMapper> m;
  m->SetInputData(shown);
  if (coloured) {
    m->SetLookupTable(lut);
    m->SetScalarRange(range[0], range[1]);
    if (mv.on_cells)
      m->SetScalarModeToUseCellFieldData();
    else
      m->SetScalarModeToUsePointFieldData();
    m->SelectColorArray("c");
    m->ScalarVisibilityOn();
  } else {
    m->ScalarVisibilityOff();
  }
  out.actor = vtkSmartPointer<vtkActor>::New();
  out.actor->SetMapper(m);
  auto* prop = out.actor->GetProperty();
  if (!coloured) prop->SetColor(kUniformMeshColour[0], kUniformMeshColour[1], kUniformMeshColour[2]);
  if (mesh.cells() <= kMaxCellsWithEdges) {
    prop->EdgeVisibilityOn();
    prop->SetEdgeColor(kMeshEdgeColour[0], kMeshEdgeColour[1], kMeshEdgeColour[2]);
  }
  prop->SetLineWidth(2.0f);  // line cells (bars, springs)
  if (dim == 2) {
    prop->SetAmbient(1.0);
    prop->SetDiffuse(0.0);
    prop->SetSpecular(0.0);
  } else {
    prop->SetAmbient(0.25);
    prop->SetDiffuse(0.8);
    prop->SetSpecular(0.1);
  }
  return out;
}

/// Rigid walls: dark lines in 2D; in 3D translucent planes with a dark outline (their
/// boundary edges, not the diagonal between a rectangle's two triangles), so that the
/// particles behind them stay readable.
std::vector<vtkSmartPointer<vtkActor>> wall_actors(const MeshFrame& walls, int dim, int height) {
  const vtkSmartPointer<vtkUnstructuredGrid> ug = detail::mesh_grid(walls);
  auto flat = [](vtkActor* actor) {
    auto* prop = actor->GetProperty();
    prop->SetColor(kWallColour[0], kWallColour[1], kWallColour[2]);
    prop->SetAmbient(1.0);
    prop->SetDiffuse(0.0);
    prop->SetSpecular(0.0);
  };
  std::vector<vtkSmartPointer<vtkActor>> out;
  vtkNew<vtkDataSetMapper> m;
  m->SetInputData(ug);
  m->ScalarVisibilityOff();
  out.push_back(vtkSmartPointer<vtkActor>::New());
  out.back()->SetMapper(m);
  flat(out.back());
  if (dim == 2) {
    out.back()->GetProperty()->SetLineWidth(static_cast<float>(std::max(3.0, height / 250.0)));
    return out;
  }
  out.back()->GetProperty()->SetColor(kWallFill[0], kWallFill[1], kWallFill[2]);
  out.back()->GetProperty()->SetOpacity(0.25);
  vtkNew<vtkPolyData> surface;  // the triangles as polygons, which vtkFeatureEdges takes
  surface->SetPoints(ug->GetPoints());
  vtkNew<vtkCellArray> polys;
  for (vtkIdType c = 0; c < ug->GetNumberOfCells(); ++c)
    if (ug->GetCellType(c) == VTK_TRIANGLE) polys->InsertNextCell(ug->GetCell(c)->GetPointIds());
  surface->SetPolys(polys);
  vtkNew<vtkFeatureEdges> outline;
  outline->SetInputData(surface);
  outline->BoundaryEdgesOn();
  outline->FeatureEdgesOff();
  outline->NonManifoldEdgesOff();
  outline->ManifoldEdgesOff();
  outline->ColoringOff();
  vtkNew<vtkPolyDataMapper> lines;
  lines->SetInputConnection(outline->GetOutputPort());
  lines->ScalarVisibilityOff();
  out.push_back(vtkSmartPointer<vtkActor>::New());
  out.back()->SetMapper(lines);
  flat(out.back());
  out.back()->GetProperty()->SetLineWidth(2.0f);
  return out;
}

}  // namespace

void render_frame(const RenderRequest& rq) {
  STRATA_CHECK(rq.particles || rq.mesh, Input, "render_frame: no particles and no mesh given");
  STRATA_CHECK(!rq.png.empty(), Input, "render_frame: no output file given");
  PointCloud no_particles;
  if (!rq.particles) no_particles.dim = rq.mesh->dim;
  const PointCloud& cloud = rq.particles ? *rq.particles : no_particles;
  validate(cloud);
  if (rq.mesh) validate(*rq.mesh);
  if (rq.walls) validate(*rq.walls);
  const RenderStyle& s = rq.style;
  STRATA_CHECK(s.width >= 16 && s.height >= 16 && s.width <= 8192 && s.height <= 8192, Input,
               "render: picture size {}x{} outside 16..8192 pixels", s.width, s.height);
  const PointCloud& bond_pts = rq.bond_points ? *rq.bond_points : cloud;
  if (rq.bonds) validate(bond_pts, rq.bonds);
  ensure_display();

  const int dim = cloud.dim;
  const int W = s.width, H = s.height;
  const int font = std::max(10, H / 42);
  const Array* radius = cloud.find(kRadiusArray);

  // ---- particles: glyph centres with radius and display value --------------------------
  const std::vector<double> values = s.field.empty() ? std::vector<double>{} : field_values(cloud, s);
  const MeshValues mesh_values = rq.mesh ? field_values(*rq.mesh, s) : MeshValues{};
  if (!s.field.empty() && values.empty() && mesh_values.values.empty())
    log::warn("render: {} no array '{}'; drawing in one colour",
              rq.mesh ? "particles and mesh have" : "particles have", s.field);
  const bool coloured = !values.empty() || !mesh_values.values.empty();
  std::array<double, 2> range =
      s.range ? *s.range : merge(finite_range(values), finite_range(mesh_values.values));
  const bool categorical = !s.categories.empty();
  if (categorical) range = {-0.5, static_cast<double>(s.categories.size()) - 0.5};
  if (!s.range && !categorical && s.colormap == Colormap::CoolWarm && range[0] <= range[1]) {
    // A diverging map is centred on zero: white means "no stress".
    const double m = std::max(std::abs(range[0]), std::abs(range[1]));
    range = {-m, m};
  }
  if (!categorical) range = widen(range);

  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkFloatArray> rad, col;
  rad->SetName("r");
  col->SetName("c");
  double bounds[6] = {1e300, -1e300, 1e300, -1e300, 1e300, -1e300};
  double mean_r = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const double* p = &cloud.xyz[3 * i];
    if (clipped(s, dim, p)) continue;
    const double r = radius ? radius->at(i) : 0.0;
    pts->InsertNextPoint(p);
    rad->InsertNextValue(static_cast<float>(r * s.radius_factor));
    if (!values.empty()) col->InsertNextValue(static_cast<float>(values[i]));
    for (int k = 0; k < 3; ++k) {
      bounds[2 * k] = std::min(bounds[2 * k], p[k] - r);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], p[k] + r);
    }
    mean_r += r;
  }
  const auto shown = pts->GetNumberOfPoints();
  if (shown > 0) mean_r /= static_cast<double>(shown);
  auto lut =
      categorical ? make_categorical_lut(s.categories.size()) : make_lut(s.colormap, range[0], range[1]);
  MeshActor mesh;
  if (rq.mesh) {
    mesh = mesh_actor(*rq.mesh, mesh_values, s, dim, lut, range);
    if (mesh.actor)
      for (int k = 0; k < 3; ++k) {
        bounds[2 * k] = std::min(bounds[2 * k], mesh.bounds[2 * k]);
        bounds[2 * k + 1] = std::max(bounds[2 * k + 1], mesh.bounds[2 * k + 1]);
      }
  }
  if (shown == 0 && !mesh.actor) std::fill(bounds, bounds + 6, 0.0), bounds[1] = bounds[3] = bounds[5] = 1.0;
  // Walls are part of the model: the camera takes them in (they reach a little beyond the
  // particles, and a wall that has not yet met them shows where it is).
  const auto walls = rq.walls && rq.walls->cells() > 0 ? wall_actors(*rq.walls, dim, H)
                                                       : std::vector<vtkSmartPointer<vtkActor>>{};
  if (!walls.empty())
    for (std::size_t i = 0; i < rq.walls->nodes(); ++i)
      for (int k = 0; k < 3; ++k) {
        bounds[2 * k] = std::min(bounds[2 * k], rq.walls->xyz[3 * i + k]);
        bounds[2 * k + 1] = std::max(bounds[2 * k + 1], rq.walls->xyz[3 * i + k]);
      }
  if (!radius && shown > 0) {
    // No radius: a size from the point density of the bounding box.
    const double area = (bounds[1] - bounds[0]) * (bounds[3] - bounds[2]);
    mean_r = 0.5 * std::sqrt(std::max(area, 1e-30) / std::max<vtkIdType>(shown, 1));
    for (vtkIdType i = 0; i < shown; ++i) rad->SetValue(i, static_cast<float>(mean_r * s.radius_factor));
    log::warn("render: particles have no '{}' array; drawing them with radius {:.3g}", kRadiusArray, mean_r);
  }
  vtkNew<vtkPolyData> centres;
  centres->SetPoints(pts);
  centres->GetPointData()->AddArray(rad);
  if (!values.empty()) {
    centres->GetPointData()->AddArray(col);
    centres->GetPointData()->SetActiveScalars("c");
  }

  vtkNew<vtkGlyph3DMapper> pmap;
  pmap->SetInputData(centres);
  if (dim == 2) {
    vtkNew<vtkRegularPolygonSource> disk;
    disk->SetNumberOfSides(24);
    disk->SetRadius(1.0);
    disk->SetNormal(0, 0, 1);
    disk->GeneratePolylineOff();
    pmap->SetSourceConnection(disk->GetOutputPort());
  } else {
    vtkNew<vtkSphereSource> ball;
    ball->SetRadius(1.0);
    ball->SetThetaResolution(16);
    ball->SetPhiResolution(12);
    pmap->SetSourceConnection(ball->GetOutputPort());
  }
  pmap->SetScaleArray("r");
  pmap->SetScaleModeToScaleByMagnitude();
  pmap->SetScaling(true);
  pmap->OrientOff();
  if (!values.empty()) {
    pmap->SetLookupTable(lut);
    pmap->SetScalarRange(range[0], range[1]);
    pmap->SetScalarModeToUsePointFieldData();
    pmap->SelectColorArray("c");
    pmap->ScalarVisibilityOn();
  } else {
    pmap->ScalarVisibilityOff();
  }
  vtkNew<vtkActor> particles;
  particles->SetMapper(pmap);
  if (values.empty())
    particles->GetProperty()->SetColor(kUniformParticleColour[0], kUniformParticleColour[1],
                                       kUniformParticleColour[2]);
  if (dim == 2) {  // flat colours that match the colour bar exactly
    particles->GetProperty()->SetAmbient(1.0);
    particles->GetProperty()->SetDiffuse(0.0);
    particles->GetProperty()->SetSpecular(0.0);
  } else {
    particles->GetProperty()->SetAmbient(0.35);
    particles->GetProperty()->SetDiffuse(0.7);
    particles->GetProperty()->SetSpecular(0.1);
  }

  // ---- window, renderers (layer 0 particles, 1 crack halos, 2 cracks + annotations) -----
  vtkNew<vtkRenderWindow> win;
  win->SetOffScreenRendering(1);
  win->SetSize(W, H);
  win->SetNumberOfLayers(3);
  win->SetMultiSamples(0);
  vtkNew<vtkRenderer> scene, halo_layer, top;
  scene->SetBackground(1, 1, 1);
  scene->SetLayer(0);
  halo_layer->SetLayer(1);
  top->SetLayer(2);
  // The bond layers join after the 3D depth pass below, which draws the scene alone.
  win->AddRenderer(scene);
  if (shown > 0) scene->AddActor(particles);
  if (mesh.actor) {
    if (dim == 2 && shown > 0) {
      // Behind the disks (the 2D camera looks down -z), so coupled models show particles on top.
      const double extent = std::max(bounds[1] - bounds[0], bounds[3] - bounds[2]);
      mesh.actor->SetPosition(0, 0, -1e-3 * extent);
    }
    scene->AddActor(mesh.actor);
  }
  scene->UseFXAAOn();

  // Model area: left part of the window, leaving the right strip for colour bar and legend.
  const double mx0 = 0.03, mx1 = coloured || rq.bonds ? 0.77 : 0.97, my0 = 0.05, my1 = 0.87;
  const double side = 0.80;  // left edge of colour bar and legend
  vtkCamera* cam = scene->GetActiveCamera();
  if (dim == 2) {
    fit_2d_camera(cam, bounds, W, H, mx0, mx1, my0, my1);
  } else {
    auto d = s.view_direction;
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    STRATA_CHECK(n > 0, Input, "render: view direction is zero");
    const auto& u = s.view_up;
    const double cross[3] = {d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]};
    STRATA_CHECK(std::hypot(cross[0], cross[1], cross[2]) > 1e-9 * n * std::hypot(u[0], u[1], u[2]), Input,
                 "render: the up vector ({}, {}, {}) is zero or parallel to the view direction ({}, {}, {})",
                 u[0], u[1], u[2], d[0], d[1], d[2]);
    if (s.clip_plane)
      STRATA_CHECK(std::hypot((*s.clip_plane)[3], (*s.clip_plane)[4], (*s.clip_plane)[5]) > 0, Input,
                   "render: the clip plane's normal is zero");
    const double c[3] = {0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
                         0.5 * (bounds[4] + bounds[5])};
    cam->SetFocalPoint(c);
    cam->SetPosition(c[0] - d[0] / n, c[1] - d[1] / n, c[2] - d[2] / n);
    cam->SetViewUp(s.view_up.data());
    cam->SetViewAngle(25);
    scene->ResetCamera(bounds);
    fit_3d_camera(scene, bounds, W, H, mx0, mx1, my0, my1);

    // A key light from the upper left and a weaker headlight, both fixed to the camera.
    scene->AutomaticLightCreationOff();
    scene->RemoveAllLights();
    vtkNew<vtkLight> key, head;
    key->SetLightTypeToCameraLight();
    key->SetPosition(kKeyLight[0], kKeyLight[1], kKeyLight[2]);
    key->SetFocalPoint(0, 0, 0);
    key->SetIntensity(0.65);
    head->SetLightTypeToHeadlight();
    head->SetIntensity(0.45);
    scene->AddLight(key);
    scene->AddLight(head);

    // Particle colours (from the colour map or uniform) darkened by the face of the
    // assembly each particle lies on, so the model's shape reads as a solid's.
    if (shown > 0) {
      std::vector<double> xyz(3 * static_cast<std::size_t>(shown));
      for (vtkIdType i = 0; i < shown; ++i) pts->GetPoint(i, &xyz[3 * static_cast<std::size_t>(i)]);
      const std::vector<double> shade = face_shading(xyz, mean_r, cam);
      vtkNew<vtkUnsignedCharArray> rgb;
      rgb->SetName("rgb");
      rgb->SetNumberOfComponents(3);
      rgb->SetNumberOfTuples(shown);
      for (vtkIdType i = 0; i < shown; ++i) {
        Rgb c = kUniformParticleColour;
        if (!values.empty()) lut->GetColor(col->GetValue(i), c.data());
        for (int k = 0; k < 3; ++k)
          rgb->SetValue(3 * i + k,
                        static_cast<unsigned char>(std::clamp(std::lround(255 * c[k] * shade[i]), 0L, 255L)));
      }
      centres->GetPointData()->AddArray(rgb);
      pmap->SetColorModeToDirectScalars();
      pmap->SetScalarModeToUsePointFieldData();
      pmap->SelectColorArray("rgb");
      pmap->ScalarVisibilityOn();
    }
  }
  halo_layer->SetActiveCamera(cam);
  top->SetActiveCamera(cam);

  // 3D: bonds are drawn over the scene, so only those next to a particle the picture
  // shows are drawn: cracks on the model's surface, just under it, and on the clip plane's
  // cut, not those deep inside. The scene is drawn once alone; a particle is seen when the
  // surface at its centre's pixel lies at most 1.5 radii in front of its centre (its own
  // front lies one radius in front), or when nothing is drawn in front of it at all (as
  // for a particle the clip plane removed).
  std::vector<float> depth;
  std::vector<signed char> seen_point;
  SeenTest seen;
  if (dim == 3 && rq.bonds && rq.bonds->size() > 0 &&
      (s.show_broken_bonds || s.show_intact_bonds || s.show_contacts)) {
    win->Render();
    depth.resize(static_cast<std::size_t>(W) * static_cast<std::size_t>(H));
    win->GetZbufferData(0, 0, W - 1, H - 1, depth.data());
    seen_point.assign(bond_pts.size(), -1);
    const Array* r_of = bond_pts.find(kRadiusArray);
    double towards[3];
    cam->GetDirectionOfProjection(towards);
    seen = [&, r_of, towards](std::size_t i) {
      if (seen_point[i] < 0) {
        const double* p = &bond_pts.xyz[3 * i];
        double d[4];
        scene->SetWorldPoint(p[0], p[1], p[2], 1);
        scene->WorldToDisplay();
        scene->GetDisplayPoint(d);
        const double x = std::floor(d[0]), y = std::floor(d[1]);
        bool shown_here = false;
        if (x >= 0 && y >= 0 && x < W && y < H) {
          const float z =
              depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x)];
          shown_here = z >= 1.0f;  // nothing drawn at this pixel
          if (!shown_here) {
            scene->SetDisplayPoint(d[0], d[1], z);
            scene->DisplayToWorld();
            scene->GetWorldPoint(d);
            if (d[3] != 0)
              for (int k = 0; k < 3; ++k) d[k] /= d[3];
            const double behind =
                (p[0] - d[0]) * towards[0] + (p[1] - d[1]) * towards[1] + (p[2] - d[2]) * towards[2];
            shown_here = behind <= 1.5 * (r_of ? r_of->at(i) : mean_r);
          }
        }
        seen_point[i] = shown_here ? 1 : 0;
      }
      return seen_point[i] == 1;
    };
  }
  // Walls join after the depth pass: a translucent plane in front hides no crack.
  for (const auto& wall : walls) {
    // In 2D over the disks (the camera looks down -z).
    if (dim == 2) wall->SetPosition(0, 0, 1e-3 * std::max(bounds[1] - bounds[0], bounds[3] - bounds[2]));
    scene->AddActor(wall);
  }
  win->AddRenderer(halo_layer);
  win->AddRenderer(top);

  // ---- bonds ----------------------------------------------------------------------------
  std::vector<std::pair<const ModeStyle*, std::size_t>> legend;
  double px_per_unit = 0;
  {
    double p0[3], p1[3];
    scene->SetWorldPoint(bounds[0], bounds[2], bounds[4], 1);
    scene->WorldToDisplay();
    scene->GetDisplayPoint(p0);
    scene->SetWorldPoint(bounds[0] + 2 * mean_r, bounds[2], bounds[4], 1);
    scene->WorldToDisplay();
    scene->GetDisplayPoint(p1);
    px_per_unit = mean_r > 0 ? std::hypot(p1[0] - p0[0], p1[1] - p0[1]) / (2 * mean_r) : 0;
  }
  const double diameter_px = 2 * mean_r * px_per_unit;
  const double line_w = s.bond_line_width > 0 ? s.bond_line_width : std::clamp(0.22 * diameter_px, 1.5, 5.0);
  if (rq.bonds && rq.bonds->size() > 0) {
    const LineSet& bonds = *rq.bonds;
    const Array* state = bonds.find(kBondStateArray);
    if (!state) log::warn("render: bonds have no '{}' array; drawing all as tensile cracks", kBondStateArray);
    const Array* bond_radius = bond_pts.find(kRadiusArray);
    // Intact bonds and contacts as thin centre-to-centre lines under the cracks.
    auto thin_lines = [&](BondState code, const Rgb& colour, double width) {
      vtkNew<vtkPoints> lp;
      vtkNew<vtkCellArray> cells;
      std::size_t count = 0;
      for (std::size_t b = 0; b < bonds.size(); ++b) {
        if (std::lround(state->at(b)) != static_cast<long>(code)) continue;
        const double* a = &bond_pts.xyz[3 * bonds.ends[2 * b]];
        const double* c = &bond_pts.xyz[3 * bonds.ends[2 * b + 1]];
        const double mid[3] = {0.5 * (a[0] + c[0]), 0.5 * (a[1] + c[1]), 0.5 * (a[2] + c[2])};
        if (clipped(s, dim, mid)) continue;
        ++count;
        if (seen && !seen(static_cast<std::size_t>(bonds.ends[2 * b])) &&
            !seen(static_cast<std::size_t>(bonds.ends[2 * b + 1])))
          continue;
        const vtkIdType ids[2] = {lp->InsertNextPoint(a), lp->InsertNextPoint(c)};
        cells->InsertNextCell(2, ids);
      }
      if (cells->GetNumberOfCells() == 0) return count;
      vtkNew<vtkPolyData> pd;
      pd->SetPoints(lp);
      pd->SetLines(cells);
      vtkNew<vtkPolyDataMapper> m;
      m->SetInputData(pd);
      vtkNew<vtkActor> a;
      a->SetMapper(m);
      a->GetProperty()->SetColor(colour[0], colour[1], colour[2]);
      a->GetProperty()->SetLineWidth(static_cast<float>(width));
      a->GetProperty()->LightingOff();
      halo_layer->AddActor(a);
      return count;
    };
    if (s.show_intact_bonds && state)
      thin_lines(BondState::Intact, kIntactColour, std::max(1.0, 0.4 * line_w));
    std::size_t contacts = 0;
    if (s.show_contacts && state)
      contacts = thin_lines(BondState::Contact, kContactMode.colour, std::max(1.0, 0.5 * line_w));
    if (s.show_broken_bonds) {
      for (const auto& mode : kModes) {
        auto set = crack_set(bond_pts, bonds, state, bond_radius, static_cast<int>(mode.state), s, dim, seen);
        if (!state && mode.state != BondState::BrokenTension) continue;
        legend.emplace_back(&mode, set.count);
        if (set.drawn == 0) continue;
        // A white halo under each crack keeps it visible on any particle colour.
        // (One mapper per actor: a mapper's buffers belong to one renderer.)
        vtkNew<vtkActor> halo, crack;
        halo->SetMapper(crack_mapper(set.centres, dim));
        crack->SetMapper(crack_mapper(set.centres, dim));
        halo->GetProperty()->SetColor(1, 1, 1);
        crack->GetProperty()->SetColor(mode.colour[0], mode.colour[1], mode.colour[2]);
        for (auto* a : {halo.Get(), crack.Get()}) {
          a->GetProperty()->SetAmbient(1.0);
          a->GetProperty()->SetDiffuse(0.0);
          a->GetProperty()->SetRenderLinesAsTubes(false);
        }
        halo->GetProperty()->SetLineWidth(static_cast<float>(line_w + 2.5));
        crack->GetProperty()->SetLineWidth(static_cast<float>(line_w));
        if (dim == 3) halo->GetProperty()->SetRepresentationToWireframe();
        halo_layer->AddActor(halo);
        top->AddActor(crack);
      }
    }
    if (s.show_contacts && state) legend.emplace_back(&kContactMode, contacts);
  }

  // ---- annotations --------------------------------------------------------------------
  double ytop = 0.975;
  if (!s.title.empty()) {
    top->AddActor2D(text(s.title, 0.03, ytop, static_cast<int>(font * 1.3), true, kText));
    ytop -= 1.3 * 1.35 * font / H;
  }
  auto time = rq.time ? rq.time : cloud.time;
  auto step = rq.step ? rq.step : cloud.step;
  if (rq.mesh && !time) time = rq.mesh->time;
  if (rq.mesh && !step) step = rq.mesh->step;
  std::string when;
  if (time) when = "t = " + format_time(*time);
  if (step) when += (when.empty() ? "" : ",   ") + ("step " + thousands(*step));
  if (!when.empty()) top->AddActor2D(text(when, 0.03, ytop, font, false, kText));

  if (coloured && categorical) {
    // Legend: a swatch and the name of each category present, top right.
    std::vector<bool> present(s.categories.size(), false);
    for (double v : values) {
      const long k = std::lround(v);
      if (k >= 0 && static_cast<std::size_t>(k) < present.size()) present[static_cast<std::size_t>(k)] = true;
    }
    double y = 0.88;
    top->AddActor2D(text(s.field_label.empty() ? s.field : s.field_label, side, y, font, true, kText,
                         VTK_TEXT_LEFT, VTK_TEXT_CENTERED));
    // the upper category first, as layers stack
    for (std::size_t k = present.size(); k-- > 0;) {
      if (!present[k]) continue;
      y -= 1.6 * font / H;
      double rgba[4];
      lut->GetTableValue(static_cast<vtkIdType>(k), rgba);
      top->AddActor2D(legend_line(side, side + 0.035, y, Rgb{rgba[0], rgba[1], rgba[2]}, 0.9 * font));
      top->AddActor2D(text(s.categories[k], side + 0.045, y, static_cast<int>(font * 0.8), false, kText,
                           VTK_TEXT_LEFT, VTK_TEXT_CENTERED));
    }
  } else if (coloured) {
    vtkNew<vtkScalarBarActor> bar;
    bar->SetLookupTable(lut);
    std::string label = s.field_label.empty() ? s.field : s.field_label;
    if (!s.unit.empty()) label += " [" + s.unit + "]";
    bar->SetTitle(label.c_str());
    bar->SetNumberOfLabels(s.colormap == Colormap::CoolWarm ? 7 : 6);  // 7: zero gets a label
    bar->SetLabelFormat("%-#.3g");
    bar->SetOrientationToVertical();
    bar->UnconstrainedFontSizeOn();
    bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedDisplay();
    bar->GetPositionCoordinate()->SetValue(side, rq.bonds ? 0.30 : 0.10);
    bar->SetWidth(0.15);
    bar->SetHeight(rq.bonds ? 0.56 : 0.76);
    bar->SetBarRatio(0.28);
    bar->SetTextPad(6);
    bar->SetVerticalTitleSeparation(font / 2);
    bar->SetMaximumWidthInPixels(W);
    for (auto* p : {bar->GetTitleTextProperty(), bar->GetLabelTextProperty()}) {
      p->SetFontFamilyToArial();
      p->SetColor(kText[0], kText[1], kText[2]);
      p->ShadowOff();
      p->ItalicOff();
    }
    bar->GetTitleTextProperty()->SetFontSize(font);
    bar->GetTitleTextProperty()->BoldOn();
    bar->GetLabelTextProperty()->SetFontSize(static_cast<int>(font * 0.85));
    bar->GetLabelTextProperty()->BoldOff();
    bar->GetTitleTextProperty()->SetJustificationToLeft();
    top->AddActor2D(bar);
  }
  if (!legend.empty()) {
    // Legend: line sample + "tensile crack (n)" per mode, bottom right.
    double y = 0.05 + (legend.size() - 1) * 1.6 * font / H;
    top->AddActor2D(text(s.show_contacts ? "bonds and contacts" : "broken bonds", side, y + 1.7 * font / H,
                         font, true, kText, VTK_TEXT_LEFT, VTK_TEXT_CENTERED));
    for (const auto& [mode, count] : legend) {
      top->AddActor2D(legend_line(side, side + 0.035, y, mode->colour, std::max(3.0, line_w + 1)));
      top->AddActor2D(text(fmt::format("{} ({})", mode->label, thousands(static_cast<std::int64_t>(count))),
                           side + 0.045, y, static_cast<int>(font * 0.8), false, kText, VTK_TEXT_LEFT,
                           VTK_TEXT_CENTERED));
      y -= 1.6 * font / H;
    }
  }

  win->Render();
  write_png(win, rq.png);
}

std::vector<fs::path> render_frames(const FrameFiles& files, const fs::path& out_dir,
                                    const RenderStyle& style, const std::function<bool()>& stop) {
  const std::size_t frames =
      std::max({files.particles.size(), files.bonds.size(), files.meshes.size(), files.walls.size()});
  for (const auto* list : {&files.particles, &files.bonds, &files.meshes, &files.walls})
    STRATA_CHECK(
        list->empty() || list->size() == frames, Input,
        "render: {} particle, {} bond, {} mesh and {} wall frames (each list must be empty or as long "
        "as the longest)",
        files.particles.size(), files.bonds.size(), files.meshes.size(), files.walls.size());
  auto at = [](const std::vector<fs::path>& list, std::size_t k) {
    return list.empty() ? fs::path() : list[k];
  };
  RenderStyle s = style;
  // Every frame is read once before the first is drawn: a damaged file stops the drawing
  // before it starts, and the colour range (unless the style fixes one) is the whole
  // series', so a colour means the same in every frame.
  const bool find_range = !s.range && !s.field.empty();
  std::array<double, 2> r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (std::size_t k = 0; k < frames; ++k) {
    if (const auto f = at(files.particles, k); !f.empty()) {
      const VtpContents v = read_vtp(f);
      if (find_range) r = merge(r, finite_range(field_values(v.points, s)));
    }
    if (const auto f = at(files.bonds, k); !f.empty()) read_vtp(f);
    if (const auto f = at(files.meshes, k); !f.empty()) {
      const MeshFrame m = read_vtu(f);
      if (find_range) r = merge(r, finite_range(field_values(m, s).values));
    }
    if (const auto f = at(files.walls, k); !f.empty()) read_vtu(f);
  }
  if (find_range && r[0] <= r[1]) s.range = r;
  std::vector<fs::path> out;
  for (std::size_t k = 0; k < frames; ++k) {
    if (stop && stop()) {
      log::info("drawing stopped on request after {} of {} frames", k, frames);
      break;
    }
    RenderRequest rq;
    VtpContents particles, bonds;
    MeshFrame mesh, walls;
    if (const auto f = at(files.particles, k); !f.empty()) {
      particles = read_vtp(f);
      STRATA_CHECK(particles.points.size() > 0, Input, "render: {} holds no particles: nothing to draw",
                   f.string());
      rq.particles = &particles.points;
    }
    if (const auto f = at(files.bonds, k); !f.empty()) {
      bonds = read_vtp(f);
      rq.bonds = &bonds.lines;
      rq.bond_points = &bonds.points;
    }
    if (const auto f = at(files.meshes, k); !f.empty()) {
      mesh = read_vtu(f);
      rq.mesh = &mesh;
    }
    if (const auto f = at(files.walls, k); !f.empty()) {
      walls = read_vtu(f);
      rq.walls = &walls;
    }
    STRATA_CHECK(rq.particles || rq.mesh, Input, "render: frame {} has neither particles nor a mesh", k);
    rq.png = out_dir / fmt::format("frame_{:06d}.png", k);
    rq.style = s;
    render_frame(rq);
    out.push_back(rq.png);
    log::debug("rendered {}", rq.png.string());
  }
  return out;
}

std::vector<fs::path> render_series(const SeriesPaths& series, const fs::path& out_dir,
                                    const RenderStyle& style, const std::function<bool()>& stop) {
  const fs::path& pvd = series.main;
  const bool mesh_only = is_mesh_series(pvd);
  STRATA_CHECK(!(mesh_only && !series.mesh.empty()), Input,
               "render: {} lists FEM frames (.vtu), and a mesh series {} was given too", pvd.string(),
               series.mesh.string());
  for (const fs::path* other : {&series.mesh, &series.walls})
    STRATA_CHECK(other->empty() || is_mesh_series(*other), Input,
                 "render: the {} series {} does not list .vtu frames",
                 other == &series.mesh ? "mesh" : "wall", other->string());
  const auto entries = read_pvd(pvd);
  STRATA_CHECK(!entries.empty(), Input, "render: {} lists no frames: nothing to draw", pvd.string());
  auto path_of = [](const fs::path& list, const PvdEntry& e) {
    return e.file.is_absolute() ? e.file : list.parent_path() / e.file;
  };
  FrameFiles files;
  for (const auto& e : entries) (mesh_only ? files.meshes : files.particles).push_back(path_of(pvd, e));
  // The frames of another series with the same times as the main frames (relative
  // tolerance 1e-9); an empty path where it has none.
  auto match = [&](const fs::path& other, std::vector<fs::path>& out) {
    if (other.empty()) return;
    const auto list = read_pvd(other);
    for (const auto& e : entries) {
      fs::path found;
      for (const auto& b : list)
        if (b.time == e.time || std::abs(b.time - e.time) <=
                                    1e-9 * std::max(1e-300, std::max(std::abs(b.time), std::abs(e.time)))) {
          found = path_of(other, b);
          break;
        }
      out.push_back(found);
    }
  };
  match(series.bonds, files.bonds);
  match(series.mesh, files.meshes);
  match(series.walls, files.walls);
  log::info("rendering {} frames of {} to {}", entries.size(), pvd.string(), out_dir.string());
  return render_frames(files, out_dir, style, stop);
}

namespace {

// ffmpeg on PATH, or "".
std::string find_ffmpeg() {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(ss, dir, ':');) {
    const std::string full = (dir.empty() ? std::string(".") : dir) + "/ffmpeg";
    struct stat st {};
    if (::stat(full.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(full.c_str(), X_OK) == 0)
      return full;
  }
  return {};
}

// H.264 through ffmpeg; false (logged) when ffmpeg fails.
bool ffmpeg_movie(const std::string& ffmpeg, const fs::path& png_dir, const fs::path& mp4, int fps) {
  const auto tmp = fs::path(mp4.string() + ".tmp");
  const std::string pattern = (png_dir / "frame_%06d.png").string(), rate = std::to_string(fps);
  std::vector<std::string> args = {ffmpeg,
                                   "-nostdin",
                                   "-y",
                                   "-loglevel",
                                   "error",
                                   "-framerate",
                                   rate,
                                   "-i",
                                   pattern,
                                   "-vf",
                                   "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                   "-c:v",
                                   "libx264",
                                   "-pix_fmt",
                                   "yuv420p",
                                   "-movflags",
                                   "+faststart",
                                   "-f",
                                   "mp4",
                                   tmp.string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  STRATA_CHECK(pid >= 0, IO, "fork for ffmpeg failed");
  if (pid == 0) {
    const int devnull = ::open("/dev/null", O_RDWR);
    if (devnull >= 0) ::dup2(devnull, 0);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(tmp)) {
    std::error_code ec;
    fs::remove(tmp, ec);
    log::warn("ffmpeg failed (status {}); no movie {}, the PNG frames are kept in {}", status, mp4.string(),
              png_dir.string());
    return false;
  }
  detail::commit(tmp, mp4);
  return true;
}

// Ogg Theora through VTK, frame by frame: the frames are read one at a time, so a long
// series costs the memory of one picture. Their sizes are checked from the PNG headers
// before anything is written.
void theora_movie(const fs::path& png_dir, const fs::path& ogv, int fps) {
  std::vector<fs::path> pngs;
  for (int k = 0;; ++k) {
    fs::path png = png_dir / fmt::format("frame_{:06d}.png", k);
    if (!fs::exists(png)) break;
    pngs.push_back(std::move(png));
  }
  vtkNew<vtkPNGReader> reader;
  auto size_of = [&](const fs::path& png) {
    reader->SetFileName(png.c_str());
    reader->UpdateInformation();
    int ext[6];
    reader->GetDataExtent(ext);
    return std::array<int, 2>{ext[1] - ext[0] + 1, ext[3] - ext[2] + 1};
  };
  const std::array<int, 2> size = size_of(pngs.front());
  for (const fs::path& png : pngs) {
    const std::array<int, 2> s = size_of(png);
    STRATA_CHECK(s == size, IO,
                 "make_movie: {} is {} x {} pixels, the first frame {} x {}: a movie's frames share one size",
                 png.string(), s[0], s[1], size[0], size[1]);
  }
  const auto tmp = fs::path(ogv.string() + ".tmp");
  try {
    vtkNew<vtkOggTheoraWriter> writer;
    writer->SetInputConnection(reader->GetOutputPort());
    writer->SetFileName(tmp.c_str());
    writer->SetRate(fps);
    writer->SetQuality(2);      // the highest of VTK's three: crack lines stay sharp
    writer->SetSubsampling(1);  // 4:2:0, what every Theora player decodes (and a third faster)
    reader->SetFileName(pngs.front().c_str());
    writer->Start();
    for (const fs::path& png : pngs) {
      reader->SetFileName(png.c_str());
      writer->Write();
      STRATA_CHECK(writer->GetError() == 0, IO, "make_movie: the Theora encoder failed on {}", png.string());
    }
    writer->End();
    STRATA_CHECK(fs::exists(tmp), IO, "make_movie: the Theora encoder wrote no {}", tmp.string());
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  detail::commit(tmp, ogv);
}

}  // namespace

fs::path make_movie(const fs::path& png_dir, const fs::path& stem, int fps) {
  STRATA_CHECK(fs::exists(png_dir / "frame_000000.png"), IO, "make_movie: no {}",
               (png_dir / "frame_000000.png").string());
  STRATA_CHECK(fps >= 1 && fps <= 1000, Input, "make_movie: {} frames per second must be in [1, 1000]", fps);
  detail::make_parent(stem);
  const std::string ffmpeg = find_ffmpeg();
  fs::path movie = stem;
  if (!ffmpeg.empty()) {
    movie.replace_extension(".mp4");
    if (!ffmpeg_movie(ffmpeg, png_dir, movie, fps)) return {};
  } else {
    movie.replace_extension(".ogv");
    theora_movie(png_dir, movie, fps);
  }
  log::info("wrote movie {}", movie.string());
  return movie;
}

#else  // !STRATA_WITH_RENDER

void render_frame(const RenderRequest&) { fail_missing_feature("STRATA_WITH_RENDER", "rendering pictures"); }
std::vector<fs::path> render_frames(const FrameFiles&, const fs::path&, const RenderStyle&,
                                    const std::function<bool()>&) {
  fail_missing_feature("STRATA_WITH_RENDER", "rendering pictures");
}
std::vector<fs::path> render_series(const SeriesPaths&, const fs::path&, const RenderStyle&,
                                    const std::function<bool()>&) {
  fail_missing_feature("STRATA_WITH_RENDER", "rendering pictures");
}
fs::path make_movie(const fs::path&, const fs::path&, int) {
  fail_missing_feature("STRATA_WITH_RENDER", "rendering pictures");
}

#endif

}  // namespace strata::io
