// Tests of the io library: VTK frames read back with VTK's readers, the .pvd index under
// interruption, CSV round trips, and headless pictures and plots checked pixel by pixel.
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/display.hpp>
#include <strata/io/frame.hpp>
#include <strata/io/plot.hpp>
#include <strata/io/render.hpp>
#include <strata/io/series.hpp>
#include <strata/io/vtk.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <unistd.h>

#if STRATA_WITH_VTK
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>
#endif
#if STRATA_WITH_RENDER
#include <vtkImageData.h>
#include <vtkPNGReader.h>
#include <vtkUnsignedCharArray.h>
#endif

namespace fs = std::filesystem;
using namespace strata;
using namespace strata::io;

namespace {

/// A fresh folder per test, removed afterwards.
class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("strata_test_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  fs::path dir_;
};

/// A 2D hexagonal patch of `cols` x `rows` disks of radius r, with displacement growing
/// to the right, ids, and bonds to the right and upper neighbours.
struct Patch {
  PointCloud cloud;
  LineSet bonds;
};

[[maybe_unused]] Patch hex_patch(int cols, int rows, double r = 0.5e-3) {
  Patch p;
  p.cloud.dim = 2;
  Array radius{std::string(kRadiusArray), 1, {}, ArrayType::Float64};
  Array disp{"displacement", 3, {}, ArrayType::Float32};
  Array id{"id", 1, {}, ArrayType::Int64};
  const double dy = r * std::sqrt(3.0);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const double x = 2 * r * i + (j % 2) * r, y = dy * j;
      p.cloud.xyz.insert(p.cloud.xyz.end(), {x, y, 0.0});
      radius.values.push_back(r);
      disp.values.insert(disp.values.end(), {1e-6 * i, -2e-7 * j, 0.0});
      id.values.push_back(j * cols + i);
    }
  p.cloud.point_data = {radius, disp, id};
  Array state{std::string(kBondStateArray), 1, {}, ArrayType::Int32};
  Array fn{"Fn", 1, {}, ArrayType::Float64};
  auto add = [&](int a, int b) {
    p.bonds.ends.insert(p.bonds.ends.end(), {a, b});
    const int n = static_cast<int>(p.bonds.size());
    // A diagonal band of tensile cracks, some shear cracks near the middle, a few closed.
    const int ia = a % cols, ja = a / cols;
    int s = 0;
    if (std::abs(ia - ja) <= 0) s = 1;
    if (std::abs(ia + ja - cols) <= 0) s = 2;
    if (s == 1 && ja % 5 == 0) s = 3;
    state.values.push_back(s);
    fn.values.push_back(100.0 * n);
  };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const int a = j * cols + i;
      if (i + 1 < cols) add(a, a + 1);
      if (j + 1 < rows) {
        const int up_left = (j % 2) ? a + cols : a + cols - 1;
        const int up_right = (j % 2) ? a + cols + 1 : a + cols;
        if (up_left >= (j + 1) * cols && up_left < (j + 2) * cols) add(a, up_left);
        if (up_right < (j + 2) * cols && ((j % 2) == 0 || i + 1 < cols)) add(a, up_right);
      }
    }
  p.bonds.cell_data = {state, fn};
  return p;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

// ---- VTK frames ---------------------------------------------------------------------------
#if STRATA_WITH_VTK

