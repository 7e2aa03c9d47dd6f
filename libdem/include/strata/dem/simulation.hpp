#pragma once
/// Bonded-particle DEM: 2D disks or 3D spheres without rotation, solid-lattice
/// bonds that break in tension or shear, frictional contacts, leapfrog integration,
/// damping, boundary conditions on named groups, probes, and a checked time step.
///
/// `Simulation` is the run-time-dimension front end; the work is done by `Model<D>`
/// (libdem/src/model.hpp), a structure-of-arrays model whose step loop computes every pair
/// force exactly once and sums forces per particle in a fixed order, so results are bit-for-
/// bit the same for any number of threads. See docs/dem.md for the physics and the design.
///
/// Indices: `add_particle` returns the particle's id (0, 1, 2, ... in the order of the
/// calls). Every function taking particle indices takes ids. Read-access functions return
/// arrays in the model's internal (spatially sorted) order together with `ids()`.
#include <strata/core/ramp.hpp>
#include <strata/dem/laws.hpp>
#include <strata/dem/material.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace strata {
class StateWriter;
class StateReader;
}  // namespace strata

namespace strata::dem {

/// Axes masks for boundary conditions.
enum Axes : unsigned { kX = 1, kY = 2, kZ = 4, kXY = 3, kXYZ = 7 };

/// How a bond broke.
enum class BreakMode : std::uint8_t { Tension = 1, Shear = 2 };

/// Kind of a bond or contact (see pair_state in laws.hpp).
enum class PairKind : std::uint8_t { Intact = 0, BrokenTension = 1, BrokenShear = 2, Contact = 3 };

/// One bond break.
struct BreakEvent {
  std::int64_t step;               ///< step during which it broke (0-based)
  std::array<double, 3> position;  ///< midpoint of the two centres at that step
  BreakMode mode;
  std::uint32_t id_i, id_j;  ///< particle ids
};

/// Run settings.
struct Settings {
  double dt = 0;                ///< time step (s)
  bool allow_unstable = false;  ///< dt > critical_dt() warns instead of throwing
  enum class Damping { None, Viscous, Local };
  Damping damping = Damping::None;
  double viscous_c = 0;             ///< artificial viscosity c (N·s/m): F -= c·v
  double local_alpha = 0.7;         ///< local non-viscous damping α in [0,1): F -= α|F|sign(v)
  std::array<double, 3> gravity{};  ///< body acceleration (m/s²)
  bool contact_detection = true;    ///< search for new contacts between unbonded particles
  /// Steps between two full blow-up checks (kinetic and stored energy against the budget;
  /// <= 0: never). Between them every step compares the fastest particle's speed with what
  /// the budget allows and checks at once when it is exceeded.
  int energy_check_every = 100;
  double skin = 0;  ///< Verlet skin (m); 0: half the largest radius
  /// Threads are used only with at least this many particles each (smaller models run on
  /// fewer threads; results do not depend on it). Tests lower it to exercise threading.
  int min_particles_per_thread = 4096;
  /// A model whose bonds sit in lattice slots (a lattice numbered row by row) steps its bonds
  /// direction by direction while it has no contacts, on any number of threads; false takes
  /// the general bond pass. Results do not depend on it (tests compare the two).
  bool lattice_slots = true;
};

/// A bond or contact as seen by writers.
struct PairView {
  std::uint32_t i, j;  ///< internal indices (see ids())
  PairKind kind;
  bool touching;                     ///< broken bond / contact currently in contact
  bool reclosed;                     ///< broken bond that opened and has closed again
  double fn;                         ///< normal force (N, compression positive) at the last step's state
  double fs;                         ///< magnitude of the shear force (N)
  std::array<double, 3> force_on_i;  ///< force vector the pair exerts on particle i (N)
};

/// A rigid wall as seen by writers: a plane at its current position.
struct WallView {
  std::array<double, 3> point;     ///< a point of the plane now (m)
  std::array<double, 3> normal;    ///< unit normal towards the particles' side
  std::array<double, 3> velocity;  ///< m/s
  double stiffness;                ///< penalty stiffness (N/m)
};

namespace detail {
class ModelBase;
}

/// The DEM model and its time loop, dimension chosen at construction (2 or 3).
class Simulation {
 public:
  Simulation(int dim, Settings settings);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  int dim() const;
  const Settings& settings() const;

