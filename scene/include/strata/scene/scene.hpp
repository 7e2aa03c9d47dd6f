#pragma once
/// Scene files: declared keys, validation with file:line:col messages, typed access.
///
/// Every key a scene may hold is declared once in the schema table (schema.cpp) with its
/// type, unit, allowed range or choices, default and doc string. The same table validates
/// input (files and `--set` overrides) and generates docs/scene-reference.md.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace strata::scene {

/// Where a value came from: a position in a scene file, or a `--set` override.
struct SourcePos {
  std::string file;     ///< scene file path as given, or "--set" for overrides
  int line = 0;         ///< 1-based; 0 when unknown
  int column = 0;       ///< 1-based; 0 when unknown
  std::string setting;  ///< for overrides: the "key=value" text as given to `--set`
  /// "scene.toml:42:17" (or "--set solver.dt=1" for an override)
  std::string str() const;
};

/// Value types a key can have.
enum class Type {
  Bool,
  Integer,
  Real,
  String,
  Choice,       ///< a string from a fixed list
  Path,         ///< a file path, relative to the scene file, that must exist
  OutputPath,   ///< a path, relative to the scene file, that need not exist
  RealList,     ///< array of reals (integers accepted); optional fixed length
  IntegerList,  ///< array of integers (reals without a fractional part accepted), e.g. η values
  StringList,
  RealTable,  ///< array of arrays of reals, e.g. polygon vertices or force histories
};

/// One declared key.
struct KeySpec {
  std::string name;
  Type type = Type::Real;
  std::string unit;  ///< "N/m", "s", "" for none
  std::string doc;   ///< one or two sentences
  bool required = false;
  std::string default_value;   ///< TOML text of the default ("" when none or required)
  std::optional<double> min;   ///< numeric lower bound (also applied to list elements)
  std::optional<double> max;   ///< numeric upper bound
  bool min_exclusive = false;  ///< min is a strict bound (> instead of >=)
  bool max_exclusive = false;
  std::vector<std::string> choices;    ///< for Choice and StringList elements (empty: any)
  int length_min = 0, length_max = 0;  ///< for lists; for RealTable, of each row; 0: unbounded
  /// One component per axis: a RealList (or each RealTable row) must have as many entries as
  /// [scene].dimension; a StringList may only name axes of that dimension. List defaults are
  /// written for 3D and cut to the dimension.
  bool per_axis = false;
  bool allow_inf = false;  ///< a Real that accepts `inf` (e.g. "never breaks")
  /// [coupled] keys: the values of [coupled].case the key applies to (empty: every case). The
  /// loader refuses a key given for another case, naming the keys that case takes.
  std::vector<std::string> cases;
  /// For a key whose default depends on other keys (no default_value): the reference's
  /// default column, e.g. "per case: chain6, metamaterial `3`; wave `1`".
  std::string default_note;
};

/// One declared table: a plain table ([solver]) or an array of tables ([[region]]).
struct TableSpec {
  std::string name;
  bool array = false;     ///< written [[name]], any number of entries
  bool required = false;  ///< must appear at least once
  std::string doc;
  std::vector<KeySpec> keys;
};

/// The scene schema: every table and key strata accepts.
const std::vector<TableSpec>& schema();

/// docs/scene-reference.md, generated from schema().
std::string reference_markdown();

/// Text shared by error messages and the reference (schema.cpp).
/// "> 0", ">= 0 and < 1", "2 or 3"; "" when the key has no numeric bounds.
std::string range_text(const KeySpec& key);
/// "real", "list of reals", ... as the reference's type column shows it.
std::string type_name(Type type);

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

  /// Throws an Input error "file:line:col: message" pointing at `key`'s value.
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  // Construction (used by the loader).
  Table(std::string label, SourcePos pos) : label_(std::move(label)), pos_(std::move(pos)) {}
  void set(const std::string& key, Value v) { values_[key] = std::move(v); }

 private:
  const Value& get(const std::string& key) const;
  std::string label_;
  SourcePos pos_;
  std::map<std::string, Value> values_;
};

/// A validated scene.
class Scene {
 public:
  std::filesystem::path file;  ///< the scene file as given
  std::filesystem::path dir;   ///< its directory: paths in the scene are relative to it

  /// A plain table; always present (filled with defaults when not written), except
  /// [coupled], which is present only in a coupled-chain scene (see coupled()).
  const Table& table(const std::string& name) const;
  /// The entries of an array of tables (possibly empty).
  const std::vector<Table>& tables(const std::string& name) const;

  /// A coupled scene (the coupled chains of Li et al. 2023, or the 2D coupled wave of
  /// examples/04_coupled_wave): it has a [coupled] table, which describes the whole model, and no particle or
  /// mesh tables
  /// ([scene], [[material]], [[region]], ...).
  bool coupled() const { return !tables("coupled").empty(); }

  // Construction (used by the loader).
  std::map<std::string, std::vector<Table>> entries;
};

/// The tables a coupled-chain scene may hold besides [coupled], and of [output] the keys that
/// apply to it (the sweep's files go to output.directory; output.render = false skips the plot).
const std::vector<std::string>& coupled_scene_tables();
const std::vector<std::string>& coupled_output_keys();
/// The [coupled] keys that apply to `case_name` (KeySpec::cases), in schema order.
std::vector<std::string> coupled_case_keys(const std::string& case_name);

/// Reads, validates and returns a scene. `overrides` are "key=value" strings from `--set`,
/// with keys like "solver.dt" or "region.specimen.diameter" / "region[0].diameter"; values
/// are TOML values and are validated exactly like the file. Throws strata::Error (Input)
/// with a "file:line:col: what is wrong and what is allowed" message at the first problem.
Scene load(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});

/// Validates scene text (for tests); `file` is the name used in messages and for paths.
Scene parse(const std::string& text, const std::filesystem::path& file,
            const std::vector<std::string>& overrides = {});

}  // namespace strata::scene
