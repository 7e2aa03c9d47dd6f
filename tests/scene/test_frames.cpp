// The frame builders of a run (scene/src/frames.cpp) written with io and read back with VTK's
// own readers: contacts as line cells with state 4 in the bond frames, and FEM meshes as
// unstructured grids with displacement, velocity and element stress, walls as lines (2D) or
// rectangles (3D) where they are now.
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/fem/mesh.hpp>
#include <strata/io/vtk.hpp>

#include <cmath>

#include <strata/scene/frames.hpp>
#include "io_test_util.hpp"

#if STRATA_WITH_VTK
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>
#endif

namespace fs = std::filesystem;
using namespace strata;
using namespace strata::io::test;

#if STRATA_WITH_VTK
namespace {
/// Three unbonded disks: 0 and 1 overlap by 5 % of a radius, 2 is far away.
dem::Simulation three_disks() {
  dem::Material m;
  m.density = 2650;
  m.kn = 1e7;
  m.ks = 4e6;
  m.friction = 0.5;
  dem::Simulation sim(2, dem::Settings{.dt = 1e-9, .allow_unstable = true});
  const int mat = sim.add_material(m);
  const double r = 0.5e-3;
  sim.add_particle({0, 0, 0}, r, mat);
  sim.add_particle({1.95 * r, 0, 0}, r, mat);
  sim.add_particle({10 * r, 0, 0}, r, mat);
  sim.add_to_group({0, 1}, "pair");
  sim.add_to_group({2}, "lonely");
  sim.initialise();
  sim.run(1);
  return sim;
}
}  // namespace

TEST_F(IoTest, ContactsAreLineCellsWithState4) {
  const dem::Simulation sim = three_disks();
  // The engine's own view of the touching contact, to compare the file with.
  std::vector<dem::PairView> touching;
  for (const auto& c : sim.contacts())
    if (c.kind == dem::PairKind::Contact && c.touching) touching.push_back(c);
  ASSERT_EQ(touching.size(), 1u);
  EXPECT_GT(touching[0].fn, 0.0) << "overlapping disks push apart: compression is positive";

  scene::FrameSelection sel;
  sel.bonds = scene::FrameSelection::Bonds::All;
  const io::PointCloud all = scene::particle_frame(sim, {"id"});
  const io::LineSet lines = scene::bond_frame(sim, sel);
  const auto file = dir_ / "bonds.vtp";
  io::write_lines(file, all, lines);

  vtkNew<vtkXMLPolyDataReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  vtkPolyData* pd = r->GetOutput();
  ASSERT_EQ(pd->GetNumberOfLines(), 1);  // no bonds; one touching contact; disk 2 touches nothing
  EXPECT_EQ(pd->GetNumberOfPoints(), 2);
  auto* state = pd->GetCellData()->GetArray("state");
  auto* fn = pd->GetCellData()->GetArray("Fn");
  auto* fs = pd->GetCellData()->GetArray("Fs");
  ASSERT_TRUE(state && fn && fs);
  EXPECT_EQ(state->GetComponent(0, 0), static_cast<double>(io::BondState::Contact));
  EXPECT_EQ(state->GetComponent(0, 0), 4.0);
  EXPECT_EQ(fn->GetComponent(0, 0), touching[0].fn);  // Float64 written and read: exact
  EXPECT_EQ(fs->GetComponent(0, 0), touching[0].fs);
  auto* ids = pd->GetPointData()->GetArray("id");
  ASSERT_TRUE(ids);
  EXPECT_EQ(ids->GetComponent(0, 0) + ids->GetComponent(1, 0), 1.0);  // particles 0 and 1

  // Selections: no contacts when switched off, and only those inside the selected groups.
  sel.contacts = false;
  EXPECT_EQ(scene::bond_frame(sim, sel).size(), 0u);
  sel.contacts = true;
  dem::Simulation copy = three_disks();
  sel.groups = {"lonely"};
  EXPECT_EQ(scene::bond_frame(copy, sel).size(), 0u);
  sel.groups = {"pair"};
  EXPECT_EQ(scene::bond_frame(copy, sel).size(), 1u);
  sel.groups.clear();
  sel.slice_thickness = 0.2e-3;  // a slice x = 0 ± 0.1 mm holds disk 0 only
  sel.slice_point = {0, 0, 0};
  sel.slice_normal = {1, 0, 0};
  EXPECT_EQ(scene::bond_frame(copy, sel).size(), 0u);
}

