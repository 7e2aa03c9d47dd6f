#include <strata/scene/run.hpp>

#include <signal.h>
#include <string.h>
#include <strata/config.hpp>
#include <strata/core/clock.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>
#include <strata/scene/model_report.hpp>

#include <algorithm>
#include <cmath>

#include "cadence.hpp"
#include "checkpoint.hpp"
#include "run_output.hpp"

namespace strata::scene {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// The next chunk of steps between two looks at the observer: about 0.25 s of stepping,
/// from the `took` seconds the last `n` steps took (chunk: the last chunk's size).
std::int64_t next_chunk(std::int64_t n, double took, std::int64_t chunk) {
  return std::clamp<std::int64_t>(took > 0 ? std::int64_t(double(n) * 0.25 / took) : 2 * chunk, 1, 1 << 20);
}

/// "SIGINT" for a signal number, else "stop request N".
std::string stop_name(int reason) {
  const char* abbrev = reason > 0 && reason < NSIG ? sigabbrev_np(reason) : nullptr;
  return abbrev ? fmt::format("SIG{}", abbrev) : fmt::format("stop request {}", reason);
}
}  // namespace

struct Run::Impl {
  const Scene& sc;
  RunOptions opt;
  BuiltModel m;
  std::string fingerprint;
  std::unique_ptr<io::CheckpointReader> ckpt;
  FrameSelection selection;
  json model;
  fs::path dir;

  Impl(const Scene& scene, RunOptions options)
      : sc(scene), opt(std::move(options)), m(build_model(sc, opt.force)) {
    const OutputTable& o = sc.output;
    if (!STRATA_WITH_HDF5 && !opt.restart.empty())
      fail_missing_feature("STRATA_WITH_HDF5", "checkpoints (--restart)");
    if (!STRATA_WITH_HDF5 && o.checkpoint_every > 0)
      fail_missing_feature("STRATA_WITH_HDF5", "checkpoints (output.checkpoint_every)");
    fingerprint = scene_fingerprint(sc);
    m.take_initial_energy();  // the coupled check's start: the built state, also on a restart
    if (!opt.restart.empty()) {
      ckpt = open_checkpoint(opt.restart, fingerprint, sc);
      if (m.has_particles()) m.sim().load_state(*ckpt);
      if (m.has_network()) m.network().load_state(*ckpt, "network/");
      if (m.has_fem()) m.fem().load_state(*ckpt);
      m.coupled_last_good = m.step_count();
    }
    selection = RunOutput::selection(m, o);
    model = model_json(m, sc);
    dir = opt.output.empty() ? o.directory.value : opt.output;
  }

  RunResult execute(RunObserver& observer);
};

Run::Run(const Scene& sc, RunOptions opt) : impl_(std::make_unique<Impl>(sc, std::move(opt))) {}
Run::~Run() = default;
const BuiltModel& Run::model() const { return impl_->m; }
BuiltModel& Run::model() { return impl_->m; }
const json& Run::model_summary() const { return impl_->model; }
const fs::path& Run::directory() const { return impl_->dir; }
RunResult Run::execute(RunObserver& observer) { return impl_->execute(observer); }

