#pragma once
// Not API: the arrays of the DEM model as the step kernel (step_kernel.hpp) sees them. The
// model itself (set-up, search, time step, probes, checkpoints) is libdem/src/model.hpp;
// the kernel is in a header so that a law added from outside libdem (register_law.hpp)
// gets a step loop compiled for it.
#include <strata/core/aligned.hpp>
#include <strata/dem/laws/common.hpp>
#include <strata/dem/simulation.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace strata::dem::detail {

inline constexpr std::uint32_t kNone = 0xffffffffu;
/// Particles per accumulator block: energy/work sums are formed per block and added in
/// block order, so they do not depend on the thread count. Thread ranges are whole blocks.
inline constexpr std::ptrdiff_t kBlock = 256;

/// Shear components per pair: a scalar along the tangent in 2D, a vector in 3D.
template <int D>
inline constexpr int kNsOf = D == 2 ? 1 : 3;

/// A constant of each particle (radius, inverse mass), stored once while every particle has
/// the same value (bit for bit) and one per particle from the first that differs: a model of
/// one size and material keeps 16 bytes per particle fewer.
class ParticleConst {
 public:
  double operator[](std::size_t i) const { return all_.empty() ? one_ : all_[i]; }
  std::size_t size() const { return n_; }
  bool uniform() const { return all_.empty(); }
  /// A pointer b such that b[i - first] is particle i's value, for i in the block of kBlock
  /// particles from `first` (the step loop reads a block's values without a branch).
  const double* block(std::size_t first) const { return all_.empty() ? fill_.data() : all_.data() + first; }
  /// The values one per particle, or nullptr while they are uniform.
  const double* per_particle() const { return all_.empty() ? nullptr : all_.data(); }
  void push_back(double value) {
    if (all_.empty()) {
      if (n_ == 0) {
        one_ = value;
        fill_.assign(kBlock, value);
      }
      if (std::bit_cast<std::uint64_t>(value) == std::bit_cast<std::uint64_t>(one_)) {
        ++n_;
        return;
      }
      all_.assign(n_, one_);
    }
    all_.push_back(value);
    ++n_;
  }
  /// Reorders as a[i] = a[perm[i]].
  void permute(const std::vector<std::uint32_t>& perm) {
    if (all_.empty()) return;
    aligned_vector<double> out(perm.size());
    for (std::size_t i = 0; i < perm.size(); ++i) out[i] = all_[perm[i]];
    all_.swap(out);
  }
  /// `count` more particles of one value.
  void append(std::size_t count, double value) {
    if (count == 0) return;
    push_back(value);
    if (!all_.empty()) all_.insert(all_.end(), count - 1, value);
    n_ += count - 1;
  }
  std::vector<double> values() const {
    return all_.empty() ? std::vector<double>(n_, one_) : std::vector<double>(all_.begin(), all_.end());
  }
  void assign(const std::vector<double>& values) {
    all_.clear();
    n_ = 0;
    for (const double x : values) push_back(x);
  }
  double max() const { return all_.empty() ? one_ : *std::max_element(all_.begin(), all_.end()); }
  std::size_t bytes() const { return all_.capacity() * sizeof(double); }

 private:
  aligned_vector<double> all_;
  aligned_vector<double> fill_;  // kBlock copies of the one value (block())
  double one_ = 0;
  std::size_t n_ = 0;
};

/// Bonds or contacts stored CSR by owner: the pairs (i, j > i) of owner i are
/// off[i] .. off[i+1]-1, sorted by j; i is implied.
struct PairList {
  std::vector<std::uint32_t> off{0};
  std::vector<std::uint32_t> j;
  std::vector<std::uint8_t> st;
  /// NS shear components per pair; empty when the model keeps none. Bonds keep theirs in
  /// ModelData::bond_us (32 bits where it suffices) and fill this one only to carry them
  /// (checkpoints, reordering).
  std::vector<double> us;
  // Bonds given as data only (Simulation::set_bonds; empty otherwise): rest length (the
  // initial centre distance), stiffness factor and strength factor of each bond; all apply
  // while the bond is intact.
  std::vector<double> r0, kf, sf;
  /// The pairs (also while a model stepping in lattice slots has let its bonds' partners go).
  std::size_t size() const { return off.back(); }
  std::size_t bytes() const {
    return off.capacity() * 4 + j.capacity() * 4 + st.capacity() +
           (us.capacity() + r0.capacity() + kf.capacity() + sf.capacity()) * 8;
  }
};

