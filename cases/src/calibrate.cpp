#include <strata/cases/calibrate.hpp>

#include <strata/core/error.hpp>
#include <strata/dem/lattice_elastic.hpp>
#include <strata/io/csv.hpp>
#include <strata/scene/files.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace strata::cases {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// A real as TOML reads it back to the same double (TOML floats need a '.' or an exponent).
std::string num(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::string s = fmt::format("{:.17g}", x);
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

std::string vec(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
  return s + "]";
}

const scene::CalibrateTable& table_of(const scene::Scene& sc) {
  STRATA_CHECK(sc.calibrate.has_value(), Input,
               "{}: not a calibration: `strata calibrate` needs a [calibrate] table (the targets E, ν, UCS "
               "and tensile strength, and the lattice); see docs/scene-reference.md",
               sc.file.string());
  return *sc.calibrate;
}

/// The expected peak strain of a specimen at the targets: UCS/E for the uniaxial one; the
/// disc's platens approach by several times σt/E at the peak (the elastic solution of a disc
/// under diametral loads gives 5-10 σt/E, more with local crushing).
double expected_peak_strain(const scene::CalibrateTable& c, const std::string& specimen) {
  return specimen == "uniaxial" ? c.ucs / c.youngs_modulus : 8 * c.tensile_strength / c.youngs_modulus;
}

/// Length of a specimen along its loading axis.
double loaded_length(const scene::CalibrateTable& c, const std::string& specimen) {
  return specimen == "uniaxial" ? 2 * specimen_width(c) : specimen_width(c);
}

double thickness_of(const scene::Scene& sc) {
  return sc.scene.dimension == 2 ? sc.scene.thickness.value : 1.0;
}

/// Kn, Ks that give the lattice (E, ν) by the analytical relations (see analytical_springs).
LatticeParameters springs_for(const scene::Scene& sc, double e, double nu) {
  const auto& c = *sc.calibrate;
  const dem::LatticeSprings k = sc.scene.dimension == 2
                                    ? dem::hex_springs(e * thickness_of(sc), nu)
                                    : dem::close_packed_stacking_axis_springs(e, nu, c.diameter);
  LatticeParameters p;
  p.kn = k.kn, p.ks = k.ks;
  return p;
}

/// Relative misfit of a measured value.
double misfit(double got, double want) { return std::abs(got - want) / std::abs(want); }

}  // namespace

double specimen_width(const scene::CalibrateTable& c) {
  return c.specimen_width > 0 ? c.specimen_width.value : 40 * c.diameter.value;
}

LatticeParameters analytical_springs(const scene::Scene& sc) {
  const auto& c = table_of(sc);
  return springs_for(sc, c.youngs_modulus, c.poisson_ratio);
}

