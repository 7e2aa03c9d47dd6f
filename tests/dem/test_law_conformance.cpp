// Conformance of every pair law in the registry: random bond states through the reference
// kernel (`apply`, as the step's scalar path calls it) and through the bond pass's
// vectorised chunk function (the law's batch form `lane`), compared bit for bit.
//
// Bit-exact, not within a tolerance: the bond pass promises that a bond gives the same
// bits on either path (docs/dem.md, "Memory layout and the step loop"), which is what
// keeps a run independent of which bonds a chunk holds and of the thread count. Both paths
// use the same expressions in the same order, and libdem is compiled without FMA
// contraction; this file is compiled with libdem's floating-point flags as well (see
// tests/dem/CMakeLists.txt), for the law it registers itself.
#include "dem_test_util.hpp"

#include <strata/core/state_io.hpp>
#include <strata/dem/register_law.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

using namespace strata;
using namespace strata::dem;
namespace ps = strata::dem::pair_state;

namespace {

// A law registered from outside libdem, as a program would: linear springs that never
// break; broken bonds and contacts push only while touching.
struct LinearSpringLaw {
  static constexpr const char* kName = "test_linear_spring";
  static constexpr const char* kDescription = "test: linear springs, no breakage";
  double kn = 0, ks = 0;
  static LinearSpringLaw from_material(const Material& m) { return {m.kn, m.ks}; }
  LinearSpringLaw scaled(double f) const { return {kn * f, ks * f}; }
  PairStiffness stiffness() const { return {kn, ks}; }
  template <int NS>
  PairOutcome<NS> apply(std::uint8_t& st, double un, double* us, const double* /*dus*/) const {
    PairOutcome<NS> o;
    if ((st & ps::kKindMask) != ps::kIntact && un <= 0) {
      for (int a = 0; a < NS; ++a) us[a] = 0;
      st = static_cast<std::uint8_t>((st & ~ps::kTouching) | ps::kSeparated);
      return o;
    }
    if ((st & ps::kKindMask) != ps::kIntact) st |= ps::kTouching;
    o.fn = kn * un;
    for (int a = 0; a < NS; ++a) o.fs[a] = ks * us[a];
    return o;
  }
  template <int NS>
  double energy(std::uint8_t st, double un, const double* us) const {
    if ((st & ps::kKindMask) != ps::kIntact && un <= 0) return 0.0;
    double u2 = 0;
    for (int a = 0; a < NS; ++a) u2 += us[a] * us[a];
    return 0.5 * kn * un * un + 0.5 * ks * u2;
  }
  template <int NS, bool kBroken, bool kEnergy>
  BondLaneResult<NS> lane(const BondLane<NS>& b) const {
    const bool intact = !kBroken || b.st == ps::kIntact;
    const bool on = intact | (b.un > 0);
    const double kni = intact ? kn * b.kf : kn, ksi = intact ? ks * b.kf : ks;
    BondLaneResult<NS> o;
    double u2 = 0;
    for (int a = 0; a < NS; ++a) {
      o.us[a] = on ? b.us[a] : 0.0;
      u2 += o.us[a] * o.us[a];
    }
    o.fn = on ? kni * b.un : 0.0;
    for (int a = 0; a < NS; ++a) o.fs[a] = ksi * o.us[a];
    o.st = intact ? b.st
                  : (on ? (b.st | ps::kTouching) : ((b.st & ~std::int64_t{ps::kTouching}) | ps::kSeparated));
    if constexpr (kEnergy) o.energy = on ? 0.5 * kni * b.un * b.un + 0.5 * ksi * u2 : 0.0;
    return o;
  }
};
const bool kRegistered = (register_law<LinearSpringLaw>(), true);

// splitmix64: a fixed, portable stream of random numbers.
struct Rng {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform(double lo = 0, double hi = 1) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53;
  }
  int pick(int n) { return static_cast<int>(next() % static_cast<std::uint64_t>(n)); }
  bool coin() { return next() & 1; }
  // A factor 1 ± 10^-u, u in [1, 15]: close to a threshold on either side.
  double near_one() { return 1 + (coin() ? 1 : -1) * std::pow(10.0, -uniform(1, 15)); }
};

