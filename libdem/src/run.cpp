// Set-up and run loop of the DEM: the choice of the pair law (by the materials' law name,
// through the registry), initialise(), the time-step check, the loop over steps with the
// Verlet-list rebuilds and the blow-up check, and the merge of break events.
#include "model.hpp"

#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/numbers.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace strata::dem::detail {

Material pair_material(const Material& a, const Material& b) {
  if (&a == &b) return a;
  auto hm = [](double p, double q) { return p + q > 0 ? 2 * p * q / (p + q) : 0.0; };
  Material m = a;
  m.kn = hm(a.kn, b.kn);
  m.ks = hm(a.ks, b.ks);
  m.friction = std::min(a.friction, b.friction);
  m.tensile_strength = std::min(a.tensile_strength, b.tensile_strength);
  m.shear_strength = std::min(a.shear_strength, b.shear_strength);
  m.friction_strengthens_bonds = a.friction_strengthens_bonds && b.friction_strengthens_bonds;
  return m;
}

// The pair law: the registry's engine for the materials' law name, and its nmat × nmat
// table of pair laws and stiffnesses.
template <int D>
void Model<D>::refresh_laws() {
  nmat = static_cast<int>(materials.size());
  stiff.clear();
  if (nmat == 0) return;
  const std::string& name = materials[0].law;
  for (const Material& m : materials)
    STRATA_CHECK(m.law == name, Input,
                 "the materials name the pair laws '{}' and '{}': all materials of a model must use one law",
                 name, m.law);
  if (!engine || name != engine->name()) {
    const LawEntry* e = find_law(name);
    if (!e) {
      std::string known;
      for (const LawEntry* k : all_laws()) known += (known.empty() ? "" : ", ") + k->name;
      fail(ErrorKind::Input, "no pair law named '{}' (known: {})", name, known);
    }
    if constexpr (D == 2)
      engine = e->make2();
    else
      engine = e->make3();
  }
  std::vector<Material> pm;
  for (int a = 0; a < nmat; ++a)
    for (int b = 0; b < nmat; ++b) pm.push_back(pair_material(materials[a], materials[b]));
  engine->set_materials(pm, nmat);
  for (int a = 0; a < nmat; ++a)
    for (int b = 0; b < nmat; ++b) stiff.push_back(engine->stiffness(a, b));
}

template <int D>
bool Model<D>::keeps_shear() {
  if (nmat != static_cast<int>(materials.size())) refresh_laws();
  return stiff.empty() ||
         std::any_of(stiff.begin(), stiff.end(), [](const PairStiffness& k) { return k.ks != 0; });
}

template <int D>
double Model<D>::shear_unit() const {
  double reach = engine->shear_reach();
  // no law bounds an intact bond's shear (unbreakable bonds): a hundredth of the largest
  // diameter, a shear strain of 1 %; bonds sheared further are kept wide
  if (!(reach > 0)) reach = 0.02 * rad.max();
  if (!(reach > 0)) reach = 1;
  return BondShear<kNs>::unit_for(reach);
}

template <int D>
void Model<D>::fit_shear_history() {
  slots_release();
  const bool keep = keeps_shear();
  if (!keep) {
    contacts.us.clear();
    contacts.us.shrink_to_fit();
    bond_us.clear();
  } else {
    if (contacts.us.size() != contacts.size() * kNs) contacts.us.assign(contacts.size() * kNs, 0.0);
    const double unit = shear_unit();
    if (bond_us.q.size() != bonds.size() * kNs)
      bond_us.reset(bonds.size(), unit);
    else if (bond_us.unit != unit)  // the laws changed: the same histories in the new steps
      bond_us.take(bond_us.expanded(), bonds.st, unit);
  }
  bonds.us = {};
}

