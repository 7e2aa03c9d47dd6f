// The building blocks of a picture (render_parts.hpp).
#include "render_parts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "atomic_file.hpp"
#include "strata/core/error.hpp"
#include "strata/core/log.hpp"
#include "strata/io/display.hpp"
#include "strata/io/vtk.hpp"
#include "vtk_grid.hpp"

#if STRATA_WITH_RENDER
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

#if STRATA_WITH_RENDER
namespace strata::io::render_parts {

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
                                   const Rgb& colour, int justify, int vjustify) {
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

}  // namespace strata::io::render_parts
#endif
