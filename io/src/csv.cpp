#include "strata/io/csv.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <utility>

#include "atomic_file.hpp"
#include "strata/core/error.hpp"

namespace strata::io {

CsvWriter::CsvWriter(const std::filesystem::path& path, std::vector<std::string> columns,
                     std::size_t flush_every)
    : path_(path), columns_(std::move(columns)), flush_every_(flush_every == 0 ? 1 : flush_every) {
  STRATA_CHECK(!columns_.empty(), Input, "CSV file {}: no columns", path_.string());
  for (const auto& c : columns_)
    STRATA_CHECK(!c.empty() && c.find_first_of(",\"\n\r") == std::string::npos, Input,
                 "CSV file {}: column name '{}' must be non-empty without comma, quote or newline",
                 path_.string(), c);
  detail::make_parent(path_);
  file_ = std::fopen(path_.c_str(), "w");
  STRATA_CHECK(file_, IO, "cannot open {} for writing: {}", path_.string(), std::strerror(errno));
  const std::string header = fmt::format("{}\n", fmt::join(columns_, ","));
  std::fputs(header.c_str(), file_);
  std::fflush(file_);
}

CsvWriter CsvWriter::append(const std::filesystem::path& path, std::vector<std::string> columns,
                            double keep_until, std::size_t flush_every) {
  if (!std::filesystem::exists(path)) return CsvWriter(path, std::move(columns), flush_every);
  std::ifstream in(path, std::ios::binary);
  STRATA_CHECK(in, IO, "cannot open {}", path.string());
  std::string header, line, kept;
  std::getline(in, header);
  if (!header.empty() && header.back() == '\r') header.pop_back();
  const std::string expected = fmt::format("{}", fmt::join(columns, ","));
  STRATA_CHECK(header == expected, Input, "{} has the columns '{}', expected '{}': not written by this scene",
               path.string(), header, expected);
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    // a row cut short by a killed run has no newline and may not parse: drop it too
    if (in.eof() || line.empty()) break;
    char* end = nullptr;
    const double first = std::strtod(line.c_str(), &end);
    if (end == line.c_str() || !(first <= keep_until)) break;
    kept += line;
    kept += '\n';
    ++rows;
  }
  in.close();
  detail::write_text_atomic(path, expected + "\n" + kept);

  CsvWriter w;
  w.path_ = path;
  w.columns_ = std::move(columns);
  w.flush_every_ = flush_every == 0 ? 1 : flush_every;
  w.rows_ = rows;
  w.file_ = std::fopen(path.c_str(), "a");
  STRATA_CHECK(w.file_, IO, "cannot open {} for appending: {}", path.string(), std::strerror(errno));
  return w;
}

CsvWriter::~CsvWriter() {
  if (file_) std::fclose(file_);  // no throw from a destructor; close() reports errors
}

CsvWriter::CsvWriter(CsvWriter&& o) noexcept
    : path_(std::move(o.path_)),
      columns_(std::move(o.columns_)),
      flush_every_(o.flush_every_),
      rows_(o.rows_),
      file_(std::exchange(o.file_, nullptr)) {}

CsvWriter& CsvWriter::operator=(CsvWriter&& o) noexcept {
  if (this != &o) {
    if (file_) std::fclose(file_);
    path_ = std::move(o.path_);
    columns_ = std::move(o.columns_);
    flush_every_ = o.flush_every_;
    rows_ = o.rows_;
    file_ = std::exchange(o.file_, nullptr);
  }
  return *this;
}

void CsvWriter::row(std::span<const double> values) {
  STRATA_CHECK(file_, IO, "CSV file {} is closed", path_.string());
  STRATA_CHECK(values.size() == columns_.size(), Input, "CSV file {}: row with {} values for {} columns",
               path_.string(), values.size(), columns_.size());
  line_.clear();
  for (std::size_t j = 0; j < values.size(); ++j) {
    if (j) line_ += ',';
    fmt::format_to(std::back_inserter(line_), "{}", values[j]);  // shortest round-trip form
  }
  line_ += '\n';
  STRATA_CHECK(std::fwrite(line_.data(), 1, line_.size(), file_) == line_.size(), IO,
               "cannot write to {}: {}", path_.string(), std::strerror(errno));
  if (++rows_ % flush_every_ == 0) flush();
}

void CsvWriter::flush() {
  if (file_)
    STRATA_CHECK(std::fflush(file_) == 0, IO, "cannot write to {}: {}", path_.string(), std::strerror(errno));
}

void CsvWriter::close() {
  if (!file_) return;
  const bool ok = std::fflush(file_) == 0;
  const int err = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  STRATA_CHECK(ok && closed, IO, "cannot write to {}: {}", path_.string(), std::strerror(err));
}

const std::vector<double>& CsvTable::column(std::string_view name) const {
  for (std::size_t j = 0; j < names.size(); ++j)
    if (names[j] == name) return columns[j];
  fail(ErrorKind::Input, "no column '{}' (columns: {})", name, fmt::join(names, ", "));
}

CsvTable read_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  STRATA_CHECK(in, IO, "cannot open {}", path.string());
  CsvTable t;
  std::string line;
  STRATA_CHECK(std::getline(in, line), IO, "{}: empty file (no header line)", path.string());
  if (!line.empty() && line.back() == '\r') line.pop_back();
  for (std::size_t pos = 0;;) {
    const auto comma = line.find(',', pos);
    std::string name = line.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    // Tolerate surrounding spaces and quotes from other tools.
    while (!name.empty() && (name.front() == ' ' || name.front() == '"')) name.erase(name.begin());
    while (!name.empty() && (name.back() == ' ' || name.back() == '"')) name.pop_back();
    t.names.push_back(std::move(name));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  t.columns.resize(t.names.size());
  for (std::size_t lineno = 2; std::getline(in, line); ++lineno) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line.front() == '#') continue;
    const char* p = line.c_str();
    for (std::size_t j = 0; j < t.names.size(); ++j) {
      char* end = nullptr;
      const double v = std::strtod(p, &end);
      STRATA_CHECK(end != p, IO, "{}:{}: column {} ('{}') is not a number", path.string(), lineno, j + 1,
                   t.names[j]);
      while (*end == ' ') ++end;
      const bool last = j + 1 == t.names.size();
      STRATA_CHECK(last ? *end == '\0' : *end == ',', IO, "{}:{}: expected {} values separated by commas",
                   path.string(), lineno, t.names.size());
      t.columns[j].push_back(v);
      p = end + 1;
    }
  }
  return t;
}

}  // namespace strata::io
