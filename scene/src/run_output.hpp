#pragma once
// Internal: everything a run writes (probes, frames, breaks, summary, pictures), in one place.
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <strata/config.hpp>
#include <strata/core/log.hpp>
#include <strata/core/memory.hpp>
#include <strata/core/state_io.hpp>
#include <strata/dem/hough.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/io/render.hpp>
#include <strata/io/series.hpp>
#include <strata/scene/files.hpp>
#include <strata/scene/frames.hpp>
#include <strata/scene/model.hpp>
#include <strata/scene/scene.hpp>

#include "wedge_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace strata::scene {

using nlohmann::json;
namespace fs = std::filesystem;

class RunOutput {
 public:
  /// `resume`: a restart from a checkpoint taken after the outputs of its step were written;
  /// frames and probe rows later than that step (written before the run stopped) are dropped.
  RunOutput(const fs::path& dir, const Scene& sc, const BuiltModel& m, const StateReader* resume)
      : dir_(dir),
        out_(sc.output),
        fields_(with_render_field(out_.fields, out_.render_field)),
        title_(sc.network ? sc.network->title.value : sc.scene.title.value),
        particles_on_(m.has_particles()),
        fem_on_(m.has_fem() && !m.has_network()),
        network_on_(m.has_network()),
        fem_energies_on_(m.has_fem()) {
    if (particles_on_) group_names_ = m.sim().group_names();
    const auto mode = resume ? io::Series::Mode::Resume : io::Series::Mode::Fresh;
    if (particles_on_) {
      particles_.emplace(dir, "particles", mode);
      bonds_.emplace(dir, "bonds", mode);
      if (!m.sim().walls().empty()) walls_.emplace(dir, "walls", mode);
    }
    if (fem_on_) fem_.emplace(dir, "fem", mode);
    std::vector<std::string> cols{"step", "time"};
    if (m.platens.enabled)
      cols.insert(cols.end(), {"strain", "stress", "force_top", "force_bottom", "lateral_strain"});
    if (particles_on_)
      cols.insert(cols.end(), {"kinetic_energy", "bond_energy", "external_work", "damping_dissipation",
                               "broken_tension", "broken_shear", "contacts"});
    if (network_on_) cols.insert(cols.end(), {"particle_energy", "particle_load_work"});
    if (fem_energies_on_) cols.insert(cols.end(), {"fem_kinetic_energy", "fem_strain_energy"});
    for (const auto& p : m.network_probes)
      cols.insert(cols.end(), {fmt::format("node{}_u", p.node), fmt::format("node{}_v", p.node)});
    // [probe] wedge_group and wedge_friction: checked with the scene (a 2D group, basal < internal)
    wedge_group_ = *sc.probe.wedge_group;
    wedge_backstop_ = *sc.probe.wedge_backstop;
    if (sc.probe.wedge_friction.given) wedge_friction_ = *sc.probe.wedge_friction;
    for (const auto& g : sc.probe.gauges.value) {
      if (!m.groups.count(g) && !m.fem_groups.count(g))
        sc.probe.gauges.fail(fmt::format("no [[group]] or [[region]] is called '{}'", g));
      gauges_.push_back(g);
      for (int a = 0; a < m.dim; ++a) cols.push_back(fmt::format("{}_u{}", g, "xyz"[a]));
    }
    if (!resume) {
      probes_.emplace(dir / "probes.csv", cols);
      return;
    }
    first_step_ = m.step_count();
    for (auto* series : {&particles_, &bonds_, &fem_, &walls_})
      if (*series) (*series)->truncate_after(m.time());
    probes_.emplace(io::CsvWriter::append(dir / "probes.csv", cols, double(m.step_count())));
    time_ = resume->get<double>("driver/probes/time");
    if (particles_on_) {
      kinetic_ = resume->get<double>("driver/probes/kinetic_energy", time_.size());
      bond_ = resume->get<double>("driver/probes/bond_energy", time_.size());
      work_ = resume->get<double>("driver/probes/external_work", time_.size());
    }
    if (network_on_) network_ = resume->get<double>("driver/probes/network_energy", time_.size());
    if (fem_energies_on_) {
      fem_kinetic_ = resume->get<double>("driver/probes/fem_kinetic_energy", time_.size());
      fem_strain_ = resume->get<double>("driver/probes/fem_strain_energy", time_.size());
    }
    strain_ = resume->get<double>("driver/probes/strain");
    stress_ = resume->get<double>("driver/probes/stress", strain_.size());
    lateral_ = resume->get<double>("driver/probes/lateral_strain", strain_.size());
    probe_steps_ = resume->get<std::int64_t>("driver/probes/step", strain_.size());
  }