TEST_F(IoTest, ParticlesReadBackWithVtkReader) {
  auto p = hex_patch(6, 5);
  p.cloud.time = 1.25e-3;
  p.cloud.step = 62500;
  const auto file = dir_ / "particles.vtp";
  write_particles(file, p.cloud);
  ASSERT_TRUE(fs::exists(file));
  EXPECT_FALSE(fs::exists(dir_ / "particles.vtp.tmp"));

  vtkNew<vtkXMLPolyDataReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  vtkPolyData* pd = r->GetOutput();
  ASSERT_EQ(pd->GetNumberOfPoints(), 30);
  EXPECT_EQ(pd->GetNumberOfVerts(), 30);  // vertex cells: ParaView shows points directly
  EXPECT_EQ(pd->GetNumberOfLines(), 0);
  double x[3];
  pd->GetPoint(7, x);
  EXPECT_DOUBLE_EQ(x[0], p.cloud.xyz[21]);
  EXPECT_DOUBLE_EQ(x[1], p.cloud.xyz[22]);
  auto* radius = pd->GetPointData()->GetArray("radius");
  auto* disp = pd->GetPointData()->GetArray("displacement");
  auto* id = pd->GetPointData()->GetArray("id");
  ASSERT_TRUE(radius && disp && id);
  EXPECT_EQ(radius->GetDataType(), VTK_DOUBLE);
  EXPECT_EQ(disp->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(disp->GetNumberOfComponents(), 3);
  EXPECT_TRUE(id->GetDataType() == VTK_LONG_LONG || id->GetDataType() == VTK_LONG);
  EXPECT_DOUBLE_EQ(radius->GetComponent(11, 0), 0.5e-3);
  EXPECT_FLOAT_EQ(static_cast<float>(disp->GetComponent(13, 0)), static_cast<float>(1e-6 * 1));
  EXPECT_EQ(id->GetComponent(29, 0), 29);
  ASSERT_TRUE(pd->GetFieldData()->GetArray("TimeValue"));
  EXPECT_DOUBLE_EQ(pd->GetFieldData()->GetArray("TimeValue")->GetComponent(0, 0), 1.25e-3);
  EXPECT_EQ(pd->GetFieldData()->GetArray("step")->GetComponent(0, 0), 62500);

  // strata's own reader gives the same back, with types and metadata.
  const auto back = read_vtp(file);
  EXPECT_EQ(back.points.dim, 2);
  EXPECT_EQ(back.points.xyz, p.cloud.xyz);
  EXPECT_EQ(back.points.find("id")->type, ArrayType::Int64);
  EXPECT_EQ(back.points.find("radius")->values, p.cloud.find("radius")->values);
  EXPECT_EQ(back.points.time, p.cloud.time);
  EXPECT_EQ(back.points.step, p.cloud.step);
}

TEST_F(IoTest, FileIsAppendedRawZlibWith64BitHeaders) {
  const auto p = hex_patch(4, 4);
  write_particles(dir_ / "a.vtp", p.cloud);
  const std::string head = slurp(dir_ / "a.vtp").substr(0, 400);
  EXPECT_NE(head.find("header_type=\"UInt64\""), std::string::npos) << head;
  EXPECT_NE(head.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos) << head;
  const std::string all = slurp(dir_ / "a.vtp");
  EXPECT_NE(all.find("format=\"appended\""), std::string::npos);
  EXPECT_NE(all.find("encoding=\"raw\""), std::string::npos);
}

TEST_F(IoTest, ParticlesWithoutRadiusAreRefused) {
  PointCloud c;
  c.dim = 2;
  c.xyz = {0, 0, 0};
  EXPECT_THROW(write_particles(dir_ / "x.vtp", c), Error);
  c.point_data.push_back({std::string(kRadiusArray), 1, {1.0, 2.0}});  // 2 values for 1 point
  EXPECT_THROW(write_particles(dir_ / "x.vtp", c), Error);
  EXPECT_FALSE(fs::exists(dir_ / "x.vtp"));
}

TEST_F(IoTest, BondsReadBackAsLinesWithCellData) {
  const auto p = hex_patch(6, 5);
  // Only the broken bonds: the file keeps just the points they use.
  LineSet broken;
  Array state{std::string(kBondStateArray), 1, {}, ArrayType::Int32};
  Array fn{"Fn", 1, {}};
  std::set<std::int64_t> used;
  const auto* all_state = p.bonds.find(kBondStateArray);
  for (std::size_t b = 0; b < p.bonds.size(); ++b)
    if (all_state->at(b) != 0) {
      broken.ends.push_back(p.bonds.ends[2 * b]);
      broken.ends.push_back(p.bonds.ends[2 * b + 1]);
      used.insert(p.bonds.ends[2 * b]);
      used.insert(p.bonds.ends[2 * b + 1]);
      state.values.push_back(all_state->at(b));
      fn.values.push_back(p.bonds.find("Fn")->at(b));
    }
  broken.cell_data = {state, fn};
  ASSERT_GT(broken.size(), 3u);
  const auto file = dir_ / "bonds.vtp";
  write_lines(file, p.cloud, broken);

  vtkNew<vtkXMLPolyDataReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  vtkPolyData* pd = r->GetOutput();
  EXPECT_EQ(pd->GetNumberOfPoints(), static_cast<vtkIdType>(used.size()));
  ASSERT_EQ(pd->GetNumberOfLines(), static_cast<vtkIdType>(broken.size()));
  ASSERT_TRUE(pd->GetCellData()->GetArray("state"));
  ASSERT_TRUE(pd->GetCellData()->GetArray("Fn"));
  EXPECT_EQ(pd->GetCellData()->GetArray("state")->GetDataType(), VTK_INT);
  ASSERT_TRUE(pd->GetPointData()->GetArray("id"));

  // Each line joins the same two particles as before (compared through their ids and coordinates).
  const auto back = read_vtp(file);
  ASSERT_EQ(back.lines.size(), broken.size());
  const auto* ids = back.points.find("id");
  for (std::size_t b = 0; b < broken.size(); ++b) {
    for (int e = 0; e < 2; ++e) {
      const auto k = static_cast<std::size_t>(back.lines.ends[2 * b + e]);
      const auto orig = static_cast<std::size_t>(broken.ends[2 * b + e]);
      EXPECT_EQ(ids->at(k), static_cast<double>(orig));
      EXPECT_EQ(back.points.xyz[3 * k], p.cloud.xyz[3 * orig]);
    }
    EXPECT_EQ(back.lines.find("state")->at(b), state.at(b));
    EXPECT_EQ(back.lines.find("Fn")->at(b), fn.at(b));
  }
}

TEST_F(IoTest, LineEndOutOfRangeIsRefused) {
  auto p = hex_patch(3, 3);
  p.bonds.ends[5] = 9;  // 9 points: 0..8
  EXPECT_THROW(write_lines(dir_ / "b.vtp", p.cloud, p.bonds), Error);
}

// ---- series ---------------------------------------------------------------------------------

TEST_F(IoTest, PvdListsExactlyTheFramesWritten) {
  auto p = hex_patch(4, 3);
  Series particles(dir_, "particles"), bonds(dir_, "bonds");
  const double times[] = {0.0, 1e-4, 2.5e-4};
  for (double t : times) {
    p.cloud.time = t;
    particles.add_particles(t, p.cloud);
    bonds.add_lines(t, p.cloud, p.bonds);
  }
  const auto entries = read_pvd(dir_ / "particles.pvd");
  ASSERT_EQ(entries.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(entries[k].time, times[k]);
    EXPECT_EQ(entries[k].file, fs::path("particles_00000" + std::to_string(k) + ".vtp"));
    EXPECT_TRUE(fs::exists(dir_ / entries[k].file));
  }
  EXPECT_EQ(read_pvd(dir_ / "bonds.pvd").size(), 3u);
  EXPECT_FALSE(fs::exists(dir_ / "particles.pvd.tmp"));
  const std::string text = slurp(dir_ / "particles.pvd");
  EXPECT_NE(text.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("</VTKFile>"), std::string::npos);
  // Times survive the index with full precision.
  EXPECT_NE(text.find("timestep=\"0.00025\""), std::string::npos) << text;
}

TEST_F(IoTest, FrameNeverRenamedIsNotListed) {
  auto p = hex_patch(4, 3);
  {
    Series s(dir_, "particles");
    s.add_particles(0.0, p.cloud);
    s.add_particles(1.0, p.cloud);
    // A run killed while writing frame 2 leaves its temporary (and maybe a .pvd.tmp) behind:
    // construct exactly that state.
    std::ofstream(s.next_frame_path().string() + ".tmp") << "<?xml version=\"1.0\"?><VTKFile type=\"PolyD";
    std::ofstream(s.pvd_path().string() + ".tmp") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Coll";
    // A writer that fails half-way does not list its frame either.
    EXPECT_THROW(s.add_frame(2.0, [](const fs::path&) { throw std::runtime_error("killed"); }),
                 std::runtime_error);
    EXPECT_EQ(s.frames().size(), 2u);
  }
  auto entries = read_pvd(dir_ / "particles.pvd");
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[1].file, fs::path("particles_000001.vtp"));
  EXPECT_TRUE(fs::exists(dir_ / "particles_000002.vtp.tmp"));
  EXPECT_FALSE(fs::exists(dir_ / "particles_000002.vtp"));
  // Every listed frame is complete: VTK reads each one.
  for (const auto& e : entries) EXPECT_EQ(read_vtp(dir_ / e.file).points.size(), p.cloud.size());

  // A restarted run resumes the index, clears the stale temporaries and goes on at frame 2.
  Series resumed(dir_, "particles", Series::Mode::Resume);
  EXPECT_FALSE(fs::exists(dir_ / "particles_000002.vtp.tmp"));
  EXPECT_FALSE(fs::exists(dir_ / "particles.pvd.tmp"));
  EXPECT_EQ(resumed.frames().size(), 2u);
  EXPECT_EQ(resumed.next_frame_path(), dir_ / "particles_000002.vtp");
  resumed.add_particles(2.0, p.cloud);
  EXPECT_EQ(read_pvd(dir_ / "particles.pvd").size(), 3u);
}

