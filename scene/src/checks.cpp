// Pass 4 of the loader: checks between the keys of a scene (shape-dependent keys,
// cross-references, unique names, [coupled] keys against its case), on the validated tables.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <strata/preprocess/geometry.hpp>

#include "loader_text.hpp"
#include "table.hpp"

namespace strata::scene {

namespace fs = std::filesystem;

namespace {

using namespace text;

class KeyChecks {
 public:
  explicit KeyChecks(const ReportProblem& report) : report_(report) {}

  static std::string entry_title(const TableSpec& spec, const Table& t) {
    if (!spec.array) return bracket(spec);
    if (t.has("name")) return fmt::format("{} '{}'", bracket(spec), t.str("name"));
    const std::string& l = t.label();
    return fmt::format("{} at index {}", bracket(spec),
                       l.substr(l.find('[') + 1, l.size() - l.find('[') - 2));
  }

  /// `key` of `t` must be one of `names`, the names of `what` ("[[material]]").
  void check_reference(const Table& t, const std::string& key, const std::string& what,
                       const std::vector<std::string>& names, const std::string& why = "") {
    const std::string& v = t.str(key);
    if (std::find(names.begin(), names.end(), v) != names.end()) return;
    report(t.where(key),
           fmt::format("{} = \"{}\" names no {}{}{} ({})", key, v, what, why, did_you_mean(v, names),
                       names.empty() ? "there are none" : "defined: " + join(names)));
  }

  /// Names of the entries of an array table; a repeated name is a problem.
  std::vector<std::string> unique_names(const Tables& scene, const std::string& table) {
    std::vector<std::string> names;
    const auto& entries = scene.tables(table);
    for (std::size_t j = 0; j < entries.size(); ++j) {
      const std::string& n = entries[j].str("name");
      if (n.empty()) report(entries[j].where("name"), "name must not be empty");
      const auto it = std::find(names.begin(), names.end(), n);
      if (it != names.end()) {
        report(entries[j].where("name"),
               fmt::format("[[{}]] name '{}' is used twice (first at {})", table, n,
                           entries[static_cast<std::size_t>(it - names.begin())].where("name").str()));
      }
      names.push_back(n);
    }
    return names;
  }

  /// `t` must have `key` when `condition_key` has the value that needs it.
  void need(const TableSpec& spec, const Table& t, const std::string& key, const std::string& condition_key) {
    if (t.has(key)) return;
    report(t.where(condition_key),
           fmt::format("{} needs '{}' for {} = \"{}\" ({})", entry_title(spec, t), key, condition_key,
                       t.str(condition_key), first_sentence(find_key(spec, key)->doc)));
  }

  /// Checks between the keys of [coupled] (stability needs the model: report.cpp, wave_report.cpp).
  void check_coupled(const Tables& scene) {
    const Table& c = scene.table("coupled");
    const TableSpec& spec = *find_table("coupled");
    const std::string& name = c.str("case");
    // A key declared for other cases (KeySpec::cases) is refused, naming what this case takes.
    for (const KeySpec& k : spec.keys) {
      if (k.cases.empty() || !c.given(k.name) ||
          std::find(k.cases.begin(), k.cases.end(), name) != k.cases.end())
        continue;
      std::vector<std::string> quoted;
      for (const auto& other : k.cases) quoted.push_back("\"" + other + "\"");
      report(c.where(k.name),
             fmt::format("{} applies only to case = {} (this scene has case = \"{}\"); remove "
                         "it (case = \"{}\" takes: {})",
                         k.name, join(quoted, " or "), name, name, join(coupled_case_keys(name))));
    }
    const bool wave = name == "wave";
    if (wave) {
      need(spec, c, "geometry", "case");
    } else {
      need(spec, c, "dt_dem", "case");
    }
    // Not given: the case's default list (the chains': the paper's, up to 20).
    const std::vector<std::int64_t> etas = c.has("eta") ? c.integers("eta") : std::vector<std::int64_t>{20};
    for (std::size_t j = 0; j < etas.size(); ++j) {
      if (std::find(etas.begin(), etas.begin() + static_cast<std::ptrdiff_t>(j), etas[j]) !=
          etas.begin() + static_cast<std::ptrdiff_t>(j)) {
        report(c.where("eta"), fmt::format("eta: {} is listed twice", etas[j]));
        break;
      }
    }
    if (wave || etas.empty() || !c.has("dt_dem")) return;
    const double duration = c.real("duration") > 0 ? c.real("duration") : name == "chain6" ? 20.0 : 0.075;
    const std::int64_t eta_max = *std::max_element(etas.begin(), etas.end());
    const double dt_fem = static_cast<double>(eta_max) * c.real("dt_dem");
    if (std::floor(duration / dt_fem + 1e-9) < 1)
      report(c.given("duration") ? c.where("duration") : c.where("eta"),
             fmt::format("duration = {:g} s holds no FEM step of eta = {} (eta*dt_dem = {:g} s): lengthen "
                         "duration or lower eta",
                         duration, eta_max, dt_fem));
  }

