// Checkpoint and restart: 2N steps straight and N + save + load into a new Simulation + N
// must give the same bits (state hash, energies, work, dissipation, break list), in memory
// and through an HDF5 file; wrong checkpoints are refused with a clear message.
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/parallel.hpp>
#include <strata/core/state_io.hpp>
#include <strata/dem/presets.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/io/checkpoint.hpp>
#include <strata/io/csv.hpp>
#include <strata/preprocess/lattice.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <limits>
#include <random>

using namespace strata;
using namespace strata::dem;
namespace fs = std::filesystem;

namespace {

// The solid-lattice rock of Liu, Pollard & Shi (2013) for 1 mm disks, with breakable bonds.
Material lattice_rock() { return strata::dem::liu2013_rock(); }
constexpr double kD = 1e-3;

/// 2D: a block of that rock squeezed fast between two platen rows so that bonds break and contacts
/// form within a few hundred steps (viscous damping, contact detection, Verlet rebuilds).
Simulation build_2d_rows(int columns, int rows, const Material& rock = lattice_rock()) {
  const preprocess::Lattice lat = preprocess::hex2d_rows(columns, rows, kD);
  Simulation sim(2, Settings{.dt = 1e-12,
                             .damping = Settings::Damping::Viscous,
                             .viscous_c = 1.16e3,
                             .energy_check_every = 100,
                             .min_particles_per_thread = 1});
  const int mat = sim.add_material(rock);
  for (const auto& p : lat.x) sim.add_particle(p, lat.radius, mat);
  sim.add_to_group(preprocess::top_row(lat), "top");
  sim.add_to_group(preprocess::bottom_row(lat), "bottom");
  sim.prescribe_velocity("top", {0, -2.0, 0}, kY);
  sim.prescribe_velocity("bottom", {0, 2.0, 0}, kY);
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(0.5 * sim.critical_dt());
  return sim;
}
Simulation build_2d() { return build_2d_rows(30, 28); }
/// The same block with normal springs only (ks = 0): the model keeps no shear history.
Simulation build_2d_central() {
  Material rock = lattice_rock();
  rock.ks = 0;
  return build_2d_rows(30, 28, rock);
}

/// 3D: the other kinds of state — step displacement of the top (per-particle trapezoid
/// work history), a force history on the bottom, a moving wall, gravity, local damping.
Simulation build_3d() {
  const preprocess::Lattice lat =
      preprocess::close_packed_box(preprocess::Packing::FCC, {0, 0, 0}, {6e-3, 6e-3, 6e-3}, kD);
  Simulation sim(3, Settings{.dt = 1e-12,
                             .damping = Settings::Damping::Local,
                             .local_alpha = 0.3,
                             .gravity = {0, 0, -9.81},
                             .energy_check_every = 50,
                             .min_particles_per_thread = 1});
  const int mat = sim.add_material(lattice_rock());
  double xmax = -1;
  for (const auto& p : lat.x) {
    sim.add_particle(p, lat.radius, mat);
    xmax = std::max(xmax, p[0]);
  }
  sim.add_to_group(preprocess::top_row(lat), "top");
  sim.add_to_group(preprocess::bottom_row(lat), "bottom");
  sim.fix("bottom", kZ);
  sim.step_displacement("top", {0, 0, -2e-6}, 7);
  sim.force_history("bottom", {0.0, 1e-6}, {{0, 0, 0}, {50.0, 0, 0}});
  // a radial load normal to a vertical borehole through the block's middle, on the spheres
  // near it, and forty groups of one sphere each (more groups than a bit mask would hold)
  std::vector<std::uint32_t> near_axis;
  for (std::uint32_t i = 0; i < lat.size(); ++i)
    if (std::hypot(lat.x[i][0] - 3e-3, lat.x[i][1] - 3e-3) < 1.6e-3 && lat.x[i][2] > 1e-3)
      near_axis.push_back(i);
  EXPECT_GE(near_axis.size(), 8u);
  sim.add_to_group(near_axis, "borehole");
  sim.radial_force_history("borehole", {0.0, 2e-6}, {0.0, 80.0}, {3e-3, 3e-3, 0}, {0, 0, 1});
  for (std::uint32_t k = 0; k < 40; ++k) sim.add_to_group({k * 3}, "one_" + std::to_string(k));
  sim.fix("one_39", kX);
  sim.add_wall({xmax + lat.radius * 0.999, 0, 0}, {-1, 0, 0}, {-2.0, 0, 0}, 1e8);
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(0.5 * sim.critical_dt());
  return sim;
}

struct Outcome {
  std::uint64_t hash;
  std::int64_t step;
  double time, ke, eb, work, diss;
  std::size_t broken, contacts;
  std::int64_t last_good;
  std::vector<BreakEvent> breaks;
  std::array<double, 3> top_force;
};

Outcome outcome(const Simulation& s) {
  return {s.state_hash(),          s.step_count(),   s.time(),
          s.kinetic_energy(),      s.bond_energy(),  s.external_work(),
          s.damping_dissipation(), s.broken_count(), s.contact_count(),
          s.last_good_step(),      s.breaks(),       s.group_force("top")};
}

void expect_same(const Outcome& a, const Outcome& b) {
  // exact equality: the restart must continue along the same floating-point path
  EXPECT_EQ(a.hash, b.hash);
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.ke, b.ke);
  EXPECT_EQ(a.eb, b.eb);
  EXPECT_EQ(a.work, b.work);
  EXPECT_EQ(a.diss, b.diss);
  EXPECT_EQ(a.broken, b.broken);
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.last_good, b.last_good);
  EXPECT_EQ(a.top_force, b.top_force);
  ASSERT_EQ(a.breaks.size(), b.breaks.size());
  for (std::size_t k = 0; k < a.breaks.size(); ++k) {
    EXPECT_EQ(a.breaks[k].step, b.breaks[k].step);
    EXPECT_EQ(a.breaks[k].id_i, b.breaks[k].id_i);
    EXPECT_EQ(a.breaks[k].id_j, b.breaks[k].id_j);
    EXPECT_EQ(a.breaks[k].mode, b.breaks[k].mode);
    EXPECT_EQ(a.breaks[k].position, b.breaks[k].position);
  }
}

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("strata_ckpt_" + std::to_string(std::random_device{}()) + "_" + name);
}

