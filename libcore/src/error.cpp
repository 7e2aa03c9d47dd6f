#include "strata/core/error.hpp"

#include <cstdio>
#include <cstdlib>

namespace strata {

void fail_missing_feature(const char* option, const std::string& what) {
  fail(ErrorKind::Unsupported, "{} needs a part this build of strata leaves out: reconfigure with -D{}=ON",
       what, option);
}

namespace detail {
void assert_failed(const char* expr, const char* file, int line, const std::string& msg) {
  std::fprintf(stderr, "strata internal error: %s:%d: assertion `%s` failed%s%s\n", file, line, expr,
               msg.empty() ? "" : ": ", msg.c_str());
  std::abort();
}
}  // namespace detail
}  // namespace strata
