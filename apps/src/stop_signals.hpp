#pragma once
// SIGINT and SIGTERM during a run: the handler only sets a flag, which the run polls between
// chunks of steps (scene::RunObserver::stop_requested).
#include <signal.h>

#include <atomic>

namespace strata::app {

/// Routes SIGINT and SIGTERM to a flag for the lifetime of the object; restores the previous
/// handlers afterwards.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  /// The signal received (0: none).
  static int received();

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

}  // namespace strata::app
