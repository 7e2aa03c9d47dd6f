#include <strata/core/error.hpp>
#include <strata/couple/chains.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace strata::couple {

std::size_t CoupledChain::fem_local(std::int64_t g) const {
  const auto it = std::find(fem_global.begin(), fem_global.end(), g);
  STRATA_CHECK(it != fem_global.end(), Input, "node {} is not in the FEM partition", g);
  return static_cast<std::size_t>(it - fem_global.begin());
}
std::size_t CoupledChain::dem_local(std::int64_t g) const {
  const auto it = std::find(dem_global.begin(), dem_global.end(), g);
  STRATA_CHECK(it != dem_global.end(), Input, "node {} is not in the DEM partition", g);
  return static_cast<std::size_t>(it - dem_global.begin());
}

namespace {

// FEM mesh of a set of nodes: spring elements + point masses, plus one fixed wall node when
// ground springs are present. Returns the wall node id (or -1).
fem::Mesh network_mesh(const SpringNetwork& net, const std::vector<std::int64_t>& nodes,
                       const std::unordered_map<std::int64_t, std::int32_t>& local, std::int32_t& wall) {
  std::vector<double> masses;
  for (std::int64_t g : nodes) masses.push_back(net.mass[static_cast<std::size_t>(g)]);
  std::vector<std::int32_t> si, sj;
  std::vector<double> sk;
  for (std::size_t s = 0; s < net.k.size(); ++s) {
    const auto a = local.find(net.i[s]), b = local.find(net.j[s]);
    if (a == local.end() || b == local.end()) continue;
    si.push_back(a->second);
    sj.push_back(b->second);
    sk.push_back(net.k[s]);
  }
  wall = -1;
  for (std::size_t s = 0; s < net.ground_k.size(); ++s) {
    const auto a = local.find(net.ground_i[s]);
    if (a == local.end()) continue;
    if (wall < 0) {
      wall = static_cast<std::int32_t>(masses.size());
      masses.push_back(0.0);
    }
    si.push_back(wall);
    sj.push_back(a->second);
    sk.push_back(net.ground_k[s]);
  }
  return fem::spring_mass_mesh(masses, si, sj, sk);
}

}  // namespace

CoupledChain split_chain(const ChainModel& model, const std::vector<std::int64_t>& fem_nodes,
                         const std::vector<std::int64_t>& dem_nodes, const SplitSettings& s) {
  const SpringNetwork& net = model.net;
  const auto n = static_cast<std::int64_t>(net.mass.size());
  std::vector<char> inF(static_cast<std::size_t>(n), 0), inD(static_cast<std::size_t>(n), 0);
  for (std::int64_t g : fem_nodes) {
    STRATA_CHECK(g >= 0 && g < n, Input, "split_chain: FEM node {} out of range", g);
    inF[static_cast<std::size_t>(g)] = 1;
  }
  for (std::int64_t g : dem_nodes) {
    STRATA_CHECK(g >= 0 && g < n, Input, "split_chain: DEM node {} out of range", g);
    inD[static_cast<std::size_t>(g)] = 1;
  }
  // which overlap nodes touch FEM-only or DEM-only nodes
  std::vector<char> touchF(static_cast<std::size_t>(n), 0), touchD(static_cast<std::size_t>(n), 0);
  for (std::size_t sp = 0; sp < net.k.size(); ++sp) {
    const auto a = static_cast<std::size_t>(net.i[sp]), b = static_cast<std::size_t>(net.j[sp]);
    const bool fa = inF[a] && !inD[a], fb = inF[b] && !inD[b], da = inD[a] && !inF[a], db = inD[b] && !inF[b];
    STRATA_CHECK(
        !((fa && db) || (da && fb)), Input,
        "split_chain: spring {}-{} joins an FEM-only and a DEM-only node; the partitions must overlap by one "
        "layer",
        a, b);
    if (fb) touchF[a] = 1;
    if (fa) touchF[b] = 1;
    if (db) touchD[a] = 1;
    if (da) touchD[b] = 1;
  }
  auto role_of = [&](std::int64_t g, bool fem_side) {
    const auto i = static_cast<std::size_t>(g);
    if (!(inF[i] && inD[i])) return Role::Internal;
    STRATA_CHECK(
        !(touchF[i] && touchD[i]), Input,
        "split_chain: overlap node {} touches both FEM-only and DEM-only nodes (overlap thinner than one "
        "layer)",
        g);
    const bool fem_external = touchD[i] != 0;  // linked to the DEM interior: the DEM owns it
    return fem_side ? (fem_external ? Role::External : Role::Boundary)
                    : (fem_external ? Role::Boundary : Role::External);
  };
  CoupledChain c;
  c.fem_global = fem_nodes;
  c.dem_global = dem_nodes;
  for (std::int64_t g : fem_nodes) c.fem_roles.push_back(role_of(g, true));
  for (std::int64_t g : dem_nodes) c.dem_roles.push_back(role_of(g, false));
  c.overlap = make_overlap(c.fem_global, c.fem_roles, c.dem_global, c.dem_roles);

  // FEM partition (libfem)
  std::unordered_map<std::int64_t, std::int32_t> floc, dloc;
  for (std::size_t k = 0; k < fem_nodes.size(); ++k) floc[fem_nodes[k]] = static_cast<std::int32_t>(k);
  for (std::size_t k = 0; k < dem_nodes.size(); ++k) dloc[dem_nodes[k]] = static_cast<std::int32_t>(k);
  std::int32_t wall = -1;
  fem::Mesh mesh = network_mesh(net, fem_nodes, floc, wall);
  fem::SolverSettings fs;
  fs.scheme = s.fem_scheme;
  fs.dt = s.eta * s.dt_dem;
  fs.allow_unstable = s.allow_unstable;
  fem::Solver solver(std::move(mesh), fs);
  if (wall >= 0) solver.fix(static_cast<std::size_t>(wall));
  // DEM partition (spring network, velocity Verlet)
  SpringNetwork dn;
  for (std::int64_t g : dem_nodes) dn.mass.push_back(net.mass[static_cast<std::size_t>(g)]);
  for (std::size_t sp = 0; sp < net.k.size(); ++sp) {
    const auto a = dloc.find(net.i[sp]), b = dloc.find(net.j[sp]);
    if (a != dloc.end() && b != dloc.end()) dn.add_spring(a->second, b->second, net.k[sp]);
  }
  for (std::size_t sp = 0; sp < net.ground_k.size(); ++sp) {
    const auto a = dloc.find(net.ground_i[sp]);
    if (a != dloc.end()) dn.add_ground_spring(a->second, net.ground_k[sp]);
  }
  auto dem = std::make_unique<SpringNetworkPartition>(std::move(dn), s.dt_dem, "DEM", s.allow_unstable);
  // loads go to the partition that owns the node
  for (const SineLoad& l : model.loads) {
    const auto gi = static_cast<std::int64_t>(l.node);
    if (floc.count(gi) && role_of(gi, true) != Role::External)
      solver.add_load(static_cast<std::size_t>(floc[gi]), l);
    else if (dloc.count(gi) && role_of(gi, false) != Role::External)
      dem->add_load(static_cast<std::size_t>(dloc[gi]), l);
    else
      fail(ErrorKind::Input, "split_chain: load on node {} that no partition owns", l.node);
  }
  c.fem = std::make_unique<FemPartition>(std::move(solver), "FEM");
  c.dem = std::move(dem);
  return c;
}

