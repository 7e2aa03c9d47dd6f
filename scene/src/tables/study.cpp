// [study], [[vary]] and [[measure]]: their keys, declared once (they validate scene files and
// generate docs/scene-reference.md), and their reading into StudyTable, VaryTable and
// MeasureTable.
#include "table_file.hpp"

namespace strata::scene::tables {

TableSpec study_spec() {
  // A study file: the loader allows beside [study] only [[vary]], [[measure]] and some
  // [output] keys (job_tables(), schema.cpp); checks between keys (roles naming [[vary]]
  // keys, pointers) are in checks.cpp, the run in cases/src/study.cpp.
  return {"study",
          false,
          false,
          "A parameter study: the scene it names run once for every combination of the values of its "
          "[[vary]] keys (each given to the scene as `--set` would give it), and the numbers its "
          "[[measure]] entries read from each run's summary.json tabulated with their mean and spread "
          "over the `spread` key (e.g. the random seeds) and plotted against the `x` key. A study file "
          "holds [study], [[vary]], [[measure]] and, besides, only output.directory and output.render. "
          "Every run writes its summary.json and probes.csv into runs/NNNN/ (no frames, no pictures, no "
          "checkpoint).",
          {
              K("title", String).def(R"("")").doc("A name for the study, shown in its tables and plots."),
              K("scene", Path).required().doc("The scene file to run, relative to the study file."),
              K("set", StringList)
                  .def("[]")
                  .doc("Overrides given to every run, written as `--set` takes them, e.g. "
                       "[\"solver.steps=4000\"]."),
              K("spread", String)
                  .def(R"("")")
                  .doc("A [[vary]] key over which the table and the plots take the mean and the standard "
                       "deviation (e.g. scene.seed); empty: none, every run is its own row."),
              K("x", String)
                  .def(R"("")")
                  .doc("The [[vary]] key along the plots' horizontal axis; one curve per combination of the "
                       "other keys but `spread`. Empty: the first [[vary]] key that is not `spread`."),
          }};
}

TableSpec vary_spec() {
  return {"vary",
          true,
          false,
          "One key of a study's scene and the values the study gives it (see [study]).",
          {
              K("key", String)
                  .required()
                  .doc("The key as `--set` names it, e.g. region.specimen.rc, region[0].size or "
                       "scene.seed."),
              K("values", RealList).required().length(1, 0).doc("The values, in the order they run."),
              K("components", Integer)
                  .ge(0)
                  .le(3)
                  .def("0")
                  .doc("0: each value is given as a number; 2 or 3: as the list [v, v] or [v, v, v] (e.g. "
                       "the size of a cube)."),
              K("label", String).def(R"("")").doc("Its name in tables and plots; empty: the key."),
          }};
}

TableSpec measure_spec() {
  return {"measure",
          true,
          false,
          "One number a study reads from each run's summary.json (see [study]).",
          {
              K("name", String).required().doc("Its name in tables and plots, e.g. \"nu\"."),
              K("value", String)
                  .required()
                  .doc("Where it is in summary.json, as a JSON pointer, e.g. "
                       "\"/measured_elastic/poisson_ratio\" or \"/regions/0/eccentric/weakened_bonds\"."),
              K("divide_by", String)
                  .def(R"("")")
                  .doc("A second JSON pointer to divide by, e.g. the lattice's analytical E "
                       "\"/regions/0/lattice_elastic/along_z/youngs_modulus\"; empty: none."),
          }};
}

StudyTable read_study(const Table& t) {
  Reader read(t, "study");
  StudyTable s;
  s.pos = t.where();
  read("title", s.title);
  read("scene", s.scene);
  read("set", s.set);
  read("spread", s.spread);
  read("x", s.x);
  read.done();
  return s;
}

VaryTable read_vary(const Table& t) {
  Reader read(t, "vary");
  VaryTable v;
  v.pos = t.where();
  read("key", v.key);
  read("values", v.values);
  read("components", v.components);
  read("label", v.label);
  read.done();
  return v;
}

MeasureTable read_measure(const Table& t) {
  Reader read(t, "measure");
  MeasureTable m;
  m.pos = t.where();
  read("name", m.name);
  read("value", m.value);
  read("divide_by", m.divide_by);
  read.done();
  return m;
}

}  // namespace strata::scene::tables