  // ---- building the model -----------------------------------------------------------
  /// Adds a material; returns its index.
  int add_material(const Material& m);
  /// Reserves space for n particles (avoids growth peaks in memory while building).
  void reserve(std::size_t n);
  /// Adds a particle at rest, in no group; returns its id. mass <= 0: density × cell
  /// measure (2D: (√3/2)·d², the hex cell area; 3D: d³/√2, the close-packed cell volume).
  std::size_t add_particle(std::array<double, 3> x, double radius, int material, double mass = 0);
  /// Adds particles at x, all of one radius and material, as add_particle one by one (the
  /// same ids and bits, filled in parallel); returns the first one's id.
  std::size_t add_particles(const std::vector<std::array<double, 3>>& x, double radius, int material,
                            double mass = 0);
  std::size_t particle_count() const;
  /// Bonds every pair with |xi - xj| <= (ri + rj)(1 + tolerance). O(N) with a cell grid.
  void bond_touching_pairs(double tolerance = 1e-6);
  /// Bonds given as data instead (the eccentric lattices of Zhao, Qiao, Zhang, Sun & Chen
  /// 2021): bond b joins particles first[b] and second[b] (ids); its rest length is the
  /// centres' distance now (so the model starts unloaded whatever the offsets), and while
  /// intact its Kn and Ks are scaled by factor[b] in (0, 1] (the γ of weakened bonds;
  /// empty: all 1). A broken bond pushes back (material stiffness, friction) when shorter
  /// than its rest length. Unbonded neighbours of a strongly eccentric lattice may overlap
  /// at the start (3D: Ra > 0.41; 2D: Ra > 0.73): turn contact detection off for such
  /// models. While intact, bond b's strengths (for the solid-lattice law Fn_max and Fs0) are
  /// scaled by strength[b] > 0 (a spread of bond strengths; empty: all 1). Call it once,
  /// before initialise(), instead of bond_touching_pairs(). Costs 24 bytes per bond.
  void set_bonds(const std::vector<std::uint32_t>& first, const std::vector<std::uint32_t>& second,
                 const std::vector<double>& factor = {}, const std::vector<double>& strength = {});
  /// Sets the velocity of particle `id` (initial conditions).
  void set_velocity(std::size_t id, std::array<double, 3> v);

  // ---- groups (any number; a particle may be in several) -------------------------------
  /// Index of a named group, created on first use (groups are numbered in that order).
  int group_index(const std::string& name);
  /// Adds the particles with these ids to the group.
  void add_to_group(const std::vector<std::uint32_t>& ids, const std::string& name);
  /// Ids of the particles in a group, ascending.
  std::vector<std::uint32_t> group_members(const std::string& name) const;
  /// Per particle (internal order): 1 when it belongs to one of the named groups.
  std::vector<std::uint8_t> in_groups(const std::vector<std::string>& names) const;
  /// Per particle (internal order): the group_index of the last-made group it belongs to
  /// (the most specific one where groups refine regions), -1 for none.
  std::vector<std::int32_t> last_group() const;
  std::vector<std::int32_t> last_group(std::span<const std::uint32_t> rows) const;
  /// Names of the groups, by group_index (the values of last_group()).
  const std::vector<std::string>& group_names() const;