/// The shear histories of a model's bonds, NS components each, in 32 bits where that holds
/// them closely enough. An intact bond's components are integer multiples of `unit`, a power
/// of two chosen so that kReach = 2^30 units span at least twice the largest shear
/// displacement an intact bond of the model's pair laws holds (Fs0/Ks for the solid-lattice
/// law): the spacing is then under 4e-9 of that reach (3.6e-15 m for the rock of Liu,
/// Pollard & Shi 2013), against increments of about 3e-13 m per step in a quasi-static run.
/// Each step's new value is rounded to a neighbouring step at random, up with probability
/// equal to its fraction of the step (stochastic rounding), so that the rounding adds no
/// bias: rounding to nearest would repeat the same error every step where the increments
/// are steady (a quasi-static run), up to 0.6 % of the history there. The random numbers
/// are a hash of the bond's index, the step number and the component, so the results do not
/// depend on the thread count and a restart continues with the same bits. A bond the
/// 32 bits cannot hold is "wide": a broken bond (its friction slip is not bounded by a
/// strength) or an intact one beyond the reach (a bond strengthened by friction, or by its
/// strength factor). Its first slot then holds the index of its entry in `wide`, where its
/// components are kept in double precision. Which bonds are wide follows from the state
/// alone (broken, or beyond the reach), so a model reloaded from a checkpoint continues with
/// the same bits; the order of the entries in `wide` is not part of the state.
template <int NS>
struct BondShear {
  static constexpr double kReach = 1073741824.0;  ///< 2^30: the largest |Us|/unit held
  static constexpr double kReach2 = kReach * kReach;
  static constexpr std::int32_t kWideBelow = -(1 << 30);  ///< a first slot below it marks a wide bond
  /// NS per bond; let go (empty) while a model in lattice slots holds them there
  /// (ModelData::slots_let_go)
  std::vector<std::int32_t> q;
  std::size_t count = 0;     ///< NS × the model's bonds: q's size where it is held
  std::vector<double> wide;  ///< NS per wide bond (and stale entries of bonds held in 32 bits again)
  double unit = 0, inv = 0;  ///< powers of two; inv = 1/unit
  /// Whether an intact bond may be wide (one went beyond the reach at some time): until
  /// then only broken bonds are, and the bond pass finds them by their state alone.
  bool intact_wide = false;
  /// A bond that became wide during a step (h: where its first component is held, here or
  /// in lattice slots; neither is resized during a step), with its new components.
  struct Fresh {
    std::int32_t* h;
    bool intact;
    double u[NS];
  };
  /// Per thread of the plan: the bonds that became wide in this step; merge() gives them
  /// their entries when the step is done, in thread order.
  std::vector<std::vector<Fresh>> fresh;

