// Coupled dynamic runs through the general overlap (preprocess::build_coupled_model): a
// libdem lattice with unbreakable bonds (DemPartition) and linear plane-stress triangles
// (FemPartition) with matched elastic constants, exchanging through interpolated links
// (shape functions at DEM externals, least-squares fits at FEM externals).
#include <gtest/gtest.h>
#include <strata/core/clock.hpp>
#include <strata/core/error.hpp>
#include <strata/core/parallel.hpp>
#include <strata/couple/coupler.hpp>
#include <strata/couple/dem_partition.hpp>
#include <strata/couple/fem_partition.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/overlap.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>

using namespace strata;
using couple::Execution;
namespace sp = strata::preprocess;

namespace {

bool verbose() { return std::getenv("STRATA_TEST_VERBOSE") != nullptr; }

// The 2D lattice of the coupled-wave example (unbreakable bonds) and the plane-stress
// continuum it is equivalent to at long wavelengths (thickness t = 1 m): E·t =
// 2√3·Kn(Kn+Ks)/(3Kn+Ks), ν = (Kn−Ks)/(3Kn+Ks), FEM density ρ/t with ρ the lattice's mass per
// area (a disk of diameter d weighs ρ·(√3/2)·d²).
constexpr double kKn = 6.587e10, kKs = 2.371e10, kRho = 2650, kD = 1e-3;
const double kE = 2 * std::sqrt(3.0) * kKn * (kKn + kKs) / (3 * kKn + kKs);
const double kNu = (kKn - kKs) / (3 * kKn + kKs);
const double kC = std::sqrt(kE / ((1 - kNu * kNu) * kRho));  // P-wave speed with u_y = 0
const double kMass = kRho * std::sqrt(3.0) / 2 * kD * kD;
const double kDemDtCrit = 2 / std::sqrt(dem::hex_lattice_lambda_max(kKn, kKs, kMass));

std::filesystem::path data(const std::string& name) {
  return std::filesystem::path(STRATA_SOURCE_DIR) / "tests" / "preprocess" / "data" / name;
}

/// The coupled model of a test geometry (built once): d = 1 mm, a uniform FEM mesh of
/// element size d (the pulse sees no grading); `general` forces the general path.
const sp::OverlapModel& model(const std::string& file, bool general = true) {
  static std::map<std::pair<std::string, bool>, sp::OverlapModel> cache;
  auto it = cache.find({file, general});
  if (it == cache.end()) {
    sp::OverlapOptions o;
    o.d = kD;
    o.far_size = kD;
    o.force_general = general;
    const std::vector<std::string> p{file == "disk_in_square.geo" ? "disk" : "dem"}, f{"fem"};
    it = cache.emplace(std::pair{file, general}, sp::build_coupled_model(data(file), p, f, o)).first;
  }
  return it->second;
}

/// These partitions are small (a few thousand DOFs): one thread for their loops (two
/// threads on two shared cores made a run 40 x slower, OpenMP barriers at every step).
struct OneThread {
  int before = par::threads();
  OneThread() { par::set_threads(1); }
  ~OneThread() { par::set_threads(before); }
};

/// Whether element e belongs to an overlap ring (the particle side's).
bool is_ring(const sp::OverlapModel& m, std::size_t e) {
  return m.method == sp::OverlapMethod::General && m.fem.cell_group[e] >= m.ring_group(0);
}

/// What one run needs.
struct RunSetup {
  double dt_dem = 0.3 * kDemDtCrit;
  int eta = 1;
  Execution mode = Execution::Serial;
  bool rollers = false;             ///< u_y = 0 on y = 0 and y = H (DEM: the lowest and highest rows)
  double pulse_v0 = 0;              ///< > 0: a traction pulse on x = 0 with this particle velocity
  double pulse_length = 20 * kD;    ///< c·T
  std::array<double, 2> v_rigid{};  ///< initial velocity of everything
};

/// The two partitions and the coupler.
struct Run {
  const sp::OverlapModel* m = nullptr;
  std::unique_ptr<couple::FemPartition> fem;
  std::unique_ptr<couple::DemPartition> dem;
  std::unique_ptr<couple::Coupler> cp;
  double fem_explicit_dt = 0;
  std::vector<double> node_mass;  ///< lumped mass of the FEM regions' elements only
};

fem::Mesh fem_mesh(const sp::OverlapModel& m) {
  fem::Mesh mesh;
  mesh.dim = 2;
  for (std::size_t n = 0; n < m.fem.node_count(); ++n) mesh.add_node(m.fem.x[n], m.fem.y[n]);
  fem::ElementBlock b;
  b.type = fem::ElementType::Tri3;
  b.material.E = kE;
  b.material.nu = kNu;
  b.material.rho = kRho;  // ρ/t with t = 1 m
  b.material.thickness = 1;
  b.material.plane = fem::PlaneMode::Stress;
  b.conn.assign(m.fem.cells.begin(), m.fem.cells.end());
  mesh.blocks.push_back(std::move(b));
  return mesh;
}

/// preprocess's point links as libcouple DOF links.
std::vector<couple::Link> links(const sp::OverlapLinks& l) {
  std::vector<couple::Link> point;
  for (std::size_t k = 0; k < l.size(); ++k) {
    couple::Link p{l.source[l.first[k]], l.target[k], {}, {}};
    for (auto j = l.first[k]; j < l.first[k + 1]; ++j)
      p.sources.push_back(l.source[j]), p.weight.push_back(l.weight[j]);
    point.push_back(std::move(p));
  }
  return couple::dof_links(point, 2);
}

std::unique_ptr<Run> make_run(const sp::OverlapModel& m, const RunSetup& s) {
  auto run = std::make_unique<Run>();
  run->m = &m;
  const auto& P = m.particles;
  double ylo = HUGE_VAL, yhi = -HUGE_VAL;
  for (const auto& x : P.x) ylo = std::min(ylo, x[1]), yhi = std::max(yhi, x[1]);
  const double H = m.fem.bounds().hi[1], tol = 1e-6 * kD;

  // DEM: every particle (band sites are driven by the coupler), bonded where they touch
  dem::Settings ds;
  ds.dt = s.dt_dem;
  ds.contact_detection = false;
  dem::Simulation sim(2, ds);
  dem::Material mat;
  mat.density = kRho;
  mat.kn = kKn;
  mat.ks = kKs;
  const int mi = sim.add_material(mat);
  sim.reserve(P.size());
  for (const auto& x : P.x) sim.add_particle(x, P.radius, mi);
  sim.bond_touching_pairs();
  if (s.rollers) {
    std::vector<std::uint32_t> ends;
    for (std::uint32_t i = 0; i < P.size(); ++i)
      if (P.x[i][1] < ylo + tol || P.x[i][1] > yhi - tol) ends.push_back(i);
    sim.add_to_group(ends, "rollers");
    sim.fix("rollers", dem::kY);
  }
  for (std::uint32_t i = 0; i < P.size(); ++i) sim.set_velocity(i, {s.v_rigid[0], s.v_rigid[1], 0});
  run->dem = std::make_unique<couple::DemPartition>(std::move(sim));

  // FEM: the FEM regions and the overlap ring, one material
  const fem::Mesh mesh = fem_mesh(m);
  fem::SolverSettings fs;
  fs.dt = s.eta * s.dt_dem;
  fem::Solver probe(mesh, fs);
  for (std::uint32_t n = 0; n < m.fem.node_count(); ++n)
    if (m.node_tag[n] == sp::OverlapTag::External) probe.prescribe(2 * n), probe.prescribe(2 * n + 1);
  run->fem_explicit_dt = probe.stability().explicit_dt_crit;
  fs.scheme = fs.dt <= run->fem_explicit_dt ? fem::Scheme::CentralDifference : fem::Scheme::ImplicitNewmark;
  fem::Solver solver(mesh, fs);
  if (s.rollers)
    for (std::uint32_t n = 0; n < m.fem.node_count(); ++n)
      if (m.node_tag[n] != sp::OverlapTag::External && (m.fem.y[n] < tol || m.fem.y[n] > H - tol))
        solver.fix(2 * n + 1);
  if (s.v_rigid[0] != 0 || s.v_rigid[1] != 0) {
    Eigen::VectorXd u0 = Eigen::VectorXd::Zero(Eigen::Index(2 * m.fem.node_count())), v0 = u0;
    for (std::size_t n = 0; n < m.fem.node_count(); ++n)
      v0(Eigen::Index(2 * n)) = s.v_rigid[0], v0(Eigen::Index(2 * n + 1)) = s.v_rigid[1];
    solver.set_initial_state(u0, v0);
  }
  if (s.pulse_v0 > 0) {
    // traction σ0·sin²(πt/T) on x = 0, σ0 = ρ·c·v0: a right-going pulse of particle velocity
    // v0; consistent nodal loads (half of each adjacent edge)
    std::vector<std::pair<double, std::uint32_t>> edge;
    for (std::uint32_t n = 0; n < m.fem.node_count(); ++n)
      if (m.fem.x[n] < tol) edge.emplace_back(m.fem.y[n], n);
    std::sort(edge.begin(), edge.end());
    const double sigma0 = kRho * kC * s.pulse_v0, T = s.pulse_length / kC;
    for (std::size_t k = 0; k < edge.size(); ++k) {
      const double len = 0.5 * ((k > 0 ? edge[k].first - edge[k - 1].first : 0) +
                                (k + 1 < edge.size() ? edge[k + 1].first - edge[k].first : 0));
      const double amp = sigma0 * len;
      solver.add_load(2 * edge[k].second, [amp, T](double t) {
        if (t <= 0 || t >= T) return 0.0;
        const double sn = std::sin(M_PI * t / T);
        return amp * sn * sn;
      });
    }
  }
  run->fem = std::make_unique<couple::FemPartition>(std::move(solver));

  // lumped masses of the FEM regions' elements (the ring belongs to the particle side)
  run->node_mass.assign(m.fem.node_count(), 0.0);
  for (std::size_t e = 0; e < m.fem.cell_count(); ++e) {
    if (is_ring(m, e)) continue;
    const double w = kRho * m.fem.cell_measure(e) / 3;
    for (int k = 0; k < 3; ++k) run->node_mass[m.fem.cells[3 * e + std::size_t(k)]] += w;
  }

  couple::Overlap ov;
  ov.fem_to_dem = links(m.fem_to_dem);
  ov.dem_to_fem = links(m.dem_to_fem);
  run->cp = std::make_unique<couple::Coupler>(*run->fem, *run->dem, std::move(ov), s.eta, s.mode);
  run->cp->initialise();
  return run;
}

/// Energy of each side's own domain: the FEM regions' elements (kinetic energy from their
/// lumped masses, strain energy) and the particle regions' particles (kinetic energy with
/// the leapfrog half-step velocity, bonds between them, half of each bond to a band site).
struct Energy {
  double fem = 0, dem = 0;
  double band_kinetic = 0, ring = 0;  ///< diagnostics: energy in the overlap zone, not counted
  double total() const { return fem + dem; }
};

Energy energy(const Run& r) {
  const sp::OverlapModel& m = *r.m;
  Energy out;
  const auto& u = r.fem->solver().u();
  const auto& v = r.fem->solver().v();
  const double f = kE / (1 - kNu * kNu);
  for (std::size_t e = 0; e < m.fem.cell_count(); ++e) {
    const std::uint32_t* c = &m.fem.cells[3 * e];
    double& to = is_ring(m, e) ? out.ring : out.fem;
    for (int k = 0; k < 3; ++k) {  // lumped mass: a third of the element's at each node
      const auto n = Eigen::Index(c[k]);
      to += 0.5 * kRho * m.fem.cell_measure(e) / 3 * (v(2 * n) * v(2 * n) + v(2 * n + 1) * v(2 * n + 1));
    }
    double exx = 0, eyy = 0, gxy = 0;
    const double A2 = 2 * m.fem.cell_measure(e);
    double sgn = 0;
    {
      const double x0 = m.fem.x[c[0]], y0 = m.fem.y[c[0]];
      sgn = ((m.fem.x[c[1]] - x0) * (m.fem.y[c[2]] - y0) - (m.fem.y[c[1]] - y0) * (m.fem.x[c[2]] - x0)) > 0
                ? 1
                : -1;
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = c[k], j = c[(k + 1) % 3], l = c[(k + 2) % 3];
      const double b = sgn * (m.fem.y[j] - m.fem.y[l]), cc = sgn * (m.fem.x[l] - m.fem.x[j]);
      const double ux = u(Eigen::Index(2 * i)), uy = u(Eigen::Index(2 * i + 1));
      exx += b * ux / A2, eyy += cc * uy / A2, gxy += (cc * ux + b * uy) / A2;
    }
    to += 0.5 * A2 / 2 * f * (exx * exx + eyy * eyy + 2 * kNu * exx * eyy + (1 - kNu) / 2 * gxy * gxy);
  }
  const dem::Simulation& sim = r.dem->simulation();
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    const double vx = r.dem->velocity(2 * i), vy = r.dem->velocity(2 * i + 1);
    if (m.particle_region[i] < 0) {
      out.band_kinetic += 0.5 * kMass * (vx * vx + vy * vy);
      continue;
    }
    out.dem += 0.5 * kMass * (vx * vx + vy * vy);
  }
  const auto ids = sim.ids();
  for (const auto& b : sim.bonds()) {
    const int in = (m.particle_region[ids[b.i]] >= 0) + (m.particle_region[ids[b.j]] >= 0);
    out.dem += 0.5 * in * (b.fn * b.fn / (2 * kKn) + b.fs * b.fs / (2 * kKs));
  }
  return out;
}

}  // namespace

