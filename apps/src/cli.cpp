// The `strata` command line (CLI11): run, check, mesh, bench, render, report, compare, calibrate,
// reference.
//
// Exit status: 0 success, 1 the run failed, 2 bad usage or bad scene, 130/143 a run stopped by
// SIGINT/SIGTERM (with a checkpoint).
#include "cli.hpp"

#include <CLI/CLI.hpp>
#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>
#include <strata/preprocess/geometry.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string_view>

#include <strata/cases/chain_report.hpp>
#include <strata/cases/wave_report.hpp>
#include <strata/scene/files.hpp>
#include <strata/scene/scene.hpp>
#include "bench_dem.hpp"
#include "build_parts_cli.hpp"
#include "commands.hpp"
#include "compare_cmd.hpp"
#include "render_cmd.hpp"

namespace strata::app {
namespace {

std::string version_text() {
  std::string s = fmt::format("strata {}\noptional parts:", STRATA_VERSION);
  for (const auto& f : config::kFeatures) {
    s += fmt::format("\n  {:<20} {:<3} {}", f.option, f.enabled ? "on" : "off", f.what);
    // the gmsh library's own version: which .geo syntax this build reads
    if (f.enabled && std::string_view(f.option) == "STRATA_WITH_GMSH")
      s += fmt::format(", gmsh {}", preprocess::gmsh_version());
  }
  return s;
}

/// A number above `lo` (or at least `lo` when `inclusive`): CLI11's own PositiveNumber and
/// NonNegativeNumber print their range as the 309 digits of the largest double.
CLI::Validator number_from(double lo, bool inclusive) {
  const std::string what = fmt::format("NUMBER {} {}", inclusive ? ">=" : ">", lo);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double x = 0;
        if (!CLI::detail::lexical_cast(text, x)) return fmt::format("{} is not a number", text);
        if (std::isfinite(x) && (inclusive ? x >= lo : x > lo)) return "";
        return fmt::format("{} must be a finite number {} {}", text, inclusive ? ">=" : ">", lo);
      },
      what);
}
const CLI::Validator kPositive = number_from(0, false), kNonNegative = number_from(0, true);

