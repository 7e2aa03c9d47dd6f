// Tests of the io library's pictures: headless display, rendered frames and plots, read back
// with vtkPNGReader and checked pixel by pixel.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/io/display.hpp>
#include <strata/io/plot.hpp>
#include <strata/io/render.hpp>
#include <strata/io/series.hpp>

#include <array>
#include <cstdlib>
#include <set>

#include "io_test_util.hpp"

#if STRATA_WITH_RENDER
#include <vtkImageData.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>
#endif

namespace fs = std::filesystem;
using namespace strata;
using namespace strata::io;
using namespace strata::io::test;

#if defined(__SANITIZE_ADDRESS__)
// Mesa's llvmpipe (the GL of Xvfb) leaks 112 bytes per process from a driver it unloads at
// exit, so the leak cannot even be attributed; leak checking stays on in test_io, which
// covers all the io code that does not draw. Address errors are still caught here.
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }
#endif

// ---- pictures ---------------------------------------------------------------------------------
#if STRATA_WITH_RENDER
namespace {
struct Image {
  int width = 0, height = 0;
  std::vector<std::array<unsigned char, 3>> pixels;
};

Image read_png(const fs::path& file) {
  vtkNew<vtkPNGReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  Image img;
  int* d = r->GetOutput()->GetDimensions();
  img.width = d[0];
  img.height = d[1];
  auto* a = r->GetOutput()->GetPointData()->GetScalars();
  const int nc = a->GetNumberOfComponents();
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    img.pixels.push_back({static_cast<unsigned char>(a->GetComponent(i, 0)),
                          static_cast<unsigned char>(a->GetComponent(i, std::min(1, nc - 1))),
                          static_cast<unsigned char>(a->GetComponent(i, std::min(2, nc - 1)))});
  return img;
}

std::size_t count(const Image& img, bool (*pred)(int r, int g, int b)) {
  std::size_t n = 0;
  for (const auto& p : img.pixels) n += pred(p[0], p[1], p[2]);
  return n;
}

std::size_t distinct_colours(const Image& img) {
  std::set<int> c;
  for (const auto& p : img.pixels) c.insert(p[0] << 16 | p[1] << 8 | p[2]);
  return c.size();
}

/// An 8 x 8 x 8 cube of spheres (radius 0.5 on a unit grid) with "stress" = x - 3.5.
PointCloud sphere_cube() {
  PointCloud c;
  c.dim = 3;
  Array radius{std::string(kRadiusArray), 1, {}};
  Array stress{"stress", 1, {}};
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        c.xyz.insert(c.xyz.end(), {1.0 * i, 1.0 * j, 1.0 * k});
        radius.values.push_back(0.5);
        stress.values.push_back(i - 3.5);
      }
  c.point_data = {radius, stress};
  return c;
}

/// A 400 x 300 picture of `cloud` (sphere_cube) shaded by "stress" in the cool-warm colour
/// map, written to `png`.
RenderRequest stress_picture(const PointCloud& cloud, const fs::path& png) {
  RenderRequest rq;
  rq.particles = &cloud;
  rq.png = png;
  rq.style.width = 400;
  rq.style.height = 300;
  rq.style.field = "stress";
  rq.style.colormap = Colormap::CoolWarm;
  return rq;
}
}  // namespace

TEST(IoDisplay, EnsureDisplayGivesAUsableDisplay) {
  const std::string d = ensure_display();
  EXPECT_FALSE(d.empty());
  EXPECT_TRUE(display_usable());
  EXPECT_EQ(ensure_display(), d);  // idempotent
}

