// DemPartition: a libdem Simulation as a coupled partition (DOF = id·dim + axis). Driven
// (external) DOFs follow set_external exactly, free DOFs read back what libdem has, the rules
// on when externals may be declared, and a coupled DEM–DEM chain of disks that must match
// the same chain run as one Simulation.
#include <gtest/gtest.h>
#include <strata/core/error.hpp>
#include <strata/couple/coupler.hpp>
#include <strata/couple/dem_partition.hpp>
#include <strata/preprocess/lattice.hpp>

#include <cmath>

using namespace strata;
using namespace strata::couple;

namespace {

// libdem stores positions, so a displacement read back is (x0 + u) − x0: exact up to the
// round-off of coordinates of a few mm (ulp 9e-19 m); 1e-17 m is about 10 ulps.
constexpr double kPosTol = 1e-17;

dem::Material rock() {
  dem::Material m;
  m.density = 2.65e3;
  m.kn = 6.587e10;
  m.ks = 2.371e10;
  return m;  // unbreakable bonds
}

// A 2D hex block of rows x cols disks of 1 mm, bonded, at dt = 0.5 x the lattice limit.
dem::Simulation block(int rows, int cols, double* dt_out = nullptr) {
  const double d = 1e-3;
  const dem::Material m = rock();
  const double mass = m.density * std::sqrt(3.0) / 2 * d * d;
  const double dt = 0.5 * 2 / std::sqrt(dem::hex_lattice_lambda_max(m.kn, m.ks, mass));
  if (dt_out) *dt_out = dt;
  dem::Simulation sim(2, dem::Settings{.dt = dt, .contact_detection = false});
  const int mi = sim.add_material(m);
  const preprocess::Lattice lat = preprocess::hex2d_rows(rows, cols, d);
  for (const auto& x : lat.x) sim.add_particle(x, lat.radius, mi);
  sim.bond_touching_pairs();
  return sim;
}

}  // namespace

// Driven DOFs: after set_external(u, v) at t_n, u(t_n + k·dt) = u + v·k·dt and the velocity is
// v, exactly up to the round-off of the stored positions (kPosTol). Free DOFs read back libdem's own
// kinematics.
TEST(DemPartition, DrivenDofsFollowSetExternalAndReadBack) {
  double dt = 0;
  DemPartition p(block(4, 6, &dt));
  ASSERT_EQ(p.dim(), 2);
  ASSERT_EQ(p.dofs(), p.simulation().particle_count() * 2);
  // particle 0 driven in x and y, particle 1 in x only
  p.make_external(0);
  p.make_external(1);
  p.make_external(2);
  p.prepare();
  EXPECT_GT(p.critical_dt(), dt);
  EXPECT_THROW(p.make_external(4), Error);  // the set is frozen by prepare()
  p.set_external(0, 1e-6, 0.01);
  p.set_external(1, -2e-6, -0.02);
  p.set_external(2, 3e-6, 0.03);
  p.initialise();
  EXPECT_THROW(p.set_external(3, 0, 0), Error);  // particle 1, y: not external
  // pending values are visible before the step
  EXPECT_NEAR(p.displacement(0), 1e-6, kPosTol);
  EXPECT_EQ(p.velocity(2), 0.03);
  for (int k = 1; k <= 5; ++k) {
    p.step();
    const double t = k * dt;
    EXPECT_NEAR(p.displacement(0), 1e-6 + 0.01 * t, kPosTol);
    EXPECT_NEAR(p.displacement(1), -2e-6 - 0.02 * t, kPosTol);
    EXPECT_NEAR(p.displacement(2), 3e-6 + 0.03 * t, kPosTol);
    EXPECT_EQ(p.velocity(0), 0.01);
    EXPECT_EQ(p.velocity(2), 0.03);
  }
  EXPECT_NEAR(p.time(), 5 * dt, 1e-20);
  // the free ones moved (pulled by the driven ones) and read back libdem's values
  std::array<double, 3> u, v;
  p.simulation().kinematics(5, u, v);
  EXPECT_EQ(p.displacement(10), u[0]);
  EXPECT_EQ(p.displacement(11), u[1]);
  EXPECT_EQ(p.velocity(10), v[0]);
  EXPECT_NE(u[0], 0.0);
  // a new exchange: jumps to the new value
  p.set_external(0, 5e-6, 0);
  p.step();
  EXPECT_NEAR(p.displacement(0), 5e-6, kPosTol);
  EXPECT_EQ(p.velocity(0), 0.0);
}

