// `strata report wave --frames N` end to end (examples/04_coupled_wave): the VTK series of
// one coupled run, read back with io's readers. Particles (.vtp) and the FEM mesh (.vtu)
// share their times; every frame has the arrays the report promises, with one tuple per
// particle / node / cell; and at the coincident overlap sites the FEM and particle files
// hold the same displacement and velocity. The frames are the state at the start of a
// system step after the exchange (X_E(DEM) = X_B(FEM), X_E(FEM) = X_B(DEM)): both sides of
// a coincident pair are then the same double, and written as Float64 they read back equal,
// so the tolerance is 0 (exact), on both interfaces of the FEM | DEM | FEM model too.
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/io/series.hpp>
#include <strata/io/vtk.hpp>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "../cli/cli_test_util.hpp"

namespace io = strata::io;
namespace fs = std::filesystem;

namespace {

const io::Array& point_array(const io::PointCloud& p, const char* name, int components) {
  const io::Array* a = p.find(name);
  EXPECT_NE(a, nullptr) << "particles: no array " << name;
  if (!a) throw std::runtime_error(name);
  EXPECT_EQ(a->components, components) << name;
  EXPECT_EQ(a->tuples(), p.size()) << name;
  return *a;
}

const io::Array& mesh_array(const io::MeshFrame& m, const char* name, int components, bool cell) {
  const io::Array* a = cell ? m.find_cell(name) : m.find_point(name);
  EXPECT_NE(a, nullptr) << "mesh: no array " << name;
  if (!a) throw std::runtime_error(name);
  EXPECT_EQ(a->components, components) << name;
  EXPECT_EQ(a->tuples(), cell ? m.cells() : m.nodes()) << name;
  return *a;
}

struct Counts {
  std::size_t pairs = 0;  ///< coincident (particle, node) sites
  double max_u = 0;       ///< largest |u| at those sites over all frames (m)
};

/// Reads DIR/series and checks it; `out` receives what it found.
void check_series(const fs::path& dir, std::size_t frames, Counts& out) {
  const auto pe = io::read_pvd(dir / "particles.pvd"), fe = io::read_pvd(dir / "fem.pvd");
  EXPECT_EQ(pe.size(), frames);
  EXPECT_EQ(fe.size(), frames);
  if (pe.size() != frames || fe.size() != frames) return;
  EXPECT_TRUE(io::is_mesh_series(dir / "fem.pvd"));
  EXPECT_EQ(pe.front().time, 0.0);
  for (std::size_t k = 0; k < frames; ++k) {
    EXPECT_EQ(pe[k].time, fe[k].time) << "frame " << k;  // the same times on both sides
    if (k > 0) {
      EXPECT_GT(pe[k].time, pe[k - 1].time);
    }
  }

  // Reference positions of the particles (frame 0: nothing has moved yet), by id.
  const io::VtpContents p0 = io::read_vtp(dir / pe[0].file);
  std::map<long long, std::array<double, 3>> x0;
  {
    const io::Array& id = point_array(p0.points, "id", 1);
    for (std::size_t i = 0; i < p0.points.size(); ++i)
      x0[std::llround(id.at(i))] = {p0.points.xyz[3 * i], p0.points.xyz[3 * i + 1], p0.points.xyz[3 * i + 2]};
    EXPECT_EQ(x0.size(), p0.points.size()) << "ids are not unique";
  }
  for (std::size_t k = 0; k < frames; ++k) {
    SCOPED_TRACE(::testing::Message() << "frame " << k);
    const io::PointCloud p = io::read_vtp(dir / pe[k].file).points;
    const io::MeshFrame m = io::read_vtu(dir / fe[k].file);
    ASSERT_EQ(p.size(), x0.size());
    ASSERT_GT(m.nodes(), 0u);
    ASSERT_GT(m.cells(), 0u);
    EXPECT_EQ(p.dim, 2);
    EXPECT_EQ(m.dim, 2);
    for (auto t : m.cell_types) ASSERT_EQ(t, io::CellType::Triangle);
    point_array(p, "radius", 1);
    const io::Array& id = point_array(p, "id", 1);
    const io::Array& pu = point_array(p, "displacement", 3);
    const io::Array& pv = point_array(p, "velocity", 3);
    const io::Array& ptag = point_array(p, "overlap", 1);
    const io::Array& mu = mesh_array(m, "displacement", 3, false);
    const io::Array& mv = mesh_array(m, "velocity", 3, false);
    const io::Array& ntag = mesh_array(m, "overlap", 1, false);
    mesh_array(m, "stress", 6, true);
    mesh_array(m, "von_mises", 1, true);

    // Coincident sites: a particle's reference centre is an FEM node, bit for bit.
    std::map<std::array<double, 3>, std::size_t> node_at;
    for (std::size_t n = 0; n < m.nodes(); ++n)
      node_at[{m.xyz[3 * n], m.xyz[3 * n + 1], m.xyz[3 * n + 2]}] = n;
    std::size_t pairs = 0, tagged_particles = 0, tagged_nodes = 0;
    for (std::size_t n = 0; n < m.nodes(); ++n) tagged_nodes += ntag.at(n) != 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double tag = ptag.at(i);
      tagged_particles += tag != 0;
      const auto it = node_at.find(x0.at(std::llround(id.at(i))));
      if (it == node_at.end()) {
        EXPECT_EQ(tag, 0) << "overlap particle " << i << " has no FEM node";
        continue;
      }
      ++pairs;
      const std::size_t n = it->second;
      // DEM boundary (1) = FEM external (2), DEM external (2) = FEM boundary (1)
      EXPECT_TRUE(tag == 1 || tag == 2) << "particle " << i;
      EXPECT_EQ(ntag.at(n), 3 - tag) << "node " << n;
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(pu.at(i, a), mu.at(n, a))
            << "displacement, particle " << i << " node " << n << " axis " << a;
        EXPECT_EQ(pv.at(i, a), mv.at(n, a)) << "velocity, particle " << i << " node " << n << " axis " << a;
        out.max_u = std::max(out.max_u, std::abs(pu.at(i, a)));
      }
    }
    EXPECT_EQ(pairs, tagged_particles);
    EXPECT_EQ(pairs, tagged_nodes);
    if (k == 0) out.pairs = pairs;
    EXPECT_EQ(pairs, out.pairs);
  }
}

}  // namespace

