// Scene files: TOML parsing, `--set` overrides, validation against schema(), and the typed scene.
//
// The loader works in four passes; each pass collects its problems and throws the first one
// in file order (overrides first), so the message does not depend on map order:
//   1. TOML syntax (toml++ reports line:col);
//   2. `--set` overrides, applied onto the parsed tree (a bad address throws at once);
//   3. every table and key: known names, types, ranges, choices, files, list lengths;
//   4. checks between keys: shape-dependent keys, cross-references, unique names (checks.cpp).
// The validated tables are then read into the typed scene (tables/describe.cpp).
#include <strata/core/error.hpp>

#include <fmt/format.h>

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

#include "loader_text.hpp"
#include "table.hpp"

namespace strata::scene {

namespace fs = std::filesystem;

namespace {

using namespace text;  // loader_text.hpp

constexpr std::int64_t kLargestInteger = std::numeric_limits<std::int32_t>::max();
constexpr std::string_view kSetPath = "--set#";  // source path of override values: "--set#<index>"

struct Problem {
  SourcePos pos;
  int set_index;  // -1: in the file
  std::string message;
  bool last = false;  // reported after the others: a missing table, which has no position of its own
};

class Loader {
 public:
  Loader(const std::string& text, const fs::path& file, const std::vector<std::string>& overrides)
      : text_(text), file_(file), label_(file.string()), sets_(overrides) {
    fs::path dir = file.parent_path();
    dir_ = (dir.empty() ? fs::current_path() : fs::absolute(dir)).lexically_normal();
    lines_[label_] = split_lines(text);
  }

  Scene run() {
    toml::table root = parse_text();
    for (std::size_t i = 0; i < sets_.size(); ++i) apply_override(root, static_cast<int>(i));
    const Tables tables = check_tables(root);
    flush();
    check_between_keys(
        tables, [this](const SourcePos& pos, std::string message) { report(pos, std::move(message)); });
    flush();
    Scene scene;
    scene.file = file_;
    scene.dir = dir_;
    describe(tables, scene);
    return scene;
  }

 private:
  // -- positions and problems --

  SourcePos file_start() const { return {label_, 1, 1, {}}; }
  SourcePos set_pos(int i) const { return {"--set", 0, 0, sets_[static_cast<std::size_t>(i)]}; }

  /// -1 for a position in the file, else the index of the override.
  int set_index(const std::string* path) const {
    if (path && path->rfind(kSetPath, 0) == 0) return std::stoi(path->substr(kSetPath.size()));
    return -1;
  }

  SourcePos pos_of(const toml::source_region& s) const {
    const int i = set_index(s.path.get());
    if (i >= 0) return set_pos(i);
    if (s.begin.line == 0) return file_start();
    return {label_, static_cast<int>(s.begin.line), static_cast<int>(s.begin.column), {}};
  }

  SourcePos pos_of(const toml::node& n) const {
    auto it = created_.find(&n);
    if (it != created_.end()) return set_pos(it->second);
    return pos_of(n.source());
  }

  /// Position of a key in a table: the key itself, or its value when the key has none.
  SourcePos pos_of(const toml::key& k, const toml::node& value) const {
    if (k.source().begin.line > 0 && k.source().path && set_index(k.source().path.get()) < 0)
      return pos_of(k.source());
    return pos_of(value);
  }

  void report(const SourcePos& pos, std::string message, bool last = false) {
    int index = -1;
    if (pos.file == "--set")
      index = static_cast<int>(std::find(sets_.begin(), sets_.end(), pos.setting) - sets_.begin());
    problems_.push_back({pos, index, std::move(message), last});
  }

  /// Throws the first problem: overrides in order, then the file in line:col order, then
  /// missing tables.
  void flush() {
    if (problems_.empty()) return;
    auto order = [](const Problem& p) {
      return std::tuple(p.last, p.set_index < 0, p.set_index, p.pos.line, p.pos.column);
    };
    const auto first =
        std::min_element(problems_.begin(), problems_.end(),
                         [&](const Problem& a, const Problem& b) { return order(a) < order(b); });
    throw SceneError(ErrorKind::Input, first->pos.str() + ": " + first->message);
  }

