#pragma once
/// A partition of a coupled model (SPEC C3): a solver that owns some DOFs, advances by its
/// own time step, shows the displacement and velocity of any of its DOFs, and accepts
/// prescribed values for its external DOFs (the other partition's boundary).
///
/// The coupler talks only to this interface, so the FEM (libfem) and DEM sides are
/// interchangeable. In this version the DEM side of the chain cases is a spring network
/// integrated by velocity Verlet (SpringNetworkPartition), the scheme libdem uses; adapting a
/// libdem Simulation is later work (see libcouple/README.md for what libdem would need).
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
