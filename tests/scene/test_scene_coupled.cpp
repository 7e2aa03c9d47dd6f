// Coupled scenes ([coupled]: the chains of Li et al. 2023 and the 2D coupled wave): they load,
// map onto the sweep's options, and refuse mixed particle tables, misspelt keys, keys of
// another case and bad η values with file:line:col messages.
#include <gtest/gtest.h>

#include <strata/core/error.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include <strata/cases/chain_report.hpp>
#include <strata/cases/wave_report.hpp>
#include <strata/scene/scene.hpp>
#include "scene_fixtures.hpp"
#include "scene_test_util.hpp"

using strata::scene::Scene;
using strata::scene::test::error_of;

namespace {

// The line numbers matter: the tests below point at them (see chain_scene).
const std::string kCoupled = fixtures::chain_scene("metamaterial", "5e-5", "1, 2, 20");

std::string edit_coupled(const std::string& from, const std::string& to, std::string text = kCoupled) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "kCoupled has no '" << from << "'";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

const std::string kCoupledKeys =
    "case, title, dt_dem, eta, modes, duration, fem_scheme, dt_ref, pulse_amplitude, pulse_duration, "
    "geometry, particle_region, fem_region, exit_region, embedded, wavelengths, diameter, dt_fraction, "
    "fem_far_size, fem_growth, peak_velocity, frames, series_eta, repeats, threads";

}  // namespace

TEST(SceneCoupled, LoadsWithDefaultsAndMapsOntoTheSweepOptions) {
  const Scene s = strata::scene::parse(kCoupled, "dir/scene.toml");
  ASSERT_TRUE(s.coupled.has_value());
  const auto& c = *s.coupled;
  EXPECT_EQ(c.case_name.value, "metamaterial");
  EXPECT_EQ(c.eta.value, (std::vector<std::int64_t>{1, 2, 20}));
  EXPECT_FALSE(c.dt_ref.given);
  EXPECT_DOUBLE_EQ(c.dt_ref.value, 1e-6);
  EXPECT_EQ(c.fem_scheme.value, "auto");

  const auto o = strata::cases::coupled_report_options(s, /*force=*/false);
  EXPECT_EQ(o.case_name, "metamaterial");
  EXPECT_EQ(o.etas, (std::vector<int>{1, 2, 20}));
  EXPECT_EQ(o.modes, "serial");
  EXPECT_DOUBLE_EQ(o.dt_dem, 5e-5);
  EXPECT_DOUBLE_EQ(o.duration, 0.0);  // the case's default, filled in by the report
  EXPECT_DOUBLE_EQ(o.pulse_amplitude, 100.0);
  EXPECT_DOUBLE_EQ(o.pulse_duration, 1e-3);
  EXPECT_EQ(o.repeats, 3);
  EXPECT_TRUE(o.no_plot);
  EXPECT_TRUE(o.refuse_unstable_eta);
  EXPECT_EQ(o.output.filename(), "res");
  EXPECT_EQ(o.output.parent_path().filename(), "dir");  // relative to the scene file

  // The default η list is the paper's.
  const Scene d = strata::scene::parse(edit_coupled("eta = [1, 2, 20]\n", ""), "scene.toml");
  EXPECT_FALSE(d.coupled->eta.given);  // the default depends on the case
  EXPECT_EQ(strata::cases::coupled_report_options(d, false).etas, (std::vector<int>{1, 2, 3, 4, 5, 10, 20}));
  // A particle scene has no [coupled].
  EXPECT_FALSE(
      strata::scene::parse("[scene]\ndimension = 2\n[[material]]\nname = \"r\"\ndensity = 1\nkn = 1\n"
                           "ks = 1\n[[region]]\nname = \"b\"\nmaterial = \"r\"\ndiameter = 1\nsize = [4, 4]\n"
                           "[solver]\nsteps = 1\n",
                           "scene.toml")
          .coupled.has_value());
}

TEST(SceneCoupled, OverridesAreValidatedLikeTheFile) {
  const Scene s = strata::scene::parse(kCoupled, "scene.toml", {"coupled.dt_dem=1e-4", "coupled.eta=[1, 5]"});
  EXPECT_DOUBLE_EQ(s.coupled->dt_dem.value, 1e-4);
  EXPECT_EQ(s.coupled->eta.value, (std::vector<std::int64_t>{1, 5}));
  EXPECT_EQ(error_of(kCoupled, {"coupled.eta=[0]"}), "--set coupled.eta=[0]: eta[0] = 0 must be >= 1");
}