  bool empty() const { return count == 0; }
  static bool is_wide(std::int32_t h) { return h < kWideBelow; }
  static std::size_t index_of(std::int32_t h) { return static_cast<std::uint32_t>(h) ^ 0x80000000u; }
  static std::int32_t code_of(std::size_t index) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(index) ^ 0x80000000u);
  }
  /// x rounded to the nearest integer, ties to even (|x| < 2^51; no rounding-mode change).
  static double nearest(double x) { return (x + 0x1.8p52) - 0x1.8p52; }
  /// nearest(x) as an integer (|x| < 2^31, the default rounding mode): with GCC one
  /// conversion under the current rounding mode, which vectorises, in place of nearest()'s
  /// two additions and a truncation.
  static std::int32_t nearest_int(double x) {
#if defined(__GNUC__) && !defined(__clang__)
    return __builtin_irint(x);
#else
    return static_cast<std::int32_t>(nearest(x));
#endif
  }
  /// The salt of step `step`: a hash of its number (Wellons' lowbias32, good avalanche).
  static std::uint32_t salt_of(std::int64_t step) {
    std::uint32_t h = static_cast<std::uint32_t>(step) ^ static_cast<std::uint32_t>(step >> 32);
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return h;
  }
  /// 32 random bits for bond k in the step of `salt`: the salt, a hash of the step number,
  /// offset by a Weyl sequence over the bonds (one multiply per bond in the step loop). Over
  /// the steps, a bond's bits are the hash's shifted by a constant.
  static std::uint32_t dither_bits(std::uint32_t k, std::uint32_t salt) { return k * 0x9e3779b1u + salt; }
  /// An offset in (-1/2, 1/2), a multiple of 1/1024 plus 1/2048, from 10 of the bits h =
  /// dither_bits(k, salt), different ones for each component a: nearest(x + offset) rounds
  /// x up with probability equal to its fraction, to within 1/2048 of a step.
  static double dither(std::uint32_t h, int a) {
    return static_cast<double>((h >> (22 - 10 * a)) & 1023u) * 0x1p-10 + (0x1p-11 - 0.5);
  }
  /// Component a of a bond, x = u/unit (within the reach), in steps, stochastically
  /// rounded with h = dither_bits(k, salt): the one rounding of both the bond pass and
  /// store(), so that the two give the same bits.
  static std::int32_t steps_of(double x, std::uint32_t h, int a) { return nearest_int(x + dither(h, a)); }
  /// The unit for bonds that hold up to `reach` (m) while intact.
  static double unit_for(double reach) {
    int e = 0;
    const double m = std::frexp(2 * reach / kReach, &e);  // m in [0.5, 1)
    return std::ldexp(1.0, m == 0.5 ? e - 1 : e);
  }
  /// Whether a Us of square u2 lies within the reach, |Us|/unit <= kReach (inv² is exact):
  /// the one test of both the bond pass and fits().
  static bool within(double u2, double inv) { return u2 * (inv * inv) <= kReach2; }
  /// Whether components u lie within the reach, from |u|² summed as the bond pass sums it.
  bool fits(const double* u) const {
    double u2 = 0;
    for (int a = 0; a < NS; ++a) u2 += u[a] * u[a];
    return within(u2, inv);
  }
  /// Bond k's components into u.
  void load(std::size_t k, double* u) const { load_at(q.data() + k * NS, u); }
  /// The components of the bond held at h (its NS entries, here or in lattice slots) into u.
  void load_at(const std::int32_t* h, double* u) const {
    if (is_wide(h[0])) {
      const double* w = wide.data() + index_of(h[0]) * NS;
      for (int a = 0; a < NS; ++a) u[a] = w[a];
    } else {
      for (int a = 0; a < NS; ++a) u[a] = h[a] * unit;
    }
  }
  /// Stores bond k's new components (thread t's step, salt salt_of(step)): in 32 bits when
  /// the bond is intact and within the reach, else in its wide entry, which a bond that was
  /// not wide gets at the step's end (merge).
  void store(int t, std::size_t k, std::uint32_t salt, bool intact, const double* u) {
    store_at(t, k, q.data() + k * NS, salt, intact, u);
  }
  /// The same for bond k held at h (here or in lattice slots). code_at: where the bond's
  /// first component lives, which gets its wide entry's code at the step's end if it needs
  /// one (h itself unless said: a caller that holds a copy of the components).
  void store_at(int t, std::size_t k, std::int32_t* h, std::uint32_t salt, bool intact, const double* u,
                std::int32_t* code_at = nullptr) {
    if (intact && fits(u)) {
      const std::uint32_t bits = dither_bits(static_cast<std::uint32_t>(k), salt);
      for (int a = 0; a < NS; ++a) h[a] = steps_of(u[a] * inv, bits, a);
    } else if (is_wide(h[0])) {
      double* w = wide.data() + index_of(h[0]) * NS;
      for (int a = 0; a < NS; ++a) w[a] = u[a];
    } else {
      Fresh f{code_at ? code_at : h, intact, {}};
      for (int a = 0; a < NS; ++a) f.u[a] = u[a];
      fresh[static_cast<std::size_t>(t)].push_back(f);
    }
  }
  /// Gives the bonds that became wide in the step their entries (serial, after the step).
  void merge() {
    for (auto& list : fresh) {
      for (const Fresh& f : list) add_wide_at(f.h, f.intact, f.u);
      list.clear();
    }
  }
  /// Zero histories for `bonds` bonds, held in steps of `new_unit`.
  void reset(std::size_t bonds, double new_unit) {
    q.assign(bonds * NS, 0);
    count = q.size();
    wide.clear();
    intact_wide = false;
    unit = new_unit;
    inv = 1.0 / new_unit;
  }
  void clear() {
    count = 0;
    q.clear();
    q.shrink_to_fit();
    wide.clear();
    wide.shrink_to_fit();
  }
  /// All bonds' components, NS per bond (checkpoints, reordering).
  std::vector<double> expanded() const {
    std::vector<double> u(q.size());
    for (std::size_t k = 0; k < q.size() / NS; ++k) load(k, u.data() + k * NS);
    return u;
  }
  /// Takes components u (NS per bond) of bonds in states st, held in steps of `new_unit`:
  /// a broken bond or one beyond the reach wide, the others rounded to the nearest step
  /// (values saved from 32 bits in the same steps come back exactly).
  void take(const std::vector<double>& u, const std::vector<std::uint8_t>& st, double new_unit) {
    reset(st.size(), new_unit);
    for (std::size_t k = 0; k < st.size(); ++k) {
      const double* uk = u.data() + k * NS;
      const bool intact = (st[k] & pair_state::kKindMask) == pair_state::kIntact;
      if (intact && fits(uk)) {
        for (int a = 0; a < NS; ++a) q[k * NS + a] = nearest_int(uk[a] * inv);
      } else {
        add_wide(k, intact, uk);
      }
    }
  }
  std::size_t bytes() const { return q.capacity() * 4 + wide.capacity() * 8; }

 private:
  /// Bond k (intact or not) gets a new wide entry holding u.
  void add_wide(std::size_t k, bool intact, const double* u) { add_wide_at(q.data() + k * NS, intact, u); }
  void add_wide_at(std::int32_t* h, bool intact, const double* u) {
    intact_wide |= intact;
    h[0] = code_of(wide.size() / NS);
    wide.insert(wide.end(), u, u + NS);
  }
};

/// Boundary condition of one particle (only particles with a condition have one).
struct BcParticle {
  std::uint32_t index = 0;    // internal index
  std::uint8_t mode[3]{};     // 0 free, 1 fixed, 2 velocity, 3 step displacement
  std::uint8_t exchange = 0;  // bit a: axis a is driven by another partition (coupling)
  double value[3]{};          // velocity (mode 2) or increment (mode 3)
  std::int64_t every[3]{};    // steps between increments (mode 3)
  int history = -1;           // force history index
  /// Multiplies the force history's value per axis: 1 for a force vector; for a radial load
  /// (whose history holds its magnitude on every axis) the unit direction away from the
  /// load's centre. Derived from the start positions (set_load_directions), not saved.
  double load_dir[3] = {1, 1, 1};
  double dx_prev[3]{};    // last step's displacement (trapezoid work)
  double f_int[3]{};      // last internal force
  double w_ahead = 0;     // work booked for the half interval after the last step
  double w_ahead_ex = 0;  // the part of w_ahead on exchange axes
  double ke_driven = 0;   // ½·Σ v(n-½)·v(n+½)/m⁻¹ over the prescribed axes, last step
};

