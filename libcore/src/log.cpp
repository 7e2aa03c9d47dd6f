#include "strata/core/log.hpp"

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
}  // namespace strata::log
