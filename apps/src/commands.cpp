// The scene commands of `strata` (run, check, mesh): load the scene, call the scene library,
// print. The library builds, runs and writes; this file only shows it.
#include "commands.hpp"

#include "calibrate_cmd.hpp"
#include "stop_signals.hpp"

#include <string.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <strata/cases/chain_report.hpp>
#include <strata/cases/study.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>
#include <strata/core/progress.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/scene/model.hpp>
#include <strata/scene/model_report.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <cstdio>
#include <optional>

namespace strata::app {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

/// Loads the scene and sets the process's thread count: --threads, else the scene's.
scene::Scene load_scene(const SceneOptions& opt) {
  scene::Scene sc = scene::load(opt.scene, opt.overrides);
  // A coupled case's threads default per case; a region scene's is [solver]'s.
  const int threads = opt.threads >= 0 ? opt.threads
                      : sc.coupled     ? cases::coupled_threads(sc)
                                       : int(sc.solver.threads);
  par::set_threads(threads);
  return sc;
}

void print_model(const json& j) {
  std::printf("scene        %s\n", j["scene"].get<std::string>().c_str());
  if (!j["title"].get<std::string>().empty())
    std::printf("title        %s\n", j["title"].get<std::string>().c_str());
  std::printf("dimension    %dD\n", j["dimension"].get<int>());
  for (const auto& r : j["regions"])
    std::printf("region       %-14s %s lattice, d = %g m: %zu particles, packing density %.4f\n",
                r["name"].get<std::string>().c_str(), r["lattice"].get<std::string>().c_str(),
                r["diameter_m"].get<double>(), r["particles"].get<std::size_t>(),
                r["packing_density"].get<double>());
  for (const auto& r : j["regions"]) {
    if (!r.contains("lattice_elastic")) continue;
    const json& e = r["lattice_elastic"];
    const char* of = e["regular_lattice"].get<bool>() ? "" : " (of the regular lattice: the offsets lower E)";
    auto text = [](const json& c, const char* unit) {
      return fmt::format("E = {:.4g} {}, nu = {:.4g}", c["youngs_modulus"].get<double>(), unit,
                         c["poisson_ratio"].get<double>());
    };
    if (e.contains("isotropic")) {
      std::printf("elastic      %-14s %s (per unit thickness, isotropic)%s\n",
                  r["name"].get<std::string>().c_str(), text(e["isotropic"], "N/m").c_str(), of);
    } else {
      std::printf("elastic      %-14s along z %s; isotropic average %s%s\n",
                  r["name"].get<std::string>().c_str(), text(e["along_z"], "Pa").c_str(),
                  text(e["isotropic_average"], "Pa").c_str(), of);
      if (e.contains("along_cube_axis"))
        std::printf("elastic      %-14s along a cube axis [100] %s\n", r["name"].get<std::string>().c_str(),
                    text(e["along_cube_axis"], "Pa").c_str());
    }
  }
  for (const auto& r : j["regions"])
    if (r.contains("eccentric"))
      std::printf("eccentric    %-14s %zu bonds, %zu weakened (longer than Rc x L_max), L_max = %.4g m\n",
                  r["name"].get<std::string>().c_str(), r["eccentric"]["bonds"].get<std::size_t>(),
                  r["eccentric"]["weakened_bonds"].get<std::size_t>(),
                  r["eccentric"]["l_max_m"].get<double>());
  for (const auto& [name, n] : j["groups"].items())
    std::printf("group        %-14s %zu particles\n", name.c_str(), n.get<std::size_t>());
  std::printf("particles    %zu\nbonds        %zu\nFEM          %zu nodes, %zu elements\n",
              j["particles"].get<std::size_t>(), j["bonds"].get<std::size_t>(),
              j["fem_nodes"].get<std::size_t>(), j["fem_elements"].get<std::size_t>());
  if (!j.contains("fem_integrator"))  // `strata mesh`: FEM regions as meshed
    for (const auto& f : j.value("fem_regions", json::array()))
      std::printf("FEM region   %-14s %zu nodes, %zu elements\n", f["name"].get<std::string>().c_str(),
                  f["nodes"].get<std::size_t>(), f["elements"].get<std::size_t>());
  if (j.contains("fem_integrator")) {
    for (const auto& f : j["fem_regions"])
      std::printf("FEM region   %-14s %zu elements, E = %.4g Pa, nu = %.4g, rho = %.4g kg/m^3\n",
                  f["name"].get<std::string>().c_str(), f["elements"].get<std::size_t>(),
                  f["youngs_modulus_pa"].get<double>(), f["poisson_ratio"].get<double>(),
                  f["density_kg_m3"].get<double>());
    for (const auto& [name, n] : j["fem_groups"].items())
      std::printf("FEM group    %-14s %zu nodes\n", name.c_str(), n.get<std::size_t>());
    std::printf("FEM          %s, dt = %.4g s, explicit limit %.4g s\n",
                j["fem_integrator"].get<std::string>().c_str(), j["fem_dt_s"].get<double>(),
                j["fem_explicit_dt_crit_s"].get<double>());
  }
  if (j.contains("network"))
    std::printf(
        "network      %zu nodes, %zu springs, %zu wall springs, %zu loads; FEM part %zu nodes, "
        "particle part %zu nodes\n",
        j["network"]["nodes"].get<std::size_t>(), j["network"]["springs"].get<std::size_t>(),
        j["network"]["walls"].get<std::size_t>(), j["network"]["loads"].get<std::size_t>(),
        j["network"]["fem_nodes"].get<std::size_t>(), j["network"]["particle_nodes"].get<std::size_t>());
  if (j.contains("eta"))
    std::printf("coupling     eta = %d (%s), overlap: %zu external particles, %zu external FEM nodes\n",
                j["eta"].get<int>(), j["coupling"].get<std::string>().c_str(),
                j["overlap_external_particles"].get<std::size_t>(),
                j["overlap_external_nodes"].get<std::size_t>());
  if (!j.contains("dt_s")) return;  // `strata mesh`: no DEM model built
  std::printf("memory       %.1f MB (model arrays)\n", j["memory_bytes"].get<double>() / 1e6);
  std::printf("dt_crit      %.4g s\n", j["dt_crit_s"].get<double>());
  std::printf("dt           %.4g s%s  (dt/dt_crit = %.3f)\n", j["dt_s"].get<double>(),
              j["dt_automatic"].get<bool>() ? " (automatic)" : "", j["dt_over_dt_crit"].get<double>());
  std::printf("steps        %lld (%.4g s simulated)\n", (long long)j["steps"].get<std::int64_t>(),
              j["simulated_time_s"].get<double>());
}

/// Shows a run on the terminal: the restart, a progress line, the end; stops on SIGINT or
/// SIGTERM.
class TerminalObserver final : public scene::RunObserver {
 public:
  void restarted(std::int64_t step, double time, const fs::path& checkpoint) override {
    std::printf("restart      step %lld (t = %.6g s) of %s\n", (long long)step, time,
                checkpoint.string().c_str());
  }
  void settling(std::int64_t step, std::int64_t steps) override {
    if (step == 0) settle_.emplace("settle", steps);
    settle_->update(step);
    if (step == steps) settle_->finish(step);
  }
  void started(std::int64_t first, std::int64_t steps, const fs::path& dir) override {
    log::info("running {} steps on {} thread(s); output in {}", steps - std::min(first, steps),
              par::threads(), dir.string());
    progress_.emplace("run", steps);
  }
  void progress(std::int64_t step, std::int64_t) override { progress_->update(step); }
  int stop_requested() override { return StopSignals::received(); }
  void stepped(const scene::RunResult& r) override { progress_->finish(r.step); }