/// Rigid frictionless plane: point, unit normal (towards the particles), velocity, stiffness.
struct Wall {
  double p[3], n[3], v[3], k;
};

/// Per-block accumulators (padded to a cache line).
struct alignas(kCacheLine) BlockAcc {
  double work = 0;        // prescribed motion, applied forces, walls (accumulated)
  double work_ex = 0;     // the part of work on exchange axes (coupling, accumulated)
  double dissipated = 0;  // damping (accumulated)
  double ke = 0;          // kinetic energy at the last energy step
  double eb = 0;          // pair + wall energy at the last energy step
  double vmax2 = 0;       // largest |v|² in the last step
  double vfree2 = 0;      // the same over free motion only (prescribed axes left out)
};

/// A bond break as the step records it (per thread; merged into BreakEvents after run()).
struct RawEvent {
  std::int64_t step;
  double pos[3];
  std::uint8_t mode;
  std::uint32_t i, j;
};

/// A cross pair's slot that a thread gathers into particle `target`.
struct Incoming {
  std::uint32_t slot, target;
  bool contact;
};

/// Blocks of pending forces a thread keeps in its ring (see PendingPool): 32,768 particles,
/// 786 KB in 3D. With 32 blocks more of a large model's partners lay beyond the ring, in
/// slots, and a 1.3e7-sphere cube stepped 4 % slower.
inline constexpr std::ptrdiff_t kRingBlocks = 128;
/// Particles per slot of pending forces beyond the ring (see PendingPool): the front's
/// partners lie scattered there, a few per block, so slots of whole blocks would hold
/// mostly zeros (the slots of a 10^6-sphere cube on two threads: 4.7 B per sphere in slots
/// of whole blocks, 2.4 B in slots of 32 particles).
inline constexpr std::ptrdiff_t kSlot = 32;
static_assert(kBlock % kSlot == 0, "a block is whole slots");

/// Forces pending for particles not yet updated in a step, one pool per thread of the plan.
/// A pair's force on its partner j (j > its owner, in the same thread's range) is added to
/// j's entry when the owner is updated, and read when j is. Entries are held only along the
/// front between the particles already updated and those still to come, not in an array
/// over all particles: a ring over the block being updated and the kRingBlocks - 1 after it
/// (nearly every partner in the spatial order), and for a group of kSlot particles further
/// ahead a slot of its own, taken when a force first arrives and moved into the ring when
/// its block enters it, so that every entry sums its forces in the same order as one array
/// would.
struct PendingPool {
  std::vector<double> ring;  // D × (kRingBlocks · kBlock), component-major; block b at b mod kRingBlocks
  std::vector<double> buf;   // slots × D × kSlot, component-major within a slot
  std::vector<std::int32_t> spare;  // slots free for reuse
};

/// A cross pair as the thread of its partner computes it: its owner, its index in its list
/// (bonds or contacts) and its slot.
struct CrossPair {
  std::uint32_t owner, pair, slot;
  bool contact;
};

/// Where a thread must wait for another's cross pairs: before block `blk`, until thread `by`
/// has computed the first `count` of its list (those owned before the block's end).
struct CrossWait {
  std::ptrdiff_t blk;
  int by;
  std::size_t count;
};

/// Thread plan (rebuilt when the thread count or the contact lists change): contiguous
/// ranges of whole blocks; pairs whose partner lies in a later thread's range ("cross
/// pairs") are computed into slots, and gathered by both ends in the same order as in a
/// one-thread run. The thread of the partner computes them (phase A), in ascending owner,
/// before it moves any of its particles, counting them in its flag; the thread of the owner
/// reads that count before each block holding such owners, so that no thread waits at a
/// barrier for another's phase A.
struct Plan {
  int nt = 0;
  std::vector<std::ptrdiff_t> begin;
  std::vector<std::size_t> base_b, base_c;  // each thread's first slot of the cross pairs it owns
  std::vector<std::vector<Incoming>> in;
  std::vector<std::vector<CrossPair>> calc;   // per thread: the cross pairs it computes
  std::vector<std::vector<CrossWait>> waits;  // per thread, in block order
  /// Per thread, a cache line apart: the cross pairs it has computed since the plan was
  /// built, calc.size() per step; `epoch` counts the steps begun.
  static constexpr std::size_t kFlagStride = kCacheLine / sizeof(std::int64_t);
  std::vector<std::int64_t> done;
  std::int64_t epoch = 0;
  /// Thread u's count of computed cross pairs, shared between threads.
  std::atomic_ref<std::int64_t> counter(int u) {
    return std::atomic_ref<std::int64_t>(done[u * kFlagStride]);
  }
  /// Thread u's count when this step began.
  std::int64_t counted_before_step(int u) const {
    return (epoch - 1) * static_cast<std::int64_t>(calc[u].size());
  }
};