  // ---- boundary conditions (later calls override earlier ones per axis) ---------------
  /// Fixes the given axes of the group's particles.
  void fix(const std::string& group, unsigned axes);
  /// Moves the group's particles at velocity v along the given axes (other axes free).
  void prescribe_velocity(const std::string& group, std::array<double, 3> v, unsigned axes);
  /// Prescribes the group along `axes` (bit a: axis a; 0: the axes of the increment's
  /// non-zero components): held there, and moved by `increment` once every `every_steps`
  /// steps (the platens of Li, Yin, Liu & Cai 2017: 1.9e-9 m every 400 steps). An axis with
  /// a zero increment is held in place: platens that also hold the boundary rows sideways
  /// (rough platens) name both axes.
  void step_displacement(const std::string& group, std::array<double, 3> increment, std::int64_t every_steps,
                         unsigned axes = 0);
  /// Force on each particle of the group, from one (time, force) to the next linearly or
  /// smoothly (`ramp`, strata/core/ramp.hpp), constant outside. A particle takes the last
  /// history given for one of its groups.
  void force_history(const std::string& group, std::vector<double> times,
                     std::vector<std::array<double, 3>> forces, Ramp ramp = Ramp::Linear);
  /// A radial force on each particle of the group: magnitude from one (time, magnitude) to
  /// the next linearly or smoothly (`ramp`), constant outside, along the unit vector from `centre` to the
  /// particle's start position, with its component along `axis` removed (a pressure on the
  /// wall of a borehole along `axis`; axis = 0: radial from the point, a spherical charge).
  /// A positive magnitude pushes away from the centre: the blast load on the rim of a hole.
  /// A particle at the centre gets no force. Counts as a force history above.
  void radial_force_history(const std::string& group, std::vector<double> times,
                            std::vector<double> magnitudes, std::array<double, 3> centre,
                            std::array<double, 3> axis = {0, 0, 0}, Ramp ramp = Ramp::Linear);
  /// The unit vector a radial load pushes a point at `x` along (the first `dim` components
  /// used): from `centre` to x, its component along `axis` removed (axis 0: none); zero for
  /// a point at the centre (or on the axis).
  static std::array<double, 3> radial_direction(const std::array<double, 3>& x,
                                                const std::array<double, 3>& centre,
                                                const std::array<double, 3>& axis, int dim);
  /// Drives the group's particles along the given axes from outside (coupling):
  /// they take the displacement and velocity given by set_kinematics() and move with that
  /// velocity until the next call, exerting their bond and contact forces on the others.
  /// The work their motion does is counted as external work, like a prescribed velocity;
  /// with `exchange` (the driver is another partition of a coupled model) it is also booked
  /// apart, as exchange_work().
  void drive(const std::string& group, unsigned axes, bool exchange = false);
  /// Sets displacement u (from the initial position) and velocity v of a driven particle
  /// along its driven axes; other axes are left alone. Needs an initialised model.
  void set_kinematics(std::size_t id, const std::array<double, 3>& u, const std::array<double, 3>& v);
  /// Displacement from the initial position and velocity (leapfrog: at the last half step)
  /// of particle `id`; O(1) per call after the first.
  void kinematics(std::size_t id, std::array<double, 3>& u, std::array<double, 3>& v) const;
  /// Rigid frictionless plane through `point` with unit normal pointing to the particles'
  /// side, moving at `velocity`; penalty force k·δ·n with δ = r - (x - p)·n > 0.
  void add_wall(std::array<double, 3> point, std::array<double, 3> normal, std::array<double, 3> velocity,
                double stiffness);

  // ---- running -------------------------------------------------------------------------
  /// Sorts particles spatially, builds search structures, computes critical_dt() and
  /// checks dt (strata::Error(Numerical) when dt > critical_dt() and !allow_unstable).
  void initialise();
  /// Critical time step 2/√λmax of the bonded lattice (see docs/dem.md).
  double critical_dt() const;
  /// Rigorous upper bound of λmax(M⁻¹K) (1/s²): max_i λmax(2·Σ_b K_b)/m_i.
  double lambda_bound() const;
  /// Lanczos estimate of λmax(M⁻¹K) (1/s²) used for critical_dt (with a 1 % margin).
  double lambda_estimate() const;
  double dt() const;
  /// Changes the time step (checked against critical_dt() like initialise()).
  void set_dt(double dt);
  /// Runs n steps; throws strata::Error(Numerical) on blow-up (NaN/inf or runaway energy).
  /// With energies = false the last step does not sum the kinetic and stored energy on the
  /// way (kinetic_energy() and bond_energy() then evaluate them afresh, a pass over the
  /// pairs; the blow-up check still runs every energy_check_every steps): for callers that
  /// step one step at a time, such as the coupling. Positions and velocities are the same.
  void run(std::int64_t steps, bool energies = true);
  /// A settling stage before the first step: n steps under gravity and damping while the
  /// prescribed motions, moving walls and loads wait (each prescribed axis is held where it
  /// is, walls stand, loads are zero). The settled state then becomes the start of the run:
  /// displacements, time, step count and work are counted from it, and bonds that broke while
  /// settling keep their break events with negative steps. Several calls settle on; the state
  /// is the same as after one call with their total. Throws Input once the model has run.
  void settle(std::int64_t steps);
  std::int64_t step_count() const;
  double time() const;
  /// Step of the last passed blow-up check.
  std::int64_t last_good_step() const;

  // ---- probes ------------------------------------------------------------------------
  /// Sum of the internal (bond, contact, wall) forces on the group's particles at the
  /// current state; the reaction a platen group carries is minus this.
  std::array<double, 3> group_force(const std::string& group) const;
  /// Kinetic energy ½Σm·v(n-½)·v(n+½) at the last step (J).
  double kinetic_energy() const;
  /// Stored energy of intact bonds, touching contacts and walls at the last step (J).
  double bond_energy() const;
  /// Work done on the particles by prescribed motion, applied forces, walls and gravity (J).
  double external_work() const;
  /// The part of external_work() done through axes driven with drive(..., exchange = true):
  /// energy passed in from the other partition of a coupled model (J).
  double exchange_work() const;
  /// The energy below which the blow-up check never fires (J): the bond energy of a
  /// displacement of 1e-6 diameters at every particle.
  double energy_floor() const;
  /// Energy removed by damping (J).
  double damping_dissipation() const;
  std::size_t broken_count(BreakMode mode) const;
  std::size_t broken_count() const;
  std::size_t bond_count() const;
  /// Broken bonds and contacts currently touching.
  std::size_t contact_count() const;
  /// Steps taken with the bonds in lattice slots (Settings::lattice_slots: a lattice
  /// numbered row by row, and in 3D layer by layer, while it has no contacts).
  std::int64_t steps_in_lattice_slots() const;
  /// All bond breaks so far, ordered by (step, particle ids).
  const std::vector<BreakEvent>& breaks() const;
  /// Pairs (id_i < id_j) whose disks/spheres overlap now, found through the contact lists
  /// and bonds (for tests of the search against brute force).
  std::vector<std::array<std::uint32_t, 2>> touching_pairs() const;

