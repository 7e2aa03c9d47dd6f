#include "compare_cmd.hpp"

#include <string.h>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>
#include <strata/core/progress.hpp>

#include <cstdio>
#include <optional>

#include "stop_signals.hpp"

namespace strata::app {

namespace {

/// A progress line per run, then its row; stops on SIGINT or SIGTERM.
class CompareTerminal final : public cases::CompareObserver {
 public:
  void begin(const std::string& label, int repeat) override {
    label_ = repeat == 0 ? label : fmt::format("{} (repeat {})", label, repeat + 1);
  }
  void started(std::int64_t first, std::int64_t steps, const std::filesystem::path&) override {
    progress_.emplace(label_, steps - std::min(first, steps));
  }
  void progress(std::int64_t step, std::int64_t) override { progress_->update(step); }
  int stop_requested() override { return StopSignals::received(); }
  void stepped(const scene::RunResult& r) override { progress_->finish(r.step); }
  void end(const cases::CompareRow& row) override {
    if (row.status != "completed")
      log::warn("{}: {}: {}", row.label, row.status, row.note);
    else if (row.eta == 0)
      log::info("{}: {} steps in {}", row.label, row.steps, format_duration(row.seconds));
    else
      log::info("{}: {} steps in {}, gauge error {:.3g} %", row.label, row.steps,
                format_duration(row.seconds), 100 * row.error);
  }

 private:
  std::string label_;
  std::optional<Progress> progress_;
};

}  // namespace

int compare_cmd(const cases::CompareOptions& opt, int threads) {
  par::set_threads(threads);
  CompareTerminal observer;
  const StopSignals stop;
  std::optional<cases::CompareResult> done;
  try {
    done = cases::compare_runs(opt, observer);
  } catch (const Error&) {
    const int sig = StopSignals::received();
    if (sig == 0) throw;
    std::printf("interrupted by SIG%s; the runs so far are in %s/runs\n", sigabbrev_np(sig),
                opt.output.string().c_str());
    return 128 + sig;
  }
  const cases::CompareResult& res = *done;
  std::printf("\n%s\nthreads %d; run time = the time loop, fastest of %d run(s)\nwrote:\n",
              res.markdown.c_str(), par::threads(), opt.repeats);
  for (const auto& p : res.written) std::printf("  %s\n", p.string().c_str());
  return 0;
}

}  // namespace strata::app
