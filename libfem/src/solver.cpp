#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/numbers.hpp>
#include <strata/fem/solver.hpp>
#include <strata/fem/stability.hpp>

#include <Eigen/SparseCholesky>
#include <cmath>
#include <limits>

namespace strata::fem {

std::string to_string(Scheme s) {
  switch (s) {
    case Scheme::CentralDifference:
      return "central-difference";
    case Scheme::ExplicitNewmark:
      return "explicit-newmark";
    case Scheme::ImplicitNewmark:
      return "implicit-newmark";
  }
  return "?";
}

Scheme scheme_from_string(std::string_view s) {
  if (s == "central-difference") return Scheme::CentralDifference;
  if (s == "explicit-newmark" || s == "pc-newmark") return Scheme::ExplicitNewmark;
  if (s == "implicit-newmark") return Scheme::ImplicitNewmark;
  fail(ErrorKind::Input,
       "unknown FEM scheme '{}': use central-difference, explicit-newmark (pc-newmark) or "
       "implicit-newmark",
       s);
}

struct Solver::Factor {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
};

namespace {
constexpr std::size_t kNone = static_cast<std::size_t>(-1);
}

Solver::Solver(Mesh mesh, SolverSettings settings) : mesh_(std::move(mesh)), settings_(settings) {
  const SolverSettings& s = settings_;
  STRATA_CHECK(s.dt > 0 && std::isfinite(s.dt), Input, "FEM dt = {} must be > 0 (s)", s.dt);
  STRATA_CHECK(s.rayleigh_alpha >= 0 && s.rayleigh_beta >= 0, Input,
               "Rayleigh damping alpha = {} (1/s), beta = {} (s) must be >= 0", s.rayleigh_alpha,
               s.rayleigh_beta);
  STRATA_CHECK(s.check_every > 0, Input, "check_every = {} must be > 0", s.check_every);
  if (s.scheme == Scheme::ExplicitNewmark)
    STRATA_CHECK(
        s.gamma == 0.5 && s.beta >= 0 && s.beta <= 0.5, Input,
        "explicit predictor-corrector Newmark needs gamma = 1/2 (second order) and 0 <= beta <= 1/2; got "
        "beta = {}, gamma = {}",
        s.beta, s.gamma);
  if (s.scheme == Scheme::ImplicitNewmark)
    STRATA_CHECK(s.gamma >= 0.5 && s.beta > 0, Input,
                 "implicit Newmark needs gamma >= 1/2 and beta > 0; got {} {}", s.beta, s.gamma);
  sys_ = assemble(mesh_);
  const auto n = static_cast<std::size_t>(sys_.K.rows());
  is_prescribed_.assign(n, 0);
  prescribed_index_.assign(n, kNone);
  u_ = v_ = a_ = f_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
}

const StabilityInfo& Solver::stability() const {
  if (stab_valid_) return stab_;
  const SolverSettings& s = settings_;
  stab_.dt = s.dt;
  try {
    stab_.omega_bound = std::sqrt(element_omega2_bound(mesh_, sys_.mass, is_prescribed_));
  } catch (const Error&) {
    if (is_explicit(s.scheme)) throw;
    stab_.omega_bound = std::numeric_limits<double>::quiet_NaN();  // massless nodes: implicit only
  }
  stab_.explicit_dt_crit = explicit_dt_crit(stab_.omega_bound, s.rayleigh_alpha, s.rayleigh_beta);
  stab_.dt_crit = is_explicit(s.scheme)   ? stab_.explicit_dt_crit
                  : 2 * s.beta >= s.gamma ? std::numeric_limits<double>::infinity()
                                          : newmark_dt_crit(stab_.omega_bound, s.beta, s.gamma);
  stab_valid_ = true;
  return stab_;
}

Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;
Solver& Solver::operator=(Solver&&) noexcept = default;

void Solver::fix(std::size_t d) { prescribe(d, 0.0, 0.0); }

void Solver::mark_exchange(std::size_t d) {
  STRATA_CHECK(d < is_prescribed_.size() && is_prescribed_[d], Input,
               "FEM: mark_exchange({}): the DOF is not prescribed", d);
  prescribed_[prescribed_index_[d]].exchange = true;
}

void Solver::prescribe(std::size_t d, double u, double v) {
  STRATA_CHECK(!initialised_, Input, "FEM: prescribed DOFs must be declared before initialise()");
  STRATA_CHECK(d < is_prescribed_.size(), Input, "FEM: DOF {} out of range (model has {} DOFs)", d,
               is_prescribed_.size());
  if (!is_prescribed_[d]) {
    stab_valid_ = false;
    is_prescribed_[d] = 1;
    prescribed_index_[d] = prescribed_.size();
    prescribed_.push_back({d, u, v, time_});
  } else {
    Prescribed& p = prescribed_[prescribed_index_[d]];
    p = {d, u, v, time_, p.exchange};
  }
  u_[static_cast<Eigen::Index>(d)] = u;
  v_[static_cast<Eigen::Index>(d)] = v;
}

void Solver::add_load(std::size_t d, std::function<double(double)> f) {
  STRATA_CHECK(d < is_prescribed_.size(), Input, "FEM: load on DOF {} out of range ({} DOFs)", d,
               is_prescribed_.size());
  loads_.push_back({d, std::move(f)});
}

void Solver::set_initial_state(const Eigen::VectorXd& u0, const Eigen::VectorXd& v0) {
  STRATA_CHECK(!initialised_ && u0.size() == u_.size() && v0.size() == v_.size(), Input,
               "FEM: initial state must have {} entries and be set before initialise()", u_.size());
  for (Eigen::Index i = 0; i < u_.size(); ++i)
    if (!is_prescribed_[static_cast<std::size_t>(i)]) {
      u_[i] = u0[i];
      v_[i] = v0[i];
    }
}

void Solver::check_dt() {
  const SolverSettings& s = settings_;
  stability();
  if (!(s.dt > stab_.dt_crit)) return;
  const auto [dt_text, crit_text] = distinct_pair(s.dt, stab_.dt_crit);
  const std::string what = fmt::format(
      "FEM dt = {} s exceeds the critical time step {} s of the {} scheme (ratio {}; ω_max <= "
      "{:.4g} "
      "rad/s from element eigenvalues{})",
      dt_text, crit_text, to_string(s.scheme), ratio_text(s.dt, stab_.dt_crit), stab_.omega_bound,
      s.rayleigh_alpha > 0 || s.rayleigh_beta > 0 ? ", with Rayleigh damping" : "");
  if (!s.allow_unstable)
    fail(ErrorKind::Input,
         "{}; lower dt to <= {:.4g} s, use implicit-newmark (beta = 1/4, gamma = 1/2), or set "
         "allow_unstable",
         what, stab_.dt_crit);
  log::warn("{}: running anyway as asked; the run may blow up", what);
}

void Solver::initialise() {
  check_dt();
  const Eigen::Index n = u_.size();
  inv_mass_ = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (is_prescribed_[static_cast<std::size_t>(i)]) continue;
    if (is_explicit(settings_.scheme))
      STRATA_CHECK(sys_.mass[i] > 0, Input,
                   "FEM: free DOF {} has no mass; explicit schemes need mass on every DOF", i);
    inv_mass_[i] = sys_.mass[i] > 0 ? 1 / sys_.mass[i] : 0.0;
  }
  const double dt = settings_.dt, al = settings_.rayleigh_alpha, br = settings_.rayleigh_beta;
  if (settings_.scheme == Scheme::ImplicitNewmark) {
    // A = (1 + γ dt α) M + (γ dt β_R + β dt²) K, prescribed rows/columns replaced by identity
    const double g = settings_.gamma, b = settings_.beta;
    const double cm = 1 + g * dt * al, ck = g * dt * br + b * dt * dt;
    Eigen::SparseMatrix<double> A = ck * sys_.K;
    A.prune([&](Eigen::Index r, Eigen::Index c, double) {
      return !is_prescribed_[static_cast<std::size_t>(r)] && !is_prescribed_[static_cast<std::size_t>(c)];
    });
    Eigen::SparseMatrix<double> D(n, n);
    std::vector<Eigen::Triplet<double>> diag;
    for (Eigen::Index i = 0; i < n; ++i)
      diag.emplace_back(i, i, is_prescribed_[static_cast<std::size_t>(i)] ? 1.0 : cm * sys_.mass[i]);
    D.setFromTriplets(diag.begin(), diag.end());
    A += D;
    factor_ = std::make_unique<Factor>();
    factor_->ldlt.compute(A);
    STRATA_CHECK(
        factor_->ldlt.info() == Eigen::Success, Numerical,
        "FEM: factorising M + γ dt C + β dt² K failed (is the model held against rigid motion or massive?)");
  }
  // initial acceleration a0 = M⁻¹(F(0) − K u0 − C v0) on free DOFs
  loads_at(time_, f_);
  w1_ = u_ + br * v_;
  f_ -= sys_.K * w1_;
  f_ -= al * sys_.mass.cwiseProduct(v_);
  a_ = inv_mass_.cwiseProduct(f_);
  energy0_ = kinetic_energy() + strain_energy();
  double kdiag = 0;
  for (Eigen::Index i = 0; i < n; ++i) kdiag = std::max(kdiag, sys_.K.coeff(i, i));
  energy_tiny_ = 1e-30 * std::max(kdiag, 1.0);
  work_force_prev_.clear();
  work_u_prev_.clear();
  for (const Load& l : loads_) {
    work_force_prev_.push_back(l.f(time_));
    work_u_prev_.push_back(u_[static_cast<Eigen::Index>(l.dof)]);
  }
  for (const Prescribed& p : prescribed_) {
    work_force_prev_.push_back(sys_.K.row(static_cast<Eigen::Index>(p.dof)).dot(u_));
    work_u_prev_.push_back(u_[static_cast<Eigen::Index>(p.dof)]);
  }
  initialised_ = true;
  last_good_ = step_;
}

