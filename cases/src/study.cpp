// Parameter studies: plan (the runs and their overrides), check (every run's scene read, the
// first and last models built), run (each run through scene::Run into runs/NNNN/), then the
// tables and plots of the measures, written all at once through a staging folder.
#include <strata/cases/study.hpp>

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <strata/core/clock.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/scene/files.hpp>
#include <strata/scene/model.hpp>
#include <strata/scene/run.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>

#include "case_helpers.hpp"

namespace strata::cases {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A value as a scene override writes it: the number, or the list [v, v(, v)].
std::string value_text(double v, std::int64_t components) {
  if (components == 0) return fmt::format("{}", v);
  std::vector<double> list(std::size_t(components), v);
  return fmt::format("[{}]", fmt::join(list, ", "));
}

std::string label_of(const scene::VaryTable& v) { return v.label->empty() ? v.key.value : v.label.value; }

/// Index of the [[vary]] entry with `key`, or -1.
int vary_index(const scene::Scene& st, const std::string& key) {
  for (std::size_t k = 0; k < st.vary.size(); ++k)
    if (st.vary[k].key.value == key) return int(k);
  return -1;
}

/// The plots' abscissa: study.x, else the first [[vary]] key that is not the spread.
int x_index(const scene::Scene& st) {
  if (!st.study->x->empty()) return vary_index(st, st.study->x);
  for (std::size_t k = 0; k < st.vary.size(); ++k)
    if (st.vary[k].key.value != st.study->spread.value) return int(k);
  return -1;
}

/// The scene of run `k`, with the overrides that keep a run of a study to its summary: no
/// frames and no pictures (the study's own plots are drawn at its end).
scene::Scene scene_of(const scene::Scene& st, const StudyPlan& plan, std::size_t k) {
  std::vector<std::string> o = plan.overrides[k];
  o.insert(o.end(), {"output.vtk=false", "output.render=false"});
  try {
    return scene::load(st.study->scene, o);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Input) throw;
    st.study->scene.fail(
        fmt::format("run {} of the study ({}): {}", k + 1, fmt::join(plan.overrides[k], " "), e.what()));
  }
}

/// Every run's scene, read once before anything runs (a bad key or value is refused here).
std::vector<scene::Scene> scenes_of(const scene::Scene& st, const StudyPlan& plan) {
  std::vector<scene::Scene> scenes;
  scenes.reserve(plan.overrides.size());
  for (std::size_t k = 0; k < plan.overrides.size(); ++k) scenes.push_back(scene_of(st, plan, k));
  return scenes;
}

/// The number at JSON pointer `ptr` of `j`, or NaN.
double number_at(const json& j, const std::string& ptr) {
  try {
    const json& v = j.at(json::json_pointer(ptr));
    return v.is_number() ? v.get<double>() : kNaN;
  } catch (const json::exception&) {
    return kNaN;
  }
}

/// Forwards a study's stop request to the run in progress.
class RunStop final : public scene::RunObserver {
 public:
  explicit RunStop(StudyObserver& o) : o_(o) {}
  int stop_requested() override { return o_.stop_requested(); }

 private:
  StudyObserver& o_;
};

std::string file_stem(const std::string& name) {
  std::string s;
  for (const char c : name) s += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return s;
}

