#include "strata/core/log.hpp"

#include "strata/core/memory.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace strata::log {

spdlog::logger& get() {
  static std::shared_ptr<spdlog::logger> logger = [] {
    auto l = spdlog::stderr_color_mt("strata");
    l->set_pattern("%^%l%$: %v");
    l->set_level(spdlog::level::info);
    return l;
  }();
  return *logger;
}

void init(Level level) {
  auto& l = get();
  switch (level) {
    case Level::Quiet:
      l.set_level(spdlog::level::warn);
      break;
    case Level::Normal:
      l.set_level(spdlog::level::info);
      break;
    case Level::Verbose:
      l.set_level(spdlog::level::debug);
      break;
    case Level::Debug:
      l.set_level(spdlog::level::trace);
      break;
  }
}

double Phases::lap(const char* phase) {
  const auto now = WallClock::now();
  const double s = seconds_between(t_, now);
  t_ = now;
  if (get().should_log(spdlog::level::debug))
    debug("{}: {} {:.3g} s (resident {:.2f} GB, peak {:.2f} GB)", task_, phase, s,
          double(sys::rss_bytes()) * 1e-9, double(sys::peak_rss_bytes()) * 1e-9);
  return s;
}
}  // namespace strata::log