TEST(SceneCoupled, ParticleTablesCannotBeMixedIn) {
  EXPECT_EQ(error_of(kCoupled + "\n[[material]]\nname = \"rock\"\ndensity = 2650\nkn = 1e9\nks = 1e9\n"),
            "scene.toml:11:1: [[material]] cannot be mixed with [coupled] (scene.toml:1:1): a coupled "
            "scene describes the whole model in [coupled] and may hold besides only [output] (keys "
            "directory, render); remove [[material]] or [coupled]");
  EXPECT_EQ(error_of("[scene]\ndimension = 2\n\n" + kCoupled),
            "scene.toml:1:1: [scene] cannot be mixed with [coupled] (scene.toml:4:1): a coupled scene "
            "describes the whole model in [coupled] and may hold besides only [output] (keys directory, "
            "render); remove [scene] or [coupled]");
  EXPECT_EQ(error_of(edit_coupled("render = false", "render = false\nframes = 10")),
            "scene.toml:10:1: output.frames does not apply to a coupled scene ([coupled] at "
            "scene.toml:1:1): its [output] takes only directory, render");
  // A particle scene given a [coupled] table by --set is a mixed scene too.
  const std::string particles = "[scene]\ndimension = 2\n";
  EXPECT_EQ(error_of(particles, {"coupled.case=chain6", "coupled.dt_dem=1e-4"}),
            "scene.toml:1:1: [scene] cannot be mixed with [coupled] (--set coupled.case=chain6): a "
            "coupled scene describes the whole model in [coupled] and may hold besides only [output] "
            "(keys directory, render); remove [scene] or [coupled]");
}

TEST(SceneCoupled, MisspeltAndMissingKeys) {
  EXPECT_EQ(error_of(edit_coupled("dt_dem = 5e-5", "dt_demm = 5e-5")),
            "scene.toml:3:1: unknown key 'dt_demm' in [coupled]; did you mean 'dt_dem'? (allowed: " +
                kCoupledKeys + ")");
  EXPECT_EQ(
      error_of(edit_coupled("case = \"metamaterial\"", "case = \"metamaterial_chain\"")),
      "scene.toml:2:8: case = \"metamaterial_chain\" must be one of chain6, metamaterial, wave; did you "
      "mean "
      "'metamaterial'?");
  EXPECT_EQ(error_of(edit_coupled("dt_dem = 5e-5\n", "")),
            "scene.toml:2:8: [coupled] needs 'dt_dem' for case = \"metamaterial\" (DEM time step dt_DEM "
            "(velocity Verlet); the FEM step is η·dt_DEM)");
  EXPECT_EQ(error_of(edit_coupled("dt_dem = 5e-5", "dt_dem = -5e-5")),
            "scene.toml:3:10: dt_dem = -5e-5 must be > 0 (s)");
  EXPECT_EQ(
      error_of(edit_coupled("modes = \"serial\"", "modes = \"serail\"")),
      "scene.toml:5:9: modes = \"serail\" must be one of serial, parallel, both; did you mean 'serial'?");
}

TEST(SceneCoupled, EtaValuesAreIntegersOfAtLeastOne) {
  EXPECT_EQ(error_of(edit_coupled("eta = [1, 2, 20]", "eta = [1, 2.5, 20]")),
            "scene.toml:4:11: eta[1] must be an integer, got a real number 2.5");
  EXPECT_EQ(error_of(edit_coupled("eta = [1, 2, 20]", "eta = [1, 0, 20]")),
            "scene.toml:4:11: eta[1] = 0 must be >= 1");
  EXPECT_EQ(error_of(edit_coupled("eta = [1, 2, 20]", "eta = [1, \"two\"]")),
            "scene.toml:4:11: eta[1] must be an integer, got a string \"two\"");
  EXPECT_EQ(error_of(edit_coupled("eta = [1, 2, 20]", "eta = 3")),
            "scene.toml:4:7: eta must be a list of integers, got an integer 3");
  EXPECT_EQ(error_of(edit_coupled("eta = [1, 2, 20]", "eta = []")),
            "scene.toml:4:7: eta must have at least 1 entry, got 0");
  EXPECT_EQ(error_of(edit_coupled("eta = [1, 2, 20]", "eta = [1, 2, 1]")),
            "scene.toml:4:7: eta: 1 is listed twice");
  // 2.0 is a fine way to write 2.
  EXPECT_EQ(strata::scene::parse(edit_coupled("eta = [1, 2, 20]", "eta = [1, 2.0]"), "scene.toml")
                .coupled->eta.value,
            (std::vector<std::int64_t>{1, 2}));
}