  /// The probe series kept for the summary and the plots (part of a checkpoint).
  void save(StateWriter& w) const {
    w.put("driver/probes/time", time_);
    if (particles_on_) {
      w.put("driver/probes/kinetic_energy", kinetic_);
      w.put("driver/probes/bond_energy", bond_);
      w.put("driver/probes/external_work", work_);
    }
    if (network_on_) w.put("driver/probes/network_energy", network_);
    if (fem_energies_on_) {
      w.put("driver/probes/fem_kinetic_energy", fem_kinetic_);
      w.put("driver/probes/fem_strain_energy", fem_strain_);
    }
    w.put("driver/probes/strain", strain_);
    w.put("driver/probes/stress", stress_);
    w.put("driver/probes/lateral_strain", lateral_);
    w.put("driver/probes/step", probe_steps_);
  }

  /// The frame fields: those asked for and the one the pictures are coloured by.
  static std::vector<std::string> with_render_field(std::vector<std::string> fields,
                                                    const std::string& render) {
    if (std::find(fields.begin(), fields.end(), render) == fields.end()) fields.push_back(render);
    return fields;
  }

  /// How pictures look: the scene's title and [output] render_field, render_contacts,
  /// render_cracks, render_size, view_direction, view_up and clip_plane (checked by
  /// check_render_keys). Groups are drawn as categories named after the groups.
  io::RenderStyle render_style() const {
    io::RenderStyle style = field_style(out_.render_field, group_names_);
    style.title = title_;
    style.show_contacts = out_.render_contacts;
    style.show_broken_bonds = out_.render_cracks;
    style.width = static_cast<int>(out_.render_size.value[0]);
    style.height = static_cast<int>(out_.render_size.value[1]);
    for (std::size_t a = 0; a < 3; ++a) {
      style.view_direction[a] = out_.view_direction.value[a];
      style.view_up[a] = out_.view_up.value[a];
    }
    if (out_.clip_plane.given) {
      std::array<double, 6> c{};
      std::copy_n(out_.clip_plane->begin(), 6, c.begin());
      style.clip_plane = c;
    }
    return style;
  }

  /// Checks what the schema cannot: no zero view or clip normal, up not along the view.
  static void check_render_keys(const OutputTable& out) {
    auto norm = [](const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
    const double* d = out.view_direction->data();
    const double* u = out.view_up->data();
    if (norm(d) == 0) out.view_direction.fail("the view direction must not be zero");
    if (norm(u) == 0) out.view_up.fail("the up vector must not be zero");
    const double cross[3] = {d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]};
    if (norm(cross) <= 1e-9 * norm(d) * norm(u))
      out.view_up.fail("the up vector must not be parallel to view_direction");
    if (out.clip_plane.given && norm(out.clip_plane->data() + 3) == 0)
      out.clip_plane.fail("the clip plane's normal (the last three numbers) must not be zero");
  }

  /// Step of the last frame written by this process (-1: none).
  std::int64_t last_frame_step() const { return last_frame_step_; }
  /// The last frame listed in the series, or an empty path.
  fs::path last_frame() const {
    const auto& series = particles_on_ ? particles_ : fem_;
    if (!series) return {};
    return series->frames().empty() ? fs::path() : dir_ / series->frames().back().file;
  }