  /// The value as the user wrote it (`-5`, `"fast"`), or TOML-formatted when that is unknown.
  std::string raw(const toml::node& n) const {
    const auto& s = n.source();
    if (s.path && s.begin.line > 0 && s.begin.line == s.end.line) {
      auto it = lines_.find(*s.path);
      if (it != lines_.end() && s.begin.line <= it->second.size()) {
        const std::string& line = it->second[s.begin.line - 1];
        const std::size_t b = s.begin.column - 1, e = s.end.column - 1;
        const bool ascii = std::all_of(line.begin(), line.begin() + std::min(e, line.size()),
                                       [](char c) { return static_cast<unsigned char>(c) < 0x80; });
        if (ascii && e > b && e <= line.size()) return line.substr(b, e - b);
      }
    }
    std::ostringstream out;
    if (auto f = n.as_floating_point()) {
      out << fmt::format("{}", f->get());
    } else {
      n.visit([&out](const auto& x) { out << x; });
    }
    return out.str();
  }

  /// "a string "fast"", "an integer 5", ...: what the user gave instead.
  std::string got(const toml::node& n) const {
    std::string r = raw(n);
    if (r.size() > 40) r = r.substr(0, 37) + "...";
    switch (n.type()) {
      case toml::node_type::string:
        return "a string " + r;
      case toml::node_type::integer:
        return "an integer " + r;
      case toml::node_type::floating_point:
        return "a real number " + r;
      case toml::node_type::boolean:
        return "a boolean " + r;
      case toml::node_type::array:
        return "a list " + r;
      case toml::node_type::table:
        return "a table";
      case toml::node_type::date:
        return "a date " + r;
      case toml::node_type::time:
        return "a time " + r;
      case toml::node_type::date_time:
        return "a date-time " + r;
      default:
        return "nothing";
    }
  }

  // -- pass 1: syntax --

  toml::table parse_text() const {
    try {
      return toml::parse(std::string_view(text_), std::string(label_));
    } catch (const toml::parse_error& e) {
      const auto& b = e.source().begin;
      fail_at({label_, static_cast<int>(b.line), static_cast<int>(b.column), {}},
              fmt::format("TOML syntax error: {}", e.description()));
    }
  }

  // -- pass 2: overrides --

