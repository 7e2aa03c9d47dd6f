#pragma once
/// Linear elastodynamics M·a + C·v + K·u = F(t) on a mesh, with lumped M, Rayleigh damping
/// C = α·M + β_R·K, fixed and prescribed (externally driven) DOFs, nodal loads, and three
/// integrators:
///
///  - CentralDifference: explicit, half-step velocity form (Belytschko, Liu & Moran, Box 6.1):
///      v_{n+½} = v_n + dt/2·a_n;  u_{n+1} = u_n + dt·v_{n+½};
///      a_{n+1} = M⁻¹(F_{n+1} − K u_{n+1} − C v_{n+½});  v_{n+1} = v_{n+½} + dt/2·a_{n+1}.
///    Identical to velocity Verlet without damping. Stable for dt <= (2/ω)(√(1+ξ²) − ξ).
///  - ExplicitNewmark: the predictor-corrector Newmark (β, γ given) of Li, Jin, Wang, Pan &
///    Yang (2023), "Parallel computing method of FEM–DEM with multiple-time step based on
///    overlapping boundary", eqs. 2–3:
///      ũ = u + dt·v + dt²(½ − β)·a;  ṽ = v + dt(1 − γ)·a;  a_{n+1} = M⁻¹(F − K ũ − C ṽ);
///      u_{n+1} = ũ + β dt²·a_{n+1};  v_{n+1} = ṽ + γ dt·a_{n+1}.
///    With lumped M this is explicit and only conditionally stable: ω·dt <= 2 for γ = ½
///    whatever β (checked by test) — not unconditionally stable, as that paper says of it
///    with β = ¼, γ = ½.
///  - ImplicitNewmark: (M + γ dt C + β dt² K)·a_{n+1} = F − K ũ − C ṽ, same predictor and
///    corrector; the matrix is factorised once (SimplicialLDLT) and reused. β = ¼, γ = ½
///    (average acceleration) is unconditionally stable and second order.
///
/// Stability rules (same as the DEM): an explicit dt above the critical step from element
/// eigenvalues (with damping) is refused with strata::Error(Input) naming both numbers,
/// unless allow_unstable (then a warning). Blow-up (a non-finite value, or the energy above
/// energy_factor x (initial energy + all work done on the model)) stops the run with
/// strata::Error(Numerical) naming the step, time and last good step.
///
/// Prescribed DOFs are driven from outside (coupling, moving supports): set_prescribed(d, u, v)
/// at time t0 makes u_d(t) = u + v·(t − t0), v_d(t) = v, a_d = 0 until set again. Fixed DOFs
/// are prescribed DOFs held at zero. The set of prescribed DOFs is frozen by initialise().
#include <strata/core/state_io.hpp>
#include <strata/fem/assembly.hpp>
#include <strata/fem/critical_step.hpp>
#include <strata/fem/mesh.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace strata::fem {

enum class Scheme { CentralDifference, ExplicitNewmark, ImplicitNewmark };
std::string to_string(Scheme s);
/// "central-difference", "explicit-newmark" (alias "pc-newmark"), "implicit-newmark";
/// throws strata::Error(Input) listing them otherwise.
Scheme scheme_from_string(std::string_view s);
/// Whether a scheme is explicit (conditionally stable).
constexpr bool is_explicit(Scheme s) { return s != Scheme::ImplicitNewmark; }

struct SolverSettings {
  Scheme scheme = Scheme::CentralDifference;
  double dt = 0;                ///< time step (s), > 0
  double beta = 0.25;           ///< Newmark β (both Newmark schemes)
  double gamma = 0.5;           ///< Newmark γ (both Newmark schemes)
  double rayleigh_alpha = 0;    ///< C = α·M + β_R·K: mass-proportional part (1/s)
  double rayleigh_beta = 0;     ///< stiffness-proportional part (s)
  bool allow_unstable = false;  ///< warn instead of refusing dt above the critical step
  int check_every = 100;        ///< steps between blow-up checks
  double energy_factor = 10;    ///< blow-up when energy > factor·(E0 + Σ|work|) + tiny
};

/// The numbers behind the time-step check.
struct StabilityInfo {
  double omega_bound = 0;       ///< upper bound of ω_max from element eigenvalues (rad/s)
  double explicit_dt_crit = 0;  ///< critical step of the explicit schemes, with damping (s)
  double dt_crit = 0;           ///< limit of the chosen scheme (+inf when unconditional)
  double dt = 0;
};

class Solver {
 public:
  /// Assembles K and M (parallel, deterministic).
  Solver(Mesh mesh, SolverSettings settings);
  ~Solver();
  Solver(Solver&&) noexcept;
  Solver& operator=(Solver&&) noexcept;

