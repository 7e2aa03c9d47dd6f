// The one table of every key a scene file may hold: the loader checks scene files against it and
// `strata reference` writes docs/scene-reference.md from it, so the two cannot disagree.
//
// To add a key: add one line to its table below with its type, unit, range, default and a
// doc string a geologist can read (with the paper it comes from, cited as in
// docs/references.md), then regenerate docs/scene-reference.md
// (`strata reference -o docs/scene-reference.md`; test_scene fails until you do). Checks that
// involve more than one key (shape-dependent keys, cross-references, list lengths against
// [scene].dimension) live in loader.cpp.
#include <strata/scene/scene.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace strata::scene {
namespace {

/// Builder that keeps each key on a few readable lines.
class K {
 public:
  K(std::string name, Type type, std::string unit = "") {
    k_.name = std::move(name);
    k_.type = type;
    k_.unit = std::move(unit);
  }
  K& doc(std::string d) {
    k_.doc = std::move(d);
    return *this;
  }
  K& required() {
    k_.required = true;
    return *this;
  }
  K& def(std::string toml_text) {
    k_.default_value = std::move(toml_text);
    return *this;
  }
  K& ge(double v) {
    k_.min = v;
    k_.min_exclusive = false;
    return *this;
  }
  K& gt(double v) {
    k_.min = v;
    k_.min_exclusive = true;
    return *this;
  }
  K& le(double v) {
    k_.max = v;
    k_.max_exclusive = false;
    return *this;
  }
  K& lt(double v) {
    k_.max = v;
    k_.max_exclusive = true;
    return *this;
  }
  K& choices(std::vector<std::string> c) {
    k_.choices = std::move(c);
    return *this;
  }
  K& length(int lo, int hi) {
    k_.length_min = lo;
    k_.length_max = hi;
    return *this;
  }
  /// One component per axis: 2 in 2D, 3 in 3D.
  K& per_axis() {
    k_.per_axis = true;
    if (k_.type != Type::StringList) k_.length_min = 2, k_.length_max = 3;
    return *this;
  }
  K& allow_inf() {
    k_.allow_inf = true;
    return *this;
  }
  /// [coupled] only: the cases the key applies to.
  K& cases(std::vector<std::string> c) {
    k_.cases = std::move(c);
    return *this;
  }
  /// A default that depends on other keys: the text of the reference's default column.
  K& default_note(std::string text) {
    k_.default_note = std::move(text);
    return *this;
  }
  operator KeySpec() const { return k_; }  // NOLINT: implicit on purpose, for the tables below

