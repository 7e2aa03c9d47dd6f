#include "atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "strata/core/error.hpp"

namespace strata::io::detail {

void make_parent(const std::filesystem::path& path) {
  const auto parent = path.parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(parent, ec);
  STRATA_CHECK(!ec, IO, "cannot create folder {}: {}", parent.string(), ec.message());
}

void commit(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::error_code ec;
  std::filesystem::rename(from, to, ec);
  STRATA_CHECK(!ec, IO, "cannot rename {} to {}: {}", from.string(), to.string(), ec.message());
}

void write_text_atomic(const std::filesystem::path& path, const std::string& text) {
  make_parent(path);
  const auto tmp = temp_path(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  STRATA_CHECK(f, IO, "cannot open {} for writing: {}", tmp.string(), std::strerror(errno));
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0 &&
                  ::fsync(::fileno(f)) == 0;
  const int err = errno;
  std::fclose(f);
  if (!ok) {
    std::filesystem::remove(tmp);
    fail(ErrorKind::IO, "cannot write {}: {}", tmp.string(), std::strerror(err));
  }
  commit(tmp, path);
}

}  // namespace strata::io::detail