/// Runs 2N steps straight and N, save, load into a rebuilt Simulation, N more on
/// `threads_after` threads (the results do not depend on the thread count; two threads
/// spin-wait at every step, which is slow on a loaded machine, so most runs use one);
/// `store` saves and loads (memory or HDF5).
void restart_equality(const std::function<Simulation()>& build, std::int64_t n,
                      const std::function<void(const Simulation&, Simulation&)>& store, bool must_break,
                      int threads_after = 1) {
  par::set_threads(1);
  Simulation straight = build();
  straight.run(n);
  const std::size_t broken_at_n = straight.broken_count();
  straight.run(n);
  const Outcome a = outcome(straight);
  if (must_break) {
    EXPECT_GT(broken_at_n, 0u) << "the first half must break bonds";
    EXPECT_GT(a.broken, broken_at_n) << "the second half must break bonds";
    EXPECT_GT(a.contacts, 0u) << "the test must exercise contacts";
  }

  Simulation first = build();
  first.run(n);
  Simulation second = build();  // rebuilt from the same description, as the driver does
  store(first, second);
  par::set_threads(threads_after);
  second.run(n);
  par::set_threads(0);
  expect_same(outcome(second), a);
}

void via_memory(const Simulation& from, Simulation& to) {
  MemoryState m;
  from.save_state(m);
  to.load_state(m);
}

void via_hdf5(const Simulation& from, Simulation& to) {
  const fs::path f = temp_file("state.h5");
  {
    io::CheckpointWriter w(
        f, {"test", "fingerprint", from.dim(), from.particle_count(), from.step_count(), from.time()});
    from.save_state(w);
    w.commit();
  }
  EXPECT_FALSE(fs::exists(f.string() + ".tmp"));
  {
    io::CheckpointReader r(f);
    EXPECT_EQ(r.info().fingerprint, "fingerprint");
    EXPECT_EQ(r.info().step, from.step_count());
    EXPECT_EQ(r.info().dimension, from.dim());
    to.load_state(r);
  }
  fs::remove(f);
}

/// One array as it was handed to a checkpoint.
struct Recorded {
  std::string name;
  StateType type;
  std::size_t count;
  std::vector<unsigned char> bytes;
};

/// Passes every array on to a checkpoint and keeps a copy of it.
class Recorder final : public StateWriter {
 public:
  explicit Recorder(StateWriter& to) : to_(to) {}
  void put_array(const std::string& name, StateType type, const void* data, std::size_t count) override {
    to_.put_array(name, type, data, count);
    const auto* b = static_cast<const unsigned char*>(data);
    arrays.push_back(
        {name, type, count, std::vector<unsigned char>(b, b + count * MemoryState::element_size(type))});
  }
  std::vector<Recorded> arrays;

