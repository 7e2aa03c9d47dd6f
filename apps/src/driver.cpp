#include "driver.hpp"

#include <unistd.h>

#include <nlohmann/json.hpp>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>
#include <strata/core/progress.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/io/render.hpp>
#include <strata/io/series.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>

#include "frames.hpp"
#include "mesh_report.hpp"
#include "model_builder.hpp"
#include "scene/scene.hpp"

namespace strata::app {

using nlohmann::json;
namespace fs = std::filesystem;

void write_file_atomic(const fs::path& path, const std::string& text) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    STRATA_CHECK(f.good(), IO, "cannot write {}", tmp.string());
    f << text;
    f.flush();
    STRATA_CHECK(f.good(), IO, "cannot write {} (disk full?)", tmp.string());
  }
  fs::rename(tmp, path);
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Peak resident memory of this process (bytes), from /proc/self/status.
std::size_t peak_rss_bytes() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
  return 0;
}

scene::Scene load_scene(const SceneOptions& opt) {
  scene::Scene sc = scene::load(opt.scene, opt.overrides);
  const int threads = opt.threads >= 0 ? opt.threads : int(sc.table("solver").integer("threads"));
  par::set_threads(threads);
  return sc;
}

json model_json(const BuiltModel& m, const scene::Scene& sc) {
  json regions = json::array();
  for (const auto& r : m.regions)
    regions.push_back({{"name", r.name},
                       {"lattice", r.lattice},
                       {"particles", r.particles},
                       {"diameter_m", r.diameter},
                       {"packing_density", r.packing}});
  json groups = json::object();
  for (const auto& [name, n] : m.groups) groups[name] = n;
  return {{"scene", sc.file.string()},
          {"title", sc.table("scene").str("title")},
          {"dimension", m.dim},
          {"regions", regions},
          {"groups", groups},
          {"particles", m.sim.particle_count()},
          {"bonds", m.sim.bond_count()},
          {"fem_nodes", 0},
          {"fem_elements", 0},
          {"memory_bytes", m.sim.memory_bytes()},
          {"dt_s", m.dt},
          {"dt_automatic", m.dt_automatic},
          {"dt_crit_s", m.dt_crit},
          {"dt_over_dt_crit", m.dt / m.dt_crit},
          {"steps", m.steps},
          {"simulated_time_s", double(m.steps) * m.dt},
          {"threads", par::threads()}};
}

void print_model(const json& j) {
  std::printf("scene        %s\n", j["scene"].get<std::string>().c_str());
  if (!j["title"].get<std::string>().empty())
    std::printf("title        %s\n", j["title"].get<std::string>().c_str());
  std::printf("dimension    %dD\n", j["dimension"].get<int>());
  for (const auto& r : j["regions"])
    std::printf("region       %-14s %s lattice, d = %g m: %zu particles, packing density %.4f\n",
                r["name"].get<std::string>().c_str(), r["lattice"].get<std::string>().c_str(),
                r["diameter_m"].get<double>(), r["particles"].get<std::size_t>(),
                r["packing_density"].get<double>());
  for (const auto& [name, n] : j["groups"].items())
    std::printf("group        %-14s %zu particles\n", name.c_str(), n.get<std::size_t>());
  std::printf("particles    %zu\nbonds        %zu\nFEM          %zu nodes, %zu elements\n",
              j["particles"].get<std::size_t>(), j["bonds"].get<std::size_t>(),
              j["fem_nodes"].get<std::size_t>(), j["fem_elements"].get<std::size_t>());
  std::printf("memory       %.1f MB (model arrays)\n", j["memory_bytes"].get<double>() / 1e6);
  std::printf("dt_crit      %.4g s\n", j["dt_crit_s"].get<double>());
  std::printf("dt           %.4g s%s  (dt/dt_crit = %.3f)\n", j["dt_s"].get<double>(),
              j["dt_automatic"].get<bool>() ? " (automatic)" : "", j["dt_over_dt_crit"].get<double>());
  std::printf("steps        %lld (%.4g s simulated)\n", (long long)j["steps"].get<std::int64_t>(),
              j["simulated_time_s"].get<double>());
}