// A plane-strain rectangle under a uniform strain: the .vtu holds the nodes, triangles,
// displacement, velocity and the analytical stress in ParaView's tensor order.
TEST_F(IoTest, FemFrameReadsBackWithStressOfAConstantStrain) {
  const double E = 30e9, nu = 0.2, exx = 2e-4, eyy = -5e-5, gxy = 1e-4;
  fem::Material mat{.E = E, .nu = nu, .rho = 2500, .thickness = 1.0, .plane = fem::PlaneMode::Strain};
  const fem::Mesh mesh = fem::rectangle_tri_mesh(3, 2, 1.5, 1.0, mat);
  Eigen::VectorXd u(static_cast<Eigen::Index>(mesh.dofs())), v(u.size());
  for (std::size_t i = 0; i < mesh.nodes(); ++i) {
    const double x = mesh.x[0][i], y = mesh.x[1][i];
    u[2 * i] = exx * x + gxy * y;
    u[2 * i + 1] = eyy * y;
    v[2 * i] = 0.1 * x;
    v[2 * i + 1] = -0.2 * y;
  }
  const io::MeshFrame frame = scene::fem_frame(mesh, u, v, 2.5e-3, 77);
  const auto file = dir_ / "fem.vtu";
  io::write_mesh(file, frame);
  EXPECT_FALSE(fs::exists(dir_ / "fem.vtu.tmp"));

  vtkNew<vtkXMLUnstructuredGridReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  vtkUnstructuredGrid* ug = r->GetOutput();
  ASSERT_EQ(ug->GetNumberOfPoints(), 12);  // (3 + 1) x (2 + 1) nodes
  ASSERT_EQ(ug->GetNumberOfCells(), 12);   // 3 x 2 squares, two triangles each
  for (vtkIdType c = 0; c < ug->GetNumberOfCells(); ++c) EXPECT_EQ(ug->GetCellType(c), VTK_TRIANGLE);
  auto* disp = ug->GetPointData()->GetArray("displacement");
  auto* vel = ug->GetPointData()->GetArray("velocity");
  auto* stress = ug->GetCellData()->GetArray("stress");
  auto* mises = ug->GetCellData()->GetArray("von_mises");
  ASSERT_TRUE(disp && vel && stress && mises);
  ASSERT_EQ(stress->GetNumberOfComponents(), 6);
  for (vtkIdType i = 0; i < ug->GetNumberOfPoints(); ++i) {
    double x[3];
    ug->GetPoint(i, x);
    EXPECT_EQ(x[2], 0.0);
    EXPECT_DOUBLE_EQ(disp->GetComponent(i, 0), exx * x[0] + gxy * x[1]);
    EXPECT_DOUBLE_EQ(disp->GetComponent(i, 1), eyy * x[1]);
    EXPECT_EQ(disp->GetComponent(i, 2), 0.0);
    EXPECT_DOUBLE_EQ(vel->GetComponent(i, 1), -0.2 * x[1]);
  }
  // Plane strain Hooke's law; the linear triangle reproduces a uniform strain exactly, so
  // the tolerance is round-off (1e-9 of the largest stress).
  const double c = E / ((1 + nu) * (1 - 2 * nu));
  const double sxx = c * ((1 - nu) * exx + nu * eyy), syy = c * (nu * exx + (1 - nu) * eyy);
  const double szz = nu * (sxx + syy), sxy = E / (2 * (1 + nu)) * gxy;
  const double want[6] = {sxx, syy, szz, sxy, 0, 0};  // xx, yy, zz, xy, yz, xz
  const double vm =
      std::sqrt(0.5 * ((sxx - syy) * (sxx - syy) + (syy - szz) * (syy - szz) + (szz - sxx) * (szz - sxx)) +
                3 * sxy * sxy);
  const double tol = 1e-9 * std::abs(sxx);
  for (vtkIdType e = 0; e < ug->GetNumberOfCells(); ++e) {
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(stress->GetComponent(e, k), want[k], tol) << e << " " << k;
    EXPECT_NEAR(mises->GetComponent(e, 0), vm, tol);
  }
  const io::MeshFrame back = io::read_vtu(file);
  EXPECT_EQ(back.dim, 2);
  EXPECT_EQ(back.time, 2.5e-3);
  EXPECT_EQ(back.step, 77);
  EXPECT_EQ(back.connectivity, frame.connectivity);
  ASSERT_TRUE(back.find_cell("block"));
  EXPECT_EQ(back.find_cell("block")->type, io::ArrayType::Int32);
}

