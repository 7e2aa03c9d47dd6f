// Bit-for-bit identical results for any thread count.
#include "dem_test_util.hpp"

#include <strata/core/parallel.hpp>
#include <strata/preprocess/ecc.hpp>

#include <gtest/gtest.h>

#include <tuple>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

namespace {
struct Outcome {
  std::uint64_t hash;
  std::size_t broken, contacts;
  double ke, eb, w, diss;
  std::vector<BreakEvent> breaks;
  std::int64_t slot_steps;
};

// A block of the uniaxial-compression rock compressed fast enough to break bonds within a few thousand steps,
// with contact detection and viscous damping; enough particles for several thread ranges. `given`
// replaces the block's lattice, `steps` its 1200 (2D) or 600 (3D) steps.
Outcome run(int dim, int threads, int chunks = 1, bool ecc = false, bool slots = true,
            const preprocess::Lattice* given = nullptr, std::int64_t steps = 0) {
  par::set_threads(threads);
  preprocess::Lattice lat = given      ? *given
                            : dim == 2 ? preprocess::hex2d_rows(44, 40, kRockD)
                                       : preprocess::close_packed_box(preprocess::Packing::FCC, {0, 0, 0},
                                                                      {12e-3, 12e-3, 12e-3}, kRockD);
  Simulation sim(dim, Settings{.dt = 1e-12,
                               .damping = Settings::Damping::Viscous,
                               .viscous_c = 1.16e3,
                               .energy_check_every = 100,
                               .min_particles_per_thread = 1,
                               .lattice_slots = slots});
  add_lattice(sim, lat, sim.add_material(rock_material()));
  sim.add_to_group(preprocess::top_row(lat), "top");
  sim.add_to_group(preprocess::bottom_row(lat), "bottom");
  const unsigned ax = dim == 2 ? kY : kZ;
  std::array<double, 3> vt{0, 0, 0}, vb{0, 0, 0};
  vt[dim - 1] = -10.0;
  vb[dim - 1] = 10.0;
  sim.prescribe_velocity("top", vt, ax);
  sim.prescribe_velocity("bottom", vb, ax);
  if (ecc) {  // eccentric lattice: per-bond rest lengths and stiffness factors
    const auto e = preprocess::make_eccentric(
        lat, {.type = preprocess::Eccentricity::Cube, .ra = 0.5, .rc = 0.6, .gamma = 0.3, .seed = 3});
    std::vector<double> f(e.bonds.stiffness_factor.begin(), e.bonds.stiffness_factor.end());
    sim.set_bonds(e.bonds.i, e.bonds.j, f);
  } else {
    sim.bond_touching_pairs();
  }
  sim.initialise();
  sim.set_dt(0.5 * sim.critical_dt());
  if (steps == 0) steps = dim == 2 ? 1200 : 600;
  for (int c = 0; c < chunks; ++c) sim.run(steps / chunks);
  Outcome o{sim.state_hash(),          sim.broken_count(), sim.contact_count(),
            sim.kinetic_energy(),      sim.bond_energy(),  sim.external_work(),
            sim.damping_dissipation(), sim.breaks(),       sim.steps_in_lattice_slots()};
  par::set_threads(0);
  return o;
}

void check(int dim, bool ecc = false) {
  // 1, 2 and 3 threads; and 2 threads in 3 chunks (probes between chunks must not change
  // the trajectory: the driver runs in chunks, a restart continues in chunks)
  // A lattice numbered row by row (and in 3D layer by layer) steps in lattice slots on any
  // number of threads (while it has no contacts); the general bond pass (f and h) gives the
  // same bits.
  const Outcome a = run(dim, 1, 1, ecc), b = run(dim, 2, 1, ecc), c = run(dim, 3, 1, ecc),
                d = run(dim, 2, 3, ecc), f = run(dim, 1, 1, ecc, false), g = run(dim, 1, 3, ecc),
                h = run(dim, 3, 1, ecc, false);
  EXPECT_GT(a.broken, 10u) << "the test must exercise breaking";
  if (!ecc) {
    for (const Outcome* o : {&a, &b, &c, &d})
      EXPECT_GT(o->slot_steps, 100) << "the lattice must step in slots, through its first breaks";
    EXPECT_EQ(f.slot_steps, 0);
    EXPECT_EQ(h.slot_steps, 0);
  }
  for (const Outcome* o : {&b, &c, &d, &f, &g, &h}) {
    // exact equality: the design sums every force in a fixed order
    EXPECT_EQ(o->hash, a.hash);
    EXPECT_EQ(o->broken, a.broken);
    EXPECT_EQ(o->contacts, a.contacts);
    EXPECT_EQ(o->ke, a.ke);
    EXPECT_EQ(o->eb, a.eb);
    EXPECT_EQ(o->w, a.w);
    EXPECT_EQ(o->diss, a.diss);
    ASSERT_EQ(o->breaks.size(), a.breaks.size());
    for (std::size_t k = 0; k < a.breaks.size(); ++k) {
      EXPECT_EQ(o->breaks[k].step, a.breaks[k].step);
      EXPECT_EQ(o->breaks[k].id_i, a.breaks[k].id_i);
      EXPECT_EQ(o->breaks[k].position, a.breaks[k].position);
    }
  }
}
}  // namespace

