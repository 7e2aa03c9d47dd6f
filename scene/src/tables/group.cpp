// [[group]]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into GroupTable.
#include "table_file.hpp"

namespace strata::scene::tables {
namespace {
const Word<GroupSelect> kSelect[] = {{"all", GroupSelect::All},
                                     {"top_row", GroupSelect::TopRow},
                                     {"bottom_row", GroupSelect::BottomRow},
                                     {"left_column", GroupSelect::LeftColumn},
                                     {"right_column", GroupSelect::RightColumn},
                                     {"top_layer", GroupSelect::TopLayer},
                                     {"bottom_layer", GroupSelect::BottomLayer},
                                     {"box", GroupSelect::Box},
                                     {"physical", GroupSelect::Physical},
                                     {"hole_rim", GroupSelect::HoleRim}};
}  // namespace

TableSpec group_spec() {
  return {
      "group",
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
              .choices(words(kSelect))
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
      }};
}

GroupTable read_group(const Table& t) {
  Reader read(t, "group");
  GroupTable g;
  g.pos = t.where();
  read("name", g.name);
  read("region", g.region);
  read("select", g.select, kSelect);
  read("physical", g.physical);
  read("hole", g.hole);
  read("width", g.width);
  read("box_min", g.box_min);
  read("box_max", g.box_max);
  read.done();
  return g;
}

}  // namespace strata::scene::tables

namespace strata::scene {
std::string_view to_string(GroupSelect v) { return tables::word_of(tables::kSelect, v); }
}  // namespace strata::scene