TEST_F(IoTest, RenderFrame2DShowsColouredParticlesAndCracks) {
  const auto p = hex_patch(30, 30);
  RenderRequest rq;
  rq.particles = &p.cloud;
  rq.bonds = &p.bonds;
  rq.time = 1.23e-3;
  rq.step = 61500;
  rq.png = dir_ / "frame.png";
  rq.style.width = 640;
  rq.style.height = 480;
  rq.style.title = "test patch";
  rq.style.field = "displacement";
  rq.style.field_label = "displacement";
  rq.style.unit = "\u00b5m";
  rq.style.field_scale = 1e6;
  render_frame(rq);
  ASSERT_TRUE(fs::exists(rq.png));
  if (const char* keep = std::getenv("STRATA_TEST_KEEP_PNG"))
    fs::copy_file(rq.png, keep, fs::copy_options::overwrite_existing);
  const Image img = read_png(rq.png);
  EXPECT_EQ(img.width, 640);
  EXPECT_EQ(img.height, 480);
  EXPECT_GT(distinct_colours(img), 50u);
  const auto white = count(img, [](int r, int g, int b) { return r > 250 && g > 250 && b > 250; });
  EXPECT_GT(white, img.pixels.size() / 10);  // background
  EXPECT_LT(white, img.pixels.size() * 9 / 10);
  // Viridis particles: purple-blue at low and yellow-green at high displacement.
  EXPECT_GT(count(img, [](int r, int g, int b) { return b > 100 && r < 90 && g < 60; }), 200u);
  EXPECT_GT(count(img, [](int r, int g, int b) { return g > 180 && r > 150 && b < 90; }), 200u);
  // Tensile cracks in red, shear cracks in blue.
  EXPECT_GT(count(img, [](int r, int g, int b) { return r > 180 && g < 60 && b < 60; }), 100u);
  EXPECT_GT(count(img, [](int r, int g, int b) { return b > 200 && r < 70 && g > 80 && g < 130; }), 50u);
}

TEST_F(IoTest, Pictures2DFromMicrometresToHundredsOfKilometres) {
  // The same 30 x 30 patch of disks at radius 0.1 µm (a 6 µm model) up to 5 km (a 300 km
  // model, placed at map coordinates of 500 km east, 4,000 km north): the camera's depth
  // range must follow the model, or the picture is blank.
  for (const auto& [r, x0, y0] :
       {std::array<double, 3>{1e-7, 0, 0}, {0.5e-3, 0, 0}, {50, 0, 0}, {5e3, 5e5, 4e6}}) {
    auto p = hex_patch(30, 30, r);
    for (std::size_t i = 0; i < p.cloud.xyz.size(); i += 3) {
      p.cloud.xyz[i] += x0;
      p.cloud.xyz[i + 1] += y0;
    }
    RenderRequest rq;
    rq.particles = &p.cloud;
    rq.png = dir_ / "scale.png";
    rq.style.width = 400;
    rq.style.height = 300;
    rq.style.field = "displacement";
    render_frame(rq);
    const Image img = read_png(rq.png);
    // the disks cover about half the model area (~60 % of the window), in colour
    const auto drawn = count(img, [](int r8, int g8, int b8) { return !(r8 > 240 && g8 > 240 && b8 > 240); });
    EXPECT_GT(drawn, img.pixels.size() / 4) << "radius " << r << " m: the picture is (nearly) blank";
    EXPECT_GT(distinct_colours(img), 30u) << "radius " << r << " m";
  }
}

TEST_F(IoTest, RenderFrame3DWithClipPlane) {
  const PointCloud c = sphere_cube();
  RenderRequest rq = stress_picture(c, dir_ / "cube.png");
  rq.style.unit = "MPa";
  rq.style.clip_plane = std::array<double, 6>{3.5, 3.5, 3.5, 0, 0, 1};
  render_frame(rq);
  const Image img = read_png(rq.png);
  EXPECT_EQ(img.width, 400);
  EXPECT_EQ(img.height, 300);
  EXPECT_GT(distinct_colours(img), 50u);
  EXPECT_GT(count(img, [](int r, int g, int b) { return b > r + 60; }), 300u);  // cool side
  EXPECT_GT(count(img, [](int r, int g, int b) { return r > b + 60; }), 300u);  // warm side
}

namespace {
/// Pixels in the model area (the left 75 % of the picture: the colour bar and legend sit
/// right of 0.80) that satisfy `pred`.
std::size_t count_in_model_area(const Image& img, bool (*pred)(int r, int g, int b)) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    const auto x = static_cast<int>(i % static_cast<std::size_t>(img.width));
    if (x < img.width * 3 / 4) n += pred(img.pixels[i][0], img.pixels[i][1], img.pixels[i][2]);
  }
  return n;
}
bool warm(int r, int, int b) { return r > b + 60; }
bool cool(int r, int, int b) { return b > r + 60; }
bool not_background(int r, int g, int b) { return r < 245 || g < 245 || b < 245; }
}  // namespace