TEST(Determinism, SameHashFor1To3Threads2D) { check(2); }
TEST(Determinism, SameHashFor1To3Threads3D) { check(3); }
TEST(Determinism, SameHashFor1To3ThreadsEccentric2D) { check(2, true); }

TEST(Determinism, TimeStepBoundAndEstimateSameFor1To3Threads) {
  // The rigorous bound and the Lanczos estimate are formed in parallel over chunks of 1024
  // particles, with the sums of a serial pass: the same bits for any thread count. An
  // eccentric block of 5 chunks, bonds given as data (stiffness factors, rest lengths).
  const auto lat = preprocess::hex2d_rows(80, 64, kRockD);
  const auto e = preprocess::make_eccentric(
      lat, {.type = preprocess::Eccentricity::Cube, .ra = 0.5, .rc = 0.6, .gamma = 0.3, .seed = 5});
  std::vector<double> f(e.bonds.stiffness_factor.begin(), e.bonds.stiffness_factor.end());
  std::vector<std::array<double, 2>> got;
  for (int threads : {1, 2, 3}) {
    par::set_threads(threads);
    Simulation sim(2, Settings{.dt = 1e-12, .min_particles_per_thread = 1});
    add_lattice(sim, e.lattice, sim.add_material(rock_material()));
    sim.set_bonds(e.bonds.i, e.bonds.j, f);
    sim.initialise();
    got.push_back({sim.lambda_bound(), sim.lambda_estimate()});
  }
  par::set_threads(0);
  ASSERT_GT(lat.size(), 4 * 1024u);
  EXPECT_GT(got[0][0], got[0][1]);  // the bound lies above the estimate
  for (std::size_t k = 1; k < got.size(); ++k) {
    EXPECT_EQ(got[k][0], got[0][0]) << "bound, threads " << k + 1;
    EXPECT_EQ(got[k][1], got[0][1]) << "estimate, threads " << k + 1;
  }
}

TEST(Determinism, ParticleAddedAfterStepsInSlots) {
  // A particle added to a 2D lattice that has stepped in lattice slots: the bonds' state
  // comes back from the slots before the particle arrays grow, and the run goes on with the
  // same bits as on the general path.
  auto run = [](bool slots) {
    const auto lat = preprocess::hex2d_rows(30, 24, kRockD);
    Simulation sim(2, Settings{.dt = 1e-12, .lattice_slots = slots});
    add_lattice(sim, lat, sim.add_material(rock_material()));
    sim.add_to_group(preprocess::top_row(lat), "top");
    sim.prescribe_velocity("top", {0, -10.0, 0}, kY);
    sim.bond_touching_pairs();
    sim.initialise();
    sim.set_dt(0.5 * sim.critical_dt());
    sim.run(300);
    const std::int64_t before = sim.steps_in_lattice_slots();
    sim.add_particle({0.0, 1.0, 0.0}, kRockD / 2, 0);  // far above the block
    sim.run(300);
    return std::array<std::uint64_t, 3>{sim.state_hash(), static_cast<std::uint64_t>(before),
                                        static_cast<std::uint64_t>(sim.steps_in_lattice_slots())};
  };
  const auto a = run(true), b = run(false);
  EXPECT_EQ(a[1], 300u);
  EXPECT_EQ(a[2], 600u);  // the lone particle has no bond: the slots are built anew
  EXPECT_EQ(b[2], 0u);
  EXPECT_EQ(a[0], b[0]);
}

