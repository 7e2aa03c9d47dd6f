// [[wall]]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into WallTable.
#include "table_file.hpp"

namespace strata::scene::tables {

TableSpec wall_spec() {
  return {"wall",
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
          }};
}

WallTable read_wall(const Table& t) {
  Reader read(t, "wall");
  WallTable w;
  w.pos = t.where();
  read("name", w.name);
  read("point", w.point);
  read("normal", w.normal);
  read("velocity", w.velocity);
  read("stiffness", w.stiffness);
  read.done();
  return w;
}

}  // namespace strata::scene::tables
