#pragma once
// Internal: the structure-of-arrays DEM model, templated on the dimension D (2 or 3).
// The public front end is strata::dem::Simulation (simulation.hpp), which forwards to
// ModelBase; virtual calls happen per API call, never per pair. The pair law's part (the
// step kernel and the probes that evaluate pair forces) is a LawEngine chosen at set-up.
//
// Model<D>'s members are defined by responsibility, each file with its explicit
// instantiations for D = 2 and 3:
//   model.cpp        particle storage, ids and groups, spatial order (Morton, or rows), read access
//   search.cpp       cell grid, bonding, the Verlet contact list, the thread plan, lattice slots
//   boundary.cpp     boundary conditions, force histories, driven particles
//   run.cpp          choice of the pair law, initialise(), the run loop, blow-up checks
//   critical_dt.cpp  critical time step: rigorous bound and Lanczos estimate
//   probes.cpp       energies, work, forces on groups, break and contact counts
//   state.cpp        checkpoints (save/load) and the state hash
// The step kernel itself is strata/dem/detail/step_kernel.hpp, compiled in step.cpp.
#include <strata/core/parallel.hpp>
#include <strata/core/ramp.hpp>
#include <strata/dem/detail/law_engine.hpp>
#include <strata/dem/detail/model_data.hpp>
#include <strata/dem/simulation.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace strata::dem::detail {

struct BcSpec {
  enum Kind { Fix, Velocity, StepDisp, Force } kind;
  std::uint32_t group;  ///< index into ModelBase::group_names
  unsigned axes;
  std::array<double, 3> value{};
  std::int64_t every = 0;
  int history = -1;
  bool exchange = false;  ///< drive(): the group is driven by another partition
};

struct ForceHistory {
  std::vector<double> t;
  std::vector<std::array<double, 3>> f;  ///< radial: the magnitude in f[k][0]
  /// A radial load: each particle is pushed along the unit vector from `centre` to its start
  /// position, with the component along `axis` removed (a borehole; axis 0: from the point).
  bool radial = false;
  std::array<double, 3> centre{}, axis{};
  Ramp ramp = Ramp::Linear;  ///< from one listed force to the next
  /// The force at `time`; a radial load's magnitude on every axis (BcParticle::load_dir
  /// turns it into a vector).
  std::array<double, 3> at(double time) const;
};

/// The run state of a Model<D>, by reference, for checkpoints (state.cpp). Together with
/// ModelBase's public members it is everything that influences future steps; the rest
/// (pair-law table, id lookup cache, thread plan, cross-pair slots) is derived from it.
struct StateRefs {
  int dim = 0;
  std::array<aligned_vector<double>*, 3> x{}, v{}, x0{};  // first `dim` used
  ParticleConst* im = nullptr;
  ParticleConst* rad = nullptr;
  std::vector<std::uint32_t>* id = nullptr;
  std::vector<std::uint32_t>* grp = nullptr;
  std::vector<std::uint8_t>* mat = nullptr;
  aligned_vector<std::uint8_t>* flags = nullptr;
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
  std::int64_t* settled = nullptr;
  bool* initialised = nullptr;
  bool* bcs_dirty = nullptr;
  bool* energy_valid = nullptr;
  bool* budget_dirty = nullptr;
  bool* contacts_on = nullptr;
};

/// The particles an accessor reads: every one in internal order (all), or listed internal rows.
struct Rows {
  std::span<const std::uint32_t> list;
  bool all = true;
  std::size_t count(std::size_t n) const { return all ? n : list.size(); }
  std::size_t operator[](std::size_t k) const { return all ? k : list[k]; }
};

class ModelBase {
 public:
  virtual ~ModelBase() = default;
  Settings settings;
  std::vector<Material> materials;
  std::vector<std::string> group_names;
  /// The distinct sets of groups particles belong to, each sorted ascending (indices into
  /// group_names); set 0 is the empty set and a particle's entry in grp is the index of its
  /// set. Particles share few combinations of groups, so membership costs 4 bytes per
  /// particle whatever the number of groups.
  std::vector<std::vector<std::uint32_t>> group_sets{{}};
  /// Index of the set `set` ∪ {group}, added when new.
  std::uint32_t set_with(std::uint32_t set, std::uint32_t group);
  /// One entry per set: 1 when it holds one of `groups`.
  std::vector<std::uint8_t> sets_holding(const std::vector<std::uint32_t>& groups) const;
  std::vector<BcSpec> bc_specs;
  std::vector<ForceHistory> histories;
  std::vector<Wall> walls;