// A ratio to a limit: well inside, near it (either side) or beyond it.
double ratio(Rng& r) {
  switch (r.pick(4)) {
    case 0:
      return r.uniform(0, 0.9);
    case 1:
    case 2:
      return r.near_one();
    default:
      return r.uniform(1.1, 3);
  }
}

// Random unit vector (in the plane for 2D).
std::array<double, 3> direction(Rng& r, int dim) {
  for (;;) {
    std::array<double, 3> n{r.uniform(-1, 1), r.uniform(-1, 1), dim == 3 ? r.uniform(-1, 1) : 0.0};
    const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (l > 0.1 && l <= 1) return {n[0] / l, n[1] / l, n[2] / l};
  }
}

// Materials: the rock of the uniaxial test in both shear criteria, a weak frictional one,
// one without strength limits and one without friction.
std::vector<Material> materials() {
  std::vector<Material> out;
  Material m = test::rock_material();
  out.push_back(m);
  m.friction_strengthens_bonds = false;
  out.push_back(m);
  m.friction = 0.9;
  m.tensile_strength = 1e3;
  m.shear_strength = 5e2;
  m.ks = 0.1 * m.kn;
  out.push_back(m);
  out.push_back(test::rock_material(false));
  m = test::rock_material();
  m.friction = 0;
  out.push_back(m);
  return out;
}

// Coverage counters (the reference path's view of each case).
struct Coverage {
  long held = 0, broke_tension = 0, broke_shear = 0, touching = 0, slipping = 0, open = 0, reclosed = 0;
  long deferred = 0;  // broken bonds found open that touch now, left to the reference kernel
};