  /// A spread of bond strengths needs its coefficient of variation ([[region]], [calibrate]).
  void check_spread(const Table& t) {
    if (t.str("strength_spread") != "none" && !(t.real("strength_cov") > 0))
      report(t.given("strength_cov") ? t.where("strength_cov") : t.where("strength_spread"),
             fmt::format("strength_spread = \"{}\" needs strength_cov > 0 (the coefficient of variation "
                         "of the bond strengths, e.g. 0.2)",
                         t.str("strength_spread")));
  }

  /// Checks between the keys of [calibrate] and [scene].dimension.
  void check_calibrate(const Tables& scene) {
    const Table& c = scene.table("calibrate");
    check_spread(c);
    const int dim = static_cast<int>(scene.table("scene").integer("dimension"));
    const std::string& lattice = c.str("lattice");
    if (lattice == "hex" && dim == 3)
      report(c.where("lattice"), "lattice = \"hex\" is for 2D calibrations; in 3D use hcp or fcc (or auto)");
    if ((lattice == "hcp" || lattice == "fcc") && dim == 2)
      report(c.where("lattice"),
             fmt::format("lattice = \"{}\" is for 3D calibrations; in 2D use hex (or auto)", lattice));
    // Kn/Ks lattices: nu = (1 - r)/(3 + r) in 2D, (1 - r)/(5 + r) along z in 3D, r = Ks/Kn >= 0.
    const double nu_max = dim == 2 ? 1.0 / 3.0 : 0.2;
    if (c.real("poisson_ratio") > nu_max)
      report(c.where("poisson_ratio"),
             fmt::format("poisson_ratio = {} is above {}, the largest that bonds of normal and shear springs "
                         "give {} (with Ks = 0); allowed: -1 < poisson_ratio <= {}",
                         c.real("poisson_ratio"), dim == 2 ? "1/3" : "1/5",
                         dim == 2 ? "a hexagonal lattice" : "a close packing along its stacking axis",
                         dim == 2 ? "1/3" : "0.2"));
    if (c.real("ucs") <= c.real("tensile_strength"))
      report(c.where("ucs"),
             fmt::format("ucs = {} Pa is not above tensile_strength = {} Pa; rocks are several "
                         "times stronger in compression than in tension",
                         c.real("ucs"), c.real("tensile_strength")));
    const double w = c.real("specimen_width");
    if (w > 0 && w < 10 * c.real("diameter"))
      report(
          c.where("specimen_width"),
          fmt::format("specimen_width = {} m holds fewer than 10 particles of diameter {} m across; allowed: "
                      "0 (40 diameters) or at least 10 diameters",
                      w, c.real("diameter")));
  }

