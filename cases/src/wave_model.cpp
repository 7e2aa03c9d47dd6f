// The coupled wave's model and one run of it (see wave_report.hpp): each point of the sweep
// as a scene (regions from the geometry file, roller groups, the smooth traction pulse),
// built and stepped through scene::Run, with its gauges read through the coupler's
// observers, its pictures of the pulse crossing the overlap, and the windows that separate
// the incident, reflected and transmitted pulses.
#include <strata/cases/wave_report.hpp>

#include "case_helpers.hpp"
#include "wave_internal.hpp"

#include <nlohmann/json.hpp>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>
#include <strata/couple/dem_partition.hpp>
#include <strata/couple/fem_partition.hpp>
#include <strata/dem/lattice_elastic.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/io/render.hpp>
#include <strata/scene/files.hpp>
#include <strata/scene/run.hpp>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include <strata/cases/chain_report.hpp>
#include <strata/core/clock.hpp>
#include <strata/scene/frames.hpp>
#include <strata/scene/scene.hpp>

namespace strata::cases {

using scene::fem_frame;
using scene::particle_frame;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace wave_detail;

// The bonds of Liu, Pollard & Shi 2013 (elastic: the pulse must not break anything).
constexpr double kKn = 6.587e10, kKs = 2.371e10, kRho = 2.65e3;

}  // namespace

PulsePlan wave_detail::plan_of(const WaveModel& m, const WaveOptions& opt, double lambda_d) {
  const double lambda = lambda_d * m.d;
  double limit = 4.0 / 3.0 *
                 std::min({m.fem_gauge_depth, m.dem_length, m.load_depth - m.fem_gauge_depth,
                           m.dem_length - m.dem_gauge_depth});
  // Embedded: the second interface's reflection must arrive at the FEM gauge before the first
  // one's, bounced off the loaded side, comes back; the exit gauge must see the pulse before
  // its bounce off the exit block's far side.
  if (m.embedded)
    limit = std::min({limit, 4.0 / 3.0 * (m.load_depth - m.fem_gauge_depth - m.dem_length),
                      4.0 / 3.0 * (m.exit_length - m.exit_gauge_depth)});
  STRATA_CHECK(
      lambda_d > 0 && lambda <= limit, Input,
      "wave: a pulse of {} particle diameters ({:.4g} m) is too long for this geometry: incident, "
      "reflected and transmitted pulses separate in time only up to {:.4g} m ({:.1f} diameters); use "
      "a longer geometry or a shorter pulse",
      lambda_d, lambda, limit, limit / m.d);
  PulsePlan p;
  p.T = lambda / m.c;
  p.t_inc = (m.load_depth - m.fem_gauge_depth) / m.c;
  p.t_ref = (m.load_depth + m.fem_gauge_depth) / m.c;
  p.t_tra = (m.load_depth + m.dem_gauge_depth) / m.c;
  p.t_end = std::max(p.t_ref, p.t_tra) + kAfter * p.T;
  if (m.embedded) {
    p.t_ref2 = p.t_ref + 2 * m.dem_length / m.c;
    p.t_exit = (m.load_depth + m.dem_length + m.exit_gauge_depth) / m.c;
    p.t_end = std::max({p.t_end, p.t_ref2 + kAfter * p.T, p.t_exit + kAfter * p.T});
  }
  p.sigma0 = m.rho * m.c * opt.peak_velocity;
  return p;
}

namespace {

// Peak |v| and ∫v² dt (trapezoid) of a sampled signal over [a, b].
struct WindowMeasure {
  double peak = 0, energy = 0, signed_peak = 0;
};
WindowMeasure measure(const std::vector<double>& t, const std::vector<double>& v, double a, double b) {
  WindowMeasure w;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < a || t[i] > b) continue;
    if (std::abs(v[i]) > w.peak) w.peak = std::abs(v[i]), w.signed_peak = v[i];
    if (i + 1 < t.size() && t[i + 1] <= b)
      w.energy += 0.5 * (v[i] * v[i] + v[i + 1] * v[i + 1]) * (t[i + 1] - t[i]);
  }
  return w;
}

// measure() over the arrival window of a pulse of duration T that arrives at t_arrival.
WindowMeasure measure_arrival(const std::vector<double>& t, const std::vector<double>& v, double t_arrival,
                              double T) {
  return measure(t, v, t_arrival - kBefore * T, t_arrival + kAfter * T);
}