std::string specimen_scene(const scene::Scene& sc, const std::string& specimen, const LatticeParameters& p,
                           double strain_rate, double strain, bool final_run) {
  const auto& c = table_of(sc);
  const int dim = sc.scene.dimension;
  const double w = specimen_width(c), d = c.diameter;
  const bool uniaxial = specimen == "uniaxial";
  const double length = loaded_length(c, specimen);
  // the loading axis: y in 2D and for the discs, z for the 3D cylinder (the stacking axis)
  const int axis = uniaxial && dim == 3 ? 2 : 1;
  const char* axis_name = axis == 2 ? "z" : "y";
  const double speed = 0.5 * strain_rate * length;  // each platen
  std::vector<double> down(std::size_t(dim), 0.0), up(std::size_t(dim), 0.0);
  down[std::size_t(axis)] = -speed, up[std::size_t(axis)] = speed;
  const double viscous_c =
      2 * c.damping_ratio * std::sqrt(p.kn * dem::lattice_particle_mass(dim, c.density, d));

  std::string s =
      fmt::format("# {} specimen of the calibration {} (written by strata calibrate).\n",
                  uniaxial ? "Uniaxial compression" : "Brazilian disc", sc.file.filename().string());
  if (!uniaxial)
    s +=
        "# The probe's stress is the load over D*t; the Brazilian tensile strength is 2/pi times its peak.\n";
  s += fmt::format("\n[scene]\ntitle = \"{} {}\"\ndimension = {}\n",
                   sc.scene.title.value.empty() ? "Calibration" : sc.scene.title.value,
                   uniaxial ? "- uniaxial compression" : "- Brazilian disc", dim);
  if (dim == 2) s += fmt::format("thickness = {}\n", num(sc.scene.thickness));
  s += fmt::format("seed = {}\n", sc.scene.seed.value);
  s += fmt::format(
      "\n[[material]]\nname = \"rock\"\ndensity = {}\nkn = {}\nks = {}\nfriction = {}\n"
      "tensile_strength = {}\nshear_strength = {}\nfriction_strengthens_bonds = {}\n",
      num(c.density), num(p.kn), num(p.ks), num(c.friction), num(p.fn_max), num(p.fs0),
      c.friction_strengthens_bonds.value ? "true" : "false");
  s +=
      fmt::format("\n[[region]]\nname = \"specimen\"\nmaterial = \"rock\"\nlattice = \"{}\"\ndiameter = {}\n",
                  c.lattice.value, num(d));
  if (uniaxial && dim == 2)
    s += fmt::format("shape = \"box\"\norigin = [0.0, 0.0]\nsize = {}\n", vec({w, 2 * w}));
  else if (uniaxial)
    s += fmt::format("shape = \"cylinder\"\ncenter = {}\nradius = {}\nheight = {}\n", vec({w / 2, w / 2, w}),
                     num(w / 2), num(2 * w));
  else if (dim == 2)
    s += fmt::format("shape = \"disk\"\ncenter = {}\nradius = {}\n", vec({w / 2, w / 2}), num(w / 2));
  else
    s += fmt::format("shape = \"cylinder\"\ncenter = {}\nradius = {}\nheight = {}\n",
                     vec({w / 2, w / 2, w / 4}), num(w / 2), num(w / 2));
  if (c.strength_spread != scene::StrengthSpread::None)
    s += fmt::format("strength_spread = \"{}\"\nstrength_cov = {}\n", scene::to_string(c.strength_spread),
                     num(c.strength_cov));
  if (uniaxial || dim == 2) {
    const std::string top = uniaxial && dim == 3 ? "top_layer" : "top_row";
    const std::string bottom = uniaxial && dim == 3 ? "bottom_layer" : "bottom_row";
    s += fmt::format(
        "\n[[group]]\nname = \"top\"\nselect = \"{}\"\n\n[[group]]\nname = \"bottom\"\nselect = \"{}\"\n",
        top, bottom);
  } else {
    // 3D disc: the line of particles along the thickness at the top and the bottom, centres
    // within 0.45 d of the highest (lowest) a centre can be, R - d/2 from the axis
    const double band = w - 0.95 * d;
    s += fmt::format("\n[[group]]\nname = \"top\"\nselect = \"box\"\nbox_min = {}\nbox_max = {}\n",
                     vec({-w, band, -w}), vec({2 * w, 2 * w, 2 * w}));
    s += fmt::format("\n[[group]]\nname = \"bottom\"\nselect = \"box\"\nbox_min = {}\nbox_max = {}\n",
                     vec({-w, -w, -w}), vec({2 * w, w - band, 2 * w}));
  }
  // Uniaxial: frictionless platens (only the loading axis held). The disc: the loading rows
  // held in every direction, as the jaws of the test hold the disc.
  const std::string axes = uniaxial ? fmt::format("[\"{}\"]", axis_name) : "";
  for (const auto& [group, v] : {std::pair{"top", down}, std::pair{"bottom", up}}) {
    s += fmt::format("\n[[boundary]]\ngroup = \"{}\"\ntype = \"velocity\"\n", group);
    if (!axes.empty()) s += fmt::format("axes = {}\n", axes);
    s += fmt::format("velocity = {}\n", vec(v));
  }
  s += fmt::format("\n[solver]\ndt_safety = 0.3\nduration = {}\ndamping = \"viscous\"\nviscous_c = {}\n",
                   num(strain / strain_rate), num(viscous_c));
  s += fmt::format(
      "\n[probe]\nstress_strain = true\ntop_group = \"top\"\nbottom_group = \"bottom\"\naxis = \"{}\"\n"
      "stop_after_peak = 0.6\n",
      axis_name);
  s += fmt::format("\n[output]\ndirectory = \"{}\"\n", specimen);
  if (final_run)
    // frames spread over the whole strain: a run that stops at 60 % of its peak writes a third of them
    s += fmt::format("frames = 30\nrender = {}\nrender_field = \"damage\"\n",
                     sc.output.render.value ? "true" : "false");
  else
    s += "frames = 0\nvtk = false\nrender = false\n";
  return s;
}

