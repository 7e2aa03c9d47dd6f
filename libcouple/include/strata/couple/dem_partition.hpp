#pragma once
/// DEM-side partition: a libdem bonded-particle `dem::Simulation` (2D or 3D) as a coupled
/// partition (the overlapping-boundary coupling of Li, Jin, Wang, Pan & Yang 2023).
///
/// DOFs: d = particle_id·dim + axis (particle ids as returned by `add_particle`, in the
/// order of the calls; libdem's internal spatial sort is invisible here).
///
/// External DOFs are driven particles: make_external(d) only collects them; prepare() puts
/// the particles with an external x (y, z) DOF into the group "couple_external_x" (…_y,
/// …_z), calls `Simulation::drive(group, axis)` for each and then `Simulation::initialise()`
/// (which sorts the particles, builds the bond plan and computes the critical step, so the
/// coupler's stability check sees libdem's own limit). set_external() values are cached and
/// handed to `Simulation::set_kinematics` (one call per particle, all its driven axes) just
/// before the next step; a driven particle then moves with the copied velocity until the
/// next exchange while its bonds still push and pull on its neighbours.
///
/// Leapfrog and the copy. libdem integrates x(n+1) = x(n) + v(n+½)·dt, so after step n the
/// displacement is at t_n but the velocity of a free particle is v(n−½), half a step old.
/// velocity(d) returns that half-step velocity unchanged (for a driven particle it is the
/// copied velocity). The FEM side therefore moves its external nodes over the next system
/// step with v(n−½) instead of v(t_n): a lag of dt_DEM·a/2 in velocity, i.e. an extra
/// displacement error of η·dt_DEM²·a/2 at the end of a system step, against the
/// η²·dt_DEM²·a/2 that the constant-velocity extrapolation of the scheme itself makes. It
/// matters only at η = 1 (where it doubles the extrapolation error) and is reported, not
/// corrected. Gauges that read DEM velocities should time-stamp them at t − dt/2.
///
/// Shear displacements of bonds are accumulated by libdem from velocities; the position
/// jump of a driven particle at an exchange (u_copied − u_extrapolated ≈ a·(η·dt)²/2) is not
/// seen by the shear increment, so the shear of a bond touching a driven particle drifts by
/// at most η·dt·|Δv|/2 over a run. The normal part (from positions) is exact.
///
/// Blow-up: libdem's own check (NaN, kinetic energy above 10 x (initial energy + |external
/// work|)); the work done by driven particles counts as external work.
#include <strata/couple/partition.hpp>
#include <strata/dem/simulation.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace strata::couple {

class DemPartition final : public Partition {
 public:
  /// `sim` must hold the model (particles, bonds, materials, boundary conditions) and must not
  /// be initialised yet; its Settings::dt is the DEM step.
  explicit DemPartition(dem::Simulation sim, std::string name = "DEM");

  dem::Simulation& simulation() { return sim_; }
  const dem::Simulation& simulation() const { return sim_; }
  int dim() const { return dim_; }

  std::string name() const override { return name_; }
  std::string integrator() const override { return "leapfrog (libdem)"; }
  double dt() const override { return sim_.dt(); }
  double time() const override { return sim_.time(); }
  std::size_t dofs() const override { return sim_.particle_count() * static_cast<std::size_t>(dim_); }
  /// Displacement from the initial position at time() (a pending copied value if set since
  /// the last step).
  double displacement(std::size_t d) const override;
  /// Velocity: v(n−½) of a free particle (leapfrog), the copied velocity of a driven one.
  double velocity(std::size_t d) const override;
  void make_external(std::size_t d) override;
  void set_external(std::size_t d, double u, double v) override;
  /// Drives the external particles and initialises the Simulation (throws strata::Error
  /// (Numerical) from libdem when dt exceeds its critical step and the DEM settings do not
  /// allow it).
  void prepare() override;
  void initialise() override;
  void step() override;
  double critical_dt() const override;
  double explicit_critical_dt() const override { return critical_dt(); }
  bool is_explicit() const override { return true; }

  /// Number of driven (external) particles.
  std::size_t external_particles() const { return ext_.size(); }

 private:
  struct Driven {
    std::uint32_t id;
    unsigned axes = 0;  ///< dem::Axes mask of its external DOFs
    std::array<double, 3> u{}, v{};
    bool dirty = false;
  };
  Driven* driven_of(std::size_t d, const char* what);
  void flush();

  dem::Simulation sim_;
  std::string name_;
  int dim_;
  std::vector<std::int32_t> ext_index_;  ///< particle id -> index into ext_, -1 if free
  std::vector<Driven> ext_;
  std::vector<std::uint32_t> dirty_;
  bool prepared_ = false, initialised_ = false;
};

}  // namespace strata::couple
