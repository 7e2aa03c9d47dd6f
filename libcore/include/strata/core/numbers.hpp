#pragma once
/// Numbers in messages: two values compared in a message must not print alike.
#include <fmt/format.h>

#include <string>
#include <utility>

namespace strata {

/// `a` and `b` in the shortest %g form (at least `digits` significant digits, at most 17)
/// in which they differ when they are different, e.g. "1.4340001e-07" and "1.434e-07"
/// rather than "1.434e-07" twice.
inline std::pair<std::string, std::string> distinct_pair(double a, double b, int digits = 4) {
  for (int p = digits; p < 17; ++p) {
    std::string sa = fmt::format("{:.{}g}", a, p), sb = fmt::format("{:.{}g}", b, p);
    if (a == b || sa != sb) return {std::move(sa), std::move(sb)};
  }
  return {fmt::format("{:.17g}", a), fmt::format("{:.17g}", b)};
}

/// a/b with three decimals ("1.500"), or with the digits that show it above 1 when a is
/// just above b ("1.0000000000000002" rather than "1.000").
inline std::string ratio_text(double a, double b) {
  const double r = a / b;
  std::string s = fmt::format("{:.3f}", r);
  if (r > 1 && s == "1.000") s = distinct_pair(r, 1.0).first;
  return s;
}

}  // namespace strata