// A wall moving at constant velocity is written where it is at the frame's time, in its
// plane, covering the particles' box projected onto it, with its normal and velocity; read
// back with VTK's reader. Tolerances: round-off of a few coordinates (1e-12 of the model size).
TEST_F(IoTest, WallsAreWrittenWhereTheyAreNow) {
  for (const int dim : {2, 3}) {
    dem::Material m;
    m.density = 2650;
    m.kn = 1e7;
    m.ks = 4e6;
    dem::Simulation sim(dim, dem::Settings{.dt = 1e-6, .allow_unstable = true});
    const int mat = sim.add_material(m);
    const double r = 0.5e-3;
    for (int i = 0; i < 4; ++i)
      sim.add_particle({2 * r * i, 2 * r * (i % 2), dim == 3 ? r * i : 0.0}, r, mat);
    // A floor tilted by 30 degrees, below the particles, moving up along its normal.
    const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
    const std::array<double, 3> n =
        dim == 2 ? std::array<double, 3>{-s, c, 0} : std::array<double, 3>{-s, 0.6 * c, 0.8 * c};
    const std::array<double, 3> p0{0, -0.01, 0}, v{0.5 * n[0], 0.5 * n[1], 0.5 * n[2]};
    sim.add_wall(p0, n, v, 1e6);
    sim.initialise();
    sim.run(10);
    const double t = sim.time();

    const io::MeshFrame frame = scene::wall_frame(sim);
    const auto file = dir_ / "walls.vtu";
    io::write_mesh(file, frame);
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(file.c_str());
    reader->Update();
    vtkUnstructuredGrid* ug = reader->GetOutput();
    ASSERT_EQ(ug->GetNumberOfCells(), dim == 2 ? 1 : 2) << dim << "D";
    for (vtkIdType k = 0; k < ug->GetNumberOfCells(); ++k)
      EXPECT_EQ(ug->GetCellType(k), dim == 2 ? VTK_LINE : VTK_TRIANGLE);
    ASSERT_EQ(ug->GetNumberOfPoints(), dim == 2 ? 2 : 4);
    // Every corner on the plane through p0 + v t with normal n.
    const double tol = 1e-12;
    double lo = 1e300, hi = -1e300;  // extent along the in-plane direction of x's projection
    std::array<double, 3> along{1 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2]};
    const double len = std::sqrt(along[0] * along[0] + along[1] * along[1] + along[2] * along[2]);
    for (vtkIdType i = 0; i < ug->GetNumberOfPoints(); ++i) {
      double x[3];
      ug->GetPoint(i, x);
      double off = 0, a = 0;
      for (int k = 0; k < 3; ++k) {
        off += (x[k] - p0[k] - v[k] * t) * n[k];
        a += x[k] * along[k] / len;
      }
      EXPECT_NEAR(off, 0.0, tol) << dim << "D corner " << i;
      if (dim == 2) {
        EXPECT_EQ(x[2], 0.0);
      }
      lo = std::min(lo, a);
      hi = std::max(hi, a);
    }
    // The particles' centres, projected onto the same direction, lie inside the extent.
    for (const auto& x : sim.positions()) {
      const double a = (x[0] * along[0] + x[1] * along[1] + x[2] * along[2]) / len;
      EXPECT_GT(a, lo + r) << dim << "D";
      EXPECT_LT(a, hi - r) << dim << "D";
    }
    auto* normal = ug->GetCellData()->GetArray("normal");
    auto* velocity = ug->GetCellData()->GetArray("velocity");
    auto* index = ug->GetCellData()->GetArray("wall");
    ASSERT_TRUE(normal && velocity && index);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(normal->GetComponent(0, k), n[k], 1e-15);
      EXPECT_NEAR(velocity->GetComponent(0, k), v[k], 1e-15);
    }
    EXPECT_EQ(index->GetComponent(ug->GetNumberOfCells() - 1, 0), 0.0);
  }
}