  /// Checks between the keys of [network]: rows name nodes of `mass`, stiffnesses are
  /// positive, and the [solver] keys it takes (the others are for particle regions).
  void check_network(const Tables& scene) {
    const Table& n = scene.table("network");
    const auto nodes = static_cast<std::int64_t>(n.reals("mass").size());
    auto node_ok = [&](double x) { return x == std::floor(x) && x >= 0 && x < double(nodes); };
    const std::string allowed = fmt::format("node numbers 0 to {} (one per mass)", nodes - 1);
    auto rows = [&](const std::string& key, std::size_t node_columns, const char* what) {
      const auto& table = n.real_table(key);
      for (std::size_t r = 0; r < table.size(); ++r) {
        for (std::size_t c = 0; c < node_columns; ++c)
          if (!node_ok(table[r][c])) {
            report(n.where(key), fmt::format("{}[{}]: node {} is not one of the network's; allowed: {}", key,
                                             r, table[r][c], allowed));
            return;
          }
        if (node_columns == 2 && table[r][0] == table[r][1]) {
          report(n.where(key), fmt::format("{}[{}] joins node {} to itself", key, r, table[r][0]));
          return;
        }
        if (!(table[r][node_columns] > 0)) {
          report(n.where(key),
                 fmt::format("{}[{}]: {} = {} must be > 0", key, r, what, table[r][node_columns]));
          return;
        }
      }
    };
    rows("springs", 2, "the stiffness (N/m)");
    rows("walls", 1, "the stiffness (N/m)");
    rows("sine_loads", 1, "the period (s)");
    for (const auto& row : n.real_table("sine_loads"))
      if (!(row[3] >= 0))
        report(n.where("sine_loads"), fmt::format("sine_loads: end = {} s must be >= 0", row[3]));
    for (const std::string key : {"fem_nodes", "particle_nodes", "probe_nodes"})
      for (std::int64_t i : n.integers(key))
        if (i >= nodes) {
          report(n.where(key),
                 fmt::format("{}: node {} is not one of the network's; allowed: {}", key, i, allowed));
          break;
        }
    const Table& solver = scene.table("solver");
    for (const std::string key : {"settle", "damping", "viscous_c", "local_damping", "gravity",
                                  "contact_detection", "min_particles_per_thread", "lattice_slots"})
      if (solver.given(key))
        report(solver.where(key),
               fmt::format(
                   "solver.{} does not apply to a network scene ([network]); its [solver] takes dt, "
                   "dt_safety, steps, duration, allow_unstable, threads, fem_integrator, eta and coupling",
                   key));
  }

  /// Checks between the keys of a study: [[vary]] keys named once, `spread` and `x` naming
  /// them, at least one [[vary]] and one [[measure]], JSON pointers that start with '/'.
  void check_study(const Tables& scene) {
    const Table& s = scene.table("study");
    const auto& vary = scene.tables("vary");
    const auto& measures = scene.tables("measure");
    if (vary.empty()) report(s.where(), "a study needs at least one [[vary]] (a key and its values)");
    if (measures.empty())
      report(s.where(), "a study needs at least one [[measure]] (a number of summary.json)");
    std::vector<std::string> keys;
    for (const Table& v : vary) {
      const std::string& k = v.str("key");
      if (std::find(keys.begin(), keys.end(), k) != keys.end())
        report(v.where("key"), fmt::format("[[vary]] key '{}' is varied twice", k));
      if (k.find('=') != std::string::npos)
        report(v.where("key"),
               fmt::format("[[vary]] key '{}': write the key alone; its values go in values", k));
      keys.push_back(k);
    }
    for (const std::string role : {"spread", "x"}) {
      const std::string& k = s.str(role);
      if (!k.empty() && std::find(keys.begin(), keys.end(), k) == keys.end())
        report(s.where(role), fmt::format("study.{} = \"{}\" is not a [[vary]] key (varied: {})", role, k,
                                          keys.empty() ? std::string("none") : join(keys)));
    }
    if (!s.str("x").empty() && s.str("x") == s.str("spread"))
      report(s.where("x"), "study.x and study.spread name the same key; the spread is taken over it");
    unique_names(scene, "measure");
    for (const Table& m : measures)
      for (const std::string key : {"value", "divide_by"}) {
        const std::string& p = m.str(key);
        if ((key == "value" || !p.empty()) && (p.empty() || p[0] != '/'))
          report(m.where(key), fmt::format("{} = \"{}\" is not a JSON pointer into summary.json; allowed: a "
                                           "path such as \"/measured_elastic/poisson_ratio\"",
                                           key, p));
      }
  }

