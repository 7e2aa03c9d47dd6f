// [[boundary]]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into BoundaryTable.
#include "table_file.hpp"

namespace strata::scene::tables {
namespace {
const Word<BoundaryType> kBoundaryType[] = {{"fixed", BoundaryType::Fixed},
                                            {"velocity", BoundaryType::Velocity},
                                            {"step_displacement", BoundaryType::StepDisplacement}};
}  // namespace

TableSpec boundary_spec() {
  return {
      "boundary",
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
              .choices(words(kBoundaryType))
              .doc("fixed: held in place; velocity: moved at `velocity`; step_displacement: moved by "
                   "`increment` every `every` steps (Li et al. 2017 move their platens 1.9e-9 m every 400 "
                   "steps)."),
          K("axes", StringList)
              .choices({"x", "y", "z"})
              .per_axis()
              .length(1, 3)
              .def(R"(["x", "y", "z"])")
              .doc("Which components are prescribed; the others stay free. An axis named here is held even "
                   "where its velocity or increment is zero: platens that hold the boundary rows sideways "
                   "(rough platens) name both axes, frictionless ones only the loading axis. Default: all "
                   "axes."),
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
      }};
}

BoundaryTable read_boundary(const Table& t) {
  Reader read(t, "boundary");
  BoundaryTable b;
  b.pos = t.where();
  read("group", b.group);
  read("type", b.type, kBoundaryType);
  read("axes", b.axes);
  read("velocity", b.velocity);
  read("increment", b.increment);
  read("every", b.every);
  read.done();
  return b;
}

}  // namespace strata::scene::tables

namespace strata::scene {
std::string_view to_string(BoundaryType v) { return tables::word_of(tables::kBoundaryType, v); }
}  // namespace strata::scene
