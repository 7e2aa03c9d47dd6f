#include "driver.hpp"

#include <signal.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/memory.hpp>
#include <strata/core/parallel.hpp>
#include <strata/core/progress.hpp>
#include <strata/core/state_io.hpp>
#include <strata/io/checkpoint.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/io/render.hpp>
#include <strata/io/series.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>

#include "frames.hpp"
#include "mesh_report.hpp"
#include "model_builder.hpp"
#include "report.hpp"
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

scene::Scene load_scene(const SceneOptions& opt) {
  scene::Scene sc = scene::load(opt.scene, opt.overrides);
  // A coupled scene's threads default per case (report.cpp); a particle scene's is [solver]'s.
  const int threads = opt.threads >= 0 ? opt.threads
                      : sc.coupled()   ? coupled_threads(sc)
                                       : int(sc.table("solver").integer("threads"));
  par::set_threads(threads);
  return sc;
}

/// What every model report holds: scene, regions, groups (`strata check`, `run`, `mesh`).
json model_counts_json(const scene::Scene& sc, int dim, const std::vector<RegionInfo>& regions_in,
                       const std::map<std::string, std::size_t>& groups_in) {
  json regions = json::array();
  for (const auto& r : regions_in)
    regions.push_back({{"name", r.name},
                       {"lattice", r.lattice},
                       {"particles", r.particles},
                       {"diameter_m", r.diameter},
                       {"packing_density", r.packing}});
  json groups = json::object();
  for (const auto& [name, n] : groups_in) groups[name] = n;
  return {{"scene", sc.file.string()},
          {"title", sc.table("scene").str("title")},
          {"dimension", dim},
          {"regions", regions},
          {"groups", groups}};
}

json model_json(const BuiltModel& m, const scene::Scene& sc) {
  json j = model_counts_json(sc, m.dim, m.regions, m.groups);
  j.update({{"particles", m.sim.particle_count()},
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
            {"threads", par::threads()}});
  return j;
}

