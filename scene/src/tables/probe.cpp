// [probe]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into ProbeTable.
#include "table_file.hpp"

namespace strata::scene::tables {

TableSpec probe_spec() {
  return {
      "probe",
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
          K("stop_after_peak", Real)
              .ge(0)
              .lt(1)
              .def("0.0")
              .doc("stress_strain: stop the run once bonds have broken and the axial stress has fallen "
                   "below this fraction of its peak (the specimen has failed), as a laboratory test stops "
                   "after the peak; summary.json gives the step. 0: run every step."),
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
          K("wedge_group", String)
              .def(R"("")")
              .doc("2D thrust wedge: the [[group]] (or [[region]]) of the cover that a piston or a [[wall]] "
                   "moving along x shortens under gravity along -y (wedge_backstop); summary.json then "
                   "reports its taper (the "
                   "surface slope from the deformation front to the backstop), its width and uplift, and the "
                   "dips of its fore- and backthrusts (lines through its most strained particles, the "
                   "shear zones since settling). Empty: none."),
          K("wedge_backstop", String)
              .def(R"("")")
              .doc("The [[group]] (or [[region]]) of particles driven along x that shortens the wedge's "
                   "cover (a piston); its face towards the cover is the backstop of the wedge. Empty: the "
                   "[[wall]] that moves along x."),
          K("wedge_friction", RealList)
              .gt(0)
              .length(2, 2)
              .doc("Internal and basal friction coefficients of the cover for the critical taper of a "
                   "dry, non-cohesive Coulomb wedge (Dahlen 1984) and its fault dips, reported next to "
                   "the measured ones (wedge_group); the basal one must be the smaller."),
      }};
}

ProbeTable read_probe(const Table& t) {
  Reader read(t, "probe");
  ProbeTable p;
  p.pos = t.where();
  read("stress_strain", p.stress_strain);
  read("top_group", p.top_group);
  read("bottom_group", p.bottom_group);
  read("axis", p.axis);
  read("stop_after_peak", p.stop_after_peak);
  read("energy", p.energy);
  read("broken_bonds", p.broken_bonds);
  read("gauges", p.gauges);
  read("wedge_group", p.wedge_group);
  read("wedge_backstop", p.wedge_backstop);
  read("wedge_friction", p.wedge_friction);
  read.done();
  return p;
}

}  // namespace strata::scene::tables
