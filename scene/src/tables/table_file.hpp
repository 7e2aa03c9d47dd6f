#pragma once
// Internal: what the file of one table (tables/<name>.cpp) needs to declare its keys and to
// read a validated Table into the table's struct (description.hpp).
//
// To add a key: add one line to its table's declaration with its type, unit, range, default
// and a doc string a geologist can read (with the paper it comes from, cited as in
// docs/references.md), a field to the table's struct in description.hpp, and one line to the
// table's read function; then regenerate docs/scene-reference.md
// (`strata reference -o docs/scene-reference.md`; test_scene fails until you do). A key
// declared and not read is an internal error at the first load. Checks that involve more
// than one key (shape-dependent keys, cross-references, list lengths against
// [scene].dimension) live in loader.cpp.
#include <strata/core/error.hpp>
#include <strata/scene/description.hpp>
#include <strata/scene/scene.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "../table.hpp"

namespace strata::scene::tables {

/// Builder that keeps each key on a few readable lines.
class K {
 public:
  K(std::string name, Type type, std::string unit = "") {
    k_.name = std::move(name);
    k_.type = type;
    k_.unit = std::move(unit);
  }
  K& doc(std::string d) {
    k_.doc = std::move(d);
    return *this;
  }
  K& required() {
    k_.required = true;
    return *this;
  }
  K& def(std::string toml_text) {
    k_.default_value = std::move(toml_text);
    return *this;
  }
  K& ge(double v) {
    k_.min = v;
    k_.min_exclusive = false;
    return *this;
  }
  K& gt(double v) {
    k_.min = v;
    k_.min_exclusive = true;
    return *this;
  }
  K& le(double v) {
    k_.max = v;
    k_.max_exclusive = false;
    return *this;
  }
  K& lt(double v) {
    k_.max = v;
    k_.max_exclusive = true;
    return *this;
  }
  K& choices(std::vector<std::string> c) {
    k_.choices = std::move(c);
    return *this;
  }
  K& length(int lo, int hi) {
    k_.length_min = lo;
    k_.length_max = hi;
    return *this;
  }
  /// One component per axis: 2 in 2D, 3 in 3D.
  K& per_axis() {
    k_.per_axis = true;
    if (k_.type != Type::StringList) k_.length_min = 2, k_.length_max = 3;
    return *this;
  }
  K& allow_inf() {
    k_.allow_inf = true;
    return *this;
  }
  /// [coupled] only: the cases the key applies to.
  K& cases(std::vector<std::string> c) {
    k_.cases = std::move(c);
    return *this;
  }
  /// A default that depends on other keys: the text of the reference's default column.
  K& default_note(std::string text) {
    k_.default_note = std::move(text);
    return *this;
  }
  operator KeySpec() const { return k_; }  // NOLINT: implicit on purpose, for the declarations

 private:
  KeySpec k_;
};

constexpr Type Bool = Type::Bool, Integer = Type::Integer, Real = Type::Real, String = Type::String,
               Choice = Type::Choice, Path = Type::Path, OutputPath = Type::OutputPath,
               RealList = Type::RealList, IntegerList = Type::IntegerList, StringList = Type::StringList,
               RealTable = Type::RealTable;

/// One choice of a Choice key: the word of the scene file and its enum value. A key's list of
/// words gives both its declared choices (in the reference's order) and its reading.
template <class E>
struct Word {
  std::string_view word;
  E value;
};

/// [[region]] and [calibrate] strength_spread.
inline constexpr Word<StrengthSpread> kSpread[] = {
    {"none", StrengthSpread::None}, {"normal", StrengthSpread::Normal}, {"weibull", StrengthSpread::Weibull}};

/// The declared choices of a list of words.
template <class E, std::size_t N>
std::vector<std::string> words(const Word<E> (&list)[N]) {
  std::vector<std::string> out;
  for (const auto& w : list) out.emplace_back(w.word);
  return out;
}

/// The word of a choice.
template <class E, std::size_t N>
std::string_view word_of(const Word<E> (&list)[N], E value) {
  for (const auto& w : list)
    if (w.value == value) return w.word;
  fail(ErrorKind::Internal, "scene: choice {} has no word", static_cast<int>(value));
}

/// Reads the keys of one validated Table into a struct's fields, each with its position.
class Reader {
 public:
  /// `table` is the schema name of the table ("solver", "region").
  Reader(const Table& t, std::string_view table);

