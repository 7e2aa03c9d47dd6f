// The FEM solver's time step before initialise, and its state for checkpoints: everything a
// continued run reads (the matrices and the factorisation are rebuilt from the mesh).
#include <strata/core/error.hpp>
#include <strata/fem/solver.hpp>

#include <cmath>

namespace strata::fem {

void Solver::set_dt(double dt) {
  STRATA_CHECK(!initialised_, Input, "FEM: set_dt() after initialise()");
  STRATA_CHECK(std::isfinite(dt) && dt > 0, Input, "FEM: dt = {} must be finite and > 0 (s)", dt);
  settings_.dt = dt;
  stab_valid_ = false;
}

void Solver::set_scheme(Scheme scheme) {
  STRATA_CHECK(!initialised_, Input, "FEM: set_scheme() after initialise()");
  settings_.scheme = scheme;
  stab_valid_ = false;
}

namespace {
std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }
void from_vector(const std::vector<double>& in, Eigen::VectorXd& v) {
  v = Eigen::Map<const Eigen::VectorXd>(in.data(), static_cast<Eigen::Index>(in.size()));
}
}  // namespace

void Solver::save_state(StateWriter& out, const std::string& prefix) const {
  out.put_scalar<double>(prefix + "time", time_);
  out.put_scalar<std::int64_t>(prefix + "step", step_);
  out.put_scalar<std::int64_t>(prefix + "last_good", last_good_);
  out.put(prefix + "u", to_vector(u_));
  out.put(prefix + "v", to_vector(v_));
  out.put(prefix + "a", to_vector(a_));
  std::vector<double> pre;  // u0, v0, t0 of each prescribed DOF
  for (const Prescribed& p : prescribed_) pre.insert(pre.end(), {p.u0, p.v0, p.t0});
  out.put(prefix + "prescribed", pre);
  out.put_scalar<double>(prefix + "energy0", energy0_);
  out.put_scalar<double>(prefix + "work_abs", work_abs_);
  out.put_scalar<double>(prefix + "user_work", user_work_);
  out.put(prefix + "work_force_prev", work_force_prev_);
  out.put(prefix + "work_u_prev", work_u_prev_);
}

void Solver::load_state(const StateReader& in, const std::string& prefix) {
  STRATA_CHECK(initialised_, Input, "FEM: load_state() before initialise()");
  const auto n = static_cast<std::size_t>(u_.size());
  time_ = in.get_scalar<double>(prefix + "time");
  step_ = in.get_scalar<std::int64_t>(prefix + "step");
  last_good_ = in.get_scalar<std::int64_t>(prefix + "last_good");
  from_vector(in.get<double>(prefix + "u", n), u_);
  from_vector(in.get<double>(prefix + "v", n), v_);
  from_vector(in.get<double>(prefix + "a", n), a_);
  const std::vector<double> pre = in.get<double>(prefix + "prescribed", 3 * prescribed_.size());
  for (std::size_t k = 0; k < prescribed_.size(); ++k) {
    prescribed_[k].u0 = pre[3 * k];
    prescribed_[k].v0 = pre[3 * k + 1];
    prescribed_[k].t0 = pre[3 * k + 2];
  }
  energy0_ = in.get_scalar<double>(prefix + "energy0");
  work_abs_ = in.get_scalar<double>(prefix + "work_abs");
  user_work_ = in.get_scalar<double>(prefix + "user_work");
  work_force_prev_ = in.get<double>(prefix + "work_force_prev", work_force_prev_.size());
  work_u_prev_ = in.get<double>(prefix + "work_u_prev", work_u_prev_.size());
}

}  // namespace strata::fem