namespace {
/// Two bonded disks along x, the left one fixed, the right one driven along x: a bond that
/// breaks in tension at 1 N.
struct DrivenPair {
  dem::Simulation sim{2, dem::Settings{.dt = 1e-9, .allow_unstable = true}};
  static constexpr double r = 0.5e-3;
  DrivenPair() {
    dem::Material m;
    m.density = 2650;
    m.kn = 1e7;
    m.ks = 4e6;
    m.friction = 0.5;
    m.tensile_strength = 1.0;
    const int mat = sim.add_material(m);
    sim.add_particle({0, 0, 0}, r, mat);
    sim.add_particle({2 * r, 0, 0}, r, mat);
    sim.add_to_group({0}, "left");
    sim.add_to_group({1}, "right");
    sim.fix("left", 0b11);
    sim.drive("right", 0b11);
    sim.bond_touching_pairs();
    sim.initialise();
  }
  /// Moves the right disk to `gap` (m, negative: overlap) from touching and steps once.
  void place(double gap) {
    sim.set_kinematics(1, {gap, 0, 0}, {0, 0, 0});
    sim.run(1);
  }
  /// The drawn state of the bond (BondState code), or -1 when it is not written.
  int drawn(const scene::FrameSelection& sel = {}) const {
    const io::LineSet lines = scene::bond_frame(sim, sel);
    return lines.size() == 0 ? -1 : int(lines.find(io::kBondStateArray)->at(0));
  }
};
}  // namespace

// A broken bond is drawn as it is now: open in tension, then closed while the disks touch
// again, then open again when they part once more (not closed for ever once it has closed).
TEST_F(IoTest, BrokenBondsAreDrawnInTheirCurrentState) {
  DrivenPair p;
  scene::FrameSelection all;
  all.bonds = scene::FrameSelection::Bonds::All;
  EXPECT_EQ(p.drawn(all), int(io::BondState::Intact));
  p.place(0.1 * DrivenPair::r);  // stretched by 5e-5 m: Fn = 500 N > 1 N
  EXPECT_EQ(p.drawn(), int(io::BondState::BrokenTension));
  p.place(-0.02 * DrivenPair::r);  // pressed together again
  EXPECT_EQ(p.drawn(), int(io::BondState::Closed));
  p.place(0.2 * DrivenPair::r);  // apart once more
  EXPECT_EQ(p.drawn(), int(io::BondState::BrokenTension));
  p.place(-0.01 * DrivenPair::r);
  EXPECT_EQ(p.drawn(), int(io::BondState::Closed));
}

// [output] groups (and slices) filter broken bonds as they filter particles and contacts: a
// crack between two particles outside the selected groups is not written.
TEST_F(IoTest, GroupSelectionFiltersBrokenBonds) {
  DrivenPair p;
  p.place(0.1 * DrivenPair::r);
  scene::FrameSelection sel;
  EXPECT_EQ(p.drawn(sel), int(io::BondState::BrokenTension));
  sel.groups = {"right"};
  EXPECT_EQ(p.drawn(sel), -1) << "the left disk is not in the selection";
  p.sim.add_to_group({0, 1}, "both");
  sel.groups = {"both"};
  EXPECT_EQ(p.drawn(sel), int(io::BondState::BrokenTension));
  sel.groups.clear();
  sel.slice_thickness = 0.5 * DrivenPair::r;  // a slice normal to x through the left disk only
  sel.slice_normal = {1, 0, 0};
  EXPECT_EQ(p.drawn(sel), -1);
}
#endif