// One FEM block and one particle block: three frames (t = 0, the middle, the end); the pulse
// (v0 = 0.1 m/s, T = 20 d / c = 3.3 µs) leaves a displacement of about v0·T/2 = 1.7e-7 m
// behind it, so by the last frame the overlap has moved: at least half of that is required,
// so that the equality is not one of zeros.
TEST(WaveSeries, QuickRunWritesBothSidesWithEqualOverlapValues) {
  const fs::path dir = cli_test::temp_dir("wave_series");
  const auto r = cli_test::run_strata("report wave --quick --frames 3 -o " + dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  Counts c;
  check_series(dir / "series", 3, c);
  EXPECT_GT(c.pairs, 30u);  // two rows of about 20 sites
  EXPECT_GT(c.max_u, 0.5 * 0.1 * (20e-3 / 6013.6) / 2);
#if STRATA_WITH_RENDER
  for (int k = 0; k < 3; ++k)
    EXPECT_GT(fs::file_size(dir / "series" / "png" / ("crossing_" + std::to_string(k) + ".png")), 10000u)
        << k;
#endif
  fs::remove_all(dir);
}

// FEM | DEM | FEM: one mesh of two blocks, two overlaps; the same checks cover both.
TEST(WaveSeries, EmbeddedStripHasTwoOverlapsInTheSeries) {
  const fs::path dir = cli_test::temp_dir("wave_series_embedded");
  const auto r = cli_test::run_strata(
      "report wave --embedded --quick --modes serial --no-plot --frames 3 -o " + dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir / "series" / "png"));  // --no-plot: no pictures
  Counts c;
  check_series(dir / "series", 3, c);
  EXPECT_GT(c.pairs, 60u);  // four rows of about 20 sites
  EXPECT_GT(c.max_u, 0.5 * 0.1 * (20e-3 / 6013.6) / 2);
  fs::remove_all(dir);
}