// 3D: DOF = id·3 + axis; one sphere of an HCP block driven on all three axes, one on z only.
TEST(DemPartition, DrivenDofsIn3D) {
  const double d = 1e-3;
  const dem::Material m = rock();
  const preprocess::Lattice lat =
      preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0}, {4e-3, 4e-3, 4e-3}, d);
  const double dt = 1e-9;  // far below the limit (~1e-7 s): the test is about the DOF map
  dem::Simulation sim(3, dem::Settings{.dt = dt, .contact_detection = false});
  const int mi = sim.add_material(m);
  for (const auto& x : lat.x) sim.add_particle(x, lat.radius, mi);
  sim.bond_touching_pairs();
  DemPartition p(std::move(sim));
  ASSERT_EQ(p.dofs(), lat.size() * 3);
  for (std::size_t a = 0; a < 3; ++a) p.make_external(3 * 2 + a);
  p.make_external(3 * 5 + 2);
  p.initialise();
  p.set_external(3 * 2 + 0, 1e-7, 1.0);
  p.set_external(3 * 2 + 1, -1e-7, -1.0);
  p.set_external(3 * 2 + 2, 2e-7, 2.0);
  p.set_external(3 * 5 + 2, 3e-7, 0.5);
  EXPECT_THROW(p.set_external(3 * 5 + 0, 0, 0), Error);  // particle 5, x: free
  for (int k = 1; k <= 3; ++k) p.step();
  EXPECT_NEAR(p.displacement(6), 1e-7 + 3 * dt, kPosTol);
  EXPECT_NEAR(p.displacement(7), -1e-7 - 3 * dt, kPosTol);
  EXPECT_NEAR(p.displacement(8), 2e-7 + 6 * dt, kPosTol);
  EXPECT_NEAR(p.displacement(17), 3e-7 + 1.5 * dt, kPosTol);
  EXPECT_EQ(p.velocity(17), 0.5);
  std::array<double, 3> u, v;
  p.simulation().kinematics(5, u, v);  // x and y of particle 5 are free: libdem's values
  EXPECT_EQ(p.displacement(15), u[0]);
  EXPECT_EQ(p.velocity(16), v[1]);
}

TEST(DemPartition, RefusesBadDofsAndEarlyQuestions) {
  DemPartition p(block(2, 3));
  EXPECT_THROW(p.make_external(p.dofs()), Error);
  EXPECT_THROW(p.critical_dt(), Error);  // known only once libdem has initialised the model
  EXPECT_THROW(p.step(), Error);
  EXPECT_THROW(p.set_external(0, 0, 0), Error);
}

