// Dynamic answers (wave speed, natural frequency), second-order convergence in dt, and the
// critical-step rules (element eigenvalues vs exact vs h/c, damping, refusal, blow-up).
#include <gtest/gtest.h>
#include <strata/core/error.hpp>
#include <strata/fem/critical_step.hpp>
#include <strata/fem/solver.hpp>
#include <strata/fem/stability.hpp>

#include <Eigen/Dense>
#include <cmath>

using namespace strata::fem;

namespace {

const Material kSteel{.E = 2e11, .rho = 7800, .area = 1e-4};

// Dense ω² spectrum of the free DOFs (generalized K φ = λ M φ with diagonal M).
Eigen::VectorXd dense_omega2(const Assembled& sys, const std::vector<char>& fixed) {
  std::vector<Eigen::Index> fr;
  for (Eigen::Index i = 0; i < sys.K.rows(); ++i)
    if (fixed.empty() || !fixed[static_cast<std::size_t>(i)]) fr.push_back(i);
  const Eigen::MatrixXd Kd = Eigen::MatrixXd(sys.K);
  const auto n = static_cast<Eigen::Index>(fr.size());
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      A(i, j) = Kd(fr[i], fr[j]) / std::sqrt(sys.mass[fr[i]] * sys.mass[fr[j]]);
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues();
}

// One mass m on a spring k to a fixed node: ω = sqrt(k/m).
Solver oscillator(double k, double m, SolverSettings s, double u0 = 1.0) {
  Mesh mesh = spring_mass_mesh({0.0, m}, {0}, {1}, {k});
  Solver sol(std::move(mesh), s);
  sol.fix(0);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(2), v = Eigen::VectorXd::Zero(2);
  u[1] = u0;
  sol.set_initial_state(u, v);
  return sol;
}

double oscillator_error(Scheme scheme, double dt) {
  SolverSettings s{.scheme = scheme, .dt = dt};
  Solver sol = oscillator(4.0, 1.0, s);  // ω = 2
  sol.initialise();
  const double T = 5.0;
  sol.advance(std::llround(T / dt));
  return std::abs(sol.u()[1] - std::cos(2.0 * sol.time()));
}

}  // namespace

// Step load P at the free end of a fixed–free bar: the reaction at the support jumps from 0
// to 2P when the wave arrives at t = L/c. The front is spread over a few elements by
// dispersion; the time at which the reaction passes P is within 2% of L/c (200 elements).
TEST(FemDynamics, BarWaveSpeed) {
  const double L = 2.0, P = 1e3, c = std::sqrt(kSteel.E / kSteel.rho);
  Mesh mesh = bar_mesh(200, L, kSteel, 1);
  const double dtc = (L / 200) / c;  // exact for lumped 2-node bars: h/c
  Solver sol(std::move(mesh), SolverSettings{.scheme = Scheme::CentralDifference, .dt = 0.5 * dtc});
  sol.fix(0);
  sol.add_load(200, [P](double) { return P; });
  sol.initialise();
  EXPECT_NEAR(sol.stability().explicit_dt_crit, dtc, 1e-9 * dtc);  // element bound = h/c for bars
  double t_arrive = -1;
  while (sol.time() < 2 * L / c) {
    sol.step();
    const double reaction = std::abs(sol.system().K.row(0).dot(sol.u()));
    if (reaction >= P) {
      t_arrive = sol.time();
      break;
    }
  }
  EXPECT_NEAR(t_arrive, L / c, 0.02 * L / c);
}

