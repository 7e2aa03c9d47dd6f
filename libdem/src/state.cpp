// Checkpoints of the DEM: Simulation::save_state / load_state, and the state hash.
//
// One description of the state (describe() below) drives both directions, so what is saved
// and what is loaded cannot drift apart. Everything a later step reads is stored as it is in
// memory (internal particle order, CSR pair lists, per-block accumulators, the Verlet-list
// displacement bound), so a loaded model steps on along the same floating-point path as the
// one that saved it. Derived data (pair-law table, thread plan) is rebuilt by state_loaded().
#include <strata/core/error.hpp>
#include <strata/core/state_io.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include "model.hpp"

namespace strata::dem {
namespace {

using detail::BcParticle;
using detail::BcSpec;
using detail::BlockAcc;
using detail::ForceHistory;
using detail::ModelBase;
using detail::PairList;
using detail::StateRefs;
using detail::Wall;

// Version of the layout below; a change of layout must raise it. Format 1 had no pair-law
// names (all its materials use solid_lattice); formats 1 and 2 stored groups as one bit per
// group (at most 32) instead of group sets, and had no radial loads; formats 1 to 3 had
// linear force histories only (no ramp); formats 1 to 4 stored a force accumulator per
// particle, zero between steps, which is not read; formats 1 to 5 held the bonds' shear
// histories in double precision throughout (they are taken into 32-bit steps on loading)
// and did not count the steps of settling stages (taken as none). All are still read.
constexpr std::int64_t kFormat = 6;
constexpr std::int64_t kOldestFormat = 1;

// How a member of type T is stored: bool as uint8, int and enums as int64.
template <typename T>
auto stored_tag() {
  if constexpr (std::is_enum_v<T> || std::is_same_v<T, int>)
    return std::int64_t{};
  else if constexpr (std::is_same_v<T, bool>)
    return std::uint8_t{};
  else if constexpr (std::is_same_v<T, unsigned>)
    return std::uint32_t{};
  else
    return T{};
}
template <typename T>
using Stored = decltype(stored_tag<T>());

// Number of elements of a member: C arrays and std::array have several, scalars one.
template <typename M>
struct Extent {
  using Elem = M;
  static constexpr std::size_t n = 1;
  static Elem& at(M& m, std::size_t) { return m; }
};
template <typename E, std::size_t N>
struct Extent<E[N]> {
  using Elem = E;
  static constexpr std::size_t n = N;
  static Elem& at(E (&m)[N], std::size_t k) { return m[k]; }
};
template <typename E, std::size_t N>
struct Extent<std::array<E, N>> {
  using Elem = E;
  static constexpr std::size_t n = N;
  static Elem& at(std::array<E, N>& m, std::size_t k) { return m[k]; }
};

// Writes the state described by describe().
struct Saver {
  static constexpr bool kLoading = false;
  StateWriter& w;

  bool has(const std::string&) const { return true; }
  template <typename T>
  void scalar(const std::string& name, T& value) {
    w.put_scalar<Stored<T>>("dem/" + name, static_cast<Stored<T>>(value));
  }
  template <typename T, typename A>
  void vec(const std::string& name, std::vector<T, A>& values) {
    w.put("dem/" + name, values);
  }
  void vec(const std::string& name, detail::ParticleConst& values) { w.put("dem/" + name, values.values()); }
  void strings(const std::string& name, std::vector<std::string>& values) {
    std::vector<std::uint32_t> len;
    std::string all;
    for (const auto& s : values) {
      len.push_back(static_cast<std::uint32_t>(s.size()));
      all += s;
    }
    w.put("dem/" + name + "/length", len);
    w.put_string("dem/" + name + "/text", all);
  }
  // Rows of a struct stored as one array per member ("columns").
  template <typename S, typename Fn>
  void table(const std::string& name, std::vector<S>& rows, Fn&& columns) {
    w.put_scalar<std::int64_t>("dem/" + name + "/count", static_cast<std::int64_t>(rows.size()));
    columns([&](const char* col, auto S::*member) {
      using M = std::remove_reference_t<decltype(rows[0].*member)>;
      using X = Extent<M>;
      using St = Stored<typename X::Elem>;
      std::vector<St> out;
      out.reserve(rows.size() * X::n);
      for (S& r : rows)
        for (std::size_t k = 0; k < X::n; ++k) out.push_back(static_cast<St>(X::at(r.*member, k)));
      w.put("dem/" + name + "/" + col, out);
    });
  }
};

// Reads the state described by describe(), checking element types and counts.
struct Loader {
  static constexpr bool kLoading = true;
  const StateReader& r;

