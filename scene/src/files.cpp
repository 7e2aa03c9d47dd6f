#include <fmt/format.h>
#include <unistd.h>
#include <strata/core/error.hpp>
#include <strata/scene/files.hpp>

#include <algorithm>
#include <fstream>

namespace strata::scene {

namespace fs = std::filesystem;

void write_file_atomic(const fs::path& path, const std::string& text) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    STRATA_CHECK(f.good(), IO, "cannot write {}", tmp.string());
    f << text;
    f.flush();
    STRATA_CHECK(f.good(), IO, "cannot write {} (disk full?)", tmp.string());
  }
  fs::rename(tmp, path);
}

Staging::Staging(const fs::path& dir) {
  final_ = fs::absolute(dir).lexically_normal();
  if (final_.filename().empty()) final_ = final_.parent_path();
  tmp_ = final_.parent_path() / fmt::format(".{}.partial-{}", final_.filename().string(), ::getpid());
  fs::remove_all(tmp_);
  fs::create_directories(tmp_);
}

Staging::~Staging() {
  std::error_code ec;
  fs::remove_all(tmp_, ec);
}

std::vector<fs::path> Staging::commit(const fs::path& shown) {
  fs::create_directories(final_);
  std::vector<fs::path> moved;
  for (const auto& e : fs::directory_iterator(tmp_)) {
    const fs::path target = final_ / e.path().filename();
    if (fs::is_directory(target)) fs::remove_all(target);  // a folder (series/) of an earlier run
    fs::rename(e.path(), target);
    moved.push_back(shown / e.path().filename());
  }
  std::sort(moved.begin(), moved.end());
  return moved;
}

}  // namespace strata::scene
