// FEM–DEM coupling through the overlapping boundary (Li et al. 2023): roles and copy rule, the
// 6-DOF chain against its exact solution, serial == parallel bit for bit, the coupled
// stability rules, and the metamaterial chain's stability numbers.
#include <gtest/gtest.h>
#include <strata/core/error.hpp>
#include <strata/couple/chains.hpp>

#include <cmath>

using namespace strata::couple;
using strata::fem::Scheme;

namespace {

// One coupled chain6 run; returns the FEM probe history of m3.
ProbeHistory run_chain6(int eta, Execution mode, double duration, Scheme scheme = Scheme::ExplicitNewmark) {
  CoupledChain c = split_chain(chain6_model(), {0, 1, 2, 3}, {2, 3, 4, 5},
                               SplitSettings{.dt_dem = 1e-4, .eta = eta, .fem_scheme = scheme});
  Coupler cp(*c.fem, *c.dem, c.overlap, eta, mode);
  cp.probe_fem(c.fem_local(2), "m3");
  cp.probe_dem(c.dem_local(5), "m6");
  cp.initialise();
  cp.run(static_cast<std::int64_t>(std::floor(duration / (eta * 1e-4) + 1e-9)));
  ProbeHistory h = cp.fem_probes()[0];
  h.t.insert(h.t.end(), cp.dem_probes()[0].t.begin(), cp.dem_probes()[0].t.end());
  h.u.insert(h.u.end(), cp.dem_probes()[0].u.begin(), cp.dem_probes()[0].u.end());
  return h;
}

}  // namespace

// The 6-DOF chain: FEM m1..m4, DEM m3..m6; FEM B = m3 = DEM E, FEM E = m4 = DEM B.
TEST(Couple, Chain6RolesAndOverlap) {
  const CoupledChain c = split_chain(chain6_model(), {0, 1, 2, 3}, {2, 3, 4, 5}, SplitSettings{});
  EXPECT_EQ(c.fem_roles, (std::vector<Role>{Role::Internal, Role::Internal, Role::Boundary, Role::External}));
  EXPECT_EQ(c.dem_roles, (std::vector<Role>{Role::External, Role::Boundary, Role::Internal, Role::Internal}));
  ASSERT_EQ(c.overlap.fem_to_dem.size(), 1u);
  EXPECT_EQ(c.overlap.fem_to_dem[0].from, 2u);  // FEM m3 -> DEM m3
  EXPECT_EQ(c.overlap.fem_to_dem[0].to, 0u);
  ASSERT_EQ(c.overlap.dem_to_fem.size(), 1u);
  EXPECT_EQ(c.overlap.dem_to_fem[0].from, 1u);  // DEM m4 -> FEM m4
  EXPECT_EQ(c.overlap.dem_to_fem[0].to, 3u);
  // no overlap: refused
  EXPECT_THROW(split_chain(chain6_model(), {0, 1, 2}, {3, 4, 5}, SplitSettings{}), strata::Error);
}

// The exact modal solution satisfies the equations of motion and starts from rest.
TEST(Couple, Chain6ExactSolutionIsConsistent) {
  const Chain6Exact ex;
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(ex.u(i, 0.0), 0.0, 1e-15);
  const double h = 1e-4;
  for (int i = 0; i < 6; ++i) EXPECT_NEAR((ex.u(i, h) - ex.u(i, -h)) / (2 * h), 0.0, 1e-8);  // v(0) = 0
  // M u'' + K u = f at t = 3.7 s (central differences, error O(h²) ≈ 1e-7)
  const double t = 3.7, H = 1e-3;
  for (int i = 0; i < 6; ++i) {
    const double acc = (ex.u(i, t + H) - 2 * ex.u(i, t) + ex.u(i, t - H)) / (H * H);
    double ku = (i == 0 ? 2 : i == 5 ? 1 : 2) * ex.u(i, t);
    if (i > 0) ku -= ex.u(i - 1, t);
    if (i < 5) ku -= ex.u(i + 1, t);
    const double f = i == 1 ? std::sin(M_PI / 2 * t) : 0.0;
    EXPECT_NEAR(acc + ku, f, 1e-5) << "mass " << i + 1;
  }
}

// Serial and parallel runs give identical results, bit for bit, on both sides.
TEST(Couple, SerialAndParallelAreBitIdentical) {
  for (int eta : {1, 3, 20}) {
    const ProbeHistory s = run_chain6(eta, Execution::Serial, 2.0);
    const ProbeHistory p = run_chain6(eta, Execution::Parallel, 2.0);
    ASSERT_EQ(s.u.size(), p.u.size());
    for (std::size_t k = 0; k < s.u.size(); ++k) {
      ASSERT_EQ(s.u[k], p.u[k]) << "eta " << eta << " sample " << k;
      ASSERT_EQ(s.t[k], p.t[k]);
    }
  }
  // implicit FEM as well
  const ProbeHistory s = run_chain6(4, Execution::Serial, 1.0, Scheme::ImplicitNewmark);
  const ProbeHistory p = run_chain6(4, Execution::Parallel, 1.0, Scheme::ImplicitNewmark);
  EXPECT_EQ(s.u, p.u);
}