  /// Reads `key` into `out`: the value (when the key has one), its position (the table header
  /// when defaulted or left out) and whether the user wrote it.
  template <class T>
  void operator()(const std::string& key, Located<T>& out) {
    if (locate(key, out)) out.value = value<T>(key);
  }
  /// Reads a Choice key into its enum through its list of words.
  template <class E, std::size_t N>
  void operator()(const std::string& key, Located<E>& out, const Word<E> (&list)[N]) {
    if (!locate(key, out)) return;
    const std::string& s = t_.str(key);
    const auto* w =
        std::find_if(std::begin(list), std::end(list), [&](const Word<E>& x) { return x.word == s; });
    if (w == std::end(list))
      fail(ErrorKind::Internal, "scene: {}.{} = \"{}\" has no enum value", t_.label(), key, s);
    out.value = w->value;
  }

  /// Throws an internal error unless every declared key of the table was read.
  void done() const;

 private:
  /// Position and given flag; false when the key has no value.
  template <class T>
  bool locate(const std::string& key, Located<T>& out) {
    read_.push_back(key);
    out.pos = t_.where(key);
    out.given = t_.given(key);
    return t_.has(key);
  }
  template <class T>
  T value(const std::string& key) const {
    if constexpr (std::is_same_v<T, bool>)
      return t_.boolean(key);
    else if constexpr (std::is_same_v<T, std::int64_t>)
      return t_.integer(key);
    else if constexpr (std::is_same_v<T, int>)
      return static_cast<int>(t_.integer(key));
    else if constexpr (std::is_same_v<T, double>)
      return t_.real(key);
    else if constexpr (std::is_same_v<T, std::string>)
      return t_.str(key);
    else if constexpr (std::is_same_v<T, std::filesystem::path>)
      return t_.path(key);
    else if constexpr (std::is_same_v<T, std::vector<double>>)
      return t_.reals(key);
    else if constexpr (std::is_same_v<T, std::vector<std::int64_t>>)
      return t_.integers(key);
    else if constexpr (std::is_same_v<T, std::vector<std::string>>)
      return t_.strings(key);
    else if constexpr (std::is_same_v<T, std::vector<std::vector<double>>>)
      return t_.real_table(key);
    else
      static_assert(sizeof(T) == 0, "no scene type for this field");
  }

  const Table& t_;
  const TableSpec& spec_;
  std::vector<std::string> read_;
};

// ---- one pair per table, in the order of the schema (and of docs/scene-reference.md) -------

TableSpec scene_spec();
SceneTable read_scene(const Table& t);

TableSpec material_spec();
MaterialTable read_material(const Table& t);

TableSpec region_spec();
RegionTable read_region(const Table& t);

TableSpec group_spec();
GroupTable read_group(const Table& t);

TableSpec boundary_spec();
BoundaryTable read_boundary(const Table& t);

TableSpec load_spec();
LoadTable read_load(const Table& t);

TableSpec wall_spec();
WallTable read_wall(const Table& t);

TableSpec solver_spec();
SolverTable read_solver(const Table& t);

TableSpec output_spec();
OutputTable read_output(const Table& t);

TableSpec probe_spec();
ProbeTable read_probe(const Table& t);

TableSpec coupled_spec();
CoupledTable read_coupled(const Table& t);

TableSpec calibrate_spec();
CalibrateTable read_calibrate(const Table& t);

TableSpec network_spec();
NetworkTable read_network(const Table& t);

TableSpec study_spec();
StudyTable read_study(const Table& t);
TableSpec vary_spec();
VaryTable read_vary(const Table& t);
TableSpec measure_spec();
MeasureTable read_measure(const Table& t);

}  // namespace strata::scene::tables