// The clip plane x > 3.5 (normal +x) removes exactly the spheres with stress > 0, which the
// fixed diverging range draws warm: the unclipped picture shows many warm pixels, the
// clipped one none in the model area, while cool (x < 3.5) spheres stay in both.
TEST_F(IoTest, ClipPlaneRemovesTheNormalSide) {
  const PointCloud c = sphere_cube();
  RenderRequest rq = stress_picture(c, dir_ / "whole.png");
  rq.style.range = std::array<double, 2>{-3.5, 3.5};
  rq.style.view_direction = {-1, -0.3, -0.5};  // from +x, so the warm side faces the camera
  render_frame(rq);
  rq.style.clip_plane = std::array<double, 6>{3.5, 3.5, 3.5, 1, 0, 0};
  rq.png = dir_ / "clipped.png";
  render_frame(rq);
  const Image whole = read_png(dir_ / "whole.png"), clipped = read_png(dir_ / "clipped.png");
  EXPECT_GT(count_in_model_area(whole, warm), 2000u);
  EXPECT_EQ(count_in_model_area(clipped, warm), 0u);
  EXPECT_GT(count_in_model_area(clipped, cool), 2000u);
  EXPECT_GT(count_in_model_area(clipped, not_background), 5000u);  // the camera is refitted, not empty
}

namespace {
/// An n x n x n block of spheres (radius 0.5 on a unit grid), in one colour; with `notch`,
/// the corner octant i, j, k >= n/2 (the corner nearest the default camera) is left out.
PointCloud sphere_block(int n, bool notch) {
  PointCloud c;
  c.dim = 3;
  Array radius{std::string(kRadiusArray), 1, {}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (notch && i >= n / 2 && j >= n / 2 && k >= n / 2) continue;
        c.xyz.insert(c.xyz.end(), {1.0 * i, 1.0 * j, 1.0 * k});
        radius.values.push_back(0.5);
      }
  c.point_data = {radius};
  return c;
}

/// Bonds of sphere_block(n, false) to the +x, +y and +z neighbours, all intact except the
/// x bonds between i = n/2 - 1 and n/2 with 2 <= j, k <= n - 4: a square of tensile cracks
/// across the middle of the block, three or more spheres inside every face the default
/// camera sees.
LineSet interior_crack_bonds(int n) {
  LineSet b;
  Array state{std::string(kBondStateArray), 1, {}, ArrayType::Int32};
  auto id = [n](int i, int j, int k) { return static_cast<std::int64_t>((k * n + j) * n + i); };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int axis = 0; axis < 3; ++axis) {
          const int q[3] = {i + (axis == 0), j + (axis == 1), k + (axis == 2)};
          if (q[0] >= n || q[1] >= n || q[2] >= n) continue;
          b.ends.insert(b.ends.end(), {id(i, j, k), id(q[0], q[1], q[2])});
          const bool crack = axis == 0 && i == n / 2 - 1 && j >= 2 && j <= n - 4 && k >= 2 && k <= n - 4;
          state.values.push_back(crack ? static_cast<double>(BondState::BrokenTension) : 0.0);
        }
  b.cell_data = {state};
  return b;
}

/// Mean brightness (0..255) of each square tile of `tile` pixels, row by row.
std::vector<double> tile_brightness(const Image& img, int tile) {
  const int tx = img.width / tile, ty = img.height / tile;
  std::vector<double> out(static_cast<std::size_t>(tx * ty), 0.0);
  for (int y = 0; y < ty * tile; ++y)
    for (int x = 0; x < tx * tile; ++x) {
      const auto& p = img.pixels[static_cast<std::size_t>(y * img.width + x)];
      out[static_cast<std::size_t>((y / tile) * tx + x / tile)] += (p[0] + p[1] + p[2]) / 3.0;
    }
  for (auto& v : out) v /= tile * tile;
  return out;
}

bool crack_red(int r, int g, int b) { return r > 160 && g < 80 && b < 80; }
}  // namespace