/// `strata mesh`'s report of a model description: counts only, no DEM quantities (dt_crit,
/// dt, memory of the model arrays are `strata check`'s, which builds the DEM model).
json description_json(const ModelDescription& d, const scene::Scene& sc, std::size_t bonds) {
  std::map<std::string, std::size_t> groups;
  for (const auto& g : d.groups) groups[g.name] = g.count;
  json j = model_counts_json(sc, d.dim, d.regions, groups);
  json fem = json::array();
  for (const auto& f : d.fem)
    fem.push_back({{"name", f.name}, {"nodes", f.mesh.node_count()}, {"elements", f.mesh.cell_count()}});
  j.update({{"particles", d.particle_count()},
            {"bonds", bonds},
            {"fem_nodes", d.fem_nodes()},
            {"fem_elements", d.fem_elements()},
            {"fem_regions", fem},
            {"threads", par::threads()}});
  return j;
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
  for (const auto& f : j.value("fem_regions", json::array()))
    std::printf("FEM region   %-14s %zu nodes, %zu elements\n", f["name"].get<std::string>().c_str(),
                f["nodes"].get<std::size_t>(), f["elements"].get<std::size_t>());
  if (!j.contains("dt_s")) return;  // `strata mesh`: no DEM model built
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
  /// `resume`: a restart from a checkpoint taken after the outputs of its step were written;
  /// frames and probe rows later than that step (written before the run stopped) are dropped.
  RunOutput(const fs::path& dir, const scene::Scene& sc, const BuiltModel& m, const StateReader* resume)
      : dir_(dir),
        out_(sc.table("output")),
        fields_(out_.strings("fields")),
        title_(sc.table("scene").str("title")),
        particles_(dir, "particles", resume ? io::Series::Mode::Resume : io::Series::Mode::Fresh),
        bonds_(dir, "bonds", resume ? io::Series::Mode::Resume : io::Series::Mode::Fresh) {
    std::vector<std::string> cols{"step", "time"};
    if (m.platens.enabled) cols.insert(cols.end(), {"strain", "stress", "force_top", "force_bottom"});
    cols.insert(cols.end(), {"kinetic_energy", "bond_energy", "external_work", "damping_dissipation",
                             "broken_tension", "broken_shear", "contacts"});
    if (!resume) {
      probes_.emplace(dir / "probes.csv", cols);
      return;
    }
    first_step_ = m.sim.step_count();
    particles_.truncate_after(m.sim.time());
    bonds_.truncate_after(m.sim.time());
    probes_.emplace(io::CsvWriter::append(dir / "probes.csv", cols, double(m.sim.step_count())));
    time_ = resume->get<double>("driver/probes/time");
    kinetic_ = resume->get<double>("driver/probes/kinetic_energy", time_.size());
    bond_ = resume->get<double>("driver/probes/bond_energy", time_.size());
    work_ = resume->get<double>("driver/probes/external_work", time_.size());
    strain_ = resume->get<double>("driver/probes/strain");
    stress_ = resume->get<double>("driver/probes/stress", strain_.size());
    probe_steps_ = resume->get<std::int64_t>("driver/probes/step", strain_.size());
  }

  /// The probe series kept for the summary and the plots (part of a checkpoint).
  void save(StateWriter& w) const {
    w.put("driver/probes/time", time_);
    w.put("driver/probes/kinetic_energy", kinetic_);
    w.put("driver/probes/bond_energy", bond_);
    w.put("driver/probes/external_work", work_);
    w.put("driver/probes/strain", strain_);
    w.put("driver/probes/stress", stress_);
    w.put("driver/probes/step", probe_steps_);
  }

  /// How pictures look: the scene's title and [output] render_field, render_contacts,
  /// view_direction, view_up and clip_plane (checked by check_render_keys).
  io::RenderStyle render_style() const {
    io::RenderStyle style = field_style(out_.str("render_field"));
    style.title = title_;
    style.show_contacts = out_.boolean("render_contacts");
    for (std::size_t a = 0; a < 3; ++a) {
      style.view_direction[a] = out_.reals("view_direction")[a];
      style.view_up[a] = out_.reals("view_up")[a];
    }
    if (out_.has("clip_plane")) {
      std::array<double, 6> c{};
      std::copy_n(out_.reals("clip_plane").begin(), 6, c.begin());
      style.clip_plane = c;
    }
    return style;
  }

  /// Checks what the schema cannot: no zero view or clip normal, up not along the view.
  static void check_render_keys(const scene::Table& out) {
    auto norm = [](const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
    const double* d = out.reals("view_direction").data();
    const double* u = out.reals("view_up").data();
    if (norm(d) == 0) out.fail("view_direction", "the view direction must not be zero");
    if (norm(u) == 0) out.fail("view_up", "the up vector must not be zero");
    const double cross[3] = {d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]};
    if (norm(cross) <= 1e-9 * norm(d) * norm(u))
      out.fail("view_up", "the up vector must not be parallel to view_direction");
    if (out.has("clip_plane") && norm(out.reals("clip_plane").data() + 3) == 0)
      out.fail("clip_plane", "the clip plane's normal (the last three numbers) must not be zero");
  }

  /// Step of the last frame written by this process (-1: none).
  std::int64_t last_frame_step() const { return last_frame_step_; }
  /// The last frame listed in the series, or an empty path.
  fs::path last_frame() const {
    return particles_.frames().empty() ? fs::path() : dir_ / particles_.frames().back().file;
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
    last_frame_step_ = m.sim.step_count();
    if (!out_.boolean("vtk")) return;
    const io::PointCloud all = particle_frame(m.sim, fields_);
    const io::PointCloud pc = select_particles(m.sim, all, selection_);
    const io::LineSet bonds = bond_frame(m.sim, selection_);
    particles_.add_particles(m.sim.time(), pc);
    bonds_.add_lines(m.sim.time(), all, bonds);
#if STRATA_WITH_RENDER
    if (out_.boolean("render") && out_.boolean("render_while_running")) {
      io::RenderRequest req;
      req.particles = &pc;
      req.bonds = &bonds;
      req.bond_points = &all;
      req.png = dir_ / "png" / fmt::format("frame_{:06d}.png", particles_.frames().size() - 1);
      req.style = render_style();
      io::render_frame(req);
      rendered_while_running_ = true;
    }
#endif
  }

  void set_selection(FrameSelection sel) { selection_ = std::move(sel); }

  /// Particles and bonds the frames hold, from [output]; groups by name. Validates, so call
  /// it before anything is written.
  static FrameSelection selection(BuiltModel& m, const scene::Table& out) {
    FrameSelection selection_;
    const std::string& p = out.str("particles");
    selection_.particles = p == "surface" ? FrameSelection::Particles::Surface
                           : p == "none"  ? FrameSelection::Particles::None
                                          : FrameSelection::Particles::All;
    const std::string& b = out.str("bonds");
    selection_.bonds = b == "all"    ? FrameSelection::Bonds::All
                       : b == "none" ? FrameSelection::Bonds::None
                                     : FrameSelection::Bonds::Broken;
    selection_.contacts = out.boolean("contacts");
    check_render_keys(out);
    for (const auto& g : out.strings("groups")) {
      if (!m.groups.count(g)) out.fail("groups", fmt::format("no [[group]] or [[region]] is called '{}'", g));
      selection_.group_mask |= 1u << m.sim.group_bit(g);
    }
    selection_.slice_thickness = out.real("slice_thickness");
    for (std::size_t a = 0; a < 3; ++a) {
      selection_.slice_point[a] = a < out.reals("slice_point").size() ? out.reals("slice_point")[a] : 0.0;
      selection_.slice_normal[a] = a < out.reals("slice_normal").size() ? out.reals("slice_normal")[a] : 0.0;
    }
    double len = 0;
    for (double c : selection_.slice_normal) len += c * c;
    if (selection_.slice_thickness > 0 && len == 0)
      out.fail("slice_normal", "the slice normal must not be zero");
    for (double& c : selection_.slice_normal) c /= len > 0 ? std::sqrt(len) : 1.0;
    if (selection_.particles == FrameSelection::Particles::Surface) selection_.find_surface(m.sim);
    return selection_;
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
    // this process's steps (a restart continues from first_step_)
    summary["particle_steps_per_s"] =
        run_seconds > 0
            ? double(m.sim.particle_count()) * double(m.sim.step_count() - first_step_) / run_seconds
            : 0.0;
    if (first_step_ > 0) summary["restarted_at_step"] = first_step_;
    summary["state_hash"] = fmt::format("{:016x}", m.sim.state_hash());
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
    const std::string& title = title_;
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
      if (!rendered_while_running_) {
        const auto pngs =
            io::render_series(particles_.pvd_path(), dir_ / "png", render_style(), bonds_.pvd_path());
        if (pngs.empty()) return;
      }
      written_.push_back(dir_ / "png" / "");
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
  void add_written(const fs::path& p) { written_.push_back(p); }

 private:
  fs::path dir_;
  const scene::Table& out_;
  std::vector<std::string> fields_;
  std::string title_;
  FrameSelection selection_;
  bool rendered_while_running_ = false;
  io::Series particles_, bonds_;
  std::optional<io::CsvWriter> probes_;
  std::vector<double> time_, kinetic_, bond_, work_, strain_, stress_;
  std::vector<std::int64_t> probe_steps_;
  std::vector<fs::path> written_;
  std::int64_t last_frame_step_ = -1;
  std::int64_t first_step_ = 0;
};

// ---- checkpoints and restart --------------------------------------------------------------

/// Fingerprint of a validated scene: FNV-1a of a canonical text of every key (defaults
/// included, in schema order; referenced files by their contents), leaving out what a
/// restart may change without changing the model or its trajectory: the [output] table,
/// solver.steps, solver.duration and solver.threads.
std::string scene_fingerprint(const scene::Scene& sc) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::string_view text) {
    for (const unsigned char c : text) {
      h ^= c;
      h *= 1099511628211ull;
    }
    h ^= 0xff;  // separator
    h *= 1099511628211ull;
  };
  for (const scene::TableSpec& spec : scene::schema()) {
    if (spec.name == "output") continue;
    const std::vector<scene::Table>* list = &sc.tables(spec.name);
    std::vector<scene::Table> plain;
    if (!spec.array && sc.tables(spec.name).empty()) continue;  // [coupled] of a particle scene
    if (!spec.array) plain.push_back(sc.table(spec.name)), list = &plain;
    for (const scene::Table& t : *list) {
      mix(t.label());
      for (const scene::KeySpec& k : spec.keys) {
        if (spec.name == "solver" && (k.name == "steps" || k.name == "duration" || k.name == "threads"))
          continue;
        mix(k.name);
        if (!t.has(k.name)) {
          mix("<none>");
          continue;
        }
        using T = scene::Type;
        switch (k.type) {
          case T::Bool:
            mix(t.boolean(k.name) ? "true" : "false");
            break;
          case T::Integer:
            mix(fmt::format("{}", t.integer(k.name)));
            break;
          case T::Real:
            mix(fmt::format("{}", t.real(k.name)));
            break;
          case T::String:
          case T::Choice:
          case T::OutputPath:
            mix(t.str(k.name));
            break;
          case T::Path: {  // contents, so that a moved scene folder keeps its fingerprint
            std::ifstream f(t.str(k.name), std::ios::binary);
            mix(std::string(std::istreambuf_iterator<char>(f), {}));
            break;
          }
          case T::RealList:
            mix(fmt::format("{}", fmt::join(t.reals(k.name), ",")));
            break;
          case T::IntegerList:
            mix(fmt::format("{}", fmt::join(t.integers(k.name), ",")));
            break;
          case T::StringList:
            mix(fmt::format("{}", fmt::join(t.strings(k.name), ",")));
            break;
          case T::RealTable:
            for (const auto& row : t.real_table(k.name)) mix(fmt::format("{}", fmt::join(row, ",")));
            break;
        }
      }
    }
  }
  return fmt::format("{:016x}", h);
}

