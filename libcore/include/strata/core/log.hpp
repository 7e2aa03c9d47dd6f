#pragma once
/// Logging through spdlog: one logger named "strata" writing to stderr.
#include <spdlog/spdlog.h>

namespace strata::log {

/// Verbosity of the `strata` command.
enum class Level { Quiet, Normal, Verbose, Debug };

/// Sets up the "strata" logger (idempotent) and its level.
void init(Level level = Level::Normal);

/// The "strata" logger, set up on first use.
spdlog::logger& get();

template <typename... Args>
void info(spdlog::format_string_t<Args...> f, Args&&... args) {
  get().info(f, std::forward<Args>(args)...);
}
template <typename... Args>
void warn(spdlog::format_string_t<Args...> f, Args&&... args) {
  get().warn(f, std::forward<Args>(args)...);
}
template <typename... Args>
void debug(spdlog::format_string_t<Args...> f, Args&&... args) {
  get().debug(f, std::forward<Args>(args)...);
}
template <typename... Args>
void error(spdlog::format_string_t<Args...> f, Args&&... args) {
  get().error(f, std::forward<Args>(args)...);
}
}  // namespace strata::log