// n random bond states of the given material, dimension and rest-length mode.
dem::detail::BondCases make_cases(Rng& r, const Material& m, int dim, int rest, bool energy, std::size_t n) {
  dem::detail::BondCases cs;
  cs.material = m;
  cs.rest = rest;
  cs.energy = energy;
  cs.dt = 1e-8 * r.uniform(0.5, 2);
  cs.step = static_cast<std::int64_t>(r.pick(1000000));
  const double d = 1e-3;
  const double fn_max0 = std::isfinite(m.tensile_strength) ? m.tensile_strength : 1e4;
  const double fs00 = std::isfinite(m.shear_strength) ? m.shear_strength : 3e4;
  for (std::size_t i = 0; i < n; ++i) {
    const double rp = rest == 1 ? 0.5 * d : r.uniform(0.4, 0.6) * d;
    const double rj = rest == 1 ? 0.5 * d : r.uniform(0.4, 0.6) * d;
    const double r0 = r.uniform(0.8, 1.2) * d, kf = r.coin() ? 1.0 : r.uniform(0.3, 1.0);
    const double sf = r.coin() ? 1.0 : r.uniform(0.5, 1.5);  // a spread of bond strengths
    const double l0 = rest == 2 ? r0 : rp + rj;
    // the state: intact (most), broken in tension or shear with random flags
    std::uint8_t st = ps::kIntact;
    if (r.pick(3) > 0) {
      st = r.coin() ? ps::kBrokenTension : ps::kBrokenShear;
      if (r.coin()) st |= ps::kTouching;
      if (r.coin()) st |= ps::kSeparated;
      if (r.pick(4) == 0) st |= ps::kReclosed;
    }
    const bool intact = st == ps::kIntact;
    const double kn = m.kn * (intact && rest == 2 ? kf : 1.0), ks = m.ks * (intact && rest == 2 ? kf : 1.0);
    // this bond's strengths (the law scales them by sf where it has strengths to scale)
    const double fn_max = fn_max0 * (intact && rest == 2 ? sf : 1.0),
                 fs0 = fs00 * (intact && rest == 2 ? sf : 1.0);
    // normal overlap: intact near the tensile limit or in compression; broken touching or open
    double un;
    if (intact)
      un = (r.coin() ? -ratio(r) * fn_max : r.uniform(0, 3) * fn_max) / kn;
    else
      un = (r.pick(3) > 0 ? 1.0 : -1.0) * r.uniform(0, 2) * fn_max / m.kn;
    if (r.pick(50) == 0) un = 0;  // exactly touching: rest length = distance
    // shear: |Ks·Us| near the intact limit or the friction cap
    const double fn = kn * un;
    const double lim = intact ? fs0 + (m.friction_strengthens_bonds ? m.friction * std::max(fn, 0.0) : 0.0)
                              : m.friction * std::max(fn, 0.0) + (r.pick(4) == 0 ? fs0 : 0.0);
    const double s = (ks > 0 ? ratio(r) * lim / ks : r.uniform(0, 1e-6));
    const auto nrm = direction(r, dim);
    const double len = l0 - un;
    std::array<double, 3> xp{r.uniform(-0.01, 0.01), r.uniform(-0.01, 0.01),
                             dim == 3 ? r.uniform(-0.01, 0.01) : 0.0};
    if (r.pick(20) == 0) xp = {0, 0, 0};
    std::array<double, 3> xj{};
    for (int a = 0; a < 3; ++a) xj[a] = xp[a] + len * nrm[a];
    // stored Us (3D: mostly in the tangent plane, with a small normal part the step removes)
    std::array<double, 3> us{0, 0, 0};
    auto t = direction(r, dim);
    const double tn = t[0] * nrm[0] + t[1] * nrm[1] + t[2] * nrm[2];
    for (int a = 0; a < 3; ++a) t[a] -= (1 - 1e-3 * r.uniform()) * tn * nrm[a];
    const double tl = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int a = 0; a < 3; ++a) t[a] /= tl;
    const double f_inc = r.pick(4) == 0 ? r.uniform(0, 1) : r.uniform(0, 0.01);  // increment / |Us|
    if (dim == 2)
      us[0] = (r.coin() ? 1 : -1) * s * (1 - f_inc);
    else
      for (int a = 0; a < 3; ++a) us[a] = t[a] * s * (1 - f_inc);
    // velocities: this step's relative displacement, mostly along Us (so that |Us| after
    // the step is close to the target), or in a random direction
    std::array<double, 3> vp{r.uniform(-1, 1), r.uniform(-1, 1), dim == 3 ? r.uniform(-1, 1) : 0.0}, vj = vp;
    std::array<double, 3> dv = direction(r, dim);
    if (r.pick(4) > 0) {
      if (dim == 2)
        dv = {-nrm[1] * (us[0] < 0 ? -1 : 1), nrm[0] * (us[0] < 0 ? -1 : 1), 0};
      else
        dv = t;
    }
    const double mag = s * f_inc / cs.dt;
    for (int a = 0; a < 3; ++a) vj[a] += mag * dv[a];
    cs.xp.push_back(xp);
    cs.xj.push_back(xj);
    cs.vp.push_back(vp);
    cs.vj.push_back(vj);
    cs.rp.push_back(rp);
    cs.rj.push_back(rj);
    cs.r0.push_back(r0);
    cs.kf.push_back(kf);
    cs.sf.push_back(sf);
    cs.st.push_back(st);
    cs.us.push_back(us);
  }
  if (rest != 2) cs.r0.clear(), cs.kf.clear(), cs.sf.clear();
  return cs;
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

