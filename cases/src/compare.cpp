// Error against run time of one scene over η, against a reference scene of the same geometry:
//   load both -> run the reference -> run the scene at each η -> gauge errors -> table, plots.
#include <strata/cases/compare.hpp>

#include <fmt/format.h>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/scene/files.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "case_helpers.hpp"

namespace strata::cases {

namespace fs = std::filesystem;
using nlohmann::json;

double gauge_error(const std::vector<double>& ref_time, const std::vector<std::vector<double>>& ref,
                   const std::vector<double>& run_time, const std::vector<std::vector<double>>& run) {
  STRATA_CHECK(ref.size() == run.size(), Internal, "gauge_error: {} reference columns, {} run columns",
               ref.size(), run.size());
  constexpr double inf = std::numeric_limits<double>::infinity();
  double scale = 0, worst = 0;
  for (const auto& col : ref)
    for (double v : col) {
      if (!std::isfinite(v)) return inf;
      scale = std::max(scale, std::abs(v));
    }
  if (ref_time.empty()) return inf;
  for (std::size_t i = 0; i < run_time.size(); ++i) {
    const double t = run_time[i];
    if (t < ref_time.front() || t > ref_time.back()) continue;
    // the reference row at or after t, and the weight of the row before it
    const std::size_t k =
        std::size_t(std::lower_bound(ref_time.begin(), ref_time.end(), t) - ref_time.begin());
    const std::size_t k0 = k == 0 ? 0 : k - 1;
    const double span = ref_time[k] - ref_time[k0];
    const double w = span > 0 ? (ref_time[k] - t) / span : 0.0;
    for (std::size_t j = 0; j < ref.size(); ++j) {
      const double u = run[j][i];
      if (!std::isfinite(u)) return inf;
      const double r = w * ref[j][k0] + (1 - w) * ref[j][k];
      worst = std::max(worst, std::abs(u - r));
    }
  }
  if (scale == 0) return worst == 0 ? 0.0 : inf;
  return worst / scale;
}

namespace {

/// Outputs of a timed run: no frames, pictures or checkpoints between steps, so the run time
/// is the solver's. The user's overrides come after these and may turn frames back on.
std::vector<std::string> run_overrides(const CompareOptions& opt, int eta) {
  std::vector<std::string> o{"output.frames=0", "output.frame_every_time=0", "output.frame_every_breaks=0",
                             "output.checkpoint_every=0", "output.render=false"};
  o.insert(o.end(), opt.overrides.begin(), opt.overrides.end());
  if (eta > 0) o.push_back(fmt::format("solver.eta={}", eta));
  return o;
}

/// Gauges and their columns, in file order.
using GaugeColumns = std::vector<std::pair<std::string, std::vector<std::string>>>;

/// The gauge columns of a probes.csv (<gauge>_ux, _uy, _uz), grouped by gauge in file order.
GaugeColumns gauge_columns(const io::CsvTable& t) {
  GaugeColumns out;
  for (const auto& name : t.names) {
    if (name.size() < 4) continue;
    const std::string tail = name.substr(name.size() - 3);
    if (tail != "_ux" && tail != "_uy" && tail != "_uz") continue;
    const std::string gauge = name.substr(0, name.size() - 3);
    if (out.empty() || out.back().first != gauge) out.push_back({gauge, {}});
    out.back().second.push_back(name);
  }
  return out;
}

std::vector<std::vector<double>> columns_of(const io::CsvTable& t, const std::vector<std::string>& names) {
  std::vector<std::vector<double>> out;
  for (const auto& n : names) out.push_back(t.column(n));
  return out;
}

/// Runs `sc` `repeats` times into `dir`; the fastest run's numbers go into `row`.
void timed_runs(const scene::Scene& sc, const fs::path& dir, const CompareOptions& opt, CompareRow& row,
                CompareObserver& observer) {
  row.directory = dir;
  for (int k = 0; k < std::max(1, opt.repeats); ++k) {
    observer.begin(row.label, k);
    scene::Run run(sc, {dir, opt.force, {}});
    const json& model = run.model_summary();
    if (row.label != "reference") row.eta = int(run.model().eta);
    row.particles = model.value("particles", std::size_t(0));
    row.fem_nodes = model.value("fem_nodes", std::size_t(0));
    const scene::RunResult r = run.execute(observer);
    if (r.status == scene::RunStatus::Interrupted)
      fail(ErrorKind::Input, "compare: {} interrupted by a stop request at step {}", row.label, r.step);
    row.steps = r.step;
    row.seconds = k == 0 ? r.step_seconds : std::min(row.seconds, r.step_seconds);
  }
  row.status = "completed";
}

std::string percent(double e) { return std::isfinite(e) ? fmt::format("{:.3g} %", 100 * e) : "∞"; }

std::string markdown(const CompareResult& res) {
  std::string md = "| run | particles | FEM nodes | steps | run time (s) | gauge error |";
  for (const auto& g : res.gauges) md += fmt::format(" {} |", g);
  md += "\n|---|---:|---:|---:|---:|---:|";
  for (std::size_t i = 0; i < res.gauges.size(); ++i) md += "---:|";
  md += "\n";
  for (const auto& r : res.rows) {
    if (r.status == "completed") {
      md += fmt::format("| {} | {} | {} | {} | {:.3f} | {} |", r.label, r.particles, r.fem_nodes, r.steps,
                        r.seconds, r.eta == 0 ? std::string("—") : percent(r.error));
      for (std::size_t i = 0; i < res.gauges.size(); ++i)
        md += fmt::format(" {} |", r.eta == 0 || i >= r.gauge_errors.size() ? std::string("—")
                                                                            : percent(r.gauge_errors[i]));
    } else {
      md += fmt::format("| {} | | | | | {} |", r.label, r.status);
      for (std::size_t i = 0; i < res.gauges.size(); ++i) md += " |";
    }
    md += "\n";
  }
  for (const auto& r : res.rows)
    if (!r.note.empty()) md += fmt::format("\n{}: {}\n", r.label, r.note);
  return md;
}

std::string csv(const CompareResult& res) {
  std::string s = "label,eta,status,particles,fem_nodes,steps,seconds,error";
  for (const auto& g : res.gauges) s += ",error_" + g;
  s += "\n";
  auto num = [](double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string("inf"); };
  for (const auto& r : res.rows) {
    const bool done = r.status == "completed";
    s += fmt::format("{},{},{},{},{},{},{},{}", r.label, r.eta, r.status, r.particles, r.fem_nodes, r.steps,
                     done ? num(r.seconds) : "nan", done ? num(r.error) : "nan");
    for (std::size_t i = 0; i < res.gauges.size(); ++i) {
      s += ',';
      s += done && i < r.gauge_errors.size() ? num(r.gauge_errors[i]) : std::string("nan");
    }
    s += "\n";
  }
  return s;
}

json summary(const CompareOptions& opt, const CompareResult& res) {
  json rows = json::array();
  auto finite = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  for (const auto& r : res.rows) {
    json g = json::object();
    for (std::size_t i = 0; i < r.gauge_errors.size(); ++i) g[res.gauges[i]] = finite(r.gauge_errors[i]);
    rows.push_back({{"label", r.label},
                    {"eta", r.eta},
                    {"status", r.status},
                    {"note", r.note},
                    {"particles", r.particles},
                    {"fem_nodes", r.fem_nodes},
                    {"steps", r.steps},
                    {"seconds", r.seconds},
                    {"error", finite(r.error)},
                    {"gauge_errors", g},
                    {"directory", r.directory.string()}});
  }
  return {{"scene", opt.scene.string()},
          {"reference", opt.reference.string()},
          {"overrides", opt.overrides},
          {"repeats", opt.repeats},
          {"gauges", res.gauges},
          {"error_definition",
           "per gauge: max over probe rows and the gauge's columns of |u - u_ref| / max over the "
           "reference of |u_ref|; error: the largest gauge's"},
          {"rows", rows}};
}

/// compare.png: gauge error against run time, one marker per η, the reference's run time as a
/// vertical line. compare_gauges.png: each gauge's largest component over time, every run.
void plots(const CompareResult& res, const io::CsvTable& ref, const GaugeColumns& groups,
           const std::map<int, io::CsvTable>& runs, const fs::path& dir) {
  io::PlotRequest p;
  p.title = "Gauge error against run time";
  p.x_label = "run time [s]";
  p.y_label = "gauge error [%]";
  double ymax = 0;
  for (const auto& r : res.rows)
    if (r.eta > 0 && r.status == "completed" && std::isfinite(r.error)) {
      p.series.push_back({fmt::format("eta = {}", r.eta), {r.seconds}, {100 * r.error}, true, false});
      ymax = std::max(ymax, 100 * r.error);
    }
  const CompareRow& rr = res.rows.front();
  p.series.push_back(
      {"reference (all particles)", {rr.seconds, rr.seconds}, {0.0, 1.1 * std::max(ymax, 1.0)}});
  p.png = dir / "compare.png";
  io::plot_xy(p);

  // Gauges of very different size on one chart: each column over its reference's largest
  // |u|, time in a unit that keeps the tick labels short.
  const double t_end = ref.column("time").empty() ? 0.0 : ref.column("time").back();
  const auto [t_scale, t_unit] = t_end < 1e-3 ? std::pair{1e6, "µs"}
                                 : t_end < 1  ? std::pair{1e3, "ms"}
                                              : std::pair{1.0, "s"};
  auto scaled = [](std::vector<double> v, double f) {
    for (double& x : v) x *= f;
    return v;
  };
  io::PlotRequest g;
  g.title = "Gauge histories";
  g.x_label = fmt::format("time [{}]", t_unit);
  g.y_label = "gauge displacement / largest reference value [-]";
  for (const auto& [gauge, cols] : groups) {
    // the component with the largest reference value
    std::string col = cols.front();
    double big = -1;
    for (const auto& c : cols) {
      double m = 0;
      for (double v : ref.column(c)) m = std::max(m, std::abs(v));
      if (m > big) big = m, col = c;
    }
    const double f = big > 0 ? 1 / big : 1.0;
    g.series.push_back(
        {fmt::format("{} reference", col), scaled(ref.column("time"), t_scale), scaled(ref.column(col), f)});
    for (const auto& [eta, t] : runs)
      g.series.push_back({fmt::format("{} eta = {}", col, eta), scaled(t.column("time"), t_scale),
                          scaled(t.column(col), f)});
  }
  g.png = dir / "compare_gauges.png";
  io::plot_xy(g);
}

}  // namespace

CompareResult compare_runs(const CompareOptions& opt, CompareObserver& observer) {
  // Load everything first: a bad key in either scene is reported before anything runs.
  const scene::Scene ref_scene = scene::load(opt.reference, run_overrides(opt, 0));
  const auto& ref_gauges = ref_scene.probe.gauges;
  if (ref_gauges.value.empty())
    ref_gauges.fail(
        "the reference records no gauges; name the same groups in [probe] gauges of both scenes (the mean "
        "displacement of each is a column of probes.csv)");
  // no --eta: one run at the scene's own solver.eta (0 here, known once the model is built)
  std::vector<int> etas = opt.etas.empty() ? std::vector<int>{0} : opt.etas;
  for (int e : opt.etas) STRATA_CHECK(e >= 1, Input, "compare: --eta {} must be an integer >= 1", e);
  std::vector<scene::Scene> scenes;
  for (int e : etas) scenes.push_back(scene::load(opt.scene, run_overrides(opt, e)));
  for (const auto& g : ref_gauges.value) {
    const auto& mine = scenes.front().probe.gauges;
    if (std::find(mine.value.begin(), mine.value.end(), g) == mine.value.end())
      mine.fail(
          fmt::format("the reference records gauge '{}' and this scene does not; name the same groups in "
                      "[probe] gauges of both scenes",
                      g));
  }

  const fs::path dir = opt.output;
  CompareResult res;
  res.rows.push_back(CompareRow{});
  res.rows.back().label = "reference";
  timed_runs(ref_scene, dir / "runs" / "reference", opt, res.rows.back(), observer);
  observer.end(res.rows.back());
  const io::CsvTable ref = io::read_csv(dir / "runs" / "reference" / "probes.csv");
  const auto groups = gauge_columns(ref);
  STRATA_CHECK(!groups.empty(), Input,
               "{}: the reference records no gauges; name the same groups in [probe] gauges of both "
               "scenes (columns <group>_ux, _uy of probes.csv)",
               opt.reference.string());
  for (const auto& [gauge, cols] : groups) res.gauges.push_back(gauge);

  std::map<int, io::CsvTable> tables;
  for (std::size_t i = 0; i < etas.size(); ++i) {
    CompareRow row;
    row.label = etas[i] ? fmt::format("eta = {}", etas[i]) : "scene";
    row.eta = etas[i];
    const fs::path run_dir = dir / "runs" / (etas[i] ? fmt::format("eta_{}", etas[i]) : "scene");
    try {
      timed_runs(scenes[i], run_dir, opt, row, observer);
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::Input) {
        row.status = "refused";
      } else if (e.kind() == ErrorKind::Numerical) {
        row.status = "failed";
      } else {
        throw;
      }
      row.note = detail::first_line(e.what());
    }
    if (row.status == "completed") {
      io::CsvTable t = io::read_csv(run_dir / "probes.csv");
      for (const auto& [gauge, cols] : groups) {
        for (const auto& c : cols)
          STRATA_CHECK(std::find(t.names.begin(), t.names.end(), c) != t.names.end(), Input,
                       "{}: the scene records no gauge column {} that the reference has; name the same "
                       "groups in [probe] gauges of both scenes",
                       opt.scene.string(), c);
        row.gauge_errors.push_back(
            gauge_error(ref.column("time"), columns_of(ref, cols), t.column("time"), columns_of(t, cols)));
      }
      row.error = *std::max_element(row.gauge_errors.begin(), row.gauge_errors.end());
      tables.emplace(row.eta, std::move(t));
    }
    observer.end(row);
    res.rows.push_back(std::move(row));
  }
  STRATA_CHECK(!tables.empty(), Input, "compare: no eta could run ({}: {})", res.rows[1].label,
               res.rows[1].note);

  res.markdown = markdown(res);
  scene::write_file_atomic(dir / "compare.csv", csv(res));
  scene::write_file_atomic(dir / "compare.md", res.markdown);
  scene::write_file_atomic(dir / "summary.json", summary(opt, res).dump(2) + "\n");
  res.written = {dir / "compare.csv", dir / "compare.md", dir / "summary.json"};
  if (!opt.no_plot) {
    if (STRATA_WITH_RENDER) {
      plots(res, ref, groups, tables, dir);
      res.written.push_back(dir / "compare.png");
      res.written.push_back(dir / "compare_gauges.png");
    } else {
      log::warn("plots skipped: this build has no rendering (reconfigure with -DSTRATA_WITH_RENDER=ON)");
    }
  }
  return res;
}

}  // namespace strata::cases