/// Everything a run writes, in one place.
class RunOutput {
 public:
  RunOutput(const fs::path& dir, const scene::Scene& sc, const BuiltModel& m)
      : dir_(dir),
        out_(sc.table("output")),
        fields_(out_.strings("fields")),
        particles_(dir, "particles"),
        bonds_(dir, "bonds") {
    std::vector<std::string> cols{"step", "time"};
    if (m.platens.enabled) cols.insert(cols.end(), {"strain", "stress", "force_top", "force_bottom"});
    cols.insert(cols.end(), {"kinetic_energy", "bond_energy", "external_work", "damping_dissipation",
                             "broken_tension", "broken_shear", "contacts"});
    probes_.emplace(dir / "probes.csv", cols);
  }

  void probe(const BuiltModel& m) {
    const auto& s = m.sim;
    std::vector<double> row{double(s.step_count()), s.time()};
    if (m.platens.enabled) {
      const AxialState a = axial_state(m);
      row.insert(row.end(), {a.strain, a.stress, a.force_top, a.force_bottom});
      strain_.push_back(a.strain);
      stress_.push_back(a.stress);
      probe_steps_.push_back(s.step_count());
    }
    row.insert(row.end(), {s.kinetic_energy(), s.bond_energy(), s.external_work(), s.damping_dissipation(),
                           double(s.broken_count(dem::BreakMode::Tension)),
                           double(s.broken_count(dem::BreakMode::Shear)), double(s.contact_count())});
    time_.push_back(s.time());
    kinetic_.push_back(s.kinetic_energy());
    bond_.push_back(s.bond_energy());
    work_.push_back(s.external_work());
    probes_->row(row);
  }

  void frame(const BuiltModel& m) {
    if (!out_.boolean("vtk")) return;
    const io::PointCloud pc = particle_frame(m.sim, fields_);
    particles_.add_particles(m.sim.time(), pc);
    bonds_.add_lines(m.sim.time(), pc, broken_bond_frame(m.sim));
  }

  /// Writes what is known at the end of a run (or at a failure): breaks, summary, plots.
  void finish(const BuiltModel& m, const json& model, double run_seconds, const std::string& status) {
    probes_->close();
    io::CsvWriter breaks(dir_ / "breaks.csv", {"step", "time", "x", "y", "z", "mode", "id_i", "id_j"});
    for (const auto& b : m.sim.breaks())
      breaks.row({double(b.step), double(b.step) * m.dt, b.position[0], b.position[1], b.position[2],
                  double(int(b.mode)), double(b.id_i), double(b.id_j)});
    breaks.close();

    json summary = model;
    summary["status"] = status;
    summary["steps_done"] = m.sim.step_count();
    summary["wall_seconds"] = run_seconds;
    summary["particle_steps_per_s"] =
        run_seconds > 0 ? double(m.sim.particle_count()) * double(m.sim.step_count()) / run_seconds : 0.0;
    summary["broken_tension"] = m.sim.broken_count(dem::BreakMode::Tension);
    summary["broken_shear"] = m.sim.broken_count(dem::BreakMode::Shear);
    if (!stress_.empty()) {
      const auto peak = std::max_element(stress_.begin(), stress_.end()) - stress_.begin();
      summary["peak_stress_pa"] = stress_[peak];
      summary["peak_strain"] = strain_[peak];
      // First tensile break: the strain of the first probe row at or after its step.
      for (const auto& b : m.sim.breaks()) {
        if (b.mode != dem::BreakMode::Tension) continue;
        const auto it = std::lower_bound(probe_steps_.begin(), probe_steps_.end(), b.step);
        if (it != probe_steps_.end()) summary["tensile_onset_strain"] = strain_[it - probe_steps_.begin()];
        break;
      }
    }
    write_file_atomic(dir_ / "summary.json", summary.dump(2) + "\n");
    written_.push_back(dir_ / "summary.json");
    written_.push_back(dir_ / "probes.csv");
    written_.push_back(dir_ / "breaks.csv");
    if (!particles_.frames().empty()) {
      written_.push_back(particles_.pvd_path());
      written_.push_back(bonds_.pvd_path());
    }
  }

