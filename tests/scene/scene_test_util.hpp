#pragma once
// Helpers shared by the scene tests (test_scene*.cpp, test_coupled_run.cpp): the message of the
// error a scene text is refused with, and fresh folders for their runs.
#include <gtest/gtest.h>
#include <strata/core/error.hpp>
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace strata::scene::test {

namespace fs = std::filesystem;

/// The message of the Input error that parsing `text` (as the file `file`, with the
/// command-line settings `sets`) throws, or "no error".
inline std::string error_of(const std::string& text, const std::vector<std::string>& sets = {},
                            const fs::path& file = "scene.toml") {
  try {
    parse(text, file, sets);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input) << e.what();
    return e.what();
  }
  return "no error";
}

/// The message of the Input error that parsing `text` (as the file `file`) or setting up its
/// run into `out` throws, or "no error": what only a run's setup refuses.
inline std::string setup_error_of(const std::string& text, const fs::path& file, const fs::path& out) {
  try {
    const Scene sc = parse(text, file, {});
    Run run(sc, {out, false, {}});
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input) << e.what();
    return e.what();
  }
  return "no error";
}

/// strata_<name> in the temporary folder, removed with all it held (a path nothing is at).
inline fs::path fresh_path(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("strata_" + name);
  fs::remove_all(p);
  return p;
}

/// strata_<name> in the temporary folder, emptied: removed with all it held and made again.
inline fs::path empty_dir(const std::string& name) {
  const fs::path d = fresh_path(name);
  fs::create_directories(d);
  return d;
}

}  // namespace strata::scene::test