 private:
  StateWriter& to_;
};

/// Opens checkpoint `f` and reads back its info and every array; whether all of it is bit
/// for bit what was written (a strata::Error from the reader goes to the caller).
bool reads_back_the_same(const fs::path& f, const io::CheckpointInfo& info,
                         const std::vector<Recorded>& arrays) {
  io::CheckpointReader r(f);
  const io::CheckpointInfo& got = r.info();
  bool same = got.version == info.version && got.fingerprint == info.fingerprint &&
              got.dimension == info.dimension && got.particles == info.particles && got.step == info.step &&
              std::memcmp(&got.time, &info.time, sizeof(double)) == 0;
  for (const Recorded& a : arrays) {
    if (!r.has(a.name)) return false;
    const std::size_t n = r.count(a.name, a.type);
    if (n != a.count) return false;
    std::vector<unsigned char> bytes(a.bytes.size() + 1);  // one more: data() is never null
    r.get_array(a.name, a.type, bytes.data(), n);
    bytes.pop_back();
    same = same && bytes == a.bytes;
  }
  return same;
}

}  // namespace

TEST(Checkpoint, RestartInMemoryIsBitIdentical2D) { restart_equality(build_2d, 300, via_memory, true, 2); }

// 147: the checkpoint falls right after a step-displacement jump (every 7 steps), when the
// trapezoid-rule work history of the top particles is not zero.
TEST(Checkpoint, RestartInMemoryIsBitIdentical3D) { restart_equality(build_3d, 147, via_memory, false); }

TEST(Checkpoint, RestartOfACentralForceLatticeIsBitIdentical) {
  // no shear history is kept or stored: the state holds empty shear displacements
  restart_equality(build_2d_central, 300, via_memory, true, 2);
  if (STRATA_WITH_HDF5) restart_equality(build_2d_central, 300, via_hdf5, true);
}

TEST(Checkpoint, RestartThroughHdf5IsBitIdentical2D) {
  if (!STRATA_WITH_HDF5) GTEST_SKIP() << "built without HDF5";
  restart_equality(build_2d, 300, via_hdf5, true);
}

TEST(Checkpoint, RestartThroughHdf5IsBitIdentical3D) {
  if (!STRATA_WITH_HDF5) GTEST_SKIP() << "built without HDF5";
  restart_equality(build_3d, 147, via_hdf5, false);
}

namespace {
/// Copies array `name`, whatever its element type, from one state to another.
void copy_array(const MemoryState& from, MemoryState& to, const std::string& name) {
  for (const StateType t : {StateType::UInt8, StateType::UInt32, StateType::Int64, StateType::Float64}) {
    std::size_t n = 0;
    try {
      n = from.count(name, t);
    } catch (const Error&) {
      continue;  // stored with another type
    }
    std::vector<unsigned char> bytes(n * MemoryState::element_size(t) + 1);
    from.get_array(name, t, bytes.data(), n);
    to.put_array(name, t, bytes.data(), n);
    return;
  }
  ADD_FAILURE() << "no array " << name;
}
}  // namespace

// Checkpoints of formats 1 and 2 kept a bit mask of groups per particle and per boundary
// condition (at most 32 groups). Such a state, made here from a format-3 one, loads into the
// same model (groups as sets) and continues along the same bits.
TEST(Checkpoint, StatesWithGroupBitMasksStillLoad) {
  par::set_threads(1);
  Simulation a = build_2d();
  a.run(100);
  MemoryState now;
  a.save_state(now);
  ASSERT_TRUE(now.has("dem/group_sets/offsets"));
  const auto off = now.get<std::uint32_t>("dem/group_sets/offsets");
  const auto members = now.get<std::uint32_t>("dem/group_sets/members");
  MemoryState old;
  for (const std::string& name : now.names()) {
    if (name.rfind("dem/group_sets/", 0) == 0 || name.find("/radial") != std::string::npos ||
        name.find("/centre") != std::string::npos || name.find("/axis") != std::string::npos ||
        name.find("/ramp") != std::string::npos)
      continue;
    if (name == "dem/format") {
      old.put_scalar<std::int64_t>(name, 2);
    } else if (name == "dem/particles/group_set") {
      std::vector<std::uint32_t> bits;
      for (const auto set : now.get<std::uint32_t>(name)) {
        std::uint32_t mask = 0;
        for (auto k = off[set]; k < off[set + 1]; ++k) mask |= 1u << members[k];
        bits.push_back(mask);
      }
      old.put("dem/particles/group_bits", bits);
    } else if (name == "dem/boundary_specs/group") {
      std::vector<std::uint32_t> masks;
      for (const auto g : now.get<std::uint32_t>(name)) masks.push_back(1u << g);
      old.put("dem/boundary_specs/mask", masks);
    } else {
      copy_array(now, old, name);
    }
  }
  Simulation b = build_2d();
  b.load_state(old);
  EXPECT_EQ(b.group_members("top"), a.group_members("top"));
  EXPECT_EQ(b.group_members("bottom"), a.group_members("bottom"));
  a.run(200);
  b.run(200);
  expect_same(outcome(b), outcome(a));
  par::set_threads(0);
}