template <int D>
void Model<D>::initialise() {
  STRATA_CHECK(n() > 0, Input, "initialise: the model has no particles");
  STRATA_CHECK(!materials.empty(), Input, "initialise: no material");
  STRATA_CHECK(settings.dt > 0 && std::isfinite(settings.dt), Input, "dt = {} must be > 0 (s)", settings.dt);
  STRATA_CHECK(settings.local_alpha >= 0 && settings.local_alpha < 1, Input,
               "local_alpha = {} must be in [0, 1)", settings.local_alpha);
  STRATA_CHECK(settings.viscous_c >= 0, Input, "viscous_c = {} must be >= 0 (N·s/m)", settings.viscous_c);
  log::Phases ph("DEM set-up");
  if (!sorted) {
    sort_particles();
    ph.lap("spatial order");
  }
  refresh_laws();
  fit_shear_history();
  resolve_bcs();
  acc.assign(static_cast<std::size_t>((n() + kBlock - 1) / kBlock), BlockAcc{});
  const double rmax = rad.max();
  skin = start_skin();
  contacts_on = settings.contact_detection;
  ph.lap("laws and boundary conditions");
  if (contacts_on) {
    if (found_contacts.off.size() == n() + 1 && found_contacts_skin == skin) {
      take_contacts(std::move(found_contacts));  // found with the bonds
    } else {
      rebuild_contacts();
    }
    ph.lap("contact list");
  }
  found_contacts = PairList{};
  compute_critical_dt();
  ph.lap("critical time step");
  check_dt();
  keep_start_positions();  // allocated after the time-step estimate's temporaries
  // energy budget of the blow-up check: initial kinetic + stored energy
  energy_budget0 = dry_kinetic() + dry_bond_energy();
  energy_tiny = static_cast<double>(n()) * 0.5 * max_stiffness() * std::pow(1e-6 * 2 * rmax, 2);
  ph.lap("energy budget");
  build_plan(par::threads());
  ph.lap("thread plan");
  initialised = true;
  last_good = step_;
}

// x0 = x, one axis per thread: on a large model the copies' first touch of fresh memory is
// most of the time, and runs in parallel
template <int D>
void Model<D>::keep_start_positions() {
  par::parallel_team(small_model() ? 1 : std::min(par::threads(), D), [&](int t, int team) {
    for (int a = t; a < D; a += team) x0[a] = x[a];
  });
}

template <int D>
void Model<D>::check_dt() {
  if (!initialised && dt_crit == 0) return;  // checked by initialise()
  if (settings.dt > dt_crit) {
    const auto [dt_text, crit_text] = distinct_pair(settings.dt, dt_crit);
    const std::string ratio = ratio_text(settings.dt, dt_crit);
    if (!settings.allow_unstable)
      fail(ErrorKind::Numerical,
           "dt = {} s exceeds the critical time step {} s (ratio {}); lower dt or set allow_unstable",
           dt_text, crit_text, ratio);
    log::warn("dt = {} s exceeds the critical time step {} s (ratio {}): the run may blow up", dt_text,
              crit_text, ratio);
  }
}

// The step's context that does not change from step to step.
template <int D>
StepCtx Model<D>::step_context() const {
  StepCtx c;
  c.dt = settings.dt;
  c.t = 0;
  for (int a = 0; a < 3; ++a) c.g[a] = settings.gravity[a];
  c.step = 0;
  c.salt = 0;
  c.hist.resize(histories.size());
  c.damping = settings.damping;
  c.viscous_c = settings.viscous_c;
  c.local_alpha = settings.local_alpha;
  c.walls = walls.data();
  c.nwalls = walls.size();
  c.slots = settings.lattice_slots;
  return c;
}