  virtual int dim() const = 0;
  virtual void reserve(std::size_t n) = 0;
  virtual std::size_t add_particle(std::array<double, 3> x, double r, int mat, double mass) = 0;
  virtual std::size_t add_particles(const std::vector<std::array<double, 3>>& x, double r, int mat,
                                    double mass) = 0;
  virtual std::size_t particle_count() const = 0;
  virtual void bond_touching_pairs(double tol) = 0;
  virtual void set_bonds(const std::vector<std::uint32_t>& i, const std::vector<std::uint32_t>& j,
                         const std::vector<double>& factor, const std::vector<double>& strength) = 0;
  virtual void set_velocity(std::size_t id, std::array<double, 3> v) = 0;
  /// Driven particles (coupling): displacement and velocity of one particle by id.
  virtual void set_kinematics(std::size_t id, const std::array<double, 3>& u,
                              const std::array<double, 3>& v) = 0;
  virtual void kinematics(std::size_t id, std::array<double, 3>& u, std::array<double, 3>& v) const = 0;
  virtual void add_to_group(const std::vector<std::uint32_t>& ids, std::uint32_t group) = 0;
  virtual std::vector<std::uint32_t> members(std::uint32_t group) const = 0;
  virtual void bcs_changed() = 0;
  virtual void initialise() = 0;
  virtual double critical_dt() const = 0;
  virtual double lambda_bound() const = 0;
  virtual double lambda_estimate() const = 0;
  virtual void check_dt() = 0;
  /// A wall was added: on an initialised model, the critical step is computed anew (walls
  /// limit it) and dt checked against it.
  virtual void walls_changed() = 0;
  virtual void run(std::int64_t steps, bool energies_at_end) = 0;
  virtual void settle(std::int64_t steps) = 0;
  virtual std::int64_t step_count() const = 0;
  virtual double time() const = 0;
  virtual std::int64_t last_good_step() const = 0;
  virtual std::array<double, 3> group_force(std::uint32_t group) const = 0;
  virtual double kinetic_energy() const = 0;
  virtual double bond_energy() const = 0;
  virtual double external_work() const = 0;
  virtual double exchange_work() const = 0;
  virtual double energy_floor() const = 0;
  virtual double damping_dissipation() const = 0;
  virtual std::size_t broken_count(int mode) const = 0;
  virtual std::size_t bond_count() const = 0;
  virtual std::size_t contact_count() const = 0;
  virtual std::int64_t steps_in_lattice_slots() const = 0;
  virtual const std::vector<BreakEvent>& breaks() const = 0;
  virtual std::vector<std::array<std::uint32_t, 2>> touching_pairs() const = 0;
  virtual std::vector<std::array<double, 3>> positions(Rows rows) const = 0;
  virtual std::vector<std::array<double, 3>> velocities(Rows rows) const = 0;
  virtual std::vector<std::array<double, 3>> displacements(Rows rows) const = 0;
  virtual std::vector<double> radii(Rows rows) const = 0;
  virtual std::vector<std::uint32_t> ids(Rows rows) const = 0;
  virtual std::vector<std::uint8_t> bond_counts() const = 0;
  /// Each particle's index into group_sets (internal order).
  virtual const std::vector<std::uint32_t>& particle_sets() const = 0;
  virtual std::vector<float> damage(Rows rows) const = 0;
  virtual std::vector<PairView> pairs(PairSet which) const = 0;
  virtual std::size_t memory_bytes() const = 0;
  /// The bonds' shear histories as doubles, NS per bond (checkpoints; empty when the model
  /// keeps none).
  virtual std::vector<double> bond_shear() const = 0;
  virtual std::size_t streamed_bytes_per_step() const = 0;
  virtual std::uint64_t state_hash() const = 0;
  /// Checkpoints (state.cpp): the run state by reference, and the rebuild of derived data
  /// after it has been overwritten.
  virtual StateRefs state_refs() = 0;
  virtual void state_loaded() = 0;
};

