#pragma once
// Not API: the registry row of a law (law_engine.hpp), with the step kernel compiled for it
// and the two paths of the conformance test: the reference kernel as the step's scalar
// path calls it (Engine::pair_force) and the bond pass's chunk function (bond_chunks).
#include <strata/dem/detail/step_kernel.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace strata::dem::detail {

/// The cases' shear histories held as a model holds its bonds' (BondShear), in steps set
/// by the law's reach (1 mm where it has none), so that both paths read and store them alike.
template <int D, class Law>
BondShear<kNsOf<D>> case_shear(const Law& law, const BondCases& cs) {
  constexpr int kNs = kNsOf<D>;
  const double reach = shear_reach_of(law);
  std::vector<double> u(cs.size() * kNs);
  for (std::size_t i = 0; i < cs.size(); ++i)
    for (int a = 0; a < kNs; ++a) u[i * kNs + a] = cs.us[i][a];
  BondShear<kNs> h;
  h.take(u, cs.st, BondShear<kNs>::unit_for(reach > 0 ? reach : 1e-3));
  h.fresh.resize(1);
  return h;
}

/// The cases through the reference kernel, each as a pair (0, 1) of its own two particles.
template <int D, class Law>
BondResults reference_cases(const BondCases& cs) {
  constexpr int kNs = kNsOf<D>;
  const Law law = Law::from_material(cs.material);
  BondShear<kNs> hist = case_shear<D>(law, cs);
  BondResults r;
  const std::size_t n = cs.size();
  r.force.assign(n, {0, 0, 0});
  r.us.assign(n, {0, 0, 0});
  r.us_before.assign(n, {0, 0, 0});
  r.widened.assign(n, 0);
  r.st.assign(n, 0);
  r.energy.assign(n, 0);
  r.verdict.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    double xs[D][2], vs[D][2];
    const double* X[D];
    const double* V[D];
    for (int a = 0; a < D; ++a) {
      xs[a][0] = cs.xp[i][a];
      xs[a][1] = cs.xj[i][a];
      vs[a][0] = cs.vp[i][a];
      vs[a][1] = cs.vj[i][a];
      X[a] = xs[a];
      V[a] = vs[a];
    }
    std::uint8_t st = cs.st[i];
    double us[kNs];
    hist.load(i, us);
    for (int a = 0; a < kNs; ++a) r.us_before[i][a] = us[a];
    // the step's law_for: an intact bond of an eccentric lattice has its stiffness scaled
    const bool scaled = cs.rest == 2 && (st & pair_state::kKindMask) == pair_state::kIntact;
    const double rest = cs.rest == 2 ? cs.r0[i] : cs.rp[i] + cs.rj[i];
    double F[D];
    int broke = 0;
    const double e = Engine<D, Law>::template pair_force<true>(
        X, V, rest, 0, 1, st, us, scaled ? bond_law(law, cs.kf[i], cs.sf[i]) : law, cs.dt, F, broke);
    for (int a = 0; a < D; ++a) r.force[i][a] = F[a];
    const bool was_wide = BondShear<kNs>::is_wide(hist.q[i * kNs]);
    hist.store(0, i, BondShear<kNs>::salt_of(cs.step), (st & pair_state::kKindMask) == pair_state::kIntact,
               us);
    r.widened[i] = !was_wide && !hist.fresh[0].empty();
    hist.merge();
    hist.load(i, us);
    for (int a = 0; a < kNs; ++a) r.us[i][a] = us[a];
    r.st[i] = st;
    r.energy[i] = e;
    r.verdict[i] = static_cast<std::uint8_t>(broke);
  }
  return r;
}

template <int D, class Law, bool kEnergy>
void run_chunks(int rest, const BondSpan& sp, const Law& law, double dt, double d_uniform, std::size_t mq) {
  if (rest == 2)
    bond_chunks<D, Law, kEnergy, kPerBond>(sp, law, dt, d_uniform, mq);
  else if (rest == 1)
    bond_chunks<D, Law, kEnergy, kUniform>(sp, law, dt, d_uniform, mq);
  else
    bond_chunks<D, Law, kEnergy, kRadiusSum>(sp, law, dt, d_uniform, mq);
}