  // ---- set-up (before initialise) ----
  /// Holds DOF `d` at zero.
  void fix(std::size_t d);
  /// Makes DOF `d` driven from outside, starting at u, v (see set_prescribed).
  void prescribe(std::size_t d, double u = 0, double v = 0);
  /// Marks a prescribed DOF as driven by another partition of a coupled model: the work done
  /// through it is energy exchanged inside the model, left out of user_work().
  void mark_exchange(std::size_t d);
  /// Adds a nodal force f(t) (N) on DOF `d`.
  void add_load(std::size_t d, std::function<double(double)> f);
  /// Initial displacement and velocity of the free DOFs (default: rest).
  void set_initial_state(const Eigen::VectorXd& u0, const Eigen::VectorXd& v0);
  /// Sets the time step (s, > 0); only before initialise(), e.g. once a coupled model knows
  /// the step its other partition allows.
  void set_dt(double dt);
  /// Sets the integrator; only before initialise().
  void set_scheme(Scheme scheme);
  /// Checks dt, factorises (implicit), computes the initial acceleration.
  void initialise();

  // ---- time stepping ----
  /// New value of a prescribed DOF at the current time; it then moves with velocity v.
  void set_prescribed(std::size_t d, double u, double v);
  void step();
  void advance(std::int64_t steps);

  // ---- state and derived numbers ----
  double time() const { return time_; }
  std::int64_t steps_done() const { return step_; }
  double dt() const { return settings_.dt; }
  const Eigen::VectorXd& u() const { return u_; }
  const Eigen::VectorXd& v() const { return v_; }
  const Eigen::VectorXd& a() const { return a_; }
  const Mesh& mesh() const { return mesh_; }
  const SolverSettings& settings() const { return settings_; }
  const Assembled& system() const { return sys_; }
  /// ω bound (prescribed DOFs held) and critical steps; computed on first use after the
  /// last prescribe()/fix().
  const StabilityInfo& stability() const;
  /// ω_max of the constrained system from Lanczos (reporting; cost grows with iterations).
  LanczosResult omega_max_exact(int max_iterations = 300) const;
  /// ½ Σ_free m v² (prescribed DOFs belong to whoever drives them).
  double kinetic_energy() const;
  /// ½ uᵀ K u.
  double strain_energy() const;
  /// Σ |work| done on the model by loads and prescribed DOFs so far (J).
  double work_bound() const { return work_abs_; }
  /// Work done on the model by loads and the prescribed DOFs not marked with
  /// mark_exchange(), with its sign (J): what an energy balance of a coupled model counts as
  /// input (an oscillating reaction does no net work, where work_bound() counts every swing).
  double user_work() const { return user_work_; }
  /// The energy below which the blow-up check never fires (J): round-off of the model at
  /// rest.
  double energy_floor() const { return energy_tiny_; }
  /// Writes the state a continued run needs (time, step, u, v, a, prescribed DOFs' current
  /// values, work and energy bookkeeping) under `prefix` ("fem/").
  void save_state(StateWriter& out, const std::string& prefix = "fem/") const;
  /// Restores a state written by save_state on a solver built and initialised from the same
  /// mesh and settings; the run then continues bit for bit as if it had not stopped. Throws
  /// strata::Error (IO) on a size mismatch.
  void load_state(const StateReader& in, const std::string& prefix = "fem/");
  /// Last step that passed the blow-up check (0 before the first).
  std::int64_t last_good_step() const { return last_good_; }
  /// Mask of the prescribed (incl. fixed) DOFs.
  const std::vector<char>& prescribed_mask() const { return is_prescribed_; }

 private:
  struct Prescribed {
    std::size_t dof;
    double u0, v0, t0;
    bool exchange = false;  ///< driven by another partition (mark_exchange)
  };
  struct Load {
    std::size_t dof;
    std::function<double(double)> f;
  };
  struct Factor;

  void check_dt();
  void apply_prescribed(double t, Eigen::VectorXd& u, Eigen::VectorXd& v);
  void loads_at(double t, Eigen::VectorXd& f) const;
  void accumulate_work(double t_new);
  void check_blowup();

  Mesh mesh_;
  SolverSettings settings_;
  Assembled sys_;
  mutable StabilityInfo stab_;
  mutable bool stab_valid_ = false;
  std::vector<Prescribed> prescribed_;
  std::vector<std::size_t> prescribed_index_;  // dof -> index in prescribed_ (or npos)
  std::vector<char> is_prescribed_;
  std::vector<Load> loads_;
  Eigen::VectorXd u_, v_, a_, inv_mass_, f_, w1_, w2_;
  std::unique_ptr<Factor> factor_;
  double time_ = 0;
  std::int64_t step_ = 0, last_good_ = 0;
  bool initialised_ = false;
  double energy0_ = 0, work_abs_ = 0, user_work_ = 0, energy_tiny_ = 0;
  std::vector<double> work_force_prev_, work_u_prev_;  // per load then per prescribed DOF
};

/// Static solution of K u = f with DOFs marked in `prescribed` held at u_prescribed (sparse
/// LDLᵀ). Returns the full displacement vector; throws strata::Error(Input) if K_ff is singular.
Eigen::VectorXd static_solve(const Assembled& sys, const std::vector<char>& prescribed,
                             const Eigen::VectorXd& u_prescribed, const Eigen::VectorXd& f);

}  // namespace strata::fem