template <int D>
std::unique_ptr<ModelBase> make_model(const Settings& s);

/// Pair rule: the combined material of a pair of materials a and b (the same material
/// gives its own values; two give harmonic-mean stiffnesses, as springs in series scaled so
/// that equal materials give back their own, the weaker strengths and the smaller friction).
Material pair_material(const Material& a, const Material& b);

/// The DEM model of dimension D: ModelData<D>'s arrays plus set-up and run state.
template <int D>
class Model final : public ModelBase, public ModelData<D> {
 public:
  using Data = ModelData<D>;
  using Data::acc;
  using Data::bcp;
  using Data::bond_owner;
  using Data::bond_us;
  using Data::bonds;
  using Data::bonds_current;
  using Data::bonds_let_go;
  using Data::contacts;
  using Data::cross_b;
  using Data::cross_c;
  using Data::dist2;
  using Data::evbuf;
  using Data::flags;
  using Data::grp;
  using Data::id;
  using Data::im;
  using Data::kNs;
  using Data::mat;
  using Data::n;
  using Data::pend;
  using Data::pend_slot;
  using Data::plan;
  using Data::rad;
  using Data::rest_of;
  using Data::scaled;
  using Data::scratch;
  using Data::slots;
  using Data::slots_release;
  using Data::slots_steps;
  using Data::uniform_diameter;
  using Data::v;
  using Data::wall_energy_and_force;
  using Data::x;
  using Data::x0;

  explicit Model(const Settings& s) { settings = s; }

  // ---- set-up state --------------------------------------------------------------------
  mutable std::vector<std::uint32_t> inv_cache;  // id -> internal index (built on demand)
  std::unique_ptr<LawEngine<D>> engine;          // the pair law's kernels (refresh_laws)
  std::vector<PairStiffness> stiff;              // nmat × nmat stiffnesses of the pair laws
  int nmat = 0;
  bool sorted = false, initialised = false, bcs_dirty = true;
  bool rows_kept = false;  // kept in the order added row by row until bonded (keep_rows_if_lattice)
  double dt_crit = 0, lam_est = 0, lam_bound = 0;

  // ---- run state -------------------------------------------------------------------------
  std::int64_t step_ = 0, last_good = 0;
  std::int64_t settled = 0;  // steps of settling stages before step 0 (they seed BondShear's rounding)
  double time_ = 0;
  bool energy_valid = false;  // acc[].ke/eb are from the last step
  double energy_budget0 = 0, energy_tiny = 0;
  double v2_alarm = -1;       // < 0: to be computed (update_alarm); derived, not part of the state
  bool budget_dirty = false;  // velocities were set after initialise()
  bool contacts_on = false;
  double skin = 0, disp_bound = 0;
  std::vector<BreakEvent> events;
  bool plan_dirty = true;

  int dim() const override { return D; }

  /// Small models stay on one thread in set-up loops (a parallel region costs more than it
  /// saves there, and much more on a loaded machine).
  bool small_model() const { return small_model(n()); }
  /// The same for a model of `count` particles (one about to be that size).
  bool small_model(std::size_t count) const {
    return static_cast<std::ptrdiff_t>(count) <
           2 * static_cast<std::ptrdiff_t>(std::max(1, settings.min_particles_per_thread));
  }

  /// parallel_for for set-up loops (one thread for small models).
  template <typename F>
  void for_range(std::ptrdiff_t count, F&& fn) const {
    if (small_model()) {
      for (std::ptrdiff_t i = 0; i < count; ++i) fn(i);
    } else {
      par::parallel_for(count, std::forward<F>(fn));
    }
  }

