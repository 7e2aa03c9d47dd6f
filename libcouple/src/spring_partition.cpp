#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/couple/spring_partition.hpp>
#include <strata/fem/critical_step.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace strata::couple {

SpringNetworkPartition::SpringNetworkPartition(SpringNetwork net, double dt, std::string name,
                                               bool allow_unstable)
    : net_(std::move(net)), dt_(dt), name_(std::move(name)), allow_unstable_(allow_unstable) {
  const std::size_t n = net_.mass.size();
  STRATA_CHECK(dt > 0 && std::isfinite(dt), Input, "{}: dt = {} must be > 0 (s)", name_, dt);
  STRATA_CHECK(net_.i.size() == net_.j.size() && net_.i.size() == net_.k.size() &&
                   net_.ground_i.size() == net_.ground_k.size(),
               Input, "{}: spring arrays differ in length", name_);
  for (double m : net_.mass) STRATA_CHECK(m > 0, Input, "{}: mass {} kg must be > 0", name_, m);
  for (std::size_t s = 0; s < net_.k.size(); ++s)
    STRATA_CHECK(net_.k[s] > 0 && net_.i[s] >= 0 && net_.j[s] >= 0 &&
                     static_cast<std::size_t>(net_.i[s]) < n && static_cast<std::size_t>(net_.j[s]) < n,
                 Input, "{}: spring {} ({} - {}, k = {}) is invalid", name_, s, net_.i[s], net_.j[s],
                 net_.k[s]);
  u_.assign(n, 0.0);
  v_.assign(n, 0.0);
  a_.assign(n, 0.0);
  f_.assign(n, 0.0);
  external_.assign(n, 0);
}

void SpringNetworkPartition::add_load(std::size_t d, std::function<double(double)> f) {
  STRATA_CHECK(d < dofs(), Input, "{}: load on DOF {} out of range", name_, d);
  loads_.push_back({d, std::move(f)});
}

void SpringNetworkPartition::set_dt(double dt) {
  STRATA_CHECK(!initialised_, Input, "{}: set_dt() after initialise", name_);
  STRATA_CHECK(dt > 0 && std::isfinite(dt), Input, "{}: dt = {} must be > 0 (s)", name_, dt);
  dt_ = dt;
}

void SpringNetworkPartition::make_external(std::size_t d) {
  STRATA_CHECK(!initialised_ && d < dofs(), Input, "{}: make_external({}) after initialise or out of range",
               name_, d);
  if (external_[d]) return;
  external_[d] = 1;
  ext_list_.push_back(d);
  ext_u0_.push_back(0.0);
  ext_v0_.push_back(0.0);
  ext_t0_.push_back(time_);
}

void SpringNetworkPartition::set_external(std::size_t d, double u, double v) {
  const auto it = std::find(ext_list_.begin(), ext_list_.end(), d);
  STRATA_CHECK(it != ext_list_.end(), Input, "{}: DOF {} is not external", name_, d);
  const auto k = static_cast<std::size_t>(it - ext_list_.begin());
  ext_u0_[k] = u;
  ext_v0_[k] = v;
  ext_t0_[k] = time_;
  u_[d] = u;
  v_[d] = v;
  if (initialised_) ext_u_prev_[k] = u;  // a copied value is not work done
}

double SpringNetworkPartition::omega_bound() const {
  std::vector<double> row(dofs(), 0.0);
  for (std::size_t s = 0; s < net_.k.size(); ++s) {
    row[static_cast<std::size_t>(net_.i[s])] += 2 * net_.k[s];
    row[static_cast<std::size_t>(net_.j[s])] += 2 * net_.k[s];
  }
  for (std::size_t s = 0; s < net_.ground_k.size(); ++s)
    row[static_cast<std::size_t>(net_.ground_i[s])] += net_.ground_k[s];
  double w2 = 0;
  for (std::size_t d = 0; d < dofs(); ++d)
    if (!external_[d]) w2 = std::max(w2, row[d] / net_.mass[d]);
  return std::sqrt(w2);
}

double SpringNetworkPartition::critical_dt() const {
  const double w = omega_bound();
  return w > 0 ? 2 / w : std::numeric_limits<double>::infinity();
}

