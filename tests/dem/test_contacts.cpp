// Contact search never misses a touching pair (Verlet list with skin vs brute force).
#include "dem_test_util.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

namespace {
void gas(int dim) {
  // Particles on a loose grid (spacing 1.3·d) with random velocities and no bonds; they
  // collide through frictional contacts. At 60 probes the engine's touching pairs must
  // equal the brute-force O(N²) set exactly.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), ur(0.4e-3, 0.6e-3);
  // soft contacts (Kn = 1e7 N/m) so a collision lasts many steps and probes see overlaps
  Material m = rock_material();
  m.kn = 1e7;
  m.ks = 4e6;
  Simulation sim(dim, Settings{.dt = 1e-12});
  const int mat = sim.add_material(m);
  const int n1 = dim == 2 ? 24 : 8;
  const double sp = 1.3e-3;
  for (int k = 0; k < (dim == 3 ? n1 : 1); ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n1; ++i) sim.add_particle({i * sp, j * sp, k * sp}, ur(rng), mat);
  sim.initialise();
  sim.set_dt(0.3 * sim.critical_dt());
  // random velocities moving a particle up to 2e-5 m (~0.04 r) per step
  const double vmax = 2e-5 / sim.dt();
  for (std::size_t id = 0; id < sim.particle_count(); ++id)
    sim.set_velocity(id, {vmax * u(rng), vmax * u(rng), dim == 3 ? vmax * u(rng) : 0});
  int total_touching = 0;
  for (int probe = 0; probe < 60; ++probe) {
    sim.run(37);
    const auto x = sim.positions();
    const auto r = sim.radii();
    const auto ids = sim.ids();
    std::vector<std::array<std::uint32_t, 2>> brute;
    for (std::size_t i = 0; i < x.size(); ++i)
      for (std::size_t j = i + 1; j < x.size(); ++j) {
        double d2 = 0;
        for (int a = 0; a < dim; ++a) d2 += (x[i][a] - x[j][a]) * (x[i][a] - x[j][a]);
        if (d2 < (r[i] + r[j]) * (r[i] + r[j]))
          brute.push_back({std::min(ids[i], ids[j]), std::max(ids[i], ids[j])});
      }
    std::sort(brute.begin(), brute.end());
    EXPECT_EQ(sim.touching_pairs(), brute) << "probe " << probe;
    total_touching += static_cast<int>(brute.size());
  }
  EXPECT_GT(total_touching, 20) << "the gas must actually collide";
}
}  // namespace

TEST(Contacts, SearchNeverMisses2D) { gas(2); }
TEST(Contacts, SearchNeverMisses3D) { gas(3); }

namespace {
// The contact candidates bond_touching_pairs finds in its own search (for initialise) are
// the pairs a search of their own finds: within ri + rj + skin and not bonded.
void candidates_with_the_bonds(int dim) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ur(0.45e-3, 0.55e-3), jitter(-0.05e-3, 0.05e-3);
  auto build = [&](Simulation& sim) {
    rng.seed(11);
    const int mat = sim.add_material(rock_material());
    const int n1 = dim == 2 ? 40 : 12;
    const double sp = 1.05e-3;  // some neighbours touch (bonds), others lie within the skin
    for (int k = 0; k < (dim == 3 ? n1 : 1); ++k)
      for (int j = 0; j < n1; ++j)
        for (int i = 0; i < n1; ++i)
          sim.add_particle({i * sp + jitter(rng), j * sp + jitter(rng), dim == 3 ? k * sp + jitter(rng) : 0},
                           ur(rng), mat);
  };
  const Settings s{.dt = 1e-12, .contact_detection = true};
  Simulation found(dim, s), searched(dim, s);
  build(found);
  build(searched);
  found.bond_touching_pairs();  // bonds and contact candidates in one search
  std::vector<std::uint32_t> bi, bj;
  const auto ids = found.ids();
  for (const auto& b : found.bonds()) bi.push_back(ids[b.i]), bj.push_back(ids[b.j]);
  searched.set_bonds(bi, bj, {}, {});  // the same bonds; initialise searches the contacts itself
  found.initialise();
  searched.initialise();
  const auto a = found.contacts(), b = searched.contacts();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_GT(a.size(), 20u) << "the test needs near, unbonded pairs";
  EXPECT_GT(bi.size(), 20u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].i, b[k].i) << k;
    EXPECT_EQ(a[k].j, b[k].j) << k;
  }
}
}  // namespace

TEST(Contacts, CandidatesFoundWithTheBondsAreThoseOfTheirOwnSearch2D) { candidates_with_the_bonds(2); }
TEST(Contacts, CandidatesFoundWithTheBondsAreThoseOfTheirOwnSearch3D) { candidates_with_the_bonds(3); }

namespace {
// bond_touching_pairs bonds exactly the pairs within (ri + rj)(1 + tolerance), as a brute-force
// O(N²) search finds them: radii of 0.45-0.55 mm on a jittered grid, with and without the
// contact candidates listed in the same search, particles in the grid's edge cells included.
void bonds_against_brute_force(int dim, bool contacts) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> ur(0.45e-3, 0.55e-3), jitter(-0.08e-3, 0.08e-3);
  Simulation sim(dim, Settings{.dt = 1e-12, .contact_detection = contacts});
  const int mat = sim.add_material(rock_material());
  const int n1 = dim == 2 ? 40 : 11;
  const double sp = 1.02e-3;
  for (int k = 0; k < (dim == 3 ? n1 : 1); ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n1; ++i)
        sim.add_particle({i * sp + jitter(rng), j * sp + jitter(rng), dim == 3 ? k * sp + jitter(rng) : 0},
                         ur(rng), mat);
  const double tol = 0.01;
  sim.bond_touching_pairs(tol);
  const auto x = sim.positions();
  const auto r = sim.radii();
  const auto ids = sim.ids();
  std::vector<std::array<std::uint32_t, 2>> brute, found;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      double d2 = 0;
      for (int a = 0; a < dim; ++a) d2 += (x[j][a] - x[i][a]) * (x[j][a] - x[i][a]);
      const double reach = r[i] + r[j];  // as the search rounds it
      if (d2 <= reach * reach * ((1 + tol) * (1 + tol)))
        brute.push_back({std::min(ids[i], ids[j]), std::max(ids[i], ids[j])});
    }
  for (const auto& b : sim.bonds())
    found.push_back({std::min(ids[b.i], ids[b.j]), std::max(ids[b.i], ids[b.j])});
  std::sort(brute.begin(), brute.end());
  std::sort(found.begin(), found.end());
  EXPECT_GT(brute.size(), x.size() / 2) << "the test needs many bonds";
  EXPECT_EQ(found, brute);
}
}  // namespace

TEST(Contacts, BondsAreTheTouchingPairsOfABruteForceSearch2D) {
  bonds_against_brute_force(2, false);
  bonds_against_brute_force(2, true);
}
TEST(Contacts, BondsAreTheTouchingPairsOfABruteForceSearch3D) {
  bonds_against_brute_force(3, false);
  bonds_against_brute_force(3, true);
}
