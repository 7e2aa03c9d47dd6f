#pragma once
/// DEM-side partition for chains and spring networks: point masses with one DOF each,
/// linear springs between DOFs and to the ground, nodal loads, integrated by velocity Verlet
/// (the libdem integrator, and the DEM integrator of Li, Jin, Wang, Pan & Yang 2023):
///   v += dt/2·a;  u += dt·v;  a = M⁻¹ f(u, t+dt);  v += dt/2·a.
/// Critical step from the rigorous bound ω² <= max_i (2 Σ_{springs at i} k + Σ_{ground} k)/m_i
/// (the same bound libdem uses, 2·λmax(Σ K_b)/m); for a uniform chain ω = 2√(k/m).
/// Same rules as the DEM: dt above it is refused (Input) unless allow_unstable; blow-up
/// (non-finite state or energy above 10·(E0 + Σ|work|)) stops with a Numerical error.
#include <strata/core/state_io.hpp>
#include <strata/couple/partition.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace strata::couple {

/// Masses and springs of a 1-DOF-per-node network (chains, lattices projected on one axis).
struct SpringNetwork {
  std::vector<double> mass;            ///< kg per DOF, > 0
  std::vector<std::int32_t> i, j;      ///< spring ends
  std::vector<double> k;               ///< spring stiffness (N/m)
  std::vector<std::int32_t> ground_i;  ///< springs to a fixed point (walls)
  std::vector<double> ground_k;

  void add_spring(std::int32_t a, std::int32_t b, double kk) {
    i.push_back(a);
    j.push_back(b);
    k.push_back(kk);
  }
  void add_ground_spring(std::int32_t a, double kk) {
    ground_i.push_back(a);
    ground_k.push_back(kk);
  }
};

class SpringNetworkPartition final : public Partition {
 public:
  SpringNetworkPartition(SpringNetwork net, double dt, std::string name = "DEM", bool allow_unstable = false);

  void add_load(std::size_t d, std::function<double(double)> f);
  /// Changes the time step before initialise() (a model whose step follows from its limits).
  void set_dt(double dt);

  std::string name() const override { return name_; }
  std::string integrator() const override { return "velocity Verlet"; }
  double dt() const override { return dt_; }
  double time() const override { return time_; }
  std::size_t dofs() const override { return net_.mass.size(); }
  double displacement(std::size_t d) const override { return u_[d]; }
  double velocity(std::size_t d) const override { return v_[d]; }
  void make_external(std::size_t d) override;
  void set_external(std::size_t d, double u, double v) override;
  void initialise() override;
  void step() override;
  double critical_dt() const override;
  double explicit_critical_dt() const override { return critical_dt(); }
  bool is_explicit() const override { return true; }

  /// Bound of ω_max used for the critical step (rad/s).
  double omega_bound() const;
  /// ω_max of the network with external DOFs held, from Lanczos (reporting).
  double omega_max_exact() const;
  double energy() const;
  /// Work of the loads so far, with its sign (J): what an energy balance of a coupled model
  /// counts as input (the work passed through the external DOFs is left out).
  double load_work() const { return load_work_; }
  /// Steps done, and the last step that passed the blow-up check (0 before the first).
  std::int64_t steps_done() const { return step_; }
  std::int64_t last_good_step() const { return last_good_; }
  /// The nodal displacements and velocities (external DOFs hold their copied values).
  const std::vector<double>& u() const { return u_; }
  const std::vector<double>& v() const { return v_; }
  /// Writes the state a continued run needs (time, step, u, v, a, forces, the external DOFs'
  /// copied values and the work and energy bookkeeping) under `prefix`.
  void save_state(StateWriter& out, const std::string& prefix) const;
  /// Restores a state written by save_state on a partition built and initialised the same
  /// way; the run then continues bit for bit. Throws strata::Error (IO) on a size mismatch.
  void load_state(const StateReader& in, const std::string& prefix);

 private:
  void forces(double t);
  void check_blowup();

  SpringNetwork net_;
  double dt_;
  std::string name_;
  bool allow_unstable_;
  std::vector<double> u_, v_, a_, f_;
  std::vector<char> external_;
  std::vector<std::size_t> ext_list_;
  std::vector<double> ext_u0_, ext_v0_, ext_t0_;
  struct Load {
    std::size_t dof;
    std::function<double(double)> f;
    double f_prev = 0, u_prev = 0;
  };
  std::vector<Load> loads_;
  std::vector<double> ext_f_prev_, ext_u_prev_;
  double time_ = 0, energy0_ = 0, work_abs_ = 0, load_work_ = 0;
  std::int64_t step_ = 0, last_good_ = 0;
  bool initialised_ = false;
};

}  // namespace strata::couple
