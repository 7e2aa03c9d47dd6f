// Scene files: parsing, defaults, paths, `--set` overrides, and the exact error messages users see.
#include <gtest/gtest.h>

#include <strata/core/error.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <strata/scene/model.hpp>
#include <strata/scene/scene.hpp>
#include "scene_fixtures.hpp"
#include "scene_test_util.hpp"

namespace fs = std::filesystem;
using strata::scene::Scene;
using strata::scene::test::error_of;

namespace {

// A small valid 2D scene. The line numbers matter: the tests below point at them
// (kPlatenGroups is lines 17 to 27).
const std::string kBase = R"toml([scene]
title = "test"
dimension = 2

[[material]]
name = "rock"
density = 2650
kn = 6.5e10
ks = 2.4e10

[[region]]
name = "specimen"
material = "rock"
diameter = 0.001
size = [0.03, 0.03]

)toml" + fixtures::kPlatenGroups +
                          R"toml(
[solver]
dt = 2e-8
steps = 1000
)toml";

/// kBase with the first occurrence of `from` replaced by `to`.
std::string edit_base(const std::string& from, const std::string& to, std::string text = kBase) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "kBase has no '" << from << "'";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// A fresh, empty folder for scene and geometry files, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            (std::string("strata_scene_") + info->test_suite_name() + "_" + info->name() + "_" +
             std::to_string(std::hash<std::string>{}(fs::current_path().string())));
    fs::remove_all(path_);
    fs::create_directories(path_);
    path_ = fs::canonical(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p;
  }

 private:
  fs::path path_;
};

const std::string kMaterialKeys =
    "name, law, density, kn, ks, friction, tensile_strength, shear_strength, friction_strengthens_bonds, "
    "youngs_modulus, poisson_ratio";
const std::string kSolverKeys =
    "dt, dt_safety, steps, duration, settle, damping, viscous_c, local_damping, gravity, contact_detection, "
    "allow_unstable, threads, min_particles_per_thread, lattice_slots, fem_integrator, eta, coupling";

}  // namespace

// ---- valid scenes ----------------------------------------------------------------------------