// A rigid translation stays a translation: the transfers reproduce affine fields (weights
// sum to 1), so no strain appears anywhere, at η = 1 and 3, through a curved interface.
// Displacements are 30 m/s·t (up to 0.1 mm): FEM element strains and DEM bond strains stay at
// round-off, measured 1e-13 at most; bound 1e-12.
TEST(OverlapCoupling, RigidTranslationStaysATranslation) {
  const OneThread one;
  const sp::OverlapModel& m = model("disk_in_square.geo");
  for (int eta : {1, 3}) {
    RunSetup s;
    s.eta = eta;
    s.v_rigid = {30, -20};
    auto r = make_run(m, s);
    r->cp->run(300 / eta);
    const double t = r->fem->time();
    ASSERT_NEAR(r->dem->time(), t, 1e-12 * t);
    double worst_u = 0, worst_strain = 0;
    for (std::size_t i = 0; i < m.particles.size(); ++i)
      for (int a = 0; a < 2; ++a)
        worst_u = std::max(
            worst_u, std::abs(r->dem->displacement(2 * i + std::size_t(a)) - s.v_rigid[std::size_t(a)] * t));
    const auto& u = r->fem->solver().u();
    for (std::size_t n = 0; n < m.fem.node_count(); ++n)
      for (int a = 0; a < 2; ++a)
        worst_u = std::max(worst_u,
                           std::abs(u(Eigen::Index(2 * n + std::size_t(a))) - s.v_rigid[std::size_t(a)] * t));
    for (std::size_t e = 0; e < m.fem.cell_count(); ++e) {
      const std::uint32_t* c = &m.fem.cells[3 * e];
      for (int k = 0; k < 3; ++k) {  // change of each edge's length over its length
        const auto i = c[k], j = c[(k + 1) % 3];
        const double dx = m.fem.x[j] - m.fem.x[i], dy = m.fem.y[j] - m.fem.y[i];
        const double du = u(Eigen::Index(2 * j)) - u(Eigen::Index(2 * i)),
                     dv = u(Eigen::Index(2 * j + 1)) - u(Eigen::Index(2 * i + 1));
        worst_strain = std::max(
            worst_strain, std::abs(std::hypot(dx + du, dy + dv) - std::hypot(dx, dy)) / std::hypot(dx, dy));
      }
    }
    for (const auto& b : r->dem->simulation().bonds())
      worst_strain = std::max(worst_strain, std::abs(b.fn) / (kKn * kD));
    if (verbose())
      std::printf("eta %d: t = %.3g s, |u - v t| <= %.2e m of %.2e m, strain <= %.2e\n", eta, t, worst_u,
                  30 * t, worst_strain);
    EXPECT_LT(worst_u, 1e-12 * 30 * t);
    EXPECT_LT(worst_strain, 1e-12);
  }
}