// "auto": central difference while η·dt_DEM is below the FEM's explicit limit (rollers and
// overlap externals held, computed once by build_wave_model), implicit Newmark above it.
std::string scheme_name(const WaveModel& m, int eta, const std::string& scheme) {
  if (scheme != "auto") return fem::to_string(fem::scheme_from_string(scheme));
  return eta * m.dt_dem <= m.fem_explicit_dt ? "central-difference" : "implicit-newmark";
}

// ---- the model as a scene: every run builds and steps it through the scene library ----

// The smallest box around `pts` (2D), widened by `tol`; no point of `others` may fall inside
// (the box selects exactly `pts`).
std::pair<std::array<double, 2>, std::array<double, 2>> box_around(
    const std::vector<std::array<double, 3>>& pts, const std::vector<std::array<double, 3>>& others,
    double tol, const char* what) {
  STRATA_CHECK(!pts.empty(), Internal, "wave: no {} to select", what);
  std::array<double, 2> lo{HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL};
  for (const auto& p : pts)
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], p[a] - tol), hi[a] = std::max(hi[a], p[a] + tol);
  for (const auto& p : others)
    STRATA_CHECK(p[0] < lo[0] || p[0] > hi[0] || p[1] < lo[1] || p[1] > hi[1], Internal,
                 "wave: the box around the {} also holds the point ({}, {})", what, p[0], p[1]);
  return {lo, hi};
}

// A [[group]] selecting the box `b` (from `region`; empty: every region and FEM node).
std::string group_text(const std::string& name, const std::string& region,
                       const std::pair<std::array<double, 2>, std::array<double, 2>>& b) {
  return fmt::format(
      "[[group]]\nname = \"{}\"\nregion = \"{}\"\nselect = \"box\"\nbox_min = [{:.17g}, {:.17g}]\n"
      "box_max = [{:.17g}, {:.17g}]\n\n",
      name, region, b.first[0], b.first[1], b.second[0], b.second[1]);
}

// What one run of the sweep is: the pulse (none: a model for its stability numbers only), η,
// the coupling, the FEM integrator, the DEM steps and the frames of its series.
struct WavePoint {
  const PulsePlan* pulse = nullptr;
  int eta = 1;
  couple::Execution mode = couple::Execution::Serial;
  std::string scheme = "central-difference";
  std::int64_t dem_steps = 0;
  int frames = 0;
};