  /// Set-up loops over fixed chunks of particles: fn(c) for c in [0, nc), the chunks split
  /// evenly over the threads (one thread for small models, as for_range).
  template <typename F>
  void for_chunks(std::ptrdiff_t nc, F&& fn) const {
    const int nt = small_model() ? 1 : static_cast<int>(std::min<std::ptrdiff_t>(par::threads(), nc));
    par::parallel_team(nt, [&](int t, int team) {
      for (std::ptrdiff_t c = nc * t / team; c < nc * (t + 1) / team; ++c) fn(c);
    });
  }

  // ---- storage and spatial order (model.cpp) ---------------------------------------------
  void reserve(std::size_t cap) override;
  std::size_t add_particle(std::array<double, 3> p, double r, int m, double mass) override;
  std::size_t add_particles(const std::vector<std::array<double, 3>>& p, double r, int m,
                            double mass) override;
  double checked_mass(double r, int m, double mass) const;
  std::size_t particle_count() const override { return n(); }
  std::vector<std::uint32_t> index_of_id() const;
  std::size_t index_of(std::size_t ident, const char* what) const;
  void set_velocity(std::size_t ident, std::array<double, 3> vel) override;
  void add_to_group(const std::vector<std::uint32_t>& ids, std::uint32_t group) override;
  std::vector<std::uint32_t> members(std::uint32_t group) const override;
  void bcs_changed() override { bcs_dirty = true; }
  void sort_particles(bool rows_allowed = false);
  bool added_in_rows() const;
  void keep_rows_if_lattice();
  void reorder(const std::vector<std::uint32_t>& perm);
  std::vector<std::array<double, 3>> pack(const std::array<aligned_vector<double>, D>& a, Rows rows) const;
  std::vector<std::array<double, 3>> positions(Rows rows) const override { return pack(x, rows); }
  std::vector<std::array<double, 3>> velocities(Rows rows) const override { return pack(v, rows); }
  std::vector<std::array<double, 3>> displacements(Rows rows) const override;
  std::vector<double> radii(Rows rows) const override;
  std::vector<std::uint32_t> ids(Rows rows) const override;
  std::vector<std::uint8_t> bond_counts() const override;
  const std::vector<std::uint32_t>& particle_sets() const override { return grp; }
  std::vector<float> damage(Rows rows) const override;
  std::size_t memory_bytes() const override;
  std::size_t streamed_bytes_per_step() const override;
  std::vector<double> bond_shear() const override { return bond_us.expanded(); }

  // ---- neighbour search, bonds, contacts, thread plan (search.cpp) -----------------------
  /// Cell grid over the particles: cell side h >= the largest search distance.
  struct Grid {
    double lo[3]{}, h = 1;
    std::int64_t dims[3]{1, 1, 1};
    std::vector<std::uint32_t> start, list;
    /// Position and radius of each listed particle, in list order: the candidates of a row of
    /// cells are read in one sweep.
    std::unique_ptr<std::array<double, D + 1>[]> at;
    std::int64_t cell_of(const double* p) const;
  };
  Grid build_grid(double h) const;
  std::size_t neighbours_after(const Grid& g, std::size_t p, std::vector<std::uint32_t>& cand) const;
  template <int kLists, typename Classify>
  std::array<PairList, kLists> build_pairs(const Grid& g, Classify&& classify) const;
  void bond_touching_pairs(double tol) override;
  void set_bonds(const std::vector<std::uint32_t>& bi, const std::vector<std::uint32_t>& bj,
                 const std::vector<double>& factor, const std::vector<double>& strength) override;
  bool bonded(std::size_t p, std::uint32_t q) const;
  void rebuild_contacts();
  /// Gives `candidates` (pairs within ri + rj + skin, not bonded) their states, carrying those
  /// of pairs already in the contact list, and makes them the contact list.
  void take_contacts(PairList candidates);
  /// The contact candidates bond_touching_pairs found in the same search as the bonds, for
  /// initialise(); valid while the particle count (its offsets' size less one) and the skin
  /// are those it had.
  PairList found_contacts;
  double found_contacts_skin = 0;
  /// The skin initialise() gives the contact search.
  double start_skin() const { return settings.skin > 0 ? settings.skin : 0.5 * rad.max(); }
  int effective_threads(int nt) const;
  /// The first particle of each thread's range (nt + 1 entries): whole blocks, each range
  /// about equal work, a cross pair counted as cross_cost bonds (thread plan).
  std::vector<std::ptrdiff_t> thread_ranges(int nt, double cross_cost) const;
  void build_plan(int nt);