  void probe(const BuiltModel& m) {
    std::vector<double> row{double(m.step_count()), m.time()};
    if (m.platens.enabled) {
      const AxialState a = axial_state(m);
      row.insert(row.end(), {a.strain, a.stress, a.force_top, a.force_bottom, a.lateral_strain});
      strain_.push_back(a.strain);
      stress_.push_back(a.stress);
      lateral_.push_back(a.lateral_strain);
      probe_steps_.push_back(m.step_count());
    }
    time_.push_back(m.time());
    if (particles_on_) {
      const auto& s = m.sim();
      // each energy once: where the last step did not sum them (at step 0, say), each is a
      // pass over every pair
      const double kinetic = s.kinetic_energy(), bond = s.bond_energy(), work = s.external_work();
      row.insert(row.end(), {kinetic, bond, work, s.damping_dissipation(),
                             double(s.broken_count(dem::BreakMode::Tension)),
                             double(s.broken_count(dem::BreakMode::Shear)), double(s.contact_count())});
      kinetic_.push_back(kinetic);
      bond_.push_back(bond);
      work_.push_back(work);
    }
    if (network_on_) {
      const double e = m.network().energy();
      row.insert(row.end(), {e, m.network().load_work()});
      network_.push_back(e);
    }
    if (fem_energies_on_) {
      const auto& f = m.fem();
      row.insert(row.end(), {f.kinetic_energy(), f.strain_energy()});
      fem_kinetic_.push_back(f.kinetic_energy());
      fem_strain_.push_back(f.strain_energy());
    }
    for (const auto& p : m.network_probes) {
      const auto [u, v] = m.network_probe(p);
      row.insert(row.end(), {u, v});
    }
    if (!gauges_.empty()) {
      const auto sums = gauge_displacements(m);
      row.insert(row.end(), sums.begin(), sums.end());
    }
    probes_->row(row);
  }

  /// Whether the specimen has failed: a bond has broken and the axial stress of the last probe
  /// row has fallen below `fraction` of its peak so far, after the peak ([probe] stop_after_peak).
  bool specimen_failed(const BuiltModel& m, double fraction) const {
    if (!(fraction > 0) || stress_.empty() || m.sim().breaks().empty()) return false;
    const double peak = *std::max_element(stress_.begin(), stress_.end());
    return peak > 0 && stress_.back() < fraction * peak;
  }

  /// What finish() wrote to summary.json.
  const json& summary() const { return summary_; }

  /// The run stopped at `step` because the specimen had failed (summary.json says so).
  void stopped_after_peak(std::int64_t step) { stopped_after_peak_ = step; }

  /// Mean displacement of each gauge group (its particles and FEM nodes together), `dim`
  /// components per gauge.
  std::vector<double> gauge_displacements(const BuiltModel& m) const {
    std::vector<double> out;
    std::vector<std::array<double, 3>> u;
    std::vector<std::uint32_t> where;
    if (particles_on_) {
      u = m.sim().displacements();
      const auto ids = m.sim().ids();
      where.resize(ids.size());
      for (std::size_t i = 0; i < ids.size(); ++i) where[ids[i]] = std::uint32_t(i);
    }
    for (const auto& g : gauges_) {
      std::array<double, 3> sum{};
      double n = 0;
      if (m.groups.count(g))
        for (auto id : m.sim().group_members(g)) {
          for (int a = 0; a < 3; ++a) sum[a] += u[where[id]][a];
          n += 1;
        }
      if (const auto it = m.fem_groups.find(g); it != m.fem_groups.end())
        for (auto node : it->second) {
          for (int a = 0; a < m.dim; ++a) sum[a] += m.fem().u()[Eigen::Index(node) * m.dim + a];
          n += 1;
        }
      for (int a = 0; a < m.dim; ++a) out.push_back(n > 0 ? sum[a] / n : 0.0);
    }
    return out;
  }