// A block with its corner octant removed, seen from the default direction (the missing
// corner is the one nearest the camera, so the outline is the same as the whole block's):
// the faces inside the notch face other ways than the block's faces seen in the same place,
// so they must be shaded differently, and many tiles of the picture must differ clearly
// in brightness from the whole block's picture.
TEST_F(IoTest, MissingCornerOfA3DBlockIsVisible) {
  const PointCloud whole = sphere_block(8, false), notched = sphere_block(8, true);
  RenderRequest rq;
  rq.style.width = 400;
  rq.style.height = 300;
  rq.particles = &whole;
  rq.png = dir_ / "block_whole.png";
  render_frame(rq);
  rq.particles = &notched;
  rq.png = dir_ / "block_notched.png";
  render_frame(rq);
  const auto a = tile_brightness(read_png(dir_ / "block_whole.png"), 20),
             b = tile_brightness(read_png(dir_ / "block_notched.png"), 20);
  ASSERT_EQ(a.size(), b.size());
  std::size_t differ = 0;
  for (std::size_t t = 0; t < a.size(); ++t) differ += std::abs(a[t] - b[t]) > 25;
  EXPECT_GE(differ, 15u) << "of " << a.size() << " tiles";
}

// Broken bonds deep inside a block cannot be seen from outside: no crack colour is drawn
// over the block. A clip plane through the cracks opens the block and shows them.
TEST_F(IoTest, HiddenCracksIn3DAreNotDrawnUntilAClipPlaneOpensThem) {
  const int n = 10;
  const PointCloud block = sphere_block(n, false);
  const LineSet bonds = interior_crack_bonds(n);
  RenderRequest rq;
  rq.particles = &block;
  rq.bonds = &bonds;
  rq.style.width = 400;
  rq.style.height = 300;
  rq.png = dir_ / "cracks_hidden.png";
  render_frame(rq);
  rq.style.clip_plane = std::array<double, 6>{n / 2 - 0.4, 0, 0, 1, 0, 0};  // cuts the cracked bonds
  rq.png = dir_ / "cracks_cut.png";
  render_frame(rq);
  const auto hidden = count_in_model_area(read_png(dir_ / "cracks_hidden.png"), crack_red);
  const auto cut = count_in_model_area(read_png(dir_ / "cracks_cut.png"), crack_red);
  EXPECT_EQ(hidden, 0u);
  EXPECT_GT(cut, 1000u);
}

namespace {
/// The walls' colour (dark slate, 0.20 0.24 0.32 of full scale), within 12 per channel.
bool wall_slate(int r, int g, int b) {
  return std::abs(r - 51) < 12 && std::abs(g - 61) < 12 && std::abs(b - 82) < 12;
}

/// A wall frame of one line (2D) from (x0, y) to (x1, y).
MeshFrame wall_line(double x0, double x1, double y) {
  MeshFrame w;
  w.dim = 2;
  w.xyz = {x0, y, 0, x1, y, 0};
  w.add_cell(CellType::Line, {0, 1});
  return w;
}
}  // namespace

// A 2D wall is a dark line where it is, above the disks, taken into the picture even when it
// stands well away from them (20 mm above a patch 7 mm high).
TEST_F(IoTest, WallsAreDrawnAsLinesIn2D) {
  const auto p = hex_patch(20, 8);  // x from 0 to 20 mm, y from 0 to about 6 mm
  const MeshFrame wall = wall_line(-1e-3, 21e-3, 26e-3);
  RenderRequest rq;
  rq.particles = &p.cloud;
  rq.style.width = 400;
  rq.style.height = 300;
  rq.png = dir_ / "no_wall.png";
  render_frame(rq);
  rq.walls = &wall;
  rq.png = dir_ / "wall.png";
  render_frame(rq);
  EXPECT_EQ(count(read_png(dir_ / "no_wall.png"), wall_slate), 0u);
  const Image img = read_png(rq.png);
  std::size_t wall_pixels = 0;
  double wall_row = 0;
  int top_particle_row = -1, left = img.width, right = -1;
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    const auto& c = img.pixels[i];
    const int x = static_cast<int>(i % static_cast<std::size_t>(img.width));
    const int y = static_cast<int>(i / static_cast<std::size_t>(img.width));  // 0 at the bottom
    if (wall_slate(c[0], c[1], c[2])) {
      ++wall_pixels;
      wall_row += y;
      left = std::min(left, x);
      right = std::max(right, x);
    } else if (std::abs(c[0] - 219) < 15 && std::abs(c[1] - 209) < 15 && std::abs(c[2] - 184) < 15) {
      top_particle_row = std::max(top_particle_row, y);  // the disks' sandstone beige
    }
  }
  ASSERT_GT(wall_pixels, 0u);
  wall_row /= static_cast<double>(wall_pixels);
  // Wider than the patch: the line runs 1 mm beyond it on both sides (22 of 20 mm).
  EXPECT_GT(right - left, img.width / 2);
  EXPECT_GE(wall_pixels, 2u * static_cast<std::size_t>(right - left));  // 3 pixels, their edges smoothed
  // 20 mm above the 6 mm patch: the gap is about three patch heights.
  EXPECT_GT(wall_row, top_particle_row + 40);
}