 private:
  std::optional<Progress> progress_, settle_;
};

/// Shows a study on the terminal: one progress line over its runs; stops on SIGINT or SIGTERM.
class StudyTerminal final : public cases::StudyObserver {
 public:
  void started(std::size_t runs) override { progress_.emplace("study", std::int64_t(runs), "runs", 2.0); }
  void done(std::size_t run, const cases::StudyPoint& p) override {
    if (p.status != "completed") log::warn("run {}: {}", run + 1, p.status);
    progress_->update(std::int64_t(run + 1));
  }
  int stop_requested() override { return StopSignals::received(); }

 private:
  std::optional<Progress> progress_;
};

}  // namespace

int check_scene(const SceneOptions& opt, bool json_out) {
  const scene::Scene sc = load_scene(opt);
  if (sc.coupled) return cases::check_coupled_scene(scene::require_build_parts(sc), json_out, opt.force);
  if (sc.study) {
    STRATA_CHECK(!json_out, Input, "--json: {} is a study ([study]); its check prints text",
                 sc.file.string());
    return cases::check_study_scene(sc);
  }
  if (sc.calibrate) {
    STRATA_CHECK(!json_out, Input, "--json: {} is a calibration ([calibrate]); its check prints text",
                 sc.file.string());
    return check_calibration(sc);
  }
  const scene::BuiltModel m = scene::build_model(sc, opt.force);
  const json j = scene::model_json(m, sc);
  if (json_out)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_model(j);
  return 0;
}

