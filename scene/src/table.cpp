// The loader's validation layer: positions, and validated values stored by key name.
#include "table.hpp"

#include <strata/core/error.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace strata::scene {

std::string SourcePos::str() const {
  if (file == "--set") return "--set " + setting;
  if (line <= 0) return file;
  return fmt::format("{}:{}:{}", file, line, column);
}

void fail_at(const SourcePos& pos, const std::string& message) {
  throw SceneError(ErrorKind::Input, pos.str() + ": " + message);
}

SourcePos Table::where(const std::string& key) const {
  auto it = values_.find(key);
  return it != values_.end() && it->second.given ? it->second.pos : pos_;
}

bool Table::given(const std::string& key) const {
  auto it = values_.find(key);
  return it != values_.end() && it->second.given;
}

bool Table::has(const std::string& key) const { return values_.count(key) != 0; }

const Value& Table::get(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end())
    throw Error(ErrorKind::Internal,
                fmt::format("scene: {}.{} has no value (not declared, or optional and not given: "
                            "check has() first)",
                            label_, key));
  return it->second;
}

namespace {
[[noreturn]] void wrong_access(const std::string& label, const std::string& key, const char* as) {
  throw Error(ErrorKind::Internal,
              fmt::format("scene: {}.{} read as {}, which is not its declared type", label, key, as));
}
}  // namespace

bool Table::boolean(const std::string& key) const {
  const Value& v = get(key);
  if (v.type != Type::Bool) wrong_access(label_, key, "a bool");
  return v.b;
}

std::int64_t Table::integer(const std::string& key) const {
  const Value& v = get(key);
  if (v.type != Type::Integer) wrong_access(label_, key, "an integer");
  return v.i;
}

double Table::real(const std::string& key) const {
  const Value& v = get(key);
  if (v.type == Type::Integer) return static_cast<double>(v.i);
  if (v.type != Type::Real) wrong_access(label_, key, "a real");
  return v.r;
}

const std::string& Table::str(const std::string& key) const {
  const Value& v = get(key);
  if (v.type != Type::String && v.type != Type::Choice && v.type != Type::Path && v.type != Type::OutputPath)
    wrong_access(label_, key, "a string");
  return v.s;
}

const std::vector<double>& Table::reals(const std::string& key) const {
  const Value& v = get(key);
  if (v.type != Type::RealList) wrong_access(label_, key, "a list of reals");
  return v.reals;
}

const std::vector<std::int64_t>& Table::integers(const std::string& key) const {
  const Value& v = get(key);
  if (v.type != Type::IntegerList) wrong_access(label_, key, "a list of integers");
  return v.integers;
}

const std::vector<std::string>& Table::strings(const std::string& key) const {
  const Value& v = get(key);
  if (v.type != Type::StringList) wrong_access(label_, key, "a list of strings");
  return v.strings;
}

const std::vector<std::vector<double>>& Table::real_table(const std::string& key) const {
  const Value& v = get(key);
  if (v.type != Type::RealTable) wrong_access(label_, key, "a list of rows of reals");
  return v.table;
}

const Table& Tables::table(const std::string& name) const {
  auto it = entries.find(name);
  const bool plain = std::any_of(schema().begin(), schema().end(),
                                 [&](const TableSpec& t) { return t.name == name && !t.array; });
  if (!plain || it == entries.end() || it->second.size() != 1)
    throw Error(ErrorKind::Internal,
                fmt::format("scene: no single table [{}] (not declared, or an array)", name));
  return it->second.front();
}

const std::vector<Table>& Tables::tables(const std::string& name) const {
  static const std::vector<Table> none;
  auto it = entries.find(name);
  return it == entries.end() ? none : it->second;
}

}  // namespace strata::scene
