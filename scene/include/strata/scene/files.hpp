#pragma once
/// Writing output files so that readers never see half of them: one file through a
/// temporary name and a rename, a set of files through a staging folder.
#include <filesystem>
#include <string>
#include <vector>

namespace strata::scene {

/// Writes `text` to `path` through a temporary file and a rename, so readers never see a
/// half-written file. Creates the parent folder. Throws strata::Error (IO).
void write_file_atomic(const std::filesystem::path& path, const std::string& text);

/// A folder beside the output folder that receives a set of files first; commit() moves them
/// into the output folder (one rename each, replacing what is there), so it never holds half
/// of the set, and a failure before that leaves nothing (the staging folder is removed).
class Staging {
 public:
  explicit Staging(const std::filesystem::path& dir);
  ~Staging();
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;
  const std::filesystem::path& path() const { return tmp_; }
  /// Moves every staged file and folder into the output folder; returns their paths as
  /// `shown / name`, sorted.
  std::vector<std::filesystem::path> commit(const std::filesystem::path& shown);

 private:
  std::filesystem::path final_, tmp_;
};

}  // namespace strata::scene