void Solver::set_prescribed(std::size_t d, double u, double v) {
  STRATA_CHECK(d < is_prescribed_.size() && is_prescribed_[d], Input,
               "FEM: DOF {} is not prescribed; declare it with prescribe() before initialise()", d);
  const std::size_t k = prescribed_index_[d];
  prescribed_[k] = {d, u, v, time_, prescribed_[k].exchange};  // still exchange if marked so
  u_[static_cast<Eigen::Index>(d)] = u;
  v_[static_cast<Eigen::Index>(d)] = v;
  if (initialised_) work_u_prev_[loads_.size() + k] = u;  // a copied value is not work done
}

void Solver::apply_prescribed(double t, Eigen::VectorXd& u, Eigen::VectorXd& v) {
  for (const Prescribed& p : prescribed_) {
    const auto d = static_cast<Eigen::Index>(p.dof);
    u[d] = p.u0 + p.v0 * (t - p.t0);
    v[d] = p.v0;
  }
}

void Solver::loads_at(double t, Eigen::VectorXd& f) const {
  f.setZero();
  for (const Load& l : loads_) f[static_cast<Eigen::Index>(l.dof)] += l.f(t);
}

void Solver::step() {
  STRATA_CHECK(initialised_, Input, "FEM: step() before initialise()");
  const double dt = settings_.dt, al = settings_.rayleigh_alpha, br = settings_.rayleigh_beta;
  const double t1 = time_ + dt;
  const Eigen::VectorXd& M = sys_.mass;
  switch (settings_.scheme) {
    case Scheme::CentralDifference: {
      v_ += (0.5 * dt) * a_;  // v_{n+1/2}
      apply_prescribed(t1, u_, v_);
      for (Eigen::Index i = 0; i < u_.size(); ++i)
        if (!is_prescribed_[static_cast<std::size_t>(i)]) u_[i] += dt * v_[i];
      loads_at(t1, f_);
      w1_ = u_ + br * v_;
      f_ -= sys_.K * w1_;
      if (al != 0) f_ -= al * M.cwiseProduct(v_);
      a_ = inv_mass_.cwiseProduct(f_);
      v_ += (0.5 * dt) * a_;
      break;
    }
    case Scheme::ExplicitNewmark:
    case Scheme::ImplicitNewmark: {
      const double b = settings_.beta, g = settings_.gamma;
      u_ += dt * v_ + (dt * dt * (0.5 - b)) * a_;  // predictors ũ, ṽ
      v_ += (dt * (1 - g)) * a_;
      apply_prescribed(t1, u_, v_);
      loads_at(t1, f_);
      w1_ = u_ + br * v_;
      f_ -= sys_.K * w1_;
      if (al != 0) f_ -= al * M.cwiseProduct(v_);
      if (settings_.scheme == Scheme::ExplicitNewmark) {
        a_ = inv_mass_.cwiseProduct(f_);
      } else {
        for (const Prescribed& p : prescribed_) f_[static_cast<Eigen::Index>(p.dof)] = 0;
        a_ = factor_->ldlt.solve(f_);
        for (const Prescribed& p : prescribed_) a_[static_cast<Eigen::Index>(p.dof)] = 0;
      }
      u_ += (b * dt * dt) * a_;  // correctors
      v_ += (g * dt) * a_;
      break;
    }
  }
  time_ = t1;
  ++step_;
  // work done on the model (loads and prescribed DOFs), trapezoidal, summed in absolute value
  std::size_t k = 0;
  for (const Load& l : loads_) {
    const double fnew = l.f(time_), unew = u_[static_cast<Eigen::Index>(l.dof)];
    const double dw = 0.5 * (fnew + work_force_prev_[k]) * (unew - work_u_prev_[k]);
    work_abs_ += std::abs(dw);
    user_work_ += dw;
    work_force_prev_[k] = fnew;
    work_u_prev_[k++] = unew;
  }
  for (const Prescribed& p : prescribed_) {
    const double unew = u_[static_cast<Eigen::Index>(p.dof)];
    if (unew != work_u_prev_[k] || p.v0 != 0) {
      const double fnew = sys_.K.row(static_cast<Eigen::Index>(p.dof)).dot(u_);
      const double dw = 0.5 * (fnew + work_force_prev_[k]) * (unew - work_u_prev_[k]);
      work_abs_ += std::abs(dw);
      if (!p.exchange) user_work_ += dw;
      work_force_prev_[k] = fnew;
      work_u_prev_[k] = unew;
    }
    ++k;
  }
  if (step_ % settings_.check_every == 0) check_blowup();
}

