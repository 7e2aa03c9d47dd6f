// Eccentric lattices (ECC4D, Zhao, Qiao, Zhang, Sun & Chen 2021): bond statistics against
// what the offsets imply.
#include <gtest/gtest.h>

#include <strata/core/parallel.hpp>
#include <strata/preprocess/ecc.hpp>
#include <strata/preprocess/lattice.hpp>

#include <cmath>
#include <numeric>

using namespace strata;
using namespace strata::preprocess;

namespace {
struct Moments {
  double mean = 0, sd = 0, max = 0;
};
Moments moments(const std::vector<double>& v) {
  Moments m;
  for (double x : v) m.mean += x, m.max = std::max(m.max, x);
  m.mean /= double(v.size());
  for (double x : v) m.sd += (x - m.mean) * (x - m.mean);
  m.sd = std::sqrt(m.sd / double(v.size() - 1));
  return m;
}
const double kD = 1e-3;
Lattice block3d(Packing p = Packing::HCP) { return close_packed_box(p, {0, 0, 0}, {0.03, 0.03, 0.03}, kD); }
}  // namespace

TEST(Ecc, RegularLatticeHasOneBondLength) {
  const Lattice l = block3d();
  EccOptions o;
  o.type = Eccentricity::Cube;
  o.ra = 0;
  const EccLattice e = make_eccentric(l, o);
  // Interior spheres of a close packing have 12 neighbours: bonds/particle -> 6 minus surface.
  EXPECT_GT(double(e.bonds.size()) / double(l.size()), 5.0);
  EXPECT_LT(double(e.bonds.size()) / double(l.size()), 6.0);
  for (double len : e.bonds.length) EXPECT_NEAR(len, kD, 1e-12);
  EXPECT_EQ(e.bonds.weakened(), 0u);
  // 2D hexagonal: 3 bonds per interior disk.
  const Lattice h = hex2d_box(0, 0, 0.05, 0.05, kD);
  const BondList b = touching_pairs(h);
  EXPECT_GT(double(b.size()) / double(h.size()), 2.8);
  EXPECT_LT(double(b.size()) / double(h.size()), 3.0);
}

TEST(Ecc, CubeOffsetsGiveTheExpectedBondLengthSpread) {
  // Type A: offsets uniform in [-a, a]^3, a = Ra·R. Each component has variance a²/3, the
  // difference of two has 2a²/3, so to first order a bond's length L = d + (u_j − u_i)·n has
  // standard deviation a·√(2/3), and its mean grows by the transverse part, 2·(2a²/3)/(2d).
  const Lattice l = block3d();
  for (double ra : {0.1, 0.3}) {
    EccOptions o;
    o.type = Eccentricity::Cube;
    o.ra = ra;
    o.seed = 7;
    const EccLattice e = make_eccentric(l, o);
    const double a = ra * kD / 2;
    const Moments m = moments(e.bonds.length);
    // ~75k bonds: sampling error of the sd ~ 0.3 %; second-order terms ~ (a/d)² ~ 2 %.
    EXPECT_NEAR(m.sd, a * std::sqrt(2.0 / 3.0), 0.04 * a * std::sqrt(2.0 / 3.0)) << "ra " << ra;
    EXPECT_NEAR(m.mean, kD + 2 * a * a / (3 * kD),
                0.1 * a * a / kD + 3 * m.sd / std::sqrt(double(e.bonds.size())));
    EXPECT_LE(m.max, kD + 2 * std::sqrt(3.0) * a);
    // Offsets: each component within a, variance a²/3.
    std::vector<double> dx(l.size());
    for (std::size_t i = 0; i < l.size(); ++i) {
      dx[i] = e.lattice.x[i][0] - l.x[i][0];
      EXPECT_LE(std::abs(dx[i]), a * (1 + 1e-12));
    }
    EXPECT_NEAR(moments(dx).sd, a / std::sqrt(3.0), 0.02 * a / std::sqrt(3.0));
  }
}

TEST(Ecc, SphereOffsetsHaveFixedLengthAndNoDrift) {
  const Lattice l = block3d(Packing::FCC);
  EccOptions o;
  o.type = Eccentricity::Sphere;
  o.ra = 0.5;
  const EccLattice e = make_eccentric(l, o);
  const double a = 0.5 * kD / 2;
  double mz = 0;
  for (std::size_t i = 0; i < l.size(); ++i) {
    const double dx = e.lattice.x[i][0] - l.x[i][0], dy = e.lattice.x[i][1] - l.x[i][1],
                 dz = e.lattice.x[i][2] - l.x[i][2];
    EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), a, 1e-15);
    mz += dz;
  }
  // Uniform on the whole sphere: the mean z offset is 0 (the formula of Zhao et al. 2021
  // would give a/2).
  EXPECT_NEAR(mz / double(l.size()), 0.0, 4 * a / std::sqrt(3.0 * double(l.size())));
  // Same second moments as Type A: bond length sd ≈ a·√(2/3).
  EXPECT_NEAR(moments(e.bonds.length).sd, a * std::sqrt(2.0 / 3.0), 0.06 * a * std::sqrt(2.0 / 3.0));
}

TEST(Ecc, WeakenedBondsAreTheLongOnes) {
  const Lattice l = block3d();
  EccOptions o;
  o.type = Eccentricity::Cube;
  o.ra = 0.9;
  o.rc = 0.5;
  o.gamma = 0.001;  // the case of Zhao et al. 2021 (Ra 0.9, Rc 0.5, γ 0.001)
  const EccLattice e = make_eccentric(l, o);
  std::size_t weak = 0;
  for (std::size_t k = 0; k < e.bonds.size(); ++k) {
    const bool longer = e.bonds.length[k] > o.rc * e.bonds.max_length;
    EXPECT_EQ(e.bonds.stiffness_factor[k], longer ? 0.001f : 1.0f);
    weak += longer;
  }
  EXPECT_EQ(weak, e.bonds.weakened());
  EXPECT_GT(weak, 0u);
  EXPECT_LT(weak, e.bonds.size());
}

TEST(Ecc, SameOffsetsForAnyNumberOfThreadsAndSeedsDiffer) {
  const Lattice l = block3d();
  EccOptions o;
  o.type = Eccentricity::Cube;
  o.ra = 0.4;
  const int before = par::threads();
  par::set_threads(1);
  const EccLattice a = make_eccentric(l, o);
  par::set_threads(2);
  const EccLattice b = make_eccentric(l, o);
  par::set_threads(before);
  EXPECT_EQ(a.lattice.x, b.lattice.x);
  EXPECT_EQ(a.bonds.i, b.bonds.i);
  EXPECT_EQ(a.bonds.j, b.bonds.j);
  o.seed = 2;
  EXPECT_NE(make_eccentric(l, o).lattice.x, a.lattice.x);
}

TEST(Ecc, Histograms) {
  const std::vector<double> v{0.0, 0.1, 0.5, 0.99, 1.0, 2.0, -1.0};
  const auto h = histogram(v, 0, 1, 2);
  EXPECT_EQ(h, (std::vector<std::size_t>{3, 4}));
  const Lattice hx = hex2d_box(0, 0, 0.01, 0.01, kD);
  const BondList b = touching_pairs(hx);
  std::vector<double> az, polar;
  bond_directions(hx, b, az, polar);
  // A regular hexagonal lattice has bonds at 0°, 60° and 120° only.
  for (double x : az)
    EXPECT_TRUE(std::abs(x) < 1e-6 || std::abs(x - 60) < 1e-6 || std::abs(x - 120) < 1e-6) << x;
  EXPECT_TRUE(polar.empty());
}