  bool has(const std::string& name) const { return r.has("dem/" + name); }
  template <typename T>
  void scalar(const std::string& name, T& value) {
    value = static_cast<T>(r.get_scalar<Stored<T>>("dem/" + name));
  }
  template <typename T, typename A>
  void vec(const std::string& name, std::vector<T, A>& values) {
    r.get_into("dem/" + name, values);
  }
  void vec(const std::string& name, detail::ParticleConst& values) {
    values.assign(r.get<double>("dem/" + name));
  }
  void strings(const std::string& name, std::vector<std::string>& values) {
    const auto len = r.get<std::uint32_t>("dem/" + name + "/length");
    const std::string all = r.get_string("dem/" + name + "/text");
    values.clear();
    std::size_t pos = 0;
    for (const auto l : len) {
      STRATA_CHECK(pos + l <= all.size(), IO, "state 'dem/{}': lengths exceed the text", name);
      values.push_back(all.substr(pos, l));
      pos += l;
    }
  }
  template <typename S, typename Fn>
  void table(const std::string& name, std::vector<S>& rows, Fn&& columns) {
    const auto count = r.get_scalar<std::int64_t>("dem/" + name + "/count");
    STRATA_CHECK(count >= 0, IO, "state 'dem/{}/count' = {} is negative", name, count);
    rows.assign(static_cast<std::size_t>(count), S{});
    columns([&](const char* col, auto S::*member) {
      using M = std::remove_reference_t<decltype(rows[0].*member)>;
      using X = Extent<M>;
      using St = Stored<typename X::Elem>;
      const auto in = r.get<St>("dem/" + name + "/" + col, rows.size() * X::n);
      for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t k = 0; k < X::n; ++k)
          X::at(rows[i].*member, k) = static_cast<typename X::Elem>(in[i * X::n + k]);
    });
  }
};

template <typename Io>
void pair_list(Io& io, const std::string& name, PairList& L) {
  io.vec(name + "/offsets", L.off);
  io.vec(name + "/partner", L.j);
  io.vec(name + "/state", L.st);
  io.vec(name + "/shear_displacement", L.us);  // bonds: carried in L.us while saved or loaded
  io.vec(name + "/rest_length", L.r0);         // eccentric lattices only (else empty)
  io.vec(name + "/stiffness_factor", L.kf);
  if (io.has(name + "/strength_factor"))  // from format 3
    io.vec(name + "/strength_factor", L.sf);
  else if constexpr (Io::kLoading)
    L.sf.assign(L.kf.size(), 1.0);
}

// The whole state, in one place for both directions.
template <typename Io>
void describe(Io& io, ModelBase& m, const StateRefs& s) {
  // settings (min_particles_per_thread is a performance knob that does not change results)
  Settings& st = m.settings;
  io.scalar("settings/dt", st.dt);
  io.scalar("settings/allow_unstable", st.allow_unstable);
  io.scalar("settings/damping", st.damping);
  io.scalar("settings/viscous_c", st.viscous_c);
  io.scalar("settings/local_alpha", st.local_alpha);
  std::vector<double> g(st.gravity.begin(), st.gravity.end());
  io.vec("settings/gravity", g);
  if constexpr (Io::kLoading) {
    STRATA_CHECK(g.size() == 3, IO, "state 'dem/settings/gravity' has {} components, expected 3", g.size());
    for (int a = 0; a < 3; ++a) st.gravity[a] = g[a];
  }
  io.scalar("settings/contact_detection", st.contact_detection);
  io.scalar("settings/energy_check_every", st.energy_check_every);
  io.scalar("settings/skin", st.skin);

  // model definition: materials, groups, boundary conditions, walls
  io.table("materials", m.materials, [](auto&& col) {
    col("density", &Material::density);
    col("kn", &Material::kn);
    col("ks", &Material::ks);
    col("friction", &Material::friction);
    col("tensile_strength", &Material::tensile_strength);
    col("shear_strength", &Material::shear_strength);
    col("friction_strengthens_bonds", &Material::friction_strengthens_bonds);
  });
  // pair law of each material, by name (absent from format 1: solid_lattice)
  std::vector<std::string> law_names;
  for (const Material& mt : m.materials) law_names.push_back(mt.law);
  if (io.has("material_laws/text")) {
    io.strings("material_laws", law_names);
    if constexpr (Io::kLoading) {
      STRATA_CHECK(law_names.size() == m.materials.size(), IO,
                   "state 'dem/material_laws': {} names for {} materials", law_names.size(),
                   m.materials.size());
      for (std::size_t k = 0; k < law_names.size(); ++k) m.materials[k].law = law_names[k];
    }
  }
  io.strings("groups", m.group_names);
  // Formats 1 and 2 kept a bit mask per particle and per boundary spec; group_bits_to_sets()
  // turns them into sets after loading.
  const bool group_bits = !io.has("group_sets/offsets");
  if (!group_bits) {
    std::vector<std::uint32_t> off{0}, members;
    for (const auto& set : m.group_sets) {
      members.insert(members.end(), set.begin(), set.end());
      off.push_back(static_cast<std::uint32_t>(members.size()));
    }
    io.vec("group_sets/offsets", off);
    io.vec("group_sets/members", members);
    if constexpr (Io::kLoading) {
      STRATA_CHECK(!off.empty() && off.front() == 0 && off.back() == members.size() &&
                       std::is_sorted(off.begin(), off.end()),
                   IO, "damaged state: group set offsets");
      m.group_sets.clear();
      for (std::size_t k = 0; k + 1 < off.size(); ++k)
        m.group_sets.emplace_back(members.begin() + off[k], members.begin() + off[k + 1]);
    }
  }
  io.table("boundary_specs", m.bc_specs, [&](auto&& col) {
    col("kind", &BcSpec::kind);
    col(group_bits ? "mask" : "group", &BcSpec::group);
    col("axes", &BcSpec::axes);
    col("value", &BcSpec::value);
    col("every", &BcSpec::every);
    col("history", &BcSpec::history);
  });
  std::int64_t nhist = static_cast<std::int64_t>(m.histories.size());
  io.scalar("force_histories/count", nhist);
  if constexpr (Io::kLoading) {
    STRATA_CHECK(nhist >= 0, IO, "state 'dem/force_histories/count' = {} is negative", nhist);
    m.histories.assign(static_cast<std::size_t>(nhist), ForceHistory{});
  }
  for (std::size_t h = 0; h < m.histories.size(); ++h) {
    ForceHistory& fh = m.histories[h];
    const std::string p = "force_histories/" + std::to_string(h);
    io.vec(p + "/time", fh.t);
    std::vector<double> flat;
    for (const auto& f : fh.f) flat.insert(flat.end(), f.begin(), f.end());
    io.vec(p + "/force", flat);
    if constexpr (Io::kLoading) {
      STRATA_CHECK(flat.size() == 3 * fh.t.size(), IO, "state 'dem/{}': {} forces for {} times", p,
                   flat.size() / 3, fh.t.size());
      fh.f.resize(fh.t.size());
      for (std::size_t k = 0; k < fh.f.size(); ++k)
        for (int a = 0; a < 3; ++a) fh.f[k][a] = flat[3 * k + a];
    }
    if (io.has(p + "/radial")) {  // from format 3
      io.scalar(p + "/radial", fh.radial);
      std::vector<double> centre(fh.centre.begin(), fh.centre.end()), axis(fh.axis.begin(), fh.axis.end());
      io.vec(p + "/centre", centre);
      io.vec(p + "/axis", axis);
      if constexpr (Io::kLoading) {
        STRATA_CHECK(centre.size() == 3 && axis.size() == 3, IO, "damaged state: 'dem/{}' centre or axis", p);
        std::copy(centre.begin(), centre.end(), fh.centre.begin());
        std::copy(axis.begin(), axis.end(), fh.axis.begin());
      }
    }
    if (io.has(p + "/ramp")) {  // from format 4; linear before
      std::int64_t ramp = fh.ramp == Ramp::Smooth ? 1 : 0;
      io.scalar(p + "/ramp", ramp);
      if constexpr (Io::kLoading) {
        STRATA_CHECK(ramp == 0 || ramp == 1, IO, "damaged state: 'dem/{}/ramp' = {}", p, ramp);
        fh.ramp = ramp == 1 ? Ramp::Smooth : Ramp::Linear;
      }
    }
  }
  io.table("walls", m.walls, [](auto&& col) {
    col("point", &Wall::p);  // moves with the wall's velocity every step
    col("normal", &Wall::n);
    col("velocity", &Wall::v);
    col("stiffness", &Wall::k);
  });

  // particles (internal, spatially sorted order; id maps back to insertion order)
  static const char* kAxis[3] = {"x", "y", "z"};
  for (int a = 0; a < s.dim; ++a) {
    io.vec(std::string("particles/position/") + kAxis[a], *s.x[a]);
    io.vec(std::string("particles/velocity/") + kAxis[a], *s.v[a]);
    io.vec(std::string("particles/start_position/") + kAxis[a], *s.x0[a]);
  }
  io.vec("particles/inverse_mass", *s.im);
  io.vec("particles/radius", *s.rad);
  io.vec("particles/id", *s.id);
  io.vec(group_bits ? "particles/group_bits" : "particles/group_set", *s.grp);
  io.vec("particles/material", *s.mat);
  io.vec("particles/flags", *s.flags);

  // bonds and contacts (CSR by owner) with their state and shear displacement Us. The model
  // holds the bonds' Us in 32 bits where it can (BondShear); a checkpoint stores them as
  // doubles, which state_loaded() takes back.
  if constexpr (!Io::kLoading) s.bonds->us = m.bond_shear();
  pair_list(io, "bonds", *s.bonds);
  if constexpr (!Io::kLoading) s.bonds->us = {};
  pair_list(io, "contacts", *s.contacts);

  // per-particle boundary-condition records: trapezoid-rule history of the reaction work
  io.table("boundary_particles", *s.bcp, [](auto&& col) {
    col("index", &BcParticle::index);
    col("mode", &BcParticle::mode);
    col("value", &BcParticle::value);
    col("every", &BcParticle::every);
    col("history", &BcParticle::history);
    col("dx_prev", &BcParticle::dx_prev);
    col("f_int", &BcParticle::f_int);
    col("w_ahead", &BcParticle::w_ahead);
    col("exchange", &BcParticle::exchange);
    col("w_ahead_exchange", &BcParticle::w_ahead_ex);
  });
  // per-block accumulators: work and dissipation are summed per block, in block order
  io.table("blocks", *s.acc, [](auto&& col) {
    col("work", &BlockAcc::work);
    col("exchange_work", &BlockAcc::work_ex);
    col("dissipated", &BlockAcc::dissipated);
    col("kinetic_energy", &BlockAcc::ke);
    col("stored_energy", &BlockAcc::eb);
    col("vmax2", &BlockAcc::vmax2);
  });
  io.table("breaks", *s.events, [](auto&& col) {
    col("step", &BreakEvent::step);
    col("position", &BreakEvent::position);
    col("mode", &BreakEvent::mode);
    col("id_i", &BreakEvent::id_i);
    col("id_j", &BreakEvent::id_j);
  });

  // run state
  io.scalar("run/step", *s.step);
  io.scalar("run/last_good_step", *s.last_good);
  io.scalar("run/time", *s.time);
  io.scalar("run/dt_crit", *s.dt_crit);
  io.scalar("run/lambda_estimate", *s.lam_est);
  io.scalar("run/lambda_bound", *s.lam_bound);
  io.scalar("run/energy_budget0", *s.energy_budget0);
  io.scalar("run/energy_tiny", *s.energy_tiny);
  io.scalar("run/skin", *s.skin);
  io.scalar("run/displacement_bound", *s.disp_bound);  // Verlet-list rebuild counter
  if (io.has("run/settled_steps"))                     // from format 6
    io.scalar("run/settled_steps", *s.settled);
  io.scalar("run/bcs_dirty", *s.bcs_dirty);
  io.scalar("run/energy_valid", *s.energy_valid);
  io.scalar("run/budget_dirty", *s.budget_dirty);
  io.scalar("run/contact_detection_on", *s.contacts_on);
}

// Formats 1 and 2: a particle's entry was a bit mask of its groups and a boundary spec's the
// bit of its group; both become indices (into group sets and group names).
void group_bits_to_sets(ModelBase& m, const StateRefs& s) {
  for (BcSpec& b : m.bc_specs) {
    STRATA_CHECK(b.group != 0 && (b.group & (b.group - 1)) == 0, IO, "damaged state: boundary group mask {}",
                 b.group);
    b.group = static_cast<std::uint32_t>(std::countr_zero(b.group));
  }
  m.group_sets.assign(1, {});
  std::vector<std::pair<std::uint32_t, std::uint32_t>> seen;  // bit mask -> set
  for (std::uint32_t& g : *s.grp) {
    const auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& e) { return e.first == g; });
    if (it != seen.end()) {
      g = it->second;
      continue;
    }
    std::uint32_t set = 0;
    for (std::uint32_t bit = 0; bit < 32; ++bit)
      if (g >> bit & 1u) set = m.set_with(set, bit);
    seen.emplace_back(g, set);
    g = set;
  }
}