/// Opens a checkpoint for `strata run --restart` and refuses one of another scene or
/// another strata version (exit status 2; nothing has been written yet).
std::unique_ptr<io::CheckpointReader> open_checkpoint(const fs::path& file, const std::string& fingerprint,
                                                      const scene::Scene& sc) {
  std::unique_ptr<io::CheckpointReader> r;
  try {
    r = std::make_unique<io::CheckpointReader>(file);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::IO) throw;
    fail(ErrorKind::Input, "--restart: {}", e.what());
  }
  const io::CheckpointInfo& info = r->info();
  STRATA_CHECK(info.version == STRATA_VERSION, Input,
               "--restart: checkpoint {} was written by strata {}, this is strata {}; checkpoints are read "
               "only by the version that wrote them",
               file.string(), info.version, STRATA_VERSION);
  STRATA_CHECK(info.fingerprint == fingerprint, Input,
               "--restart: checkpoint {} belongs to another scene: its scene fingerprint is {}, {} (with its "
               "--set options) has {}. Only [output], solver.steps, solver.duration and solver.threads may "
               "change between a run and its restart",
               file.string(), info.fingerprint, sc.file.string(), fingerprint);
  return r;
}

/// Writes `<dir>/checkpoint.h5` (through a temporary file and a rename).
fs::path write_checkpoint(const fs::path& dir, const BuiltModel& m, const std::string& fingerprint,
                          const RunOutput& out, std::int64_t frame_breaks, double wall_seconds) {
  const fs::path file = dir / "checkpoint.h5";
  io::CheckpointWriter w(
      file, {STRATA_VERSION, fingerprint, m.dim, m.sim.particle_count(), m.sim.step_count(), m.sim.time()});
  m.sim.save_state(w);
  out.save(w);
  w.put_scalar<std::int64_t>("driver/frame_breaks", frame_breaks);
  w.put_scalar<double>("driver/wall_seconds", wall_seconds);
  w.commit();
  log::debug("checkpoint at step {} written to {}", m.sim.step_count(), file.string());
  return file;
}