TEST(SceneCoupled, ChecksBetweenKeys) {
  EXPECT_EQ(error_of(edit_coupled("case = \"metamaterial\"", "case = \"chain6\"\npulse_amplitude = 5")),
            "scene.toml:3:19: pulse_amplitude applies only to case = \"metamaterial\" (this scene has case = "
            "\"chain6\"); remove it (case = \"chain6\" takes: case, title, dt_dem, eta, modes, duration, "
            "fem_scheme, repeats, threads)");
  EXPECT_EQ(error_of(edit_coupled("modes = \"serial\"", "modes = \"serial\"\nduration = 5e-4")),
            "scene.toml:6:12: duration = 0.0005 s holds no FEM step of eta = 20 (eta*dt_dem = 0.001 s): "
            "lengthen duration or lower eta");
}

TEST(SceneCoupled, MissingTablesOfAParticleSceneStillReported) {
  // Without [coupled], a scene still needs its particle tables.
  EXPECT_NE(error_of("[output]\ndirectory = \"x\"\n").find("missing required table [scene]"),
            std::string::npos);
}

// ---- case = "wave": the 2D coupled wave of examples/04_coupled_wave -----------------------

namespace {

const std::filesystem::path kWaveDir =
    std::filesystem::path(STRATA_SOURCE_DIR) / "examples" / "04_coupled_wave";
/// A wave scene "in" the example folder, so that geometry = "wave.geo" resolves to its file.
const std::filesystem::path kWaveFile = kWaveDir / "t.toml";

// The line numbers matter: the tests below point at them.
const std::string kWave = R"toml([coupled]
case = "wave"
geometry = "wave.geo"
wavelengths = [20]
eta = [1, 5]
modes = "serial"

[output]
directory = "res"
render = false
)toml";

std::string wave_error(const std::string& text) {
  try {
    strata::scene::parse(text, kWaveFile);
  } catch (const strata::Error& e) {
    EXPECT_EQ(e.kind(), strata::ErrorKind::Input) << e.what();
    return e.what();
  }
  return "no error";
}

const std::string kWaveKeys =
    "case, title, eta, modes, fem_scheme, geometry, particle_region, fem_region, exit_region, embedded, "
    "wavelengths, diameter, dt_fraction, fem_far_size, fem_growth, peak_velocity, frames, series_eta, "
    "repeats, threads";

}  // namespace

TEST(SceneCoupledWave, LoadsAndMapsOntoTheWaveOptions) {
  const Scene s = strata::scene::parse(kWave, kWaveFile);
  ASSERT_TRUE(s.coupled.has_value());
  const auto o = strata::cases::wave_scene_options(s, /*force=*/false);
  // The geometry is resolved relative to the scene file's folder.
  EXPECT_EQ(o.geometry, (kWaveDir / "wave.geo").lexically_normal());
  EXPECT_EQ(o.wavelengths, (std::vector<double>{20}));
  EXPECT_EQ(o.etas, (std::vector<int>{1, 5}));
  EXPECT_EQ(o.modes, "serial");
  EXPECT_EQ(o.particle_region, "dem");
  EXPECT_EQ(o.fem_region, "fem");
  EXPECT_EQ(o.exit_region, "");
  EXPECT_FALSE(o.embedded);
  EXPECT_EQ(o.fem_scheme, "auto");
  EXPECT_DOUBLE_EQ(o.d, 1e-3);
  EXPECT_DOUBLE_EQ(o.dt_fraction, 0.15);
  EXPECT_DOUBLE_EQ(o.fem_far_size, 1.0);
  EXPECT_DOUBLE_EQ(o.peak_velocity, 0.1);
  EXPECT_EQ(o.frames, 12);
  EXPECT_EQ(o.series_eta, 1);
  EXPECT_EQ(o.repeats, 1);  // the wave's defaults, not the chains' (3 and 0)
  EXPECT_EQ(o.threads, 1);
  EXPECT_EQ(strata::cases::coupled_threads(s), 1);
  EXPECT_TRUE(o.no_plot);
  EXPECT_TRUE(o.refuse_unstable_eta);
  EXPECT_FALSE(strata::cases::wave_scene_options(s, /*force=*/true).refuse_unstable_eta);
  EXPECT_EQ(o.output, (kWaveDir / "res").lexically_normal());

  // η and λ not given: the report's defaults, which differ with embedded = true.
  std::string bare = kWave;
  const std::string sweep = "wavelengths = [20]\neta = [1, 5]\n";
  bare.replace(bare.find(sweep), sweep.size(), "");
  const auto d = strata::cases::wave_scene_options(strata::scene::parse(bare, kWaveFile), false);
  EXPECT_EQ(d.etas, strata::cases::kWaveEtas);
  EXPECT_EQ(d.wavelengths, strata::cases::kWaveWavelengths);
  const auto e = strata::cases::wave_scene_options(
      strata::scene::parse(bare, kWaveFile, {"coupled.embedded=true", "coupled.geometry=wave_embedded.geo"}),
      false);
  EXPECT_EQ(e.etas, strata::cases::kWaveEmbeddedEtas);
  EXPECT_EQ(e.wavelengths, strata::cases::kWaveEmbeddedWavelengths);
  EXPECT_EQ(e.geometry, (kWaveDir / "wave_embedded.geo").lexically_normal());
}