RunResult Run::Impl::execute(RunObserver& observer) {
  observer.model_ready(model);
  const OutputTable& o = sc.output;
  fs::create_directories(dir);
  RunOutput out(dir, sc, m, ckpt.get());
  out.set_selection(std::move(selection));

  RunResult result;
  result.directory = dir;
  // The loop counts in units of q steps of dt: whole system steps of a coupled model.
  const std::int64_t q = m.coupled() ? m.eta : 1;
  const std::int64_t steps = m.steps / q;
  const std::int64_t first = m.step_count() / q;  // 0, or the checkpoint's step
  const Cadence cad(o, steps, m.dt * double(q), q);
  auto broken = [&] { return m.has_particles() ? m.sim().broken_count() : std::size_t(0); };
  std::int64_t frame_breaks = 0;  // broken bonds at the last frame (output.frame_every_breaks)
  double wall_before = 0;         // run time before the restart
  if (ckpt) {
    frame_breaks = ckpt->get_scalar<std::int64_t>("driver/frame_breaks");
    wall_before = ckpt->get_scalar<double>("driver/wall_seconds");
    observer.restarted(first * q, m.time(), opt.restart);
    ckpt.reset();
    if (first >= steps)
      log::warn("the checkpoint is at step {}, solver.steps = {}: nothing left to run (raise solver.steps)",
                first, steps);
  }

  const auto t0 = WallClock::now();
  log::Phases ph("run");     // strata -v: the time and memory of the steps and of the checkpoint
  std::int64_t settled = 0;  // settling steps of this execution (in the step rate)
  auto finish_result = [&] {
    result.first_step = first * q;
    result.step = m.step_count();
    result.time = m.time();
    result.wall_seconds = seconds_since(t0);
    const double n = m.has_particles() ? double(m.sim().particle_count()) : 0.0;
    result.particle_steps_per_s =
        result.wall_seconds > 0 ? n * double(result.step - result.first_step + settled) / result.wall_seconds
                                : 0.0;
    result.last_frame = out.last_frame();
    result.written = out.written();
    result.summary = out.summary();
    return result;
  };
  if (m.settle_steps > 0 && opt.restart.empty()) {
    // The settling stage, in chunks of about 0.25 s so that a stop request is seen soon.
    std::int64_t chunk = 4;
    observer.settling(0, m.settle_steps);
    while (settled < m.settle_steps) {
      if (const int reason = observer.stop_requested()) {
        out.finish(m, model, seconds_since(t0),
                   fmt::format("interrupted by {} while settling, at step {} of {}", stop_name(reason),
                               settled, m.settle_steps));
        result.status = RunStatus::Interrupted;
        result.stop_reason = reason;
        return finish_result();
      }
      const std::int64_t n = std::min(chunk, m.settle_steps - settled);
      const auto c0 = WallClock::now();
      m.sim().settle(n);
      settled += n;
      const double took = seconds_since(c0);
      chunk = next_chunk(n, took, chunk);
      observer.settling(settled, m.settle_steps);
    }
    log::info("settled for {} steps ({:.4g} s); the run starts from the settled state", m.settle_steps,
              double(m.settle_steps) * m.dt);
  }
  observer.started(first * q, steps * q, dir);
  auto wall = [&] { return wall_before + seconds_since(t0); };
  const double stop_after_peak = sc.probe.stop_after_peak;
  std::int64_t max_chunk = 4;  // steps per run() call, adapted to ~0.25 s so signals are seen soon
  try {
    for (;;) {
      const std::int64_t s = m.step_count() / q;
      // outputs of step s (a restart's first step had them before its checkpoint was taken)
      if (!(first > 0 && s == first)) {
        if (cad.probe_due(s)) out.probe(m);
        if (cad.frame_due(s, broken(), std::size_t(frame_breaks))) {
          out.frame(m);
          frame_breaks = std::int64_t(broken());
        }
      }
      if (s >= steps) break;
      if (stop_after_peak > 0 && out.specimen_failed(m, stop_after_peak)) {
        // The specimen has failed: the last frame and the summary say where, as at the end.
        if (out.last_frame_step() != s * q) out.frame(m);
        out.stopped_after_peak(s * q);
        break;
      }
      if (const int reason = observer.stop_requested()) {
        // Interrupted: the current frame, a checkpoint, what is known so far; then stop.
        if (out.last_frame_step() != s * q) {
          out.frame(m);
          frame_breaks = std::int64_t(broken());
        }
        fs::path ck;
        if (STRATA_WITH_HDF5) ck = write_checkpoint(dir, m, fingerprint, out, frame_breaks, wall());
        out.finish(m, model, seconds_since(t0),
                   fmt::format("interrupted by {} at step {}", stop_name(reason), s * q));
        result.status = RunStatus::Interrupted;
        result.stop_reason = reason;
        result.checkpoint = ck;
        return finish_result();
      }
      if (cad.checkpoint_due(s) && s != first)
        write_checkpoint(dir, m, fingerprint, out, frame_breaks, wall());
      const std::int64_t to =
          std::min({cad.next_probe(s), cad.next_frame(s), cad.next_checkpoint(s), steps, s + max_chunk});
      const auto c0 = WallClock::now();
      m.advance((to - s) * q);
      const double took = seconds_since(c0);
      if (to - s == max_chunk || took > 0.25) max_chunk = next_chunk(to - s, took, max_chunk);
      observer.progress(m.step_count(), steps * q);
    }
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Numerical) throw;
    // Frames after the last passed health check may already hold the blow-up: drop them.
    const std::int64_t good = m.last_good_step();
    const fs::path last = out.keep_frames_until((double(good) + 0.5) * m.dt);
    out.finish(m, model, seconds_since(t0), fmt::format("failed: {}", e.what()));
    const std::string kept = last.empty() ? std::string("no good frame had been written")
                                          : fmt::format(
                                                "last good frame kept: {} (the state at step {} passed "
                                                "the health check)",
                                                last.string(), good);
    fail(ErrorKind::Numerical, "{}\nrun stopped; {}; probes up to the failure in {}", e.what(), kept,
         (dir / "probes.csv").string());
  }
  const double run_seconds = seconds_since(t0);
  ph.lap("steps, probes and frames");
  // A checkpoint at the end lets a later `--restart` (with more steps) continue the run.
  if (STRATA_WITH_HDF5 && opt.final_checkpoint) {
    result.checkpoint = write_checkpoint(dir, m, fingerprint, out, frame_breaks, wall());
    out.add_written(result.checkpoint);
    ph.lap("checkpoint written");
  }
  out.finish(m, model, run_seconds, "completed");
  RunResult r = finish_result();
  r.step_seconds = run_seconds;
  observer.stepped(r);
  if (const int reason = out.pictures(sc, [&] { return observer.stop_requested(); })) {
    // Every step and file is there; only pictures are missing (`strata render` draws them).
    r.status = RunStatus::PicturesInterrupted;
    r.stop_reason = reason;
  }
  r.written = out.written();
  return r;
}

}  // namespace strata::scene