/// Per-thread scratch of the bond pass of one block: each bond's force on its owner, its
/// energy, and whether the reference kernel must redo it.
template <int D>
struct Scratch {
  std::array<std::vector<double>, D> fb;
  std::vector<double> en;
  std::vector<std::uint8_t> slow;
  /// The owner of each bond of the block relative to the block's start (one byte: kBlock =
  /// 256), expanded from the CSR offsets block by block where the model keeps no
  /// ModelData::bond_owner.
  std::vector<std::uint8_t> own;
  static_assert(kBlock <= 256, "own holds owner offsets in one byte");
  /// Zero shear histories the bond pass reads where the model keeps none (never written).
  std::vector<std::int32_t> no_us;
  /// The bond pass in lattice slots: the bonds left to the reference kernel (bond index,
  /// owner, direction); the verdicts of one direction's entries of a block go to `slow`.
  std::vector<std::array<std::uint32_t, 3>> sref;
  void fit(std::size_t m) {
    if (own.size() < m + 8) own.resize(m + 8);  // the owners' eight-byte writes reach 7 past the last bond
    if (en.size() >= m) return;
    for (auto& a : fb) a.resize(m);
    en.resize(m);
    slow.resize(m);
  }
};

/// The most ring entries a direction of the slots takes (the longest offset it serves:
/// 32512, rows of that many disks or layers of that many spheres).
inline constexpr std::size_t kMaxSlotRing = 32768;

/// Bonds in lattice slots: a model whose particles are numbered so that every bond's
/// partner lies at one of a few fixed offsets from its owner (a hexagonal lattice numbered
/// row by row: owner + 1, owner + L - 1, owner + L for rows of L and L - 1 disks). Its bond
/// pass can then run direction by direction: eight consecutive owners have eight consecutive
/// partners, whose positions and velocities load as whole vectors instead of element by
/// element; and each particle pulls its bonds' forces from per-direction arrays, in the
/// order the step loop otherwise pushes them (ascending owner, then its own bonds by
/// ascending partner), so the two forms give the same bits. Set by Model::build_plan; the
/// step kernel takes this form for a model of one material, bonds without per-bond rest
/// lengths and no contacts at the time, on any number of threads: each has a ring of its
/// own, and the bonds that cross into a later thread's range are computed by that thread
/// (phase A) and copied into both rings (docs/dem.md, "Bonds in lattice slots").
template <int D>
struct LatticeSlots {
  /// Directions: three for a hexagonal lattice of rows of L and L - 1 disks (partners p + 1,
  /// p + L - 1, p + L), four for one of rows of L disks each (an owner in an even row bonds
  /// to p + 1, p + L - 1 and p + L, one in an odd row to p + 1, p + L and p + L + 1). A
  /// close-packed box of layers of M spheres adds four to six into the next layer (p + M +
  /// {-L, -1, 0, 1, L - 1, L} and their like): at most ten.
  static constexpr int kMax = D == 2 ? 4 : 10;
  using Mask = std::conditional_t<D == 2, std::uint8_t, std::uint16_t>;
  int n = 0;                  // directions; 0: the model is not held in slots
  std::uint32_t off[kMax]{};  // each direction's partner offset, ascending
  /// Per particle, bit d: it owns a bond in direction d (its partner is p + off[d]). That
  /// bond's index is bonds.off[p] + the number of p's bonds in earlier directions.
  aligned_vector<Mask> mask;
  /// Forces (D per direction) and energies of the bonds a block's owners hold, per thread
  /// and direction, in a ring over the particles: direction d's has ring[d] entries, a
  /// power of two, at least off[d] + kBlock, so an owner's entry lives until its partner
  /// has pulled it (in 3D the directions within a layer need a few hundred entries, those
  /// into the next layer a layer's worth).
  std::size_t ring[kMax]{};
  std::size_t at[kMax]{};  // the entries of directions before d: sum of ring[0..d)
  std::size_t per = 0;     // the entries of all directions: one thread's
  int threads = 1;
  // f: [thread][direction][axis][ring entry], en: [thread][direction][ring entry]
  aligned_vector<double> f, en;
  /// The bonds' state by column and owner, [col[d]][p], and their shear histories
  /// (BondShear's 32-bit steps or wide code) by column, component and owner,
  /// [col[d]][a][p] (us_at): the bond pass reads each component of consecutive owners as one
  /// vector, with nothing to split apart. Where a model steps in slots these are its bonds'
  /// state, and the bonds' own arrays (PairList::st, BondShear::q) are brought up to date
  /// when something else reads them (ModelData::bonds_current). Directions no particle
  /// owns both of share a column (p + L - 1 and p + L + 1 in a lattice of rows of equal
  /// length: 3 columns for 4 directions). An entry without a bond in any of its column's
  /// directions holds kIntact and zeros; the bond pass leaves every entry without a bond
  /// in the direction it computes as it was.
  aligned_vector<std::uint8_t> st;
  aligned_vector<std::int32_t> uq;
  bool held = false;   // st and uq hold the bonds' state
  bool ahead = false;  // ... and the bonds' own arrays are behind it
  /// The bond of owner p in direction d (bit d of mask[p] set), given p's first bond.
  static std::uint32_t bond(std::uint32_t first, Mask m, int d) {
    return first + static_cast<std::uint32_t>(std::popcount(static_cast<unsigned>(m & ((1u << d) - 1))));
  }
  int cols = 0;
  int col[kMax]{};
  /// Per direction, the runs of owners with a bond in it, [begin, end) in pairs from
  /// run[run_at[d]] to run[run_at[d + 1]], across gaps of fewer than kGap owners without
  /// one (the bond pass computes those as stand-ins and drops them): a direction that
  /// alternates with the row leaves whole rows out, which the pass then skips.
  static constexpr std::uint32_t kGap = 16;
  std::vector<std::uint32_t> run;
  std::size_t run_at[kMax + 1]{};
  /// Direction d's runs from the first that ends past owner lo on (a pointer to its begin),
  /// and the end of d's runs.
  std::pair<const std::uint32_t*, const std::uint32_t*> runs_from(int d, std::uint32_t lo) const {
    const std::uint32_t* rb = run.data() + run_at[d];
    const std::uint32_t* rend = run.data() + run_at[d + 1];
    std::ptrdiff_t first = 0, hi = (rend - rb) / 2;  // ends are the odd entries, ascending
    while (first < hi) {
      const std::ptrdiff_t mid = (first + hi) / 2;
      if (rb[2 * mid + 1] <= lo)
        first = mid + 1;
      else
        hi = mid;
    }
    return {rb + 2 * first, rend};
  }
  /// The entry of owner p's bond in direction d in st, of n particles.
  std::size_t entry(int d, std::size_t p, std::size_t n) const {
    return static_cast<std::size_t>(col[d]) * n + p;
  }
  /// Where component a of the shear history of owner p's bond in direction d lies in uq, of
  /// n particles.
  std::size_t us_at(int d, int a, std::size_t p, std::size_t n) const {
    return (static_cast<std::size_t>(col[d]) * kNsOf<D> + static_cast<std::size_t>(a)) * n + p;
  }
  /// The direction of bond k, owned by a particle with mask m whose first bond is `first`.
  int direction(std::uint32_t first, Mask m, std::uint32_t k) const {
    int d = 0;
    for (std::uint32_t b = first;; ++d)
      if (m >> d & 1u && b++ == k) return d;
  }
  /// Whether owner p holds a bond to partner q > p.
  bool bonds_to(std::size_t p, std::size_t q) const {
    for (int d = 0; d < n; ++d)
      if (off[d] == q - p) return mask[p] >> d & 1u;
    return false;
  }
  double* force(int t, int d, int a) {
    return f.data() + (static_cast<std::size_t>(t) * per + at[d]) * D + static_cast<std::size_t>(a) * ring[d];
  }
  double* energy(int t, int d) { return en.data() + static_cast<std::size_t>(t) * per + at[d]; }
  /// Direction d's ring entry of owner p.
  std::size_t slot(int d, std::size_t p) const { return p & (ring[d] - 1); }
};

