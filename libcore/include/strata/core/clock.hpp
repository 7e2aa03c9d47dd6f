#pragma once
/// Wall-clock time as strata reports it: run times, set-up times, benchmark rates.
#include <chrono>

namespace strata {

/// The clock of every wall time strata reports: monotonic, unaffected by changes of the
/// system's date.
using WallClock = std::chrono::steady_clock;

/// Seconds from t0 to t1.
inline double seconds_between(WallClock::time_point t0, WallClock::time_point t1) {
  return std::chrono::duration<double>(t1 - t0).count();
}

/// Seconds of wall-clock time since t0.
inline double seconds_since(WallClock::time_point t0) { return seconds_between(t0, WallClock::now()); }

}  // namespace strata