// A checkpoint needs no rebuilt model: an empty Simulation of the same dimension takes it.
TEST(Checkpoint, LoadsIntoAnEmptySimulation) {
  par::set_threads(1);
  Simulation a = build_2d();
  a.run(100);
  MemoryState m;
  a.save_state(m);
  a.run(100);
  Simulation b(2, Settings{.min_particles_per_thread = 1});
  b.load_state(m);
  EXPECT_EQ(b.particle_count(), a.particle_count());
  EXPECT_EQ(b.dt(), a.dt());
  EXPECT_EQ(b.group_members("top"), a.group_members("top"));
  b.run(100);
  EXPECT_EQ(b.state_hash(), a.state_hash());
  par::set_threads(0);
}

TEST(Checkpoint, RefusesAnotherDimensionOrParticleCount) {
  Simulation a = build_2d();
  MemoryState m;
  a.save_state(m);
  Simulation three(3, Settings{});
  try {
    three.load_state(m);
    FAIL() << "a 2D state loaded into a 3D model";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input);
    EXPECT_NE(std::string(e.what()).find("2D model, this model is 3D"), std::string::npos) << e.what();
  }
  Simulation other(2, Settings{.dt = 1e-9});
  other.add_particle({0, 0, 0}, 5e-4, other.add_material(lattice_rock()));
  try {
    other.load_state(m);
    FAIL() << "a state loaded into a model with another particle count";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input);
    EXPECT_NE(std::string(e.what()).find("this model 1"), std::string::npos) << e.what();
  }
  EXPECT_EQ(other.particle_count(), 1u) << "a refused load must leave the model as it was";
}

TEST(Checkpoint, Hdf5FilesAreCheckedOnOpening) {
  if (!STRATA_WITH_HDF5) {
    EXPECT_THROW(io::CheckpointReader("x.h5"), Error);
    return;
  }
  EXPECT_THROW(io::CheckpointReader(temp_file("missing.h5")), Error);
  const fs::path text = temp_file("not_hdf5.h5");
  std::ofstream(text) << "not a checkpoint\n";
  try {
    io::CheckpointReader r(text);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a strata checkpoint"), std::string::npos) << e.what();
  }
  fs::remove(text);
  // an uncommitted writer leaves nothing behind
  const fs::path f = temp_file("uncommitted.h5");
  {
    io::CheckpointWriter w(f, {});
    w.put_scalar<double>("a/b", 1.0);
  }
  EXPECT_FALSE(fs::exists(f));
  EXPECT_FALSE(fs::exists(f.string() + ".tmp"));
  // types and counts are checked
  {
    io::CheckpointWriter w(f, {"v", "fp", 2, 0, 0, 0});
    w.put_scalar<double>("a/b", 1.5);
    w.put<std::uint32_t>("a/ids", {});
    w.commit();
  }
  io::CheckpointReader r(f);
  EXPECT_EQ(r.get_scalar<double>("a/b"), 1.5);
  EXPECT_TRUE(r.get<std::uint32_t>("a/ids").empty());
  EXPECT_TRUE(r.has("a/b"));
  EXPECT_FALSE(r.has("a/c"));
  EXPECT_FALSE(r.has("x/y/z"));
  EXPECT_THROW(r.get<std::int64_t>("a/b"), Error);
  EXPECT_THROW(r.get<double>("a/missing"), Error);
  fs::remove(f);
}