void Solver::advance(std::int64_t steps) {
  for (std::int64_t i = 0; i < steps; ++i) step();
}

void Solver::check_blowup() {
  const double e = u_.allFinite() && v_.allFinite() ? kinetic_energy() + strain_energy()
                                                    : std::numeric_limits<double>::infinity();
  const double budget = settings_.energy_factor * (energy0_ + work_abs_) + energy_tiny_;
  if (!(e <= budget))
    fail(ErrorKind::Numerical,
         "FEM blow-up at step {}, t = {:.6g} s: energy {:.4g} J exceeds {:.4g} J ({} x (initial {:.4g} J + "
         "work "
         "{:.4g} J)); dt = {:.4g} s, explicit critical dt = {:.4g} s, scheme {}; last good step {}",
         step_, time_, e, budget, settings_.energy_factor, energy0_, work_abs_, settings_.dt,
         stab_.explicit_dt_crit, to_string(settings_.scheme), last_good_);
  last_good_ = step_;
}

double Solver::kinetic_energy() const {
  double e = 0;
  for (Eigen::Index i = 0; i < v_.size(); ++i)
    if (!is_prescribed_[static_cast<std::size_t>(i)]) e += sys_.mass[i] * v_[i] * v_[i];
  return 0.5 * e;
}

double Solver::strain_energy() const { return 0.5 * u_.dot(sys_.K * u_); }