fem::Solver monolithic_solver(const ChainModel& model, const fem::SolverSettings& s) {
  std::vector<std::int64_t> all(model.net.mass.size());
  std::unordered_map<std::int64_t, std::int32_t> loc;
  for (std::size_t k = 0; k < all.size(); ++k) {
    all[k] = static_cast<std::int64_t>(k);
    loc[all[k]] = static_cast<std::int32_t>(k);
  }
  std::int32_t wall = -1;
  fem::Solver solver(network_mesh(model.net, all, loc, wall), s);
  if (wall >= 0) solver.fix(static_cast<std::size_t>(wall));
  for (const SineLoad& l : model.loads) solver.add_load(l.node, l);
  return solver;
}

// ---- 6-DOF chain ----------------------------------------------------------------------

namespace {
constexpr double kChainOmega = M_PI / 2;  // forcing frequency Ω (rad/s)
constexpr double kChainP = 1.0;           // force amplitude (N)
}  // namespace

ChainModel chain6_model() {
  ChainModel m;
  m.net.mass.assign(6, 1.0);
  m.net.add_ground_spring(0, 1.0);                                                         // k1: wall–m1
  for (int i = 0; i < 5; ++i) m.net.add_spring(i, i + 1, 1.0);                             // k2..k6
  m.loads.push_back({.node = 1, .amplitude = kChainP, .period = 2 * M_PI / kChainOmega});  // on m2
  return m;
}

