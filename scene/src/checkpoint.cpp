#include "checkpoint.hpp"

#include <fmt/format.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>

namespace strata::scene {

namespace fs = std::filesystem;

std::string scene_fingerprint(const Scene& sc) { return sc.fingerprint; }

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
  if (m.has_network()) m.network().save_state(w, "network/");
  if (m.has_fem()) m.fem().save_state(w);
  out.save(w);
  w.put_scalar<std::int64_t>("driver/frame_breaks", frame_breaks);
  w.put_scalar<double>("driver/wall_seconds", wall_seconds);
  w.commit();
  log::debug("checkpoint at step {} written to {}", m.step_count(), file.string());
  return file;
}

}  // namespace strata::scene