  /// Plots and pictures (needs STRATA_WITH_RENDER).
  void pictures(const scene::Scene& sc) {
    if (!out_.boolean("render")) return;
#if STRATA_WITH_RENDER
    const std::string title = sc.table("scene").str("title");
    if (!stress_.empty()) {
      io::PlotRequest p;
      p.title = title.empty() ? "Axial stress against axial strain" : title;
      p.x_label = "axial strain [-]";
      p.y_label = "axial stress [MPa]";
      std::vector<double> mpa(stress_.size());
      for (std::size_t i = 0; i < mpa.size(); ++i) mpa[i] = stress_[i] / 1e6;
      p.series.push_back({"strata", strain_, mpa});
      p.png = dir_ / "stress_strain.png";
      io::plot_xy(p);
      written_.push_back(p.png);
    }
    {
      io::PlotRequest p;
      p.title = "Energy";
      p.x_label = "time [s]";
      p.y_label = "energy [J]";
      p.series.push_back({"kinetic", time_, kinetic_});
      p.series.push_back({"bond strain", time_, bond_});
      p.series.push_back({"work of external forces", time_, work_});
      p.png = dir_ / "energy.png";
      io::plot_xy(p);
      written_.push_back(p.png);
    }
    if (!particles_.frames().empty()) {
      io::RenderStyle style;
      style.title = title;
      style.field = out_.str("render_field");
      if (style.field == "displacement") style.field_scale = 1e3, style.unit = "mm";
      if (style.field == "velocity") style.unit = "m/s";
      if (style.field == "damage") style.field_label = "damage";
      const auto pngs = io::render_series(particles_.pvd_path(), dir_ / "png", style, bonds_.pvd_path());
      if (!pngs.empty()) written_.push_back(dir_ / "png" / "");
      if (out_.boolean("movie") && io::make_movie(dir_ / "png", dir_ / "movie.mp4"))
        written_.push_back(dir_ / "movie.mp4");
    }
#else
    (void)sc;
    log::warn("pictures skipped: this build has no rendering (reconfigure with -DSTRATA_WITH_RENDER=ON)");
#endif
  }

  /// Drops frames later than `time` from the series (they may hold a blow-up in progress);
  /// returns the last frame kept, or an empty path.
  fs::path keep_frames_until(double time) {
    if (particles_.frames().empty()) return {};
    particles_.truncate_after(time);
    bonds_.truncate_after(time);
    return particles_.frames().empty() ? fs::path() : dir_ / particles_.frames().back().file;
  }

  const std::vector<fs::path>& written() const { return written_; }

 private:
  fs::path dir_;
  const scene::Table& out_;
  std::vector<std::string> fields_;
  io::Series particles_, bonds_;
  std::optional<io::CsvWriter> probes_;
  std::vector<double> time_, kinetic_, bond_, work_, strain_, stress_;
  std::vector<std::int64_t> probe_steps_;
  std::vector<fs::path> written_;
};

}  // namespace

int check_scene(const SceneOptions& opt, bool json_out) {
  const scene::Scene sc = load_scene(opt);
  const BuiltModel m = build_model(sc, opt.force);
  const json j = model_json(m, sc);
  if (json_out)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_model(j);
  return 0;
}

int mesh_scene(const SceneOptions& opt, bool json_out) {
  const scene::Scene sc = load_scene(opt);
  const BuiltModel m = build_model(sc, /*force=*/true);
  json j = model_json(m, sc);
  j["seconds"] = m.build_seconds;
  j["particles_per_s"] = m.build_seconds > 0 ? double(m.sim.particle_count()) / m.build_seconds : 0.0;
  // Bond counts by length class (length / d, classes 0.02 wide): one class for a regular
  // lattice, a spread for an eccentric one (SPEC C4).
  const double d_ref = m.regions.empty() ? 0.0 : m.regions.front().diameter;
  const BondStats bonds = bond_stats(m.sim, d_ref);
  if (!bonds.length.empty()) j["bond_length_classes"] = bond_length_classes(bonds);
  if (!opt.output.empty()) {
    io::Series particles(opt.output, "model");
    const io::PointCloud pc = particle_frame(m.sim, {"id", "group"});
    j["written"] = json::array({particles.add_particles(0.0, pc).string()});
    for (const auto& f : write_bond_histograms(bonds, opt.output)) j["written"].push_back(f.string());
  }
  j["peak_rss_bytes"] = peak_rss_bytes();
  if (json_out) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    print_model(j);
    if (j.contains("bond_length_classes")) {
      std::printf("bond lengths (length/d: bonds)");
      for (const auto& [cls, n] : j["bond_length_classes"].items())
        std::printf("  %s: %zu", cls.c_str(), n.get<std::size_t>());
      std::printf("\n");
    } else if (m.sim.bond_count() > 0) {
      std::printf("bond lengths not listed: more than %zu bonds\n", kMaxReportedBonds);
    }
    std::printf("built in     %.3f s (%.3g particles/s), peak memory %.1f MB\n", m.build_seconds,
                j["particles_per_s"].get<double>(), j["peak_rss_bytes"].get<double>() / 1e6);
    if (j.contains("written"))
      for (const auto& w : j["written"]) std::printf("wrote        %s\n", w.get<std::string>().c_str());
  }
  return 0;
}