 private:
  KeySpec k_;
};

constexpr Type Bool = Type::Bool, Integer = Type::Integer, Real = Type::Real, String = Type::String,
               Choice = Type::Choice, Path = Type::Path, OutputPath = Type::OutputPath,
               RealList = Type::RealList, IntegerList = Type::IntegerList, StringList = Type::StringList,
               RealTable = Type::RealTable;

std::vector<TableSpec> make_schema() {
  std::vector<TableSpec> s;

  s.push_back(
      {"scene",
       false,
       true,
       "What the model is: a title, 2D or 3D, and the random seed.",
       {
           K("title", String).def(R"("")").doc("A name for the run, shown in reports and pictures."),
           K("dimension", Integer)
               .required()
               .ge(2)
               .le(3)
               .doc("2 for a plane model of disks (hexagonal lattice), 3 for a model of spheres "
                    "(close-packed lattice)."),
           K("thickness", Real, "m")
               .gt(0)
               .def("1.0")
               .doc("Out-of-plane thickness of a 2D model: forces per unit thickness are divided by it "
                    "to give stresses. Not used in 3D."),
           K("seed", Integer)
               .ge(0)
               .def("1")
               .doc("Seed of the random numbers (the centroid offsets of eccentric lattices); the same seed "
                    "gives the same model."),
       }});

  s.push_back(
      {"material",
       true,
       true,
       "A bonded-particle material: density, bond stiffnesses and bond strengths of the solid-lattice "
       "law (Liu, Pollard & Shi 2013). Regions refer to a material by its name.",
       {
           K("name", String).required().doc("The material's name, used by the `material` key of [[region]]."),
           K("law", Choice)
               .choices({"solid_lattice"})
               .def(R"("solid_lattice")")
               .doc("Force law between particles. solid_lattice: linear normal and shear springs with "
                    "bonds that break (Liu, Pollard & Shi 2013)."),
           K("density", Real, "kg/m^2 in 2D, kg/m^3 in 3D")
               .required()
               .gt(0)
               .doc("Mass density: per unit thickness in 2D (a disk of diameter d has mass "
                    "ρ·(√3/2)·d², the area per disk of the hexagonal lattice), per volume in 3D."),
           K("kn", Real, "N/m")
               .required()
               .gt(0)
               .doc("Kn: normal stiffness of a bond or contact, Fn = Kn·Un with Un the overlap, "
                    "compression positive (Liu, Pollard & Shi 2013)."),
           K("ks", Real, "N/m")
               .required()
               .ge(0)
               .doc("Ks: shear stiffness, Fs = Ks·Us with Us the shear displacement accumulated since "
                    "the contact formed (Liu, Pollard & Shi 2013)."),
           K("friction", Real)
               .ge(0)
               .def("0.0")
               .doc("μ: friction coefficient. A broken bond whose particles still touch carries "
                    "|Fs| ≤ μ·Fn and no tension (Liu, Pollard & Shi 2013)."),
           K("tensile_strength", Real, "N")
               .ge(0)
               .allow_inf()
               .def("inf")
               .doc("Fn_max: a bond breaks in tension when its normal force falls below −Fn_max "
                    "(Liu, Pollard & Shi 2013). inf: bonds never break in tension."),
           K("shear_strength", Real, "N")
               .ge(0)
               .allow_inf()
               .def("inf")
               .doc("Fs0: an intact bond breaks in shear when |Fs| exceeds Fs0 (Fs0 + μ·Fn with "
                    "friction_strengthens_bonds). inf: bonds never break in shear."),
           K("friction_strengthens_bonds", Bool)
               .def("true")
               .doc("Shear limit of an intact bond: Fs0 + μ·max(Fn, 0) when true (criterion (5) of Li et al. "
                    "2017, the default: at that paper's settings it gives the peak at strain 3.06e-3 against "
                    "its 2.8e-3), Fs0 alone when false (peak at 1.80e-3). See docs/dem.md."),
           K("youngs_modulus", Real, "Pa")
               .gt(0)
               .doc("E of the material where it fills an FEM region; give it with poisson_ratio. Default: "
                    "the continuum of the material's lattice, 2D E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks) per unit "
                    "thickness t, 3D the isotropic average 2√2·Kn(2Kn+3Ks)/(d(4Kn+Ks)) at the particle "
                    "regions' diameter d (Liu, Pollard & Shi 2013), so that particles and elements of one "
                    "material match across an overlap."),
           K("poisson_ratio", Real)
               .gt(-1)
               .lt(0.5)
               .doc("ν of the material where it fills an FEM region (with youngs_modulus). Default: the "
                    "lattice's, (Kn−Ks)/(3Kn+Ks) in 2D, (Kn−Ks)/(4Kn+Ks) in 3D."),
       }});

  s.push_back(
      {"region",
       true,
       true,
       "A part of the model: a lattice of particles (disks in 2D, spheres in 3D) or a finite-element "
       "mesh, filling a simple shape or a geometry file.",
       {
           K("name", String).required().doc("The region's name, used by the `region` key of [[group]]."),
           K("kind", Choice)
               .choices({"particles", "fem"})
               .def(R"("particles")")
               .doc("particles: bonded particles (DEM); fem: finite elements."),
           K("material", String).required().doc("The [[material]] that fills the region, by name."),
           K("lattice", Choice)
               .choices({"auto", "hex", "hcp", "fcc"})
               .def(R"("auto")")
               .doc("Packing of the particles: hex (2D), hcp or fcc (3D); auto is hex in 2D and hcp "
                    "in 3D."),
           K("diameter", Real, "m").gt(0).doc("Particle diameter d; required when kind = \"particles\"."),
           K("shape", Choice)
               .choices({"box", "disk", "sphere", "polygon", "file"})
               .def(R"("box")")
               .doc("What the region fills: box (origin, size), disk in 2D or sphere in 3D (center, "
                    "radius), polygon in 2D (points), or a geometry file (file)."),
           K("origin", RealList, "m").per_axis().def("[0.0, 0.0, 0.0]").doc("Lower corner of a box."),
           K("size", RealList, "m")
               .per_axis()
               .gt(0)
               .doc("Extent of a box along each axis; required when shape = \"box\"."),
           K("center", RealList, "m")
               .per_axis()
               .doc("Centre of a disk or sphere; required when shape = \"disk\" or \"sphere\"."),
           K("radius", Real, "m")
               .gt(0)
               .doc("Radius of a disk or sphere; required when shape = \"disk\" or \"sphere\"."),
           K("points", RealTable, "m")
               .length(2, 2)
               .doc("Corners of a polygon in order, as [[x, y], ...] (at least 3); required when "
                    "shape = \"polygon\"."),
           K("file", Path)
               .doc("Geometry file (.geo, .msh, .step, .stl or .off), relative to the scene file; "
                    "required when shape = \"file\"."),
           K("orientation", Real, "degrees")
               .def("0.0")
               .doc("Rotation of the lattice about the z axis, counter-clockwise."),
           K("mesh_size", Real, "m")
               .ge(0)
               .def("0.0")
               .doc("Finite-element size for kind = \"fem\"; 0 chooses one automatically."),
           K("physical", String)
               .def(R"("")")
               .doc("For shape = \"file\": the gmsh physical group (a physical surface in 2D, a physical "
                    "volume in 3D) that is this region, by name; empty: the whole geometry. A closed STL/OFF "
                    "surface has one region, named after the file."),
           K("min_boundary_distance", Real, "m")
               .ge(0)
               .def("0.0")
               .doc("For shape = \"file\": keep only particles whose centres lie at least this far inside "
                    "the boundary; 0 keeps every centre inside (the count is then area or volume × site "
                    "density), d/2 keeps whole particles inside (as primitive shapes always do)."),
           K("eccentricity", Choice)
               .choices({"none", "cube", "sphere"})
               .def(R"("none")")
               .doc("Eccentric lattice (ECC4D, Zhao et al. 2021): move each particle's centroid by a random "
                    "offset, uniform in a cube of half-side ra·R (cube, Type A) or uniform on a sphere (a "
                    "circle in 2D) of radius ra·R (sphere, Type B); bonds stay those of the regular "
                    "lattice, with their initial lengths as rest lengths (the model starts unloaded). With "
                    "an eccentric region in the scene every region is bonded within itself only (no bonds "
                    "between regions)."),
           K("ra", Real)
               .ge(0)
               .lt(1)
               .def("0.0")
               .doc("Ra: eccentricity of the centroid offsets, as a fraction of the particle radius R "
                    "(Zhao et al. 2021)."),
           K("rc", Real)
               .gt(0)
               .le(1)
               .def("1.0")
               .doc("Rc: bonds longer than Rc·L_max, with L_max the longest bond of the region, are "
                    "weakened by gamma (Zhao et al. 2021)."),
           K("gamma", Real)
               .gt(0)
               .le(1)
               .def("1.0")
               .doc("γ: stiffness factor of the weakened bonds, k -> γ·k (Zhao et al. 2021 use 0.001)."),
       }});

  s.push_back(
      {"group",
       true,
       false,
       "A named set of particles picked from a region, for boundary conditions, loads and probes. Every "
       "region is also a group of its own name, holding all its particles.",
       {
           K("name", String)
               .required()
               .doc("The group's name, used by [[boundary]], [[load]] and [probe]; it must differ from every "
                    "region name."),
           K("region", String).def(R"("")").doc("The [[region]] to pick from, by name; empty: all regions."),
           K("select", Choice)
               .choices({"all", "top_row", "bottom_row", "left_column", "right_column", "top_layer",
                         "bottom_layer", "box", "physical", "hole_rim"})
               .def(R"("all")")
               .doc("Which particles: all; the row with the largest or smallest y (top_row, "
                    "bottom_row); the column with the smallest or largest x (left_column, "
                    "right_column); the layer with the largest or smallest z in 3D (top_layer, "
                    "bottom_layer); those whose centres lie between box_min and box_max (box); for "
                    "regions from geometry files, those of a gmsh physical group (physical: inside a "
                    "physical surface/volume, or within `width` of a physical curve/surface), or those "
                    "within `width` of the rim of hole number `hole` of a 2D region (hole_rim)."),
           K("physical", String)
               .def(R"("")")
               .doc("The gmsh physical group of select = \"physical\", by name."),
           K("hole", Integer)
               .ge(1)
               .def("1")
               .doc("Which hole of select = \"hole_rim\": holes are numbered 1, 2, ... from left to right "
                    "(by the x, then y, of their centres)."),
           K("width", Real, "m")
               .ge(0)
               .def("0.0")
               .doc("Width of the band of particles along a boundary (select = \"physical\" on a curve or "
                    "surface, select = \"hole_rim\"): centres within this distance of it; 0 means one "
                    "particle diameter."),
           K("box_min", RealList, "m")
               .per_axis()
               .doc("Lower corner of the selection box; required when select = \"box\"."),
           K("box_max", RealList, "m")
               .per_axis()
               .doc("Upper corner of the selection box; required when select = \"box\"."),
       }});

  s.push_back(
      {"boundary",
       true,
       false,
       "A prescribed motion of a group: held fixed, moved at a constant velocity, or moved in steps "
       "(the loading platens of the uniaxial compression test of Li et al. 2017).",
       {
           K("group", String)
               .required()
               .doc("The [[group]] it applies to, by name (a [[region]] name stands for all its particles)."),
           K("type", Choice)
               .required()
               .choices({"fixed", "velocity", "step_displacement"})
               .doc("fixed: held in place; velocity: moved at `velocity`; step_displacement: moved by "
                    "`increment` every `every` steps (Li et al. 2017 move their platens 1.9e-9 m every 400 "
                    "steps)."),
           K("axes", StringList)
               .choices({"x", "y", "z"})
               .per_axis()
               .length(1, 3)
               .def(R"(["x", "y", "z"])")
               .doc("Which components are prescribed; the others stay free. Default: all axes."),
           K("velocity", RealList, "m/s")
               .per_axis()
               .doc("Velocity, one component per axis; required when type = \"velocity\"."),
           K("increment", RealList, "m")
               .per_axis()
               .doc("Displacement added every `every` steps; required when type = "
                    "\"step_displacement\"."),
           K("every", Integer, "steps")
               .ge(1)
               .def("1")
               .doc("Steps between two increments (type = \"step_displacement\")."),
       }});

  s.push_back(
      {"load",
       true,
       false,
       "A force history applied to a group, e.g. the blast pulse on the rim of a hole (the double-hole "
       "plate of Zhao et al. 2021); "
       "the force is interpolated linearly between the listed times.",
       {
           K("group", String)
               .required()
               .doc("The [[group]] it applies to, by name (a [[region]] name stands for all its particles)."),
           K("type", Choice)
               .choices({"force_history"})
               .def(R"("force_history")")
               .doc("force_history: forces given at a list of times."),
           K("times", RealList, "s")
               .required()
               .ge(0)
               .length(1, 0)
               .doc("Times of the force values, increasing."),
           K("forces", RealTable, "N")
               .required()
               .per_axis()
               .doc("One force per time, each with one component per axis, as [[fx, fy], ...]."),
           K("per", Choice)
               .choices({"particle", "group"})
               .def(R"("particle")")
               .doc("particle: each particle of the group gets the force; group: the force is shared "
                    "equally by the group's particles."),
       }});

  s.push_back(
      {"wall",
       true,
       false,
       "A rigid flat wall (a platen) that particles cannot cross; it pushes back with a linear "
       "spring and may move at a constant velocity.",
       {
           K("name", String).required().doc("The wall's name, used in output."),
           K("point", RealList, "m").required().per_axis().doc("A point on the wall."),
           K("normal", RealList)
               .required()
               .per_axis()
               .doc("Direction perpendicular to the wall, pointing into the particles (need not be of "
                    "unit length)."),
           K("velocity", RealList, "m/s")
               .per_axis()
               .def("[0.0, 0.0, 0.0]")
               .doc("Constant velocity of the wall."),
           K("stiffness", Real, "N/m")
               .ge(0)
               .def("0.0")
               .doc("Normal stiffness of particle-wall contacts; 0 uses the largest material kn."),
       }});

  s.push_back(
      {"solver",
       false,
       false,
       "Time stepping and damping. Before a run strata compares the time step with the critical one "
       "(for the 2D hexagonal lattice dt_crit = 2·√(m/(6Kn+2Ks))).",
       {
           K("dt", Real, "s")
               .ge(0)
               .def("0.0")
               .doc("Time step; 0 chooses dt_safety × dt_crit. A dt above dt_crit is refused unless "
                    "allow_unstable = true."),
           K("dt_safety", Real)
               .gt(0)
               .le(1)
               .def("0.2")
               .doc("Fraction of the critical time step used when dt = 0 (Li et al. 2017 used "
                    "0.14)."),
           K("steps", Integer)
               .ge(0)
               .def("0")
               .doc("Number of time steps; when 0 the run lasts `duration`. Set steps or duration."),
           K("duration", Real, "s").ge(0).def("0.0").doc("Simulated time, used when steps = 0."),
           K("damping", Choice)
               .choices({"none", "viscous", "local"})
               .def(R"("none")")
               .doc("none; viscous: a force −c·v on each particle (the artificial viscosity of Li et al. "
                    "2017); local: each force component is reduced by local_damping times its size, "
                    "against the velocity (Cundall's local damping)."),
           K("viscous_c", Real, "N·s/m")
               .ge(0)
               .def("0.0")
               .doc("c of the viscous damping force −c·v (Li et al. 2017 use 1.16e3 N·s/m)."),
           K("local_damping", Real)
               .ge(0)
               .lt(1)
               .def("0.7")
               .doc("Coefficient of local damping (damping = \"local\")."),
           K("gravity", RealList, "m/s^2")
               .per_axis()
               .def("[0.0, 0.0, 0.0]")
               .doc("Acceleration of gravity, e.g. [0, -9.81] in 2D."),
           K("contact_detection", Choice)
               .choices({"auto", "on", "off"})
               .def(R"("auto")")
               .doc("Search for new contacts between particles that were not bonded at the start: on, "
                    "off, or auto (on only when particles can meet new neighbours, e.g. when bonds can "
                    "break or walls move, and off with eccentric regions, whose offset centroids can "
                    "overlap unbonded neighbours at the start)."),
           K("allow_unstable", Bool)
               .def("false")
               .doc("Run even when dt exceeds the critical time step, with a warning."),
           K("threads", Integer)
               .ge(0)
               .def("0")
               .doc("Number of threads; 0 uses all cores. Results are the same for any number."),
           K("min_particles_per_thread", Integer)
               .ge(1)
               .def("4096")
               .doc("A thread is used only for at least this many particles (a parallel step costs a few "
                    "microseconds of synchronisation, more than it saves on small models when other work "
                    "shares the cores). Results do not depend on it."),
           K("fem_integrator", Choice)
               .choices({"auto", "central-difference", "explicit-newmark", "implicit-newmark"})
               .def(R"("auto")")
               .doc("Time integrator of FEM regions. auto: central difference while the FEM step is below "
                    "its explicit limit, implicit Newmark (β = 1/4, γ = 1/2, unconditionally stable) above "
                    "it. explicit-newmark is the predictor-corrector Newmark with a lumped mass: explicit, "
                    "stable only for ω·dt ≤ 2."),
           K("eta", Integer)
               .ge(1)
               .le(1000000)
               .def("1")
               .doc("η: FEM step over DEM step in a model with particle and FEM regions. One system step "
                    "is one FEM step of η·dt and η particle steps of dt; the two sides exchange the overlap "
                    "at every system step."),
           K("coupling", Choice)
               .choices({"serial", "parallel"})
               .def(R"("serial")")
               .doc("How a coupled model runs its two sides: one after the other, or the FEM side and the "
                    "particles on two threads meeting once per system step. Both give the same bits."),
       }});

  s.push_back(
      {"output",
       false,
       false,
       "What a run writes, and how often.",
       {
           K("directory", OutputPath)
               .def(R"("out")")
               .doc("Output folder, relative to the scene file; `strata run -o` overrides it."),
           K("frames", Integer)
               .ge(0)
               .def("20")
               .doc("Number of VTK frames, evenly spaced over the run; 0 writes none. "
                    "frame_every_breaks and frame_every_time take precedence."),
           K("frame_every_time", Real, "s")
               .ge(0)
               .def("0.0")
               .doc("Simulated time between two frames (at the nearest step), plus the first and the "
                    "last; 0: not used. Takes precedence over frames."),
           K("frame_every_breaks", Integer)
               .ge(0)
               .def("0")
               .doc("Write a frame whenever this many more bonds have broken since the last frame "
                    "(checked at every probe row), plus the first and the last; 0: not used. Takes "
                    "precedence over frame_every_time and frames."),
           K("checkpoint_every", Integer, "steps")
               .ge(0)
               .def("0")
               .doc("Steps between two checkpoints (`checkpoint.h5` in the output folder, replaced "
                    "each time); 0: only at the end of the run and when it is interrupted (SIGINT, "
                    "SIGTERM). `strata run SCENE --restart checkpoint.h5` continues the run. Needs "
                    "STRATA_WITH_HDF5."),
           K("probe_every", Integer, "steps")
               .ge(0)
               .def("0")
               .doc("Steps between two probe rows; 0 gives about 1000 rows per run."),
           K("vtk", Bool)
               .def("true")
               .doc("Write VTK frames (.vtp/.vtu files and a .pvd collection) for ParaView."),
           K("render", Bool).def("true").doc("Render the frames to PNG pictures."),
           K("render_field", Choice)
               .choices({"displacement", "velocity", "damage", "group"})
               .def(R"("damage")")
               .doc("What colours the particles in the pictures; damage also colours broken bonds "
                    "by how they broke (tension or shear)."),
           K("fields", StringList)
               .choices({"id", "radius", "displacement", "velocity", "force", "group", "damage"})
               .def(R"(["id", "radius", "displacement", "velocity", "force", "group", "damage"])")
               .doc("Per-particle fields written to the VTK frames."),
           K("movie", Bool).def("true").doc("Join the pictures into an MP4 movie when ffmpeg is installed."),
           K("render_while_running", Bool)
               .def("false")
               .doc("Render each frame to PNG as soon as it is written, so pictures of a long run can be "
                    "watched while it goes on (each picture then has its own colour range, except for "
                    "damage); otherwise all frames are rendered at the end with one colour range."),
           K("render_contacts", Bool)
               .def("false")
               .doc("Also draw the contacts of the bond frames (output.contacts) in the pictures, as thin "
                    "green lines."),
           K("view_direction", RealList)
               .length(3, 3)
               .def("[-1.0, -0.6, -0.45]")
               .doc("3D pictures: direction from the camera towards the model (need not be a unit vector; "
                    "not zero). 2D pictures always look down -z."),
           K("view_up", RealList)
               .length(3, 3)
               .def("[0.0, 0.0, 1.0]")
               .doc("3D pictures: the direction that points up in the picture (not zero, not parallel to "
                    "view_direction)."),
           K("clip_plane", RealList)
               .length(6, 6)
               .doc("3D pictures: a clip plane [ox, oy, oz, nx, ny, nz], a point (m) and a normal (not "
                    "zero); particles, cracks and FEM cells on the normal's side are left out, so the "
                    "inside shows. Not set: nothing is clipped."),
           K("particles", Choice)
               .choices({"all", "surface", "none"})
               .def(R"("all")")
               .doc("Which particles the VTK frames hold: all; surface (the particles that had fewer "
                    "bonds at the start than one inside the lattice: the skin of every region and of its "
                    "holes); none. Large models can write only what a workstation can open."),
           K("groups", StringList)
               .def("[]")
               .doc("Only particles of these [[group]]s or [[region]]s in the VTK frames; empty: all."),
           K("slice_point", RealList, "m")
               .per_axis()
               .def("[0.0, 0.0, 0.0]")
               .doc("A point of the slice plane (see slice_thickness)."),
           K("slice_normal", RealList)
               .per_axis()
               .def("[0.0, 0.0, 1.0]")
               .doc("Normal of the slice plane (see slice_thickness)."),
           K("slice_thickness", Real, "m")
               .ge(0)
               .def("0.0")
               .doc("Only particles whose centres lie within half this distance of the slice plane "
                    "(slice_point, slice_normal) in the VTK frames; 0: no slice."),
           K("bonds", Choice)
               .choices({"broken", "all", "none"})
               .def(R"("broken")")
               .doc("Which bonds the bond frames hold: broken (cracks: tension, shear, closed again), all "
                    "(also intact bonds, with their forces), none."),
           K("contacts", Bool)
               .def("true")
               .doc("Also write the contacts between particles that were never bonded and touch now to the "
                    "bond frames, as lines with state 4, Fn and Fs; only those whose two particles pass "
                    "output.groups and the slice. Pictures draw them only with render_contacts."),
       }});

  s.push_back(
      {"probe",
       false,
       false,
       "Measurements written as CSV rows during the run (every output.probe_every steps).",
       {
           K("stress_strain", Bool)
               .def("false")
               .doc("Record the axial stress and strain of a specimen between two groups, as in a "
                    "laboratory compression test (Li et al. 2017); needs top_group and bottom_group."),
           K("top_group", String)
               .def(R"("top")")
               .doc("The [[group]] (or [[region]]) at the upper end of the specimen (stress_strain)."),
           K("bottom_group", String)
               .def(R"("bottom")")
               .doc("The [[group]] (or [[region]]) at the lower end of the specimen (stress_strain)."),
           K("axis", Choice).choices({"x", "y", "z"}).def(R"("y")").doc("Loading axis of stress_strain."),
           K("energy", Bool)
               .def("true")
               .doc("Record the kinetic energy, the elastic energy of bonds and contacts, and the work "
                    "done by damping."),
           K("broken_bonds", Bool)
               .def("true")
               .doc("Record the number of bonds broken in tension and in shear."),
           K("gauges", StringList)
               .def("[]")
               .doc("Groups whose mean displacement is recorded at every probe row (columns <group>_ux, "
                    "<group>_uy and, in 3D, <group>_uz): particles, FEM nodes or both. Gauges compare runs "
                    "of one geometry, e.g. a coupled model against an all-particle one."),
       }});

  // A coupled scene: the loader allows beside it only the tables and [output] keys of
  // coupled_scene_tables() and coupled_output_keys() (below), and of [coupled] only the keys
  // whose cases() hold its case; checks between these keys (keys a case needs, duration
  // against η·dt_DEM) are in loader.cpp, stability (it needs the model) in
  // cases/src/chain_report.cpp and cases/src/wave_report.cpp.
  const std::vector<std::string> chains{"chain6", "metamaterial"}, wave{"wave"};
  s.push_back(
      {"coupled",
       false,
       false,
       "A coupled FEM–DEM model run as a sweep over the time-step ratio η: a chain of Li et al. 2023 "
       "(chain6, metamaterial; error and run time per η against an exact or reference answer) or "
       "the 2D coupled wave of examples/04_coupled_wave (wave; reflection and transmission of a "
       "pulse per η and pulse length). A scene with [coupled] describes the whole model: besides "
       "it, it may hold only [output] with directory and render. Keys marked with a case apply "
       "only to it.",
       {
           K("case", Choice)
               .required()
               .choices({"chain6", "metamaterial", "wave"})
               .doc("Which model: chain6, the 6-DOF verification chain (k = 1 N/m, m = 1 kg, P·sin(πt/2) on "
                    "m2; error of m3 against the exact modal solution); metamaterial, 800 outer masses and "
                    "200 resonators (error of DEM mass 250 against a monolithic implicit Newmark run at "
                    "dt_ref), as in Li et al. 2023; wave, a 1D strain pulse from an FEM block into a "
                    "particle block built from a 2D geometry file (R and T against the matched-impedance "
                    "answer R = 0, T = 1), see examples/04_coupled_wave."),
           K("title", String).def(R"("")").doc("A name for the run, shown in the report."),
           K("dt_dem", Real, "s")
               .gt(0)
               .cases(chains)
               .doc("DEM time step dt_DEM (velocity Verlet); the FEM step is η·dt_DEM; required for the "
                    "chains. An unstable dt_DEM is refused by `strata check` and `strata run` (the "
                    "metamaterial chain needs dt_DEM <= 7.68e-5 s; the 1e-4 s of Li et al. 2023 is "
                    "unstable). The wave sets dt_DEM with dt_fraction."),
           K("eta", IntegerList)
               .ge(1)
               .length(1, 0)
               .default_note(
                   "per case: chain6, metamaterial `[1, 2, 3, 4, 5, 10, 20]` (those of Li et al. 2023); "
                   "wave `[1, 2, 4, 5, 10]`, embedded `[1, 2, 5]`")
               .doc("Time-step ratios η = dt_FEM/dt_DEM of the sweep, one run per value and mode "
                    "(and per wavelength for the wave)."),
           K("modes", Choice)
               .choices({"serial", "parallel", "both"})
               .def(R"("both")")
               .doc("serial: both partitions on one thread; parallel: each on its own thread, meeting "
                    "once per system step; both: every η in both modes (results are the same bit for bit, "
                    "only the run time differs)."),
           K("duration", Real, "s")
               .ge(0)
               .def("0.0")
               .cases(chains)
               .doc("Simulated time; 0 uses the case's (20 s for chain6, 0.075 s for metamaterial). It "
                    "must hold at least one FEM step of the largest η. The wave runs until its gauges "
                    "have seen the reflected and transmitted pulses."),
           K("fem_scheme", Choice)
               .choices({"auto", "central-difference", "explicit-newmark", "implicit-newmark"})
               .def(R"("auto")")
               .doc("Integrator of the FEM partition: explicit-newmark is the predictor-corrector Newmark "
                    "of Li et al. 2023 with a lumped mass (explicit: stable only for ω·dt <= 2); "
                    "central-difference is explicit too; implicit-newmark (β = 1/4, γ = 1/2, factorised "
                    "once) is unconditionally stable. auto is explicit-newmark for chain6, implicit-newmark "
                    "for metamaterial, and per η for the wave: central-difference while η·dt_DEM is below "
                    "the FEM's explicit limit, implicit-newmark above it. An explicit FEM above its limit "
                    "is refused."),
           K("dt_ref", Real, "s")
               .gt(0)
               .def("1e-6")
               .cases({"metamaterial"})
               .doc("Step of the monolithic implicit Newmark reference run."),
           K("pulse_amplitude", Real, "N")
               .def("100.0")
               .cases({"metamaterial"})
               .doc("Peak of the half-sine force pulse on outer mass 1, the free end (Li et al. 2023 show "
                    "their load history only in a figure, so this pulse is strata's choice)."),
           K("pulse_duration", Real, "s")
               .gt(0)
               .def("1e-3")
               .cases({"metamaterial"})
               .doc("Length of the half-sine force pulse."),
           K("geometry", Path)
               .cases(wave)
               .doc("2D geometry file (gmsh .geo) with the physical surfaces named by particle_region, "
                    "fem_region (and exit_region), sharing straight sides; relative to the scene file; "
                    "required for the wave (examples/04_coupled_wave/wave.geo, wave_embedded.geo)."),
           K("particle_region", String)
               .def(R"("dem")")
               .cases(wave)
               .doc("Physical surface of the geometry filled with a hexagonal lattice of particles."),
           K("fem_region", String)
               .def(R"("fem")")
               .cases(wave)
               .doc("Physical surface meshed with linear triangles for the FEM; the pulse is loaded on "
                    "its far side."),
           K("exit_region", String)
               .def(R"("")")
               .cases(wave)
               .doc("A second FEM surface beyond the particles (FEM | DEM | FEM); empty: none, or "
                    "\"fem_exit\" with embedded = true."),
           K("embedded", Bool)
               .def("false")
               .cases(wave)
               .doc("FEM | DEM | FEM: a particle strip between two FEM blocks (exit_region, default "
                    "\"fem_exit\"); also changes the defaults of eta and wavelengths."),
           K("wavelengths", RealList, "particle diameters")
               .gt(0)
               .length(1, 0)
               .cases(wave)
               .default_note("`[10, 20, 40, 80]`; embedded `[20, 40]`")
               .doc("Pulse lengths λ = c·T of the sweep, in particle diameters; each must fit the "
                    "geometry (incident, reflected and transmitted pulses must separate in time)."),
           K("diameter", Real, "m")
               .gt(0)
               .def("1e-3")
               .cases(wave)
               .doc("Particle diameter d of the lattice (and the FEM element size at the interface)."),
           K("dt_fraction", Real)
               .gt(0)
               .le(1)
               .def("0.15")
               .cases(wave)
               .doc("dt_DEM as a fraction of the lattice's critical step 2/√λmax. 0.15 keeps dt_FEM <= "
                    "1.5 × the DEM limit up to η = 10: the overlap exchange was measured unstable from "
                    "about 2 × (examples/04_coupled_wave/README.md)."),
           K("fem_far_size", Real, "particle diameters")
               .ge(1)
               .le(100)
               .def("1.0")
               .cases(wave)
               .doc("Largest FEM element; 1 gives a uniform mesh of size d, the cleanest measurement."),
           K("fem_growth", Real)
               .ge(0)
               .def("0.1")
               .cases(wave)
               .doc("Growth of the FEM element size per metre away from the interface (m/m), up to "
                    "fem_far_size."),
           K("peak_velocity", Real, "m/s")
               .gt(0)
               .def("0.1")
               .cases(wave)
               .doc("v0: peak particle velocity of the incident sin² pulse."),
           K("frames", Integer)
               .ge(0)
               .def("12")
               .cases(wave)
               .doc("VTK frames of one extra run (serial, η = series_eta, the longest pulse) in "
                    "DIR/series, with PNGs of the pulse crossing the overlap unless output.render = "
                    "false; 0: no series."),
           K("series_eta", Integer).ge(1).def("1").cases(wave).doc("η of the series run."),
           K("repeats", Integer)
               .ge(1)
               .default_note("per case: chain6, metamaterial `3`; wave `1`")
               .doc("Runs per point; the fastest run time is reported."),
           K("threads", Integer)
               .ge(0)
               .default_note("per case: chain6, metamaterial `0`; wave `1`")
               .doc("Threads for parallel loops (the wave: inside each partition; its models are small, "
                    "and a thread hand-off per step costs more than it saves); 0 uses all cores. "
                    "`strata run --threads` overrides it."),
       }});
  return s;
}

}  // namespace

