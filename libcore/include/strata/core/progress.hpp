#pragma once
/// Progress of long runs: a live line with rate and ETA on a terminal, plain periodic lines
/// (every `interval` seconds) when stderr is not a terminal.
#include <strata/core/clock.hpp>

#include <cstdint>
#include <string>

namespace strata {

class Progress {
 public:
  /// `total` units of work (e.g. steps) described by `label`; `unit` names one unit.
  Progress(std::string label, std::int64_t total, std::string unit = "steps", double interval_s = 10.0);
  ~Progress();
  /// Reports that `done` units are complete; cheap enough to call every step.
  void update(std::int64_t done) {
    if (done >= next_check_) report(done, false);
  }
  /// Prints the final line.
  void finish(std::int64_t done);
  /// Whether progress goes to a terminal.
  bool interactive() const { return tty_; }

 private:
  void report(std::int64_t done, bool final);
  std::string label_, unit_;
  std::int64_t total_, next_check_ = 0, check_every_ = 1;
  double interval_s_, last_print_s_ = 0.0;
  bool tty_, finished_ = false;
  WallClock::time_point start_;
};

/// "1 h 02 min", "3.4 s": human-readable duration.
std::string format_duration(double seconds);

}  // namespace strata