// The coupled model of one run as a scene: the lattice (the bonds of Liu, Pollard & Shi 2013,
// unbreakable, no contact search, no damping) and the FEM block(s) from the geometry file,
// rollers on the lateral sides of both (every FEM node on them, the end particles of every
// lattice column), and the sin² traction pulse on the FEM's far side (a smooth ramp through
// 0, σ0, 0 spread over that side, per = "boundary"). η·dt_DEM above the particles' step is
// allowed: measuring where the exchange grows unstable is the point of the sweep.
scene::Scene wave_scene(const WaveModel& m, const WaveOptions& opt, const WavePoint& w) {
  const auto& ov = m.overlap;
  const int ax = ov.axis, lat = 1 - ax;
  const double tol = 1e-6 * m.d;
  // FEM nodes: the roller lines (lateral extremes) and the loaded side
  std::vector<std::array<double, 3>> nodes;
  for (std::size_t n = 0; n < ov.fem.node_count(); ++n) nodes.push_back(ov.fem.node(n));
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const auto& x : nodes) lo = std::min(lo, x[lat]), hi = std::max(hi, x[lat]);
  std::vector<std::array<double, 3>> low, high, loaded, rest_low, rest_high, rest_loaded;
  for (const auto& x : nodes) {
    (x[lat] < lo + tol ? low : rest_low).push_back(x);
    (x[lat] > hi - tol ? high : rest_high).push_back(x);
    (ov.depth(x) > m.load_depth - tol ? loaded : rest_loaded).push_back(x);
  }
  // Particles: the lowest and highest of every lattice column
  std::map<long, std::pair<std::uint32_t, std::uint32_t>> ends;  // column -> (lowest, highest)
  for (std::uint32_t i = 0; i < ov.particles.size(); ++i) {
    const long col = std::lround(ov.depth(ov.particles.x[i]) / ov.layer_spacing);
    auto [it, fresh] = ends.try_emplace(col, i, i);
    if (fresh) continue;
    if (ov.particles.x[i][lat] < ov.particles.x[it->second.first][lat]) it->second.first = i;
    if (ov.particles.x[i][lat] > ov.particles.x[it->second.second][lat]) it->second.second = i;
  }
  std::vector<char> role(ov.particles.size(), 0);  // 1 lowest, 2 highest of its column
  for (const auto& [col, e] : ends) role[e.first] |= 1, role[e.second] |= 2;
  std::vector<std::array<double, 3>> p_low, p_high, p_rest_low, p_rest_high;
  for (std::uint32_t i = 0; i < ov.particles.size(); ++i) {
    if (ov.particle_tag[i] == preprocess::OverlapTag::External) continue;  // driven by the FEM
    (role[i] & 1 ? p_low : p_rest_low).push_back(ov.particles.x[i]);
    (role[i] & 2 ? p_high : p_rest_high).push_back(ov.particles.x[i]);
  }
  const std::string lat_axis = lat == 0 ? "x" : "y";
  const std::string geo = fs::absolute(m.geometry).string();
  std::string t = fmt::format(
      "[scene]\ntitle = \"coupled wave\"\ndimension = 2\nthickness = 1.0\n\n"
      "[[material]]\nname = \"lattice\"\ndensity = {:.17g}\nkn = {:.17g}\nks = {:.17g}\n\n"
      "[[region]]\nname = \"particles\"\nkind = \"particles\"\nmaterial = \"lattice\"\nshape = \"file\"\n"
      "file = \"{}\"\nphysical = \"{}\"\ndiameter = {:.17g}\n\n",
      m.rho, m.kn, m.ks, geo, opt.particle_region, m.d);
  std::vector<std::string> fem_regions{opt.fem_region};
  if (m.embedded) fem_regions.push_back(opt.exit_region.empty() ? "fem_exit" : opt.exit_region);
  for (std::size_t k = 0; k < fem_regions.size(); ++k)
    t += fmt::format(
        "[[region]]\nname = \"fem{}\"\nkind = \"fem\"\nmaterial = \"lattice\"\nshape = \"file\"\nfile = "
        "\"{}\"\n"
        "physical = \"{}\"\nmesh_size = {:.17g}\n\n",
        k, geo, fem_regions[k], opt.fem_far_size * m.d);
  t += group_text("fem_low", "", box_around(low, rest_low, tol, "lower FEM side"));
  t += group_text("fem_high", "", box_around(high, rest_high, tol, "upper FEM side"));
  t += group_text("ends_low", "particles", box_around(p_low, p_rest_low, tol, "lower column ends"));
  t += group_text("ends_high", "particles", box_around(p_high, p_rest_high, tol, "upper column ends"));
  for (const char* g : {"fem_low", "fem_high", "ends_low", "ends_high"})
    t += fmt::format("[[boundary]]\ngroup = \"{}\"\ntype = \"fixed\"\naxes = [\"{}\"]\n\n", g, lat_axis);
  if (w.pulse) {
    t += group_text("loaded", "fem0", box_around(loaded, rest_loaded, tol, "loaded FEM side"));
    std::array<double, 2> peak{0, 0};
    peak[std::size_t(ax)] = -ov.fem_side * w.pulse->sigma0;  // into the particles
    t += fmt::format(
        "[[load]]\ngroup = \"loaded\"\ntimes = [0.0, {:.17g}, {:.17g}]\n"
        "forces = [[0.0, 0.0], [{:.17g}, {:.17g}], [0.0, 0.0]]\nper = \"boundary\"\nramp = \"smooth\"\n\n",
        w.pulse->T / 2, w.pulse->T, peak[0], peak[1]);
  }
  t += fmt::format(
      "[solver]\ndt = {:.17g}\nsteps = {}\neta = {}\ncoupling = \"{}\"\nfem_integrator = \"{}\"\n"
      "damping = \"none\"\ncontact_detection = \"off\"\nallow_unstable = true\nthreads = {}\n\n"
      "[output]\nframes = {}\nrender = false\nprobe_every = {}\n",
      m.dt_dem, std::max<std::int64_t>(w.dem_steps, w.eta), w.eta, couple::to_string(w.mode), w.scheme,
      opt.threads, w.frames, std::max<std::int64_t>(w.dem_steps, w.eta));
  return scene::parse(t, (fs::absolute(m.geometry).parent_path() / "wave.generated.toml").string(), {});
}