/// The cases through the bond pass: owners 0..n-1, partners n..2n-1, in chunks as the bond
/// pass runs a block's bonds (every partner within the thread's range).
template <int D, class Law>
BondResults batch_cases(const BondCases& cs) {
  constexpr int kNs = kNsOf<D>;
  const Law law = Law::from_material(cs.material);
  const std::size_t n = cs.size();
  std::array<std::vector<double>, 3> X, V, F;
  for (int a = 0; a < 3; ++a) {
    X[a].assign(2 * n, 0.0);
    V[a].assign(2 * n, 0.0);
    F[a].assign(n, 0.0);
  }
  std::vector<double> R(2 * n), r0(cs.r0), kf(cs.kf), sf(cs.sf), en(n, 0.0);
  BondShear<kNs> hist = case_shear<D>(law, cs);
  const std::vector<double> before = hist.expanded();
  double no_wide[kNs] = {};
  std::vector<std::uint32_t> j(n);
  std::vector<std::uint8_t> own(n), st(cs.st), slow(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) {
      X[a][i] = cs.xp[i][a];
      X[a][n + i] = cs.xj[i][a];
      V[a][i] = cs.vp[i][a];
      V[a][n + i] = cs.vj[i][a];
    }
    R[i] = cs.rp[i];
    R[n + i] = cs.rj[i];
    j[i] = static_cast<std::uint32_t>(n + i);
    own[i] = static_cast<std::uint8_t>(i % kChunk);
  }
  for (std::size_t c0 = 0; c0 < n; c0 += kChunk) {
    const std::size_t mq = std::min(kChunk, n - c0);
    const BondSpan sp{X[0].data(),
                      X[1].data(),
                      X[D - 1].data(),
                      V[0].data(),
                      V[1].data(),
                      V[D - 1].data(),
                      R.data(),
                      cs.rest == 2 ? r0.data() + c0 : nullptr,
                      cs.rest == 2 ? kf.data() + c0 : nullptr,
                      cs.rest == 2 ? sf.data() + c0 : nullptr,
                      F[0].data() + c0,
                      F[1].data() + c0,
                      F[D - 1].data() + c0,
                      en.data() + c0,
                      hist.q.data() + c0 * kNs,
                      hist.wide.empty() ? no_wide : hist.wide.data(),
                      cs.shear_kept ? hist.unit : 0.0,
                      cs.shear_kept ? hist.inv : 0.0,
                      cs.shear_kept,
                      cs.shear_kept && hist.intact_wide,
                      static_cast<std::uint32_t>(c0),
                      BondShear<kNs>::salt_of(cs.step),
                      own.data() + c0,
                      j.data() + c0,
                      st.data() + c0,
                      slow.data() + c0,
                      static_cast<std::uint32_t>(c0),
                      static_cast<std::uint32_t>(2 * n)};
    const double d_uniform = n > 0 ? 2 * cs.rp[0] : 0.0;
    if (cs.energy)
      run_chunks<D, Law, true>(cs.rest, sp, law, cs.dt, d_uniform, mq);
    else
      run_chunks<D, Law, false>(cs.rest, sp, law, cs.dt, d_uniform, mq);
  }
  BondResults r;
  r.force.assign(n, {0, 0, 0});
  r.us.assign(n, {0, 0, 0});
  r.us_before.assign(n, {0, 0, 0});
  r.st = st;
  r.energy = en;
  r.verdict = slow;
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) r.force[i][a] = F[a][i];
    double us[kNs];
    hist.load(i, us);
    for (int a = 0; a < kNs; ++a) {
      r.us[i][a] = us[a];
      r.us_before[i][a] = before[i * kNs + a];
    }
  }
  return r;
}

/// Dimension 2 or 3 of the conformance paths.
template <class Law>
BondResults reference_any(int dim, const BondCases& cs) {
  return dim == 2 ? reference_cases<2, Law>(cs) : reference_cases<3, Law>(cs);
}
template <class Law>
BondResults batch_any(int dim, const BondCases& cs) {
  if constexpr (HasLane<Law, 1> && HasLane<Law, 3>) {
    return dim == 2 ? batch_cases<2, Law>(cs) : batch_cases<3, Law>(cs);
  } else {
    return reference_any<Law>(dim, cs);  // no batch form: the bond pass runs `apply` for every bond
  }
}

/// The registry row of Law, with the step kernel compiled for it in this translation unit.
template <class Law>
LawEntry make_law_entry() {
  LawEntry e;
  e.name = Law::kName;
  e.description = Law::kDescription;
  e.make2 = []() -> std::unique_ptr<LawEngine<2>> { return std::make_unique<Engine<2, Law>>(); };
  e.make3 = []() -> std::unique_ptr<LawEngine<3>> { return std::make_unique<Engine<3, Law>>(); };
  e.reference = &reference_any<Law>;
  e.batch = &batch_any<Law>;
  e.has_batch = HasLane<Law, 1> && HasLane<Law, 3>;
  return e;
}

}  // namespace strata::dem::detail