  void apply_override(toml::table& root, int index) {
    const std::string& text = sets_[static_cast<std::size_t>(index)];
    const SourcePos at = set_pos(index);
    const auto eq = text.find('=');
    if (eq == std::string::npos)
      fail_at(at, "expected key=value, e.g. solver.dt=1e-8 or material.rock.kn=1e9");
    const std::string path = trim(std::string_view(text).substr(0, eq));
    const std::string value = trim(std::string_view(text).substr(eq + 1));

    // Address: table.key, table[i].key or table.name.key.
    std::vector<std::string> parts;
    for (std::size_t b = 0;;) {
      const auto dot = path.find('.', b);
      parts.push_back(path.substr(b, dot == std::string::npos ? std::string::npos : dot - b));
      if (dot == std::string::npos) break;
      b = dot + 1;
    }
    std::string tname = parts[0];
    std::optional<std::size_t> entry_index;
    if (const auto lb = tname.find('['); lb != std::string::npos) {
      const auto rb = tname.find(']', lb);
      const std::string digits = rb == std::string::npos ? "" : tname.substr(lb + 1, rb - lb - 1);
      if (digits.empty() || rb != tname.size() - 1 || !std::all_of(digits.begin(), digits.end(), [](char c) {
            return std::isdigit(static_cast<unsigned char>(c));
          }))
        fail_at(at, fmt::format("cannot read the index in '{}': write e.g. region[0].diameter", parts[0]));
      entry_index = std::stoul(digits);
      tname = tname.substr(0, lb);
    }
    const TableSpec* spec = find_table(tname);
    if (!spec) fail_at(at, unknown_table_message("[" + tname + "]", tname));

    toml::table* target = nullptr;
    std::string key;
    if (!spec->array) {
      if (entry_index || parts.size() != 2)
        fail_at(at, fmt::format("[{0}] is a single table: write {0}.<key>=<value>, e.g. {0}.{1}=...", tname,
                                spec->keys.front().name));
      key = parts[1];
      toml::node* node = root.get(tname);
      if (!node) {
        node = &root.insert(tname, toml::table{}).first->second;
        created_[node] = index;
      }
      target = node->as_table();
      if (!target)
        fail_at(at,
                fmt::format("cannot set {}: '{}' in the scene file is not a table [{}]", path, tname, tname));
    } else {
      const bool named = find_key(*spec, "name") != nullptr;
      const std::string example = named ? fmt::format("{0}.<name>.<key> or {0}[<index>].<key>", tname)
                                        : fmt::format("{}[<index>].<key>", tname);
      if (entry_index ? parts.size() != 2 : parts.size() != 3 || !named)
        fail_at(at, fmt::format("address one [[{}]] entry: write {}", tname, example));
      key = parts.back();
      toml::array* entries = root.get(tname) ? root.get(tname)->as_array() : nullptr;
      const std::size_t count = entries ? entries->size() : 0;
      if (entry_index) {
        if (*entry_index >= count)
          fail_at(at, count == 0
                          ? fmt::format("the scene has no [[{}]] entries", tname)
                          : fmt::format("index {} is out of range: the scene has {} [[{}]] entr{} "
                                        "(index 0 to {})",
                                        *entry_index, count, tname, count == 1 ? "y" : "ies", count - 1));
        target = (*entries)[*entry_index].as_table();
      } else {
        std::vector<std::string> names;
        for (std::size_t j = 0; j < count && !target; ++j) {
          auto* t = (*entries)[j].as_table();
          auto* n = t ? t->get_as<std::string>("name") : nullptr;
          if (!n) continue;
          if (n->get() == parts[1]) target = t;
          names.push_back(n->get());
        }
        if (!target)
          fail_at(at,
                  fmt::format("no [[{}]] named '{}'{} ({})", tname, parts[1], did_you_mean(parts[1], names),
                              names.empty() ? "there are none" : "names: " + join(names)));
      }
      if (!target) fail_at(at, fmt::format("[[{}]] entry {} is not a table", tname, *entry_index));
    }
    if (!find_key(*spec, key)) fail_at(at, unknown_key_message(key, *spec));

    // The value: a TOML value, or else the text as a string (so render_field=damage works).
    const std::string source = std::string(kSetPath) + std::to_string(index);
    toml::table doc;
    for (const std::string& attempt : {"v = " + value, "v = " + toml_quote(value)}) {
      try {
        doc = toml::parse(std::string_view(attempt), std::string(source));
      } catch (const toml::parse_error&) {
        continue;
      }
      if (doc.size() == 1 && doc.get("v")) {
        lines_[source] = {attempt};
        break;
      }
      doc = toml::table{};
    }
    toml::node* v = doc.get("v");
    if (!v) fail_at(at, "cannot read the value");  // unreachable: a quoted string always parses
    target->insert_or_assign(key, std::move(*v));
  }

  // -- pass 3: tables and keys --