double SpringNetworkPartition::omega_max_exact() const {
  const auto n = static_cast<Eigen::Index>(dofs());
  std::vector<Eigen::Triplet<double>> t;
  for (std::size_t s = 0; s < net_.k.size(); ++s) {
    const int a = net_.i[s], b = net_.j[s];
    const double k = net_.k[s];
    t.emplace_back(a, a, k);
    t.emplace_back(b, b, k);
    t.emplace_back(a, b, -k);
    t.emplace_back(b, a, -k);
  }
  for (std::size_t s = 0; s < net_.ground_k.size(); ++s)
    t.emplace_back(net_.ground_i[s], net_.ground_i[s], net_.ground_k[s]);
  fem::SparseMatrix K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  const Eigen::VectorXd m = Eigen::Map<const Eigen::VectorXd>(net_.mass.data(), n);
  return fem::omega_max_lanczos(K, m, external_, 400, 1e-12).omega_max;
}

void SpringNetworkPartition::forces(double t) {
  std::fill(f_.begin(), f_.end(), 0.0);
  const std::size_t ns = net_.k.size();
  for (std::size_t s = 0; s < ns; ++s) {
    const auto a = static_cast<std::size_t>(net_.i[s]), b = static_cast<std::size_t>(net_.j[s]);
    const double fs = net_.k[s] * (u_[b] - u_[a]);  // tension pulls a towards b
    f_[a] += fs;
    f_[b] -= fs;
  }
  for (std::size_t s = 0; s < net_.ground_k.size(); ++s) {
    const auto a = static_cast<std::size_t>(net_.ground_i[s]);
    f_[a] -= net_.ground_k[s] * u_[a];
  }
  for (const Load& l : loads_)
    if (!external_[l.dof]) f_[l.dof] += l.f(t);
}

double SpringNetworkPartition::energy() const {
  double e = 0;
  for (std::size_t d = 0; d < dofs(); ++d)
    if (!external_[d]) e += 0.5 * net_.mass[d] * v_[d] * v_[d];
  for (std::size_t s = 0; s < net_.k.size(); ++s) {
    const double x = u_[static_cast<std::size_t>(net_.j[s])] - u_[static_cast<std::size_t>(net_.i[s])];
    e += 0.5 * net_.k[s] * x * x;
  }
  for (std::size_t s = 0; s < net_.ground_k.size(); ++s) {
    const double x = u_[static_cast<std::size_t>(net_.ground_i[s])];
    e += 0.5 * net_.ground_k[s] * x * x;
  }
  return e;
}

void SpringNetworkPartition::initialise() {
  const double dtc = critical_dt();
  if (dt_ > dtc) {
    const std::string what = fmt::format(
        "{} partition: dt = {:.4g} s exceeds its critical time step {:.4g} s (ratio {:.3f}; ω_max <= {:.4g} "
        "rad/s, "
        "velocity Verlet)",
        name_, dt_, dtc, dt_ / dtc, omega_bound());
    if (!allow_unstable_) fail(ErrorKind::Input, "{}; lower dt or set allow_unstable", what);
    log::warn("{}: running anyway as asked; the run may blow up", what);
  }
  forces(time_);
  for (std::size_t d = 0; d < dofs(); ++d) a_[d] = external_[d] ? 0.0 : f_[d] / net_.mass[d];
  energy0_ = energy();
  for (Load& l : loads_) {
    l.f_prev = l.f(time_);
    l.u_prev = u_[l.dof];
  }
  ext_f_prev_.assign(ext_list_.size(), 0.0);
  ext_u_prev_.assign(ext_list_.size(), 0.0);
  for (std::size_t k = 0; k < ext_list_.size(); ++k) {
    ext_f_prev_[k] = -f_[ext_list_[k]];
    ext_u_prev_[k] = u_[ext_list_[k]];
  }
  initialised_ = true;
}