const std::vector<TableSpec>& schema() {
  static const std::vector<TableSpec> s = make_schema();
  return s;
}

const std::vector<std::string>& coupled_scene_tables() {
  static const std::vector<std::string> t{"coupled", "output"};
  return t;
}

const std::vector<std::string>& coupled_output_keys() {
  static const std::vector<std::string> k{"directory", "render"};
  return k;
}

std::vector<std::string> coupled_case_keys(const std::string& case_name) {
  std::vector<std::string> out;
  for (const TableSpec& t : schema())
    if (t.name == "coupled")
      for (const KeySpec& k : t.keys)
        if (k.cases.empty() || std::find(k.cases.begin(), k.cases.end(), case_name) != k.cases.end())
          out.push_back(k.name);
  return out;
}

std::string range_text(const KeySpec& key) {
  const bool integer = key.type == Type::Integer;
  if (integer && key.min && key.max && !key.min_exclusive && !key.max_exclusive && *key.max - *key.min <= 3) {
    // A few whole numbers: list them ("2 or 3").
    std::string out;
    for (auto v = static_cast<long long>(*key.min); v <= static_cast<long long>(*key.max); ++v) {
      if (!out.empty()) out += v == static_cast<long long>(*key.max) ? " or " : ", ";
      out += fmt::format("{}", v);
    }
    return out;
  }
  std::string lo = key.min ? fmt::format("{} {}", key.min_exclusive ? ">" : ">=", *key.min) : "";
  std::string hi = key.max ? fmt::format("{} {}", key.max_exclusive ? "<" : "<=", *key.max) : "";
  if (!lo.empty() && !hi.empty()) return lo + " and " + hi;
  return lo + hi;
}

std::string type_name(Type type) {
  switch (type) {
    case Type::Bool:
      return "bool";
    case Type::Integer:
      return "integer";
    case Type::Real:
      return "real";
    case Type::String:
      return "string";
    case Type::Choice:
      return "choice";
    case Type::Path:
      return "path";
    case Type::OutputPath:
      return "output path";
    case Type::RealList:
      return "list of reals";
    case Type::IntegerList:
      return "list of integers";
    case Type::StringList:
      return "list of strings";
    case Type::RealTable:
      return "list of rows of reals";
  }
  return "?";
}

}  // namespace strata::scene