/// The tables, plots and summary of a study's points, into `dir`; the Markdown table is also
/// returned.
std::string write_results(const scene::Scene& st, const std::vector<StudyPoint>& points, const fs::path& dir,
                          bool plots, double wall_s, const std::string& status) {
  const std::size_t nv = st.vary.size(), nm = st.measures.size();
  const int spread = vary_index(st, st.study->spread);
  {
    std::vector<std::string> cols{"run"};
    for (const auto& v : st.vary) cols.push_back(label_of(v));
    for (const auto& m : st.measures) cols.push_back(m.name);
    cols.insert(cols.end(), {"wall_s", "completed"});
    io::CsvWriter csv(dir / "study.csv", cols);
    for (std::size_t k = 0; k < points.size(); ++k) {
      std::vector<double> row{double(k + 1)};
      row.insert(row.end(), points[k].values.begin(), points[k].values.end());
      row.insert(row.end(), points[k].measures.begin(), points[k].measures.end());
      row.insert(row.end(), {points[k].wall_s, points[k].status == "completed" ? 1.0 : 0.0});
      csv.row(row);
    }
    csv.close();
  }
  const std::vector<StudyGroup> groups = group_points(st, points);
  std::string md = fmt::format(
      "{}\n\n{} runs of {}{}\n\n", st.study->title->empty() ? "Study" : st.study->title.value, points.size(),
      st.study->scene->filename().string(),
      spread >= 0 ? fmt::format("; mean ± standard deviation over {}", label_of(st.vary[std::size_t(spread)]))
                  : "");
  std::string head = "|", rule = "|";
  for (std::size_t k = 0; k < nv; ++k)
    if (int(k) != spread) head += fmt::format(" {} |", label_of(st.vary[k])), rule += "---:|";
  head += " runs |";
  rule += "---:|";
  for (const auto& m : st.measures) head += fmt::format(" {} |", m.name.value), rule += "---:|";
  md += head + "\n" + rule + "\n";
  for (const StudyGroup& g : groups) {
    std::string row = "|";
    for (std::size_t k = 0; k < nv; ++k)
      if (int(k) != spread) row += fmt::format(" {} |", g.values[k]);
    row += fmt::format(" {} |", g.counted == g.runs ? fmt::format("{}", g.runs)
                                                    : fmt::format("{} of {}", g.counted, g.runs));
    for (std::size_t m = 0; m < nm; ++m)
      row += g.counted == 0 ? " – |"
             : spread >= 0  ? fmt::format(" {:.4g} ± {:.2g} |", g.mean[m], g.std[m])
                            : fmt::format(" {:.4g} |", g.mean[m]);
    md += row + "\n";
  }
  std::ofstream(dir / "study.md") << md;

  json summary = {{"status", status},
                  {"title", st.study->title.value},
                  {"scene", st.study->scene->string()},
                  {"wall_seconds", wall_s}};
  for (const auto& v : st.vary)
    summary["vary"].push_back({{"key", v.key.value}, {"label", label_of(v)}, {"values", v.values.value}});
  for (const auto& m : st.measures)
    summary["measures"].push_back(
        {{"name", m.name.value}, {"value", m.value.value}, {"divide_by", m.divide_by.value}});
  auto num = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
  for (const StudyPoint& p : points) {
    json r = {{"status", p.status}, {"wall_s", p.wall_s}};
    for (std::size_t k = 0; k < nv; ++k) r["values"].push_back(p.values[k]);
    for (std::size_t m = 0; m < nm; ++m) r["measures"].push_back(num(p.measures[m]));
    summary["runs"].push_back(r);
  }
  for (const StudyGroup& g : groups) {
    json r = {{"runs", g.runs}, {"counted", g.counted}};
    for (std::size_t k = 0; k < nv; ++k) r["values"].push_back(num(g.values[k]));
    for (std::size_t m = 0; m < nm; ++m)
      r["mean"].push_back(num(g.mean[m])), r["std"].push_back(num(g.std[m]));
    summary["groups"].push_back(r);
  }
  std::ofstream(dir / "summary.json") << summary.dump(2) << "\n";

  const int xi = x_index(st);
  if (!plots || xi < 0) return md;
  for (std::size_t m = 0; m < nm; ++m) {
    io::PlotRequest pr;
    pr.title = st.study->title->empty()
                   ? st.measures[m].name.value
                   : fmt::format("{}: {}", st.study->title.value, st.measures[m].name.value);
    pr.x_label = label_of(st.vary[std::size_t(xi)]);
    pr.y_label = st.measures[m].name;
    pr.png = dir / fmt::format("study_{}.png", file_stem(st.measures[m].name));
    std::map<std::string, std::size_t> curve;  // the other keys' values -> series
    for (const StudyGroup& g : groups) {
      if (g.counted == 0) continue;
      std::string name;
      for (std::size_t k = 0; k < nv; ++k)
        if (int(k) != spread && int(k) != xi)
          name += fmt::format("{}{} = {}", name.empty() ? "" : ", ", label_of(st.vary[k]), g.values[k]);
      if (name.empty()) name = st.measures[m].name;
      const auto [it, fresh] = curve.emplace(name, pr.series.size());
      if (fresh) pr.series.push_back({name, {}, {}, true, true});
      io::PlotSeries& s = pr.series[it->second];
      s.x.push_back(g.values[std::size_t(xi)]);
      s.y.push_back(g.mean[m]);
      if (spread >= 0) s.y_err.push_back(g.std[m]);
    }
    if (pr.series.empty()) continue;
    try {
      io::plot_xy(pr);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Unsupported) throw;
      log::warn("no plot: {}", e.what());
      return md;
    }
  }
  return md;
}

}  // namespace