// η·dt_DEM above the FEM partition's explicit limit: refused with an explicit FEM scheme
// (message says only the implicit Newmark is allowed), accepted with a note when implicit.
TEST(Couple, CoupledStabilityNamesTheFemExplicitLimit) {
  ChainModel m = chain6_model();
  for (auto& k : m.net.k) k = 1e6;  // stiffen the chain: ω_max ≈ 2e3 rad/s, explicit limit ≈ 1e-3 s
  m.net.ground_k[0] = 1e6;
  const int eta = 20;  // dt_FEM = 2e-3 s
  {
    CoupledChain c =
        split_chain(m, {0, 1, 2, 3}, {2, 3, 4, 5},
                    SplitSettings{.dt_dem = 1e-4, .eta = eta, .fem_scheme = Scheme::ExplicitNewmark});
    Coupler cp(*c.fem, *c.dem, c.overlap, eta);
    try {
      cp.initialise();
      FAIL() << "accepted an unstable FEM step";
    } catch (const strata::Error& e) {
      EXPECT_EQ(e.kind(), strata::ErrorKind::Input);
      const std::string w = e.what();
      EXPECT_NE(w.find("exceeds the FEM partition's explicit limit"), std::string::npos) << w;
      EXPECT_NE(w.find("only the implicit Newmark"), std::string::npos) << w;
    }
  }
  {
    CoupledChain c =
        split_chain(m, {0, 1, 2, 3}, {2, 3, 4, 5},
                    SplitSettings{.dt_dem = 1e-4, .eta = eta, .fem_scheme = Scheme::ImplicitNewmark});
    Coupler cp(*c.fem, *c.dem, c.overlap, eta);
    EXPECT_NO_THROW(cp.initialise());
    EXPECT_TRUE(cp.stability().ok);
    // notes: the implicit Newmark is required here, and dt_FEM is above 1.2 x the DEM limit
    // (the exchange's own measured limit, examples/04_coupled_wave)
    ASSERT_EQ(cp.stability().notes.size(), 2u);
    EXPECT_NE(cp.stability().notes[0].find("only the implicit Newmark"), std::string::npos);
    EXPECT_NE(cp.stability().notes[1].find("overlap exchange may be unstable"), std::string::npos);
    EXPECT_NO_THROW(cp.run(100));
  }
}

// A DEM step above the DEM limit, forced: the parallel run stops with a blow-up error (from
// whichever side sees it first: the NaN crosses the overlap) and does not deadlock.
TEST(Couple, BlowUpInParallelRunIsReported) {
  ChainModel m = chain6_model();
  const double dt_dem = 1.05 * 2 / std::sqrt(4.0);  // DEM limit 2/ω, ω = 2√(k/m) = 2
  for (Execution mode : {Execution::Serial, Execution::Parallel}) {
    CoupledChain c = split_chain(
        m, {0, 1, 2, 3}, {2, 3, 4, 5},
        SplitSettings{
            .dt_dem = dt_dem, .eta = 1, .fem_scheme = Scheme::ImplicitNewmark, .allow_unstable = true});
    Coupler cp(*c.fem, *c.dem, c.overlap, 1, mode);
    cp.initialise(/*allow_unstable=*/true);
    try {
      cp.run(100000);
      FAIL() << "no blow-up";
    } catch (const strata::Error& e) {
      EXPECT_EQ(e.kind(), strata::ErrorKind::Numerical) << e.what();
      EXPECT_NE(std::string(e.what()).find("blow-up"), std::string::npos) << e.what();
    }
  }
}

// The metamaterial chain's ω_max = 2.60e4 rad/s → dt_crit = 7.68e-5 s for the whole chain; the DEM
// partition alone is a plain chain with ω_max = 2√(k_n/m_s) → 8.0e-5 s. The paper's
// dt_DEM = 1e-4 s is refused (Input: exit status 2) naming both limits.
TEST(Couple, MetamaterialStabilityNumbers) {
  const MetamaterialStability s = metamaterial_stability();
  std::printf("%s\n", s.text(1e-4).c_str());
  EXPECT_NEAR(s.omega_whole / 2.60e4, 1.0, 5e-3);
  EXPECT_NEAR(s.dt_whole / 7.68e-5, 1.0, 5e-3);
  EXPECT_GE(s.omega_whole_bound, s.omega_whole);
  EXPECT_NEAR(s.omega_dem, 2 * std::sqrt(7.8e6 / 0.05), 1e-6 * s.omega_dem);
  EXPECT_NEAR(s.dt_dem_crit / 8.0e-5, 1.0, 1e-3);
  try {
    check_metamaterial_dt(1e-4);
    FAIL() << "the paper's dt_DEM = 1e-4 s was accepted";
  } catch (const strata::Error& e) {
    EXPECT_EQ(e.exit_status(), 2);
    const std::string w = e.what();
    EXPECT_NE(w.find("7.68e-05 s for the whole chain"), std::string::npos) << w;
    EXPECT_NE(w.find("8.01e-05 s for the DEM partition alone"), std::string::npos) << w;
  }
  EXPECT_NO_THROW(check_metamaterial_dt(5e-5));
}
