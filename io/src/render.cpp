#include "strata/io/render.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "atomic_file.hpp"
#include "render_parts.hpp"
#include "strata/config.hpp"
#include "strata/core/error.hpp"
#include "strata/core/log.hpp"
#include "strata/io/display.hpp"
#include "strata/io/series.hpp"
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
using namespace render_parts;

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

#endif

}  // namespace strata::io
