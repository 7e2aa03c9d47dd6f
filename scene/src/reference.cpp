// docs/scene-reference.md, generated from the schema (the key declarations of scene/src/tables/,
// assembled by schema.cpp). The output depends only on schema(), so it is the same on every
// machine; test_scene checks the committed file.
#include <fmt/format.h>

#include <strata/scene/scene.hpp>

namespace strata::scene {
namespace {

/// Text safe inside a Markdown table cell.
std::string cell(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

std::string code_list(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "`" : ", `") + s + "`";
  return out;
}

std::string allowed(const KeySpec& k) {
  std::vector<std::string> parts;
  const bool list = k.type == Type::RealList || k.type == Type::IntegerList || k.type == Type::StringList;
  if (k.type == Type::Bool) parts.push_back("`true`, `false`");
  if (k.type == Type::Path) parts.push_back("an existing file");
  if (k.type == Type::Choice) parts.push_back(code_list(k.choices));
  if (list || k.type == Type::RealTable) {
    const char* what = k.type == Type::RealTable ? "rows of " : "";
    if (k.per_axis && k.type != Type::StringList) {
      parts.push_back(k.type == Type::RealTable ? "rows of one value per axis" : "one per axis");
    } else if (k.length_min > 0 || k.length_max > 0) {
      const int lo = k.length_min, hi = k.length_max;
      const bool single = (lo == hi || hi == 0) ? lo == 1 : (lo == 0 && hi == 1);
      std::string n = lo == hi  ? fmt::format("{}", lo)
                      : hi == 0 ? fmt::format("at least {}", lo)
                      : lo == 0 ? fmt::format("at most {}", hi)
                                : fmt::format("{} to {}", lo, hi);
      parts.push_back(fmt::format(
          "{}{} {}", what, n,
          k.type == Type::RealTable ? (single ? "value" : "values") : (single ? "entry" : "entries")));
    }
    if (k.type == Type::StringList && !k.choices.empty())
      parts.push_back((k.per_axis ? "axes of the scene among " : "each one of ") + code_list(k.choices));
  }
  const std::string range = range_text(k);
  if (!range.empty()) parts.push_back(list || k.type == Type::RealTable ? "each " + range : range);
  if (k.allow_inf) parts.push_back("`inf`");
  if (!k.cases.empty()) {
    std::string c;
    for (const auto& name : k.cases) c += (c.empty() ? "" : " or ") + ("`" + name + "`");
    parts.push_back("only for case " + c);
  }
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : "; ") + p;
  return out;
}

std::string default_text(const KeySpec& k) {
  if (k.required) return "**required**";
  if (!k.default_note.empty()) return k.default_note;
  if (k.default_value.empty()) return "";
  return "`" + k.default_value + "`";
}

}  // namespace

std::string reference_markdown() {
  std::string md;
  auto out = [&md](std::string_view text) { md += text; };

  out("# Scene file reference\n\n");
  out("<!-- Generated from the key declarations in scene/src/tables/ by `strata reference`; do not edit by "
      "hand. -->\n\n");
  out("A scene is a [TOML](https://toml.io) file. Quantities are in SI units (m, s, kg, N) as listed in the "
      "unit column. Paths are relative to the scene file. Any key can be changed from the command line with "
      "`--set table.key=value`, e.g. `--set solver.dt=1e-8`; entries of a list of tables are addressed by "
      "name "
      "or by 0-based index (`--set material.rock.kn=1e9`, `--set region[0].diameter=0.002`). Values given "
      "with "
      "`--set` are checked exactly like the file.\n\n");
  out("Integers are accepted where reals are expected, and reals without a fractional part (`3.2e7`) where "
      "integers are. Lists marked *one per axis* have 2 components (x, y) in a 2D scene and 3 (x, y, z) in "
      "a 3D one; their defaults are written for 3D and cut to the dimension. Unknown keys and tables are "
      "errors.\n\n");

  out("| table | |\n|---|---|\n");
  for (const TableSpec& t : schema()) {
    const std::string name = t.array ? "[[" + t.name + "]]" : "[" + t.name + "]";
    out(fmt::format("| [`{}`](#{}) | {} |\n", name, t.name, cell(t.doc)));
  }
  out("\n");

  for (const TableSpec& t : schema()) {
    out(fmt::format("## {}\n\n", t.array ? "[[" + t.name + "]]" : "[" + t.name + "]"));
    const char* presence = t.array
                               ? (t.required ? "Required: one or more entries." : "Any number of entries.")
                               : (t.required ? "Required." : "Optional: every key has a default.");
    std::vector<std::string> needed;  // an optional table with required keys, e.g. [coupled]
    for (const KeySpec& k : t.keys)
      if (k.required) needed.push_back(k.name);
    const std::string optional_with_required =
        fmt::format("Optional; when written, it needs {}.", code_list(needed));
    out(fmt::format("{} {}\n\n", t.doc,
                    !t.array && !t.required && !needed.empty() ? optional_with_required : presence));
    out("| key | type | unit | default | allowed | description |\n");
    out("|---|---|---|---|---|---|\n");
    for (const KeySpec& k : t.keys) {
      out(fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", k.name, type_name(k.type), cell(k.unit),
                      cell(default_text(k)), cell(allowed(k)), cell(k.doc)));
    }
    out("\n");
  }
  md.pop_back();  // one newline at the end
  return md;
}

}  // namespace strata::scene