// The part of a frame pair within [lo, hi] along `axis` (particles by centre, triangles with
// all three nodes inside), for a picture of the overlap.
struct FramePair {
  io::PointCloud particles;
  io::MeshFrame mesh;
};
FramePair crop(const FramePair& in, int axis, double lo, double hi) {
  FramePair out;
  const io::PointCloud& p = in.particles;
  out.particles.dim = p.dim;
  out.particles.time = p.time;
  out.particles.step = p.step;
  for (const auto& a : p.point_data) out.particles.point_data.push_back({a.name, a.components, {}, a.type});
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x = p.xyz[3 * i + std::size_t(axis)];
    if (x < lo || x > hi) continue;
    out.particles.xyz.insert(out.particles.xyz.end(), &p.xyz[3 * i], &p.xyz[3 * i] + 3);
    for (std::size_t k = 0; k < p.point_data.size(); ++k) {
      const auto& a = p.point_data[k];
      const auto c = std::size_t(a.components);
      out.particles.point_data[k].values.insert(out.particles.point_data[k].values.end(),
                                                a.values.begin() + std::ptrdiff_t(i * c),
                                                a.values.begin() + std::ptrdiff_t((i + 1) * c));
    }
  }
  const io::MeshFrame& m = in.mesh;
  io::MeshFrame& o = out.mesh;
  o.dim = m.dim;
  o.time = m.time;
  o.step = m.step;
  std::vector<std::int64_t> new_index(m.nodes(), -1);
  auto inside = [&](std::int64_t n) {
    const double x = m.xyz[3 * std::size_t(n) + std::size_t(axis)];
    return x >= lo && x <= hi;
  };
  for (const auto& a : m.point_data) o.point_data.push_back({a.name, a.components, {}, a.type});
  std::size_t first = 0;
  for (std::size_t c = 0; c < m.cells(); ++c) {
    const int npc = io::nodes_per_cell(m.cell_types[c]);
    bool keep = true;
    for (int k = 0; k < npc; ++k) keep = keep && inside(m.connectivity[first + std::size_t(k)]);
    if (keep) {
      o.cell_types.push_back(m.cell_types[c]);
      for (int k = 0; k < npc; ++k) {
        const auto n = std::size_t(m.connectivity[first + std::size_t(k)]);
        if (new_index[n] < 0) {
          new_index[n] = std::int64_t(o.nodes());
          o.xyz.insert(o.xyz.end(), &m.xyz[3 * n], &m.xyz[3 * n] + 3);
          for (std::size_t j = 0; j < m.point_data.size(); ++j) {
            const auto& a = m.point_data[j];
            const auto cc = std::size_t(a.components);
            o.point_data[j].values.insert(o.point_data[j].values.end(),
                                          a.values.begin() + std::ptrdiff_t(n * cc),
                                          a.values.begin() + std::ptrdiff_t((n + 1) * cc));
          }
        }
        o.connectivity.push_back(new_index[n]);
      }
    }
    first += std::size_t(npc);
  }
  return out;
}