/// The slots of `bonds` over n particles, with rings for `threads` threads (LatticeSlots::n
/// = 0 where they do not fit: more than LatticeSlots::kMax offsets, or one beyond a ring).
template <int D>
LatticeSlots<D> lattice_slots(const PairList& bonds, std::size_t n, int threads = 1);
/// The distinct offsets of `bonds`' partners from their owners, ascending, into offs;
/// whether they fit lattice slots (lattice_slots would hold them).
template <int D>
bool slot_offsets(const PairList& bonds, std::size_t n, std::vector<std::uint32_t>& offs);

/// What one step needs besides the arrays.
struct StepCtx {
  double dt, t, g[3];
  std::int64_t step;
  /// Seeds the rounding of the bonds' shear histories (BondShear::salt_of of the steps
  /// taken in all, settling included: a settling stage resets `step`).
  std::uint32_t salt;
  std::vector<std::array<double, 3>> hist;  // force of each force history at time t
  Settings::Damping damping;
  double viscous_c, local_alpha;
  const Wall* walls;
  std::size_t nwalls;
  bool slots;  // Settings::lattice_slots
};

/// The model's arrays: particles (structure of arrays, internal order), pairs, boundary
/// records, accumulators, and the thread plan with its scratch.
template <int D>
struct ModelData {
  static constexpr int kNs = kNsOf<D>;

  // ---- particle arrays -----------------------------------------------------------------
  std::array<aligned_vector<double>, D> x, v, x0;
  ParticleConst im, rad;  // inverse mass (1/kg), radius (m)
  std::vector<std::uint32_t> id, grp;
  std::vector<std::uint8_t> mat;
  aligned_vector<std::uint8_t> flags;  // flags bit 0: particle has a boundary condition
  PairList bonds, contacts;
  BondShear<kNs> bond_us;       // the bonds' shear histories (empty when the model keeps none)
  std::vector<BcParticle> bcp;  // sorted by index
  std::vector<BlockAcc> acc;
  LatticeSlots<D> slots;
  std::int64_t slots_steps = 0;  // steps taken in slots