void SpringNetworkPartition::step() {
  const std::size_t n = dofs();
  const double h = 0.5 * dt_, t1 = time_ + dt_;
  for (std::size_t d = 0; d < n; ++d) {
    if (external_[d]) continue;
    v_[d] += h * a_[d];
    u_[d] += dt_ * v_[d];
  }
  for (std::size_t k = 0; k < ext_list_.size(); ++k) {
    u_[ext_list_[k]] = ext_u0_[k] + ext_v0_[k] * (t1 - ext_t0_[k]);
    v_[ext_list_[k]] = ext_v0_[k];
  }
  forces(t1);
  for (std::size_t d = 0; d < n; ++d) {
    if (external_[d]) continue;
    a_[d] = f_[d] / net_.mass[d];
    v_[d] += h * a_[d];
  }
  time_ = t1;
  ++step_;
  // work by loads and by the external DOFs (reaction = −spring force there), trapezoidal
  for (Load& l : loads_) {
    if (external_[l.dof]) continue;
    const double fn = l.f(time_), un = u_[l.dof];
    const double w = 0.5 * (fn + l.f_prev) * (un - l.u_prev);
    work_abs_ += std::abs(w);
    load_work_ += w;
    l.f_prev = fn;
    l.u_prev = un;
  }
  for (std::size_t k = 0; k < ext_list_.size(); ++k) {
    const double fn = -f_[ext_list_[k]], un = u_[ext_list_[k]];
    work_abs_ += std::abs(0.5 * (fn + ext_f_prev_[k]) * (un - ext_u_prev_[k]));
    ext_f_prev_[k] = fn;
    ext_u_prev_[k] = un;
  }
  if (step_ % 100 == 0) check_blowup();
}

void SpringNetworkPartition::check_blowup() {
  const double e = energy();
  const double budget = 10 * (energy0_ + work_abs_) + 1e-30;
  if (!(e <= budget))
    fail(ErrorKind::Numerical,
         "{} partition blow-up at step {}, t = {:.6g} s: energy {:.4g} J exceeds {:.4g} J (10 x (initial "
         "{:.4g} J + "
         "work {:.4g} J)); dt = {:.4g} s, critical dt = {:.4g} s; last good step {}",
         name_, step_, time_, e, budget, energy0_, work_abs_, dt_, critical_dt(), last_good_);
  last_good_ = step_;
}

void SpringNetworkPartition::save_state(StateWriter& out, const std::string& prefix) const {
  out.put_scalar<double>(prefix + "time", time_);
  out.put_scalar<std::int64_t>(prefix + "step", step_);
  out.put_scalar<std::int64_t>(prefix + "last_good", last_good_);
  out.put(prefix + "u", u_);
  out.put(prefix + "v", v_);
  out.put(prefix + "a", a_);
  out.put(prefix + "f", f_);
  out.put(prefix + "external_u0", ext_u0_);
  out.put(prefix + "external_v0", ext_v0_);
  out.put(prefix + "external_t0", ext_t0_);
  out.put(prefix + "external_f_prev", ext_f_prev_);
  out.put(prefix + "external_u_prev", ext_u_prev_);
  std::vector<double> loads;  // f_prev, u_prev of each load
  for (const Load& l : loads_) loads.insert(loads.end(), {l.f_prev, l.u_prev});
  out.put(prefix + "loads", loads);
  out.put_scalar<double>(prefix + "energy0", energy0_);
  out.put_scalar<double>(prefix + "work_abs", work_abs_);
  out.put_scalar<double>(prefix + "load_work", load_work_);
}

void SpringNetworkPartition::load_state(const StateReader& in, const std::string& prefix) {
  STRATA_CHECK(initialised_, Input, "{}: load_state() before initialise()", name_);
  const std::size_t n = dofs(), ne = ext_list_.size();
  time_ = in.get_scalar<double>(prefix + "time");
  step_ = in.get_scalar<std::int64_t>(prefix + "step");
  last_good_ = in.get_scalar<std::int64_t>(prefix + "last_good");
  u_ = in.get<double>(prefix + "u", n);
  v_ = in.get<double>(prefix + "v", n);
  a_ = in.get<double>(prefix + "a", n);
  f_ = in.get<double>(prefix + "f", n);
  ext_u0_ = in.get<double>(prefix + "external_u0", ne);
  ext_v0_ = in.get<double>(prefix + "external_v0", ne);
  ext_t0_ = in.get<double>(prefix + "external_t0", ne);
  ext_f_prev_ = in.get<double>(prefix + "external_f_prev", ne);
  ext_u_prev_ = in.get<double>(prefix + "external_u_prev", ne);
  const std::vector<double> loads = in.get<double>(prefix + "loads", 2 * loads_.size());
  for (std::size_t k = 0; k < loads_.size(); ++k) {
    loads_[k].f_prev = loads[2 * k];
    loads_[k].u_prev = loads[2 * k + 1];
  }
  energy0_ = in.get_scalar<double>(prefix + "energy0");
  work_abs_ = in.get_scalar<double>(prefix + "work_abs");
  load_work_ = in.get_scalar<double>(prefix + "load_work");
}

}  // namespace strata::couple