template <int D>
void Model<D>::run(std::int64_t steps, bool energies_at_end) {
  STRATA_CHECK(initialised, Input, "run: call initialise() first");
  STRATA_CHECK(steps >= 0, Input, "run: steps = {} must be >= 0", steps);
  if (steps == 0) return;
  if (bcs_dirty) resolve_bcs();
  if (budget_dirty) {  // initial conditions changed: the energy budget grows with them
    energy_budget0 = std::max(energy_budget0, dry_kinetic() + dry_bond_energy());
    budget_dirty = false;
    v2_alarm = -1;
  }
  const int nt = par::threads();
  if (plan_dirty || plan.nt != effective_threads(nt)) build_plan(nt);
  StepCtx c = step_context();
  const int check = settings.energy_check_every;
  for (std::int64_t s = 0; s < steps; ++s) {
    c.step = step_;
    c.salt = BondShear<kNs>::salt_of(settled + step_);
    c.t = time_;
    for (std::size_t h = 0; h < histories.size(); ++h) c.hist[h] = histories[h].at(time_);
    const bool check_now = check > 0 && (step_ + 1) % check == 0;
    const bool energy = (energies_at_end && s == steps - 1) || check_now;
    engine->step(*this, c, energy);
    double vmax2 = 0, vfree2 = 0;
    for (const BlockAcc& A : acc) {
      vmax2 = std::max(vmax2, A.vmax2);
      vfree2 = std::max(vfree2, A.vfree2);
    }
    for (Wall& w : walls)
      for (int a = 0; a < 3; ++a) w.p[a] += w.v[a] * c.dt;
    ++step_;
    time_ += c.dt;
    energy_valid = energy;
    if (contacts_on) {
      disp_bound += std::sqrt(vmax2) * c.dt;
      if (!(disp_bound < 0.5 * skin)) {  // Verlet-skin rule (also catches NaN)
        if (!std::isfinite(disp_bound)) check_blowup(true);
        rebuild_contacts();
        build_plan(nt);
      }
    }
    if (check_now) {
      check_blowup(false);
    } else if (vfree2 > v2_alarm) {  // checked every step: catches a blow-up whatever the damping
      if (v2_alarm < 0)
        update_alarm();
      else
        check_blowup_now();
    }
  }
  merge_events();
}

template <int D>
void Model<D>::settle(std::int64_t steps) {
  STRATA_CHECK(initialised, Input, "settle: call initialise() first");
  STRATA_CHECK(step_ == 0, Input,
               "settle: the model has run {} steps; a settling stage comes before the first step", step_);
  STRATA_CHECK(steps >= 0, Input, "settle: steps = {} must be >= 0", steps);
  if (steps == 0) return;
  if (bcs_dirty) resolve_bcs();
  for (const BcParticle& b : bcp)
    STRATA_CHECK(b.exchange == 0, Input, "settle: particles driven by a coupled partition cannot settle");
  // Prescribed motions and loads wait: a prescribed axis is held where it is, no load acts,
  // walls stand.
  const std::vector<BcParticle> waiting = bcp;
  for (BcParticle& b : bcp) {
    b.history = -1;
    for (int a = 0; a < D; ++a)
      if (b.mode[a] != 0) {
        b.mode[a] = 1;
        b.value[a] = 0;
      }
  }
  std::vector<std::array<double, 3>> wall_v;
  for (Wall& w : walls) {
    wall_v.push_back({w.v[0], w.v[1], w.v[2]});
    std::fill(w.v, w.v + 3, 0.0);
  }
  run(steps, true);
  // The settled state is the start of the run.
  for (std::size_t k = 0; k < walls.size(); ++k) std::copy(wall_v[k].begin(), wall_v[k].end(), walls[k].v);
  for (std::size_t k = 0; k < bcp.size(); ++k) {
    BcParticle& b = bcp[k];
    const BcParticle& w = waiting[k];  // the same particle: nothing resolved the records anew
    b.history = w.history;
    std::copy(w.mode, w.mode + 3, b.mode);
    std::copy(w.value, w.value + 3, b.value);
    std::fill(b.dx_prev, b.dx_prev + 3, 0.0);  // held while settling: no motion to carry on
    b.w_ahead = b.w_ahead_ex = b.ke_driven = 0;
  }
  keep_start_positions();
  set_load_directions();  // radial loads point away from their centre as seen from x0
  for (BlockAcc& A : acc) A.work = A.work_ex = A.dissipated = 0;
  for (BreakEvent& e : events) e.step -= step_;
  settled += step_;
  step_ = 0;
  time_ = 0;
  last_good = 0;
  energy_budget0 = dry_kinetic() + dry_bond_energy();
  v2_alarm = -1;
}

template <int D>
void Model<D>::check_blowup(bool nan_seen) {
  double ke = 0, eb = 0;
  for (const BlockAcc& A : acc) {
    ke += A.ke;
    eb += A.eb;
  }
  check_energies(ke, eb, nan_seen, energy_valid);
}

template <int D>
void Model<D>::check_blowup_now() {
  check_energies(dry_kinetic(), dry_bond_energy(), false, false);
}