// Compares the two paths case by case; returns the number of mismatches (first few printed).
long compare(const dem::detail::BondCases& cs, const dem::detail::BondResults& ref,
             const dem::detail::BondResults& bat, int dim, const std::string& what, Coverage& cov,
             bool open_may_defer = false) {
  const int ns = dim == 2 ? 1 : 3;
  long bad = 0;
  auto report = [&](std::size_t i, const char* field) {
    if (++bad <= 5)
      std::printf("%s case %zu: %s differs (state %d -> ref %d / batch %d, verdict ref %d batch %d)\n",
                  what.c_str(), i, field, cs.st[i], ref.st[i], bat.st[i], ref.verdict[i], bat.verdict[i]);
  };
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const bool was_intact = cs.st[i] == ps::kIntact;
    if (ref.verdict[i] == 1) ++cov.broke_tension;
    if (ref.verdict[i] == 2) ++cov.broke_shear;
    if (was_intact && ref.verdict[i] == 0) ++cov.held;
    if (!was_intact) {
      if (ref.st[i] & ps::kTouching)
        ++cov.touching;
      else
        ++cov.open;
      if ((ref.st[i] & ps::kReclosed) && !(cs.st[i] & ps::kReclosed)) ++cov.reclosed;
      // slipping: the shear force sits on the friction cap mu·Fn (Fn = -F·n on the owner)
      double l2 = 0, fn = 0, u2 = 0;
      for (int a = 0; a < 3; ++a) l2 += (cs.xj[i][a] - cs.xp[i][a]) * (cs.xj[i][a] - cs.xp[i][a]);
      for (int a = 0; a < dim; ++a) fn -= ref.force[i][a] * (cs.xj[i][a] - cs.xp[i][a]) / std::sqrt(l2);
      for (int a = 0; a < ns; ++a) u2 += ref.us[i][a] * ref.us[i][a];
      const double cap = cs.material.friction * fn;
      if ((ref.st[i] & ps::kTouching) && cap > 0 && cs.material.ks * std::sqrt(u2) > (1 - 1e-9) * cap)
        ++cov.slipping;
    }
    // verdict: the bond pass leaves exactly the bonds that break now to the reference
    // kernel, and those whose shear history leaves the 32-bit steps now; taking broken bonds
    // found open with the intact ones, it may also leave those that touch again
    const bool reclosing = open_may_defer && !was_intact && !(cs.st[i] & ps::kTouching) &&
                           (ref.st[i] & ps::kTouching) && ref.verdict[i] == 0;
    const bool deferred = reclosing && bat.verdict[i] != 0;
    if (deferred) ++cov.deferred;
    if ((bat.verdict[i] != 0) != (ref.verdict[i] != 0 || ref.widened[i] != 0) && !deferred) {
      report(i, "verdict");
      continue;
    }
    if (bat.verdict[i]) {
      // left to the reference kernel: the stored state must be untouched (Us as the bond
      // pass held it, in 32-bit steps for an intact bond, and read as the reference did)
      bool kept = bat.st[i] == cs.st[i];
      for (int a = 0; a < ns; ++a)
        kept = kept && same_bits(bat.us[i][a], bat.us_before[i][a]) &&
               same_bits(bat.us_before[i][a], ref.us_before[i][a]);
      if (!kept) report(i, "stored state of a bond left to the reference kernel");
      continue;
    }
    if (bat.st[i] != ref.st[i]) report(i, "state");
    for (int a = 0; a < dim; ++a)
      if (!same_bits(bat.force[i][a], ref.force[i][a])) report(i, "force");
    for (int a = 0; a < ns; ++a)
      if (!same_bits(bat.us[i][a], ref.us[i][a])) report(i, "shear displacement");
    if (cs.energy && !same_bits(bat.energy[i], ref.energy[i])) report(i, "energy");
  }
  return bad;
}

// 2000 cases of every material, dimension, rest-length mode and energy flag, each set changed
// by adjust(cases, rest) before both paths of law run; returns the mismatches, counts the cases.
template <class Adjust>
long compare_case_sets(const dem::detail::LawEntry& law, Rng& rng, Coverage& cov, long& cases,
                       bool open_may_defer, Adjust&& adjust) {
  long bad = 0;
  for (const Material& m : materials())
    for (int dim : {2, 3})
      for (int rest : {0, 1, 2})
        for (bool energy : {true, false}) {
          auto cs = make_cases(rng, m, dim, rest, energy, 2000);
          adjust(cs, rest);
          const auto ref = law.reference(dim, cs);
          const auto bat = law.batch(dim, cs);
          const std::string what = law.name + " " + std::to_string(dim) + "D rest " + std::to_string(rest);
          bad += compare(cs, ref, bat, dim, what, cov, open_may_defer);
          cases += static_cast<long>(cs.size());
        }
  return bad;
}

}  // namespace

