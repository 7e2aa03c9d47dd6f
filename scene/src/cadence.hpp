#pragma once
// Internal: when a run's probes, frames and checkpoints are due.
#include <strata/scene/scene.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace strata::scene {

// ---- output cadences -----------------------------------------------------------------------

/// When probes, frames and checkpoints are due: pure functions of the step (and, for
/// frame_every_breaks, of the break count at the last frame), so a restart continues them.
struct Cadence {
  enum class Frames { None, Steps, Time, Breaks };
  std::int64_t steps = 0;
  std::int64_t probe_every = 1;
  Frames frames = Frames::None;
  std::int64_t frame_every = 0;   // Steps
  double frame_time = 0, dt = 0;  // Time
  std::int64_t frame_breaks = 0;  // Breaks
  std::int64_t checkpoint_every = 0;

  /// Steps are counted in units of `quantum` steps of the scene's dt (a coupled model's
  /// system steps); the [output] step counts are rounded up to whole units.
  Cadence(const OutputTable& o, std::int64_t total_steps, double time_step, std::int64_t quantum = 1)
      : steps(total_steps), dt(time_step) {
    auto units = [quantum](std::int64_t n) { return (n + quantum - 1) / quantum; };
    probe_every = o.probe_every > 0 ? units(o.probe_every) : std::max<std::int64_t>(1, steps / 1000);
    checkpoint_every = units(o.checkpoint_every);
    if (o.frame_every_breaks > 0) {
      frames = Frames::Breaks;
      frame_breaks = o.frame_every_breaks;
    } else if (o.frame_every_time > 0) {
      frames = Frames::Time;
      frame_time = o.frame_every_time;
    } else if (o.frames > 0) {
      frames = Frames::Steps;
      frame_every = std::max<std::int64_t>(1, steps / o.frames.value);
    }
  }

  /// Smallest step > s that is a multiple of `every`, or the last step.
  std::int64_t next_multiple(std::int64_t s, std::int64_t every) const {
    return std::min(steps, (s / every + 1) * every);
  }
  /// Step of the k-th frame of Frames::Time (the step nearest to k·frame_time).
  std::int64_t time_frame_step(std::int64_t k) const { return std::llround(double(k) * frame_time / dt); }

  bool probe_due(std::int64_t s) const { return s % probe_every == 0 || s == steps; }
  std::int64_t next_probe(std::int64_t s) const { return next_multiple(s, probe_every); }

  bool frame_due(std::int64_t s, std::size_t broken, std::size_t broken_at_last_frame) const {
    switch (frames) {
      case Frames::None:
        return false;
      case Frames::Steps:
        return s % frame_every == 0 || s == steps;
      case Frames::Time: {
        if (s == 0 || s == steps) return true;
        const auto k = std::int64_t(double(s) * dt / frame_time);
        return time_frame_step(k) == s || time_frame_step(k + 1) == s;
      }
      case Frames::Breaks:
        return s == 0 || s == steps ||
               (probe_due(s) && broken >= broken_at_last_frame + std::size_t(frame_breaks));
    }
    return false;
  }
  std::int64_t next_frame(std::int64_t s) const {
    switch (frames) {
      case Frames::Steps:
        return next_multiple(s, frame_every);
      case Frames::Time: {
        auto k = std::int64_t(double(s) * dt / frame_time);
        while (time_frame_step(k) <= s) ++k;
        return std::min(steps, time_frame_step(k));
      }
      default:
        return steps;  // Breaks: checked at probe rows
    }
  }
  bool checkpoint_due(std::int64_t s) const {
    return checkpoint_every > 0 && s > 0 && s % checkpoint_every == 0;
  }
  std::int64_t next_checkpoint(std::int64_t s) const {
    return checkpoint_every > 0 ? next_multiple(s, checkpoint_every) : steps;
  }
};

}  // namespace strata::scene