Chain6Exact::Chain6Exact() {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(6, 6);
  K(0, 0) = 1;  // k1 to the wall
  for (int i = 0; i < 5; ++i) {
    K(i, i) += 1;
    K(i + 1, i + 1) += 1;
    K(i, i + 1) = K(i + 1, i) = -1;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(K);  // M = I: orthonormal modes
  phi_ = es.eigenvectors();
  w_ = es.eigenvalues().cwiseSqrt();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(6);
  f[1] = kChainP;
  p_ = phi_.transpose() * f;
}

double Chain6Exact::u(int i, double t) const {
  // q_j'' + ω_j² q_j = p_j sin Ωt, q_j(0) = q_j'(0) = 0 (Ω is no natural frequency here)
  const double W = kChainOmega;
  double u = 0;
  for (int j = 0; j < 6; ++j) {
    const double wj = w_[j];
    const double q = p_[j] / (wj * wj - W * W) * (std::sin(W * t) - (W / wj) * std::sin(wj * t));
    u += phi_(i, j) * q;
  }
  return u;
}

// ---- metamaterial chain --------------------------------------------------------------

namespace {
constexpr int kOuter = 800, kResonators = 200, kFirstResonator = 100;  // outer 101..300 (0-based 100..299)
constexpr double kMs = 0.05, kKn = 7.8e6, kMv = 0.05, kKs = 2.49e6;
constexpr int kFemOuter = 300;  // outer masses 1..300 in the FEM partition
}  // namespace

ChainModel metamaterial_model(const MetamaterialParams& p) {
  STRATA_CHECK(p.pulse_duration > 0 && std::isfinite(p.pulse_amplitude), Input,
               "pulse duration {} s must be > 0", p.pulse_duration);
  ChainModel m;
  m.net.mass.assign(kOuter, kMs);
  m.net.mass.resize(kOuter + kResonators, kMv);
  for (int i = 0; i + 1 < kOuter; ++i) m.net.add_spring(i, i + 1, kKn);
  m.net.add_ground_spring(kOuter - 1, kKn);  // outer mass 800 tied to a wall
  for (int r = 0; r < kResonators; ++r) m.net.add_spring(kFirstResonator + r, kOuter + r, kKs);
  const double A = p.pulse_amplitude, T = p.pulse_duration;
  m.loads.push_back({.node = 0, .amplitude = A, .period = 2 * T, .end = T});
  return m;
}

std::vector<std::int64_t> metamaterial_fem_nodes() {
  std::vector<std::int64_t> v;
  for (int i = 0; i <= kFemOuter; ++i) v.push_back(i);  // outer 1..301 (301 external)
  for (int r = 0; r < kResonators; ++r) v.push_back(kOuter + r);
  return v;
}

std::vector<std::int64_t> metamaterial_dem_nodes() {
  std::vector<std::int64_t> v;
  for (int i = kFemOuter - 1; i < kOuter; ++i) v.push_back(i);  // outer 300 (external) .. 800
  return v;
}

std::int64_t metamaterial_dem_mass(int n) { return kFemOuter + n - 1; }

MetamaterialStability metamaterial_stability() {
  MetamaterialStability s;
  const ChainModel m = metamaterial_model();
  fem::Solver whole =
      monolithic_solver(m, fem::SolverSettings{.scheme = fem::Scheme::ImplicitNewmark, .dt = 1e-6});
  s.omega_whole = whole.omega_max_exact(600).omega_max;
  s.dt_whole = 2 / s.omega_whole;
  s.omega_whole_bound = whole.stability().omega_bound;
  CoupledChain c =
      split_chain(m, metamaterial_fem_nodes(), metamaterial_dem_nodes(),
                  SplitSettings{.dt_dem = 1e-6, .eta = 1, .fem_scheme = fem::Scheme::ImplicitNewmark});
  for (const Link& l : c.overlap.fem_to_dem) c.dem->make_external(l.to);
  for (const Link& l : c.overlap.dem_to_fem) c.fem->make_external(l.to);
  s.omega_dem = c.dem->omega_bound();
  s.dt_dem_crit = c.dem->critical_dt();
  s.omega_fem = c.fem->solver().omega_max_exact(600).omega_max;
  s.dt_fem_explicit = 2 / s.omega_fem;
  return s;
}

std::string MetamaterialStability::text(double dt_dem) const {
  return fmt::format(
      "metamaterial chain: dt_DEM = {:.4g} s\n"
      "  whole chain: omega_max = {:.4g} rad/s (exact, Lanczos; element bound {:.4g}) -> explicit limit "
      "{:.4g} s\n"
      "  DEM partition alone (plain chain, omega_max = 2*sqrt(k_n/m_s) = {:.4g} rad/s) -> limit {:.4g} s\n"
      "  FEM partition (resonators, externals held): omega_max = {:.4g} rad/s -> explicit limit {:.4g} s",
      dt_dem, omega_whole, omega_whole_bound, dt_whole, omega_dem, dt_dem_crit, omega_fem, dt_fem_explicit);
}

void check_metamaterial_dt(double dt_dem, bool allow_unstable) {
  const MetamaterialStability s = metamaterial_stability();
  if (dt_dem <= s.dt_dem_crit && dt_dem <= s.dt_whole) return;
  const std::string msg = fmt::format(
      "dt_DEM = {:.4g} s is unstable for any explicit scheme: the stable limit is {:.3g} s for the whole "
      "chain "
      "(omega_max = {:.3g} rad/s) and {:.3g} s for the DEM partition alone (omega_max = 2*sqrt(k_n/m_s) = "
      "{:.3g} "
      "rad/s); use dt_DEM <= {:.3g} s\n{}",
      dt_dem, s.dt_whole, s.omega_whole, s.dt_dem_crit, s.omega_dem, std::min(s.dt_whole, s.dt_dem_crit),
      s.text(dt_dem));
  if (dt_dem > s.dt_dem_crit && !allow_unstable) fail(ErrorKind::Input, "{}", msg);
  if (dt_dem > s.dt_whole && !allow_unstable)
    fail(ErrorKind::Input,
         "{}\n  (a coupled run with an implicit FEM partition may still run: the DEM partition "
         "alone is within its limit)",
         msg);
}

}  // namespace strata::couple