// First natural frequency of a fixed–free bar, πc/(2L): dense eigenvalue (100 lumped
// elements, relative error (π/4n)²/6 ≈ 1e-5 → tolerance 1e-4) and the period of a free
// vibration in that mode with the implicit Newmark (period error (ω dt)²/12 → 1e-4).
TEST(FemDynamics, BarNaturalFrequency) {
  const double L = 2.0, c = std::sqrt(kSteel.E / kSteel.rho), w1 = M_PI * c / (2 * L);
  const int n = 100;
  Mesh mesh = bar_mesh(n, L, kSteel, 1);
  const Assembled sys = assemble(mesh);
  std::vector<char> fixed(static_cast<std::size_t>(n + 1), 0);
  fixed[0] = 1;
  const double w1_fem = std::sqrt(dense_omega2(sys, fixed)(0));
  EXPECT_NEAR(w1_fem / w1, 1.0, 1e-4);

  const double T1 = 2 * M_PI / w1;
  Solver sol(std::move(mesh), SolverSettings{.scheme = Scheme::ImplicitNewmark, .dt = T1 / 400});
  sol.fix(0);
  Eigen::VectorXd u0(n + 1), v0 = Eigen::VectorXd::Zero(n + 1);
  for (int i = 0; i <= n; ++i) u0[i] = 1e-6 * std::sin(M_PI * i / (2.0 * n));
  sol.set_initial_state(u0, v0);
  sol.initialise();
  // times of downward zero crossings of the tip, linear interpolation
  std::vector<double> crossings;
  double prev = sol.u()[n], tprev = 0;
  while (crossings.size() < 4) {
    sol.step();
    const double cur = sol.u()[n];
    if (prev > 0 && cur <= 0) crossings.push_back(tprev + (sol.time() - tprev) * prev / (prev - cur));
    prev = cur;
    tprev = sol.time();
  }
  const double period = (crossings[3] - crossings[0]) / 3;
  EXPECT_NEAR(period / T1, 1.0, 1e-3);
}

// Second order in dt: halving dt divides the error at t = 5 by 4 (accepted: 3.6–4.4) for
// central difference, the explicit predictor-corrector Newmark (β = 1/4) and the implicit
// Newmark (β = 1/4, γ = 1/2), on x'' + 4x = 0 from x = 1.
TEST(FemDynamics, SecondOrderConvergenceInDt) {
  for (Scheme s : {Scheme::CentralDifference, Scheme::ExplicitNewmark, Scheme::ImplicitNewmark}) {
    const double e1 = oscillator_error(s, 0.02), e2 = oscillator_error(s, 0.01),
                 e3 = oscillator_error(s, 0.005);
    EXPECT_GT(e1 / e2, 3.6) << to_string(s);
    EXPECT_LT(e1 / e2, 4.4) << to_string(s);
    EXPECT_GT(e2 / e3, 3.6) << to_string(s);
    EXPECT_LT(e2 / e3, 4.4) << to_string(s);
    EXPECT_LT(e3, 1e-3) << to_string(s);
  }
}

// The predictor-corrector Newmark of Li, Jin, Wang, Pan & Yang (2023), which that paper calls
// unconditionally stable for β = 1/4, γ = 1/2: with lumped mass it is explicit and stable only
// for ω·dt <= 2 (γ = 1/2) whatever β; the implicit one runs at any dt.
// (β = 1/2 is also bounded below ω·dt = 2 but its amplitude swings grow like 1/√(4 − (ω dt)²)
// near the limit, which the energy check rightly flags; β = 0 and the paper's 1/4 are tested.)
TEST(FemDynamics, PredictorCorrectorNewmarkLimitIsTwoOverOmega) {
  for (double beta : {0.0, 0.25}) {
    SolverSettings s{.scheme = Scheme::ExplicitNewmark, .dt = 0.999, .beta = beta, .allow_unstable = true};
    Solver ok = oscillator(4.0, 1.0, s);  // ω = 2: limit dt = 1
    ok.initialise();
    EXPECT_DOUBLE_EQ(ok.stability().dt_crit, 1.0);
    EXPECT_NO_THROW(ok.advance(20000)) << "beta " << beta;
    s.dt = 1.001;
    Solver bad = oscillator(4.0, 1.0, s);
    bad.initialise();
    EXPECT_THROW(bad.advance(20000), strata::Error) << "beta " << beta;
  }
  SolverSettings s{.scheme = Scheme::ImplicitNewmark, .dt = 50.0};
  Solver imp = oscillator(4.0, 1.0, s);
  imp.initialise();
  EXPECT_TRUE(std::isinf(imp.stability().dt_crit));
  EXPECT_NO_THROW(imp.advance(1000));
  EXPECT_LE(std::abs(imp.u()[1]), 1.0 + 1e-12);  // no energy growth
}