TEST(SceneCoupledWave, TheExampleScenesLoad) {
  for (const char* f : {"scene.toml", "embedded.toml", "quick.toml"}) {
    const Scene s = strata::scene::load(kWaveDir / f);
    EXPECT_EQ(s.coupled->case_name.value, "wave") << f;
  }
  const auto q = strata::cases::wave_scene_options(strata::scene::load(kWaveDir / "quick.toml"), false);
  EXPECT_EQ(q.etas, (std::vector<int>{1, 5}));
  EXPECT_EQ(q.wavelengths, (std::vector<double>{20}));
  EXPECT_EQ(q.frames, 3);
  const auto e = strata::cases::wave_scene_options(strata::scene::load(kWaveDir / "embedded.toml"), false);
  EXPECT_TRUE(e.embedded);
  EXPECT_EQ(e.exit_region, "fem_exit");
  EXPECT_EQ(e.etas, strata::cases::kWaveEmbeddedEtas);
}

TEST(SceneCoupledWave, KeysOfAnotherCaseAreRefusedWhereTheyAre) {
  // A chain-only key in a wave scene, at its value (line 3, column 10).
  std::string text = kWave;
  text.replace(text.find("geometry"), 0, "dt_dem = 1e-4\n");
  EXPECT_EQ(wave_error(text), kWaveFile.string() +
                                  ":3:10: dt_dem applies only to case = \"chain6\" or \"metamaterial\" (this "
                                  "scene has case = \"wave\"); remove it (case = \"wave\" takes: " +
                                  kWaveKeys + ")");
  // A wave-only key in a chain scene.
  EXPECT_EQ(error_of(edit_coupled("modes = \"serial\"", "modes = \"serial\"\nwavelengths = [20]")),
            "scene.toml:6:15: wavelengths applies only to case = \"wave\" (this scene has case = "
            "\"metamaterial\"); remove it (case = \"metamaterial\" takes: case, title, dt_dem, eta, modes, "
            "duration, fem_scheme, dt_ref, pulse_amplitude, pulse_duration, repeats, threads)");
  // The same through --set.
  EXPECT_EQ(error_of(kCoupled, {"coupled.frames=3"}),
            "--set coupled.frames=3: frames applies only to case = \"wave\" (this scene has case = "
            "\"metamaterial\"); remove it (case = \"metamaterial\" takes: case, title, dt_dem, eta, modes, "
            "duration, fem_scheme, dt_ref, pulse_amplitude, pulse_duration, repeats, threads)");
}

TEST(SceneCoupledWave, GeometryIsNeededAndMustExist) {
  std::string none = kWave;
  none.replace(none.find("geometry = \"wave.geo\"\n"), 22, "");
  const std::string missing = wave_error(none);
  EXPECT_EQ(missing.rfind(kWaveFile.string() + ":2:8: [coupled] needs 'geometry' for case = \"wave\" (", 0),
            0u)
      << missing;
  std::string nope = kWave;
  nope.replace(nope.find("wave.geo"), 8, "nope.geo");
  EXPECT_EQ(wave_error(nope), kWaveFile.string() + ":3:12: geometry 'nope.geo' not found (looked for " +
                                  (kWaveDir / "nope.geo").lexically_normal().string() +
                                  "; paths are relative to the scene file)");
  // Ranges of the wave's keys are the schema's, like any other key.
  std::string bad = kWave;
  bad.replace(bad.find("wavelengths = [20]"), 18, "wavelengths = [20, -1]");
  EXPECT_EQ(wave_error(bad),
            kWaveFile.string() + ":4:20: wavelengths[1] = -1 must be > 0 (particle diameters)");
}

TEST(SceneCoupledWave, TheReferenceSaysWhichCaseAKeyIsFor) {
  const std::string md = strata::scene::reference_markdown();
  EXPECT_NE(md.find("| `geometry` | path |"), std::string::npos);
  EXPECT_NE(md.find("only for case `wave`"), std::string::npos);
  EXPECT_NE(md.find("only for case `chain6` or `metamaterial`"), std::string::npos);
  EXPECT_NE(md.find("per case: chain6, metamaterial `3`; wave `1`"), std::string::npos);
}