  /// A frame of the state now (a network scene has none to write: its nodes have no place).
  void frame(const BuiltModel& m) {
    last_frame_step_ = m.step_count();
    if (network_on_) return;
    if (!STRATA_WITH_VTK || !out_.vtk) return;  // without VTK only what the scene left at defaults
    std::optional<io::MeshFrame> mesh;
    if (fem_on_) {
      const fem::Solver& f = m.fem();
      mesh = fem_frame(f.mesh(), f.u(), f.v(), m.time(), m.step_count());
    }
    std::optional<SelectedFrame> particles;
    // a coupled frame's points are all particles: show_overlap places them
    if (particles_on_) particles = selected_frame(m.sim(), fields_, selection_, m.coupled());
    if (m.coupled())  // the state after the overlap exchange
      show_overlap(m.coupler(), m.sim(), m.dim, mesh ? &*mesh : nullptr,
                   particles ? &particles->points : nullptr);
    if (mesh) fem_->add_mesh(m.time(), *mesh);
    if (!particles_on_) return;
    const auto& sim = m.sim();
    const io::PointCloud& all = particles->points;
    const io::PointCloud pc = particles->particles();
    const io::LineSet& bonds = particles->bonds;
    particles_->add_particles(sim.time(), pc);
    bonds_->add_lines(sim.time(), all, bonds);
    std::optional<io::MeshFrame> walls;
    if (walls_) {
      walls = wall_frame(sim);
      walls_->add_mesh(sim.time(), *walls);
    }
#if STRATA_WITH_RENDER
    if (out_.render && out_.render_while_running) {
      io::RenderRequest req;
      req.particles = &pc;
      req.bonds = &bonds;
      req.bond_points = &all;
      req.mesh = mesh ? &*mesh : nullptr;
      req.walls = walls ? &*walls : nullptr;
      req.png = dir_ / "png" / fmt::format("frame_{:06d}.png", particles_->frames().size() - 1);
      req.style = render_style();
      io::render_frame(req);
      rendered_while_running_ = true;
    }
#endif
  }

  void set_selection(FrameSelection sel) { selection_ = std::move(sel); }

  /// Particles and bonds the frames hold, from [output]; groups by name. Validates, so call
  /// it before anything is written.
  static FrameSelection selection(BuiltModel& m, const OutputTable& out) {
    FrameSelection selection_;
    const std::string& p = out.particles;
    selection_.particles = p == "surface"             ? FrameSelection::Particles::Surface
                           : p == "surface_and_slice" ? FrameSelection::Particles::SurfaceAndSlice
                           : p == "none"              ? FrameSelection::Particles::None
                                                      : FrameSelection::Particles::All;
    const std::string& b = out.bonds;
    selection_.bonds = b == "all"    ? FrameSelection::Bonds::All
                       : b == "none" ? FrameSelection::Bonds::None
                                     : FrameSelection::Bonds::Broken;
    selection_.contacts = out.contacts;
    check_render_keys(out);
    for (const auto& g : out.groups.value) {
      if (!m.groups.count(g))
        out.groups.fail(fmt::format("no [[group]] or [[region]] of particles is called '{}'", g));
      selection_.groups.push_back(g);
    }
    selection_.slice_thickness = out.slice_thickness;
    for (std::size_t a = 0; a < 3; ++a) {
      selection_.slice_point[a] = a < out.slice_point->size() ? out.slice_point.value[a] : 0.0;
      selection_.slice_normal[a] = a < out.slice_normal->size() ? out.slice_normal.value[a] : 0.0;
    }
    double len = 0;
    for (double c : selection_.slice_normal) len += c * c;
    if (selection_.slice_thickness > 0 && len == 0)
      out.slice_normal.fail("the slice normal must not be zero");
    for (double& c : selection_.slice_normal) c /= len > 0 ? std::sqrt(len) : 1.0;
    if (selection_.particles == FrameSelection::Particles::SurfaceAndSlice && selection_.slice_thickness == 0)
      out.particles.fail(
          "particles = \"surface_and_slice\" writes the surface and a slice, and output.slice_thickness is 0 "
          "(no slice); allowed: slice_thickness > 0 with slice_point and slice_normal, or particles = "
          "\"surface\"");
    if (selection_.particles != FrameSelection::Particles::All &&
        selection_.particles != FrameSelection::Particles::None && m.has_particles())
      selection_.find_surface(m.sim());
    return selection_;
  }