int mesh_scene(const SceneOptions& opt, bool json_out) {
  const scene::Scene sc = load_scene(opt);
  STRATA_CHECK(!sc.coupled, Input,
               "{}: a coupled-chain scene ([coupled]) has no mesh to build; use 'strata check' for its "
               "stability numbers or 'strata run' for the sweep",
               sc.file.string());
  STRATA_CHECK(
      !sc.calibrate, Input,
      "{}: a calibration ([calibrate]) builds its own specimens; use 'strata calibrate' (or 'strata run')",
      sc.file.string());
  STRATA_CHECK(!sc.study, Input, "{}: a study ([study]) runs the scene it names; mesh that scene instead",
               sc.file.string());
  const json j = scene::mesh_report(sc, opt.output);
  if (json_out) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    print_model(j);
    if (j.contains("bond_length_classes")) {
      std::printf("bond lengths (length/d: bonds)");
      for (const auto& [cls, n] : j["bond_length_classes"].items())
        std::printf("  %s: %zu", cls.c_str(), n.get<std::size_t>());
      std::printf("\n");
    }
    std::printf("built in     %.3f s (%.3g particles/s), peak memory %.1f MB\n", j["seconds"].get<double>(),
                j["particles_per_s"].get<double>(), j["peak_rss_bytes"].get<double>() / 1e6);
    std::printf("DEM          dt_crit and model memory: see 'strata check' (it builds the DEM model)\n");
    if (j.contains("written_particles") && j["written_particles"]["selection"] != "all")
      std::printf("particles    %zu > %zu: wrote %s particles only (%zu)\n",
                  j["particles"].get<std::size_t>(), scene::kMaxWrittenParticles,
                  j["written_particles"]["selection"].get<std::string>().c_str(),
                  j["written_particles"]["count"].get<std::size_t>());
    if (j.contains("written"))
      for (const auto& w : j["written"]) std::printf("wrote        %s\n", w.get<std::string>().c_str());
  }
  return 0;
}

int calibrate_scene(const SceneOptions& opt) {
  const scene::Scene sc = load_scene(opt);
  return calibrate_cmd(sc, opt.output);
}

int run_scene(const SceneOptions& opt) {
  // Validate and build everything, and check a checkpoint to restart from, before the first
  // byte is written.
  const scene::Scene sc = load_scene(opt);
  if (sc.coupled) {  // the coupled cases: checks, the sweep, then its files all at once
    STRATA_CHECK(opt.restart.empty(), Input,
                 "--restart: {} is a coupled-chain scene ([coupled]); its sweep has no checkpoints",
                 sc.file.string());
    return cases::run_coupled_scene(scene::require_build_parts(sc), opt.output, opt.force, opt.threads);
  }
  if (sc.study) {  // its runs, then its tables and plots, all at once
    STRATA_CHECK(opt.restart.empty(), Input, "--restart: {} is a study ([study]); it has no checkpoints",
                 sc.file.string());
    StudyTerminal observer;
    const StopSignals stop;
    return cases::run_study_scene(sc, opt.output, observer);
  }
  if (sc.calibrate) {  // a calibration: its specimen runs, then its table
    STRATA_CHECK(opt.restart.empty(), Input,
                 "--restart: {} is a calibration ([calibrate]); it has no checkpoints", sc.file.string());
    return calibrate_cmd(sc, opt.output);
  }
  scene::Run run(sc, {opt.output, opt.force, opt.restart, !opt.no_checkpoint});
  print_model(run.model_summary());
  TerminalObserver observer;
  const StopSignals stop;
  const scene::RunResult r = run.execute(observer);
  const scene::BuiltModel& m = run.model();
  if (r.status == scene::RunStatus::Interrupted) {
    const int sig = r.stop_reason;
    std::printf("interrupted by SIG%s at step %lld (t = %.6g s)\n", sigabbrev_np(sig), (long long)r.step,
                r.time);
    if (!r.last_frame.empty()) std::printf("  last frame  %s\n", r.last_frame.string().c_str());
    if (!r.checkpoint.empty())
      std::printf("  checkpoint  %s\n  continue with: strata run %s -o %s --restart %s\n",
                  r.checkpoint.string().c_str(), sc.file.string().c_str(), r.directory.string().c_str(),
                  r.checkpoint.string().c_str());
    std::fflush(stdout);
    return 128 + sig;
  }
  if (r.status == scene::RunStatus::PicturesInterrupted) {
    std::printf(
        "run completed (%lld steps, every file written); drawing the pictures was interrupted by SIG%s:\n"
        "  the pictures drawn so far are in %s; draw them all with: strata render %s\n",
        (long long)r.step, sigabbrev_np(r.stop_reason), (r.directory / "png").string().c_str(),
        (r.directory / (m.has_particles() ? "particles.pvd" : "fem.pvd")).string().c_str());
    std::fflush(stdout);
    return 128 + r.stop_reason;
  }
  if (m.has_particles())
    log::info("{} steps in {} ({:.3g} particle-steps/s); {} bonds broken ({} tension, {} shear)",
              r.step - r.first_step, format_duration(r.wall_seconds), r.particle_steps_per_s,
              m.sim().broken_count(), m.sim().broken_count(dem::BreakMode::Tension),
              m.sim().broken_count(dem::BreakMode::Shear));
  else
    log::info("{} steps in {}", r.step - r.first_step, format_duration(r.wall_seconds));
  std::printf("wrote:\n");
  for (const auto& p : r.written) std::printf("  %s\n", p.string().c_str());
  return 0;
}

}  // namespace strata::app