TEST_F(IoTest, ResumeTruncatesFramesAfterTheCheckpoint) {
  auto p = hex_patch(3, 3);
  {
    Series s(dir_, "particles");
    for (int k = 0; k < 4; ++k) s.add_particles(0.5 * k, p.cloud);
  }
  Series s(dir_, "particles", Series::Mode::Resume);
  s.truncate_after(0.5);  // checkpoint at t = 0.5: frames at 1.0 and 1.5 are redone
  ASSERT_EQ(read_pvd(s.pvd_path()).size(), 2u);
  EXPECT_EQ(s.next_frame_path(), dir_ / "particles_000002.vtp");
  Series fresh(dir_, "particles");
  EXPECT_TRUE(fresh.frames().empty());
  fresh.add_particles(0, p.cloud);
  EXPECT_EQ(read_pvd(s.pvd_path()).size(), 1u);
}

#else  // !STRATA_WITH_VTK

TEST_F(IoTest, WithoutVtkWritersSayWhichOption) {
  PointCloud c;
  c.xyz = {0, 0, 0};
  c.point_data = {{std::string(kRadiusArray), 1, {1.0}}};
  try {
    write_particles(dir_ / "a.vtp", c);
    FAIL() << "write_particles did not throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Unsupported);
    EXPECT_NE(std::string(e.what()).find("STRATA_WITH_VTK"), std::string::npos) << e.what();
  }
  Series s(dir_, "particles");
  EXPECT_THROW(s.add_particles(0, c), Error);
  EXPECT_TRUE(s.frames().empty());
}

