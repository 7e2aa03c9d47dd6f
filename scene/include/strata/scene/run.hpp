#pragma once
/// One run of a scene: scene → model → time loop → outputs.
///
/// `Run` builds and checks the model (and a checkpoint to continue from) in its constructor,
/// before anything is written, so a bad scene or checkpoint leaves no file behind. execute()
/// steps the model to the end, writing probes, frames, checkpoints, the summary and pictures
/// at their cadence, and reports progress to a `RunObserver`. The library prints nothing,
/// sets no global thread count and never exits: it throws strata::Error, and the command
/// maps errors to exit codes.
#include <strata/scene/model.hpp>
#include <strata/scene/scene.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace strata::scene {

/// What a run was asked to do beyond its scene.
struct RunOptions {
  std::filesystem::path output;   ///< empty: the scene's output.directory
  bool force = false;             ///< run even when dt > dt_crit
  std::filesystem::path restart;  ///< a checkpoint to continue from (empty: a fresh run)
  /// Write a checkpoint at the end of a completed run (for a later `--restart` with more
  /// steps); a study of many runs that keeps only their summaries turns it off.
  bool final_checkpoint = true;
};

/// How a run ended.
enum class RunStatus {
  Completed,    ///< every step done, every output written
  Interrupted,  ///< stopped on request (RunObserver::stop_requested) with a checkpoint
  /// Every step done and every file written, but drawing the pictures stopped on request:
  /// the pictures drawn so far are kept (`strata render` draws the rest).
  PicturesInterrupted,
};

/// What a run wrote and where it stopped.
struct RunResult {
  RunStatus status = RunStatus::Completed;
  int stop_reason = 0;  ///< the observer's non-zero stop request (a signal number)
  std::int64_t first_step = 0, step = 0;
  double time = 0;
  double wall_seconds = 0;  ///< the whole run: stepping, outputs, the final checkpoint
  double step_seconds = 0;  ///< the time loop only (steps, probes, frames), as timed comparisons use
  double particle_steps_per_s = 0;
  std::filesystem::path directory;
  std::filesystem::path last_frame;  ///< empty: no frame written
  std::filesystem::path checkpoint;  ///< empty: none written (no HDF5, or not due)
  std::vector<std::filesystem::path> written;
  nlohmann::json summary;  ///< what summary.json holds
};

/// Progress and events of a run. Every function has a default that does nothing, so an
/// observer overrides only what it shows.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  /// The model is built and checked; `model` is the model part of summary.json.
  virtual void model_ready(const nlohmann::json& model) { (void)model; }
  /// A restart continues from `step` (time `time`) of `checkpoint`.
  virtual void restarted(std::int64_t step, double time, const std::filesystem::path& checkpoint) {
    (void)step, (void)time, (void)checkpoint;
  }
  /// The settling stage ([solver] settle) has done `step` of its `steps`; called before it
  /// starts and between its chunks.
  virtual void settling(std::int64_t step, std::int64_t steps) { (void)step, (void)steps; }
  /// The time loop starts at `first` of `steps`, writing into `dir`.
  virtual void started(std::int64_t first, std::int64_t steps, const std::filesystem::path& dir) {
    (void)first, (void)steps, (void)dir;
  }
  /// Called between chunks of steps (a few times per second at most).
  virtual void progress(std::int64_t step, std::int64_t steps) { (void)step, (void)steps; }
  /// Polled between chunks of steps: non-zero stops the run after writing the current frame,
  /// a checkpoint and the summary; the value comes back as RunResult::stop_reason.
  virtual int stop_requested() { return 0; }
  /// The run has ended (completed or interrupted); pictures are not drawn yet.
  virtual void stepped(const RunResult& r) { (void)r; }
};

class Run {
 public:
  /// Builds and checks the model; opens and checks `opt.restart`. Throws strata::Error
  /// (Input) for a scene that cannot run (dt above dt_crit without `force`, a checkpoint of
  /// another scene, ...). Nothing is written. The run keeps a reference to `sc`, which must
  /// outlive it (a temporary scene is refused at compile time).
  Run(const Scene& sc, RunOptions opt);
  Run(Scene&&, RunOptions) = delete;
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  const BuiltModel& model() const;
  /// The model, for an analysis that watches it while it runs (e.g. gauges read every step
  /// through the coupler's observers, BuiltModel::coupler()). Changing its state makes the
  /// run's outputs wrong.
  BuiltModel& model();
  /// The model part of summary.json (model_json).
  const nlohmann::json& model_summary() const;
  /// The output folder this run writes into.
  const std::filesystem::path& directory() const;

  /// Steps the model to solver.steps and writes the outputs. On a numerical blow-up it keeps
  /// the frames up to the last state that passed the health check, writes the summary
  /// ("failed: ...") and the probes, and throws strata::Error (Numerical) naming them.
  RunResult execute(RunObserver& observer);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace strata::scene