// A 3D wall in front of the model is a translucent plane with a dark outline: it changes the
// picture, yet the warm face behind it stays warm.
TEST_F(IoTest, WallsAreTranslucentPlanesIn3D) {
  const PointCloud c = sphere_cube();  // x from -0.5 to 7.5; the +x face is warm
  RenderRequest rq = stress_picture(c, dir_ / "no_wall.png");
  rq.style.range = std::array<double, 2>{-3.5, 3.5};
  rq.style.view_direction = {-1, -0.3, -0.5};  // from +x, so the warm side faces the camera
  render_frame(rq);
  // The plane x = 7.5 (normal -x, towards the particles) over the +x face, within the
  // model's bounds, so that the camera is the same in both pictures.
  MeshFrame wall;
  wall.dim = 3;
  wall.xyz = {7.5, -0.5, -0.5, 7.5, 7.5, -0.5, 7.5, 7.5, 7.5, 7.5, -0.5, 7.5};
  wall.add_cell(CellType::Triangle, {0, 1, 2});
  wall.add_cell(CellType::Triangle, {0, 2, 3});
  rq.walls = &wall;
  rq.png = dir_ / "wall.png";
  render_frame(rq);
  const Image plain = read_png(dir_ / "no_wall.png"), walled = read_png(rq.png);
  // Behind the plane the warm face is seen through it: its pixels are blended with the
  // plane's light slate (0.55 0.62 0.75) at 25 % opacity, within 6 per channel (8-bit
  // rounding and edge smoothing); the warm pixels not behind it are on the top face.
  std::size_t face = 0, seen_through = 0;
  for (std::size_t i = 0; i < plain.pixels.size(); ++i) {
    const auto& p = plain.pixels[i];
    if (!warm(p[0], p[1], p[2])) continue;
    ++face;
    const auto& w = walled.pixels[i];
    const double fill[3] = {0.55 * 255, 0.62 * 255, 0.75 * 255};
    bool blended = true;
    for (int k = 0; k < 3; ++k) blended = blended && std::abs(w[k] - (0.75 * p[k] + 0.25 * fill[k])) < 6;
    seen_through += blended;
  }
  EXPECT_GT(face, 2000u);
  EXPECT_GT(seen_through, face * 7 / 10)
      << "the face behind the wall must be seen through it";  // 79 % measured
  // Its outline in dark slate where the plain picture has none.
  std::size_t outline = 0;
  for (std::size_t i = 0; i < plain.pixels.size(); ++i) {
    const auto& p = plain.pixels[i];
    const auto& w = walled.pixels[i];
    outline += wall_slate(w[0], w[1], w[2]) && !wall_slate(p[0], p[1], p[2]);
  }
  EXPECT_GT(outline, 150u) << "the wall's outline";
}

TEST_F(IoTest, UpVectorAlongTheViewIsRefused) {
  const PointCloud c = sphere_cube();
  RenderRequest rq;
  rq.particles = &c;
  rq.png = dir_ / "x.png";
  rq.style.width = rq.style.height = 64;
  rq.style.view_direction = {0, 0, -2};
  rq.style.view_up = {0, 0, 1};
  EXPECT_THROW(render_frame(rq), Error);
  EXPECT_FALSE(fs::exists(rq.png));
}