// Pictures of the pulse crossing the overlap, drawn while the run goes: its centre
// (c·(t − T/2) from the loaded side) 30 d before, on and 30 d past the interface (embedded:
// on the first interface, in the middle of the strip, on the second interface, 20 d past
// it), cropped around the overlap(s), FEM mesh and particles coloured by the velocity along
// the wave on one scale. Drawn after the FEM step of that time (serial coupling: the
// particles are then one system step behind).
void watch_crossing(const WaveModel& m, const PulsePlan& p, const WaveRun& r, scene::BuiltModel& model,
                    std::int64_t steps, WaveSeries& ws) {
  const auto& ov = m.overlap;
  const double D = m.dem_length;
  const std::vector<double> centres = m.embedded ? std::vector<double>{0, D / 2, D, D + 20 * m.d}
                                                 : std::vector<double>{-30 * m.d, 0, 30 * m.d};
  auto at = std::make_shared<std::vector<std::int64_t>>();  // FEM steps, ascending
  for (double c : centres) {
    const double t = (m.load_depth + c) / m.c + p.T / 2;
    at->push_back(std::clamp<std::int64_t>(std::llround(t / r.dt_fem), 0, steps));
  }
  std::sort(at->begin(), at->end());
  at->erase(std::unique(at->begin(), at->end()), at->end());
  // picture window along the propagation axis: 60 d (embedded: 40 d) each side of the overlap(s)
  double lo = ov.interface, hi = ov.interface;
  for (const auto& g : ov.interfaces) lo = std::min(lo, g.coordinate), hi = std::max(hi, g.coordinate);
  const double margin = (m.embedded ? 40 : 60) * m.d;
  lo -= margin, hi += margin;
  double a = HUGE_VAL, b = -HUGE_VAL;  // lateral extent
  for (std::size_t n = 0; n < ov.fem.node_count(); ++n)
    a = std::min(a, ov.fem.node(n)[1 - ov.axis]), b = std::max(b, ov.fem.node(n)[1 - ov.axis]);
  io::RenderStyle style;
  style.field = "velocity";
  style.component = ov.axis;
  style.field_scale = -ov.fem_side;  // along the propagation direction
  style.field_label = "velocity along the wave";
  style.unit = "m/s";
  style.colormap = io::Colormap::CoolWarm;
  style.range = std::array<double, 2>{-r.v0, r.v0};
  style.width = 1800;
  style.height = std::clamp(int(std::lround(1800 * (b - a) / (hi - lo))) + 300, 500, 1400);
  style.title = fmt::format(
      "coupled FEM-DEM wave{}: lambda = {:g} d, eta = {}; FEM mesh and particles, one "
      "colour scale",
      m.embedded ? " (FEM | DEM | FEM)" : "", r.lambda_d, r.eta);
  auto step = std::make_shared<std::int64_t>(1);  // the model is initialised: the next call is step 1
  model.coupler().observe_fem(
      [at, step, style, lo, hi, axis = ov.axis, &model, &ws](const couple::Partition& f) {
        const std::int64_t now = (*step)++;
        if (!ws.pictures || !std::binary_search(at->begin(), at->end(), now)) return;
        FramePair fp;
        fp.particles = particle_frame(model.sim(), {"id", "displacement", "velocity"});
        fp.particles.time = f.time();
        fp.mesh = fem_frame(model.fem().mesh(), model.fem().u(), model.fem().v(), f.time(), now);
        const FramePair c = crop(fp, axis, lo, hi);
        io::RenderRequest rq;
        rq.particles = &c.particles;
        rq.mesh = &c.mesh;
        rq.style = style;
        rq.png = ws.dir / "png" / fmt::format("crossing_{}.png", ws.pngs.size());
        try {
          io::render_frame(rq);
          ws.pngs.push_back(rq.png);
        } catch (const Error& e) {
          if (e.kind() != ErrorKind::Unsupported) throw;
          log::warn("no pictures: {}", e.what());
          ws.pictures = false;
        }
      });
}
}  // namespace

