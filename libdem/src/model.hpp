#pragma once
// Internal: the structure-of-arrays DEM model, templated on the dimension D (2 or 3).
// The public front end is strata::dem::Simulation (simulation.hpp), which forwards to
// ModelBase; virtual calls happen per API call, never per pair.
#include "strata/dem/simulation.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace strata::dem::detail {

inline constexpr std::uint32_t kNone = 0xffffffffu;
/// Particles per accumulator block: energy/work sums are formed per block and added in
/// block order, so they do not depend on the thread count. Thread ranges are whole blocks.
inline constexpr std::ptrdiff_t kBlock = 256;

/// Bonds or contacts stored CSR by owner: the pairs (i, j > i) of owner i are
/// off[i] .. off[i+1]-1, sorted by j; i is implied.
struct PairList {
  std::vector<std::uint32_t> off{0};
  std::vector<std::uint32_t> j;
  std::vector<std::uint8_t> st;
  std::vector<double> us;  // NS shear components per pair
  // Bonds of eccentric lattices only (empty otherwise): rest length (the initial centre
  // distance) and stiffness factor of each bond; both apply while the bond is intact.
  std::vector<double> r0, kf;
  std::size_t size() const { return j.size(); }
  std::size_t bytes() const {
    return off.capacity() * 4 + j.capacity() * 4 + st.capacity() +
           (us.capacity() + r0.capacity() + kf.capacity()) * 8;
  }
};

/// Boundary condition of one particle (only particles with a condition have one).
struct BcParticle {
  std::uint32_t index = 0;  // internal index
  std::uint8_t mode[3]{};   // 0 free, 1 fixed, 2 velocity, 3 step displacement
  double value[3]{};        // velocity (mode 2) or increment (mode 3)
  std::int64_t every[3]{};  // steps between increments (mode 3)
  int history = -1;         // force history index
  double dx_prev[3]{};      // last step's displacement (trapezoid work)
  double f_int[3]{};        // last internal force
  double w_ahead = 0;       // work booked for the half interval after the last step
};

struct BcSpec {
  enum Kind { Fix, Velocity, StepDisp, Force } kind;
  std::uint32_t mask;
  unsigned axes;
  std::array<double, 3> value{};
  std::int64_t every = 0;
  int history = -1;
};

struct ForceHistory {
  std::vector<double> t;
  std::vector<std::array<double, 3>> f;
  std::array<double, 3> at(double time) const;
};

struct Wall {
  double p[3], n[3], v[3], k;
};

/// Per-block accumulators (padded to a cache line).
struct alignas(64) BlockAcc {
  double work = 0;        // prescribed motion, applied forces, walls (accumulated)
  double dissipated = 0;  // damping (accumulated)
  double ke = 0;          // kinetic energy at the last energy step
  double eb = 0;          // pair + wall energy at the last energy step
  double vmax2 = 0;       // largest |v|² in the last step
};

/// The run state of a Model<D>, by reference, for checkpoints (state.cpp). Together with
/// ModelBase's public members it is everything that influences future steps; the rest
/// (pair-law table, id lookup cache, thread plan, cross-pair slots) is derived from it.
struct StateRefs {
  int dim = 0;
  std::array<std::vector<double>*, 3> x{}, v{}, x0{}, f{};  // first `dim` used
  std::vector<double>* im = nullptr;
  std::vector<double>* rad = nullptr;
  std::vector<std::uint32_t>* id = nullptr;
  std::vector<std::uint32_t>* grp = nullptr;
  std::vector<std::uint8_t>* mat = nullptr;
  std::vector<std::uint8_t>* flags = nullptr;
  PairList* bonds = nullptr;
  PairList* contacts = nullptr;
  std::vector<BcParticle>* bcp = nullptr;
  std::vector<BlockAcc>* acc = nullptr;
  std::vector<BreakEvent>* events = nullptr;
  std::int64_t* step = nullptr;
  std::int64_t* last_good = nullptr;
  double* time = nullptr;
  double* dt_crit = nullptr;
  double* lam_est = nullptr;
  double* lam_bound = nullptr;
  double* energy_budget0 = nullptr;
  double* energy_tiny = nullptr;
  double* skin = nullptr;
  double* disp_bound = nullptr;
  bool* initialised = nullptr;
  bool* bcs_dirty = nullptr;
  bool* energy_valid = nullptr;
  bool* budget_dirty = nullptr;
  bool* contacts_on = nullptr;
};