  // ---- thread plan and step scratch ----------------------------------------------------
  Plan plan;
  std::vector<Scratch<D>> scratch;
  std::vector<std::vector<RawEvent>> evbuf;
  double uniform_diameter = 0;           // 2r when every particle has radius r, else 0 (set by build_plan)
  std::vector<double> cross_b, cross_c;  // D forces + 1 energy per slot
  /// Per group of kSlot particles: its slot in its thread's pool of pending forces, or -1
  /// (see PendingPool).
  std::vector<std::int32_t> pend_slot;
  std::vector<PendingPool> pend;  // per thread of the plan
  /// The owner of each bond relative to the start of its block (one byte per bond: kBlock =
  /// 256), kept where the model keeps no shear history: a lattice of normal springs, whose
  /// bond pass is cheap enough that deriving owners every step would cost 5 % of it, and
  /// whose memory is far below that of one with shear springs. A model with a shear history
  /// keeps none (a byte per bond, 6 B per sphere): its bond pass expands the owners of each
  /// block from the offsets (Scratch::own).
  std::vector<std::uint8_t> bond_owner;

  static constexpr std::size_t kRing = static_cast<std::size_t>(kRingBlocks * kBlock);
  /// Distance between the ring's components: 16 doubles more than kRing, so that the same
  /// particle's components do not lie a multiple of 4 KiB apart (a store to one and a load of
  /// the next would then wait on each other: 10 % of a small model's step).
  static constexpr std::size_t kRingStride = kRing + 16;

  /// Subtracts force F from the pending entry of particle j beyond the ring, in thread t's
  /// pool: the slot of j's group of kSlot particles, taken (zeroed) when the group has none
  /// yet. Out of line: rare, and kept out of the step loop's registers.
  [[gnu::noinline, gnu::cold]] void pending_far_sub(int t, std::uint32_t j, const double* F) {
    const std::size_t grp_of_j = j / kSlot;
    std::int32_t s = pend_slot[grp_of_j];
    PendingPool& P = pend[t];
    if (s < 0) {
      if (P.spare.empty()) {
        s = static_cast<std::int32_t>(P.buf.size() / (D * kSlot));
        P.buf.resize(P.buf.size() + D * kSlot, 0.0);
      } else {
        s = P.spare.back();
        P.spare.pop_back();
      }
      pend_slot[grp_of_j] = s;
    }
    double* q = P.buf.data() + static_cast<std::size_t>(s) * (D * kSlot) + j % kSlot;
    for (int a = 0; a < D; ++a) q[a * kSlot] -= F[a];
  }
  /// Block blk of thread t (whose range ends at particle e) is updated: its ring entries
  /// are zeroed, and the block kRingBlocks ahead, which takes its place in the ring, brings
  /// the forces it has pending so far from its groups' slots.
  [[gnu::noinline]] void pending_advance(int t, std::ptrdiff_t blk, std::ptrdiff_t e) {
    PendingPool& P = pend[t];
    const std::size_t at = static_cast<std::size_t>(blk % kRingBlocks) * kBlock;
    const std::ptrdiff_t nb = blk + kRingBlocks;
    for (std::ptrdiff_t g = 0; g < kBlock / kSlot; ++g) {
      const std::size_t grp = static_cast<std::size_t>(nb * (kBlock / kSlot) + g);
      const std::int32_t s = nb * kBlock + g * kSlot < e ? pend_slot[grp] : -1;
      for (int a = 0; a < D; ++a) {
        double* r = P.ring.data() + a * kRingStride + at + g * kSlot;
        if (s < 0) {
          std::fill(r, r + kSlot, 0.0);
        } else {
          double* q = P.buf.data() + (static_cast<std::size_t>(s) * D + a) * kSlot;
          std::copy(q, q + kSlot, r);
          std::fill(q, q + kSlot, 0.0);
        }
      }
      if (s >= 0) {
        P.spare.push_back(s);
        pend_slot[grp] = -1;
      }
    }
  }

  std::size_t n() const { return x[0].size(); }