WaveModel build_wave_model(const WaveOptions& opt) {
  STRATA_CHECK(opt.d > 0, Input, "wave: particle diameter {} must be > 0 (m)", opt.d);
  STRATA_CHECK(opt.dt_fraction > 0 && opt.dt_fraction <= 1, Input,
               "wave: dt fraction {} must be in (0, 1] (of the lattice's critical step)", opt.dt_fraction);
  WaveModel m;
  m.geometry = !opt.geometry.empty() ? opt.geometry
                                     : fs::path(STRATA_SOURCE_DIR) /
                                           (opt.embedded ? "examples/04_coupled_wave/wave_embedded.geo"
                                                         : "examples/04_coupled_wave/wave.geo");
  std::vector<std::string> fem_regions{opt.fem_region};
  if (!opt.exit_region.empty())
    fem_regions.push_back(opt.exit_region);
  else if (opt.embedded)
    fem_regions.push_back("fem_exit");
  preprocess::OverlapOptions oo;
  oo.kind = preprocess::LatticeKind::Hex2D;
  oo.d = opt.d;
  oo.far_size = opt.fem_far_size * opt.d;
  oo.growth = opt.fem_growth;
  const auto t0 = WallClock::now();
  m.overlap = preprocess::build_overlap(m.geometry, opt.particle_region, fem_regions, oo);
  m.build_s = seconds_since(t0);
  STRATA_CHECK(m.overlap.dim == 2, Input, "wave: the geometry must be 2D");
  m.d = opt.d;
  m.kn = kKn;
  m.ks = kKs;
  m.rho = kRho;
  // Hexagonal lattice constants (Liu, Pollard & Shi 2013), plane stress per unit thickness
  const dem::LatticeElastic el = dem::hex_elastic(m.kn, m.ks);
  m.E = el.E;
  m.nu = el.nu;
  m.c = std::sqrt(m.E / ((1 - m.nu * m.nu) * m.rho));
  const double mass = dem::lattice_particle_mass(2, m.rho, m.d);
  m.dem_dt_crit = 2 / std::sqrt(dem::hex_lattice_lambda_max(m.kn, m.ks, mass));
  m.dt_dem = opt.dt_fraction * m.dem_dt_crit;

  const auto& ov = m.overlap;
  m.particles = ov.particles.size();
  m.fem_nodes = ov.fem.node_count();
  m.fem_elements = ov.fem.cell_count();
  for (std::size_t n = 0; n < ov.fem.node_count(); ++n)
    m.load_depth = std::max(m.load_depth, ov.depth(ov.fem.node(n)));
  m.embedded = ov.interfaces.size() == 2;
  if (m.embedded) {
    // the strip between the two interfaces; the exit block beyond the second
    const preprocess::OverlapInterface& g2 = ov.interfaces[1];
    m.dem_length = std::abs(g2.coordinate - ov.interface);
    for (std::size_t n = 0; n < ov.fem.node_count(); ++n)
      m.exit_length = std::max(m.exit_length, g2.depth(ov.fem.node(n)));
    m.exit_gauge_depth = m.exit_length / 3;
  } else {
    double dmin = 0;
    for (const auto& p : ov.particles.x) dmin = std::min(dmin, ov.depth(p));
    m.dem_length = -dmin + ov.particles.radius;
  }
  m.fem_gauge_depth = m.load_depth / 2;
  // DEM gauge: the lattice column nearest a third of the particle block
  double best = std::numeric_limits<double>::infinity();
  for (const auto& p : ov.particles.x)
    if (std::abs(-ov.depth(p) - m.dem_length / 3) < std::abs(best - m.dem_length / 3)) best = -ov.depth(p);
  m.dem_gauge_depth = best;

  // FEM explicit limit, rollers fixed and the overlap's external nodes held: the model's own
  m.fem_explicit_dt =
      scene::build_model(wave_scene(m, opt, WavePoint{}), /*force=*/true).fem_explicit_dt_crit;
  return m;
}