  /// Writes what is known at the end of a run (or at a failure): breaks, summary, plots.
  void finish(const BuiltModel& m, const json& model, double run_seconds, const std::string& status) {
    probes_->close();
    if (particles_on_) {
      io::CsvWriter breaks(dir_ / "breaks.csv", {"step", "time", "x", "y", "z", "mode", "id_i", "id_j"});
      for (const auto& b : m.sim().breaks())
        breaks.row({double(b.step), double(b.step) * m.dt, b.position[0], b.position[1], b.position[2],
                    double(int(b.mode)), double(b.id_i), double(b.id_j)});
      breaks.close();
    }

    json summary = model;
    summary["status"] = status;
    summary["steps_done"] = m.step_count();
    summary["wall_seconds"] = run_seconds;
    summary["peak_resident_bytes"] = sys::peak_rss_bytes();  // of the process so far, set-up included
    // this process's steps (a restart continues from first_step_)
    const double n = particles_on_ ? double(m.sim().particle_count()) : 0.0;
    summary["particle_steps_per_s"] =
        run_seconds > 0 ? n * double(m.step_count() - first_step_) / run_seconds : 0.0;
    if (first_step_ > 0) summary["restarted_at_step"] = first_step_;
    if (stopped_after_peak_ >= 0) summary["stopped_after_peak_at_step"] = stopped_after_peak_;
    summary["state_hash"] = fmt::format("{:016x}", m.state_hash());
    if (particles_on_) {
      summary["broken_tension"] = m.sim().broken_count(dem::BreakMode::Tension);
      summary["broken_shear"] = m.sim().broken_count(dem::BreakMode::Shear);
      summary["steps_in_lattice_slots"] = m.sim().steps_in_lattice_slots();  // this process's
    }
    if (!stress_.empty()) {
      const auto peak = std::max_element(stress_.begin(), stress_.end()) - stress_.begin();
      summary["peak_stress_pa"] = stress_[peak];
      summary["peak_strain"] = strain_[peak];
      // First tensile break: the strain of the first probe row at or after its step.
      for (const auto& b : m.sim().breaks()) {
        if (b.mode != dem::BreakMode::Tension) continue;
        const auto it = std::lower_bound(probe_steps_.begin(), probe_steps_.end(), b.step);
        if (it != probe_steps_.end()) summary["tensile_onset_strain"] = strain_[it - probe_steps_.begin()];
        break;
      }
      if (const auto e = measured_elastic(m)) summary["measured_elastic"] = *e;
      if (const auto b = shear_bands(m, probe_steps_[std::size_t(peak)])) summary["shear_bands"] = *b;
    }
    if (!wedge_group_.empty())
      summary["wedge"] = wedge_report(m.sim(), wedge_group_, wedge_backstop_, wedge_friction_);
    write_file_atomic(dir_ / "summary.json", summary.dump(2) + "\n");
    summary_ = std::move(summary);
    written_.push_back(dir_ / "summary.json");
    written_.push_back(dir_ / "probes.csv");
    if (particles_on_) written_.push_back(dir_ / "breaks.csv");
    if (particles_on_ && !particles_->frames().empty()) {
      written_.push_back(particles_->pvd_path());
      written_.push_back(bonds_->pvd_path());
      if (walls_) written_.push_back(walls_->pvd_path());
    }
    if (fem_on_ && !fem_->frames().empty()) written_.push_back(fem_->pvd_path());
  }