// The explicit step is refused above the limit (Input, naming both numbers) and a forced
// unstable run stops with a Numerical error (blow-up detection).
TEST(FemDynamics, RefuseAndDetectBlowUp) {
  SolverSettings s{.scheme = Scheme::CentralDifference, .dt = 1.01};
  Solver refused = oscillator(4.0, 1.0, s);
  try {
    refused.initialise();
    FAIL() << "dt above the limit was accepted";
  } catch (const strata::Error& e) {
    EXPECT_EQ(e.kind(), strata::ErrorKind::Input);
    EXPECT_NE(std::string(e.what()).find("1.01"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("critical time step 1 s"), std::string::npos) << e.what();
  }
  s.allow_unstable = true;
  Solver forced = oscillator(4.0, 1.0, s);
  forced.initialise();
  try {
    forced.advance(100000);
    FAIL() << "no blow-up detected";
  } catch (const strata::Error& e) {
    EXPECT_EQ(e.kind(), strata::ErrorKind::Numerical);
    EXPECT_LT(forced.steps_done(), 5000);
  }
}

// Rayleigh damping lowers the explicit limit to (2/ω)(√(1+ξ²) − ξ), ξ = α/2ω + βω/2:
// stable just below it, unstable just above (stiffness-proportional ξ = 0.3 at ω = 2).
TEST(FemDynamics, DampingAwareLimit) {
  const double w = 2, beta_r = 0.3;
  const double dtc = explicit_dt_crit(w, 0, beta_r);
  EXPECT_NEAR(dtc, (2 / w) * (std::sqrt(1 + 0.09) - 0.3), 1e-15);
  SolverSettings s{.scheme = Scheme::CentralDifference,
                   .dt = 0.999 * dtc,
                   .rayleigh_beta = beta_r,
                   .allow_unstable = true};
  Solver ok = oscillator(4.0, 1.0, s);
  ok.initialise();
  EXPECT_NEAR(ok.stability().dt_crit, dtc, 1e-12);
  EXPECT_NO_THROW(ok.advance(20000));
  s.dt = 1.01 * dtc;
  Solver bad = oscillator(4.0, 1.0, s);
  bad.initialise();
  EXPECT_THROW(bad.advance(20000), strata::Error);
}

// Element eigenvalues bound the global ω_max from above (dt from them is conservative), the
// Lanczos value matches a dense solve, and h_min/c is NOT conservative for triangles and
// tetrahedra: it exceeds the exact global limit (the exact element limits are 0.67–0.92 of it).
TEST(FemDynamics, CriticalStepElementBoundVersusExactVersusHOverC) {
  const Material tri{.E = 3e10, .nu = 0.25, .rho = 2500, .thickness = 1.0};
  Mesh m2 = rectangle_tri_mesh(6, 4, 1.2, 0.8, tri);
  // perturb interior nodes to make the mesh irregular (deterministic)
  for (std::size_t i = 0; i < m2.nodes(); ++i) {
    const double x = m2.x[0][i], y = m2.x[1][i];
    if (x > 0 && x < 1.2 && y > 0 && y < 0.8) {
      m2.x[0][i] += 0.04 * std::sin(7.0 * i);
      m2.x[1][i] += 0.04 * std::cos(5.0 * i);
    }
  }
  const Material tet{.E = 5e10, .nu = 0.3, .rho = 2700};
  Mesh m3 = box_tet_mesh(3, 3, 2, 1, 1, 0.7, tet);
  for (const Mesh* mesh : {&m2, &m3}) {
    const Assembled sys = assemble(*mesh);
    const double w_bound = std::sqrt(element_omega2_bound(*mesh, sys.mass));
    const Eigen::VectorXd w2 = dense_omega2(sys, {});
    const double w_exact = std::sqrt(w2(w2.size() - 1));
    const LanczosResult lz = omega_max_lanczos(sys.K, sys.mass, {}, 400, 1e-12);
    EXPECT_NEAR(lz.omega_max / w_exact, 1.0, 1e-8) << "dim " << mesh->dim;
    EXPECT_GE(w_bound, w_exact * (1 - 1e-12)) << "dim " << mesh->dim;
    const double dt_exact = 2 / w_exact, dt_bound = 2 / w_bound, dt_hc = h_over_c_dt(*mesh);
    EXPECT_LE(dt_bound, dt_exact);
    EXPECT_GT(dt_hc, dt_exact) << "h/c would be conservative here; dim " << mesh->dim;
    RecordProperty(mesh->dim == 2 ? "tri_bound_over_hc" : "tet_bound_over_hc",
                   std::to_string(dt_bound / dt_hc));
    std::printf("dim %d: dt bound %.4g, exact %.4g, h/c %.4g (exact/(h/c) = %.3f, bound/(h/c) = %.3f)\n",
                mesh->dim, dt_bound, dt_exact, dt_hc, dt_exact / dt_hc, dt_bound / dt_hc);
  }
}

// Spring networks: the element bound with stiffness-weighted mass shares is the Gershgorin
// bound; for a uniform free–fixed chain it gives ω = 2√(k/m) exactly.
TEST(FemDynamics, SpringChainBoundIsGershgorin) {
  const int n = 50;
  std::vector<double> m(n + 1, 0.05);
  std::vector<std::int32_t> si, sj;
  std::vector<double> sk;
  for (int i = 0; i < n; ++i) {
    si.push_back(i);
    sj.push_back(i + 1);
    sk.push_back(7.8e6);
  }
  const Mesh mesh = spring_mass_mesh(m, si, sj, sk);
  const Assembled sys = assemble(mesh);
  std::vector<char> fixed(n + 1, 0);
  fixed[0] = 1;
  const double w = std::sqrt(element_omega2_bound(mesh, sys.mass, fixed));
  EXPECT_NEAR(w, 2 * std::sqrt(7.8e6 / 0.05), 1e-9 * w);
  const double w_exact = std::sqrt(dense_omega2(sys, fixed).maxCoeff());
  EXPECT_LT(w_exact, w);
  EXPECT_NEAR(omega_max_lanczos(sys.K, sys.mass, fixed, 400, 1e-13).omega_max / w_exact, 1.0, 1e-7);
}

// Work accounting of a driven end: a bar whose end DOF is prescribed (moved at a velocity)
// counts the work done through it as the user's, unless it is marked as exchange (driven by
// another partition of a coupled model), and stays so when its value is set again at every
// exchange: a coupled model's energy balance leaves that work out on both sides.
TEST(FemDynamics, ExchangeDofKeepsItsWorkOutOfTheUserWork) {
  const double L = 2.0, c = std::sqrt(kSteel.E / kSteel.rho), dtc = (L / 50) / c;
  for (const bool exchange : {false, true}) {
    Solver sol(bar_mesh(50, L, kSteel, 1),
               SolverSettings{.scheme = Scheme::CentralDifference, .dt = 0.5 * dtc});
    sol.fix(0);
    sol.prescribe(50, 0.0, 0.0);
    if (exchange) sol.mark_exchange(50);
    sol.initialise();
    const double v = 1e-3;  // m/s, pushing the end into the bar
    for (int k = 1; k <= 200; ++k) {
      sol.set_prescribed(50, -v * sol.dt() * k, -v);
      sol.step();
    }
    EXPECT_GT(sol.work_bound(), 0.0);
    if (exchange)
      EXPECT_EQ(sol.user_work(), 0.0);
    else
      EXPECT_NEAR(sol.user_work(), sol.kinetic_energy() + sol.strain_energy(), 0.05 * sol.user_work());
  }
}
