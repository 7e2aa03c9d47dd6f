// [scene]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into SceneTable.
#include "table_file.hpp"

namespace strata::scene::tables {

TableSpec scene_spec() {
  return {
      "scene",
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
      }};
}

SceneTable read_scene(const Table& t) {
  Reader read(t, "scene");
  SceneTable s;
  s.pos = t.where();
  read("title", s.title);
  read("dimension", s.dimension);
  read("thickness", s.thickness);
  read("seed", s.seed);
  read.done();
  return s;
}

}  // namespace strata::scene::tables