StudyPlan plan_study(const scene::Scene& st) {
  STRATA_CHECK(st.study, Internal, "plan_study: {} has no [study] table", st.file.string());
  StudyPlan plan;
  std::vector<std::size_t> at(st.vary.size(), 0);
  for (;;) {
    std::vector<std::string> o = st.study->set;
    std::vector<double> values;
    for (std::size_t k = 0; k < st.vary.size(); ++k) {
      const double v = st.vary[k].values.value[at[k]];
      o.push_back(fmt::format("{}={}", st.vary[k].key.value, value_text(v, st.vary[k].components)));
      values.push_back(v);
    }
    plan.overrides.push_back(std::move(o));
    plan.values.push_back(std::move(values));
    std::size_t k = st.vary.size();  // the last key fastest
    while (k > 0 && ++at[k - 1] == st.vary[k - 1].values->size()) at[--k] = 0;
    if (k == 0) break;
  }
  return plan;
}

std::vector<StudyGroup> group_points(const scene::Scene& st, const std::vector<StudyPoint>& points) {
  const int spread = vary_index(st, st.study->spread);
  const std::size_t nm = st.measures.size();
  std::vector<StudyGroup> groups;
  std::vector<std::vector<const StudyPoint*>> members;
  for (const StudyPoint& p : points) {
    std::vector<double> key = p.values;
    if (spread >= 0) key[std::size_t(spread)] = kNaN;
    auto same = [&](const StudyGroup& g) {
      for (std::size_t k = 0; k < key.size(); ++k)
        if (int(k) != spread && g.values[k] != key[k]) return false;
      return true;
    };
    std::size_t g = std::size_t(std::find_if(groups.begin(), groups.end(), same) - groups.begin());
    if (g == groups.size()) {
      groups.push_back({key, 0, 0, {}, {}});
      members.emplace_back();
    }
    members[g].push_back(&p);
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {
    StudyGroup& G = groups[g];
    G.runs = members[g].size();
    std::vector<const StudyPoint*> ok;
    for (const StudyPoint* p : members[g])
      if (std::all_of(p->measures.begin(), p->measures.end(), [](double x) { return std::isfinite(x); }))
        ok.push_back(p);
    G.counted = ok.size();
    G.mean.assign(nm, kNaN);
    G.std.assign(nm, kNaN);
    if (ok.empty()) continue;
    for (std::size_t m = 0; m < nm; ++m) {
      double s = 0;
      for (const StudyPoint* p : ok) s += p->measures[m];
      const double mean = s / double(ok.size());
      double q = 0;
      for (const StudyPoint* p : ok) q += (p->measures[m] - mean) * (p->measures[m] - mean);
      G.mean[m] = mean;
      G.std[m] = ok.size() > 1 ? std::sqrt(q / double(ok.size() - 1)) : 0.0;
    }
  }
  return groups;
}

int check_study_scene(const scene::Scene& st) {
  const StudyPlan plan = plan_study(st);
  std::printf("study        %s: %zu runs of %s\n", st.file.string().c_str(), plan.overrides.size(),
              st.study->scene->string().c_str());
  for (const auto& v : st.vary)
    std::printf("vary         %-24s %zu values: %s\n", v.key.value.c_str(), v.values->size(),
                fmt::format("{}", fmt::join(v.values.value, ", ")).c_str());
  for (const auto& m : st.measures)
    std::printf("measure      %-24s %s%s\n", m.name.value.c_str(), m.value.value.c_str(),
                m.divide_by->empty() ? "" : (" / " + m.divide_by.value).c_str());
  const std::vector<scene::Scene> scenes = scenes_of(st, plan);
  for (const std::size_t k : {std::size_t(0), plan.overrides.size() - 1}) {
    const scene::Scene& sc = scenes[k];
    const scene::BuiltModel m = st.study->scene.blame([&] { return scene::build_model(sc, false); });
    std::printf("run %-8zu %s: %zu particles, dt = %.4g s (dt/dt_crit = %.3f), %lld steps\n", k + 1,
                fmt::format("{}", fmt::join(plan.overrides[k], " ")).c_str(),
                m.has_particles() ? m.sim().particle_count() : std::size_t(0), m.dt, m.dt / m.dt_crit,
                (long long)m.steps);
    if (plan.overrides.size() == 1) break;
  }
  return 0;
}

int run_study_scene(const scene::Scene& st, const fs::path& output, StudyObserver& observer) {
  const StudyPlan plan = plan_study(st);
  const std::vector<scene::Scene> scenes = scenes_of(st, plan);
  const fs::path out = output.empty() ? st.output.directory.value : output;
  const auto t0 = WallClock::now();
  scene::Staging stage(out);
  std::vector<StudyPoint> points;
  observer.started(plan.overrides.size());
  RunStop stop(observer);
  int stopped = 0;
  for (std::size_t k = 0; k < plan.overrides.size() && !stopped; ++k) {
    StudyPoint p;
    p.values = plan.values[k];
    p.measures.assign(st.measures.size(), kNaN);
    const scene::Scene& sc = scenes[k];
    const auto r0 = WallClock::now();
    try {
      scene::Run run(sc, {stage.path() / "runs" / fmt::format("{:04d}", k + 1), false, {}, false});
      const scene::RunResult r = run.execute(stop);
      p.status = r.status == scene::RunStatus::Interrupted ? "interrupted" : "completed";
      if (r.status == scene::RunStatus::Interrupted) stopped = r.stop_reason;
      for (std::size_t m = 0; m < st.measures.size(); ++m) {
        const double v = number_at(r.summary, st.measures[m].value);
        p.measures[m] =
            st.measures[m].divide_by->empty() ? v : v / number_at(r.summary, st.measures[m].divide_by);
      }
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Numerical && e.kind() != ErrorKind::Input) throw;
      p.status = fmt::format("{}: {}", e.kind() == ErrorKind::Numerical ? "blew up" : "refused",
                             detail::first_line(e.what()));
    }
    p.wall_s = seconds_since(r0);
    points.push_back(std::move(p));
    observer.done(k, points.back());
    if (!stopped) stopped = observer.stop_requested();
  }
  const std::string status =
      stopped ? fmt::format("interrupted after {} of {} runs", points.size(), plan.overrides.size())
              : "completed";
  const std::string md = write_results(st, points, stage.path(), st.output.render, seconds_since(t0), status);
  std::fwrite(md.data(), 1, md.size(), stdout);
  const auto written = stage.commit(out);
  std::printf("wrote:\n");
  for (const auto& f : written) std::printf("  %s\n", f.string().c_str());
  return stopped ? 128 + stopped : 0;
}

}  // namespace strata::cases
