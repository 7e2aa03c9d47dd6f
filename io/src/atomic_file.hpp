#pragma once
// Internal: write-to-temporary-then-rename helpers shared by the io writers.
#include <filesystem>
#include <string>

namespace strata::io::detail {

/// `<path>.tmp`, in the same folder as `path` (so the rename is atomic on one filesystem).
inline std::filesystem::path temp_path(const std::filesystem::path& path) {
  auto t = path;
  t += ".tmp";
  return t;
}

/// Creates the parent folder of `path` if needed; throws strata::Error (IO) on failure.
void make_parent(const std::filesystem::path& path);

/// Renames `from` onto `to` (replacing it); throws strata::Error (IO) on failure.
void commit(const std::filesystem::path& from, const std::filesystem::path& to);

/// Writes `text` to `<path>.tmp`, flushes it to disk, and renames it onto `path`.
void write_text_atomic(const std::filesystem::path& path, const std::string& text);

}  // namespace strata::io::detail