#endif  // STRATA_WITH_VTK

// ---- CSV ------------------------------------------------------------------------------------

TEST_F(IoTest, CsvRoundTripIsBitExact) {
  const std::vector<double> awkward = {
      0.1, 1.0 / 3.0, -2.5e17, 4.9e-324, 1e-300, 123456789.123456789, std::numeric_limits<double>::max(),
      -0.0};
  const auto file = dir_ / "probe.csv";
  {
    CsvWriter w(file, {"time", "stress", "strain"}, 2);
    for (std::size_t i = 0; i < awkward.size(); ++i)
      w.row({static_cast<double>(i) * 2e-8, awkward[i], -awkward[i]});
    // Flushed every 2 rows: all 8 are on disk before close.
    EXPECT_EQ(read_csv(file).rows(), 8u);
    w.row({1.0, std::numeric_limits<double>::infinity(), std::nan("")});
    EXPECT_THROW(w.row({1.0, 2.0}), Error);
  }
  const auto t = read_csv(file);
  ASSERT_EQ(t.names, (std::vector<std::string>{"time", "stress", "strain"}));
  ASSERT_EQ(t.rows(), 9u);
  for (std::size_t i = 0; i < awkward.size(); ++i) {
    EXPECT_EQ(t.column("stress")[i], awkward[i]);
    EXPECT_EQ(t.column("strain")[i], -awkward[i]);
    EXPECT_EQ(t.column("time")[i], static_cast<double>(i) * 2e-8);
  }
  EXPECT_TRUE(std::isinf(t.column("stress")[8]));
  EXPECT_TRUE(std::isnan(t.column("strain")[8]));
  EXPECT_THROW(t.column("energy"), Error);
  const std::string text = slurp(file);
  EXPECT_EQ(text.substr(0, text.find('\n')), "time,stress,strain");
}