// ---- SIGINT / SIGTERM ----------------------------------------------------------------------

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void on_stop_signal(int sig) { g_signal.store(sig); }  // only sets the flag

/// Routes SIGINT and SIGTERM to the flag for the duration of a run; restores the previous
/// handlers afterwards.
class StopSignals {
 public:
  StopSignals() {
    g_signal.store(0);
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  /// The signal received (0: none).
  static int received() { return g_signal.load(); }

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

// ---- output cadences -----------------------------------------------------------------------

/// When probes, frames and checkpoints are due: pure functions of the step (and, for
/// frame_every_breaks, of the break count at the last frame), so a restart continues them.
struct Cadence {
  enum class Frames { None, Steps, Time, Breaks };
  std::int64_t steps = 0;
  std::int64_t probe_every = 1;
  Frames frames = Frames::None;
  std::int64_t frame_every = 0;   // Steps
  double frame_time = 0, dt = 0;  // Time
  std::int64_t frame_breaks = 0;  // Breaks
  std::int64_t checkpoint_every = 0;

  Cadence(const scene::Table& o, std::int64_t total_steps, double time_step)
      : steps(total_steps), dt(time_step) {
    probe_every =
        o.integer("probe_every") > 0 ? o.integer("probe_every") : std::max<std::int64_t>(1, steps / 1000);
    checkpoint_every = o.integer("checkpoint_every");
    if (o.integer("frame_every_breaks") > 0) {
      frames = Frames::Breaks;
      frame_breaks = o.integer("frame_every_breaks");
    } else if (o.real("frame_every_time") > 0) {
      frames = Frames::Time;
      frame_time = o.real("frame_every_time");
    } else if (o.integer("frames") > 0) {
      frames = Frames::Steps;
      frame_every = std::max<std::int64_t>(1, steps / o.integer("frames"));
    }
  }

  /// Smallest step > s that is a multiple of `every`, or the last step.
  std::int64_t next_multiple(std::int64_t s, std::int64_t every) const {
    return std::min(steps, (s / every + 1) * every);
  }
  /// Step of the k-th frame of Frames::Time (the step nearest to k·frame_time).
  std::int64_t time_frame_step(std::int64_t k) const { return std::llround(double(k) * frame_time / dt); }

  bool probe_due(std::int64_t s) const { return s % probe_every == 0 || s == steps; }
  std::int64_t next_probe(std::int64_t s) const { return next_multiple(s, probe_every); }

  bool frame_due(std::int64_t s, std::size_t broken, std::size_t broken_at_last_frame) const {
    switch (frames) {
      case Frames::None:
        return false;
      case Frames::Steps:
        return s % frame_every == 0 || s == steps;
      case Frames::Time: {
        if (s == 0 || s == steps) return true;
        const auto k = std::int64_t(double(s) * dt / frame_time);
        return time_frame_step(k) == s || time_frame_step(k + 1) == s;
      }
      case Frames::Breaks:
        return s == 0 || s == steps ||
               (probe_due(s) && broken >= broken_at_last_frame + std::size_t(frame_breaks));
    }
    return false;
  }
  std::int64_t next_frame(std::int64_t s) const {
    switch (frames) {
      case Frames::Steps:
        return next_multiple(s, frame_every);
      case Frames::Time: {
        auto k = std::int64_t(double(s) * dt / frame_time);
        while (time_frame_step(k) <= s) ++k;
        return std::min(steps, time_frame_step(k));
      }
      default:
        return steps;  // Breaks: checked at probe rows
    }
  }
  bool checkpoint_due(std::int64_t s) const {
    return checkpoint_every > 0 && s > 0 && s % checkpoint_every == 0;
  }
  std::int64_t next_checkpoint(std::int64_t s) const {
    return checkpoint_every > 0 ? next_multiple(s, checkpoint_every) : steps;
  }
};
}  // namespace

int check_scene(const SceneOptions& opt, bool json_out) {
  const scene::Scene sc = load_scene(opt);
  if (sc.coupled()) return check_coupled_scene(sc, json_out, opt.force);  // report.cpp
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
  STRATA_CHECK(!sc.coupled(), Input,
               "{}: a coupled-chain scene ([coupled]) has no mesh to build; use 'strata check' for its "
               "stability numbers or 'strata run' for the sweep",
               sc.file.string());
  // The model as a description only (never a dem::Simulation): regions filled, FEM regions
  // meshed, bonds counted on a cell grid by length class (regular regions; never stored).
  const auto t0 = std::chrono::steady_clock::now();
  const ModelDescription d = describe_model(sc, /*allow_fem=*/true);
  const preprocess::PairCounts bonds = count_bonds(d);
  const double seconds = seconds_since(t0);
  json j = description_json(d, sc, bonds.pairs);
  j["seconds"] = seconds;
  j["particles_per_s"] = seconds > 0 ? double(d.particle_count()) / seconds : 0.0;
  // Bond counts by length class (length / d, classes 0.02 wide): one class for a regular
  // lattice, a spread for an eccentric one (SPEC C4).
  if (bonds.pairs > 0) j["bond_length_classes"] = bond_length_classes(bonds);
  if (!opt.output.empty()) {
    // Particles: all of them up to kMaxWrittenParticles, else the surface (or none).
    const std::size_t n = d.particle_count();
    std::vector<std::uint32_t> ids;
    std::string which = "all";
    if (n <= kMaxWrittenParticles) {
      ids.resize(n);
      for (std::size_t i = 0; i < n; ++i) ids[i] = std::uint32_t(i);
    } else {
      ids = surface_particles(d);
      which = "surface";
      if (ids.size() > kMaxWrittenParticles) ids.clear(), which = "none";
    }
    j["written"] = json::array();
    j["written_particles"] = {{"selection", which}, {"count", ids.size()}};
    if (!ids.empty()) {
      io::Series particles(opt.output, "model");
      j["written"].push_back(particles.add_particles(0.0, description_particles(d, ids)).string());
    }
    if (!d.fem.empty()) {
      io::Series fem(opt.output, "fem");
      j["written"].push_back(fem.add_mesh(0.0, description_fem(d)).string());
    }
    for (const auto& f : write_bond_histograms(bond_stats(d, bonds.pairs), opt.output))
      j["written"].push_back(f.string());
  }
  j["peak_rss_bytes"] = sys::peak_rss_bytes();
  if (json_out) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    print_model(j);
    if (j.contains("bond_length_classes")) {
      std::printf("bond lengths (length/d: bonds)");
      for (const auto& [cls, n] : j["bond_length_classes"].items())
        std::printf("  %s: %zu", cls.c_str(), n.get<std::size_t>());
      std::printf("\n");
    }
    std::printf("built in     %.3f s (%.3g particles/s), peak memory %.1f MB\n", seconds,
                j["particles_per_s"].get<double>(), j["peak_rss_bytes"].get<double>() / 1e6);
    std::printf("DEM          dt_crit and model memory: see 'strata check' (it builds the DEM model)\n");
    if (j.contains("written_particles") && j["written_particles"]["selection"] != "all")
      std::printf("particles    %zu > %zu: wrote %s particles only (%zu)\n", d.particle_count(),
                  kMaxWrittenParticles, j["written_particles"]["selection"].get<std::string>().c_str(),
                  j["written_particles"]["count"].get<std::size_t>());
    if (j.contains("written"))
      for (const auto& w : j["written"]) std::printf("wrote        %s\n", w.get<std::string>().c_str());
  }
  return 0;
}