#if STRATA_WITH_VTK
// A selected frame reads only the particles it writes; what it holds must be what filtering
// the frame of every particle gives: the surface particles in a slice, in internal order, with
// their fields, and the cracks in the slice between the same particles.
TEST(SelectedFrame, HoldsWhatFilteringTheWholeFrameGives) {
  dem::Material m;
  m.density = 2650;
  m.kn = 1e7;
  m.ks = 4e6;
  m.tensile_strength = 0.05;  // N: the pull below breaks some bonds
  dem::Simulation sim(2, dem::Settings{.dt = 1e-8, .allow_unstable = true});
  const int mat = sim.add_material(m);
  const double d = 1e-3;
  std::vector<std::uint32_t> right;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 16; ++i) {
      const auto id = sim.add_particle({(i + 0.5 * (j % 2)) * d, j * d * std::sqrt(3.0) / 2, 0}, d / 2, mat);
      if (i >= 8) right.push_back(std::uint32_t(id));
    }
  sim.add_to_group(right, "right");
  sim.bond_touching_pairs();
  sim.initialise();
  sim.prescribe_velocity("right", {2.0, 0.3, 0}, dem::kXY);
  sim.run(40);
  ASSERT_GT(sim.broken_count(), 0u);

  scene::FrameSelection sel;
  sel.particles = scene::FrameSelection::Particles::Surface;
  sel.slice_thickness = 6 * d;
  sel.slice_point = {8 * d, 0, 0};
  sel.slice_normal = {1, 0, 0};
  sel.find_surface(sim);
  const std::vector<std::string> fields{"id", "displacement", "velocity", "damage", "group"};
  const scene::SelectedFrame f = scene::selected_frame(sim, fields, sel, false);
  const io::PointCloud all = scene::particle_frame(sim, fields);
  const auto ids = sim.ids();

  // the particles: filter the whole frame by hand
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (sel.surface_by_id[ids[i]] && sel.in_groups_and_slice(true, &all.xyz[3 * i])) keep.push_back(i);
  ASSERT_GT(keep.size(), 5u);
  ASSERT_LT(keep.size(), all.size());
  const io::PointCloud pc = f.particles();
  ASSERT_EQ(pc.size(), keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(pc.xyz[3 * k + a], all.xyz[3 * keep[k] + a]);
  ASSERT_EQ(pc.point_data.size(), all.point_data.size());
  for (std::size_t q = 0; q < all.point_data.size(); ++q) {
    const auto& whole = all.point_data[q];
    const auto& part = pc.point_data[q];
    EXPECT_EQ(part.name, whole.name);
    const auto c = std::size_t(whole.components);
    for (std::size_t k = 0; k < keep.size(); ++k)
      for (std::size_t e = 0; e < c; ++e)
        EXPECT_EQ(part.values[k * c + e], whole.values[keep[k] * c + e]) << part.name;
  }

  // the cracks: the same lines as bond_frame's over all particles, between the same ids
  const io::LineSet whole = scene::bond_frame(sim, sel);
  ASSERT_GT(whole.size(), 0u);
  ASSERT_EQ(f.bonds.size(), whole.size());
  const io::Array* fid = f.points.find("id");
  ASSERT_NE(fid, nullptr);
  for (std::size_t e = 0; e < whole.ends.size(); ++e)
    EXPECT_EQ(fid->values[std::size_t(f.bonds.ends[e])], double(ids[std::size_t(whole.ends[e])]));
  EXPECT_EQ(f.bonds.cell_data[0].values, whole.cell_data[0].values);  // states
  EXPECT_LT(f.points.size(), all.size());                             // not every particle was read

  // surface_and_slice: the surface and, besides, the whole slice
  sel.particles = scene::FrameSelection::Particles::SurfaceAndSlice;
  std::vector<double> want;  // ids, in internal order
  for (std::size_t i = 0; i < all.size(); ++i)
    if (sel.surface_by_id[ids[i]] || sel.in_groups_and_slice(true, &all.xyz[3 * i]))
      want.push_back(double(ids[i]));
  const io::PointCloud both = scene::selected_frame(sim, fields, sel, false).particles();
  EXPECT_GT(want.size(), keep.size());
  EXPECT_EQ(both.find("id")->values, want);
}
#endif