CalibrationResult calibrate(const scene::Scene& sc, const fs::path& output, CalibrateObserver& observer) {
  const auto& c = table_of(sc);
  const int dim = sc.scene.dimension;
  CalibrationResult res;
  const double tol = c.tolerance;
  const double nu_max = dim == 2 ? 1.0 / 3.0 : 0.2;
  const double ratio_target = c.ucs / c.tensile_strength;
  // wave speed of the target rock: c² = E·t/ρ in 2D (ρ per unit thickness), E/ρ in 3D
  const double wave = std::sqrt(c.youngs_modulus * thickness_of(sc) / c.density);
  auto strain_rate = [&](const std::string& specimen) {
    return expected_peak_strain(c, specimen) / (c.transits_to_peak * loaded_length(c, specimen) / wave);
  };

  int run_number = 0;
  // One specimen run: its scene, scene::Run, the numbers of its summary.
  auto run = [&](const std::string& stage, int iteration, const std::string& specimen,
                 const LatticeParameters& p, double strain, bool final_run) {
    CalibrationRun r;
    r.stage = stage, r.iteration = iteration, r.specimen = specimen, r.p = p;
    const double rate = strain_rate(specimen);
    const std::string label =
        final_run ? specimen : fmt::format("{:02d}_{}_{}", ++run_number, stage, specimen);
    const fs::path dir = final_run ? output / specimen : output / "runs" / label;
    // Up to twice: a specimen that has not failed by the end of its strain runs again to three times it.
    for (int attempt = 0; attempt < 2; ++attempt) {
      const std::string text = specimen_scene(sc, specimen, p, rate, strain, final_run);
      const fs::path file = final_run ? output / (specimen + ".toml") : dir / "scene.toml";
      const scene::Scene spec = scene::parse(text, file);
      observer.begin(label);
      scene::Run specimen_run(spec, {dir, false, {}});
      r.particles = specimen_run.model_summary().value("particles", std::size_t(0));
      const scene::RunResult rr = specimen_run.execute(observer);
      if (rr.status == scene::RunStatus::Interrupted)
        fail(ErrorKind::Input,
             "calibrate: {} interrupted by a stop request at step {}; the runs so far are in {}", label,
             rr.step, output.string());
      scene::write_file_atomic(file, text);
      const json& summary = rr.summary;
      r.steps = summary.value("steps_done", std::int64_t(0));
      r.seconds += rr.step_seconds;
      r.directory = dir;
      r.failed = summary.contains("stopped_after_peak_at_step");
      const double peak = summary.value("peak_stress_pa", 0.0);
      r.peak_strain = summary.value("peak_strain", 0.0);
      if (specimen == "uniaxial" && summary.contains("measured_elastic")) {
        const json& e = summary["measured_elastic"];
        r.youngs_modulus = e.value("youngs_modulus_pa", 0.0);
        r.poisson_ratio = e.value("poisson_ratio", 0.0);
      }
      if (stage != "elastic") r.strength = specimen == "uniaxial" ? peak : 2 / std::numbers::pi * peak;
      if (stage == "elastic" || r.failed) break;
      strain *= 3;
    }
    STRATA_CHECK(
        stage == "elastic" || r.failed, Numerical,
        "calibrate: the {} specimen ({}) did not fail up to strain {:.3g}; its bonds may be too strong "
        "for the loading to break them: see {}",
        specimen, label, strain, (r.directory / "probes.csv").string());
    STRATA_CHECK(r.youngs_modulus > 0 || stage != "elastic", Numerical,
                 "calibrate: the uniaxial specimen ({}) gave no elastic window to measure E in: see {}",
                 label, (r.directory / "probes.csv").string());
    observer.end(r);
    res.runs.push_back(r);
    return r;
  };

  // 1. Elastic: the analytical inversion, corrected by the measured misfit.
  double e_a = c.youngs_modulus, nu_a = c.poisson_ratio;
  LatticeParameters p = analytical_springs(sc);
  res.analytical = p;
  p.fn_max = p.fs0 = INFINITY;
  const double elastic_strain = 0.5 * expected_peak_strain(c, "uniaxial");
  for (int it = 1; it <= 4; ++it) {
    const CalibrationRun r = run("elastic", it, "uniaxial", p, elastic_strain, false);
    // within a quarter of the tolerance: the elastic runs are cheap, the strengths use the rest
    const bool e_ok = misfit(r.youngs_modulus, c.youngs_modulus) <= tol / 4;
    const bool nu_ok = std::abs(r.poisson_ratio - c.poisson_ratio) <=
                       tol / 4 * std::max(std::abs(c.poisson_ratio.value), 0.1);
    if ((e_ok && nu_ok) || it == 4) break;
    e_a *= c.youngs_modulus / r.youngs_modulus;
    nu_a = std::clamp(nu_a + (c.poisson_ratio - r.poisson_ratio), -0.9, nu_max);
    const LatticeParameters k = springs_for(sc, e_a, nu_a);
    p.kn = k.kn, p.ks = k.ks;
  }

  // 2. Strength: the ratio q = Fs0/Fn_max sets UCS/BTS; Fn_max scales both.
  // A first guess of Fn_max: the Brazilian disc of a regular lattice splits at about
  // 3 Fn_max over a particle's cross-section d·t (2D) or d² (3D).
  struct Point {
    double q, fn, ucs, bts;
    double ratio() const { return ucs / bts; }
  };
  std::vector<Point> points;
  const double q_lo = 1.0 / 16, q_hi = 64;
  double q = 2;
  double fn = c.tensile_strength * c.diameter * (dim == 2 ? thickness_of(sc) : c.diameter.value) / 3;
  auto pair_at = [&](const std::string& stage, int it, double q_at, double fn_at) {
    LatticeParameters s = p;
    s.fn_max = fn_at, s.fs0 = q_at * fn_at;
    const double u_strain = 3 * std::max(expected_peak_strain(c, "uniaxial"),
                                         points.empty() ? 0.0 : points.back().ucs / c.youngs_modulus);
    const CalibrationRun u = run(stage, it, "uniaxial", s, u_strain, stage == "final");
    const CalibrationRun b =
        run(stage, it, "brazilian", s, 4 * expected_peak_strain(c, "brazilian"), stage == "final");
    return std::pair{u, b};
  };
  for (int it = 1; it <= c.iterations; ++it) {
    const auto [u, b] = pair_at("strength", it, q, fn);
    points.push_back({q, fn, u.strength, b.strength});
    const Point& pt = points.back();
    fn *= c.tensile_strength / pt.bts;  // the next pair near the target strengths
    if (misfit(pt.ratio(), ratio_target) <= tol) break;
    // next q: secant on (log q, log ratio) through the two nearest points that bracket the
    // target, or through the last two; bisection when the secant leaves the bracket
    const Point* below = nullptr;
    const Point* above = nullptr;
    for (const Point& x : points) {
      if (x.ratio() < ratio_target && (!below || x.q > below->q)) below = &x;
      if (x.ratio() >= ratio_target && (!above || x.q < above->q)) above = &x;
    }
    double next;
    const Point& last = points.back();
    const Point& top = *std::max_element(
        points.begin(), points.end(), [](const Point& a, const Point& b) { return a.ratio() < b.ratio(); });
    if (!(below && above) && ratio_target > top.ratio() && &top != &last && points.size() >= 2) {
      // Past a maximum of the ratio below the target: close in on the maximum, between the
      // best q and its nearest neighbour tried on the side of the last one.
      const Point* side = &last;
      for (const Point& x : points)
        if (&x != &top && (x.q > top.q) == (last.q > top.q) &&
            std::abs(std::log(x.q / top.q)) < std::abs(std::log(side->q / top.q)))
          side = &x;
      if (std::abs(std::log(side->q / top.q)) < 0.1) break;  // the maximum is found: out of reach
      next = std::sqrt(top.q * side->q);
    } else if (points.size() >= 2) {
      const Point& a = below && above ? *below : points[points.size() - 2];
      const Point& z = below && above ? *above : last;
      const double slope = (std::log(z.ratio()) - std::log(a.ratio())) / (std::log(z.q) - std::log(a.q));
      next = slope > 0.02 ? std::exp(std::log(a.q) + (std::log(ratio_target) - std::log(a.ratio())) / slope)
                          : last.q * (last.ratio() < ratio_target ? 4.0 : 0.25);
      if (below && above && !(next > std::min(below->q, above->q) && next < std::max(below->q, above->q)))
        next = std::sqrt(below->q * above->q);
    } else {
      next = last.q * std::pow(ratio_target / last.ratio(), 1.5);
    }
    next = std::clamp(next, std::max(q_lo, last.q / 2), std::min(q_hi, last.q * 2));
    const bool seen = std::any_of(points.begin(), points.end(),
                                  [&](const Point& x) { return std::abs(std::log(x.q / next)) < 1e-3; });
    if (seen) break;  // at a bound already tried: the target ratio is out of reach
    // Fn_max for the next q: the tensile strength per unit Fn_max also grows with q (shear
    // takes part in the disc's failure); follow its trend on log q through the last two points
    if (points.size() >= 2) {
      const Point& a = points[points.size() - 2];
      if (std::abs(std::log(last.q / a.q)) > 1e-3) {
        const double trend = std::clamp(
            (std::log(last.bts / last.fn) - std::log(a.bts / a.fn)) / (std::log(last.q) - std::log(a.q)), 0.0,
            1.5);
        fn *= std::pow(last.q / next, trend);
      }
    }
    q = next;
  }
  // the point nearest the target ratio; strengths scaled to meet one target
  // (when several come within the tolerance of the nearest ratio, as where the ratio hardly
  // depends on q, the one nearest the starting q = 2, so that neither strength is extreme)
  auto distance = [&](const Point& a) { return std::abs(std::log(a.ratio() / ratio_target)); };
  const double nearest =
      distance(*std::min_element(points.begin(), points.end(),
                                 [&](const Point& a, const Point& b) { return distance(a) < distance(b); }));
  const bool above_all =
      std::all_of(points.begin(), points.end(), [&](const Point& x) { return x.ratio() < ratio_target; });
  const bool below_all =
      std::all_of(points.begin(), points.end(), [&](const Point& x) { return x.ratio() > ratio_target; });
  const Point best = *std::min_element(points.begin(), points.end(), [&](const Point& a, const Point& b) {
    if (!above_all && !below_all) return distance(a) < distance(b);
    const bool a_near = distance(a) <= nearest + tol, b_near = distance(b) <= nearest + tol;
    if (a_near != b_near) return a_near;
    return std::abs(std::log(a.q / 2)) < std::abs(std::log(b.q / 2));
  });
  res.ratio_reached = misfit(best.ratio(), ratio_target) <= tol;
  const bool by_ucs = !res.ratio_reached && c.match.value == "ucs";
  const double scale = by_ucs ? c.ucs / best.ucs : c.tensile_strength / best.bts;

  // 3. The final pair. E and ν are those of the last elastic run, whose bonds are the final
  // ones but unbreakable: with weak tensile bonds (a high UCS/tensile strength) a few bonds at
  // the free sides of the uniaxial specimen break early (the surface particles are pushed out
  // by their diagonal neighbours), which leaves no elastic window in the final run itself.
  const auto [u, b] = pair_at("final", 1, best.q, best.fn * scale);
  res.p = u.p;
  for (const auto& r : res.runs)
    if (r.stage == "elastic") res.youngs_modulus = r.youngs_modulus, res.poisson_ratio = r.poisson_ratio;
  res.ucs = u.strength;
  res.peak_strain = u.peak_strain;
  res.tensile_strength = b.strength;
  res.best_ratio = u.strength / b.strength;

  // ---- the files ----
  const std::string lattice = c.lattice.value == "auto" ? (dim == 2 ? "hex" : "hcp") : c.lattice.value;
  auto row = [&](const std::string& what, double target, double got, double unit, const char* f) {
    return fmt::format("| {} | {} | {} | {:+.1f} % |\n", what, fmt::format(fmt::runtime(f), target / unit),
                       fmt::format(fmt::runtime(f), got / unit), 100 * (got - target) / target);
  };
  std::string md =
      fmt::format("# Calibration{}\n\n", sc.scene.title.value.empty() ? "" : ": " + sc.scene.title.value);
  md += fmt::format(
      "{}D {} lattice of particles of diameter {:g} mm; uniaxial specimen {:g} × {:g} mm{} ({} particles), "
      "Brazilian disc of diameter {:g} mm{} ({} particles).\n\n",
      dim, lattice, c.diameter * 1e3, specimen_width(c) * 1e3, 2 * specimen_width(c) * 1e3,
      dim == 3 ? " (a cylinder)" : "", u.particles, specimen_width(c) * 1e3,
      dim == 3 ? fmt::format(", {:g} mm thick", specimen_width(c) * 500) : "", b.particles);
  md += "| quantity | target | achieved | error |\n|---|---:|---:|---:|\n";
  md += row("Young's modulus E (GPa)", c.youngs_modulus, res.youngs_modulus, 1e9, "{:.2f}");
  md += row("Poisson's ratio ν", c.poisson_ratio, res.poisson_ratio, 1, "{:.3f}");
  md += row("UCS (MPa)", c.ucs, res.ucs, 1e6, "{:.1f}");
  md += row("tensile strength, Brazilian (MPa)", c.tensile_strength, res.tensile_strength, 1e6, "{:.2f}");
  md += row("UCS / tensile strength", ratio_target, res.best_ratio, 1, "{:.2f}");
  md += fmt::format("\nStrain at the UCS: {:.3g}.\n\n", res.peak_strain);
  if (!res.ratio_reached) {
    const std::string met = by_ucs ? "UCS" : "tensile strength";
    if (above_all || below_all) {
      double edge = above_all ? 0.0 : INFINITY, edge_q = 0;
      for (const Point& x : points)
        if (above_all ? x.ratio() > edge : x.ratio() < edge) edge = x.ratio(), edge_q = x.q;
      md += fmt::format(
          "The target ratio UCS/tensile strength = {:.2f} is out of this lattice's reach: the ratios "
          "Fs0/Fn_max "
          "tried (the search keeps them between {:g} and {:g}) gave at {} {:.2f} (at Fs0/Fn_max = {:.3g}).{} "
          "strata kept a ratio near the {} and scaled the bond strengths to meet the {}.\n\n",
          ratio_target, q_lo, q_hi, above_all ? "most" : "least", edge, edge_q,
          above_all
              ? " Bonded-particle models of equal particles are known to give too low a ratio (Potyondy & "
                "Cundall 2004)."
              : "",
          above_all ? "largest" : "smallest", met);
    } else {
      md += fmt::format(
          "The ratios UCS/tensile strength of the {} pairs tried lie on both sides of the target {:.2f} but "
          "none came within the tolerance: the ratio jumps with Fs0/Fn_max where the specimens' failure "
          "changes its pattern. strata kept the nearest ({:.2f}, at Fs0/Fn_max = {:.3g}) and scaled the bond "
          "strengths to meet the {}.\n\n",
          points.size(), ratio_target, best.ratio(), best.q, met);
    }
  }
  md += fmt::format(
      "The [[material]] this gives (the specimens are uniaxial.toml and brazilian.toml):\n\n"
      "```toml\n[[material]]\n"
      "name = \"rock\"\ndensity = {}\nkn = {:.6g}\nks = {:.6g}\nfriction = {}\ntensile_strength = {:.6g}\n"
      "shear_strength = {:.6g}\nfriction_strengthens_bonds = {}\n```\n\n",
      num(c.density), res.p.kn, res.p.ks, num(c.friction), res.p.fn_max, res.p.fs0,
      c.friction_strengthens_bonds.value ? "true" : "false");
  md += fmt::format(
      "The analytical relations alone (the infinite lattice) give Kn = {:.6g} N/m and Ks = {:.6g} N/m; the "
      "measured specimen needs Kn {:+.1f} % and Ks {:+.1f} %.\n\n",
      res.analytical.kn, res.analytical.ks, 100 * (res.p.kn / res.analytical.kn - 1),
      res.analytical.ks > 0 ? 100 * (res.p.ks / res.analytical.ks - 1) : 0.0);
  md +=
      "| run | specimen | Kn (N/m) | Ks (N/m) | Fn_max (N) | Fs0/Fn_max | E (GPa) | ν | strength (MPa) | "
      "steps "
      "| run time (s) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  double total = 0;
  for (const auto& r : res.runs) {
    total += r.seconds;
    const bool elastic = r.stage == "elastic";
    md += fmt::format("| {} {} | {} | {:.4g} | {:.4g} | {} | {} | {} | {} | {} | {} | {:.2f} |\n", r.stage,
                      r.iteration, r.specimen, r.p.kn, r.p.ks,
                      elastic ? "∞" : fmt::format("{:.4g}", r.p.fn_max),
                      elastic ? "—" : fmt::format("{:.3g}", r.p.fs0 / r.p.fn_max),
                      r.youngs_modulus > 0 ? fmt::format("{:.2f}", r.youngs_modulus / 1e9) : "—",
                      r.youngs_modulus > 0 ? fmt::format("{:.3f}", r.poisson_ratio) : "—",
                      elastic ? "—" : fmt::format("{:.2f}", r.strength / 1e6), r.steps, r.seconds);
  }
  md += fmt::format("\n{} specimen runs, {:.1f} s of stepping.\n", res.runs.size(), total);
  res.markdown = md;

  json j = {{"scene", sc.file.string()},
            {"dimension", dim},
            {"lattice", lattice},
            {"targets",
             {{"youngs_modulus_pa", c.youngs_modulus.value},
              {"poisson_ratio", c.poisson_ratio.value},
              {"ucs_pa", c.ucs.value},
              {"tensile_strength_pa", c.tensile_strength.value}}},
            {"achieved",
             {{"youngs_modulus_pa", res.youngs_modulus},
              {"poisson_ratio", res.poisson_ratio},
              {"ucs_pa", res.ucs},
              {"tensile_strength_pa", res.tensile_strength},
              {"ucs_over_tensile_strength", res.best_ratio},
              {"peak_strain", res.peak_strain}}},
            {"ratio_reached", res.ratio_reached},
            {"material",
             {{"kn", res.p.kn},
              {"ks", res.p.ks},
              {"tensile_strength", res.p.fn_max},
              {"shear_strength", res.p.fs0}}},
            {"analytical", {{"kn", res.analytical.kn}, {"ks", res.analytical.ks}}},
            {"runs", res.runs.size()},
            {"stepping_seconds", total}};
  scene::write_file_atomic(output / "calibration.json", j.dump(2) + "\n");
  scene::write_file_atomic(output / "calibration.md", md);
  {
    io::CsvWriter csv(output / "calibration.csv",
                      {"run", "final", "uniaxial", "kn", "ks", "fn_max", "fs0", "youngs_modulus",
                       "poisson_ratio", "strength", "peak_strain", "steps", "seconds"});
    int k = 0;
    for (const auto& r : res.runs)
      csv.row({double(++k), r.stage == "final" ? 1.0 : 0.0, r.specimen == "uniaxial" ? 1.0 : 0.0, r.p.kn,
               r.p.ks, r.p.fn_max, r.p.fs0, r.youngs_modulus, r.poisson_ratio, r.strength, r.peak_strain,
               double(r.steps), r.seconds});
    csv.close();
  }
  res.written = {output / "calibration.md", output / "calibration.json", output / "calibration.csv",
                 output / "uniaxial.toml",  output / "brazilian.toml",   output / "uniaxial",
                 output / "brazilian"};
  return res;
}

}  // namespace strata::cases