/// -o "" is a mistake (an unset shell variable, say), not a request for the default folder.
const CLI::Validator kDirectory(
    [](std::string& text) -> std::string {
      return text.empty() ? "an empty path: name one, or leave the option out for the default" : "";
    },
    "DIR");

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "strata — bonded-particle DEM, FEM and coupled models of how rock breaks.\n"
      "Scene files (TOML) describe the model; see docs/scene-reference.md.",
      "strata"};
  app.set_version_flag("--version", std::function<std::string()>(version_text));  // gmsh only when asked
  app.require_subcommand(1);
  app.fallthrough();
  bool verbose = false, quiet = false;
  app.add_flag("-v,--verbose", verbose, "More messages");
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors");
  app.footer(
      "Examples:\n  strata check examples/01_uniaxial_compression/quick.toml\n"
      "  strata run examples/01_uniaxial_compression/quick.toml -o out/quick\n"
      "Run 'strata SUBCOMMAND --help' for each subcommand.");

  // ---- run ----
  SceneOptions opt;
  auto* run =
      app.add_subcommand("run", "Run a scene: build the model, simulate, write series, probes and pictures");
  run->add_option("scene", opt.scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  run->add_option("-o,--output", opt.output, "Output directory (default: [output] directory of the scene)")
      ->check(kDirectory);
  run->add_option("--threads", opt.threads, "Threads for parallel loops (default: [solver] threads, 0 = all)")
      ->check(CLI::Range(0, par::kMaxThreads));
  run->add_option("--set", opt.overrides,
                  "Override a scene key, validated like the file: KEY=VALUE (repeatable)")
      ->take_all();
  run->add_flag("--force", opt.force,
                "Run even when dt exceeds the critical time step (results are unreliable)");
  run->add_option("--restart", opt.restart,
                  "Continue from a checkpoint (OUTDIR/checkpoint.h5) of this scene up to its solver.steps")
      ->check(needs_part("STRATA_WITH_HDF5", "continuing from an HDF5 checkpoint"))
      ->check(CLI::ExistingFile);
  run->add_flag("--no-checkpoint", opt.no_checkpoint,
                "Write no checkpoint at the end of a completed run (a model of 1e8 spheres writes 14 GB); "
                "output.checkpoint_every and an interrupted run still write theirs");
  run->footer(
      "Example:\n  strata run examples/01_uniaxial_compression/scene.toml -o out/c1 --threads 2 \\\n"
      "      --set solver.steps=200000 --set output.frames=10\n"
      "  strata run examples/01_uniaxial_compression/scene.toml -o out/c1 --set solver.steps=400000 \\\n"
      "      --restart out/c1/checkpoint.h5\n"
      "  strata run examples/02_metamaterial_chain/scene.toml -o out/meta   # coupled chain: eta sweep\n"
      "  strata run examples/04_coupled_wave/quick.toml -o out/wave_q        # coupled wave: eta sweep\n"
      "SIGINT (Ctrl-C) or SIGTERM stop a run between two chunks of steps: it writes the current frame\n"
      "and OUTDIR/checkpoint.h5, and exits with status 130 or 143.");

  // ---- check ----
  bool check_json = false;
  auto* check =
      app.add_subcommand("check", "Validate a scene and print what would be built and the derived numbers");
  check->add_option("scene", opt.scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  check->add_option("--set", opt.overrides, "Override a scene key: KEY=VALUE (repeatable)")->take_all();
  check->add_flag("--json", check_json, "Print one JSON object instead of text");
  check->footer(
      "Example:\n  strata check examples/01_uniaxial_compression/scene.toml --set solver.dt=1e-7\n"
      "  strata check examples/02_metamaterial_chain/paper.toml   # coupled chain: exit 2, dt_DEM unstable");

  // ---- mesh ----
  bool mesh_json = false;
  auto* mesh =
      app.add_subcommand("mesh", "Build the model only and report counts, packing density and time taken");
  mesh->add_option("scene", opt.scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  mesh->add_option("-o,--output", opt.output, "Directory for the model files (default: none written)")
      ->check(kDirectory)
      ->check(needs_part("STRATA_WITH_VTK", "writing the model files (VTK series)"));
  mesh->add_option("--set", opt.overrides, "Override a scene key: KEY=VALUE (repeatable)")->take_all();
  mesh->add_flag("--json", mesh_json, "Print one JSON object");
  mesh->footer("Example:\n  strata mesh examples/01_uniaxial_compression/scene.toml --json");

  // ---- bench ----
  auto* bench = app.add_subcommand("bench", "Benchmarks that print one JSON object");
  bench->require_subcommand(1);
  BenchDemOptions bopt;
  auto* bdem = bench->add_subcommand("dem", "DEM stepping rate of a lattice block under slow compression");
  bdem->add_option("--dim", bopt.dim, "2 (hexagonal disks) or 3 (close-packed spheres)")
      ->check(CLI::IsMember({2, 3}));
  bdem->add_option("--particles", bopt.particles, "Approximate number of particles")->check(kPositive);
  bdem->add_option("--steps", bopt.steps, "Time steps to time")->check(kPositive);
  bdem->add_option("--threads", bopt.threads, "Threads (0 = all)")->check(CLI::Range(0, par::kMaxThreads));
  bdem->add_option("--lattice", bopt.lattice, "3D lattice: hcp or fcc")->check(CLI::IsMember({"hcp", "fcc"}));
  bdem->add_flag(
      "--normal-only", bopt.normal_only,
      "Normal springs only (ks = 0: central forces, no shear history kept), as LAMMPS's bond harmonic");
  bdem->footer("Example:\n  strata bench dem --dim 2 --particles 1000000 --steps 200 --threads 2");

  // ---- render ----
  RenderOptions ropt;
  auto* render = app.add_subcommand(
      "render", "Draw every frame of a series to PNG (starts Xvfb when there is no display)");
  render
      ->add_option("series", ropt.series,
                   "Particle series (.pvd) written by 'strata run', or a FEM series (.vtu frames)")
      ->required()
      ->check(CLI::ExistingFile);
  render->add_option("-o,--output", ropt.output, "Directory for the PNG frames (default: <series dir>/png)")
      ->check(kDirectory);
  render->add_option("--field", ropt.field,
                     "Array to colour by (default: damage for particles, displacement for a FEM series)");
  render->add_option("--size", ropt.size, "Picture size in pixels: W H")->expected(2);
  render->add_flag("--no-movie", ropt.no_movie, "Do not join the pictures into a movie");
  render->add_option("--mesh", ropt.mesh, "FEM series (.pvd of .vtu frames) drawn under the particles")
      ->check(CLI::ExistingFile);
  render->add_flag("--contacts", ropt.contacts, "Also draw contacts (state 4 lines of bonds.pvd)");
  render->add_flag(
      "--no-cracks", ropt.no_cracks,
      "Leave the broken bonds out (e.g. layers coloured by --field group, whose offsets show the faults)");
  // A list option checked by number_list_error: a bad one exits with status 2 and says why.
  auto numbers = [](std::size_t count, std::size_t nonzero_from, std::string what) {
    return CLI::Validator(
        [=](std::string& text) { return number_list_error(text, count, nonzero_from, what); }, what);
  };
  render->add_option("--view", ropt.view, "3D: direction from the camera to the model, X,Y,Z")
      ->check(numbers(3, 0, "a view direction X,Y,Z"));
  render->add_option("--up", ropt.up, "3D: the direction shown upwards, X,Y,Z")
      ->check(numbers(3, 0, "an up vector X,Y,Z"));
  render->add_option("--clip", ropt.clip, "3D: leave out what lies on the normal's side of a plane")
      ->check(numbers(6, 3, "a clip plane OX,OY,OZ,NX,NY,NZ"));
  render->footer(
      "Examples:\n  strata render out/c1/particles.pvd -o out/c1/png --field damage\n"
      "  strata render out/c3d/particles.pvd --view -1,-1,-0.5 --up 0,0,1 --clip 0,0,0,0,1,0\n"
      "  strata render out/fem/fem.pvd --field von_mises");

  // ---- report ----
  cases::ReportOptions rep;
  auto* report = app.add_subcommand("report",
                                    "Coupled FEM-DEM reports over eta: error against run time of the chain "
                                    "cases (chain6, metamaterial), reflection of a "
                                    "wave at a 2D coupled interface (wave): CSV, Markdown, PNG");
  report->add_option("case", rep.case_name, "chain6, metamaterial or wave")
      ->required()
      ->check(CLI::IsMember({"chain6", "metamaterial", "wave"}));
  report->add_option("-o,--output", rep.output, "Directory for <case>_sweep.{csv,md,png}")->check(kDirectory);
  auto* report_eta =
      report->add_option("--eta", rep.etas, "Time-step ratios (integers >= 1; wave default 1 2 4 5 10)")
          ->check(kPositive);
  report->add_option("--modes", rep.modes, "serial, parallel or both")
      ->check(CLI::IsMember({"serial", "parallel", "both"}));
  report->add_option("--dt-dem", rep.dt_dem, "DEM step (s); default 1e-4 (chain6), 4e-6 (metamaterial)")
      ->check(kNonNegative);
  report
      ->add_option("--duration", rep.duration,
                   "Simulated time (s); default 20 (chain6), 0.075 (metamaterial)")
      ->check(kNonNegative);
  report
      ->add_option("--fem-scheme", rep.fem_scheme, "central-difference, explicit-newmark or implicit-newmark")
      ->check(CLI::IsMember({"central-difference", "explicit-newmark", "pc-newmark", "implicit-newmark"}));
  report->add_option("--dt-ref", rep.dt_ref, "Reference step of the metamaterial case (s)")->check(kPositive);
  report->add_option("--pulse", rep.pulse_amplitude, "Metamaterial half-sine pulse amplitude (N)");
  report->add_option("--pulse-duration", rep.pulse_duration, "Metamaterial pulse duration (s)")
      ->check(kPositive);
  report->add_option("--repeats", rep.repeats, "Runs per point; the fastest is reported")->check(kPositive);
  report->add_flag("--check", rep.check_only, "Only check the time step (exit 2 when unstable)");
  report->add_flag("--no-plot", rep.no_plot, "Do not write the PNG plot");
  report->add_flag("--run-unstable", rep.run_unstable,
                   "chains: run the eta points above a limit anyway, to see them blow up");
  cases::WaveOptions wave;  // `report wave` only
  report
      ->add_option("--geometry", wave.geometry,
                   "wave: geometry file with the two regions (default examples/04_coupled_wave/wave.geo)")
      ->check(CLI::ExistingFile);
  report->add_option("--particle-region", wave.particle_region, "wave: physical group filled with particles");
  report->add_option("--fem-region", wave.fem_region, "wave: physical group meshed for the FEM");
  report->add_option("--wavelengths", wave.wavelengths, "wave: pulse lengths c*T in particle diameters")
      ->check(kPositive);
  report
      ->add_option("--dt-fraction", wave.dt_fraction,
                   "wave: dt_DEM as a fraction of the lattice's critical step")
      ->check(CLI::Range(1e-6, 1.0));
  report->add_option("--fem-far-size", wave.fem_far_size, "wave: largest FEM element in particle diameters")
      ->check(CLI::Range(1.0, 100.0));
  report->add_option("--threads", wave.threads, "wave: threads of the loops inside each partition (0 = all)")
      ->check(CLI::Range(0, par::kMaxThreads));
  report->add_flag("--quick", wave.quick, "wave: eta 1 and 5, one wavelength (20 d): a few seconds");
  report->add_flag(
      "--embedded", wave.embedded,
      "wave: FEM | DEM | FEM (examples/04_coupled_wave/wave_embedded.geo, eta 1 2 5, 20 and 40 d)");
  report->add_option("--exit-region", wave.exit_region, "wave: second FEM group, beyond the particles");
  report
      ->add_option("--frames", wave.frames,
                   "wave: VTK frames of one extra run in DIR/series (0: none; 12, quick 3)")
      ->check(kNonNegative)
      ->check(needs_part("STRATA_WITH_VTK", "a VTK series of the wave", "0"));
  report->add_option("--series-eta", wave.series_eta, "wave: eta of the series run (serial, longest pulse)")
      ->check(kPositive);
  report->footer(
      "Examples:\n  strata report chain6 -o out/chain6\n  strata report metamaterial --dt-dem 1e-4 --check\n"
      "  strata report wave -o out/wave --wavelengths 10 20 40\n"
      "The same sweeps run from scene files: strata check|run examples/02_metamaterial_chain/scene.toml,\n"
      "examples/04_coupled_wave/scene.toml ([coupled], docs/scene-reference.md).");

  // ---- calibrate ----
  SceneOptions cal;
  auto* calibrate = app.add_subcommand(
      "calibrate",
      "Choose Kn, Ks, Fn_max and Fs0 that give a rock's E, nu, UCS and tensile strength, by running uniaxial "
      "and Brazilian specimens");
  calibrate->add_option("file", cal.scene, "Calibration file: a [calibrate] table (docs/scene-reference.md)")
      ->required()
      ->check(CLI::ExistingFile);
  calibrate
      ->add_option("-o,--output", cal.output,
                   "Directory for calibration.{md,json,csv}, the specimens and runs")
      ->check(kDirectory);
  calibrate->add_option("--set", cal.overrides, "Override a key: KEY=VALUE (repeatable)")->take_all();
  calibrate->add_option("--threads", cal.threads, "Threads for parallel loops (0 = all)")
      ->check(CLI::Range(0, par::kMaxThreads));
  calibrate->footer(
      "Example:\n  strata calibrate examples/07_calibration/granite_2d.toml -o out/granite_2d\n"
      "  strata calibrate examples/07_calibration/granite_2d.toml --set calibrate.tolerance=0.05");

  // ---- compare ----
  cases::CompareOptions cmp;
  int cmp_threads = 1;
  auto* compare = app.add_subcommand(
      "compare",
      "Error against run time: a scene at several eta against a reference scene of the same geometry");
  compare->add_option("scene", cmp.scene, "Scene studied (e.g. coupled FEM-DEM)")
      ->required()
      ->check(CLI::ExistingFile);
  compare->add_option("--reference", cmp.reference, "Reference scene (e.g. all particles), same gauges")
      ->required()
      ->check(CLI::ExistingFile);
  compare->add_option("--eta", cmp.etas, "Time-step ratios (integers >= 1; default: the scene's solver.eta)")
      ->check(CLI::Range(1, 1 << 20));
  compare->add_option("-o,--output", cmp.output, "Directory for compare.{csv,md,png} and the runs")
      ->check(kDirectory);
  compare->add_option("--set", cmp.overrides, "Override a key of both scenes: KEY=VALUE (repeatable)")
      ->take_all();
  compare->add_option("--repeats", cmp.repeats, "Runs per point; the fastest is reported")
      ->check(CLI::Range(1, 100));
  compare->add_option("--threads", cmp_threads, "Threads for parallel loops (0 = all; default 1)")
      ->check(CLI::Range(0, par::kMaxThreads));
  compare->add_flag("--force", cmp.force, "Also run eta values strata would refuse as unstable");
  compare->add_flag("--no-plot", cmp.no_plot, "Do not write the PNG plots");
  compare->footer(
      "Example:\n  strata compare examples/05_tunnel/scene.toml --reference "
      "examples/05_tunnel/reference.toml \\\n"
      "      --eta 1 2 3 --set solver.steps=8000 -o out/tunnel_compare\n"
      "Each run writes probes (no frames, pictures or checkpoints unless --set turns them on) into\n"
      "OUTPUT/runs/<label>; the gauge error is max |u - u_ref| over the probe rows and gauge columns\n"
      "over the largest |u_ref| ([probe] gauges of both scenes).");

  // ---- reference ----
  std::string ref_out;
  auto* reference =
      app.add_subcommand("reference", "Print the scene-file reference (docs/scene-reference.md)");
  reference->add_option("-o,--output", ref_out, "Write to this file instead of standard output")
      ->check(kDirectory);
  reference->footer("Example:\n  strata reference -o docs/scene-reference.md");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  log::init(quiet ? log::Level::Quiet : verbose ? log::Level::Verbose : log::Level::Normal);

  try {
    if (*run) return run_scene(opt);
    if (*check) return check_scene(opt, check_json);
    if (*mesh) return mesh_scene(opt, mesh_json);
    if (*bdem) {
      std::printf("%s\n", bench_dem_json(bopt).c_str());
      return 0;
    }
    if (*render) return render_series_cmd(ropt);
    if (*compare) return compare_cmd(cmp, cmp_threads);
    if (*calibrate) return calibrate_scene(cal);
    if (*report && rep.case_name == "wave") {
      wave.output = report->count("--output") ? rep.output : std::filesystem::path("out/wave");
      if (report_eta->count()) wave.etas = rep.etas;
      wave.modes = rep.modes;
      if (!rep.fem_scheme.empty()) wave.fem_scheme = rep.fem_scheme;
      wave.repeats = report->count("--repeats") ? rep.repeats : 1;
      wave.no_plot = rep.no_plot;
      wave.check_only = rep.check_only;
      wave.refuse_unstable_eta = rep.check_only;  // --check: exit 2 when an eta would be refused
      return cases::wave_report_cmd(wave);
    }
    if (*report) return cases::report_cmd(rep);
    if (*reference) {
      const std::string md = scene::reference_markdown();
      if (ref_out.empty()) {
        std::fwrite(md.data(), 1, md.size(), stdout);
      } else {
        scene::write_file_atomic(ref_out, md);
      }
      return 0;
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "strata: error: %s\n", e.what());
    return e.exit_status();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "strata: error: %s\n", e.what());
    return 1;
  }
  return 2;
}
}  // namespace strata::app