// A tetrahedral box shaded by a cell field, whole and cut by a clip plane: the cut keeps
// the cool half (cell centroids x < 1.5) and shows it on the cut face.
TEST_F(IoTest, RenderMeshShadedByACellFieldWithClipPlane) {
  const MeshFrame m = tet_box(3);
  RenderRequest rq;
  rq.mesh = &m;
  rq.style.width = 400;
  rq.style.height = 300;
  rq.style.field = "cx";
  rq.style.colormap = Colormap::CoolWarm;
  rq.style.range = std::array<double, 2>{0.0, 3.0};  // white at 1.5
  rq.style.view_direction = {-1, -0.4, -0.5};
  rq.time = 0.5;
  rq.png = dir_ / "mesh.png";
  render_frame(rq);
  rq.style.clip_plane = std::array<double, 6>{1.5, 0, 0, 1, 0, 0};
  rq.png = dir_ / "mesh_clipped.png";
  render_frame(rq);
  if (const char* keep = std::getenv("STRATA_TEST_KEEP_PNG"))
    fs::copy_file(rq.png, keep, fs::copy_options::overwrite_existing);
  const Image whole = read_png(dir_ / "mesh.png"), clipped = read_png(dir_ / "mesh_clipped.png");
  EXPECT_GT(count_in_model_area(whole, warm), 2000u);
  EXPECT_GT(count_in_model_area(whole, cool), 500u);
  // Cells whose centroid lies beyond x = 1.5 are cut away; what is left has x <= 1.5, and
  // so cool or white colours (cut cells keep their cell value, at most 1.5 + 0.25).
  EXPECT_LT(count_in_model_area(clipped, warm), count_in_model_area(whole, warm) / 20);
  EXPECT_GT(count_in_model_area(clipped, cool), 2000u);
}

// A 2D coupled picture: the mesh shaded by a point field under particles coloured by the
// same field, one colour bar (viridis from purple at x = 0 to yellow at the right end).
TEST_F(IoTest, RenderMeshUnderParticlesIn2D) {
  MeshFrame m;
  m.dim = 2;
  Array x{"displacement", 1, {}};
  const int n = 10;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.xyz.insert(m.xyz.end(), {0.02 + 1e-3 * i, 1e-3 * j, 0.0});
      x.values.push_back(1e-6 * (20 + i));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::int64_t a = j * (n + 1) + i;
      m.add_cell(CellType::Triangle, {a, a + 1, a + n + 2});
      m.add_cell(CellType::Triangle, {a, a + n + 2, a + n + 1});
    }
  m.point_data = {x};
  m.time = 1e-3;
  auto p = hex_patch(20, 12);  // displacement 0 .. 19e-6 m along x; disks left of the mesh
  for (std::size_t i = 0; i < p.cloud.size(); ++i)
    p.cloud.find("displacement")->values[3 * i + 1] = 0;  // x component only, for a clean range
  RenderRequest rq;
  rq.particles = &p.cloud;
  rq.mesh = &m;
  rq.png = dir_ / "coupled.png";
  rq.style.width = 640;
  rq.style.height = 320;
  rq.style.field = "displacement";
  render_frame(rq);
  const Image img = read_png(rq.png);
  // Purple-blue (low) disks and yellow-green (high) mesh nodes: both ends of one range.
  EXPECT_GT(count_in_model_area(img, [](int r, int g, int b) { return b > 100 && r < 90 && g < 60; }), 200u);
  EXPECT_GT(count_in_model_area(img, [](int r, int g, int b) { return g > 180 && r > 150 && b < 90; }), 200u);
}

TEST_F(IoTest, RenderSeriesOfMeshFrames) {
  MeshFrame m = tet_box(2);
  Series fem(dir_ / "out", "fem");
  for (int k = 0; k < 2; ++k) {
    for (auto& v : m.point_data[0].values) v += 1;
    m.time = 0.1 * k;
    fem.add_mesh(0.1 * k, m);
  }
  RenderStyle style;
  style.width = 200;
  style.height = 150;
  style.field = "x";
  const auto pngs = render_series({fem.pvd_path(), {}, {}, {}}, dir_ / "png", style);
  ASSERT_EQ(pngs.size(), 2u);
  for (const auto& f : pngs) EXPECT_EQ(read_png(f).width, 200);
}

TEST_F(IoTest, ContactsAreDrawnOnlyWhenAsked) {
  auto p = hex_patch(12, 12);
  auto* state = p.bonds.find(kBondStateArray);
  for (auto& v : state->values) v = static_cast<double>(BondState::Contact);
  RenderRequest rq;
  rq.particles = &p.cloud;
  rq.bonds = &p.bonds;
  rq.style.width = 400;
  rq.style.height = 300;
  auto green = [](int r, int g, int b) { return g > r + 60 && g > b + 60; };
  rq.png = dir_ / "without.png";
  render_frame(rq);
  rq.style.show_contacts = true;
  rq.png = dir_ / "with.png";
  render_frame(rq);
  EXPECT_EQ(count_in_model_area(read_png(dir_ / "without.png"), green), 0u);
  EXPECT_GT(count_in_model_area(read_png(dir_ / "with.png"), green), 300u);
}