WaveRun run_wave(const WaveModel& m, const WaveOptions& opt, double lambda_d, int eta, couple::Execution mode,
                 const std::string& scheme, WaveSeries* series) {
  STRATA_CHECK(eta >= 1, Input, "wave: eta = {} must be an integer >= 1", eta);
  const PulsePlan p = plan_of(m, opt, lambda_d);
  const auto& ov = m.overlap;
  const int ax = ov.axis;
  const double dir = -ov.fem_side;  // propagation direction along `ax`: from the FEM into the particles

  WaveRun r;
  r.lambda_d = lambda_d;
  r.eta = eta;
  r.mode = mode;
  r.fem_scheme = scheme_name(m, eta, scheme);
  r.dt_dem = m.dt_dem;
  r.dt_fem = eta * m.dt_dem;
  r.v0 = opt.peak_velocity;
  r.pulse_T = p.T;
  r.t_inc = p.t_inc;
  r.t_ref = p.t_ref;
  r.t_tra = p.t_tra;
  r.t_ref2 = p.t_ref2;
  r.t_exit = p.t_exit;
  std::int64_t steps = static_cast<std::int64_t>(std::ceil(p.t_end / r.dt_fem));
  // the series: `frames` frames at evenly spaced system steps, t = 0 and the end included
  const int gaps = series ? std::max(1, series->frames - 1) : 1;
  steps = (steps + gaps - 1) / gaps * gaps;
  r.duration = static_cast<double>(steps) * r.dt_fem;

  // threads of the loops inside the partitions, for this run only
  struct ScopedThreads {
    int before = par::threads();
    explicit ScopedThreads(int n) { par::set_threads(n); }
    ~ScopedThreads() { par::set_threads(before); }
  } scoped_threads(opt.threads);
  const auto t0 = WallClock::now();
  // ---- the model, built and stepped through the scene library's one run path ----
  WavePoint w;
  w.pulse = &p;
  w.eta = eta;
  w.mode = mode;
  w.scheme = r.fem_scheme;
  w.dem_steps = steps * eta;
  w.frames = series && series->frames > 0 ? gaps : 0;
  const scene::Scene sc = wave_scene(m, opt, w);
  // the run's own files: the series folder, or a scratch folder removed afterwards
  struct Scratch {
    fs::path dir;
    bool keep = false;
    ~Scratch() {
      std::error_code ec;
      if (!keep) fs::remove_all(dir, ec);
    }
  } out;
  static std::atomic<int> counter{0};
  out.keep = series != nullptr;
  out.dir = series ? series->dir
                   : fs::temp_directory_path() / fmt::format("strata_wave_{}_{}", ::getpid(), counter++);
  std::optional<scene::Run> run;
  try {
    run.emplace(sc, scene::RunOptions{out.dir, /*force=*/true, {}});
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Input) throw;
    r.status = std::string("refused: ") + e.what();
    return r;
  }
  scene::BuiltModel& model = run->model();
  const couple::Partition& fem = *model.fem_partition_;
  const couple::Partition& dem = *model.dem_partition_;
  // An explicit FEM above its limit is refused as the coupler would refuse it (the scene
  // allows it only so that an unstable exchange can be measured): the coupler's own check,
  // made when the model was built.
  const couple::CoupledStability& cs = model.coupler().stability();
  if (!cs.problems.empty()) {
    r.status = fmt::format("refused: {}", fmt::join(cs.problems, "; "));
    return r;
  }

  // ---- gauges: read after every step of their partition ----
  // FEM gauge bands: nodes within half an element of the gauge line (at `depth` from the
  // interface `gi`, into its FEM block), weighted by their lumped mass
  const fem::Solver& solver = model.fem();
  const fem::Mesh& mesh = solver.mesh();
  const fem::Assembled& sys = solver.system();
  auto gauge_band = [&](const preprocess::OverlapInterface& gi, double depth, std::vector<std::size_t>& band,
                        std::vector<double>& band_m) {
    const double h = std::min(opt.fem_far_size * m.d, m.d + opt.fem_growth * depth);
    for (double wb = 0.5 * h; band.size() < 2; wb *= 1.5) {
      band.clear();
      band_m.clear();
      for (std::size_t n = 0; n < mesh.nodes(); ++n)
        if (std::abs(gi.depth({mesh.x[0][n], mesh.x[1][n], 0.0}) - depth) <= wb) {
          band.push_back(2 * n + std::size_t(ax));
          band_m.push_back(sys.mass[static_cast<Eigen::Index>(2 * n + std::size_t(ax))]);
        }
    }
  };
  std::vector<std::size_t> band, exit_band;
  std::vector<double> band_m, exit_m;
  gauge_band(ov.interfaces[0], m.fem_gauge_depth, band, band_m);
  if (m.embedded) gauge_band(ov.interfaces[1], m.exit_gauge_depth, exit_band, exit_m);
  auto band_velocity = [dir](const couple::Partition& f, const std::vector<std::size_t>& dofs,
                             const std::vector<double>& mass) {
    double s = 0, msum = 0;
    for (std::size_t k = 0; k < dofs.size(); ++k) s += mass[k] * f.velocity(dofs[k]), msum += mass[k];
    return dir * s / msum;
  };
  auto fem_gauges = [&](const couple::Partition& f) {
    r.t_fem.push_back(f.time());
    r.v_fem.push_back(band_velocity(f, band, band_m));
    if (m.embedded) r.v_exit.push_back(band_velocity(f, exit_band, exit_m));
  };
  // DEM gauge: the lattice column at dem_gauge_depth (DOF = particle id·2 + axis)
  std::vector<std::size_t> column;
  {
    const dem::Simulation& sim = model.sim();
    const auto x = sim.positions();
    const auto ids = sim.ids();
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (std::abs(-ov.depth(x[i]) - m.dem_gauge_depth) < 1e-6 * m.d)
        column.push_back(2 * ids[i] + std::size_t(ax));
    std::sort(column.begin(), column.end());
  }
  auto dem_gauge = [&](const couple::Partition& d) {
    double s = 0;
    for (std::size_t k : column) s += d.velocity(k);
    r.t_dem.push_back(d.time() - 0.5 * d.dt());  // leapfrog: the velocity of the last half step
    r.v_dem.push_back(dir * s / static_cast<double>(column.size()));
  };
  fem_gauges(fem);  // t = 0 (the model is initialised)
  dem_gauge(dem);
  model.coupler().observe_fem(fem_gauges);
  model.coupler().observe_dem(dem_gauge);
  if (series && series->pictures) watch_crossing(m, p, r, model, steps, *series);
  r.setup_s = seconds_since(t0);
  r.fem_steps = steps;
  r.dem_steps = steps * eta;
  try {
    scene::RunObserver quiet;
    const scene::RunResult res = run->execute(quiet);
    r.wall_s = r.setup_s + res.step_seconds;
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Numerical) throw;
    r.status = std::string("blew up: ") + e.what();
    return r;
  }
  r.dem_hash = model.sim().state_hash();
  r.fem_u.assign(solver.u().data(), solver.u().data() + solver.u().size());

  // ---- incident, reflected, transmitted ----
  const WindowMeasure inc = measure_arrival(r.t_fem, r.v_fem, p.t_inc, p.T);
  const WindowMeasure ref = measure_arrival(r.t_fem, r.v_fem, p.t_ref, p.T);
  const WindowMeasure tra = measure_arrival(r.t_dem, r.v_dem, p.t_tra, p.T);
  // what the FEM gauge sees between the incident and the reflected window (the incident
  // pulse's own dispersive tail): a floor under which R says nothing about the interface
  const double fa = std::max(p.t_inc + kAfter * p.T, p.t_ref - (kBefore + 1.5) * p.T),
               fb = p.t_ref - kBefore * p.T;
  r.floor = fb > fa ? measure(r.t_fem, r.v_fem, fa, fb).peak / inc.peak : std::nan("");
  r.incident = inc.signed_peak;
  r.r_peak = ref.peak / inc.peak;
  r.r_energy = ref.energy / inc.energy;
  r.t_peak = tra.peak / inc.peak;
  r.t_energy = tra.energy / inc.energy;
  if (m.embedded) {
    const WindowMeasure ref2 = measure_arrival(r.t_fem, r.v_fem, p.t_ref2, p.T);
    const WindowMeasure ex = measure_arrival(r.t_fem, r.v_exit, p.t_exit, p.T);
    r.r2_peak = ref2.peak / inc.peak;
    r.r2_energy = ref2.energy / inc.energy;
    r.exit_peak = ex.peak / inc.peak;
    r.exit_energy = ex.energy / inc.energy;
  }
  // In a linear, matched set-up no gauge can see much more than the incident peak (at most
  // (1 + R)·v0 where pulses overlap). A gauge above 2·v0, or a non-finite value, means the
  // coupled exchange pumped energy in: the interface is unstable at this dt_FEM.
  double vmax = 0;
  for (double v : r.v_fem) vmax = std::isfinite(v) ? std::max(vmax, std::abs(v)) : HUGE_VAL;
  for (double v : r.v_dem) vmax = std::isfinite(v) ? std::max(vmax, std::abs(v)) : HUGE_VAL;
  for (double v : r.v_exit) vmax = std::isfinite(v) ? std::max(vmax, std::abs(v)) : HUGE_VAL;
  if (!(vmax <= 2 * r.v0))
    r.status = fmt::format(
        "unstable: a gauge reached {:.3g} m/s = {:.3g} x v0 (dt_FEM = {:.3g} x the DEM critical step)", vmax,
        vmax / r.v0, r.dt_fem / m.dem_dt_crit);
  return r;
}

WaveStability wave_stability(const WaveModel& m, const WaveOptions& opt) {
  WaveStability s;
  for (int eta : opt.etas) {
    // The model as run_wave builds it; each partition's limit is taken with the overlap's
    // external DOFs held.
    WavePoint w;
    w.eta = eta;
    w.scheme = scheme_name(m, eta, opt.fem_scheme);
    const scene::BuiltModel built = scene::build_model(wave_scene(m, opt, w), /*force=*/true);
    couple::CoupledStability cs = built.coupler().stability();  // checked when it was built
    if (cs.dt_dem > cs.dem_dt_crit) s.dem_problem = true;
    if (!cs.problems.empty()) {
      s.refused.push_back(eta);
      s.problems.push_back(fmt::format("eta = {}: {}", eta, fmt::join(cs.problems, "; ")));
    }
    s.per_eta.push_back(std::move(cs));
  }
  return s;
}

}  // namespace strata::cases