// A loaded state must be self-consistent before any step indexes with it.
void check_loaded(const ModelBase& m, const StateRefs& s, std::size_t n) {
  const int kns = s.dim == 2 ? 1 : 3;
  auto same = [&](std::size_t size, const char* what, std::size_t expected) {
    STRATA_CHECK(size == expected, IO, "damaged state: {} has {} entries, expected {}", what, size, expected);
  };
  for (int a = 0; a < s.dim; ++a) {
    same(s.x[a]->size(), "particles/position", n);
    same(s.v[a]->size(), "particles/velocity", n);
    same(s.x0[a]->size(), "particles/start_position", n);
  }
  same(s.im->size(), "particles/inverse_mass", n);
  same(s.rad->size(), "particles/radius", n);
  same(s.grp->size(), "particles/group_set", n);
  for (const auto& set : m.group_sets)
    for (const auto g : set)
      STRATA_CHECK(g < m.group_names.size(), IO, "damaged state: group {} of {}", g, m.group_names.size());
  for (const auto k : *s.grp)
    STRATA_CHECK(k < m.group_sets.size(), IO, "damaged state: group set {} of {}", k, m.group_sets.size());
  for (const BcSpec& b : m.bc_specs)
    STRATA_CHECK(b.group < m.group_names.size(), IO, "damaged state: boundary of group {} of {}", b.group,
                 m.group_names.size());
  same(s.mat->size(), "particles/material", n);
  same(s.flags->size(), "particles/flags", n);
  std::vector<char> seen(n, 0);
  for (const auto k : *s.id) {
    STRATA_CHECK(k < n && !seen[k], IO, "damaged state: particle ids are not a permutation of 0..{}", n - 1);
    seen[k] = 1;
  }
  for (const auto k : *s.mat)
    STRATA_CHECK(k < m.materials.size(), IO, "damaged state: material {} of {}", k, m.materials.size());
  for (const PairList* L : {s.bonds, s.contacts}) {
    same(L->off.size(), "pair offsets", n + 1);
    same(L->st.size(), "pair states", L->j.size());
    if (!L->us.empty()) same(L->us.size(), "pair shear displacements", L->j.size() * kns);
    if (!L->r0.empty() || !L->kf.empty()) {
      same(L->r0.size(), "bond rest lengths", L->j.size());
      same(L->kf.size(), "bond stiffness factors", L->j.size());
      same(L->sf.size(), "bond strength factors", L->j.size());
      for (const double f : L->sf)
        STRATA_CHECK(f > 0 && std::isfinite(f), IO, "damaged state: bond strength factor {}", f);
    }
    STRATA_CHECK(L->off.front() == 0 && L->off.back() == L->j.size(), IO, "damaged state: pair offsets");
    for (std::size_t p = 0; p < n; ++p) {
      STRATA_CHECK(L->off[p] <= L->off[p + 1], IO, "damaged state: pair offsets are not ascending");
      for (std::uint32_t k = L->off[p]; k < L->off[p + 1]; ++k)
        STRATA_CHECK(L->j[k] > p && L->j[k] < n, IO, "damaged state: pair ({}, {})", p, L->j[k]);
    }
  }
  same(s.acc->size(), "blocks", (n + detail::kBlock - 1) / detail::kBlock);
  for (const BcParticle& b : *s.bcp) {
    STRATA_CHECK(b.index < n, IO, "damaged state: boundary record of particle {}", b.index);
    STRATA_CHECK(b.history < static_cast<int>(m.histories.size()), IO, "damaged state: force history {}",
                 b.history);
  }
  for (const BcSpec& b : m.bc_specs)
    STRATA_CHECK(b.history < static_cast<int>(m.histories.size()), IO, "damaged state: force history {}",
                 b.history);
}

}  // namespace

