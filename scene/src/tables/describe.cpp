// The validated tables read into the typed scene, each by the read function of its table's
// file, and the scene's fingerprint.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <fstream>
#include <iterator>

#include "table_file.hpp"

namespace strata::scene {
namespace tables {

Reader::Reader(const Table& t, std::string_view table)
    : t_(t), spec_([&]() -> const TableSpec& {
        for (const TableSpec& s : schema())
          if (s.name == table) return s;
        fail(ErrorKind::Internal, "scene: no table [{}] is declared", table);
      }()) {}

void Reader::done() const {
  for (const KeySpec& k : spec_.keys)
    if (std::count(read_.begin(), read_.end(), k.name) != 1)
      fail(ErrorKind::Internal, "scene: [{}] key '{}' is read {} times into its struct (once expected)",
           spec_.name, k.name, std::count(read_.begin(), read_.end(), k.name));
  if (read_.size() != spec_.keys.size())
    fail(ErrorKind::Internal, "scene: [{}] reads a key it does not declare", spec_.name);
}

namespace {
template <class S>
std::vector<S> read_all(const Tables& t, const std::string& name, S (*read)(const Table&)) {
  std::vector<S> out;
  for (const Table& e : t.tables(name)) out.push_back(read(e));
  return out;
}
}  // namespace

}  // namespace tables

void describe(const Tables& t, Scene& sc) {
  using namespace tables;
  sc.scene = read_scene(t.table("scene"));
  sc.solver = read_solver(t.table("solver"));
  sc.output = read_output(t.table("output"));
  sc.probe = read_probe(t.table("probe"));
  sc.materials = read_all(t, "material", read_material);
  sc.regions = read_all(t, "region", read_region);
  sc.groups = read_all(t, "group", read_group);
  sc.boundaries = read_all(t, "boundary", read_boundary);
  sc.loads = read_all(t, "load", read_load);
  sc.walls = read_all(t, "wall", read_wall);
  if (t.coupled()) sc.coupled = read_coupled(t.table("coupled"));
  if (t.calibration()) sc.calibrate = read_calibrate(t.table("calibrate"));
  if (t.network()) sc.network = read_network(t.table("network"));
  if (t.study()) sc.study = read_study(t.table("study"));
  sc.vary = read_all(t, "vary", read_vary);
  sc.measures = read_all(t, "measure", read_measure);
  sc.fingerprint = fingerprint_of(t);
}

std::string fingerprint_of(const Tables& tables) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::string_view text) {
    for (const unsigned char c : text) {
      h ^= c;
      h *= 1099511628211ull;
    }
    h ^= 0xff;  // separator
    h *= 1099511628211ull;
  };
  for (const TableSpec& spec : schema()) {
    if (spec.name == "output") continue;
    const std::vector<Table>& list = tables.tables(spec.name);  // [coupled] of a particle scene: none
    for (const Table& t : list) {
      mix(t.label());
      for (const KeySpec& k : spec.keys) {
        // Keys that set how far a run goes (steps, duration) or how its work is shared (threads,
        // min_particles_per_thread, lattice slots, serial or parallel coupling: the same bits by design): a
        // checkpoint continues under other values.
        if (spec.name == "solver" &&
            (k.name == "steps" || k.name == "duration" || k.name == "threads" ||
             k.name == "min_particles_per_thread" || k.name == "lattice_slots" || k.name == "coupling"))
          continue;
        mix(k.name);
        if (!t.has(k.name)) {
          mix("<none>");
          continue;
        }
        using T = Type;
        switch (k.type) {
          case T::Bool:
            mix(t.boolean(k.name) ? "true" : "false");
            break;
          case T::Integer:
            mix(fmt::format("{}", t.integer(k.name)));
            break;
          case T::Real:
            mix(fmt::format("{}", t.real(k.name)));
            break;
          case T::String:
          case T::Choice:
          case T::OutputPath:
            mix(t.str(k.name));
            break;
          case T::Path: {  // contents, so that a moved scene folder keeps its fingerprint
            std::ifstream f(t.str(k.name), std::ios::binary);
            mix(std::string(std::istreambuf_iterator<char>(f), {}));
            break;
          }
          case T::RealList:
            mix(fmt::format("{}", fmt::join(t.reals(k.name), ",")));
            break;
          case T::IntegerList:
            mix(fmt::format("{}", fmt::join(t.integers(k.name), ",")));
            break;
          case T::StringList:
            mix(fmt::format("{}", fmt::join(t.strings(k.name), ",")));
            break;
          case T::RealTable:
            for (const auto& row : t.real_table(k.name)) mix(fmt::format("{}", fmt::join(row, ",")));
            break;
        }
      }
    }
  }
  return fmt::format("{:016x}", h);
}

}  // namespace strata::scene