// A checkpoint with one flipped bit anywhere is refused on opening (every checksum of the file is
// checked there), unless the bit lies in bytes HDF5 does not use; then everything reads back as
// written. Never does a damaged file give other values.
TEST(Checkpoint, EveryFlippedBitIsCaughtOrHarmless) {
  if (!STRATA_WITH_HDF5) GTEST_SKIP() << "built without HDF5";
  par::set_threads(1);
  // a small real model (a few dozen disks, bonds, platen groups, 30 steps run): every kind of array the
  // DEM state has, empty ones included, about a hundred arrays in nested groups
  Simulation sim = build_2d_rows(8, 7);
  sim.run(30);
  par::set_threads(0);
  const fs::path good = temp_file("flip_good.h5");
  const io::CheckpointInfo info{"test", "fingerprint", 2, sim.particle_count(), sim.step_count(), sim.time()};
  std::vector<Recorded> arrays;
  {
    io::CheckpointWriter w(good, info);
    Recorder rec(w);
    sim.save_state(rec);
    w.commit();
    arrays = std::move(rec.arrays);
  }
  ASSERT_TRUE(reads_back_the_same(good, info, arrays));
  EXPECT_TRUE(std::any_of(arrays.begin(), arrays.end(), [](const Recorded& a) { return a.count == 0; }))
      << "the checkpoint should hold empty arrays too";
  std::vector<char> original;
  {
    std::ifstream in(good, std::ios::binary);
    original.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  fs::remove(good);
  ASSERT_GT(original.size(), 1000u);

  // ~500 flips spread over the whole file: position k * stride plus a varying offset inside the
  // stride (so that not always the same byte of a field is hit), bit k mod 8
  const std::size_t size = original.size();
  const std::size_t stride = std::max<std::size_t>(1, size / 500);
  const fs::path bad = temp_file("flip_bad.h5");
  std::size_t tried = 0, caught = 0, harmless = 0, silent = 0;
  for (std::size_t k = 0; k * stride < size; ++k) {
    const std::size_t pos = std::min(size - 1, k * stride + (k * 37) % stride);
    std::vector<char> bytes = original;
    bytes[pos] = static_cast<char>(bytes[pos] ^ (1 << (k % 8)));
    {
      std::ofstream out(bad, std::ios::binary | std::ios::trunc);
      out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    ++tried;
    try {
      if (reads_back_the_same(bad, info, arrays)) {
        ++harmless;
      } else {
        ++silent;
        ADD_FAILURE() << "bit " << k % 8 << " of byte " << pos
                      << " flipped: read back other values, no error";
      }
    } catch (const Error& e) {
      ++caught;
      EXPECT_EQ(e.kind(), ErrorKind::IO) << "byte " << pos << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos)
          << "byte " << pos << ": the message must name the file: " << e.what();
    }
  }
  fs::remove(bad);
  std::cout << "checkpoint of " << size << " bytes, " << tried << " single-bit flips: " << caught
            << " caught, " << harmless << " harmless, " << silent << " silently different\n";
  EXPECT_EQ(silent, 0u);
  EXPECT_GE(tried, 300u);
  EXPECT_GT(caught, tried * 9 / 10) << "most of the file is data or metadata under a checksum";
}

// probes.csv on a restart: rows after the checkpoint's step (and a row cut short by a kill)
// are dropped, new rows follow; another file's columns are refused.
TEST(Checkpoint, CsvAppendKeepsRowsUpToTheCheckpoint) {
  const fs::path f = temp_file("probes.csv");
  std::ofstream(f) << "step,value\n0,1.5\n10,2.5\n20,3.5\n30,4";  // last row cut short
  {
    io::CsvWriter w = io::CsvWriter::append(f, {"step", "value"}, 10);
    EXPECT_EQ(w.rows(), 2u);
    w.row({20, 7.25});
    w.close();
  }
  const io::CsvTable t = io::read_csv(f);
  EXPECT_EQ(t.column("step"), (std::vector<double>{0, 10, 20}));
  EXPECT_EQ(t.column("value"), (std::vector<double>{1.5, 2.5, 7.25}));
  try {
    io::CsvWriter::append(f, {"step", "other"}, 10);
    FAIL() << "a file with other columns was continued";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input);
  }
  fs::remove(f);
  io::CsvWriter fresh = io::CsvWriter::append(f, {"step"}, 0);  // no file: a new one
  fresh.row({1});
  fresh.close();
  EXPECT_EQ(io::read_csv(f).rows(), 1u);
  fs::remove(f);
}