namespace {

struct PulseResult {
  Energy incident;                        ///< just after the load ends, all in the FEM region
  Energy crossed;                         ///< after the pulse crossed the interface
  double max_drift = 0;                   ///< max |E(t) − E_incident| / E_incident from then on
  double max_ratio = 0, final_ratio = 0;  ///< long runs: max and last E(t) / E_incident
  std::uint64_t dem_hash = 0;
  std::vector<double> fem_u;
  double seconds = 0;
  std::string scheme;
};

/// A plane pulse (20 d long, v0 = 0.1 m/s) from x = 0 through the inclined interface of
/// inclined_wave.geo (x from 35 to 50 mm; or `geometry`), rollers on the long sides.
PulseResult pulse(int eta, Execution mode, double dt_fraction = 0.3, double long_run = 0,
                  const sp::OverlapModel* geometry = nullptr) {
  const OneThread one;
  const sp::OverlapModel& m = geometry ? *geometry : model("inclined_wave.geo");
  RunSetup s;
  s.eta = eta;
  s.mode = mode;
  s.dt_dem = dt_fraction * kDemDtCrit;
  s.rollers = true;
  s.pulse_v0 = 0.1;
  const auto t0 = WallClock::now();
  auto r = make_run(m, s);
  PulseResult out;
  out.scheme = r->fem->integrator();
  const double dt = eta * s.dt_dem, T = s.pulse_length / kC;
  // the load ends at T; the pulse's tail leaves the interface (x <= 50 mm) at (50 mm + λ)/c,
  // its head reaches the far end (130 mm) at 130 mm/c: measure in between
  const auto n_incident = std::int64_t(std::ceil(1.05 * T / dt));
  const auto n_crossed = std::int64_t(std::ceil((0.05 + s.pulse_length + 0.03) / kC / dt));
  const std::int64_t chunk = std::max<std::int64_t>(1, 10 / eta);
  std::int64_t done = 0;
  r->cp->run(n_incident);
  done = n_incident;
  out.incident = energy(*r);
  while (done < n_crossed) {
    const std::int64_t k = std::min(chunk, n_crossed - done);
    r->cp->run(k);
    done += k;
    const Energy e = energy(*r);
    out.max_drift =
        std::max(out.max_drift, std::abs(e.total() - out.incident.total()) / out.incident.total());
    if (std::getenv("STRATA_TEST_HISTORY"))
      std::printf("  t = %.3e (x_c = %.1f mm): FEM %.5f DEM %.5f total %.5f (band KE %.2e, ring %.2e)\n",
                  r->fem->time(), 1e3 * (kC * r->fem->time() - s.pulse_length / 2),
                  e.fem / out.incident.total(), e.dem / out.incident.total(),
                  e.total() / out.incident.total(), e.band_kinetic / out.incident.total(),
                  e.ring / out.incident.total());
  }
  out.crossed = energy(*r);
  // optionally on, for long_run x the crossing time: the pulse bounces between the free ends,
  // crossing the interface again and again
  const auto n_long = std::int64_t(long_run * double(n_crossed));
  out.max_ratio = 1;
  while (done < n_long) {
    const std::int64_t k = std::min<std::int64_t>(10 * chunk, n_long - done);
    r->cp->run(k);
    done += k;
    const double e = energy(*r).total() / out.incident.total();
    out.max_ratio = std::max(out.max_ratio, e);
    out.final_ratio = e;
    if (std::getenv("STRATA_TEST_HISTORY") && (done / (10 * chunk)) % 10 == 0)
      std::printf("  long: t = %.3e s (%.1f crossings): E/E0 %.4f\n", r->fem->time(),
                  double(done) / double(n_crossed), e);
    if (!std::isfinite(e) || e > 10) break;
  }
  out.seconds = seconds_since(t0);
  out.dem_hash = r->dem->simulation().state_hash();
  out.fem_u.assign(r->fem->solver().u().data(), r->fem->solver().u().data() + r->fem->solver().u().size());
  return out;
}

}  // namespace

