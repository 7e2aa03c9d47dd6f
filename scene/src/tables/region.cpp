// [[region]]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into RegionTable.
#include "table_file.hpp"

namespace strata::scene::tables {
namespace {
const Word<RegionKind> kKind[] = {{"particles", RegionKind::Particles}, {"fem", RegionKind::Fem}};
const Word<RegionShape> kShape[] = {{"box", RegionShape::Box},         {"disk", RegionShape::Disk},
                                    {"sphere", RegionShape::Sphere},   {"cylinder", RegionShape::Cylinder},
                                    {"polygon", RegionShape::Polygon}, {"file", RegionShape::File}};
const Word<RegionEccentricity> kEccentricity[] = {{"none", RegionEccentricity::None},
                                                  {"cube", RegionEccentricity::Cube},
                                                  {"sphere", RegionEccentricity::Sphere}};
const Word<LengthUnit> kUnit[] = {{"m", LengthUnit::Metre},
                                  {"cm", LengthUnit::Centimetre},
                                  {"mm", LengthUnit::Millimetre},
                                  {"km", LengthUnit::Kilometre}};
}  // namespace

TableSpec region_spec() {
  return {
      "region",
      true,
      true,
      "A part of the model: a lattice of particles (disks in 2D, spheres in 3D) or a finite-element "
      "mesh, filling a simple shape or a geometry file.",
      {
          K("name", String).required().doc("The region's name, used by the `region` key of [[group]]."),
          K("kind", Choice)
              .choices(words(kKind))
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
              .choices(words(kShape))
              .def(R"("box")")
              .doc("What the region fills: box (origin, size), disk in 2D or sphere in 3D (center, "
                   "radius), cylinder in 3D (center, radius, height: along z, such as a rock core or a "
                   "Brazilian disc), polygon in 2D (points), or a geometry file (file)."),
          K("origin", RealList, "m").per_axis().def("[0.0, 0.0, 0.0]").doc("Lower corner of a box."),
          K("size", RealList, "m")
              .per_axis()
              .gt(0)
              .doc("Extent of a box along each axis; required when shape = \"box\"."),
          K("center", RealList, "m")
              .per_axis()
              .doc("Centre of a disk, sphere or cylinder; required when shape = \"disk\", \"sphere\" or "
                   "\"cylinder\"."),
          K("radius", Real, "m")
              .gt(0)
              .doc("Radius of a disk, sphere or cylinder; required when shape = \"disk\", \"sphere\" or "
                   "\"cylinder\"."),
          K("height", Real, "m")
              .gt(0)
              .doc("Length of a cylinder along z, centred on its center; required when shape = "
                   "\"cylinder\"."),
          K("points", RealTable, "m")
              .length(2, 2)
              .doc("Corners of a polygon in order, as [[x, y], ...] (at least 3); required when "
                   "shape = \"polygon\"."),
          K("file", Path)
              .doc("Geometry file, relative to the scene file; required when shape = \"file\". gmsh reads "
                   ".geo, .msh, .step/.stp and .brep/.brp (2D or 3D); CGAL reads closed triangle surfaces "
                   ".stl and .off (3D)."),
          K("unit", Choice)
              .choices(words(kUnit))
              .def(R"("m")")
              .doc(
                  "For shape = \"file\": the length unit of the file's coordinates (most CAD files are in "
                  "mm); strata scales the geometry to metres. Every other length of the scene is in metres."),
          K("orientation", Real, "degrees")
              .def("0.0")
              .doc("Rotation of the lattice about the z axis, counter-clockwise."),
          K("mesh_size", Real, "m")
              .ge(0)
              .def("0.0")
              .doc("kind = \"fem\": the largest finite element; 0 chooses one automatically. Particle "
                   "regions of shape = \"file\": the largest element of the geometry mesh that decides "
                   "which lattice sites are inside (0: the file's own sizes); curved CAD surfaces (a STEP "
                   "sphere, small inclusions) come out a few per cent small on gmsh's default mesh, about "
                   "the particle diameter keeps the volume within 0.5 %. Not used by other shapes."),
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
              .choices(words(kEccentricity))
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
          K("strength_spread", Choice)
              .choices(words(kSpread))
              .def(R"("none")")
              .doc("A statistical spread of bond strength: each bond's tensile and shear strengths are "
                   "multiplied by one factor drawn for it, with mean 1 and coefficient of variation "
                   "strength_cov, from a normal distribution (cut at zero: drawn again below 1e-3) or a "
                   "Weibull distribution (its modulus follows from strength_cov: 0.1 gives 12.2, 0.3 "
                   "gives 3.7). The factors are drawn in bond order from the scene's seed, so a run is "
                   "reproducible. The region is then bonded within itself only, as an eccentric one."),
          K("strength_cov", Real)
              .ge(0)
              .le(1)
              .def("0.0")
              .doc("Coefficient of variation of the bond strength factors (standard deviation over "
                   "mean); required above 0 with strength_spread."),
      }};
}

RegionTable read_region(const Table& t) {
  Reader read(t, "region");
  RegionTable r;
  r.pos = t.where();
  read("name", r.name);
  read("kind", r.kind, kKind);
  read("material", r.material);
  read("lattice", r.lattice);
  read("diameter", r.diameter);
  read("shape", r.shape, kShape);
  read("origin", r.origin);
  read("size", r.size);
  read("center", r.center);
  read("radius", r.radius);
  read("height", r.height);
  read("points", r.points);
  read("file", r.file);
  read("unit", r.unit, kUnit);
  read("orientation", r.orientation);
  read("mesh_size", r.mesh_size);
  read("physical", r.physical);
  read("min_boundary_distance", r.min_boundary_distance);
  read("eccentricity", r.eccentricity, kEccentricity);
  read("ra", r.ra);
  read("rc", r.rc);
  read("gamma", r.gamma);
  read("strength_spread", r.strength_spread, kSpread);
  read("strength_cov", r.strength_cov);
  read.done();
  return r;
}

}  // namespace strata::scene::tables

namespace strata::scene {
std::string_view to_string(RegionKind v) { return tables::word_of(tables::kKind, v); }
std::string_view to_string(RegionShape v) { return tables::word_of(tables::kShape, v); }
std::string_view to_string(RegionEccentricity v) { return tables::word_of(tables::kEccentricity, v); }
std::string_view to_string(StrengthSpread v) { return tables::word_of(tables::kSpread, v); }
double metres(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Centimetre:
      return 1e-2;
    case LengthUnit::Millimetre:
      return 1e-3;
    case LengthUnit::Kilometre:
      return 1e3;
    case LengthUnit::Metre:
      break;
  }
  return 1.0;
}
}  // namespace strata::scene
