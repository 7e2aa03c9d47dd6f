#pragma once
/// Logging through spdlog: one logger named "strata" writing to stderr.
#include <spdlog/spdlog.h>
#include <strata/core/clock.hpp>

#include <string>

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

/// Wall time of the phases of a task, each written at debug level (`strata -v`) as it ends:
/// `Phases ph("set-up"); ...; ph.lap("bonds");` logs "set-up: bonds 1.23 s (resident 0.51 GB,
/// peak 0.60 GB)": the memory of the process as the phase ends, and the most it has held so far,
/// which tell where a large model's set-up needs its memory.
class Phases {
 public:
  explicit Phases(std::string task) : task_(std::move(task)), t_(WallClock::now()) {}
  /// Logs the time since the last lap (or the start) under `phase`; returns it in seconds.
  double lap(const char* phase);

 private:
  std::string task_;
  WallClock::time_point t_;
};
}  // namespace strata::log