  Tables check_tables(const toml::table& root) {
    Tables scene;

    // [scene] first: its dimension decides list lengths and defaults everywhere else.
    dim_ = 0;
    if (auto* s = root.get("scene"); s && s->is_table()) {
      auto* d = s->as_table()->get("dimension");
      if (d && d->is_integer() && (d->as_integer()->get() == 2 || d->as_integer()->get() == 3))
        dim_ = static_cast<int>(d->as_integer()->get());
    }

    for (auto&& [k, node] : root) {
      const TableSpec* spec = find_table(k.str());
      const bool is_table = node.is_table();
      const bool is_array_of_tables = node.is_array_of_tables();
      if (!spec) {
        if (is_table || is_array_of_tables) {
          const std::string written =
              is_table ? "[" + std::string(k.str()) + "]" : "[[" + std::string(k.str()) + "]]";
          report(pos_of(node), unknown_table_message(written, k.str()));
        } else {
          std::vector<std::string> owners;
          for (const auto& t : schema())
            if (find_key(t, k.str())) owners.push_back(bracket(t));
          report(pos_of(k, node), owners.empty()
                                      ? fmt::format("unknown key '{}' outside any table (tables: {})",
                                                    k.str(), join(table_names()))
                                      : fmt::format("key '{}' is outside any table; it belongs in {}",
                                                    k.str(), join(owners, " or ")));
        }
        continue;
      }
      if (spec->array && is_table) {
        report(pos_of(node),
               fmt::format("[{0}] must be written [[{0}]]: it is a list of tables, one per {0}", spec->name));
      } else if (!spec->array && is_array_of_tables) {
        report(pos_of(node),
               fmt::format("[[{0}]] must be written [{0}]: there is one [{0}] table", spec->name));
      } else if (spec->array && !node.is_array()) {
        report(pos_of(k, node), fmt::format("'{0}' must be a list of tables, written [[{0}]], got {1}",
                                            spec->name, got(node)));
      } else if (!spec->array && !is_table) {
        report(pos_of(k, node),
               fmt::format("'{0}' must be a table, written [{0}], got {1}", spec->name, got(node)));
      } else if (spec->array) {
        const auto& arr = *node.as_array();
        for (std::size_t j = 0; j < arr.size(); ++j) {
          if (!arr[j].is_table())
            report(pos_of(arr[j]), fmt::format("'{0}' must be a list of tables, written [[{0}]], got {1}",
                                               spec->name, got(arr[j])));
        }
      }
    }

    // A file with a job table ([coupled], [calibrate]) describes the whole job in it: the
    // other tables cannot be mixed with it, and of [output] only some keys apply.
    const JobTable* job = nullptr;
    const toml::node* job_node = nullptr;
    for (const JobTable& j : job_tables()) {
      const toml::node* n = root.get(j.name);
      if (!n || !n->is_table()) continue;
      if (job) {
        report(pos_of(*n), fmt::format("[{}] cannot be mixed with [{}] ({}): a file holds one of them",
                                       j.name, job->name, pos_of(*job_node).str()));
        continue;
      }
      job = &j, job_node = n;
    }
    const std::string job_at = job ? pos_of(*job_node).str() : "";
    std::vector<std::string> job_besides;
    if (job)
      for (const auto& name : job->besides) job_besides.push_back(bracket(*find_table(name)));
    auto job_allows = [&](const std::string& table) {
      return table == job->name ||
             std::find(job->besides.begin(), job->besides.end(), table) != job->besides.end();
    };

    for (const TableSpec& spec : schema()) {
      const toml::node* node = root.get(spec.name);
      std::vector<Table>& out = scene.entries[spec.name];
      const bool is_job_table = std::any_of(job_tables().begin(), job_tables().end(),
                                            [&](const JobTable& j) { return j.name == spec.name; });
      if (is_job_table && (!job || job->name != spec.name)) continue;  // no entry: not that kind of file
      if (job && !job_allows(spec.name)) {
        if (node) {
          const toml::array* arr = node->as_array();
          report(arr && !arr->empty() ? pos_of((*arr)[0]) : pos_of(*node),
                 fmt::format("{} cannot be mixed with [{}] ({}): {} {} and may hold besides only {} "
                             "(keys {}); remove {} or [{}]",
                             bracket(spec), job->name, job_at, job->kind, job->what, join(job_besides),
                             join(job->output_keys), bracket(spec), job->name));
        }
        if (!spec.array) out.push_back(check_table(spec, nullptr, spec.name, file_start(), 0));
        continue;
      }
      if (job && spec.name == "output" && node && node->is_table()) {
        for (auto&& [k, v] : *node->as_table()) {
          if (!find_key(spec, k.str()) ||
              std::find(job->output_keys.begin(), job->output_keys.end(), k.str()) != job->output_keys.end())
            continue;  // unknown keys are reported by check_table
          report(pos_of(k, v),
                 fmt::format("output.{} does not apply to {} ([{}] at {}): its [output] takes only {}",
                             k.str(), job->kind, job->name, job_at, join(job->output_keys)));
        }
      }
      if (spec.array) {
        const toml::array* arr = node ? node->as_array() : nullptr;
        if (arr) {
          for (std::size_t j = 0; j < arr->size(); ++j)
            if (auto* t = (*arr)[j].as_table())
              out.push_back(check_table(spec, t, fmt::format("{}[{}]", spec.name, j), pos_of(*t), j));
        }
        if (spec.required && (!node || (arr && arr->empty())))
          report(node ? pos_of(*node) : file_start(),
                 fmt::format("missing required table {} ({})", bracket(spec), first_sentence(spec.doc)),
                 !node);
      } else {
        const toml::table* t = node ? node->as_table() : nullptr;
        out.push_back(check_table(spec, t, spec.name, t ? pos_of(*t) : file_start(), 0));
        if (spec.required && !node)
          report(file_start(),
                 fmt::format("missing required table {} ({})", bracket(spec), first_sentence(spec.doc)),
                 true);
      }
    }
    return scene;
  }