TEST_F(IoTest, RenderSeriesGivesOnePicturePerFrame) {
  auto p = hex_patch(10, 10);
  Series particles(dir_ / "out", "particles"), bonds(dir_ / "out", "bonds");
  for (int k = 0; k < 3; ++k) {
    for (auto& v : p.cloud.find("displacement")->values) v *= 1.5;
    p.cloud.time = 1e-4 * k;
    p.cloud.step = 5000 * k;
    particles.add_particles(1e-4 * k, p.cloud);
    bonds.add_lines(1e-4 * k, p.cloud, p.bonds);
  }
  RenderStyle style;
  style.width = 320;
  style.height = 240;
  style.field = "displacement";
  const auto pngs = render_series({particles.pvd_path(), bonds.pvd_path(), {}, {}}, dir_ / "png", style);
  ASSERT_EQ(pngs.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(pngs[k], dir_ / "png" / ("frame_00000" + std::to_string(k) + ".png"));
    EXPECT_EQ(read_png(pngs[k]).width, 320);
  }
}

namespace {

// The fields of an Ogg Theora stream that say what it holds: the picture size and frame
// rate from the identification header, and the frame count from the granule position of
// the last Ogg page (the Theora specification, sections 6.2 and A.2).
struct TheoraInfo {
  bool ok = false;
  int width = 0, height = 0;
  std::uint32_t rate_num = 0, rate_den = 0;
  std::int64_t frames = 0;
};

TheoraInfo theora_info(const std::string& b) {
  TheoraInfo t;
  const auto at = b.find("\x80theora");
  if (b.rfind("OggS", 0) != 0 || at == std::string::npos || at + 42 > b.size()) return t;
  auto u = [&](std::size_t i) { return static_cast<std::uint32_t>(static_cast<unsigned char>(b[at + i])); };
  const bool counts_from_one = u(7) > 3 || (u(7) == 3 && (u(8) > 2 || (u(8) == 2 && u(9) >= 1)));
  t.width = static_cast<int>(u(14) << 16 | u(15) << 8 | u(16));
  t.height = static_cast<int>(u(17) << 16 | u(18) << 8 | u(19));
  t.rate_num = u(22) << 24 | u(23) << 16 | u(24) << 8 | u(25);
  t.rate_den = u(26) << 24 | u(27) << 16 | u(28) << 8 | u(29);
  const int shift = static_cast<int>(((u(40) & 0x03) << 3) | (u(41) >> 5));
  const auto last = b.rfind("OggS");
  if (last == std::string::npos || last + 14 > b.size()) return t;
  std::uint64_t gp = 0;
  for (int k = 7; k >= 0; --k)
    gp = gp << 8 | static_cast<unsigned char>(b[last + 6 + static_cast<std::size_t>(k)]);
  const auto g = static_cast<std::int64_t>(gp);
  t.frames = (g >> shift) + (g & ((std::int64_t{1} << shift) - 1)) + (counts_from_one ? 0 : 1);
  t.ok = true;
  return t;
}

}  // namespace

