#include "calibrate_cmd.hpp"

#include <string.h>
#include <strata/cases/calibrate.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/progress.hpp>

#include <cstdio>
#include <optional>

#include "stop_signals.hpp"

namespace strata::app {

namespace {

/// A progress line per specimen run, then its numbers; stops on SIGINT or SIGTERM.
class CalibrateTerminal final : public cases::CalibrateObserver {
 public:
  void begin(const std::string& label) override { label_ = label; }
  void started(std::int64_t first, std::int64_t steps, const std::filesystem::path&) override {
    progress_.emplace(label_, steps - std::min(first, steps));
  }
  void progress(std::int64_t step, std::int64_t) override { progress_->update(step); }
  int stop_requested() override { return StopSignals::received(); }
  void stepped(const scene::RunResult& r) override { progress_->finish(r.step); }
  void end(const cases::CalibrationRun& r) override {
    if (r.stage == "elastic")
      log::info("{}: E = {:.4g} GPa, nu = {:.4f} ({} steps, {})", label_, r.youngs_modulus / 1e9,
                r.poisson_ratio, r.steps, format_duration(r.seconds));
    else
      log::info("{}: Fs0/Fn_max = {:.3g}, {} = {:.4g} MPa ({} steps, {})", label_, r.p.fs0 / r.p.fn_max,
                r.specimen == "uniaxial" ? "UCS" : "tensile strength", r.strength / 1e6, r.steps,
                format_duration(r.seconds));
  }

 private:
  std::string label_;
  std::optional<Progress> progress_;
};

}  // namespace

int calibrate_cmd(const scene::Scene& sc, const std::filesystem::path& output) {
  const std::filesystem::path dir = output.empty() ? sc.dir / sc.output.directory.value : output;
  CalibrateTerminal observer;
  const StopSignals stop;
  std::optional<cases::CalibrationResult> done;
  try {
    done = cases::calibrate(sc, dir, observer);
  } catch (const Error&) {
    const int sig = StopSignals::received();
    if (sig == 0) throw;
    std::printf("interrupted by SIG%s; the runs so far are in %s/runs\n", sigabbrev_np(sig),
                dir.string().c_str());
    return 128 + sig;
  }
  std::printf("\n%s\nwrote:\n", done->markdown.c_str());
  for (const auto& p : done->written) std::printf("  %s\n", p.string().c_str());
  return 0;
}

int check_calibration(const scene::Scene& sc) {
  const scene::CalibrateTable& c = *sc.calibrate;
  const int dim = sc.scene.dimension;
  const double w = cases::specimen_width(c);
  const cases::LatticeParameters k = cases::analytical_springs(sc);
  std::printf("calibration  %s\n", sc.file.string().c_str());
  std::printf("targets      E = %.4g Pa, nu = %.4g, UCS = %.4g Pa, tensile strength = %.4g Pa (ratio %.3g)\n",
              c.youngs_modulus.value, c.poisson_ratio.value, c.ucs.value, c.tensile_strength.value,
              c.ucs / c.tensile_strength);
  std::printf("lattice      %dD %s, d = %g m\n", dim, c.lattice.value.c_str(), c.diameter.value);
  std::printf("analytical   Kn = %.6g N/m, Ks = %.6g N/m (%s)\n", k.kn, k.ks,
              dim == 2 ? "hexagonal lattice" : "close packing along its stacking axis z");
  std::printf("specimens    uniaxial %g x %g m%s, Brazilian disc of diameter %g m\n", w, 2 * w,
              dim == 3 ? " (cylinder along z)" : "", w);
  return 0;
}

}  // namespace strata::app