int run_scene(const SceneOptions& opt) {
  // Validate and build everything, and check a checkpoint to restart from, before the first
  // byte is written.
  const scene::Scene sc = load_scene(opt);
  if (sc.coupled()) {  // report.cpp: checks, the sweep, then its files all at once
    STRATA_CHECK(opt.restart.empty(), Input,
                 "--restart: {} is a coupled-chain scene ([coupled]); its sweep has no checkpoints",
                 sc.file.string());
    return run_coupled_scene(sc, opt.output, opt.force, opt.threads);
  }
  const scene::Table& o = sc.table("output");
  if (!STRATA_WITH_HDF5 && !opt.restart.empty())
    fail_missing_feature("STRATA_WITH_HDF5", "checkpoints (--restart)");
  if (!STRATA_WITH_HDF5 && o.integer("checkpoint_every") > 0)
    fail_missing_feature("STRATA_WITH_HDF5", "checkpoints (output.checkpoint_every)");
  BuiltModel m = build_model(sc, opt.force);
  const std::string fingerprint = scene_fingerprint(sc);
  std::unique_ptr<io::CheckpointReader> ckpt;
  if (!opt.restart.empty()) {
    ckpt = open_checkpoint(opt.restart, fingerprint, sc);
    m.sim.load_state(*ckpt);
    m.dt = m.sim.dt();
  }
  FrameSelection selection = RunOutput::selection(m, o);
  const json model = model_json(m, sc);
  print_model(model);

  const fs::path dir = opt.output.empty() ? fs::path(o.str("directory")) : opt.output;
  fs::create_directories(dir);
  RunOutput out(dir, sc, m, ckpt.get());
  out.set_selection(std::move(selection));

  const std::int64_t steps = m.steps;
  const std::int64_t first = m.sim.step_count();  // 0, or the checkpoint's step
  const Cadence cad(o, steps, m.dt);
  std::int64_t frame_breaks = 0;  // broken bonds at the last frame (output.frame_every_breaks)
  double wall_before = 0;         // run time before the restart
  if (ckpt) {
    frame_breaks = ckpt->get_scalar<std::int64_t>("driver/frame_breaks");
    wall_before = ckpt->get_scalar<double>("driver/wall_seconds");
    std::printf("restart      step %lld (t = %.6g s) of %s\n", (long long)first, m.sim.time(),
                opt.restart.string().c_str());
    ckpt.reset();
    if (first >= steps)
      log::warn("the checkpoint is at step {}, solver.steps = {}: nothing left to run (raise solver.steps)",
                first, steps);
  }

  log::info("running {} steps on {} thread(s); output in {}", steps - std::min(first, steps), par::threads(),
            dir.string());
  Progress progress("run", steps);
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return wall_before + seconds_since(t0); };
  std::int64_t max_chunk = 4;  // steps per run() call, adapted to ~0.25 s so signals are seen soon
  const StopSignals stop;
  try {
    for (;;) {
      const std::int64_t s = m.sim.step_count();
      // outputs of step s (a restart's first step had them before its checkpoint was taken)
      if (!(first > 0 && s == first)) {
        if (cad.probe_due(s)) out.probe(m);
        if (cad.frame_due(s, m.sim.broken_count(), std::size_t(frame_breaks))) {
          out.frame(m);
          frame_breaks = std::int64_t(m.sim.broken_count());
        }
      }
      if (s >= steps) break;
      if (const int sig = StopSignals::received()) {
        // Interrupted: the current frame, a checkpoint, what is known so far; then stop.
        progress.finish(s);
        if (out.last_frame_step() != s) {
          out.frame(m);
          frame_breaks = std::int64_t(m.sim.broken_count());
        }
        fs::path ck;
        if (STRATA_WITH_HDF5) ck = write_checkpoint(dir, m, fingerprint, out, frame_breaks, wall());
        out.finish(m, model, seconds_since(t0),
                   fmt::format("interrupted by SIG{} at step {}", sigabbrev_np(sig), s));
        const fs::path frame = out.last_frame();
        std::printf("interrupted by SIG%s at step %lld (t = %.6g s)\n", sigabbrev_np(sig), (long long)s,
                    m.sim.time());
        if (!frame.empty()) std::printf("  last frame  %s\n", frame.string().c_str());
        if (!ck.empty())
          std::printf("  checkpoint  %s\n  continue with: strata run %s -o %s --restart %s\n",
                      ck.string().c_str(), sc.file.string().c_str(), dir.string().c_str(),
                      ck.string().c_str());
        std::fflush(stdout);
        return 128 + sig;
      }
      if (cad.checkpoint_due(s) && s != first)
        write_checkpoint(dir, m, fingerprint, out, frame_breaks, wall());
      const std::int64_t to =
          std::min({cad.next_probe(s), cad.next_frame(s), cad.next_checkpoint(s), steps, s + max_chunk});
      const auto c0 = std::chrono::steady_clock::now();
      m.sim.run(to - s);
      const double took = seconds_since(c0);
      if (to - s == max_chunk || took > 0.25)
        max_chunk = std::clamp<std::int64_t>(
            took > 0 ? std::int64_t(double(to - s) * 0.25 / took) : 2 * max_chunk, 1, 1 << 20);
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
  // A checkpoint at the end lets a later `--restart` (with more steps) continue the run.
  if (STRATA_WITH_HDF5) out.add_written(write_checkpoint(dir, m, fingerprint, out, frame_breaks, wall()));
  out.finish(m, model, run_seconds, "completed");
  const std::int64_t done = m.sim.step_count() - first;
  log::info("{} steps in {} ({:.3g} particle-steps/s); {} bonds broken ({} tension, {} shear)", done,
            format_duration(run_seconds),
            run_seconds > 0 ? double(m.sim.particle_count()) * double(done) / run_seconds : 0.0,
            m.sim.broken_count(), m.sim.broken_count(dem::BreakMode::Tension),
            m.sim.broken_count(dem::BreakMode::Shear));
  out.pictures(sc);

  std::printf("wrote:\n");
  for (const auto& p : out.written()) std::printf("  %s\n", p.string().c_str());
  return 0;
}

}  // namespace strata::app