// A plane pulse crosses an interface inclined at 63° to it (and to every lattice row) with a
// small reflection. The two sides have the same long-wave impedance, so a continuum would
// reflect nothing; what reflects comes from the lattice's dispersion at 20 d, the strip's
// cross-section (34 lattice rows are 29.44 mm of the FEM's 30 mm: a 1.9 % impedance step
// alone reflects 9e-5 of the energy) and the interpolation. Each side's energy is counted on
// its own domain (FEM regions' elements; particle-region particles and their bonds, half of
// each bond to a band site). Measured at η = 1: reflected R_E = 2.3e-4 of the incident energy
// (bound 1e-3); after the crossing the two sides hold 0.994 of it (bound 1.5 %), steady once
// the overlap zone is quiet (it then holds 1e-6). The scheme is not derived from an energy:
// the deficit is of the order of the impedance step (the box path's copies lose 1.5 % on the
// straight interface below, and giving the FEM strip the lattice's cross-section turns both
// into a surplus of 0.3–1.3 %).
TEST(OverlapCoupling, PlanePulseCrossesAnInclinedInterface) {
  const PulseResult p = pulse(1, Execution::Serial);
  const double E0 = p.incident.total();
  const double R = p.crossed.fem / E0, Tr = p.crossed.dem / E0;
  if (verbose())
    std::printf(
        "eta 1 (%s): incident %.4e J (DEM %.1e), R_E %.3e, T_E %.5f, R_E + T_E %.5f, drift %.2e, %.2f s\n",
        p.scheme.c_str(), E0, p.incident.dem, R, Tr, R + Tr, p.max_drift, p.seconds);
  EXPECT_EQ(p.scheme, "central-difference");
  EXPECT_LT(p.incident.dem, 1e-6 * E0);  // nothing in the particles before the crossing
  EXPECT_LT(R, 1e-3);
  EXPECT_NEAR(R + Tr, 1.0, 1.5e-2);
  EXPECT_LT(p.max_drift, 1.5e-2);
}