class ModelBase {
 public:
  virtual ~ModelBase() = default;
  Settings settings;
  std::vector<Material> materials;
  std::vector<std::string> group_names;
  std::vector<BcSpec> bc_specs;
  std::vector<ForceHistory> histories;
  std::vector<Wall> walls;

  virtual int dim() const = 0;
  virtual void reserve(std::size_t n) = 0;
  virtual std::size_t add_particle(std::array<double, 3> x, double r, int mat, std::uint32_t g,
                                   double mass) = 0;
  virtual std::size_t particle_count() const = 0;
  virtual void bond_touching_pairs(double tol) = 0;
  virtual void set_bonds(const std::vector<std::uint32_t>& i, const std::vector<std::uint32_t>& j,
                         const std::vector<double>& factor) = 0;
  virtual void set_velocity(std::size_t id, std::array<double, 3> v) = 0;
  /// Driven particles (coupling): displacement and velocity of one particle by id.
  virtual void set_kinematics(std::size_t id, const std::array<double, 3>& u,
                              const std::array<double, 3>& v) = 0;
  virtual void kinematics(std::size_t id, std::array<double, 3>& u, std::array<double, 3>& v) const = 0;
  virtual void add_group_bits(const std::vector<std::uint32_t>& ids, std::uint32_t mask) = 0;
  virtual std::vector<std::uint32_t> members(std::uint32_t mask) const = 0;
  virtual void bcs_changed() = 0;
  virtual void initialise() = 0;
  virtual double critical_dt() const = 0;
  virtual double lambda_bound() const = 0;
  virtual double lambda_estimate() const = 0;
  virtual void check_dt() = 0;
  virtual void run(std::int64_t steps, bool energies_at_end) = 0;
  virtual std::int64_t step_count() const = 0;
  virtual double time() const = 0;
  virtual std::int64_t last_good_step() const = 0;
  virtual std::array<double, 3> group_force(std::uint32_t mask) const = 0;
  virtual double kinetic_energy() const = 0;
  virtual double bond_energy() const = 0;
  virtual double external_work() const = 0;
  virtual double damping_dissipation() const = 0;
  virtual std::size_t broken_count(int mode) const = 0;
  virtual std::size_t bond_count() const = 0;
  virtual std::size_t contact_count() const = 0;
  virtual const std::vector<BreakEvent>& breaks() const = 0;
  virtual std::vector<std::array<std::uint32_t, 2>> touching_pairs() const = 0;
  virtual std::vector<std::array<double, 3>> positions() const = 0;
  virtual std::vector<std::array<double, 3>> velocities() const = 0;
  virtual std::vector<std::array<double, 3>> displacements() const = 0;
  virtual std::vector<double> radii() const = 0;
  virtual std::vector<std::uint32_t> ids() const = 0;
  virtual std::vector<std::uint32_t> group_bits() const = 0;
  virtual std::vector<float> damage() const = 0;
  virtual std::vector<PairView> pairs(bool bonds) const = 0;
  virtual std::size_t memory_bytes() const = 0;
  virtual std::uint64_t state_hash() const = 0;
  /// Checkpoints (state.cpp): the run state by reference, and the rebuild of derived data
  /// after it has been overwritten.
  virtual StateRefs state_refs() = 0;
  virtual void state_loaded() = 0;
};

template <int D>
std::unique_ptr<ModelBase> make_model(const Settings& s);

}  // namespace strata::dem::detail