  /// Young's modulus and Poisson's ratio measured on the specimen: least-squares slopes of
  /// stress against axial strain and of lateral against axial strain over the probe rows
  /// whose stress lies between 10 % and 60 % of the stress at the first break (at the peak
  /// when nothing broke), where the specimen is elastic and past the first transients.
  /// Nothing when fewer than 5 rows fall in that window.
  std::optional<json> measured_elastic(const BuiltModel& m) const {
    std::size_t end = stress_.size();  // rows before the first break
    if (!m.sim().breaks().empty()) {
      const auto first = m.sim().breaks().front().step;
      end = std::size_t(std::lower_bound(probe_steps_.begin(), probe_steps_.end(), first) -
                        probe_steps_.begin());
    }
    if (end == 0) return std::nullopt;
    const double top = *std::max_element(stress_.begin(), stress_.begin() + std::ptrdiff_t(end));
    std::vector<std::size_t> rows;
    for (std::size_t i = 0; i < end; ++i)
      if (stress_[i] >= 0.1 * top && stress_[i] <= 0.6 * top) rows.push_back(i);
    if (rows.size() < 5 || !(top > 0)) return std::nullopt;
    auto slope = [&](const std::vector<double>& y) {
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (auto i : rows)
        sx += strain_[i], sy += y[i], sxx += strain_[i] * strain_[i], sxy += strain_[i] * y[i];
      const double n = double(rows.size());
      return (n * sxy - sx * sy) / (n * sxx - sx * sx);
    };
    json e;
    e["youngs_modulus_pa"] = slope(stress_);
    if (!m.platens.sides.empty()) e["poisson_ratio"] = slope(lateral_);
    e["rows"] = rows.size();
    e["window"] = "stress 10-60 % of that at the first break (or the peak), before it";
    return e;
  }

  /// The conjugate shear bands of a 2D specimen, traced by the bonds that broke from the peak
  /// stress on (dem::conjugate_bands, with the platen rows' diameter as the spacing).
  /// Nothing in 3D or when fewer than 20 bonds broke after the peak.
  std::optional<json> shear_bands(const BuiltModel& m, std::int64_t peak_step) const {
    if (m.sim().dim() != 2) return std::nullopt;
    std::vector<std::array<double, 2>> pts;
    for (const auto& b : m.sim().breaks())
      if (b.step >= peak_step) pts.push_back({b.position[0], b.position[1]});
    if (pts.size() < 20) return std::nullopt;
    const auto bands = dem::conjugate_bands(pts, m.platens.axis, 2 * m.platens.radius);
    json j;
    j["from_step"] = peak_step;
    j["breaks_after_peak"] = pts.size();
    j["bands"] = json::array();
    for (const auto& band : bands)
      j["bands"].push_back({{"angle_to_load_deg", band.angle_deg},
                            {"width_m", band.width},
                            {"breaks", band.breaks},
                            {"theta_rad", band.line.theta},
                            {"rho_m", band.line.rho}});
    // How dominant the bands are: the share of the post-peak breaks in either band. A failure
    // that localises in two bands puts a large share there; a network of many parallel damage
    // lines a small one.
    std::size_t inside = 0;
    for (const auto& p : pts)
      inside += std::any_of(bands.begin(), bands.end(), [&](const dem::ShearBand& b) { return b.holds(p); });
    j["fraction_in_bands"] = double(inside) / double(pts.size());
    return j;
  }