  /// Calls f(k, p, d) for every bond k held in slots: owner p, direction d.
  template <typename Fn>
  void for_each_slot(Fn&& f) const {
    const std::size_t N = n();
    for (std::size_t p = 0; p < N; ++p) {
      std::uint32_t k = bonds.off[p];
      for (int d = 0; d < slots.n; ++d)
        if (slots.mask[p] >> d & 1u) f(k++, p, d);
    }
  }
  /// Bond k (owner p, direction d) from the bonds' arrays into its slot, or back.
  void slot_take(std::uint32_t k, std::size_t p, int d) {
    slots.st[slots.entry(d, p, n())] = bonds.st[k];
    if (!bond_us.empty())
      for (int a = 0; a < kNs; ++a) slots.uq[slots.us_at(d, a, p, n())] = bond_us.q[std::size_t{k} * kNs + a];
  }
  void slot_give(std::uint32_t k, std::size_t p, int d) {
    bonds.j[k] = static_cast<std::uint32_t>(p + slots.off[d]);
    bonds.st[k] = slots.st[slots.entry(d, p, n())];
    if (!bond_us.empty())
      for (int a = 0; a < kNs; ++a) bond_us.q[std::size_t{k} * kNs + a] = slots.uq[slots.us_at(d, a, p, n())];
  }
  /// The bonds' state into the slots, which hold it from now on (the bonds' own arrays of
  /// it are let go by the step: slots_let_go).
  void slots_take_state() {
    const std::size_t ns = static_cast<std::size_t>(slots.cols) * n();
    slots.st.assign(ns, pair_state::kIntact);
    slots.uq.assign(bond_us.empty() ? 0 : ns * kNs, 0);
    for_each_slot([&](std::uint32_t k, std::size_t p, int d) { slot_take(k, p, d); });
    slots.held = true;
    slots.ahead = false;
  }
  /// The bonds' arrays brought up to date with the slots, where a step in slots has left
  /// them behind. Called by whatever reads them between steps: the state is the same, only
  /// where it is held changes, hence const.
  void bonds_current() const {
    if (!slots.ahead) return;
    auto& self = const_cast<ModelData&>(*this);
    if (bonds_let_go()) {  // held again
      self.bonds.j.resize(bonds.size());
      self.bonds.st.resize(bonds.size());
      self.bond_us.q.resize(bond_us.count);
    }
    self.for_each_slot([&](std::uint32_t k, std::size_t p, int d) { self.slot_give(k, p, d); });
    self.slots.ahead = false;
  }
  /// While a model steps in slots, the bonds' partners and their state (PairList::j and st,
  /// BondShear::q: 9 B per bond in 2D, 17 in 3D) are let go: the slots' masks and offsets
  /// say the partners. bonds_current() allocates them again when something reads them
  /// between steps, until the next step.
  void slots_let_go() {
    if (bonds_let_go() || bonds.size() == 0) return;
    std::vector<std::uint32_t>().swap(bonds.j);  // their memory goes (clear() would keep it)
    std::vector<std::uint8_t>().swap(bonds.st);
    std::vector<std::int32_t>().swap(bond_us.q);
    slots.ahead = true;
  }
  /// Whether the bonds' partner and state arrays are let go (slots_let_go).
  bool bonds_let_go() const { return bonds.j.size() != bonds.size(); }
  /// The bonds' arrays up to date and the slots' copy let go (before the arrays change, or a
  /// step that does not use slots).
  void slots_release() {
    bonds_current();
    slots.held = false;
  }

  double dist2(std::size_t p, std::size_t q) const {
    double s = 0;
    for (int a = 0; a < D; ++a) {
      const double d = x[a][q] - x[a][p];
      s += d * d;
    }
    return s;
  }

  /// Length at which pair k of L (between p and j) carries no normal force: ri + rj (the
  /// disks/spheres touch), or an eccentric-lattice bond's initial length (intact or broken:
  /// a broken one pushes back once shorter than that, as two touching grains would).
  double rest_of(const PairList& L, std::uint32_t k, std::size_t p, std::size_t j) const {
    return L.r0.empty() ? rad[p] + rad[j] : L.r0[k];
  }

  /// The shear history of pair k of L, or `none` zeroed when the model keeps none (every
  /// pair law's shear stiffness is zero: the law's shear force is then zero whatever it reads).
  static double* us_of(PairList& L, std::uint32_t k, double* none) {
    if (L.us.empty()) {
      for (int s = 0; s < kNs; ++s) none[s] = 0.0;
      return none;
    }
    return &L.us[std::size_t{k} * kNs];
  }

  /// Pair k of L's shear history into u: zeros when the model keeps none.
  void load_us(const PairList& L, std::uint32_t k, double* u) const {
    if (&L == &bonds) {
      if (bond_us.empty())
        for (int s = 0; s < kNs; ++s) u[s] = 0.0;
      else
        bond_us.load(k, u);
    } else {
      for (int s = 0; s < kNs; ++s) u[s] = L.us.empty() ? 0.0 : L.us[std::size_t{k} * kNs + s];
    }
  }

  /// Whether pair k of L is an intact bond given as data, whose Kn and Ks are scaled by its
  /// stiffness factor kf[k] and its strengths by its strength factor sf[k].
  bool scaled(const PairList& L, std::uint32_t k) const {
    return !L.kf.empty() && (L.st[k] & pair_state::kKindMask) == pair_state::kIntact;
  }

  /// Wall forces on particle p added to F; returns their stored energy.
  double wall_energy_and_force(const Wall* walls, std::size_t nwalls, std::size_t p, double* F) const {
    double e = 0;
    for (std::size_t k = 0; k < nwalls; ++k) {
      const Wall& w = walls[k];
      double s = 0;
      for (int a = 0; a < D; ++a) s += (x[a][p] - w.p[a]) * w.n[a];
      const double delta = rad[p] - s;
      if (delta > 0) {
        for (int a = 0; a < D; ++a) F[a] += w.k * delta * w.n[a];
        e += 0.5 * w.k * delta * delta;
      }
    }
    return e;
  }
};

}  // namespace strata::dem::detail