  /// "[[region]] 'specimen'", "[[boundary]] at index 1", "[solver]".
  static std::string title(const TableSpec& spec, const toml::table* t, std::size_t index) {
    if (!spec.array) return bracket(spec);
    if (auto* n = t ? t->get_as<std::string>("name") : nullptr)
      return fmt::format("{} '{}'", bracket(spec), n->get());
    return fmt::format("{} at index {}", bracket(spec), index);
  }

  Table check_table(const TableSpec& spec, const toml::table* t, const std::string& label,
                    const SourcePos& header, std::size_t index) {
    Table out(label, header);
    std::set<std::string> suggested;  // keys that an unknown key is probably a misspelling of
    if (t) {
      for (auto&& [k, node] : *t) {
        const KeySpec* key = find_key(spec, k.str());
        if (!key) {
          report(pos_of(k, node), unknown_key_message(k.str(), spec));
          if (auto c = closest(k.str(), key_names(spec))) suggested.insert(*c);
          continue;
        }
        if (auto v = convert(*key, node)) out.set(key->name, std::move(*v));
      }
    }
    for (const KeySpec& key : spec.keys) {
      if (t && t->contains(key.name)) continue;
      if (key.required) {
        // Not reported: a required table that is absent (reported once, as missing), and a key
        // the user misspelt (the unknown-key message says "did you mean").
        if ((t || !spec.required) && !suggested.count(key.name))
          report(header, fmt::format("{} is missing required key '{}' ({})", title(spec, t, index), key.name,
                                     first_sentence(key.doc)));
      } else if (!key.default_value.empty()) {
        out.set(key.name, default_value(key, header));
      }
    }
    return out;
  }

  /// The declared default, as a Value; per-axis lists are cut to the scene's dimension.
  Value default_value(const KeySpec& key, const SourcePos& header) {
    const std::size_t before = problems_.size();
    toml::table doc = toml::parse(std::string_view("v = " + key.default_value), std::string_view("default"));
    const int dim = std::exchange(dim_, 0);  // defaults are written for 3D: cut below, not checked
    auto v = convert(key, *doc.get("v"));
    dim_ = dim;
    if (!v || problems_.size() != before)
      throw Error(ErrorKind::Internal,
                  fmt::format("scene schema: bad default for '{}': {}", key.name,
                              problems_.size() != before ? problems_.back().message : ""));
    v->given = false;
    v->pos = header;
    if (key.per_axis && dim_ > 0) {
      if (v->reals.size() > static_cast<std::size_t>(dim_)) v->reals.resize(static_cast<std::size_t>(dim_));
      if (v->strings.size() > static_cast<std::size_t>(dim_))
        v->strings.resize(static_cast<std::size_t>(dim_));
    }
    return *v;
  }

