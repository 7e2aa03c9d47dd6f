// The schema: every table a scene file may hold, in the order of docs/scene-reference.md.
// Each table's keys are declared in its own file under tables/, next to the function that
// reads them into the table's struct (description.hpp); the loader checks scene files against
// these declarations and `strata reference` writes docs/scene-reference.md from them, so the
// three cannot disagree.
#include <strata/scene/scene.hpp>

#include <fmt/format.h>

#include <algorithm>

#include "tables/table_file.hpp"

namespace strata::scene {
namespace {

std::vector<TableSpec> make_schema() {
  using namespace tables;
  return {scene_spec(),     material_spec(), region_spec(), group_spec(),  boundary_spec(), load_spec(),
          wall_spec(),      solver_spec(),   output_spec(), probe_spec(),  network_spec(),  coupled_spec(),
          calibrate_spec(), study_spec(),    vary_spec(),   measure_spec()};
}

}  // namespace

const std::vector<TableSpec>& schema() {
  static const std::vector<TableSpec> s = make_schema();
  return s;
}

const std::vector<JobTable>& job_tables() {
  static const std::vector<JobTable> t{
      {"coupled",
       {"output"},
       {"directory", "render"},
       "a coupled scene",
       "describes the whole model in [coupled]"},
      {"network",
       {"solver", "output"},
       {"directory", "probe_every", "checkpoint_every", "render"},
       "a network scene",
       "describes the whole model in [network]"},
      {"study",
       {"vary", "measure", "output"},
       {"directory", "render"},
       "a study",
       "runs the scene it names over the values of its [[vary]] keys"},
      {"calibrate",
       {"scene", "output"},
       {"directory", "render"},
       "a calibration",
       "describes its targets and lattice in [calibrate] and builds its own specimens"}};
  return t;
}

std::vector<std::string> coupled_case_keys(const std::string& case_name) {
  std::vector<std::string> out;
  for (const TableSpec& t : schema())
    if (t.name == "coupled")
      for (const KeySpec& k : t.keys)
        if (k.cases.empty() || std::find(k.cases.begin(), k.cases.end(), case_name) != k.cases.end())
          out.push_back(k.name);
  return out;
}

std::string range_text(const KeySpec& key) {
  const bool integer = key.type == Type::Integer;
  if (integer && key.min && key.max && !key.min_exclusive && !key.max_exclusive && *key.max - *key.min <= 3) {
    // A few whole numbers: list them ("2 or 3").
    std::string out;
    for (auto v = static_cast<long long>(*key.min); v <= static_cast<long long>(*key.max); ++v) {
      if (!out.empty()) out += v == static_cast<long long>(*key.max) ? " or " : ", ";
      out += fmt::format("{}", v);
    }
    return out;
  }
  std::string lo = key.min ? fmt::format("{} {}", key.min_exclusive ? ">" : ">=", *key.min) : "";
  std::string hi = key.max ? fmt::format("{} {}", key.max_exclusive ? "<" : "<=", *key.max) : "";
  if (!lo.empty() && !hi.empty()) return lo + " and " + hi;
  return lo + hi;
}

std::string type_name(Type type) {
  switch (type) {
    case Type::Bool:
      return "bool";
    case Type::Integer:
      return "integer";
    case Type::Real:
      return "real";
    case Type::String:
      return "string";
    case Type::Choice:
      return "choice";
    case Type::Path:
      return "path";
    case Type::OutputPath:
      return "output path";
    case Type::RealList:
      return "list of reals";
    case Type::IntegerList:
      return "list of integers";
    case Type::StringList:
      return "list of strings";
    case Type::RealTable:
      return "list of rows of reals";
  }
  return "?";
}

}  // namespace strata::scene