namespace detail {
namespace {
std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}
}  // namespace

template <int D>
std::uint64_t Model<D>::state_hash() const {
  bonds_current();
  std::uint64_t h = 1469598103934665603ull;
  for (int a = 0; a < D; ++a) {
    h = fnv(h, x[a].data(), x[a].size() * sizeof(double));
    h = fnv(h, v[a].data(), v[a].size() * sizeof(double));
  }
  for (const auto* L : {&bonds, &contacts}) {
    h = fnv(h, L->j.data(), L->j.size() * 4);
    h = fnv(h, L->st.data(), L->st.size());
    if (L == &contacts) {
      h = fnv(h, L->us.data(), L->us.size() * sizeof(double));
    } else if (!bond_us.empty()) {  // the values, not where they are held
      for (std::size_t k = 0; k < bonds.size(); ++k) {
        double u[kNs];
        bond_us.load(k, u);
        h = fnv(h, u, sizeof u);
      }
    }
  }
  return h;
}

template <int D>
StateRefs Model<D>::state_refs() {
  slots_release();  // a checkpoint reads or replaces the bonds' own arrays
  StateRefs r;
  r.dim = D;
  for (int a = 0; a < D; ++a) {
    r.x[a] = &x[a];
    r.v[a] = &v[a];
    r.x0[a] = &x0[a];
  }
  r.im = &im;
  r.rad = &rad;
  r.id = &id;
  r.grp = &grp;
  r.mat = &mat;
  r.flags = &flags;
  r.bonds = &bonds;
  r.contacts = &contacts;
  r.bcp = &bcp;
  r.acc = &acc;
  r.events = &events;
  r.step = &step_;
  r.last_good = &last_good;
  r.time = &time_;
  r.dt_crit = &dt_crit;
  r.lam_est = &lam_est;
  r.lam_bound = &lam_bound;
  r.energy_budget0 = &energy_budget0;
  r.energy_tiny = &energy_tiny;
  r.skin = &skin;
  r.disp_bound = &disp_bound;
  r.settled = &settled;
  r.initialised = &initialised;
  r.bcs_dirty = &bcs_dirty;
  r.energy_valid = &energy_valid;
  r.budget_dirty = &budget_dirty;
  r.contacts_on = &contacts_on;
  return r;
}