TEST(SceneLoad, FullSceneParsesWithDefaultsAndResolvedPaths) {
  TempDir dir;
  dir.write("geom/specimen.geo", "// gmsh geometry\n");
  const fs::path file = dir.write("case/../scene.toml", R"toml([scene]
title = "Uniaxial compression"
dimension = 2

[[material]]
name = "rock"
density = 2.65e3
kn = 6.587e10
ks = 2.371e10
friction = 0.239
tensile_strength = 1.252e4
shear_strength = 3.690e4

[[material]]
name = "soft"
density = 2000
kn = 1e9
ks = 0

[[region]]
name = "specimen"
material = "rock"
diameter = 0.001
size = [0.030, 0.0304]

[[region]]
name = "far_field"
kind = "fem"
material = "soft"
shape = "file"
file = "geom/specimen.geo"

[[group]]
name = "top"
region = "specimen"
select = "top_row"

[[group]]
name = "bottom"
select = "bottom_row"

[[boundary]]
group = "top"
type = "step_displacement"
axes = ["y"]
increment = [0.0, -1.9e-9]
every = 400

[[load]]
group = "top"
times = [0, 1e-5, 2.5e-5]
forces = [[0, 0], [0, -1.07e5], [0, 0]]
per = "group"

[[wall]]
name = "platen"
point = [0, 0.0304]
normal = [0, -1]

[solver]
dt = 2e-8
steps = 3.2e7
damping = "viscous"
viscous_c = 1.16e3

[output]
directory = "results"
fields = ["displacement", "damage"]

[probe]
stress_strain = true
)toml");
  const Scene s = strata::scene::load(file);
  EXPECT_EQ(s.file, file);
  EXPECT_EQ(s.dir, file.parent_path().lexically_normal());

  const auto& scene = s.scene;
  EXPECT_EQ(scene.title.value, "Uniaxial compression");
  EXPECT_EQ(scene.dimension.value, 2);
  EXPECT_EQ(scene.thickness.value, 1.0);  // default
  EXPECT_FALSE(scene.thickness.given);
  EXPECT_EQ(scene.seed.value, 1);

  ASSERT_EQ(s.materials.size(), 2u);
  const auto& rock = s.materials[0];
  EXPECT_EQ(rock.pos.str(), file.string() + ":5:1");  // the table header
  EXPECT_EQ(rock.law.value, "solid_lattice");
  EXPECT_EQ(rock.density.value, 2650.0);
  EXPECT_EQ(rock.kn.value, 6.587e10);
  EXPECT_EQ(rock.friction.value, 0.239);
  EXPECT_EQ(rock.tensile_strength.value, 1.252e4);
  EXPECT_TRUE(rock.friction_strengthens_bonds.value);
  const auto& soft = s.materials[1];
  EXPECT_EQ(soft.ks.value, 0.0);  // an integer where a real is expected
  EXPECT_EQ(soft.tensile_strength.value, std::numeric_limits<double>::infinity());  // default: never breaks
  EXPECT_EQ(soft.friction.value, 0.0);

  ASSERT_EQ(s.regions.size(), 2u);
  const auto& specimen = s.regions[0];
  EXPECT_EQ(to_string(specimen.kind), "particles");
  EXPECT_EQ(specimen.lattice.value, "auto");
  EXPECT_EQ(to_string(specimen.shape), "box");
  EXPECT_EQ(specimen.size.value, (std::vector<double>{0.030, 0.0304}));
  EXPECT_EQ(specimen.origin.value, (std::vector<double>{0.0, 0.0}));  // 3D default cut to 2D
  EXPECT_FALSE(specimen.origin.given);
  EXPECT_EQ(specimen.origin.pos.str(), file.string() + ":20:1");  // defaulted: the table header
  EXPECT_EQ(specimen.size.pos.str(), file.string() + ":24:8");
  EXPECT_FALSE(specimen.radius.given);
  EXPECT_EQ(specimen.orientation.value, 0.0);
  const auto& far = s.regions[1];
  EXPECT_EQ(far.file.value, dir.path() / "geom" / "specimen.geo");  // relative to the scene file
  EXPECT_FALSE(far.diameter.given);                                 // not needed by kind = "fem"
  EXPECT_EQ(far.mesh_size.value, 0.0);

  const auto& top = s.groups[0];
  EXPECT_EQ(top.region.value, "specimen");
  EXPECT_EQ(s.groups[1].region.value, "");  // all regions

  const auto& platen = s.boundaries[0];
  EXPECT_EQ(platen.axes.value, (std::vector<std::string>{"y"}));
  EXPECT_EQ(platen.increment.value, (std::vector<double>{0.0, -1.9e-9}));
  EXPECT_EQ(platen.every.value, 400);

  const auto& pulse = s.loads[0];
  EXPECT_EQ(pulse.type.value, strata::scene::LoadType::ForceHistory);
  EXPECT_EQ(pulse.times.value, (std::vector<double>{0.0, 1e-5, 2.5e-5}));
  EXPECT_EQ(pulse.forces.value[1], (std::vector<double>{0.0, -1.07e5}));
  EXPECT_EQ(to_string(pulse.per), "group");

  ASSERT_EQ(s.walls.size(), 1u);
  EXPECT_EQ(s.walls[0].velocity.value, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(s.walls[0].stiffness.value, 0.0);

  const auto& solver = s.solver;
  EXPECT_EQ(solver.dt.value, 2e-8);
  EXPECT_EQ(solver.steps.value, 32000000);  // 3.2e7: a real with no fraction is a fine count
  EXPECT_EQ(solver.dt_safety.value, 0.2);
  EXPECT_EQ(to_string(solver.damping), "viscous");
  EXPECT_EQ(solver.local_damping.value, 0.7);
  EXPECT_EQ(solver.gravity.value, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(to_string(solver.contact_detection), "auto");
  EXPECT_FALSE(solver.allow_unstable.value);
  EXPECT_EQ(solver.threads.value, 0);

  const auto& output = s.output;
  EXPECT_EQ(output.directory.value, dir.path() / "results");
  EXPECT_EQ(output.frames.value, 20);
  EXPECT_EQ(output.fields.value, (std::vector<std::string>{"displacement", "damage"}));
  EXPECT_EQ(output.render_field.value, "damage");
  EXPECT_TRUE(output.movie.value);

  const auto& probe = s.probe;
  EXPECT_TRUE(probe.stress_strain.value);
  EXPECT_EQ(probe.top_group.value, "top");
  EXPECT_EQ(probe.axis.value, "y");
}

TEST(SceneLoad, AbsentPlainTablesHoldTheirDefaults) {
  const Scene s = strata::scene::parse(kBase, "scene.toml");
  const auto& output = s.output;
  EXPECT_FALSE(output.directory.given);
  EXPECT_EQ(output.directory.value, (fs::current_path() / "out").lexically_normal());
  EXPECT_EQ(output.fields.value, (std::vector<std::string>{"id", "radius", "displacement", "velocity",
                                                           "force", "group", "damage"}));
  EXPECT_EQ(output.pos.str(), "scene.toml:1:1");
  EXPECT_EQ(s.boundaries[0].axes.value, (std::vector<std::string>{"x", "y"}));
  EXPECT_FALSE(s.probe.stress_strain.value);
}

TEST(SceneLoad, ChoicesAreEnumsAndValuesFailAtTheirPositions) {
  namespace sc = strata::scene;
  const Scene s = sc::parse(kBase, "scene.toml", {"solver.damping=local"});
  EXPECT_EQ(s.solver.damping, sc::SolverDamping::Local);
  EXPECT_EQ(s.regions[0].kind, sc::RegionKind::Particles);
  EXPECT_EQ(s.regions[0].shape, sc::RegionShape::Box);
  EXPECT_EQ(s.solver.contact_detection, sc::ContactDetection::Auto);
  EXPECT_EQ(sc::to_string(sc::GroupSelect::HoleRim), "hole_rim");
  EXPECT_FALSE(s.coupled.has_value());
  EXPECT_FALSE(s.regions[0].radius.given);  // no default, not written
  // A value fails at the position it was written; a defaulted one at its table's header.
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const strata::Error& e) {
      EXPECT_EQ(e.kind(), strata::ErrorKind::Input);
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([&] { s.solver.steps.fail("too many"); }), "scene.toml:31:9: too many");
  EXPECT_EQ(message([&] { s.solver.dt_safety.fail("too safe"); }), "scene.toml:29:1: too safe");
  EXPECT_EQ(message([&] { s.solver.damping.fail("too damped"); }), "--set solver.damping=local: too damped");
}

TEST(SceneLoad, ThreeDimensionalDefaultsKeepThreeComponents) {
  std::string text = edit_base("dimension = 2", "dimension = 3");
  text = edit_base("size = [0.03, 0.03]", "size = [0.03, 0.03, 0.03]", text);
  const Scene s = strata::scene::parse(text, "scene.toml");
  EXPECT_EQ(s.regions[0].origin.value, (std::vector<double>{0.0, 0.0, 0.0}));
  EXPECT_EQ(s.boundaries[0].axes.value, (std::vector<std::string>{"x", "y", "z"}));
}

TEST(SceneLoad, MissingSceneFileIsAnInputError) {
  TempDir dir;
  const fs::path file = dir.path() / "nothing.toml";
  try {
    strata::scene::load(file);
    FAIL() << "no error";
  } catch (const strata::Error& e) {
    EXPECT_EQ(e.kind(), strata::ErrorKind::Input);
    EXPECT_EQ(std::string(e.what()),
              file.string() + ": cannot read the scene file (looked for " + file.string() + ")");
  }
}

// ---- the four acceptance errors --------------------------------------------------------------

TEST(SceneErrors, FourAcceptanceErrorsHaveExactPositionsAndDifferentMessages) {
  TempDir dir;
  const fs::path file = dir.path() / "scene.toml";

  const std::string misspelt = error_of(edit_base("kn = 6.5e10", "kn_typo = 6.5e10"));
  EXPECT_EQ(misspelt, "scene.toml:8:1: unknown key 'kn_typo' in [[material]]; did you mean 'kn'? (allowed: " +
                          kMaterialKeys + ")");

  const std::string negative = error_of(edit_base("kn = 6.5e10", "kn = -5"));
  EXPECT_EQ(negative, "scene.toml:8:6: kn = -5 must be > 0 (N/m)");

  const std::string wrong_type = error_of(edit_base("dt = 2e-8", "dt = \"fast\""));
  EXPECT_EQ(wrong_type, "scene.toml:30:6: dt must be a real number (s), got a string \"fast\"");

  const std::string missing_file =
      error_of(edit_base("size = [0.03, 0.03]", "shape = \"file\"\nfile = \"geom/specimen.geo\""), {}, file);
  EXPECT_EQ(missing_file, file.string() + ":16:8: file 'geom/specimen.geo' not found (looked for " +
                              (dir.path() / "geom" / "specimen.geo").string() +
                              "; paths are relative to the scene file)");

  const std::set<std::string> distinct = {misspelt, negative, wrong_type, missing_file};
  EXPECT_EQ(distinct.size(), 4u);
}

// ---- other errors ----------------------------------------------------------------------------

TEST(SceneErrors, UnknownTableSuggestsTheClosest) {
  EXPECT_EQ(error_of(edit_base("[solver]", "[solvr]")),
            "scene.toml:29:1: unknown table [solvr]; did you mean [solver]? (allowed: [scene], [[material]], "
            "[[region]], [[group]], [[boundary]], [[load]], [[wall]], [solver], [output], [probe], "
            "[network], [coupled], [calibrate], [study], [[vary]], [[measure]])");
  EXPECT_EQ(
      error_of(edit_base("[[group]]", "[[groups]]")),
      "scene.toml:17:1: unknown table [[groups]]; did you mean [[group]]? (allowed: [scene], [[material]], "
      "[[region]], [[group]], [[boundary]], [[load]], [[wall]], [solver], [output], [probe], [network], "
      "[coupled], "
      "[calibrate], [study], [[vary]], [[measure]])");
}

TEST(SceneErrors, TableWrittenWithTheWrongBrackets) {
  EXPECT_EQ(error_of(edit_base("[[region]]", "[region]")),
            "scene.toml:11:1: [region] must be written [[region]]: it is a list of tables, one per region");
  EXPECT_EQ(error_of(edit_base("[solver]", "[[solver]]")),
            "scene.toml:29:1: [[solver]] must be written [solver]: there is one [solver] table");
}

TEST(SceneErrors, KeyOutsideAnyTable) {
  EXPECT_EQ(error_of("seed = 3\n" + kBase),
            "scene.toml:1:1: key 'seed' is outside any table; it belongs in [scene]");
}

TEST(SceneErrors, UnknownKeyWithoutACloseMatchListsTheAllowedKeys) {
  EXPECT_EQ(error_of(edit_base("steps = 1000", "steps = 1000\ncolour = 1")),
            "scene.toml:32:1: unknown key 'colour' in [solver] (allowed: " + kSolverKeys + ")");
  EXPECT_EQ(error_of(edit_base("steps = 1000", "steps = 1000\nseed = 1")),
            "scene.toml:32:1: unknown key 'seed' in [solver]; 'seed' is a key of [scene] (allowed: " +
                kSolverKeys + ")");
}

TEST(SceneErrors, BadChoiceSuggestsTheClosest) {
  EXPECT_EQ(
      error_of(edit_base("steps = 1000", "steps = 1000\ndamping = \"visous\"")),
      "scene.toml:32:11: damping = \"visous\" must be one of none, viscous, local; did you mean 'viscous'?");
  EXPECT_EQ(error_of(edit_base("steps = 1000", "steps = 1000\ndamping = \"heavy\"")),
            "scene.toml:32:11: damping = \"heavy\" must be one of none, viscous, local");
}

TEST(SceneErrors, MissingRequiredKeyPointsAtTheTableHeader) {
  EXPECT_EQ(
      error_of(edit_base("material = \"rock\"\n", "")),
      "scene.toml:11:1: [[region]] 'specimen' is missing required key 'material' (the [[material]] that "
      "fills the region, by name)");
  EXPECT_EQ(
      error_of(edit_base("type = \"fixed\"\n", "")),
      "scene.toml:25:1: [[boundary]] at index 0 is missing required key 'type' (fixed: held in place; "
      "velocity: moved at `velocity`; step_displacement: moved by `increment` every `every` steps (Li et al. "
      "2017 move their platens 1.9e-9 m every 400 steps))");
  EXPECT_EQ(
      error_of(edit_base("dimension = 2\n", "")),
      "scene.toml:1:1: [scene] is missing required key 'dimension' (2 for a plane model of disks (hexagonal "
      "lattice), 3 for a model of spheres (close-packed lattice))");
}

TEST(SceneErrors, MissingRequiredTable) {
  EXPECT_EQ(error_of(kBase.substr(0, kBase.find("[[material]]")) + kBase.substr(kBase.find("[[region]]"))),
            "scene.toml:1:1: missing required table [[material]] (a bonded-particle material: density, bond "
            "stiffnesses and bond strengths of the solid-lattice law (Liu, Pollard & Shi 2013))");
  EXPECT_EQ(error_of(""),
            "scene.toml:1:1: missing required table [scene] (what the model is: a title, 2D or 3D, "
            "and the random seed)");
  // A missing table has no position of its own: a problem at a real position is reported first.
  EXPECT_EQ(error_of("[scene]\ndimension = \"two\"\n"),
            "scene.toml:2:13: dimension must be an integer, got a string \"two\"");
}

TEST(SceneErrors, TomlSyntaxErrorKeepsLineAndColumn) {
  EXPECT_EQ(error_of(edit_base("kn = 6.5e10", "kn = 6.5e10 N/m")),
            "scene.toml:8:13: TOML syntax error: Error while parsing key-value pair: expected a comment or "
            "whitespace, saw 'N'");
}

TEST(SceneErrors, IntegersAndInfinity) {
  EXPECT_EQ(error_of(edit_base("steps = 1000", "steps = 1.5")),
            "scene.toml:31:9: steps must be an integer, got a real number 1.5");
  EXPECT_EQ(error_of(edit_base("steps = 1000", "steps = -1")), "scene.toml:31:9: steps = -1 must be >= 0");
  EXPECT_EQ(error_of(edit_base("dimension = 2", "dimension = 4")),
            "scene.toml:3:13: dimension = 4 must be 2 or 3");
  EXPECT_EQ(error_of(edit_base("steps = 1000", "steps = 1000\ndt_safety = 1.5")),
            "scene.toml:32:13: dt_safety = 1.5 must be > 0 and <= 1");
  EXPECT_EQ(error_of(edit_base("ks = 2.4e10", "ks = inf")), "scene.toml:9:6: ks = inf must be finite (N/m)");
  EXPECT_EQ(error_of(edit_base("ks = 2.4e10", "ks = nan")),
            "scene.toml:9:6: ks = nan must be a number (N/m)");
  const Scene s =
      strata::scene::parse(edit_base("ks = 2.4e10", "ks = 2.4e10\nshear_strength = inf"), "scene.toml");
  EXPECT_TRUE(std::isinf(s.materials[0].shear_strength.value));
  EXPECT_TRUE(s.materials[0].shear_strength.given);
}

TEST(SceneErrors, WrongTypesInLists) {
  EXPECT_EQ(error_of(edit_base("size = [0.03, 0.03]", "size = 0.03")),
            "scene.toml:15:8: size must be a list of real numbers (m), got a real number 0.03");
  EXPECT_EQ(error_of(edit_base("size = [0.03, 0.03]", "size = [0.03, \"a\"]")),
            "scene.toml:15:15: size[1] must be a real number (m), got a string \"a\"");
  EXPECT_EQ(error_of(edit_base("size = [0.03, 0.03]", "size = [0.03, -0.03]")),
            "scene.toml:15:15: size[1] = -0.03 must be > 0 (m)");
}

TEST(SceneErrors, ListLengthMustMatchTheDimension) {
  EXPECT_EQ(error_of(edit_base("size = [0.03, 0.03]", "size = [0.03, 0.03, 0.03]")),
            "scene.toml:15:8: size has 3 components, but the scene is 2D: give one per axis (x, y)");
  EXPECT_EQ(error_of(edit_base("type = \"fixed\"", "type = \"fixed\"\naxes = [\"x\", \"z\"]")),
            "scene.toml:28:14: axes: 'z' is not an axis of a 2D scene (allowed: x, y)");
  EXPECT_EQ(error_of(edit_base("dimension = 2", "dimension = 3")),
            "scene.toml:15:8: size has 2 components, but the scene is 3D: give one per axis (x, y, z)");
  EXPECT_EQ(error_of(kBase, {"probe.axis=z"}),
            "--set probe.axis=z: axis = \"z\" is not an axis of a 2D scene (allowed: x, y)");
  EXPECT_EQ(error_of(kBase + "[[load]]\ngroup = \"top\"\ntimes = []\nforces = []\n"),
            "scene.toml:34:9: times must have at least 1 entry, got 0");
  EXPECT_EQ(error_of(kBase + "[[load]]\ngroup = \"top\"\ntimes = [0, 1]\nforces = [[0, 1], [0, 1, 2]]\n"),
            "scene.toml:35:19: forces[1] has 3 components, but the scene is 2D: give one per axis (x, y)");
}

TEST(SceneErrors, CrossReferences) {
  EXPECT_EQ(
      error_of(edit_base("material = \"rock\"", "material = \"rok\"")),
      "scene.toml:13:12: material = \"rok\" names no [[material]]; did you mean 'rock'? (defined: rock)");
  EXPECT_EQ(
      error_of(edit_base("group = \"bottom\"", "group = \"botom\"")),
      "scene.toml:26:9: group = \"botom\" names no [[group]] or [[region]]; did you mean 'bottom'? (defined: "
      "top, bottom, specimen)");
  EXPECT_NO_THROW(
      strata::scene::parse(edit_base("group = \"bottom\"", "group = \"specimen\""), "scene.toml"));
  EXPECT_EQ(
      error_of(edit_base("name = \"top\"", "name = \"specimen\"")),
      "scene.toml:18:8: [[group]] name 'specimen' is already a [[region]] name (every region is also a group "
      "of its own name)");
  EXPECT_EQ(error_of(edit_base("select = \"top_row\"", "select = \"top_row\"\nregion = \"sample\"")),
            "scene.toml:20:10: region = \"sample\" names no [[region]] (defined: specimen)");
  EXPECT_EQ(error_of(edit_base("name = \"bottom\"", "name = \"top\"")),
            "scene.toml:22:8: [[group]] name 'top' is used twice (first at scene.toml:18:8)");
  EXPECT_EQ(
      error_of(kBase + "\n[probe]\nstress_strain = true\ntop_group = \"upper\"\n"),
      "scene.toml:35:13: top_group = \"upper\" names no [[group]] or [[region]], which stress_strain = true "
      "needs (defined: top, bottom, specimen)");
}

TEST(SceneErrors, ShapeAndTypeDependentKeys) {
  EXPECT_EQ(
      error_of(edit_base("size = [0.03, 0.03]\n", "")),
      "scene.toml:11:1: [[region]] 'specimen' needs 'size' for shape = \"box\" (extent of a box along each "
      "axis)");
  EXPECT_EQ(error_of(edit_base("size = [0.03, 0.03]", "shape = \"disk\"\ncenter = [0, 0]")),
            "scene.toml:15:9: [[region]] 'specimen' needs 'radius' for shape = \"disk\" (radius of a disk, "
            "sphere or cylinder)");
  EXPECT_EQ(
      error_of(edit_base("diameter = 0.001\n", "")),
      "scene.toml:11:1: [[region]] 'specimen' needs 'diameter' for kind = \"particles\" (particle diameter "
      "d)");
  EXPECT_EQ(
      error_of(edit_base("type = \"fixed\"", "type = \"velocity\"")),
      "scene.toml:27:8: [[boundary]] at index 0 needs 'velocity' for type = \"velocity\" (velocity, one "
      "component per axis)");
  EXPECT_EQ(error_of(edit_base("size = [0.03, 0.03]", "size = [0.03, 0.03]\nlattice = \"hcp\"")),
            "scene.toml:16:11: lattice = \"hcp\" is for 3D scenes; in 2D use hex (or auto)");
  EXPECT_EQ(error_of(kBase + "[[wall]]\nname = \"w\"\npoint = [0, 0]\nnormal = [0, 0]\n"),
            "scene.toml:35:10: normal must not be zero: give the direction pointing into the particles");
  EXPECT_EQ(error_of(edit_base("steps = 1000\n", "")),
            "scene.toml:29:1: the run has no length: set solver.steps or solver.duration (both are 0)");
  EXPECT_EQ(
      error_of(kBase +
               "[[load]]\ngroup = \"top\"\ntimes = [0, 2e-5, 1e-5]\nforces = [[0, 1], [0, 2], [0, 3]]\n"),
      "scene.toml:34:9: times must increase: times[2] = 1e-05 is not after times[1] = 2e-05");
  // radial loads: magnitudes, not forces; one per time; no axis in 2D
  const std::string radial = kBase + "[[load]]\ngroup = \"top\"\ntype = \"radial\"\ntimes = [0, 1e-5]\n";
  EXPECT_EQ(
      error_of(radial),
      "scene.toml:34:8: [[load]] at index 0 needs 'magnitudes' for type = \"radial\" (one magnitude per "
      "time, positive away from `center`)");
  EXPECT_EQ(error_of(radial + "magnitudes = [0, 1, 2]\n"),
            "scene.toml:36:14: magnitudes has 3 entries but times has 2: give one magnitude per time");
  EXPECT_EQ(error_of(radial + "magnitudes = [0, 1]\naxis = [0, 1]\n"),
            "scene.toml:37:8: axis is for 3D scenes: in 2D the radial load lies in the plane");
  EXPECT_EQ(error_of(radial + "magnitudes = [0, 1]\nforces = [[0, 1], [0, 1]]\n"),
            "scene.toml:37:10: forces is for type = \"force_history\"; a radial load gives `magnitudes`");
  EXPECT_EQ(error_of(kBase + "[[load]]\ngroup = \"top\"\ntimes = [0]\nforces = [[0, 1]]\ncenter = [0, 0]\n"),
            "scene.toml:36:10: center is for type = \"radial\"; a force_history load gives its force "
            "vectors in `forces`");
}

// ---- overrides -------------------------------------------------------------------------------

TEST(SceneOverrides, AppliedBeforeValidationAndRemembered) {
  const Scene s =
      strata::scene::parse(kBase, "scene.toml", {"solver.dt=1e-9", "output.render_field=velocity"});
  EXPECT_EQ(s.solver.dt.value, 1e-9);
  EXPECT_TRUE(s.solver.dt.given);
  EXPECT_EQ(s.solver.dt.pos.str(), "--set solver.dt=1e-9");
  EXPECT_EQ(s.solver.steps.value, 1000);               // the rest of the file is untouched
  EXPECT_EQ(s.output.render_field.value, "velocity");  // a bare word is read as a string
}

TEST(SceneOverrides, ErrorsPointAtTheOverride) {
  EXPECT_EQ(error_of(kBase, {"solver.dt=-1"}), "--set solver.dt=-1: dt = -1 must be >= 0 (s)");
  EXPECT_EQ(
      error_of(kBase, {"solver.dtt=1"}),
      "--set solver.dtt=1: unknown key 'dtt' in [solver]; did you mean 'dt'? (allowed: " + kSolverKeys + ")");
  EXPECT_EQ(
      error_of(kBase, {"solvr.dt=1"}),
      "--set solvr.dt=1: unknown table [solvr]; did you mean [solver]? (allowed: [scene], [[material]], "
      "[[region]], [[group]], [[boundary]], [[load]], [[wall]], [solver], [output], [probe], [network], "
      "[coupled], "
      "[calibrate], [study], [[vary]], [[measure]])");
  EXPECT_EQ(
      error_of(kBase, {"output.render_field=dmage"}),
      "--set output.render_field=dmage: render_field = \"dmage\" must be one of displacement, velocity, "
      "damage, group, shear_strain; did you mean 'damage'?");
  EXPECT_EQ(error_of(kBase, {"solver.dt"}),
            "--set solver.dt: expected key=value, e.g. solver.dt=1e-8 or "
            "material.rock.kn=1e9");
  // Overrides are checked before the file: their problems come first.
  EXPECT_EQ(error_of(edit_base("kn = 6.5e10", "kn = -5"), {"solver.steps=0.5"}),
            "--set solver.steps=0.5: steps must be an integer, got a real number 0.5");
}

TEST(SceneOverrides, CreateKeysAndTables) {
  // A key the file did not write, inside a written table.
  Scene s = strata::scene::parse(kBase, "scene.toml", {"solver.damping=local"});
  EXPECT_EQ(to_string(s.solver.damping), "local");
  EXPECT_EQ(s.solver.damping.pos.str(), "--set solver.damping=local");
  // A whole table the file did not write.
  s = strata::scene::parse(kBase, "scene.toml", {"output.frames=5", "probe.stress_strain=true"});
  EXPECT_EQ(s.output.frames.value, 5);
  EXPECT_TRUE(s.probe.stress_strain.value);
  EXPECT_EQ(s.probe.pos.str(), "--set probe.stress_strain=true");
  // A created table is checked like the file: here the default top_group does not exist.
  EXPECT_EQ(error_of(edit_base("name = \"top\"", "name = \"upper\""), {"probe.stress_strain=true"}),
            "--set probe.stress_strain=true: top_group = \"top\" names no [[group]] or [[region]], which "
            "stress_strain = true needs (defined: upper, bottom, specimen)");
}

TEST(SceneOverrides, ArrayEntriesByNameAndByIndex) {
  const Scene s = strata::scene::parse(kBase, "scene.toml",
                                       {"material.rock.kn=1e9", "region[0].diameter=0.002",
                                        "scene.title=\"x y\"", "boundary[0].axes=[\"y\"]"});
  EXPECT_EQ(s.materials[0].kn.value, 1e9);
  EXPECT_EQ(s.materials[0].kn.pos.str(), "--set material.rock.kn=1e9");
  EXPECT_EQ(s.regions[0].diameter.value, 0.002);
  EXPECT_EQ(s.scene.title.value, "x y");
  EXPECT_EQ(s.boundaries[0].axes.value, (std::vector<std::string>{"y"}));

  EXPECT_EQ(error_of(kBase, {"material.granit.kn=1"}),
            "--set material.granit.kn=1: no [[material]] named "
            "'granit' (names: rock)");
  EXPECT_EQ(error_of(kBase, {"material.rok.kn=1"}),
            "--set material.rok.kn=1: no [[material]] named 'rok'; did you mean 'rock'? (names: rock)");
  EXPECT_EQ(
      error_of(kBase, {"region[1].diameter=1"}),
      "--set region[1].diameter=1: index 1 is out of range: the scene has 1 [[region]] entry (index 0 to 0)");
  EXPECT_EQ(error_of(kBase, {"material.kn=1"}),
            "--set material.kn=1: address one [[material]] entry: write material.<name>.<key> or "
            "material[<index>].<key>");
  EXPECT_EQ(
      error_of(kBase, {"boundary.bottom.type=velocity"}),
      "--set boundary.bottom.type=velocity: address one [[boundary]] entry: write boundary[<index>].<key>");
  EXPECT_EQ(error_of(kBase, {"material[0].kn=-1"}), "--set material[0].kn=-1: kn = -1 must be > 0 (N/m)");
  EXPECT_EQ(
      error_of(kBase, {"material.rock.kn_typo=1"}),
      "--set material.rock.kn_typo=1: unknown key 'kn_typo' in [[material]]; did you mean 'kn'? (allowed: " +
          kMaterialKeys + ")");
}

// ---- the schema and its reference ------------------------------------------------------------

TEST(SceneSchema, EveryKeyIsDocumentedAndEveryDefaultIsValid) {
  for (const auto& t : strata::scene::schema()) {
    EXPECT_FALSE(t.doc.empty()) << t.name;
    for (const auto& k : t.keys) {
      EXPECT_FALSE(k.doc.empty()) << t.name << "." << k.name;
      EXPECT_FALSE(k.required && !k.default_value.empty()) << t.name << "." << k.name;
    }
  }
  // Every default converts and passes its own checks: kBase (which leaves most keys out) parses in 2D and 3D.
  std::string text3 = edit_base("dimension = 2", "dimension = 3");
  text3 = edit_base("size = [0.03, 0.03]", "size = [0.03, 0.03, 0.03]", text3);
  EXPECT_NO_THROW(strata::scene::parse(text3, "scene.toml"));
}

TEST(SceneSchema, ReferenceDocIsInSyncWithTheSchema) {
  // On a mismatch the fresh page is also written to the build folder, so it can be copied over.
  const fs::path doc = fs::path(STRATA_SOURCE_DIR) / "docs" / "scene-reference.md";
  const fs::path fresh = fs::path(STRATA_BINARY_DIR) / "scene-reference.md";
  const std::string how =
      "Regenerate it from the source folder with\n  strata reference -o docs/scene-reference.md\n"
      "or copy " +
      fresh.string() + " (written by this test) to docs/scene-reference.md";
  std::stringstream committed;
  if (std::ifstream in(doc); in) committed << in.rdbuf();
  const std::string generated = strata::scene::reference_markdown();
  if (committed.str() != generated) std::ofstream(fresh) << generated;
  EXPECT_TRUE(committed.str() == generated)
      << doc.string()
      << " is missing or differs from the schema (the key declarations in scene/src/tables/). " << how;
}

// ---- boundary conditions ---------------------------------------------------------------------

// A step_displacement boundary prescribes every axis it names, zero increment or not: platens
// that name x and y hold the top row sideways (rough platens), while naming y alone leaves x
// free (frictionless platens), where the block's Poisson expansion moves the row's ends out.
TEST(SceneBoundaries, AxesNamedWithAZeroIncrementAreHeld) {
  auto largest_lateral_displacement = [](const std::string& axes) {
    const std::string text =
        edit_base("[solver]", "[[boundary]]\ngroup = \"top\"\ntype = \"step_displacement\"\naxes = " + axes +
                                  "\nincrement = [0.0, -2e-8]\nevery = 1\n\n[solver]");
    const Scene sc = strata::scene::parse(text, "scene.toml", {});
    strata::scene::BuiltModel m = strata::scene::build_model(sc, false);
    m.advance(1000);
    const auto u = m.sim().displacements();
    const auto ids = m.sim().ids();
    std::vector<std::size_t> where(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) where[ids[i]] = i;
    double largest = 0;
    for (const auto id : m.sim().group_members("top")) largest = std::max(largest, std::abs(u[where[id]][0]));
    return largest;
  };
  EXPECT_EQ(largest_lateral_displacement(R"(["x", "y"])"), 0.0);
  // Frictionless: 2e-5 m of shortening of the 30 mm block (strain 6.7e-4, ν ≈ 0.19) widens
  // it by about 0.19 × 6.7e-4 × 30 mm = 3.8e-6 m, 1.9e-6 m at each end of an unconstrained
  // row; with the bottom row held, the top row's ends move 1.1e-6 m after these 1000 steps
  // (about 4 wave transits). The bar is a fifth of that.
  EXPECT_GT(largest_lateral_displacement(R"(["y"])"), 2e-7);
}

// Platens that move by a step every 400 steps (the loading of Li, Yin, Liu & Cai 2017) run on:
// the health check compares kinetic and stored energy in the leapfrog's product form, and
// the platens' own kinetic energy is left out in that form too (in the form ½m·v² it made
// the sum negative at the first step and stopped the run as a blow-up).
TEST(SceneBoundaries, PlatensSteppingEveryFewStepsAreNoBlowUp) {
  const std::string text =
      edit_base("[solver]",
                "[[boundary]]\ngroup = \"top\"\ntype = \"step_displacement\"\naxes = [\"y\"]\n"
                "increment = [0.0, -1.9e-9]\nevery = 400\n\n[solver]");
  const Scene sc = strata::scene::parse(text, "scene.toml", {});
  strata::scene::BuiltModel m = strata::scene::build_model(sc, false);
  EXPECT_NO_THROW(m.advance(1000));
  EXPECT_EQ(m.step_count(), 1000);
  // Two steps of the top row, 3.8e-9 m in all: the block is strained, and stores energy.
  EXPECT_GT(m.sim().bond_energy(), 0.0);
}

// ---- loads -----------------------------------------------------------------------------------

// A radial load shared by a group (per = "group"): at the first step the lattice is at rest
// and unstrained, so each particle's velocity is its applied force times dt/m: every force
// points away from the centre (by default the group's mean position), and their magnitudes
// add up to the load's magnitude, as the blast load on the rim of a hole is shared.
TEST(SceneLoads, RadialLoadSharedByAGroupPushesAwayFromTheCentre) {
  for (const std::string center : {"", "center = [0.0151, 0.0148]\n"}) {
    const std::string text =
        edit_base("[solver]",
                  "[[group]]\nname = \"rim\"\nselect = \"box\"\nbox_min = [0.012, 0.012]\n"
                  "box_max = [0.018, 0.018]\n\n[[load]]\ngroup = \"rim\"\ntype = \"radial\"\n"
                  "times = [0, 1]\nmagnitudes = [2e5, 2e5]\nper = \"group\"\n" +
                      center + "\n[solver]");
    const Scene sc = strata::scene::parse(text, "scene.toml", {});
    strata::scene::BuiltModel m = strata::scene::build_model(sc, false);
    const auto& sim = m.sim();
    const auto members = sim.group_members("rim");
    ASSERT_GT(members.size(), 20u);
    const auto x0 = sim.positions();
    const auto ids = sim.ids();
    std::vector<std::size_t> where(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) where[ids[i]] = i;
    std::array<double, 2> c{0.0151, 0.0148};
    if (center.empty()) {
      c = {0, 0};
      for (auto id : members)
        for (int a = 0; a < 2; ++a) c[a] += x0[where[id]][a] / double(members.size());
    }
    m.advance(1);
    const auto v = m.sim().velocities();
    const double mass = 2650 * std::sqrt(3.0) / 2 * 1e-6;  // ρ·(√3/2)·d²
    double total = 0;
    std::size_t at_centre = 0;
    for (auto id : members) {
      const std::size_t i = where[id];
      const double rx = x0[i][0] - c[0], ry = x0[i][1] - c[1], r = std::hypot(rx, ry);
      const double fx = v[i][0] * mass / m.dt, fy = v[i][1] * mass / m.dt;
      const double f = std::hypot(fx, fy);
      total += f;
      if (r < 1e-12) {  // a particle at the centre has no direction, and no force
        ++at_centre;
        EXPECT_EQ(f, 0.0);
        continue;
      }
      EXPECT_NEAR(fx * ry - fy * rx, 0.0, 1e-9 * f * r) << "force along the radius, particle " << id;
      EXPECT_GT(fx * rx + fy * ry, 0.0) << "outward, particle " << id;
    }
    const double n = double(members.size());
    EXPECT_NEAR(total, 2e5 * (n - double(at_centre)) / n, 1e-9 * 2e5);
  }
}

// ---- a spread of bond strengths ----------------------------------------------------------------

// The strength factors have mean 1 and the coefficient of variation asked for (20,000
// draws: the sample mean within 1 %, the sample CoV within 3 % of its value), are all
// positive, and are the same for the same seed and different for another.
TEST(SceneRegions, StrengthFactorsHaveTheirMeanAndSpreadAndFollowTheSeed) {
  using strata::scene::StrengthSpread;
  for (const auto spread : {StrengthSpread::Normal, StrengthSpread::Weibull})
    for (const double cov : {0.1, 0.3}) {
      const auto f = strata::scene::strength_factors(spread, cov, 20000, 42);
      double sum = 0, sum2 = 0, lowest = 1;
      for (double x : f) sum += x, sum2 += x * x, lowest = std::min(lowest, x);
      const double mean = sum / double(f.size());
      const double sd = std::sqrt(sum2 / double(f.size()) - mean * mean);
      EXPECT_NEAR(mean, 1.0, 0.01) << to_string(spread) << " " << cov;
      EXPECT_NEAR(sd / mean / cov, 1.0, 0.03) << to_string(spread) << " " << cov;
      EXPECT_GT(lowest, 0.0);
      EXPECT_EQ(f, strata::scene::strength_factors(spread, cov, 20000, 42));
      EXPECT_NE(f, strata::scene::strength_factors(spread, cov, 20000, 43));
    }
  EXPECT_EQ(strata::scene::strength_factors(StrengthSpread::None, 0.2, 3, 1), std::vector<double>(3, 1.0));
  EXPECT_EQ(error_of(edit_base("size = [0.03, 0.03]", "size = [0.03, 0.03]\nstrength_spread = \"weibull\"")),
            "scene.toml:16:19: strength_spread = \"weibull\" needs strength_cov > 0 (the coefficient of "
            "variation of the bond strengths, e.g. 0.2)");
}

// A region with a spread of strengths starts to crack earlier than the same region without
// one: under the same slow compression, the weakest bonds (factors well below 1) break
// first, and so the first break comes at a smaller platen displacement.
TEST(SceneRegions, ASpreadOfStrengthsBreaksTheWeakestBondsFirst) {
  auto first_break = [](const std::string& extra) {
    const std::string text = edit_base(
        "size = [0.03, 0.03]", "size = [0.03, 0.03]\n" + extra,
        edit_base(
            "[solver]",
            "[[boundary]]\ngroup = \"top\"\ntype = \"velocity\"\naxes = [\"y\"]\nvelocity = [0.0, -0.5]\n\n"
            "[solver]",
            edit_base("ks = 2.4e10", "ks = 2.4e10\ntensile_strength = 1.25e4\nshear_strength = 3.7e4")));
    const Scene sc = strata::scene::parse(text, "scene.toml", {});
    strata::scene::BuiltModel m = strata::scene::build_model(sc, false);
    while (m.sim().broken_count() == 0 && m.step_count() < 200000) m.advance(100);
    return m.step_count();
  };
  const auto plain = first_break("");
  const auto spread = first_break("strength_spread = \"normal\"\nstrength_cov = 0.3");
  ASSERT_LT(plain, 200000) << "nothing broke";
  EXPECT_LT(double(spread), 0.8 * double(plain));
}