TEST(LawConformance, EveryLawOfTheRegistryGivesTheSameBitsOnBothPaths) {
  ASSERT_TRUE(kRegistered);
  const auto laws = dem::detail::all_laws();
  ASSERT_GE(laws.size(), std::size(kLaws) + 1);
  Rng rng{20130101};
  for (const dem::detail::LawEntry* law : laws) {
    Coverage cov;
    long cases = 0;
    const long bad = compare_case_sets(*law, rng, cov, cases, false, [](dem::detail::BondCases&, int) {});
    std::printf(
        "%s: %ld cases (batch form: %s); held %ld, broke in tension %ld, in shear %ld; broken touching %ld "
        "(slipping %ld, closed again %ld), open %ld\n",
        law->name.c_str(), cases, law->has_batch ? "yes" : "no", cov.held, cov.broke_tension, cov.broke_shear,
        cov.touching, cov.slipping, cov.reclosed, cov.open);
    EXPECT_EQ(bad, 0) << law->name;
    EXPECT_TRUE(law->has_batch) << law->name;
    // every regime was visited
    EXPECT_GT(cov.held, 1000) << law->name;
    EXPECT_GT(cov.touching, 1000) << law->name;
    EXPECT_GT(cov.open, 1000) << law->name;
    if (law->name == SolidLatticeLaw::kName) {
      EXPECT_GT(cov.reclosed, 500);
      EXPECT_GT(cov.broke_tension, 500);
      EXPECT_GT(cov.broke_shear, 500);
      EXPECT_GT(cov.slipping, 500);
    }
  }
}

// Broken bonds as the law leaves them once found open (separated, not touching, Us zero),
// among intact ones: chunks without a touching broken bond, which a law whose open bonds
// carry nothing (kOpenIsInert) takes through the intact form of the bond pass. Four in
// five stay open (the partner moved out beyond the rest length), the others touch again.
TEST(LawConformance, OpenBrokenBondsAmongIntactOnesGiveTheSameBitsOnBothPaths) {
  ASSERT_TRUE(kRegistered);
  Rng rng{19700101};
  for (const dem::detail::LawEntry* law : dem::detail::all_laws()) {
    Coverage cov;
    long cases = 0;
    const long bad =
        compare_case_sets(*law, rng, cov, cases, true, [&](dem::detail::BondCases& cs, int rest) {
          for (std::size_t i = 0; i < cs.size(); ++i) {
            if (cs.st[i] == ps::kIntact) continue;
            cs.st[i] = static_cast<std::uint8_t>((cs.st[i] & ~ps::kTouching) | ps::kSeparated);
            cs.us[i] = {0, 0, 0};
            if (rng.pick(5) == 0) continue;
            const double l0 = rest == 2 ? cs.r0[i] : cs.rp[i] + cs.rj[i];
            double l2 = 0;
            for (int a = 0; a < 3; ++a) l2 += (cs.xj[i][a] - cs.xp[i][a]) * (cs.xj[i][a] - cs.xp[i][a]);
            const double f = l0 * (1 + rng.uniform(1e-6, 1e-2)) / std::sqrt(l2);
            for (int a = 0; a < 3; ++a) cs.xj[i][a] = cs.xp[i][a] + f * (cs.xj[i][a] - cs.xp[i][a]);
          }
        });
    std::printf("%s: held %ld, broke %ld; open %ld, touching again %ld (left to the reference kernel %ld)\n",
                law->name.c_str(), cov.held, cov.broke_tension + cov.broke_shear, cov.open, cov.touching,
                cov.deferred);
    EXPECT_EQ(bad, 0) << law->name;
    EXPECT_GT(cov.open, 1000) << law->name;
    EXPECT_GT(cov.touching, 100) << law->name;
    // the intact form took the chunks: it leaves a bond that touches again to the reference kernel
    if (law->name == SolidLatticeLaw::kName) {
      EXPECT_GT(cov.deferred, 100);
    }
  }
}