  void run(const Tables& scene) {
    if (scene.coupled()) return check_coupled(scene);
    if (scene.network()) return check_network(scene);
    if (scene.study()) return check_study(scene);
    for (const std::string table : {"vary", "measure"})
      if (!scene.tables(table).empty())
        report(scene.tables(table).front().where(),
               fmt::format("[[{}]] belongs to a study file ([study]), which names the scene it runs", table));
    if (scene.calibration()) return check_calibrate(scene);
    const int dim = static_cast<int>(scene.table("scene").integer("dimension"));
    const auto materials = unique_names(scene, "material");
    const auto regions = unique_names(scene, "region");
    unique_names(scene, "wall");
    // Every region is also a group of its own name, so boundaries, loads and probes may name
    // either; a [[group]] must not take a region's name.
    auto groups = unique_names(scene, "group");
    for (const Table& g : scene.tables("group")) {
      if (std::find(regions.begin(), regions.end(), g.str("name")) != regions.end())
        report(g.where("name"),
               fmt::format("[[group]] name '{}' is already a [[region]] name (every region is "
                           "also a group of its own name)",
                           g.str("name")));
    }
    groups.insert(groups.end(), regions.begin(), regions.end());
    const std::string group_what = "[[group]] or [[region]]";

    for (const Table& m : scene.tables("material"))
      if (m.given("youngs_modulus") != m.given("poisson_ratio")) {
        const std::string given = m.given("youngs_modulus") ? "youngs_modulus" : "poisson_ratio";
        const std::string other = given == "youngs_modulus" ? "poisson_ratio" : "youngs_modulus";
        report(m.where(given),
               fmt::format("material '{}' gives {} without {}: the continuum of an FEM region "
                           "needs both (or neither, for the lattice's own)",
                           m.str("name"), given, other));
      }
    // Kn and Ks: what the particles of a material are made of, and the continuum of an FEM
    // region whose material gives no youngs_modulus of its own. A material of FEM regions
    // with E and ν needs neither.
    const TableSpec& material_spec = *find_table("material");
    for (const Table& m : scene.tables("material")) {
      bool lattice = false;
      for (const Table& r : scene.tables("region"))
        if (r.str("material") == m.str("name"))
          lattice = lattice || r.str("kind") == "particles" || !m.given("youngs_modulus");
      for (const char* key : {"kn", "ks"})
        if (lattice && !m.given(key))
          report(m.where(), fmt::format("{} is missing required key '{}' ({})", entry_title(material_spec, m),
                                        key, first_sentence(find_key(material_spec, key)->doc)));
    }
    const TableSpec& region_spec = *find_table("region");
    for (const Table& r : scene.tables("region")) {
      check_reference(r, "material", "[[material]]", materials);
      if (r.str("kind") == "particles") need(region_spec, r, "diameter", "kind");
      check_spread(r);
      const std::string& lattice = r.str("lattice");
      if (lattice == "hex" && dim == 3)
        report(r.where("lattice"), "lattice = \"hex\" is for 2D scenes; in 3D use hcp or fcc (or auto)");
      if ((lattice == "hcp" || lattice == "fcc") && dim == 2)
        report(r.where("lattice"),
               fmt::format("lattice = \"{}\" is for 3D scenes; in 2D use hex (or auto)", lattice));
      const std::string& shape = r.str("shape");
      if (shape == "box") need(region_spec, r, "size", "shape");
      if (shape == "disk" || shape == "sphere") {
        if (shape == "disk" && dim == 3)
          report(r.where("shape"), "shape = \"disk\" is for 2D scenes; in 3D use \"sphere\" or \"cylinder\"");
        if (shape == "sphere" && dim == 2)
          report(r.where("shape"), "shape = \"sphere\" is for 3D scenes; in 2D use \"disk\"");
        need(region_spec, r, "center", "shape");
        need(region_spec, r, "radius", "shape");
      }
      if (shape == "cylinder") {
        if (dim == 2) report(r.where("shape"), "shape = \"cylinder\" is for 3D scenes; in 2D use \"disk\"");
        need(region_spec, r, "center", "shape");
        need(region_spec, r, "radius", "shape");
        need(region_spec, r, "height", "shape");
      }
      if (shape == "polygon") {
        if (dim == 3)
          report(r.where("shape"),
                 "shape = \"polygon\" is for 2D scenes; in 3D use a geometry file (shape = \"file\")");
        need(region_spec, r, "points", "shape");
        if (r.has("points") && r.real_table("points").size() < 3)
          report(r.where("points"), fmt::format("points has {} corners; a polygon needs at least 3",
                                                r.real_table("points").size()));
      }
      if (r.given("mesh_size") && r.str("kind") == "particles" && shape != "file")
        report(
            r.where("mesh_size"),
            fmt::format("mesh_size sets the FEM element size (kind = \"fem\") or the geometry mesh of a "
                        "particle region read from a file (shape = \"file\"); a {} of particles has no mesh",
                        shape));
      if (shape == "file") {
        need(region_spec, r, "file", "shape");
        if (r.has("file")) {
          const fs::path file(r.str("file"));
          if (!preprocess::is_gmsh_file(file) && !preprocess::is_surface_file(file))
            report(r.where("file"),
                   fmt::format("file '{}' is not a geometry file strata reads ({})", file.filename().string(),
                               preprocess::geometry_extensions_text()));
        }
      }
    }

    const TableSpec& group_spec = *find_table("group");
    for (const Table& g : scene.tables("group")) {
      if (!g.str("region").empty()) check_reference(g, "region", "[[region]]", regions);
      if (g.str("select") == "box") {
        need(group_spec, g, "box_min", "select");
        need(group_spec, g, "box_max", "select");
        if (g.has("box_min") && g.has("box_max")) {
          const auto &lo = g.reals("box_min"), &hi = g.reals("box_max");
          for (std::size_t c = 0; c < lo.size() && c < hi.size(); ++c) {
            if (!(hi[c] > lo[c])) {
              report(
                  g.where("box_max"),
                  fmt::format("box_max[{0}] = {1} must be greater than box_min[{0}] = {2}", c, hi[c], lo[c]));
              break;
            }
          }
        }
      }
    }

    const TableSpec& boundary_spec = *find_table("boundary");
    for (const Table& b : scene.tables("boundary")) {
      check_reference(b, "group", group_what, groups);
      if (b.str("type") == "velocity") need(boundary_spec, b, "velocity", "type");
      if (b.str("type") == "step_displacement") need(boundary_spec, b, "increment", "type");
    }

    const TableSpec& load_spec = *find_table("load");
    for (const Table& l : scene.tables("load")) {
      check_reference(l, "group", group_what, groups);
      const auto& times = l.reals("times");
      for (std::size_t j = 1; j < times.size(); ++j) {
        if (!(times[j] > times[j - 1])) {
          report(l.where("times"),
                 fmt::format("times must increase: times[{}] = {} is not after times[{}] = {}", j, times[j],
                             j - 1, times[j - 1]));
          break;
        }
      }
      const bool radial = l.str("type") == "radial";
      if (!radial) {
        need(load_spec, l, "forces", "type");
        if (l.has("forces") && l.real_table("forces").size() != times.size())
          report(l.where("forces"),
                 fmt::format("forces has {} rows but times has {} entries: give one force per time",
                             l.real_table("forces").size(), times.size()));
        for (const char* key : {"magnitudes", "center", "axis"})
          if (l.given(key))
            report(l.where(key), fmt::format("{} is for type = \"radial\"; a force_history load gives "
                                             "its force vectors in `forces`",
                                             key));
        continue;
      }
      need(load_spec, l, "magnitudes", "type");
      if (l.has("magnitudes") && l.reals("magnitudes").size() != times.size())
        report(l.where("magnitudes"),
               fmt::format("magnitudes has {} entries but times has {}: give one magnitude per time",
                           l.reals("magnitudes").size(), times.size()));
      if (l.given("forces"))
        report(l.where("forces"), "forces is for type = \"force_history\"; a radial load gives `magnitudes`");
      if (l.given("axis")) {
        const auto& axis = l.reals("axis");
        if (dim == 2)
          report(l.where("axis"), "axis is for 3D scenes: in 2D the radial load lies in the plane");
        else if (std::all_of(axis.begin(), axis.end(), [](double x) { return x == 0.0; }))
          report(l.where("axis"), "axis must not be zero: give the borehole's direction (or leave it out)");
      }
    }

    for (const Table& w : scene.tables("wall")) {
      const auto& n = w.reals("normal");
      if (std::all_of(n.begin(), n.end(), [](double x) { return x == 0.0; }))
        report(w.where("normal"), "normal must not be zero: give the direction pointing into the particles");
    }

    const Table& solver = scene.table("solver");
    if (solver.integer("steps") == 0 && solver.real("duration") == 0.0)
      report(solver.where(), "the run has no length: set solver.steps or solver.duration (both are 0)");

    const Table& output = scene.table("output");
    if (dim != 2) {
      if (output.str("render_field") == "shear_strain")
        report(output.where("render_field"),
               "shear_strain is measured in 2D scenes only (allowed in 3D: "
               "displacement, velocity, damage, group)");
      const auto& fields = output.strings("fields");
      if (std::find(fields.begin(), fields.end(), "shear_strain") != fields.end())
        report(output.where("fields"), "shear_strain is measured in 2D scenes only");
    }

    const Table& probe = scene.table("probe");
    const std::string& axis = probe.str("axis");
    if (axis == "z" && dim == 2)
      report(probe.where("axis"), "axis = \"z\" is not an axis of a 2D scene (allowed: x, y)");
    if (probe.boolean("stress_strain")) {
      check_reference(probe, "top_group", group_what, groups, ", which stress_strain = true needs");
      check_reference(probe, "bottom_group", group_what, groups, ", which stress_strain = true needs");
    }
    if (!probe.str("wedge_group").empty()) {
      check_reference(probe, "wedge_group", group_what, groups);
      if (dim != 2) report(probe.where("wedge_group"), "a thrust wedge is measured in 2D scenes only");
      if (!probe.str("wedge_backstop").empty()) check_reference(probe, "wedge_backstop", group_what, groups);
    }
    if (probe.has("wedge_friction")) {
      const auto& mu = probe.reals("wedge_friction");
      if (mu.size() == 2 && !(mu[1] < mu[0]))
        report(probe.where("wedge_friction"),
               fmt::format("the basal friction {} (second) must be below the internal friction {} (first): a "
                           "base as strong as the cover makes no wedge",
                           mu[1], mu[0]));
    }
    if (!probe.boolean("stress_strain") && probe.real("stop_after_peak") > 0) {
      report(probe.where("stop_after_peak"),
             "stop_after_peak needs the specimen's stress: set stress_strain = true (with top_group and "
             "bottom_group), or leave stop_after_peak at 0");
    }
  }

 private:
  void report(const SourcePos& pos, std::string message) { report_(pos, std::move(message)); }

  const ReportProblem& report_;
};

}  // namespace

void check_between_keys(const Tables& tables, const ReportProblem& report) { KeyChecks(report).run(tables); }

}  // namespace strata::scene