  std::optional<Value> type_error(const KeySpec& key, const std::string& name, const toml::node& n) {
    std::string expected;
    switch (key.type) {
      case Type::Bool:
        expected = "true or false";
        break;
      case Type::Integer:
        expected = "an integer";
        break;
      case Type::Real:
        expected = "a real number";
        break;
      case Type::String:
        expected = "a string";
        break;
      case Type::Choice:
        expected = "one of " + join(key.choices);
        break;
      case Type::Path:
        expected = "a file path (a string)";
        break;
      case Type::OutputPath:
        expected = "a path (a string)";
        break;
      case Type::RealList:
        expected = "a list of real numbers";
        break;
      case Type::IntegerList:
        expected = "a list of integers";
        break;
      case Type::StringList:
        expected = "a list of strings";
        break;
      case Type::RealTable:
        expected = "a list of rows of real numbers, e.g. [[0, 0], [1, 0]]";
        break;
    }
    report(pos_of(n), fmt::format("{} must be {}{}, got {}", name, expected, unit_suffix(key), got(n)));
    return std::nullopt;
  }

  /// A real number (integers accepted) within the key's range; `name` is "kn" or "size[1]".
  std::optional<double> real_of(const KeySpec& key, const std::string& name, const toml::node& n) {
    double x = 0;
    if (auto i = n.as_integer()) {
      x = static_cast<double>(i->get());
    } else if (auto f = n.as_floating_point()) {
      x = f->get();
    } else {
      report(pos_of(n), fmt::format("{} must be a real number{}, got {}", name, unit_suffix(key), got(n)));
      return std::nullopt;
    }
    if (std::isnan(x)) {
      report(pos_of(n), fmt::format("{} = {} must be a number{}", name, raw(n), unit_suffix(key)));
      return std::nullopt;
    }
    if (std::isinf(x) && !(key.allow_inf && x > 0 && key.type == Type::Real)) {
      report(pos_of(n), fmt::format("{} = {} must be finite{}", name, raw(n), unit_suffix(key)));
      return std::nullopt;
    }
    if (!in_range(key, x)) {
      report(pos_of(n), fmt::format("{} = {} must be {}{}", name, raw(n), range_text(key), unit_suffix(key)));
      return std::nullopt;
    }
    return x;
  }

  std::optional<std::int64_t> integer_of(const KeySpec& key, const std::string& name, const toml::node& n) {
    std::int64_t i = 0;
    if (auto v = n.as_integer()) {
      i = v->get();
    } else if (auto f = n.as_floating_point()) {
      // 3.2e7 is a fine way to write a step count; 1.5 is not a count.
      const double x = f->get();
      if (!std::isfinite(x) || std::floor(x) != x || std::abs(x) > 9.0e15) {
        report(pos_of(n),
               fmt::format("{} must be an integer{}, got a real number {}", name, unit_suffix(key), raw(n)));
        return std::nullopt;
      }
      i = static_cast<std::int64_t>(x);
    } else if (key.type == Type::IntegerList) {  // an entry of a list
      report(pos_of(n), fmt::format("{} must be an integer{}, got {}", name, unit_suffix(key), got(n)));
      return std::nullopt;
    } else {
      type_error(key, name, n);
      return std::nullopt;
    }
    if (!in_range(key, static_cast<double>(i))) {
      report(pos_of(n), fmt::format("{} = {} must be {}{}", name, raw(n), range_text(key), unit_suffix(key)));
      return std::nullopt;
    }
    // Counts, ratios and cadences end up in ints: a larger value would wrap round (η =
    // 4294967297 ran as η = 1). No key needs more.
    if (i > kLargestInteger || i < -kLargestInteger) {
      report(pos_of(n), fmt::format("{} = {} is too large: integers in a scene are at most {} in size", name,
                                    raw(n), kLargestInteger));
      return std::nullopt;
    }
    return i;
  }

