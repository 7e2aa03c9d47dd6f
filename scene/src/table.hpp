#pragma once
// Internal: the loader's validation layer. The loader checks every key of a scene file
// against its declaration and stores the values by key name in a Table; the files of
// tables/ then read each Table into its typed struct (description.hpp). Only the loader and
// those files read values by key name.
#include <strata/scene/scene.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace strata::scene {

/// A stored, validated value.
struct Value {
  Type type = Type::Real;
  bool b = false;
  std::int64_t i = 0;
  double r = 0.0;
  std::string s;                           ///< String, Choice, Path (resolved), OutputPath (resolved)
  std::vector<double> reals;               ///< RealList
  std::vector<std::int64_t> integers;      ///< IntegerList
  std::vector<std::string> strings;        ///< StringList
  std::vector<std::vector<double>> table;  ///< RealTable
  SourcePos pos;
  bool given = false;  ///< false: filled from the default
};

/// One validated table instance ([solver], or one [[region]] entry).
class Table {
 public:
  /// "solver" or "region[2]" (0-based index), for messages.
  const std::string& label() const { return label_; }
  /// Position of the table header (or of the file start for tables not written).
  const SourcePos& where() const { return pos_; }
  /// Position of a key's value, or of the table header when the key was defaulted.
  SourcePos where(const std::string& key) const;
  /// Whether the user wrote the key (not defaulted).
  bool given(const std::string& key) const;
  /// Whether the key has a value (given or defaulted).
  bool has(const std::string& key) const;

  bool boolean(const std::string& key) const;
  std::int64_t integer(const std::string& key) const;
  double real(const std::string& key) const;
  /// String, Choice, Path or OutputPath (paths are resolved relative to the scene file).
  const std::string& str(const std::string& key) const;
  std::filesystem::path path(const std::string& key) const { return str(key); }
  const std::vector<double>& reals(const std::string& key) const;
  const std::vector<std::int64_t>& integers(const std::string& key) const;
  const std::vector<std::string>& strings(const std::string& key) const;
  const std::vector<std::vector<double>>& real_table(const std::string& key) const;

  Table(std::string label, SourcePos pos) : label_(std::move(label)), pos_(std::move(pos)) {}
  void set(const std::string& key, Value v) { values_[key] = std::move(v); }

 private:
  const Value& get(const std::string& key) const;
  std::string label_;
  SourcePos pos_;
  std::map<std::string, Value> values_;
};

/// Every table of a scene by name: a plain table as one entry, an array of tables as its
/// entries in file order. [coupled] has an entry only in a coupled scene, [calibrate] only
/// in a calibration.
struct Tables {
  std::map<std::string, std::vector<Table>> entries;

  /// A plain table ([coupled] only in a coupled scene).
  const Table& table(const std::string& name) const;
  /// The entries of an array of tables (possibly empty).
  const std::vector<Table>& tables(const std::string& name) const;
  bool coupled() const { return !tables("coupled").empty(); }
  bool calibration() const { return !tables("calibrate").empty(); }
  bool network() const { return !tables("network").empty(); }
  bool study() const { return !tables("study").empty(); }
};

/// Reports one problem of a scene at a position (the loader throws the first in file order).
using ReportProblem = std::function<void(const SourcePos& pos, std::string message)>;

/// Pass 4 of the loader: checks between keys (checks.cpp), on tables whose keys are valid.
void check_between_keys(const Tables& tables, const ReportProblem& report);

/// Reads the validated tables into the typed scene (tables/describe.cpp).
void describe(const Tables& tables, Scene& scene);

/// Scene::fingerprint of the validated tables (tables/describe.cpp).
std::string fingerprint_of(const Tables& tables);

}  // namespace strata::scene