// After a load: the particles are in their saved (sorted) order; rebuild what derives
// from the state. The thread plan is a function of the pair lists and the thread count
// only, so rebuilding it does not change the floating-point path.
template <int D>
void Model<D>::state_loaded() {
  refresh_laws();
  STRATA_CHECK(!keeps_shear() ||
                   (bonds.us.size() == bonds.size() * kNs && contacts.us.size() == contacts.size() * kNs),
               IO,
               "damaged state: pairs without shear displacements, but the pair law has a shear stiffness");
  if (keeps_shear())
    bond_us.take(bonds.us, bonds.st, shear_unit());
  else
    bond_us.clear();
  bonds.us = {};
  set_load_directions();  // derived from the start positions
  inv_cache.clear();
  sorted = true;
  plan_dirty = true;
  for (auto& b : evbuf) b.clear();
}

template std::uint64_t Model<2>::state_hash() const;
template std::uint64_t Model<3>::state_hash() const;
template StateRefs Model<2>::state_refs();
template StateRefs Model<3>::state_refs();
template void Model<2>::state_loaded();
template void Model<3>::state_loaded();

}  // namespace detail

void Simulation::save_state(StateWriter& out) const {
  const StateRefs s = m_->state_refs();
  STRATA_CHECK(*s.initialised, Input, "save_state: call initialise() first");
  out.put_scalar<std::int64_t>("dem/format", kFormat);
  out.put_scalar<std::int64_t>("dem/dimension", s.dim);
  out.put_scalar<std::int64_t>("dem/particles/count", static_cast<std::int64_t>(m_->particle_count()));
  Saver saver{out};  // describe() takes references for both directions; the Saver only reads
  describe(saver, *m_, s);
}