// The energy of a healthy run stays below 10 × (initial + |work done on it|) (+ a floor for
// a model at rest). With the kinetic energy of the step ½Σm·v(n-½)·v(n+½) (`product_ke`),
// kinetic plus stored energy is the leapfrog's conserved quadratic form, positive for every
// state exactly when dt is below the critical step: a clearly negative sum means the fastest
// mode is growing.
template <int D>
void Model<D>::check_energies(double ke, double eb, bool nan_seen, bool product_ke) {
  // Prescribed motion brings its own kinetic energy, which no work pays for: left out, in
  // the form `ke` has. (The product form of a platen that moves by a step every n > 1 steps
  // is zero, while ½m·v(n+½)² is not: taking that would make the sum negative at each step.)
  double driven = 0;
  for (const BcParticle& b : bcp) {
    if (product_ke) {
      driven += b.ke_driven;
      continue;
    }
    for (int a = 0; a < D; ++a)
      if (b.mode[a] != 0) driven += 0.5 * v[a][b.index] * v[a][b.index] / im[b.index];
  }
  ke -= driven;
  const double w = std::abs(external_work());
  const double budget = 10 * (energy_budget0 + w) + energy_tiny;
  const bool exploded = nan_seen || !std::isfinite(ke) || !std::isfinite(eb) || ke > budget;
  const bool indefinite = product_ke && ke + eb < -0.01 * (std::abs(ke) + eb) - energy_tiny;
  if (exploded || indefinite) {
    merge_events();
    fail(ErrorKind::Numerical,
         "blow-up at step {}, t={:.6g} s: kinetic energy {:.4g} J, stored energy {:.4g} J, work input "
         "{:.4g} J{} (dt = {:.4g} s, critical dt = {:.4g} s); last good step {}",
         step_, time_, ke, eb, w,
         indefinite && !exploded ? " (kinetic + stored energy negative: the fastest mode grows)" : "",
         settings.dt, dt_crit, last_good);
  }
  last_good = step_;
  update_alarm();
}

template <int D>
void Model<D>::update_alarm() {
  // A partition of a coupled model also takes energy through the jumps of its driven
  // particles' positions at each exchange, which no work records: the speed test between
  // checks would see it as a blow-up. The coupled model checks its whole energy instead.
  for (const BcParticle& b : bcp)
    if (b.exchange) {
      v2_alarm = std::numeric_limits<double>::infinity();
      return;
    }
  const double budget = 10 * (energy_budget0 + std::abs(external_work())) + energy_tiny;
  const double imax = im.max();
  v2_alarm = 2 * budget * imax;  // ½·|v|²/im_p > budget for any particle p
}

template <int D>
void Model<D>::merge_events() {
  std::vector<BreakEvent> fresh;
  for (auto& buf : evbuf) {
    for (const RawEvent& r : buf)
      fresh.push_back(
          {r.step, {r.pos[0], r.pos[1], r.pos[2]}, static_cast<BreakMode>(r.mode), id[r.i], id[r.j]});
    buf.clear();
  }
  std::sort(fresh.begin(), fresh.end(), [](const BreakEvent& a, const BreakEvent& b) {
    if (a.step != b.step) return a.step < b.step;
    if (a.id_i != b.id_i) return a.id_i < b.id_i;
    return a.id_j < b.id_j;
  });
  events.insert(events.end(), fresh.begin(), fresh.end());
}

#define STRATA_DEM_INSTANTIATE(D)                  \
  template void Model<D>::refresh_laws();          \
  template bool Model<D>::keeps_shear();           \
  template void Model<D>::fit_shear_history();     \
  template double Model<D>::shear_unit() const;    \
  template void Model<D>::initialise();            \
  template void Model<D>::check_dt();              \
  template void Model<D>::keep_start_positions();  \
  template StepCtx Model<D>::step_context() const; \
  template void Model<D>::run(std::int64_t, bool); \
  template void Model<D>::settle(std::int64_t);    \
  template void Model<D>::check_blowup(bool);      \
  template void Model<D>::merge_events();
STRATA_DEM_INSTANTIATE(2)
STRATA_DEM_INSTANTIATE(3)
#undef STRATA_DEM_INSTANTIATE

}  // namespace strata::dem::detail