namespace {

// A row of 40 disks (1D chain along x, y fixed) split into two DemPartitions overlapping by
// two disks, coupled, against the same row as one Simulation: a half-sine force pulse on
// disk 0 travels through the overlap to disk 30. Returns max |error| / peak at disk 30.
double dem_dem_chain_error(int eta) {
  const int n = 40, split = 20;  // left: disks 0..21 (21 external), right: 20..39 (20 external)
  const double d = 1e-3;
  const dem::Material m = rock();
  const double mass = m.density * std::sqrt(3.0) / 2 * d * d;
  const double dt = 0.3 * 2 / std::sqrt(4 * m.kn / mass);
  const double T = 40 * dt, F = 1e3;
  auto chain = [&](int first, int last, bool load, double step) {
    dem::Simulation s(2, dem::Settings{.dt = step, .contact_detection = false});
    const int mi = s.add_material(m);
    for (int i = first; i <= last; ++i) s.add_particle({i * d, 0, 0}, d / 2, mi, mass);
    s.bond_touching_pairs();
    std::vector<std::uint32_t> all;
    for (int i = 0; i <= last - first; ++i) all.push_back(static_cast<std::uint32_t>(i));
    s.add_to_group(all, "all");
    s.fix("all", dem::kY);
    if (load) {
      std::vector<double> t;
      std::vector<std::array<double, 3>> f;
      for (int k = 0; k <= 40; ++k) {
        t.push_back(k * T / 40);
        f.push_back({F * std::sin(M_PI * k / 40), 0, 0});
      }
      t.push_back(1);
      f.push_back({0, 0, 0});
      s.add_to_group({0}, "load");
      s.force_history("load", t, f);
    }
    return s;
  };
  dem::Simulation whole = chain(0, n - 1, true, dt);
  whole.initialise();
  // left plays the FEM side (step η·dt): its boundary disk 20 is copied to right's external
  // disk 20, right's boundary disk 21 to left's external disk 21
  DemPartition left(chain(0, split + 1, true, eta * dt), "left"),
      right(chain(split, n - 1, false, dt), "right");
  std::vector<std::int64_t> lid, rid;
  std::vector<Role> lrole, rrole;
  for (int i = 0; i <= split + 1; ++i)
    for (int a = 0; a < 2; ++a) {
      lid.push_back(2 * i + a);
      lrole.push_back(i == split ? Role::Boundary : i == split + 1 ? Role::External : Role::Internal);
    }
  for (int i = split; i < n; ++i)
    for (int a = 0; a < 2; ++a) {
      rid.push_back(2 * i + a);
      rrole.push_back(i == split ? Role::External : i == split + 1 ? Role::Boundary : Role::Internal);
    }
  Coupler cp(left, right, make_overlap(lid, lrole, rid, rrole), eta);
  cp.probe_dem(2 * (30 - split), "disk 30");
  cp.initialise();
  const int steps = 240;  // the pulse reaches disk 30 after about 100 steps
  std::vector<double> ref;
  for (int k = 0; k < steps; ++k) {
    whole.run(1);
    std::array<double, 3> u, v;
    whole.kinematics(30, u, v);
    ref.push_back(u[0]);
  }
  cp.run(steps / eta);
  const auto& got = cp.dem_probes()[0].u;
  EXPECT_EQ(got.size(), ref.size() + 1);
  double peak = 0, err = 0;
  for (int k = 0; k < steps; ++k) {
    peak = std::max(peak, std::abs(ref[k]));
    err = std::max(err, std::abs(got[k + 1] - ref[k]));
  }
  std::printf("DEM-DEM chain, eta = %d: peak %.4g m, max error %.4g m (%.3g of the peak)\n", eta, peak, err,
              err / peak);
  EXPECT_GT(peak, 1e-9);
  return err / peak;
}

}  // namespace

// η = 1: leapfrog evaluates forces at the positions of t_n only, and the copy overwrites the
// driven disk's position with the other side's x(t_n) before every force evaluation, so the
// split chain is the whole chain up to round-off (bound 1e-12 of the peak; measured 0). This
// checks the DOF map, the exchange and the driven-particle path of libdem together.
TEST(DemPartition, DemDemChainMatchesOneSimulationAtEtaOne) { EXPECT_LT(dem_dem_chain_error(1), 1e-12); }

// η = 2, 3: the left side steps 2·dt (3·dt; 0.9 of its limit) and its external disk moves with
// the copied half-step velocity between exchanges; the error grows with η but stays small for
// a pulse of 40 dt. Bounds: measured 4.2e-3 (η = 2) and 8.0e-3 (η = 3) of the peak (printed),
// x 2 margin.
TEST(DemPartition, DemDemChainErrorGrowsWithEta) {
  const double e2 = dem_dem_chain_error(2), e3 = dem_dem_chain_error(3);
  EXPECT_LT(e2, 0.0085);
  EXPECT_LT(e3, 0.016);
  EXPECT_GT(e3, e2);
}

// The work done through driven DOFs is booked apart as exchange work, so that a coupled
// model can tell the energy passed between its parts from the work of loads and boundaries.
TEST(DemPartition, WorkThroughDrivenDofsIsExchangeWork) {
  // driven by the other partition only: all the external work is exchange work
  DemPartition p(block(4, 6));
  p.make_external(0);
  p.prepare();
  p.set_external(0, 0, 0.05);
  p.initialise();
  for (int k = 0; k < 200; ++k) p.step();
  const dem::Simulation& s = p.simulation();
  EXPECT_GT(std::abs(s.external_work()), 0.0);
  EXPECT_EQ(s.exchange_work(), s.external_work());  // the same terms, summed in the same order

  // moved by a boundary condition of its own: no exchange work
  dem::Simulation b = block(4, 6);
  b.add_to_group(std::vector<std::uint32_t>{0}, "pushed");
  b.prescribe_velocity("pushed", {0.05, 0, 0}, 1u);
  b.initialise();
  b.run(200);
  EXPECT_GT(std::abs(b.external_work()), 0.0);
  EXPECT_EQ(b.exchange_work(), 0.0);
}
