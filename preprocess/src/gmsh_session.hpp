#pragma once
// One gmsh session at a time (gmsh keeps global state): initialise once, serialise access,
// turn gmsh's errors into strata::Error with the file and gmsh's own message.
#include <strata/config.hpp>
#include <strata/core/error.hpp>

#include <mutex>
#include <string>

#if STRATA_WITH_GMSH
#include <gmsh.h>
#endif

namespace strata::preprocess::detail {

#if STRATA_WITH_GMSH
/// Holds the gmsh lock for its lifetime; the model is empty at the start and at the end.
class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  /// Runs f(); a gmsh error becomes Error(Input, "<what>: <gmsh's message>"), and gmsh is
  /// restarted (its parser does not recover from a syntax error otherwise).
  template <typename F>
  auto run(const std::string& what, F&& f) -> decltype(f()) {
    try {
      return f();
    } catch (const std::string& e) {
      restart();
      fail(ErrorKind::Input, "{}: {}", what, explain(e));
    } catch (const strata::Error&) {
      throw;
    } catch (const std::exception& e) {
      restart();
      fail(ErrorKind::Input, "{}: {}", what, explain(e.what()));
    }
  }

  /// run(f) under "<file>: gmsh X cannot <action>", then refuses an error gmsh logged
  /// without throwing (it logs some, e.g. of a .geo file it could partly read, and goes on).
  template <typename F>
  void run_checked(const std::string& file, const std::string& action, F&& f) {
    const std::string what = cannot(file, action);
    run(what, std::forward<F>(f));
    const std::string err = last_error();
    if (!err.empty()) fail(ErrorKind::Input, "{}: {}", what, explain(err));
  }

  /// Last error gmsh logged (empty when none).
  static std::string last_error();
  /// The version of the gmsh library in use, e.g. "4.8.4" (read once).
  static const std::string& version();
  /// "<file>: gmsh 4.8.4 cannot <action>": gmsh errors name gmsh's version, since files
  /// written for a newer gmsh often use what this one does not know.
  static std::string cannot(const std::string& file, const std::string& action);
  /// gmsh's message, with a hint after a syntax error (most often a file for a newer gmsh).
  static std::string explain(const std::string& message);

 private:
  static void restart();
  std::unique_lock<std::mutex> lock_;
  int threads_;  // strata's thread count: gmsh's General.NumThreads sets OpenMP's, restored at the end
};

}  // namespace strata::preprocess::detail

#include <strata/preprocess/geometry.hpp>
namespace strata::preprocess::detail {
/// Reads the meshed gmsh model of the current session into a Geometry (what: for messages).
Geometry extract_gmsh_model(const std::string& what, int dim);
#endif

/// Refuses (Input) a mesh of elements about `h` long filling the box [lo, hi] (dim 2 or 3)
/// that would need more than half this machine's memory: box area / (√3/4·h²) triangles or
/// box volume / (√2/12·h³) tetrahedra, about 500 bytes per triangle and 1000 per tetrahedron
/// in gmsh and strata. `allowed` says how to make the elements larger.
void refuse_huge_mesh(const std::string& what, int dim, const double lo[3], const double hi[3], double h,
                      const std::string& allowed);

}  // namespace strata::preprocess::detail