// The lattice `lat` in lattice slots on `threads` threads against the general path on one:
// the same bits through its first breaks, with more than `min_slot_steps` steps in slots.
static void slots_match_general(const preprocess::Lattice& lat, int threads, std::int64_t steps,
                                std::int64_t min_slot_steps) {
  const int dim = lat.dim;
  const Outcome a = run(dim, threads, 1, false, true, &lat, steps),
                b = run(dim, 1, 1, false, false, &lat, steps);
  EXPECT_GT(a.slot_steps, min_slot_steps);
  EXPECT_EQ(b.slot_steps, 0);
  EXPECT_GT(a.broken, 10u) << "the test must exercise breaking";
  EXPECT_EQ(a.hash, b.hash);
  EXPECT_EQ(a.ke, b.ke);
  EXPECT_EQ(a.eb, b.eb);
  EXPECT_EQ(a.broken, b.broken);
  EXPECT_EQ(a.breaks.size(), b.breaks.size());
}

TEST(Determinism, SlotsOnRangesShorterThanARow) {
  // Rows of 700 disks on eight threads: most threads' ranges (two blocks of 256 disks) are
  // shorter than a row, so a bond's partner may lie two ranges past its owner's.
  // In lattice slots the partner's thread still computes it in phase A (bond by bond, by
  // the reference kernel: ranges this short leave the bond pass to longer ones, which the
  // 2- and 3-thread runs above take through their breaks); the bits are those
  // of the general path on one thread, through the first breaks (the run leaves the slots
  // once disks that were never bonded touch: contacts).
  slots_match_general(preprocess::hex2d_rows(6, 700, kRockD), 8, 400, 300);
}

TEST(Determinism, SlotsInTenDirections3D) {
  // A close-packed box whose rows within a layer are all of one length: partners at
  // p + 1, p + L - 1, p + L and p + L + 1 in the layer and six offsets into the next, ten
  // directions. In lattice slots on three threads it steps with the bits of the general
  // path on one, through its first breaks.
  slots_match_general(preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0},
                                                   {10.6 * kRockD, 9 * kRockD, 9 * kRockD}, kRockD),
                      3, 600, 100);
}

TEST(Determinism, ParticlesAddedAtOnceAsOneByOne) {
  // add_particles fills the arrays in parallel: the same ids, masses and bits as adding the
  // particles one by one, also when added after single ones and before more.
  const auto lat = preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0},
                                                {8 * kRockD, 8 * kRockD, 8 * kRockD}, kRockD);
  const std::vector<std::array<double, 3>> rest(lat.x.begin() + 1, lat.x.end() - 1);
  auto run = [&](bool at_once) {
    Simulation sim(3, Settings{.dt = 1e-12, .min_particles_per_thread = 1});
    const int mat = sim.add_material(rock_material());
    sim.add_particle(lat.x.front(), lat.radius, mat);
    if (at_once) {
      EXPECT_EQ(sim.add_particles(rest, lat.radius, mat), 1u);
    } else {
      for (const auto& p : rest) sim.add_particle(p, lat.radius, mat);
    }
    EXPECT_EQ(sim.add_particle(lat.x.back(), lat.radius, mat), lat.size() - 1);
    sim.add_to_group(preprocess::top_row(lat), "top");
    sim.prescribe_velocity("top", {0, 0, -10.0}, kZ);
    sim.bond_touching_pairs();
    sim.initialise();
    sim.set_dt(0.5 * sim.critical_dt());
    sim.run(200);
    return std::tuple<std::uint64_t, double, double>{sim.state_hash(), sim.critical_dt(), sim.bond_energy()};
  };
  par::set_threads(2);
  const auto a = run(false), b = run(true);
  par::set_threads(0);
  EXPECT_GT(std::get<2>(a), 0.0);  // loaded
  EXPECT_EQ(a, b);
}