  /// Plots and pictures (needs STRATA_WITH_RENDER). `stop_requested` is asked before each
  /// picture: a non-zero answer stops drawing (the pictures drawn so far stay) and is returned.
  int pictures(const Scene& sc, const std::function<int()>& stop_requested) {
    if (!out_.render) return 0;
    int reason = 0;
    const std::function<bool()> stop = [&] { return (reason = stop_requested()) != 0; };
#if STRATA_WITH_RENDER
    const std::string& title = title_;
    if (stop()) return reason;
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
      if (particles_on_) {
        p.series.push_back({fem_on_ ? "kinetic (particles)" : "kinetic", time_, kinetic_});
        p.series.push_back({"bond strain", time_, bond_});
        p.series.push_back({"work of external forces", time_, work_});
      }
      if (network_on_) p.series.push_back({"kinetic + spring (particle part)", time_, network_});
      if (fem_energies_on_) {
        p.series.push_back({"kinetic (FEM)", time_, fem_kinetic_});
        p.series.push_back({"strain (FEM)", time_, fem_strain_});
      }
      p.png = dir_ / "energy.png";
      io::plot_xy(p);
      written_.push_back(p.png);
    }
    const bool frames =
        (particles_on_ && !particles_->frames().empty()) || (fem_on_ && !fem_->frames().empty());
    if (frames) {
      if (!rendered_while_running_) {
        std::vector<fs::path> pngs;
        if (particles_on_) {
          io::SeriesPaths series{particles_->pvd_path(), bonds_->pvd_path(), {}, {}};
          if (fem_on_) series.mesh = fem_->pvd_path();
          if (walls_) series.walls = walls_->pvd_path();
          pngs = io::render_series(series, dir_ / "png", render_style(), stop);
        } else {
          io::FrameFiles files;
          for (const auto& f : fem_->frames()) files.meshes.push_back(dir_ / f.file);
          pngs = io::render_frames(files, dir_ / "png", render_style(), stop);
        }
        if (!pngs.empty()) written_.push_back(dir_ / "png" / "");
        if (reason != 0 || pngs.empty()) return reason;
      } else {
        written_.push_back(dir_ / "png" / "");
      }
      if (out_.movie && !stop())
        if (const fs::path movie = io::make_movie(dir_ / "png", dir_ / "movie"); !movie.empty())
          written_.push_back(movie);
    }
#else
    (void)sc;
    (void)stop;
    log::warn("pictures skipped: this build has no rendering (reconfigure with -DSTRATA_WITH_RENDER=ON)");
#endif
    return reason;
  }

  /// Drops frames later than `time` from the series (they may hold a blow-up in progress);
  /// returns the last frame kept, or an empty path.
  fs::path keep_frames_until(double time) {
    for (auto* series : {&particles_, &bonds_, &fem_, &walls_})
      if (*series) (*series)->truncate_after(time);
    return last_frame();
  }

  const std::vector<fs::path>& written() const { return written_; }
  void add_written(const fs::path& p) { written_.push_back(p); }

 private:
  fs::path dir_;
  const OutputTable& out_;
  std::vector<std::string> fields_;
  std::vector<std::string> gauges_;
  std::string title_;
  std::vector<std::string> group_names_;  ///< by group index: the categories of the group field
  std::string wedge_group_;               ///< [probe] wedge_group; empty: no wedge report
  std::string wedge_backstop_;            ///< [probe] wedge_backstop; empty: the moving wall
  std::vector<double> wedge_friction_;    ///< internal, basal; empty: no critical taper
  FrameSelection selection_;
  bool rendered_while_running_ = false;
  /// fem_on_: FEM regions (series, frames, pictures); network_on_: a network scene;
  /// fem_energies_on_: an FEM part of either (its energies in the probes).
  bool particles_on_ = false, fem_on_ = false, network_on_ = false, fem_energies_on_ = false;
  std::optional<io::Series> particles_, bonds_, fem_, walls_;  // walls_ only when there are walls
  std::optional<io::CsvWriter> probes_;
  std::vector<double> time_, kinetic_, bond_, work_, fem_kinetic_, fem_strain_, network_, strain_, stress_,
      lateral_;
  std::vector<std::int64_t> probe_steps_;
  std::vector<fs::path> written_;
  std::int64_t last_frame_step_ = -1;
  std::int64_t first_step_ = 0;
  std::int64_t stopped_after_peak_ = -1;
  json summary_;  ///< the last summary written  ///< the step a failed specimen stopped the run at
};

}  // namespace strata::scene