// The interpolating overlap against the copying one (box path) on the same straight
// interface: it reflects about as little and loses less energy in the crossing, at η = 1
// and at η = 4 (dt_DEM = 0.3 x the lattice limit, dt_FEM = 1.2 x, implicit Newmark). At
// η > 1 the externals move with the transferred velocity over η·dt_DEM and both overlaps lose
// more. Measured: η = 1 general R_E 2.5e-4, loss 1.0 %; box 2.2e-4, 1.5 %. η = 4 general
// R_E 1.3e-3, loss 6.6 %; box 7.1e-3, 8.5 %.
TEST(OverlapCoupling, InterpolationDoesAsWellAsTheCopy) {
  for (int eta : {1, 4}) {
    const PulseResult g = pulse(eta, Execution::Serial, 0.3, 0, &model("straight_wave.geo", true));
    const PulseResult b = pulse(eta, Execution::Serial, 0.3, 0, &model("straight_wave.geo", false));
    ASSERT_EQ(model("straight_wave.geo", false).method, sp::OverlapMethod::Box);
    const double Rg = g.crossed.fem / g.incident.total(), Rb = b.crossed.fem / b.incident.total();
    const double Lg = 1 - g.crossed.total() / g.incident.total(),
                 Lb = 1 - b.crossed.total() / b.incident.total();
    if (verbose())
      std::printf("eta %d: general R_E %.3e loss %.3e; box R_E %.3e loss %.3e\n", eta, Rg, Lg, Rb, Lb);
    EXPECT_LT(Rg, 1.5 * Rb + 1e-4) << "eta " << eta;
    EXPECT_LT(Lg, Lb + 2e-3) << "eta " << eta;
    EXPECT_GT(Lg, -1e-2) << "eta " << eta;  // no energy made in the crossing
  }
}