// A model whose laws all have Ks = 0 keeps no shear history, and its bond pass holds Us at
// zero without computing the shear increment (a law with Ks = 0 gives a zero shear force and
// takes its verdict and energy from Un alone). The reference kernel still adds the increment
// to a zero Us. Both must give the same states, verdicts and energies bit for bit and the
// same forces (as values: where a force component is zero the two may differ in its sign,
// which no sum of forces sees).
TEST(LawConformance, WithoutShearHistoryTheBondPassGivesTheReferenceForces) {
  ASSERT_TRUE(kRegistered);
  Rng rng{19991231};
  for (const dem::detail::LawEntry* law : dem::detail::all_laws()) {
    long bad = 0, cases = 0, held = 0, broke = 0, touching = 0, open = 0;
    for (Material m : materials()) {
      m.ks = 0;
      for (int dim : {2, 3})
        for (int rest : {0, 1, 2})
          for (bool energy : {true, false}) {
            auto cs = make_cases(rng, m, dim, rest, energy, 2000);
            cs.shear_kept = false;
            for (auto& u : cs.us) u = {0, 0, 0};
            const auto ref = law->reference(dim, cs);
            const auto bat = law->batch(dim, cs);
            for (std::size_t i = 0; i < cs.size(); ++i) {
              ++cases;
              const bool was_intact = cs.st[i] == ps::kIntact;
              held += was_intact && ref.verdict[i] == 0;
              broke += ref.verdict[i] != 0;
              touching += !was_intact && (ref.st[i] & ps::kTouching);
              open += !was_intact && !(ref.st[i] & ps::kTouching);
              bool same = (bat.verdict[i] != 0) == (ref.verdict[i] != 0);
              if (same && bat.verdict[i]) {
                same = bat.st[i] == cs.st[i];  // left to the reference kernel, untouched
              } else if (same) {
                same = bat.st[i] == ref.st[i] && (!energy || same_bits(bat.energy[i], ref.energy[i]));
                for (int a = 0; a < dim; ++a) same = same && bat.force[i][a] == ref.force[i][a];
              }
              if (!same && ++bad <= 5)
                std::printf("%s %dD rest %d case %zu: state %d -> ref %d / batch %d, verdict %d / %d\n",
                            law->name.c_str(), dim, rest, i, cs.st[i], ref.st[i], bat.st[i], ref.verdict[i],
                            bat.verdict[i]);
            }
          }
    }
    std::printf("%s without shear history: %ld cases; held %ld, broke %ld, broken touching %ld, open %ld\n",
                law->name.c_str(), cases, held, broke, touching, open);
    EXPECT_EQ(bad, 0) << law->name;
    EXPECT_GT(held, 1000) << law->name;
    EXPECT_GT(touching, 1000) << law->name;
    EXPECT_GT(open, 1000) << law->name;
    if (law->name == SolidLatticeLaw::kName) {
      EXPECT_GT(broke, 500);
    }
  }
}

TEST(LawConformance, TheTableListsTheBuiltInLawsAndTheRegistryFindsThem) {
  for (const LawInfo& l : kLaws) {
    const dem::detail::LawEntry* e = dem::detail::find_law(l.name);
    ASSERT_NE(e, nullptr) << l.name;
    EXPECT_EQ(e->description, l.description);
  }
  EXPECT_EQ(std::string(kLaws[0].name), "solid_lattice");
  EXPECT_EQ(dem::detail::find_law("no_such_law"), nullptr);
  // A name that is taken is refused. The row is the test law's own under the built-in law's
  // name: register_law<SolidLatticeLaw>() would compile a second step kernel here only to be
  // refused (register_law is add_law of make_law_entry).
  dem::detail::LawEntry clash = dem::detail::make_law_entry<LinearSpringLaw>();
  clash.name = kLaws[0].name;
  EXPECT_THROW(dem::detail::add_law(std::move(clash)), Error);
  bool listed = false;
  for (const LawInfo& l : available_laws()) listed = listed || std::string(l.name) == LinearSpringLaw::kName;
  EXPECT_TRUE(listed);
}

