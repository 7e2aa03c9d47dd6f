#include "strata/core/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace strata {

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  if (s < 60) return fmt::format("{:.1f} s", s);
  if (s < 3600) return fmt::format("{} min {:02} s", int(s / 60), int(s) % 60);
  return fmt::format("{} h {:02} min", int(s / 3600), int(s / 60) % 60);
}

Progress::Progress(std::string label, std::int64_t total, std::string unit, double interval_s)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(std::max<std::int64_t>(total, 1)),
      interval_s_(interval_s),
      tty_(isatty(fileno(stderr)) != 0),
      start_(WallClock::now()) {
  if (tty_) interval_s_ = 0.25;
}

Progress::~Progress() {
  if (tty_ && !finished_ && last_print_s_ > 0) std::fputc('\n', stderr);
}

void Progress::report(std::int64_t done, bool final) {
  const double t = seconds_since(start_);
  // Check the clock about every 50 ms of work, whatever the speed of a unit.
  const double rate = t > 0 ? done / t : 0.0;
  check_every_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(rate * 0.05));
  next_check_ = done + check_every_;
  if (!final && t - last_print_s_ < interval_s_) return;
  last_print_s_ = t;
  const double frac = total_ > 0 ? std::min(1.0, double(done) / double(total_)) : 1.0;
  const double eta = rate > 0 ? (total_ - done) / rate : NAN;
  // the last line says how the work ended: all of it done, or stopped short
  const std::string end = !final ? "ETA " + format_duration(eta) : done >= total_ ? "done" : "stopped";
  const std::string line = fmt::format("{}: {:5.1f}%  {}/{} {}  {:.3g} {}/s  elapsed {}  {}", label_,
                                       100 * frac, done, total_, unit_, rate, unit_, format_duration(t), end);
  if (tty_)
    std::fprintf(stderr, "\r\033[K%s%s", line.c_str(), final ? "\n" : "");
  else
    std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

void Progress::finish(std::int64_t done) {
  if (finished_) return;
  report(done, true);
  finished_ = true;
}
}  // namespace strata
