#pragma once
/// A partition of a coupled model (overlapping-boundary coupling with multiple time steps, Li,
/// Jin, Wang, Pan & Yang 2023): a solver that owns some DOFs, advances by its own time step,
/// shows the displacement and velocity of any of its DOFs, and accepts prescribed values for
/// its external DOFs (the other partition's boundary).
///
/// The coupler talks only to this interface, so the FEM (libfem) and DEM sides are
/// interchangeable. Implementations: FemPartition (a libfem Solver), DemPartition (a libdem
/// bonded-particle Simulation, 2D or 3D; DOF = particle id·dim + axis) and
/// SpringNetworkPartition (point masses and springs by velocity Verlet, used by the 1D chain
/// cases). See libcouple/README.md.
#include <cstddef>
#include <cstdint>
#include <string>

namespace strata::couple {

/// Role of a node (DOF) in its partition: internal (only this partition), boundary (owned
/// here, copied to the other side's external), external (copied from the other side's
/// boundary, prescribed here).
enum class Role : std::uint8_t { Internal, Boundary, External };

class Partition {
 public:
  virtual ~Partition() = default;
  virtual std::string name() const = 0;
  /// Integrator in words (e.g. "velocity Verlet", "implicit-newmark").
  virtual std::string integrator() const = 0;
  virtual double dt() const = 0;
  virtual double time() const = 0;
  virtual std::size_t dofs() const = 0;
  virtual double displacement(std::size_t d) const = 0;
  virtual double velocity(std::size_t d) const = 0;
  /// Declares DOF d external (prescribed from outside); before initialise().
  virtual void make_external(std::size_t d) = 0;
  /// New value of an external DOF at the current time; until the next call it moves with
  /// the constant velocity v (u(t) = u + v·(t − now)).
  virtual void set_external(std::size_t d, double u, double v) = 0;
  /// Freezes the set of external DOFs and computes what critical_dt() needs (the coupler
  /// calls it before its stability check). Default: nothing to do. DemPartition initialises
  /// its libdem Simulation here, which is when libdem computes its critical step.
  virtual void prepare() {}
  /// Checks the step against the partition's own limit and prepares the run.
  virtual void initialise() = 0;
  /// One step of dt().
  virtual void step() = 0;
  /// Critical step of the integrator in use, external DOFs held (s); +inf if unconditional.
  virtual double critical_dt() const = 0;
  /// Critical step this partition would have with an explicit integrator (s).
  virtual double explicit_critical_dt() const = 0;
  /// Whether the integrator in use is explicit (conditionally stable).
  virtual bool is_explicit() const = 0;
};

}  // namespace strata::couple