  // ---- boundary conditions and driven particles (boundary.cpp) ---------------------------
  void resolve_bcs();
  /// BcParticle::load_dir of every particle with a condition, from its start position.
  void set_load_directions();
  void set_kinematics(std::size_t ident, const std::array<double, 3>& u,
                      const std::array<double, 3>& vel) override;
  void kinematics(std::size_t ident, std::array<double, 3>& u, std::array<double, 3>& vel) const override;

  // ---- pair law, set-up and run loop (run.cpp) ---------------------------------------------
  void refresh_laws();
  /// Whether pairs keep a shear history: not when every pair law's shear stiffness is zero
  /// (central forces only), whose shear force is then zero whatever the history holds.
  bool keeps_shear();
  /// Allocates (zero) or frees the pair lists' shear histories as keeps_shear() says.
  void fit_shear_history();
  /// The step of the bonds' 32-bit shear histories (BondShear) for the current pair laws.
  double shear_unit() const;
  void initialise() override;
  void check_dt() override;
  void keep_start_positions();
  void walls_changed() override {
    if (!initialised) return;
    compute_critical_dt();
    check_dt();
  }
  StepCtx step_context() const;
  void run(std::int64_t steps, bool energies_at_end) override;
  void settle(std::int64_t steps) override;
  void check_blowup(bool nan_seen);
  /// The blow-up check between two energy steps, on energies evaluated afresh: run when a
  /// particle moves faster than the energy budget allows (v2_alarm).
  void check_blowup_now();
  void check_energies(double ke, double eb, bool nan_seen, bool product_ke);
  /// v2_alarm from the current budget: a particle with |v|² above it holds more kinetic
  /// energy than the whole model may.
  void update_alarm();
  void merge_events();
  std::int64_t step_count() const override { return step_; }
  double time() const override { return time_; }
  std::int64_t last_good_step() const override { return last_good; }

  // ---- critical time step (critical_dt.cpp) ----------------------------------------------
  PairStiffness stiffness_of(const PairList& L, std::uint32_t k, std::size_t p, std::size_t j) const;
  template <typename Fn>
  void stiff_pairs_of(std::size_t p, Fn&& fn) const;
  void unit_normal(std::size_t p, std::uint32_t j, double nv[D]) const;
  void pair_matrix(std::size_t p, std::uint32_t j, const PairStiffness& k, double K[D][D]) const;
  void compute_critical_dt();
  double max_stiffness() const;
  double lanczos() const;
  double layer_mode_quotient() const;
  template <typename Real>
  double lanczos_impl() const;
  double critical_dt() const override { return dt_crit; }
  double lambda_bound() const override { return lam_bound; }
  double lambda_estimate() const override { return lam_est; }

  // ---- probes (probes.cpp) ---------------------------------------------------------------
  double dry_bond_energy() const;
  double dry_kinetic() const;
  std::array<double, 3> group_force(std::uint32_t group) const override;
  double kinetic_energy() const override;
  double bond_energy() const override;
  double external_work() const override;
  double exchange_work() const override;
  double energy_floor() const override { return energy_tiny; }
  double damping_dissipation() const override;
  std::size_t broken_count(int mode) const override;
  std::size_t bond_count() const override { return bonds.size(); }
  std::size_t contact_count() const override;
  std::int64_t steps_in_lattice_slots() const override { return slots_steps; }
  const std::vector<BreakEvent>& breaks() const override { return events; }
  std::vector<std::array<std::uint32_t, 2>> touching_pairs() const override;
  std::vector<PairView> pairs(PairSet which) const override;

  // ---- checkpoints and state hash (state.cpp) --------------------------------------------
  std::uint64_t state_hash() const override;
  StateRefs state_refs() override;
  void state_loaded() override;
};

}  // namespace strata::dem::detail
