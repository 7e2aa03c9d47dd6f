#pragma once
/// CSV probe files: one header line of column names, then one row of numbers per sample,
/// written with full (shortest round-trip) precision so a value read back is bit-identical.
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace strata::io {

/// Appends rows to a CSV file; the file is flushed every `flush_every` rows and on close.
class CsvWriter {
 public:
  /// Creates (truncates) `path` and writes the header. Column names must be non-empty and
  /// contain no comma, quote or newline.
  CsvWriter(const std::filesystem::path& path, std::vector<std::string> columns,
            std::size_t flush_every = 64);
  ~CsvWriter();
  CsvWriter(CsvWriter&&) noexcept;

  /// Continues a CSV file written with the same columns (a restart from a checkpoint): rows
  /// whose first column is greater than `keep_until` are dropped (they were written after
  /// the checkpoint), then new rows are appended. A missing file is created with the header.
  /// Throws strata::Error (Input) when the file's header differs from `columns`.
  static CsvWriter append(const std::filesystem::path& path, std::vector<std::string> columns,
                          double keep_until, std::size_t flush_every = 64);

  CsvWriter& operator=(CsvWriter&&) noexcept;
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  /// Writes one row; `values.size()` must equal the number of columns.
  void row(std::span<const double> values);
  void row(std::initializer_list<double> values) {
    row(std::span<const double>(values.begin(), values.size()));
  }
  /// Writes buffered rows to disk.
  void flush();
  /// Flushes and closes; further rows throw.
  void close();

  const std::vector<std::string>& columns() const { return columns_; }
  /// Rows written (for an appending writer: rows kept from the file plus rows written).
  std::size_t rows() const { return rows_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  CsvWriter() = default;

  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::size_t flush_every_ = 64;
  std::size_t rows_ = 0;
  std::FILE* file_ = nullptr;
  std::string line_;
};

/// A CSV file read back column by column.
struct CsvTable {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;  ///< columns[j][i] = row i of column j

  std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
  /// The column called `name`; throws strata::Error (Input) naming the columns if absent.
  const std::vector<double>& column(std::string_view name) const;
};

/// Reads a CSV file with a header line and numeric rows (as written by CsvWriter; "nan"
/// and "inf" are accepted). Throws strata::Error (IO) with the line number on a bad row.
CsvTable read_csv(const std::filesystem::path& path);

}  // namespace strata::io