LanczosResult Solver::omega_max_exact(int max_iterations) const {
  return omega_max_lanczos(sys_.K, sys_.mass, is_prescribed_, max_iterations);
}

Eigen::VectorXd static_solve(const Assembled& sys, const std::vector<char>& prescribed,
                             const Eigen::VectorXd& u_prescribed, const Eigen::VectorXd& f) {
  const Eigen::Index n = sys.K.rows();
  STRATA_CHECK(static_cast<Eigen::Index>(prescribed.size()) == n && u_prescribed.size() == n && f.size() == n,
               Input, "static_solve: vectors must have {} entries", n);
  Eigen::VectorXd up = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (prescribed[static_cast<std::size_t>(i)]) up[i] = u_prescribed[i];
  Eigen::VectorXd rhs = f - sys.K * up;
  Eigen::SparseMatrix<double> A = sys.K;
  A.prune([&](Eigen::Index r, Eigen::Index c, double) {
    return !prescribed[static_cast<std::size_t>(r)] && !prescribed[static_cast<std::size_t>(c)];
  });
  for (Eigen::Index i = 0; i < n; ++i)
    if (prescribed[static_cast<std::size_t>(i)]) {
      A.coeffRef(i, i) = 1;
      rhs[i] = 0;
    }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
  STRATA_CHECK(ldlt.info() == Eigen::Success, Input,
               "static_solve: the stiffness matrix is singular (is the model held against rigid motion?)");
  Eigen::VectorXd u = ldlt.solve(rhs);
  for (Eigen::Index i = 0; i < n; ++i)
    if (prescribed[static_cast<std::size_t>(i)]) u[i] = up[i];
  return u;
}

}  // namespace strata::fem
