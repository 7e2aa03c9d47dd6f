#pragma once
// Internal to strata::cases: small helpers its sources share (the wall-clock time of a run,
// the first line of an error message). One definition here: the library is compiled as one
// batch of sources per compiler run in the sanitizer and minimal builds, where two file-local
// copies would clash.
#include <chrono>
#include <string>

namespace strata::cases::detail {

using Clock = std::chrono::steady_clock;

/// Seconds of wall-clock time since t0.
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The first line of `s` (an error message's headline), without its newline.
inline std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

}  // namespace strata::cases::detail
