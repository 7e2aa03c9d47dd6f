// [[load]]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into LoadTable.
#include "table_file.hpp"

namespace strata::scene::tables {
namespace {
const Word<LoadPer> kPer[] = {
    {"particle", LoadPer::Particle}, {"group", LoadPer::Group}, {"boundary", LoadPer::Boundary}};
const Word<Ramp> kRamp[] = {{"linear", Ramp::Linear}, {"smooth", Ramp::Smooth}};
const Word<LoadType> kLoadType[] = {{"force_history", LoadType::ForceHistory}, {"radial", LoadType::Radial}};
}  // namespace

TableSpec load_spec() {
  return {
      "load",
      true,
      false,
      "A force history applied to a group: a force vector, or a radial push away from a centre such as "
      "the blast pulse on the rim of a hole (the double-hole plate of Zhao et al. 2021), or a traction "
      "on the boundary of FEM nodes. The force goes from one listed time to the next linearly or "
      "smoothly (`ramp`) and is held after the last.",
      {
          K("group", String)
              .required()
              .doc("The [[group]] it applies to, by name (a [[region]] name stands for all its particles)."),
          K("type", Choice)
              .choices(words(kLoadType))
              .def(R"("force_history")")
              .doc("force_history: force vectors given at a list of times (`forces`); radial: magnitudes "
                   "(`magnitudes`), each particle or FEM node pushed along the unit vector from `center` "
                   "to its start position (a pressure on the wall of a hole or borehole)."),
          K("times", RealList, "s")
              .required()
              .ge(0)
              .length(1, 0)
              .doc("Times of the force values, increasing."),
          K("forces", RealTable, "N")
              .per_axis()
              .doc("One force per time, each with one component per axis, as [[fx, fy], ...]; required "
                   "when type = \"force_history\"."),
          K("magnitudes", RealList, "N")
              .doc("One magnitude per time, positive away from `center`; required when type = "
                   "\"radial\"."),
          K("center", RealList, "m")
              .per_axis()
              .doc("The point the radial load pushes away from (type = \"radial\"), e.g. the centre of "
                   "the hole; default: the mean start position of the group's particles (or FEM nodes), "
                   "which is the hole's centre for a group on the whole rim."),
          K("axis", RealList)
              .per_axis()
              .doc("3D, type = \"radial\": the axis of a borehole; the push is normal to it (its "
                   "component along the axis removed). Without it the push is radial from the point "
                   "(a spherical charge)."),
          K("per", Choice)
              .choices(words(kPer))
              .def(R"("particle")")
              .doc("particle: each particle (or FEM node) of the group gets the force; group: the force "
                   "(for radial: the magnitude) is shared equally by the group's particles, as the blast "
                   "load of Zhao et al. 2021 is shared by the particles on the rim of the hole; boundary: "
                   "the values are a traction on the FEM boundary between the group's nodes, force per "
                   "unit length in 2D (N/m: the stress times the thickness) and per unit area in 3D (Pa), "
                   "and each node gets the traction times its share of that boundary (half of each "
                   "boundary edge in 2D, a third of each boundary triangle in 3D: the consistent load of "
                   "linear elements). FEM nodes only."),
          K("ramp", Choice)
              .choices(words(kRamp))
              .def(R"("linear")")
              .doc("linear: the force goes linearly from one listed time to the next; smooth: along a "
                   "half cosine, w = sin²(π/2·s) of the way s between two times, with zero rate at every "
                   "listed time: a load applied from rest sends no shock, and forces [0, P, 0] at times "
                   "[0, T/2, T] are the sin² pulse P·sin²(πt/T)."),
      }};
}

LoadTable read_load(const Table& t) {
  Reader read(t, "load");
  LoadTable l;
  l.pos = t.where();
  read("group", l.group);
  read("type", l.type, kLoadType);
  read("times", l.times);
  read("forces", l.forces);
  read("magnitudes", l.magnitudes);
  read("center", l.center);
  read("axis", l.axis);
  read("per", l.per, kPer);
  read("ramp", l.ramp, kRamp);
  read.done();
  return l;
}

}  // namespace strata::scene::tables

namespace strata::scene {
std::string_view to_string(LoadPer v) { return tables::word_of(tables::kPer, v); }
std::string_view to_string(LoadType v) { return tables::word_of(tables::kLoadType, v); }
std::string_view to_string(Ramp v) { return tables::word_of(tables::kRamp, v); }
}  // namespace strata::scene