  fs::path resolve(const std::string& p) const {
    fs::path q(p);
    return q.is_absolute() ? q.lexically_normal() : (dir_ / q).lexically_normal();
  }

  /// Checks the number of entries of a list (or of a table row) against the key's lengths and,
  /// for per-axis keys, against the scene dimension.
  bool length_ok(const KeySpec& key, const std::string& name, std::size_t n, const toml::node& node,
                 std::string_view one, std::string_view many) {
    if (key.per_axis && dim_ > 0 && key.type != Type::StringList) {
      if (n == static_cast<std::size_t>(dim_)) return true;
      report(pos_of(node), fmt::format("{} has {} {}, but the scene is {}D: give one per axis ({})", name, n,
                                       n == 1 ? "component" : "components", dim_, axes_text(dim_)));
      return false;
    }
    const auto lo = static_cast<std::size_t>(key.length_min), hi = static_cast<std::size_t>(key.length_max);
    if ((lo == 0 || n >= lo) && (hi == 0 || n <= hi)) return true;
    report(pos_of(node), fmt::format("{} must have {}, got {}", name,
                                     count_text(key.length_min, key.length_max, one, many), n));
    return false;
  }

  std::optional<Value> convert(const KeySpec& key, const toml::node& n) {
    Value v;
    v.type = key.type;
    v.pos = pos_of(n);
    v.given = true;
    const std::string& name = key.name;
    switch (key.type) {
      case Type::Bool: {
        auto b = n.as_boolean();
        if (!b) return type_error(key, name, n);
        v.b = b->get();
        return v;
      }
      case Type::Integer: {
        auto i = integer_of(key, name, n);
        if (!i) return std::nullopt;
        v.i = *i;
        return v;
      }
      case Type::Real: {
        auto r = real_of(key, name, n);
        if (!r) return std::nullopt;
        v.r = *r;
        return v;
      }
      case Type::String:
      case Type::Choice:
      case Type::Path:
      case Type::OutputPath: {
        auto s = n.as_string();
        if (!s) return type_error(key, name, n);
        v.s = s->get();
        if (key.type == Type::Choice &&
            std::find(key.choices.begin(), key.choices.end(), v.s) == key.choices.end()) {
          report(v.pos, fmt::format("{} = {} must be one of {}{}", name, raw(n), join(key.choices),
                                    did_you_mean(v.s, key.choices)));
          return std::nullopt;
        }
        if (key.type == Type::Path || key.type == Type::OutputPath) {
          if (v.s.empty()) {
            report(v.pos, fmt::format("{} must not be empty", name));
            return std::nullopt;
          }
          const fs::path p = resolve(v.s);
          if (key.type == Type::Path) {
            std::error_code ec;
            if (!fs::exists(p, ec)) {
              report(v.pos,
                     fmt::format("{} '{}' not found (looked for {}; paths are relative to the scene file)",
                                 name, v.s, p.string()));
              return std::nullopt;
            }
            if (fs::is_directory(p, ec)) {
              report(v.pos, fmt::format("{} '{}' is a folder, not a file ({})", name, v.s, p.string()));
              return std::nullopt;
            }
          }
          v.s = p.string();
        }
        return v;
      }
      case Type::RealList: {
        auto a = n.as_array();
        if (!a) return type_error(key, name, n);
        bool ok = length_ok(key, name, a->size(), n, "entry", "entries");
        for (std::size_t j = 0; j < a->size(); ++j) {
          auto x = real_of(key, fmt::format("{}[{}]", name, j), (*a)[j]);
          if (x) v.reals.push_back(*x);
          ok = ok && x.has_value();
        }
        if (!ok) return std::nullopt;
        return v;
      }
      case Type::IntegerList: {
        auto a = n.as_array();
        if (!a) return type_error(key, name, n);
        bool ok = length_ok(key, name, a->size(), n, "entry", "entries");
        for (std::size_t j = 0; j < a->size(); ++j) {
          auto x = integer_of(key, fmt::format("{}[{}]", name, j), (*a)[j]);
          if (x) v.integers.push_back(*x);
          ok = ok && x.has_value();
        }
        if (!ok) return std::nullopt;
        return v;
      }
      case Type::StringList: {
        auto a = n.as_array();
        if (!a) return type_error(key, name, n);
        bool ok = length_ok(key, name, a->size(), n, "entry", "entries");
        std::vector<std::string> allowed = key.choices;
        if (key.per_axis && dim_ > 0)
          allowed.resize(std::min(allowed.size(), static_cast<std::size_t>(dim_)));
        for (std::size_t j = 0; j < a->size(); ++j) {
          const toml::node& e = (*a)[j];
          auto s = e.as_string();
          if (!s) {
            report(pos_of(e), fmt::format("{}[{}] must be a string, got {}", name, j, got(e)));
            ok = false;
            continue;
          }
          const std::string& str = s->get();
          if (!key.choices.empty() && std::find(allowed.begin(), allowed.end(), str) == allowed.end()) {
            const bool other_axis =
                key.per_axis && std::find(key.choices.begin(), key.choices.end(), str) != key.choices.end();
            report(pos_of(e), other_axis ? fmt::format("{}: '{}' is not an axis of a {}D scene (allowed: {})",
                                                       name, str, dim_, join(allowed))
                                         : fmt::format("{}: '{}' must be one of {}{}", name, str,
                                                       join(allowed), did_you_mean(str, allowed)));
            ok = false;
            continue;
          }
          if (std::find(v.strings.begin(), v.strings.end(), str) != v.strings.end()) {
            report(pos_of(e), fmt::format("{}: '{}' is listed twice", name, str));
            ok = false;
            continue;
          }
          v.strings.push_back(str);
        }
        if (!ok) return std::nullopt;
        return v;
      }
      case Type::RealTable: {
        auto a = n.as_array();
        if (!a) return type_error(key, name, n);
        bool ok = true;
        for (std::size_t j = 0; j < a->size(); ++j) {
          const toml::node& row = (*a)[j];
          const std::string row_name = fmt::format("{}[{}]", name, j);
          auto r = row.as_array();
          if (!r) {
            report(pos_of(row), fmt::format("{} must be a list of real numbers{}, got {}", row_name,
                                            unit_suffix(key), got(row)));
            ok = false;
            continue;
          }
          ok = length_ok(key, row_name, r->size(), row, "component", "components") && ok;
          std::vector<double> values;
          for (std::size_t c = 0; c < r->size(); ++c) {
            auto x = real_of(key, fmt::format("{}[{}]", row_name, c), (*r)[c]);
            if (x) values.push_back(*x);
            ok = ok && x.has_value();
          }
          v.table.push_back(std::move(values));
        }
        if (!ok) return std::nullopt;
        return v;
      }
    }
    return std::nullopt;
  }

  // -- pass 4: checks between keys (checks.cpp) --

  const std::string& text_;
  fs::path file_;
  std::string label_;
  fs::path dir_;
  std::vector<std::string> sets_;
  std::map<std::string, std::vector<std::string>> lines_;  // by source path: for raw()
  std::map<const toml::node*, int> created_;               // tables created by an override
  std::vector<Problem> problems_;
  int dim_ = 0;  // [scene].dimension once known to be valid, else 0
};

}  // namespace

Scene parse(const std::string& text, const fs::path& file, const std::vector<std::string>& overrides) {
  return Loader(text, file, overrides).run();
}

Scene load(const fs::path& file, const std::vector<std::string>& overrides) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw Error(ErrorKind::Input, fmt::format("{}: cannot read the scene file (looked for {})", file.string(),
                                              fs::absolute(file).lexically_normal().string()));
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), file, overrides);
}

}  // namespace strata::scene