void Simulation::load_state(const StateReader& in) {
  STRATA_CHECK(in.has("dem/format"), IO, "the state holds no DEM model (no 'dem/format')");
  const auto format = in.get_scalar<std::int64_t>("dem/format");
  STRATA_CHECK(format >= kOldestFormat && format <= kFormat, Input,
               "the state has DEM format {}; this strata reads formats {} to {}", format, kOldestFormat,
               kFormat);
  const auto dim = in.get_scalar<std::int64_t>("dem/dimension");
  STRATA_CHECK(dim == m_->dim(), Input, "the state is of a {}D model, this model is {}D", dim, m_->dim());
  const auto count = in.get_scalar<std::int64_t>("dem/particles/count");
  const std::size_t have = m_->particle_count();
  STRATA_CHECK(have == 0 || static_cast<std::int64_t>(have) == count, Input,
               "the state holds {} particles, this model {}", count, have);
  STRATA_CHECK(count >= 0, IO, "damaged state: {} particles", count);

  // Load into a fresh model of the same dimension, so a failure leaves this one untouched.
  std::unique_ptr<detail::ModelBase> fresh =
      m_->dim() == 2 ? detail::make_model<2>(m_->settings) : detail::make_model<3>(m_->settings);
  const StateRefs s = fresh->state_refs();
  Loader loader{in};
  describe(loader, *fresh, s);
  if (!in.has("dem/group_sets/offsets")) group_bits_to_sets(*fresh, s);
  check_loaded(*fresh, s, static_cast<std::size_t>(count));
  *s.initialised = true;
  fresh->state_loaded();
  m_ = std::move(fresh);
}

}  // namespace strata::dem