  // ---- read access for writers (internal order) --------------------------------------
  std::vector<std::array<double, 3>> positions() const;
  std::vector<std::array<double, 3>> velocities() const;
  std::vector<std::array<double, 3>> displacements() const;
  std::vector<double> radii() const;
  std::vector<std::uint32_t> ids() const;
  /// Fraction of each particle's initial bonds that are broken.
  std::vector<float> damage() const;
  /// The same at some internal rows (each below particle_count()), in the order given: what
  /// the frames of a large model read for the particles they write, without a copy of all.
  std::vector<std::array<double, 3>> positions(std::span<const std::uint32_t> rows) const;
  std::vector<std::array<double, 3>> velocities(std::span<const std::uint32_t> rows) const;
  std::vector<std::array<double, 3>> displacements(std::span<const std::uint32_t> rows) const;
  std::vector<double> radii(std::span<const std::uint32_t> rows) const;
  std::vector<std::uint32_t> ids(std::span<const std::uint32_t> rows) const;
  std::vector<float> damage(std::span<const std::uint32_t> rows) const;
  /// Bond entries of each particle, intact or broken (internal order); 255 stands for 255 or
  /// more.
  std::vector<std::uint8_t> bond_counts() const;
  std::vector<PairView> bonds() const;
  /// The bonds that have broken, as bonds() lists them (a crack frame of a large model
  /// without a view of every intact bond).
  std::vector<PairView> broken_bonds() const;
  std::vector<PairView> contacts() const;
  /// The walls in the order they were added, where they are now.
  std::vector<WallView> walls() const;
  /// Bytes held by the model's arrays (capacity).
  std::size_t memory_bytes() const;
  /// Bytes one step moves between memory and the cores when none of the model's arrays stays
  /// in cache: every particle array the step reads once, every one it changes read and written
  /// once, and per bond or contact its partner index, state byte and shear history (read and
  /// written). The scratch of a block's bonds and the partners' positions, which the lattice
  /// order keeps within a few rows or layers, stay in cache and are not counted. For a 2D
  /// lattice that last stepped in lattice slots: per disk its arrays and per column of slots
  /// a state byte and shear history, read and written (docs/dem.md, "Bonds in lattice slots").
  std::size_t streamed_bytes_per_step() const;
  /// FNV-1a hash of positions, velocities, bond states and shear displacements.
  std::uint64_t state_hash() const;

  // ---- checkpoints (strata/core/state_io.hpp; HDF5 files: strata/io/checkpoint.hpp) -----
  /// Saves everything that influences future steps under "dem/...": settings, materials,
  /// groups, boundary conditions, walls, all particle arrays in internal order, bonds and
  /// contacts with their state and shear displacements, the Verlet-list and energy
  /// accumulators, the break list, step and time. Needs an initialised model.
  void save_state(StateWriter& out) const;
  /// Replaces the whole state by a saved one (except Settings::min_particles_per_thread,
  /// which does not change results). Stepping on gives bit-for-bit the same results as the
  /// run that saved it. The Simulation must have the saved dimension and either no
  /// particles or as many as were saved (e.g. rebuilt from the same scene); initialise()
  /// is not needed. Throws strata::Error (Input) on a mismatch, (IO) on a damaged state.
  void load_state(const StateReader& in);

 private:
  std::unique_ptr<detail::ModelBase> m_;
};

/// λmax of the infinite 2D hex lattice (1/s²) for equal masses m, from the dynamical matrix
/// over the Brillouin zone. For Kn >= 2Ks (e.g. the rock of liu2013_rock()) it is (6Kn+2Ks)/m (the M point);
/// for Kn = Ks it is 9Kn/m (the K point); in between the maximum lies on the M-K edge.
double hex_lattice_lambda_max(double kn, double ks, double mass);

}  // namespace strata::dem