namespace {
// A two-disk bond pulled apart at 1 m/s, stopped after `steps`.
Simulation pulled_pair(const char* law, std::int64_t steps) {
  Material m = test::rock_material();
  m.law = law;
  Simulation sim = test::pulled_pair(m, Settings{.dt = 1e-8}, 1.0);
  sim.bond_touching_pairs();
  sim.initialise();
  sim.run(steps);
  return sim;
}

// A saved state as a format-1 state shows it: no law names.
class Format1View final : public StateReader {
 public:
  explicit Format1View(const MemoryState& s) : s_(s) {}
  bool has(const std::string& name) const override { return !hidden(name) && s_.has(name); }
  std::size_t count(const std::string& name, StateType type) const override {
    EXPECT_FALSE(hidden(name));
    return s_.count(name, type);
  }
  void get_array(const std::string& name, StateType type, void* data, std::size_t count) const override {
    EXPECT_FALSE(hidden(name));
    s_.get_array(name, type, data, count);
    if (name == "dem/format") *static_cast<std::int64_t*>(data) = 1;
  }

 private:
  static bool hidden(const std::string& name) { return name.rfind("dem/material_laws", 0) == 0; }
  const MemoryState& s_;
};
}  // namespace

TEST(LawConformance, CheckpointsKeepTheLaw) {
  // The law's name is saved with the materials: a model of the registered law, loaded into
  // an empty Simulation, steps on bit for bit, past the strain at which a solid-lattice bond
  // would break, without breaking.
  Simulation a = pulled_pair(LinearSpringLaw::kName, 100);
  MemoryState saved;
  a.save_state(saved);
  Simulation b(2, Settings{.dt = 1e-8});
  b.load_state(saved);
  a.run(3000);
  b.run(3000);
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_EQ(b.broken_count(), 0u);
  // A state of format 1 has no law names: its materials take the solid-lattice law.
  Simulation c = pulled_pair("solid_lattice", 100);
  MemoryState saved_c;
  c.save_state(saved_c);
  Simulation d(2, Settings{.dt = 1e-8});
  d.load_state(Format1View(saved_c));
  c.run(3000);
  d.run(3000);
  EXPECT_EQ(c.state_hash(), d.state_hash());
  EXPECT_EQ(d.broken_count(), 1u);
}

TEST(LawConformance, MaterialsPickTheirLawByName) {
  // A two-disk bond pulled apart by 3e-5 m (Kn·Un = 2e6 N, far beyond Fn_max): the
  // solid-lattice bond breaks, the registered linear spring (no breakage) pulls back with
  // Kn·|Un|.
  for (const char* name : {"solid_lattice", LinearSpringLaw::kName}) {
    Simulation sim = pulled_pair(name, 3000);
    const double pull = sim.group_force("right")[0];
    if (std::string(name) == "solid_lattice") {
      EXPECT_EQ(sim.broken_count(), 1u);
      EXPECT_EQ(pull, 0.0);
    } else {
      EXPECT_EQ(sim.broken_count(), 0u);
      std::array<double, 3> u, v;
      sim.kinematics(1, u, v);
      const double kn = test::rock_material().kn;
      EXPECT_NEAR(-pull, kn * u[0], 1e-9 * kn * u[0]);
    }
  }
  // unknown names and mixed laws are refused
  Simulation sim(2, Settings{.dt = 1e-8});
  Material bad = test::rock_material();
  bad.law = "no_such_law";
  EXPECT_THROW(sim.add_material(bad), Error);
  sim.add_material(test::rock_material());
  Material other = test::rock_material();
  other.law = LinearSpringLaw::kName;
  EXPECT_THROW(sim.add_material(other), Error);
}