// η > 1 on the inclined interface: η = 4 at dt_DEM = 0.3 x the lattice limit (dt_FEM = 1.2 x
// the DEM limit, above the FEM's explicit limit: implicit Newmark). Measured R_E 2.2e-3,
// loss in the crossing 7.4 %; bounds 5e-3 and 12 %.
TEST(OverlapCoupling, EtaAboveOne) {
  const PulseResult p = pulse(4, Execution::Serial);
  const double E0 = p.incident.total();
  const double R = p.crossed.fem / E0, Tr = p.crossed.dem / E0;
  if (verbose())
    std::printf("eta 4 (%s): R_E %.3e, T_E %.5f, R_E + T_E %.5f, drift %.2e, %.2f s\n", p.scheme.c_str(), R,
                Tr, R + Tr, p.max_drift, p.seconds);
  EXPECT_EQ(p.scheme, "implicit-newmark");
  EXPECT_LT(R, 5e-3);
  EXPECT_GT(R + Tr, 0.88);
  EXPECT_LT(R + Tr, 1.0);
}

// The exchange reads both sides at t_n (Jacobi), each side evaluates its own weighted sums:
// serial and parallel runs are identical bit for bit, with the explicit FEM (η = 1) and the
// implicit one (η = 4).
TEST(OverlapCoupling, SerialAndParallelAreBitIdentical) {
  for (int eta : {1, 4}) {
    const PulseResult s = pulse(eta, Execution::Serial), p = pulse(eta, Execution::Parallel);
    EXPECT_EQ(s.dem_hash, p.dem_hash) << "eta " << eta;
    EXPECT_EQ(s.fem_u, p.fem_u) << "eta " << eta;
    EXPECT_EQ(s.crossed.total(), p.crossed.total()) << "eta " << eta;
  }
}

