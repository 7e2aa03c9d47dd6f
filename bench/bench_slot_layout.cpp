// A prototype of bonds held in lattice slots, the layout the DEM step kernel takes for a 2D
// lattice on one thread (LatticeSlots, libdem), stripped to its arithmetic.
// On a hexagonal lattice numbered row by row, with rows alternating L and L-1 disks, every
// bond a disk owns goes to p+1, p+L-1 or p+L; held as one array per direction ("slot"),
// indexed by the owner, the partners of eight consecutive owners are eight consecutive
// disks, so both ends' positions and velocities load as whole vectors, and each disk's force
// is pulled from the slots in a fixed order (the reactions of its owners p-L, p-L+1, p-1,
// then its own bonds: the order in which the step kernel sums them) without any scatter.
//
// The arithmetic per bond is the intact form's (geometry, the shear increment, the shear
// history in 32-bit steps rounded stochastically, normal and shear springs, the tensile and
// shear strength tests, the force), and per disk the damped leapfrog update with viscous
// damping; left out are the reference kernel's verdicts, boundary conditions, walls, contacts
// and the energy bookkeeping. Five variants, each a step further from the layout towards the
// general path's, the arithmetic the same:
//   BM_SlotLayout   slots; forces pulled
//   BM_Indexed      bonds direction by direction, partners loaded through an index array
//                   (element by element, as from any list of bonds); forces pulled
//   BM_IndexedPush  the same, and each disk's bond reactions pushed on to their partners
//                   through a pending-force array (the step kernel's scalar particle loop)
//   BM_CsrPush      bonds owner by owner, each owner's three in turn (the step kernel's
//                   order); reactions pushed
//   BM_CsrPull      bonds owner by owner, then each force moved into its direction's slot;
//                   forces pulled
// and BM_SlotLayoutBroken, BM_CsrPushBroken: the first and the last with two bonds in three
// broken and every bond through the intact and the broken-bond law, as after the peak.
// docs/performance.md ("Bonds in lattice slots") sets them beside the step kernel.
//
//   bench_slot_layout --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <vector>

namespace {

constexpr int kDirections = 3;  // p+1, p+L-1, p+L
constexpr double kD = 1e-3, kDt = 2e-8, kKn = 6.587e10, kKs = 2.371e10, kFmax = 1.252e4, kFs0 = 3.69e4,
                 kMu = 0.239;
constexpr double kUnit = 0x1p-48, kInv = 0x1p48;  // the shear history's step and its inverse

enum class Order { kSlots, kIndexed, kCsr };

struct Lattice {
  int n = 0, pad = 0;                                    // disks; force slots before the first
  int offset[kDirections]{};                             // partner - owner
  std::vector<double> x, y, vx, vy;                      // n and padding
  std::vector<std::int64_t> mask[kDirections];           // all ones where the bond exists
  std::vector<std::int64_t> broken[kDirections];         // all ones for a broken bond (kFull)
  std::vector<std::int32_t> partner[kDirections];        // owner + offset, as an index array
  std::vector<std::int32_t> steps[kDirections];          // shear history, 32-bit steps
  std::vector<double> fx[kDirections], fy[kDirections];  // bond forces, from pad on
  std::vector<double> pend_x, pend_y;                    // pending forces (push)
  // the same bonds owner by owner (BM_CsrPush): bond b = 3·owner + direction
  std::vector<std::int32_t> csr_owner, csr_partner, csr_steps;
  std::vector<std::uint8_t> csr_dir;
  std::vector<std::int64_t> csr_mask, csr_broken;
  std::vector<double> csr_fx, csr_fy;

