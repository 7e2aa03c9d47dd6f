#pragma once
/// Errors and checks shared by every strata library.
///
/// Two tiers:
///  - STRATA_CHECK: always on; for user input, files and numerical health. Throws
///    strata::Error carrying the values involved.
///  - STRATA_ASSERT: debug builds only; internal invariants.
/// Libraries never call exit(); `main()` catches strata::Error and maps its kind to the
/// exit status (Input -> 2, everything else -> 1).
#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace strata {

/// What went wrong, which decides the exit status of the `strata` command.
enum class ErrorKind {
  Input,        ///< bad scene, bad option, bad geometry file: exit status 2
  Unsupported,  ///< the scene needs an optional part this build leaves out: exit status 2
  Numerical,    ///< unstable time step, blow-up during a run: exit status 1
  IO,           ///< a file could not be read or written: exit status 1
  Internal,     ///< a bug in strata: exit status 1
};

/// The one exception type strata throws.
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, std::string message) : std::runtime_error(std::move(message)), kind_(kind) {}
  ErrorKind kind() const noexcept { return kind_; }
  /// Exit status of the `strata` command for this error: 2 for bad input, 1 otherwise.
  int exit_status() const noexcept {
    return kind_ == ErrorKind::Input || kind_ == ErrorKind::Unsupported ? 2 : 1;
  }

 private:
  ErrorKind kind_;
};

/// Throws Error(kind, formatted message).
template <typename... Args>
[[noreturn]] void fail(ErrorKind kind, fmt::format_string<Args...> f, Args&&... args) {
  throw Error(kind, fmt::format(f, std::forward<Args>(args)...));
}

/// Throws an Unsupported error naming the CMake option that would enable `what`.
[[noreturn]] void fail_missing_feature(const char* option, const std::string& what);

namespace detail {
[[noreturn]] void assert_failed(const char* expr, const char* file, int line, const std::string& msg);
}
}  // namespace strata

/// Always-on check: throws strata::Error(kind, message) when `cond` is false.
#define STRATA_CHECK(cond, kind, ...)                         \
  do {                                                        \
    if (!(cond)) [[unlikely]]                                 \
      ::strata::fail(::strata::ErrorKind::kind, __VA_ARGS__); \
  } while (0)

/// Debug-only check of an internal invariant; compiled out with NDEBUG.
#ifdef NDEBUG
#define STRATA_ASSERT(cond, ...) ((void)0)
#else
#define STRATA_ASSERT(cond, ...)                                                                 \
  do {                                                                                           \
    if (!(cond)) [[unlikely]]                                                                    \
      ::strata::detail::assert_failed(#cond, __FILE__, __LINE__, ::fmt::format("" __VA_ARGS__)); \
  } while (0)
#endif
