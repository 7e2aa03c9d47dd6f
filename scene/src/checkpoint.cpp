#include "checkpoint.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>

#include <fstream>
#include <iterator>

namespace strata::scene {

namespace fs = std::filesystem;

std::string scene_fingerprint(const Scene& sc) {
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
    const std::vector<Table>* list = &sc.tables(spec.name);
    std::vector<Table> plain;
    if (!spec.array && sc.tables(spec.name).empty()) continue;  // [coupled] of a particle scene
    if (!spec.array) plain.push_back(sc.table(spec.name)), list = &plain;
    for (const Table& t : *list) {
      mix(t.label());
      for (const KeySpec& k : spec.keys) {
        if (spec.name == "solver" && (k.name == "steps" || k.name == "duration" || k.name == "threads"))
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

std::unique_ptr<io::CheckpointReader> open_checkpoint(const fs::path& file, const std::string& fingerprint,
                                                      const Scene& sc) {
  std::unique_ptr<io::CheckpointReader> r;
  try {
    r = std::make_unique<io::CheckpointReader>(file);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::IO) throw;
    fail(ErrorKind::Input, "--restart: {}", e.what());
  }
  const io::CheckpointInfo& info = r->info();
  STRATA_CHECK(info.version == STRATA_VERSION, Input,
               "--restart: checkpoint {} was written by strata {}, this is strata {}; checkpoints are read "
               "only by the version that wrote them",
               file.string(), info.version, STRATA_VERSION);
  STRATA_CHECK(info.fingerprint == fingerprint, Input,
               "--restart: checkpoint {} belongs to another scene: its scene fingerprint is {}, {} (with its "
               "--set options) has {}. Only [output], solver.steps, solver.duration and solver.threads may "
               "change between a run and its restart",
               file.string(), info.fingerprint, sc.file.string(), fingerprint);
  return r;
}

fs::path write_checkpoint(const fs::path& dir, const BuiltModel& m, const std::string& fingerprint,
                          const RunOutput& out, std::int64_t frame_breaks, double wall_seconds) {
  const fs::path file = dir / "checkpoint.h5";
  const std::size_t particles = m.has_particles() ? m.sim().particle_count() : 0;
  io::CheckpointWriter w(file, {STRATA_VERSION, fingerprint, m.dim, particles, m.step_count(), m.time()});
  if (m.has_particles()) m.sim().save_state(w);
  if (m.has_fem()) m.fem().save_state(w);
  out.save(w);
  w.put_scalar<std::int64_t>("driver/frame_breaks", frame_breaks);
  w.put_scalar<double>("driver/wall_seconds", wall_seconds);
  w.commit();
  log::debug("checkpoint at step {} written to {}", m.step_count(), file.string());
  return file;
}

}  // namespace strata::scene