  Lattice(int rows, int long_row) {
    for (int r = 0; r < rows; ++r) n += r % 2 ? long_row - 1 : long_row;
    pad = (long_row / 8 + 1) * 8;
    const int m = n + 2 * long_row + 64;
    for (auto* a : {&x, &y, &vx, &vy, &pend_x, &pend_y}) a->assign(m, 0.0);
    const int off[kDirections] = {1, long_row - 1, long_row};
    for (int k = 0; k < kDirections; ++k) {
      offset[k] = off[k];
      mask[k].assign(m, 0);
      broken[k].assign(m, 0);
      partner[k].assign(m, 0);
      steps[k].assign(m, 0);
      fx[k].assign(m + pad, 0.0);
      fy[k].assign(m + pad, 0.0);
    }
    csr_steps.assign(static_cast<std::size_t>(kDirections) * n, 0);
    csr_fx.assign(static_cast<std::size_t>(kDirections) * n, 0.0);
    csr_fy.assign(static_cast<std::size_t>(kDirections) * n, 0.0);
    int p = 0;
    for (int r = 0; r < rows; ++r) {
      const int len = r % 2 ? long_row - 1 : long_row;
      for (int i = 0; i < len; ++i, ++p) {
        x[p] = (i + (len < long_row ? 0.5 : 0.0)) * kD;
        y[p] = r * kD * std::numbers::sqrt3 / 2;
        vx[p] = 1e-4 * std::sin(p);  // a small, varied motion: the springs work from the start
        vy[p] = 1e-4 * std::cos(p);
        const bool up = r + 1 < rows;
        mask[0][p] = i + 1 < len ? -1 : 0;
        mask[1][p] = up && (len < long_row || i >= 1) ? -1 : 0;
        mask[2][p] = up && (len < long_row || i + 1 < long_row) ? -1 : 0;
        for (int k = 0; k < kDirections; ++k) {
          // two bonds in three broken, as after the peak of the uniaxial-compression example
          broken[k][p] = (static_cast<std::uint32_t>(kDirections * p + k) * 0x9e3779b1u >> 16) % 3 ? -1 : 0;
          csr_broken.push_back(broken[k][p]);
          partner[k][p] = p + off[k];
          csr_owner.push_back(p);
          csr_dir.push_back(static_cast<std::uint8_t>(k));
          csr_partner.push_back(p + off[k]);
          csr_mask.push_back(mask[k][p]);
        }
      }
    }
  }
};

double bits_and(double v, std::int64_t m) {
  std::int64_t b;
  std::memcpy(&b, &v, 8);
  b &= m;
  std::memcpy(&v, &b, 8);
  return v;
}

// x where mask is all ones, else y (by bits: GCC keeps a select of a division as a branch).
inline double select(std::int64_t mask, double x, double y) {
  std::int64_t a, b;
  std::memcpy(&a, &x, 8);
  std::memcpy(&b, &y, 8);
  a = (a & mask) | (b & ~mask);
  std::memcpy(&x, &a, 8);
  return x;
}

// One bond (owner o, partner j): its force on the owner, zero where the bond is missing or
// fails, and its shear history, rounded stochastically by `bits` where it holds. With kFull,
// the form the step kernel takes once bonds break: the intact law and the broken-bond law
// (no tension; shear capped by friction at mu·Fn, a division) for every bond, and the one
// its state `broken` (all ones) names kept.
struct BondOut {
  double fx, fy;
  std::int32_t steps;
};
template <bool kFull>
inline BondOut bond_law(double xo, double yo, double vxo, double vyo, double xj, double yj, double vxj,
                        double vyj, std::int32_t q, std::int64_t m, std::int64_t broken, std::uint32_t bits) {
  double n0 = xj - xo, n1 = yj - yo;
  const double len = std::sqrt(n0 * n0 + n1 * n1);
  const double il = 1.0 / len;
  n0 *= il;
  n1 *= il;
  double us = q * kUnit + ((vyj - vyo) * n0 - (vxj - vxo) * n1) * kDt;
  double fn = kKn * (kD - len), fs = kKs * us;
  std::int64_t keep = m & -static_cast<std::int64_t>((fn > -kFmax) & (std::abs(fs) < kFs0 + kMu * fn));
  if constexpr (kFull) {
    const double fnb = bits_and(fn, -static_cast<std::int64_t>(fn > 0));
    const double cap = kMu * fnb, a = std::abs(fs);
    const double scale = select(-static_cast<std::int64_t>(a > cap), cap / a, 1.0);
    fn = select(broken, fnb, fn);
    fs = select(broken, fs * scale, fs);
    us = select(broken, us * scale, us);
    keep = (m & broken) | (keep & ~broken);
  }
  const double dither = static_cast<double>((bits >> 22) & 1023u) * 0x1p-10 + (0x1p-11 - 0.5);
  const auto s = static_cast<std::int32_t>(((us * kInv + dither) + 0x1.8p52) - 0x1.8p52);
  const auto k32 = static_cast<std::int32_t>(keep);
  return {bits_and(-fn * n0 - fs * n1, keep), bits_and(-fn * n1 + fs * n0, keep), (s & k32) | (q & ~k32)};
}

// One velocity component through the damped leapfrog update with viscous damping, under
// force F; adds its loss to diss and returns the new velocity.
inline double damped(double vo, double F, double& diss) {
  constexpr double kCv = 1.16e3, kIm = 1.0 / (2650.0 * std::numbers::pi * 0.25 * kD * kD);
  constexpr double kH = 0.5 * kCv * kDt * kIm;
  const double vn = (vo * (1 - kH) + kDt * (F * kIm)) / (1 + kH);
  const double vm = 0.5 * (vo + vn);
  diss += kCv * vm * vm * kDt;
  return vn;
}

// Pointers to a lattice's positions and velocities that the compiler may take as unaliased.
struct Motion {
  double* __restrict x;
  double* __restrict y;
  double* __restrict vx;
  double* __restrict vy;
  explicit Motion(Lattice& L) : x(L.x.data()), y(L.y.data()), vx(L.vx.data()), vy(L.vy.data()) {}
  void update(int p, double fx, double fy, double& diss) const {
    vx[p] = damped(vx[p], fx, diss);
    x[p] += vx[p] * kDt;
    vy[p] = damped(vy[p], fy, diss);
    y[p] += vy[p] * kDt;
  }
};

template <Order kOrder, bool kFull>
void bond_pass(Lattice& L, std::uint32_t salt) {
  const int n = L.n;
  const Motion M(L);
  if constexpr (kOrder == Order::kCsr) {
    const std::int32_t* __restrict P = L.csr_owner.data();
    const std::int32_t* __restrict J = L.csr_partner.data();
    const std::int64_t* __restrict mask = L.csr_mask.data();
    const std::int64_t* __restrict brk = L.csr_broken.data();
    std::int32_t* __restrict q = L.csr_steps.data();
    double* __restrict fx = L.csr_fx.data();
    double* __restrict fy = L.csr_fy.data();
#pragma omp simd
    for (int b = 0; b < kDirections * n; ++b) {
      const int p = P[b], j = J[b];
      const BondOut o =
          bond_law<kFull>(M.x[p], M.y[p], M.vx[p], M.vy[p], M.x[j], M.y[j], M.vx[j], M.vy[j], q[b], mask[b],
                          brk[b], static_cast<std::uint32_t>(b) * 0x9e3779b1u + salt);
      fx[b] = o.fx;
      fy[b] = o.fy;
      q[b] = o.steps;
    }
  } else {
    for (int k = 0; k < kDirections; ++k) {
      const int off = L.offset[k];
      const std::int32_t* __restrict pj = L.partner[k].data();
      const std::int64_t* __restrict m = L.mask[k].data();
      const std::int64_t* __restrict brk = L.broken[k].data();
      std::int32_t* __restrict q = L.steps[k].data();
      double* __restrict fx = L.fx[k].data() + L.pad;
      double* __restrict fy = L.fy[k].data() + L.pad;
#pragma omp simd
      for (int p = 0; p < n; ++p) {
        const int j = kOrder == Order::kSlots ? p + off : pj[p];
        const BondOut o =
            bond_law<kFull>(M.x[p], M.y[p], M.vx[p], M.vy[p], M.x[j], M.y[j], M.vx[j], M.vy[j], q[p], m[p],
                            brk[p], static_cast<std::uint32_t>(k * n + p) * 0x9e3779b1u + salt);
        fx[p] = o.fx;
        fy[p] = o.fy;
        q[p] = o.steps;
      }
    }
  }
}

// Each disk's force pulled from the slots: the reactions of its owners p-L, p-L+1 and p-1
// (ascending owner), then its own bonds; a missing bond's slot holds +0.
void pull_and_update(Lattice& L, double& dissipated) {
  const int n = L.n, o1 = L.offset[1], o2 = L.offset[2];
  const Motion M(L);
  const double* __restrict f0x = L.fx[0].data() + L.pad;
  const double* __restrict f0y = L.fy[0].data() + L.pad;
  const double* __restrict f1x = L.fx[1].data() + L.pad;
  const double* __restrict f1y = L.fy[1].data() + L.pad;
  const double* __restrict f2x = L.fx[2].data() + L.pad;
  const double* __restrict f2y = L.fy[2].data() + L.pad;
  double diss = 0;
#pragma omp simd reduction(+ : diss)
  for (int p = 0; p < n; ++p) {
    const double fx = (((0.0 - f2x[p - o2]) - f1x[p - o1]) - f0x[p - 1]) + f0x[p] + f1x[p] + f2x[p];
    const double fy = (((0.0 - f2y[p - o2]) - f1y[p - o1]) - f0y[p - 1]) + f0y[p] + f1y[p] + f2y[p];
    M.update(p, fx, fy, diss);
  }
  dissipated += diss;
}

// The owner-by-owner bond pass's forces moved into the direction slots, bond by bond (as an
// owner-ordered bond list must: through each bond's owner and direction).
void csr_to_slots(Lattice& L) {
  for (int b = 0; b < kDirections * L.n; ++b) {
    const int k = L.csr_dir[b], p = L.csr_owner[b];
    L.fx[k][L.pad + p] = L.csr_fx[b];
    L.fy[k][L.pad + p] = L.csr_fy[b];
  }
}

// Each disk takes the reactions its lower owners left, adds its own bonds' forces and passes
// their reactions on (scalar, as the step kernel's particle loop).
template <Order kOrder>
void push_and_update(Lattice& L, double& dissipated) {
  const Motion M(L);
  double diss = 0;
  for (int p = 0; p < L.n; ++p) {
    double F[2] = {L.pend_x[p], L.pend_y[p]};
    L.pend_x[p] = 0;
    L.pend_y[p] = 0;
    for (int k = 0; k < kDirections; ++k) {
      if (!L.mask[k][p]) continue;
      const std::size_t b = kOrder == Order::kCsr ? static_cast<std::size_t>(kDirections) * p + k : L.pad + p;
      const double gx = kOrder == Order::kCsr ? L.csr_fx[b] : L.fx[k][b];
      const double gy = kOrder == Order::kCsr ? L.csr_fy[b] : L.fy[k][b];
      L.pend_x[p + L.offset[k]] -= gx;
      L.pend_y[p + L.offset[k]] -= gy;
      F[0] += gx;
      F[1] += gy;
    }
    M.update(p, F[0], F[1], diss);
  }
  dissipated += diss;
}

// state.range(0): rows; state.range(1): disks in a long row.
template <Order kOrder, bool kPush, bool kFull = false>
void BM_Step(benchmark::State& state) {
  Lattice L(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  double dissipated = 0;
  std::uint32_t s = 0;
  for (auto _ : state) {
    bond_pass<kOrder, kFull>(L, ++s * 0x846ca68bu);
    if constexpr (kPush) {
      push_and_update<kOrder>(L, dissipated);
    } else {
      if constexpr (kOrder == Order::kCsr) csr_to_slots(L);
      pull_and_update(L, dissipated);
    }
  }
  benchmark::DoNotOptimize(dissipated);
  state.counters["disks"] = L.n;
  state.counters["particle_steps_per_s"] = benchmark::Counter(
      static_cast<double>(L.n) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_SlotLayout(benchmark::State& state) { BM_Step<Order::kSlots, false>(state); }
void BM_Indexed(benchmark::State& state) { BM_Step<Order::kIndexed, false>(state); }
void BM_IndexedPush(benchmark::State& state) { BM_Step<Order::kIndexed, true>(state); }
void BM_CsrPush(benchmark::State& state) { BM_Step<Order::kCsr, true>(state); }
void BM_CsrPull(benchmark::State& state) { BM_Step<Order::kCsr, false>(state); }
void BM_SlotLayoutBroken(benchmark::State& state) { BM_Step<Order::kSlots, false, true>(state); }
void BM_CsrPushBroken(benchmark::State& state) { BM_Step<Order::kCsr, true, true>(state); }

}  // namespace

// The uniaxial-compression example's specimen (35 rows of 30 and 29 disks: 1033) and a
// block of about 10^6 disks (1000 rows of 1000 and 999).
BENCHMARK(BM_SlotLayout)->Args({35, 30})->Args({1000, 1000})->ArgNames({"rows", "long_row"});
BENCHMARK(BM_Indexed)->Args({35, 30})->Args({1000, 1000})->ArgNames({"rows", "long_row"});
BENCHMARK(BM_IndexedPush)->Args({35, 30})->Args({1000, 1000})->ArgNames({"rows", "long_row"});
BENCHMARK(BM_CsrPush)->Args({35, 30})->Args({1000, 1000})->ArgNames({"rows", "long_row"});
BENCHMARK(BM_CsrPull)->Args({35, 30})->Args({1000, 1000})->ArgNames({"rows", "long_row"});
// After the peak: two bonds in three broken, the full form for every bond (the example only).
BENCHMARK(BM_SlotLayoutBroken)->Args({35, 30})->ArgNames({"rows", "long_row"});
BENCHMARK(BM_CsrPushBroken)->Args({35, 30})->ArgNames({"rows", "long_row"});
BENCHMARK_MAIN();
