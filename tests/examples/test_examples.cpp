// Runs each example's quick scene end to end with the `strata` command and checks what it
// wrote: the series, pictures, and for the uniaxial compression example the physics.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>
#include <strata/config.hpp>
#include <strata/dem/wedge.hpp>
#include <strata/io/csv.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

int run(const std::string& args, std::string* output = nullptr) {
  const std::string cmd = std::string(STRATA_EXE) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  std::string out;
  while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int st = pclose(p);
  if (output) *output = out;
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

std::string read_text(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Number of a key in summary.json ("key": value), NaN when absent.
double summary_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return NAN;
  return std::strtod(json.c_str() + at + key.size() + 3, nullptr);
}

const fs::path kExamples = fs::path(STRATA_SOURCE_DIR) / "examples";
const fs::path kOut = fs::path(STRATA_BINARY_DIR) / "examples-out";

}  // namespace

// examples/01_uniaxial_compression (Li et al. 2017), quick variant: the same specimen loaded
// faster. Checks:
//  - Young's modulus from the initial slope against the analytical hex-lattice value
//    E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks) = 9.236e10 N/m (t = 1 m): within 2 % — the finite
//    1033-disk block between frictionless platens measures 9.23e10 at scene.toml's slow rate
//    (see the example's README), the rest is the platen rows' dynamic response at this
//    loading rate;
//  - tensile bond failure comes first, near the affine estimate (Li et al. 2017 report 7e-4,
//    1.0e-3 affine): between 5e-4 and 1.1e-3;
//  - the peak comes after the first tensile break and the stress then drops by more than half.
TEST(Examples, UniaxialCompressionQuick) {
  if (!STRATA_WITH_VTK || !STRATA_WITH_RENDER)
    GTEST_SKIP() << "the scene asks for frames and the test checks its pictures: needs STRATA_WITH_VTK and "
                    "STRATA_WITH_RENDER";
  const fs::path out = kOut / "01_uniaxial_compression";
  fs::remove_all(out);
  std::string log;
  ASSERT_EQ(
      run("run " + (kExamples / "01_uniaxial_compression" / "quick.toml").string() + " -o " + out.string(),
          &log),
      0)
      << log;
  for (const char* f : {"particles.pvd", "bonds.pvd", "probes.csv", "breaks.csv", "summary.json",
                        "stress_strain.png", "png/frame_000000.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  // the pictures joined into a movie: H.264 where ffmpeg is installed, else Ogg Theora
  EXPECT_TRUE(fs::exists(out / "movie.mp4") || fs::exists(out / "movie.ogv"));

  const auto probes = strata::io::read_csv(out / "probes.csv");
  const auto& strain = probes.column("strain");
  const auto& stress = probes.column("stress");
  // secant modulus at 40-90 % of the tensile onset strain (elastic, past the first transients)
  const double onset = summary_number(read_text(out / "summary.json"), "tensile_onset_strain");
  ASSERT_TRUE(std::isfinite(onset)) << "no tensile break recorded";
  std::size_t a = 0, b = 0;
  for (std::size_t i = 0; i < strain.size(); ++i) {
    if (strain[i] <= 0.4 * onset) a = i;
    if (strain[i] <= 0.9 * onset) b = i;
  }
  ASSERT_GT(b, a);
  const double e_measured = (stress[b] - stress[a]) / (strain[b] - strain[a]);
  const double kn = 6.587e10, ks = 2.371e10;
  const double e_lattice = 2 * std::sqrt(3.0) * kn * (kn + ks) / (3 * kn + ks);
  EXPECT_NEAR(e_measured / e_lattice, 1.0, 0.02) << "E = " << e_measured;

  EXPECT_GT(onset, 5e-4);
  EXPECT_LT(onset, 1.1e-3);
  const std::string summary = read_text(out / "summary.json");
  const double peak_strain = summary_number(summary, "peak_strain");
  const double peak_stress = summary_number(summary, "peak_stress_pa");
  EXPECT_GT(peak_strain, onset);
  EXPECT_LT(stress.back(), 0.5 * peak_stress) << "no stress drop after the peak";

  // summary.json's measured elastic constants, from the stress and lateral-strain probes,
  // against the hex lattice's (plane stress): E·t within 2 % as above; ν = (Kn − Ks)/(3Kn + Ks)
  // = 0.1905 within 5 % (the finite block between frictionless platens measures 0.195).
  const auto measured = summary.find("\"measured_elastic\"");
  ASSERT_NE(measured, std::string::npos) << "summary.json has no measured_elastic";
  const std::string block = summary.substr(measured, summary.find('}', measured) - measured);
  const double e_summary = summary_number(block, "youngs_modulus_pa");
  const double nu_summary = summary_number(block, "poisson_ratio");
  EXPECT_NEAR(e_summary / e_lattice, 1.0, 0.02) << "measured E = " << e_summary;
  EXPECT_NEAR(nu_summary / ((kn - ks) / (3 * kn + ks)), 1.0, 0.05) << "measured nu = " << nu_summary;
}

// examples/01_uniaxial_compression, bands_quick.toml: the specimen with Weibull-distributed
// bond strengths (coefficient of variation 0.1). The spread localises failure: summary.json
// must report two conjugate shear bands, one leaning each way from the loading axis, traced by
// the bonds that broke after the peak. Checks:
//  - a peak well before the end of the run (strain 1e-2), so that the bands are post-peak;
//  - the two bands inclined 20-40 degrees to the load (the hex lattice's rows are at 30
//    degrees; Mohr-Coulomb with the bonds' friction 0.239 gives 45 - 6.7 = 38.3 degrees), of
//    opposite sides, each holding at least 20 breaks and at most 2 particle diameters wide;
//  - the bands dominate: at least 20 % of the post-peak breaks lie in them (the perfect
//    lattice's network of parallel damage lines, quick.toml, puts 11 % in its two strongest
//    lines; this scene 28 %);
//  - the spread lowers the tensile onset below the perfect lattice's 7e-4 (the weakest
//    bonds break first) but not below half of it.
TEST(Examples, UniaxialCompressionBandsQuick) {
  const fs::path out = kOut / "01_uniaxial_compression_bands";
  fs::remove_all(out);
  std::string log;
  ASSERT_EQ(run("run " + (kExamples / "01_uniaxial_compression" / "bands_quick.toml").string() + " -o " +
                    out.string() + " --set output.render=false --set output.frames=0",
                &log),
            0)
      << log;
  const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
  const double onset = summary.at("tensile_onset_strain");
  EXPECT_GT(onset, 3.5e-4);
  EXPECT_LT(onset, 7e-4);
  const double peak_strain = summary.at("peak_strain");
  EXPECT_GT(peak_strain, onset);
  EXPECT_LT(peak_strain, 4e-3);
  ASSERT_TRUE(summary.contains("shear_bands")) << summary.dump(2);
  const auto& bands = summary["shear_bands"]["bands"];
  ASSERT_EQ(bands.size(), 2u) << summary["shear_bands"].dump(2);
  const double a0 = bands[0]["angle_to_load_deg"], a1 = bands[1]["angle_to_load_deg"];
  EXPECT_LT(a0 * a1, 0) << "the two bands lean the same way";
  EXPECT_GT(double(summary["shear_bands"]["fraction_in_bands"]), 0.2);
  for (const auto& b : bands) {
    const double angle = b["angle_to_load_deg"], width = b["width_m"];
    const int breaks = b["breaks"];
    EXPECT_GT(std::abs(angle), 20.0);
    EXPECT_LT(std::abs(angle), 40.0);
    EXPECT_GT(width, 0.0);
    EXPECT_LE(width, 2e-3);
    EXPECT_GE(breaks, 20);
  }
}

// examples/02_metamaterial_chain (Li et al. 2023), quick variant of the metamaterial chain (a
// coupled-chain scene, each point a network scene run through the one run path): the sweep's
// files, and the error of DEM mass 250 against the monolithic implicit Newmark reference at
// dt_DEM = 4e-6 s:
//  - at eta = 1 below 0.1 % of the peak displacement (measured 0.026 %; the monolithic central
//    difference at the same dt has 0.037 %, the last row);
//  - growing with eta (the FEM step resolves the 1 ms pulse ever worse: measured 0.51 % at
//    eta = 4, 5.0 % at eta = 20), every point completed.
TEST(Examples, MetamaterialChainQuick) {
  const fs::path out = kOut / "02_metamaterial_chain";
  fs::remove_all(out);
  std::string log;
  ASSERT_EQ(
      run("run " + (kExamples / "02_metamaterial_chain" / "quick.toml").string() + " -o " + out.string(),
          &log),
      0)
      << log;
  for (const char* f : {"metamaterial_sweep.csv", "metamaterial_sweep.md", "summary.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const auto t = strata::io::read_csv(out / "metamaterial_sweep.csv");
  const auto &eta = t.column("eta"), &mode = t.column("mode"), &err = t.column("err_max_m"),
             &ref = t.column("ref_max_m");
  ASSERT_EQ(t.rows(), 4u) << "eta = 1, 4, 20 (serial) and the monolithic baseline";
  EXPECT_EQ(eta[0], 1);
  EXPECT_EQ(eta[1], 4);
  EXPECT_EQ(eta[2], 20);
  EXPECT_EQ(mode[3], 2) << "last row: monolithic baseline";
  for (std::size_t i = 0; i < 4; ++i) ASSERT_GT(ref[i], 0) << "the pulse did not reach DEM mass 250";
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_EQ(t.column("status")[i], 0) << "row " << i << " did not complete";
  EXPECT_LT(err[0] / ref[0], 1e-3);
  EXPECT_LT(err[3] / ref[3], 1e-3);
  EXPECT_LT(err[2] / ref[2], 0.1);
  EXPECT_GT(err[1], err[0]);
  EXPECT_GT(err[2], err[1]);
}

// The 2D coupled FEM–DEM wave, quick variant (a [coupled] scene with case = "wave": λ = 20 d,
// η = 1 and 5, serial and parallel, a series of 3 frames). The analytical answer for the matched
// impedances is R = 0, T = 1; what the run measures comes from the discretisations meeting at
// the overlap and the multi-time-step exchange (README: R = 3.5e-3, T = 1.007 at η = 1;
// R = 2.9e-2, T = 0.946 at η = 5). Checks:
//  - every point ran ("ok" = 1), the parallel rows equal the serial ones (the report itself
//    refuses to finish otherwise);
//  - η = 1: R < 1e-2 (3 x the measured value: room for compiler and platform differences,
//    none for a broken exchange, which reflects tens of percent or blows up) and
//    |T − 1| < 0.03 (the 20 d pulse's dispersion in the window is below 1 %);
//  - η = 5: R < 0.06 and |T − 1| < 0.1, and R grows with η (the external DOFs move with the
//    copied velocity for a whole system step);
//  - the series and its pictures' folder exist (3 frames of each side).
TEST(Examples, CoupledWaveQuick) {
  if (!STRATA_WITH_GMSH || !STRATA_WITH_VTK)
    GTEST_SKIP() << "the wave is a .geo file with a VTK series: needs STRATA_WITH_GMSH and STRATA_WITH_VTK";
  const fs::path out = kOut / "04_coupled_wave";
  fs::remove_all(out);
  std::string log;
  ASSERT_EQ(
      run("run " + (kExamples / "04_coupled_wave" / "quick.toml").string() + " -o " + out.string(), &log), 0)
      << log;
  for (const char* f :
       {"wave_sweep.csv", "wave_sweep.md", "summary.json", "series/particles.pvd", "series/fem.pvd"})
    EXPECT_TRUE(fs::exists(out / f)) << f << "\n" << log;
  const auto t = strata::io::read_csv(out / "wave_sweep.csv");
  const auto &eta = t.column("eta"), &mode = t.column("mode"), &ok = t.column("ok"), &r = t.column("R_peak"),
             &tp = t.column("T_peak");
  ASSERT_EQ(t.rows(), 4u) << "eta = 1 and 5, serial and parallel";
  double r1 = NAN, t1 = NAN, r5 = NAN, t5 = NAN;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    EXPECT_EQ(ok[i], 1) << "row " << i;
    if (mode[i] != 0) continue;  // serial rows (the parallel ones are the same)
    (eta[i] == 1 ? r1 : r5) = r[i];
    (eta[i] == 1 ? t1 : t5) = tp[i];
  }
  EXPECT_LT(r1, 1e-2);
  EXPECT_NEAR(t1, 1.0, 0.03);
  EXPECT_LT(r5, 0.06);
  EXPECT_NEAR(t5, 1.0, 0.1);
  EXPECT_GT(r5, r1);
}

// examples/06_double_hole_blast (Zhao et al. 2021), quick variant: 2 mm disks, the radial
// pulse (85 MPa peak on each hole's wall, 25 µs) and 150 µs of its aftermath. Checks that the
// blast does what the paper's pictures show, as breaks.csv records it:
//  - cracks start at the holes: the first break lies within two diameters of a hole's rim;
//  - the fracturing stays local: every break within 100 mm of a hole's centre and fewer than
//    3 % of the bonds broken (at this load the stress wave loses its strength within a few
//    centimetres; a load or a sharing gone wrong shatters the whole plate);
//  - the holes link up: each 5 mm of the segment between the rims holds a broken bond within
//    5 mm of the centre line;
//  - the lattice and the load are mirror-symmetric about the plate's middle, and so are the
//    cracks: as many bonds break around one hole as around the other (within 2 %).
TEST(Examples, DoubleHoleBlastQuick) {
  if (!STRATA_WITH_GMSH || !STRATA_WITH_VTK)
    GTEST_SKIP() << "the plate is a .geo file and the scene asks for frames: needs STRATA_WITH_GMSH and "
                    "STRATA_WITH_VTK";
  const fs::path out = kOut / "06_double_hole_blast";
  fs::remove_all(out);
  std::string log;
  ASSERT_EQ(run("run " + (kExamples / "06_double_hole_blast" / "quick.toml").string() + " -o " + out.string(),
                &log),
            0)
      << log;
  const auto breaks = strata::io::read_csv(out / "breaks.csv");
  const auto &x = breaks.column("x"), &y = breaks.column("y");
  ASSERT_GT(breaks.rows(), 100u) << "the blast broke (almost) nothing";
  const double cx[2] = {0.2, 0.3}, cy = 0.125, radius = 0.005, d = 0.002;
  auto nearest = [&](std::size_t k, int* hole = nullptr) {
    const double a = std::hypot(x[k] - cx[0], y[k] - cy), b = std::hypot(x[k] - cx[1], y[k] - cy);
    if (hole) *hole = a < b ? 0 : 1;
    return std::min(a, b);
  };
  EXPECT_LT(nearest(0), radius + 2 * d) << "the first crack is not at a hole";
  double farthest = 0;
  std::size_t around[2] = {0, 0};
  std::vector<char> linked(18, 0);  // 5 mm stretches from rim to rim
  for (std::size_t k = 0; k < breaks.rows(); ++k) {
    int hole = 0;
    farthest = std::max(farthest, nearest(k, &hole));
    ++around[hole];
    const double s = x[k] - (cx[0] + radius);
    if (s >= 0 && s < 0.09 && std::abs(y[k] - cy) < 0.005) linked[std::size_t(s / 0.005)] = 1;
  }
  EXPECT_LT(farthest, 0.1);
  const double bonds = summary_number(read_text(out / "summary.json"), "bonds");
  EXPECT_LT(double(breaks.rows()), 0.03 * bonds);
  for (std::size_t k = 0; k < linked.size(); ++k)
    EXPECT_TRUE(linked[k]) << "no crack between the holes at " << 5 * k << "-" << 5 * (k + 1)
                           << " mm from the left rim";
  EXPECT_NEAR(double(around[0]) / double(around[1]), 1.0, 0.02);
}

/// The number after "key": in the object "section" of a JSON text (NaN when absent).
double number_in(const std::string& json, const std::string& section, const std::string& key) {
  const auto at = json.find("\"" + section + "\":");
  return at == std::string::npos ? NAN : summary_number(json.substr(at, json.find('}', at) - at), key);
}

// examples/07_calibration, quick variant (specimens 12 particles wide) with `strata calibrate`:
//  - E and nu reach their targets within a quarter of the tolerance (5 %), as the elastic stage
//    iterates for: 1.25 % and 0.0025;
//  - the granite's UCS/tensile strength of 16.7 is out of reach of the 12-particle specimens
//    (they give about 9.5), so the UCS (match = "ucs") is met within the tolerance and the
//    report says the ratio was not reached;
//  - the written uniaxial specimen, run again with `strata run`, gives the same peak stress to
//    the last bit (the report is what the scene does);
//  - a reachable ratio (tensile strength 21 MPa) is met with both strengths within 2x the
//    tolerance (the strengths scale with the bonds' only approximately);
//  - 3D: the cylinder and the thick disc of a close packing 10 particles wide, nu = 0.15.
TEST(Examples, CalibrationQuick) {
  const fs::path quick = kExamples / "07_calibration" / "quick.toml";
  const fs::path out = kOut / "07_calibration";
  fs::remove_all(out);
  std::string log;
  ASSERT_EQ(run("calibrate " + quick.string() + " -o " + out.string() + " --set output.render=false", &log),
            0)
      << log;
  const std::string j = read_text(out / "calibration.json");
  const double tol = 0.05;
  EXPECT_NEAR(number_in(j, "achieved", "youngs_modulus_pa") / 60e9, 1.0, tol / 4);
  EXPECT_NEAR(number_in(j, "achieved", "poisson_ratio"), 0.2, tol / 4 * 0.2);
  EXPECT_NEAR(number_in(j, "achieved", "ucs_pa") / 200e6, 1.0, tol);
  EXPECT_NE(j.find("\"ratio_reached\": false"), std::string::npos);
  EXPECT_LT(number_in(j, "achieved", "ucs_over_tensile_strength"), 200.0 / 12.0);
  EXPECT_NE(read_text(out / "calibration.md").find("out of this lattice's reach"), std::string::npos);

  const fs::path rerun = kOut / "07_calibration_rerun";
  fs::remove_all(rerun);
  ASSERT_EQ(run("run " + (out / "uniaxial.toml").string() + " -o " + rerun.string(), &log), 0) << log;
  EXPECT_EQ(summary_number(read_text(rerun / "summary.json"), "peak_stress_pa"),
            number_in(j, "achieved", "ucs_pa"));

  const fs::path reach = kOut / "07_calibration_reachable";
  fs::remove_all(reach);
  ASSERT_EQ(run("calibrate " + quick.string() + " -o " + reach.string() +
                    " --set output.render=false --set calibrate.tensile_strength=21e6",
                &log),
            0)
      << log;
  const std::string r = read_text(reach / "calibration.json");
  EXPECT_NE(r.find("\"ratio_reached\": true"), std::string::npos) << r;
  EXPECT_NEAR(number_in(r, "achieved", "ucs_pa") / 200e6, 1.0, 2 * tol);
  EXPECT_NEAR(number_in(r, "achieved", "tensile_strength_pa") / 21e6, 1.0, 2 * tol);

  const fs::path three = kOut / "07_calibration_3d";
  fs::remove_all(three);
  ASSERT_EQ(run("calibrate " + quick.string() + " -o " + three.string() +
                    " --set output.render=false --set scene.dimension=3 --set calibrate.poisson_ratio=0.15"
                    " --set calibrate.specimen_width=0.01",
                &log),
            0)
      << log;
  const std::string t = read_text(three / "calibration.json");
  EXPECT_NEAR(number_in(t, "achieved", "youngs_modulus_pa") / 60e9, 1.0, tol / 4);
  EXPECT_NEAR(number_in(t, "achieved", "poisson_ratio"), 0.15, tol / 4 * 0.15);
  EXPECT_NEAR(number_in(t, "achieved", "ucs_pa") / 200e6, 1.0, tol);
}

// Every other example's quick scene runs to completion and writes its series.
// examples/08_sandbox, quick variant: a cover of 25 m disks shortened by 300 m (1.2 times
// its thickness) builds a wedge at the piston. The wedge must stand where the piston pushed
// (its toe within five thicknesses of the piston, raised by over two disk diameters), slope
// towards the foreland at a taper between 0 and the cover's angle of repose (internal
// friction 0.75-1.1 measured by biaxial tests: 37-48 degrees), and the report's critical
// taper is Dahlen's for the scene's frictions. The layer pictures are drawn by group.
TEST(Examples, SandboxQuickBuildsAWedge) {
  if (!STRATA_WITH_GMSH) GTEST_SKIP() << "the sandbox is a .geo file: needs STRATA_WITH_GMSH";
  const fs::path out = kOut / "08_sandbox";
  fs::remove_all(out);
  std::string log;
  ASSERT_EQ(run("run " + (kExamples / "08_sandbox" / "quick.toml").string() + " -o " + out.string() +
                    " --set output.render=false",
                &log),
            0)
      << log;
  const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
  ASSERT_TRUE(summary.contains("wedge")) << summary.dump(2);
  const auto& w = summary["wedge"];
  const double thickness = double(w["initial_top_m"]) - 5.0;  // the base's top is at 5 m
  EXPECT_NEAR(thickness, 250.0, 25.0);
  EXPECT_GT(double(w["max_uplift_m"]), 2 * double(w["spacing_m"])) << w.dump(2);
  EXPECT_GT(double(w["width_m"]), 0.0);
  EXPECT_LT(double(w["width_m"]), 5 * thickness);
  EXPECT_GT(double(w["taper_deg"]), 0.0);
  EXPECT_LT(double(w["taper_deg"]), 37.0);
  const auto t = strata::dem::critical_taper(0.9, 0.31);
  EXPECT_DOUBLE_EQ(double(w["critical_taper"]["taper_deg"]), t.taper_deg);
  EXPECT_FALSE(w["faults"].empty()) << w.dump(2);
  for (const auto& f : w["faults"]) {
    EXPECT_GE(double(f["dip_deg"]), 10.0);
    EXPECT_LE(double(f["dip_deg"]), 80.0);
  }
}

// examples/09_eccentric_poisson, quick variant of the study (6 mm cubes of 1 mm spheres, Type A
// offsets ra = 0.9, rc = 0.5 and 1.0, two seeds; each run a uniaxial compression measuring E and
// nu). Every run completes; measured on this build:
//  - rc = 1.0 (offsets, no bond weakened): E at 0.39 of the regular lattice's analytical E along
//    the stacking axis, nu about 0 (-0.004, 0.009); bounds: 0.1 < E/E_regular < 1, weakened 0;
//  - rc = 0.5 (bonds longer than half the longest weakened to 1e-3 of their stiffness): 54 and
//    64 % of the bonds weakened, E at 0.2-0.5 % of the regular lattice's, nu 0.19 and 0.33;
//    bounds: 30-80 % weakened, E/E_regular < 0.02, and nu above the rc = 1.0 mean by 0.1 or more:
//    the weakened network is the one that expands sideways.
TEST(Examples, EccentricPoissonStudyQuick) {
  const fs::path out = kOut / "09_eccentric_poisson";
  fs::remove_all(out);
  std::string log;
  ASSERT_EQ(run("run " + (kExamples / "09_eccentric_poisson" / "quick.toml").string() + " -o " + out.string(),
                &log),
            0)
      << log;
  for (const char* f :
       {"study.csv", "study.md", "summary.json", "runs/0001/summary.json", "runs/0004/probes.csv"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const auto t = strata::io::read_csv(out / "study.csv");
  ASSERT_EQ(t.rows(), 4u) << "rc = 0.5, 1.0 times seeds 1, 2";
  const auto &rc = t.column("Rc"), &nu = t.column("nu"), &e = t.column("E over the regular lattice's"),
             &weak = t.column("weakened bonds (fraction)"), &done = t.column("completed");
  double nu_weak = 0, nu_plain = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(done[i], 1) << "run " << i + 1;
    if (rc[i] == 1.0) {
      EXPECT_EQ(weak[i], 0.0);
      EXPECT_GT(e[i], 0.1);
      EXPECT_LT(e[i], 1.0);
      nu_plain += nu[i] / 2;
    } else {
      EXPECT_GT(weak[i], 0.3);
      EXPECT_LT(weak[i], 0.8);
      EXPECT_LT(e[i], 0.02);
      nu_weak += nu[i] / 2;
    }
  }
  EXPECT_GT(nu_weak, nu_plain + 0.1);
}

// bench/broken/uniaxial_3d.toml, the workload docs/performance.md times the broken-bond law
// on: the scene stays valid and builds the model its header describes.
TEST(Examples, BrokenBondBenchmarkSceneChecks) {
  std::string log;
  const fs::path scene = fs::path(STRATA_SOURCE_DIR) / "bench" / "broken" / "uniaxial_3d.toml";
  ASSERT_EQ(run("check " + scene.string(), &log), 0) << log;
  EXPECT_NE(log.find("particles    1986"), std::string::npos) << log;
  EXPECT_NE(log.find("bonds        10471"), std::string::npos) << log;
  EXPECT_NE(log.find("(dt/dt_crit = 0.200)"), std::string::npos) << log;
}

TEST(Examples, EveryQuickSceneRuns) {
  if (!STRATA_WITH_GMSH || !STRATA_WITH_VTK)
    GTEST_SKIP() << "the further examples are .geo files and ask for frames: needs STRATA_WITH_GMSH and "
                    "STRATA_WITH_VTK";
  int n = 0;
  for (const auto& dir : fs::directory_iterator(kExamples)) {
    const fs::path quick = dir.path() / "quick.toml";
    const auto name = dir.path().filename();
    if (!fs::exists(quick) || name == "01_uniaxial_compression" || name == "02_metamaterial_chain" ||
        name == "04_coupled_wave" || name == "06_double_hole_blast" || name == "07_calibration" ||
        name == "08_sandbox" || name == "09_eccentric_poisson")
      continue;
    const fs::path out = kOut / dir.path().filename();
    fs::remove_all(out);
    std::string log;
    EXPECT_EQ(run("run " + quick.string() + " -o " + out.string(), &log), 0) << quick << "\n" << log;
    EXPECT_TRUE(fs::exists(out / "summary.json")) << quick;
    ++n;
  }
  // Also every example with a full scene has a quick variant beside it.
  for (const auto& dir : fs::directory_iterator(kExamples))
    if (fs::exists(dir.path() / "scene.toml")) {
      EXPECT_TRUE(fs::exists(dir.path() / "quick.toml")) << dir.path();
    }
  SUCCEED() << n << " further examples ran";
}