// The stability of the exchange against dt_FEM = η·dt_DEM (run by hand with
// --gtest_also_run_disabled_tests; STRATA_TEST_SWEEP="frac eta runs" runs one point): the
// pulse run continued for 20 crossing times (the pulse bounces between the free ends and
// crosses the interface about 10 times), printing the largest total energy over the
// incident one, for the inclined interface (general path) and the straight one (box path).
TEST(OverlapCoupling, DISABLED_StabilitySweep) {
  std::vector<double> fracs{0.15, 0.3, 0.5};
  std::vector<int> etas{1, 2, 3, 4, 6, 8, 10};
  double long_run = 20;
  if (const char* e = std::getenv("STRATA_TEST_SWEEP")) {  // "frac eta runs"
    fracs = {std::atof(e)};
    etas = {std::atoi(std::strchr(e, ' ') + 1)};
    long_run = std::atof(std::strrchr(e, ' ') + 1);
  }
  for (const bool general : {true, false})
    for (double frac : fracs)
      for (int eta : etas) {
        PulseResult p;
        std::string status = "ok";
        try {
          p = pulse(eta, Execution::Serial, frac, long_run,
                    general ? &model("inclined_wave.geo") : &model("straight_wave.geo", false));
        } catch (const Error& e) {
          status = e.what();
        }
        const double E0 = p.incident.total();
        std::printf(
            "%s: dt_DEM %.2f crit, eta %2d, dt_FEM %.2f x DEM limit (%s): R_E %.2e, crossing loss %.2e, max "
            "E/E0 %.3f %s\n",
            general ? "general, inclined" : "box, straight", frac, eta, eta * frac, p.scheme.c_str(),
            E0 > 0 ? p.crossed.fem / E0 : NAN, E0 > 0 ? 1 - p.crossed.total() / E0 : NAN, p.max_ratio,
            status.substr(0, 80).c_str());
        std::fflush(stdout);
      }
}