int run_scene(const SceneOptions& opt) {
  // Validate and build everything before the first byte is written.
  const scene::Scene sc = load_scene(opt);
  BuiltModel m = build_model(sc, opt.force);
  const json model = model_json(m, sc);
  print_model(model);

  const fs::path dir = opt.output.empty() ? fs::path(sc.table("output").str("directory")) : opt.output;
  fs::create_directories(dir);
  RunOutput out(dir, sc, m);

  const scene::Table& o = sc.table("output");
  const std::int64_t steps = m.steps;
  const std::int64_t probe_every =
      o.integer("probe_every") > 0 ? o.integer("probe_every") : std::max<std::int64_t>(1, steps / 2000);
  const std::int64_t frames = o.integer("frames");
  const std::int64_t frame_every = frames > 0 ? std::max<std::int64_t>(1, steps / frames) : steps + 1;

  log::info("running {} steps on {} thread(s); output in {}", steps, par::threads(), dir.string());
  Progress progress("run", steps);
  const auto t0 = std::chrono::steady_clock::now();
  std::int64_t next_probe = 0, next_frame = frames > 0 ? 0 : steps + 1;
  try {
    for (;;) {
      const std::int64_t s = m.sim.step_count();
      if (s >= next_probe) {
        out.probe(m);
        next_probe = std::min(next_probe + probe_every, steps);
        if (s >= steps) next_probe = steps + 1;
      }
      if (s >= next_frame) {
        out.frame(m);
        next_frame = std::min(next_frame + frame_every, steps);
        if (s >= steps) next_frame = steps + 1;
      }
      if (s >= steps) break;
      m.sim.run(std::min({next_probe, next_frame, steps}) - s);
      progress.update(m.sim.step_count());
    }
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Numerical) throw;
    progress.finish(m.sim.step_count());
    // Frames after the last passed health check may already hold the blow-up: drop them.
    const std::int64_t good = m.sim.last_good_step();
    const fs::path last = out.keep_frames_until((double(good) + 0.5) * m.dt);
    out.finish(m, model, seconds_since(t0), fmt::format("failed: {}", e.what()));
    const std::string kept = last.empty() ? std::string("no good frame had been written")
                                          : fmt::format(
                                                "last good frame kept: {} (the state at step {} passed "
                                                "the health check)",
                                                last.string(), good);
    fail(ErrorKind::Numerical, "{}\nrun stopped; {}; probes up to the failure in {}", e.what(), kept,
         (dir / "probes.csv").string());
  }
  progress.finish(m.sim.step_count());
  const double run_seconds = seconds_since(t0);
  out.finish(m, model, run_seconds, "completed");
  log::info("{} steps in {} ({:.3g} particle-steps/s); {} bonds broken ({} tension, {} shear)", steps,
            format_duration(run_seconds), double(m.sim.particle_count()) * double(steps) / run_seconds,
            m.sim.broken_count(), m.sim.broken_count(dem::BreakMode::Tension),
            m.sim.broken_count(dem::BreakMode::Shear));
  out.pictures(sc);

  std::printf("wrote:\n");
  for (const auto& p : out.written()) std::printf("  %s\n", p.string().c_str());
  return 0;
}

}  // namespace strata::app
