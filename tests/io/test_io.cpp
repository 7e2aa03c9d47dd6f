// Tests of the io library's files: VTK frames read back with VTK's readers, the .pvd index
// under interruption, CSV round trips. Pictures and plots are in test_io_render.cpp.
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

#include "io_test_util.hpp"

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
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>
#endif

namespace fs = std::filesystem;
using namespace strata;
using namespace strata::io;
using namespace strata::io::test;

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

// ---- FEM meshes (.vtu) -----------------------------------------------------------------------

TEST_F(IoTest, MeshReadsBackWithVtkUnstructuredGridReader) {
  MeshFrame m = tet_box(1, /*extras=*/true);  // 6 tetrahedra, 1 triangle, 1 line
  m.time = 0.75;
  m.step = 1500;
  Array stress{"stress", 6, {}, ArrayType::Float64};
  for (std::size_t c = 0; c < m.cells(); ++c)
    for (int k = 0; k < 6; ++k) stress.values.push_back(1e6 * c + k);
  m.cell_data.push_back(stress);
  const auto file = dir_ / "mesh.vtu";
  write_mesh(file, m);
  EXPECT_FALSE(fs::exists(dir_ / "mesh.vtu.tmp"));
  const std::string text = slurp(file);
  EXPECT_NE(text.find("type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(text.find("format=\"appended\""), std::string::npos);
  EXPECT_NE(text.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(text.find("header_type=\"UInt64\""), std::string::npos);

  vtkNew<vtkXMLUnstructuredGridReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  vtkUnstructuredGrid* ug = r->GetOutput();
  ASSERT_EQ(ug->GetNumberOfPoints(), 8);
  ASSERT_EQ(ug->GetNumberOfCells(), 8);
  for (int c = 0; c < 6; ++c) EXPECT_EQ(ug->GetCellType(c), VTK_TETRA);
  EXPECT_EQ(ug->GetCellType(6), VTK_TRIANGLE);
  EXPECT_EQ(ug->GetCellType(7), VTK_LINE);
  // Connectivity, cell by cell, as given.
  std::size_t at = 0;
  for (vtkIdType c = 0; c < ug->GetNumberOfCells(); ++c) {
    vtkIdType np;
    const vtkIdType* ids;
    ug->GetCellPoints(c, np, ids);
    ASSERT_EQ(np, nodes_per_cell(m.cell_types[c]));
    for (vtkIdType k = 0; k < np; ++k) EXPECT_EQ(ids[k], m.connectivity[at++]);
  }
  auto* x = ug->GetPointData()->GetArray("x");
  auto* cx = ug->GetCellData()->GetArray("cx");
  auto* s = ug->GetCellData()->GetArray("stress");
  ASSERT_TRUE(x && cx && s);
  EXPECT_EQ(cx->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(s->GetNumberOfComponents(), 6);
  for (vtkIdType i = 0; i < 8; ++i) EXPECT_EQ(x->GetComponent(i, 0), m.xyz[3 * i]);
  for (vtkIdType c = 0; c < 8; ++c) {
    EXPECT_FLOAT_EQ(static_cast<float>(cx->GetComponent(c, 0)), static_cast<float>(m.cell_data[0].at(c)));
    for (int k = 0; k < 6; ++k) EXPECT_EQ(s->GetComponent(c, k), 1e6 * c + k);
  }
  EXPECT_EQ(ug->GetFieldData()->GetArray("TimeValue")->GetComponent(0, 0), 0.75);

  // read_vtu gives the same frame back.
  const MeshFrame back = read_vtu(file);
  EXPECT_EQ(back.dim, 3);
  EXPECT_EQ(back.xyz, m.xyz);
  EXPECT_EQ(back.cell_types, m.cell_types);
  EXPECT_EQ(back.connectivity, m.connectivity);
  EXPECT_EQ(back.time, m.time);
  EXPECT_EQ(back.step, m.step);
  ASSERT_TRUE(back.find_cell("stress"));
  EXPECT_EQ(back.find_cell("stress")->values, stress.values);
  EXPECT_EQ(back.find_point("x")->values, m.point_data[0].values);
}

TEST_F(IoTest, BadMeshesAreRefused) {
  MeshFrame m = tet_box(1);
  m.connectivity.pop_back();  // the last tetrahedron misses a node
  EXPECT_THROW(write_mesh(dir_ / "a.vtu", m), Error);
  m = tet_box(1);
  m.connectivity[3] = 8;  // nodes 0..7
  EXPECT_THROW(write_mesh(dir_ / "a.vtu", m), Error);
  m = tet_box(1);
  m.cell_data[0].values.pop_back();
  EXPECT_THROW(write_mesh(dir_ / "a.vtu", m), Error);
  EXPECT_THROW(m.add_cell(CellType::Triangle, {0, 1}), Error);
  EXPECT_FALSE(fs::exists(dir_ / "a.vtu"));
}

TEST_F(IoTest, MeshSeriesListsVtuFrames) {
  MeshFrame m = tet_box(2);
  Series fem(dir_, "fem");
  for (int k = 0; k < 3; ++k) fem.add_mesh(0.1 * k, m);
  const auto entries = read_pvd(fem.pvd_path());
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[2].file, fs::path("fem_000002.vtu"));
  EXPECT_EQ(read_vtu(dir_ / entries[2].file).cells(), m.cells());
  EXPECT_TRUE(is_mesh_series(fem.pvd_path()));
  auto p = hex_patch(3, 3);
  Series particles(dir_, "particles");
  particles.add_particles(0, p.cloud);
  EXPECT_FALSE(is_mesh_series(particles.pvd_path()));
  // A killed run's temporary .vtu is removed when the series is opened again.
  std::ofstream(fem.next_frame_path(".vtu").string() + ".tmp") << "<?xml";
  Series again(dir_, "fem", Series::Mode::Resume);
  EXPECT_FALSE(fs::exists(dir_ / "fem_000003.vtu.tmp"));
  EXPECT_EQ(again.frames().size(), 3u);
}

TEST_F(IoTest, ContactLinesKeepState4) {
  auto p = hex_patch(3, 3);
  p.bonds.find(kBondStateArray)->values[0] = static_cast<double>(BondState::Contact);
  write_lines(dir_ / "b.vtp", p.cloud, p.bonds);
  const auto back = read_vtp(dir_ / "b.vtp");
  EXPECT_EQ(back.lines.find(kBondStateArray)->at(0), 4.0);
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
  // The truncated frames' files are gone with them: the folder holds what the .pvd lists.
  EXPECT_FALSE(fs::exists(dir_ / "particles_000002.vtp"));
  EXPECT_FALSE(fs::exists(dir_ / "particles_000003.vtp"));
  Series fresh(dir_, "particles");
  EXPECT_TRUE(fresh.frames().empty());
  fresh.add_particles(0, p.cloud);
  EXPECT_EQ(read_pvd(s.pvd_path()).size(), 1u);
}

// A run into the folder of an earlier, longer run (or after a kill) leaves no frame that its
// .pvd does not list; other files in the folder are left alone.
TEST_F(IoTest, NoFrameOutsideTheIndexIsLeftBehind) {
  auto p = hex_patch(3, 3);
  {
    Series s(dir_, "particles");
    for (int k = 0; k < 5; ++k) s.add_particles(0.5 * k, p.cloud);
  }
  std::ofstream(dir_ / "notes.txt") << "mine";
  std::ofstream(dir_ / "bonds_000007.vtp") << "another series";
  {
    Series s(dir_, "particles");  // a fresh run with two frames
    s.add_particles(0.0, p.cloud);
    s.add_particles(1.0, p.cloud);
  }
  auto frames_on_disk = [&] {
    std::size_t n = 0;
    for (const auto& f : fs::directory_iterator(dir_))
      n += f.path().filename().string().starts_with("particles_");
    return n;
  };
  EXPECT_EQ(read_pvd(dir_ / "particles.pvd").size(), 2u);
  EXPECT_EQ(frames_on_disk(), 2u) << "frames 2 to 4 of the earlier run are gone";
  EXPECT_TRUE(fs::exists(dir_ / "notes.txt"));
  EXPECT_TRUE(fs::exists(dir_ / "bonds_000007.vtp"));

  // Killed after writing frame 2 but before listing it: a restart removes it.
  fs::copy_file(dir_ / "particles_000001.vtp", dir_ / "particles_000002.vtp");
  Series resumed(dir_, "particles", Series::Mode::Resume);
  EXPECT_EQ(resumed.frames().size(), 2u);
  EXPECT_EQ(frames_on_disk(), 2u);
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