TEST_F(IoTest, MakeMovieWritesTheoraWithoutFfmpegAndMp4WithIt) {
  auto p = hex_patch(4, 4);
  RenderRequest rq;
  rq.particles = &p.cloud;
  rq.style.width = 70;  // not a multiple of Theora's 16-pixel blocks
  rq.style.height = 50;
  for (int k = 0; k < 3; ++k) {
    rq.png = dir_ / "png" / fmt::format("frame_{:06d}.png", k);
    render_frame(rq);
  }
  const std::string old_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  fs::create_directories(dir_ / "bin");
  ::setenv("PATH", (dir_ / "bin").c_str(), 1);
  // no ffmpeg: VTK's Theora encoder, three frames of 70 x 50 at 12 per second
  const fs::path ogv = make_movie(dir_ / "png", dir_ / "movie", 12);
  EXPECT_EQ(ogv, dir_ / "movie.ogv");
  const TheoraInfo t = theora_info(slurp(dir_ / "movie.ogv"));
  ASSERT_TRUE(t.ok) << "not an Ogg Theora stream";
  EXPECT_EQ(t.width, 70);
  EXPECT_EQ(t.height, 50);
  EXPECT_EQ(double(t.rate_num) / t.rate_den, 12.0);
  EXPECT_EQ(t.frames, 3);
  EXPECT_FALSE(fs::exists(dir_ / "movie.ogv.tmp"));
  EXPECT_TRUE(fs::exists(rq.png));  // frames kept
  // frames of different sizes are refused, and nothing is left behind
  rq.style.width = 80;
  rq.png = dir_ / "odd" / "frame_000000.png";
  render_frame(rq);
  rq.style.width = 90;
  rq.png = dir_ / "odd" / "frame_000001.png";
  render_frame(rq);
  EXPECT_THROW(make_movie(dir_ / "odd", dir_ / "odd_movie"), strata::Error);
  EXPECT_FALSE(fs::exists(dir_ / "odd_movie.ogv"));
  EXPECT_FALSE(fs::exists(dir_ / "odd_movie.ogv.tmp"));
  // A stand-in ffmpeg that records its arguments and writes its last one.
  const auto fake = dir_ / "bin" / "ffmpeg";
  std::ofstream(fake) << "#!/bin/sh\necho \"$@\" > \"" << (dir_ / "args.txt").string()
                      << "\"\nfor a; do last=$a; done\necho movie > \"$last\"\n";
  fs::permissions(fake, fs::perms::owner_all);
  const fs::path mp4 = make_movie(dir_ / "png", dir_ / "movie");
  ::setenv("PATH", old_path.c_str(), 1);
  EXPECT_EQ(mp4, dir_ / "movie.mp4");
  EXPECT_TRUE(fs::exists(dir_ / "movie.mp4"));
  const std::string args = slurp(dir_ / "args.txt");
  EXPECT_NE(args.find("libx264"), std::string::npos) << args;
  EXPECT_NE(args.find("yuv420p"), std::string::npos) << args;
  EXPECT_NE(args.find("frame_%06d.png"), std::string::npos) << args;
}

TEST_F(IoTest, PlotXYWritesANonBlankPicture) {
  PlotRequest rq;
  rq.title = "Uniaxial compression";
  rq.x_label = "axial strain [-]";
  rq.y_label = "axial stress [MPa]";
  PlotSeries a{"run A", {}, {}}, b{"run B", {}, {}};
  for (int i = 0; i <= 100; ++i) {
    const double e = 4e-5 * i;
    a.x.push_back(e);
    a.y.push_back(92e3 * e * std::exp(-e / 2.8e-3));
    b.x.push_back(e);
    b.y.push_back(80e3 * e * std::exp(-e / 3.1e-3));
  }
  rq.series = {a, b};
  rq.png = dir_ / "curve.png";
  rq.width = 600;
  rq.height = 400;
  plot_xy(rq);
  if (const char* keep = std::getenv("STRATA_TEST_KEEP_PLOT"))
    fs::copy_file(rq.png, keep, fs::copy_options::overwrite_existing);
  Image img = read_png(rq.png);
  EXPECT_EQ(img.width, 600);
  EXPECT_EQ(img.height, 400);
  EXPECT_GT(distinct_colours(img), 10u);
  EXPECT_GT(count(img, [](int r, int g, int b) { return b > 150 && r < 80; }), 100u);  // blue curve
  EXPECT_GT(count(img, [](int r, int g, int b) { return r > 200 && g > 100 && g < 160 && b < 60; }),
            100u);  // orange

  // Log-log with a non-positive point: left out, still a picture.
  PlotRequest lg;
  lg.title = "error against run time";
  lg.x_label = "run time [s]";
  lg.y_label = "relative error [-]";
  lg.log_x = lg.log_y = true;
  lg.series = {{"eta sweep", {0.5, 1, 2, 4, 0}, {1e-2, 3e-3, 1e-3, 2e-4, 1}, true, true}};
  lg.png = dir_ / "err.png";
  lg.width = 400;
  lg.height = 300;
  plot_xy(lg);
  EXPECT_GT(distinct_colours(read_png(lg.png)), 10u);
}

#else
TEST(IoRender, WithoutRenderSupportFunctionsSayWhichOption) {
  EXPECT_THROW(ensure_display(), Error);
  EXPECT_THROW(plot_xy({}), Error);
}
#endif