TEST_F(IoTest, CsvBadInputIsReportedWithLine) {
  EXPECT_THROW(CsvWriter(dir_ / "x.csv", {"a,b"}), Error);
  std::ofstream(dir_ / "bad.csv") << "a,b\n1,2\n3,x\n";
  try {
    read_csv(dir_ / "bad.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3"), std::string::npos) << e.what();
  }
}

TEST(IoFormat, TimeWithSiPrefix) {
  EXPECT_EQ(format_time(1.234e-3), "1.23 ms");
  EXPECT_EQ(format_time(0.64), "640 ms");
  EXPECT_EQ(format_time(2.5), "2.50 s");
  EXPECT_EQ(format_time(4.56e-5), "45.6 \u00b5s");
  EXPECT_EQ(format_time(0.0), "0 s");
}

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

TEST_F(IoTest, RenderFrame3DWithClipPlane) {
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
  RenderRequest rq;
  rq.particles = &c;
  rq.png = dir_ / "cube.png";
  rq.style.width = 400;
  rq.style.height = 300;
  rq.style.field = "stress";
  rq.style.unit = "MPa";
  rq.style.colormap = Colormap::CoolWarm;
  rq.style.clip_plane = std::array<double, 6>{3.5, 3.5, 3.5, 0, 0, 1};
  render_frame(rq);
  const Image img = read_png(rq.png);
  EXPECT_EQ(img.width, 400);
  EXPECT_EQ(img.height, 300);
  EXPECT_GT(distinct_colours(img), 50u);
  EXPECT_GT(count(img, [](int r, int g, int b) { return b > r + 60; }), 300u);  // cool side
  EXPECT_GT(count(img, [](int r, int g, int b) { return r > b + 60; }), 300u);  // warm side
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
  const auto pngs = render_series(particles.pvd_path(), dir_ / "png", style, bonds.pvd_path());
  ASSERT_EQ(pngs.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(pngs[k], dir_ / "png" / ("frame_00000" + std::to_string(k) + ".png"));
    EXPECT_EQ(read_png(pngs[k]).width, 320);
  }
}

TEST_F(IoTest, MakeMovieUsesFfmpegOnlyWhenInstalled) {
  auto p = hex_patch(4, 4);
  RenderRequest rq;
  rq.particles = &p.cloud;
  rq.png = dir_ / "png" / "frame_000000.png";
  rq.style.width = 64;
  rq.style.height = 48;
  render_frame(rq);
  const std::string old_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  fs::create_directories(dir_ / "bin");
  ::setenv("PATH", (dir_ / "bin").c_str(), 1);
  EXPECT_FALSE(make_movie(dir_ / "png", dir_ / "movie.mp4"));
  EXPECT_FALSE(fs::exists(dir_ / "movie.mp4"));
  EXPECT_TRUE(fs::exists(rq.png));  // frames kept
  // A stand-in ffmpeg that records its arguments and writes its last one.
  const auto fake = dir_ / "bin" / "ffmpeg";
  std::ofstream(fake) << "#!/bin/sh\necho \"$@\" > \"" << (dir_ / "args.txt").string()
                      << "\"\nfor a; do last=$a; done\necho movie > \"$last\"\n";
  fs::permissions(fake, fs::perms::owner_all);
  const bool made = make_movie(dir_ / "png", dir_ / "movie.mp4");
  ::setenv("PATH", old_path.c_str(), 1);
  EXPECT_TRUE(made);
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
