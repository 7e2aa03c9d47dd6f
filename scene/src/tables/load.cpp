// [[load]]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into LoadTable.
#include "table_file.hpp"

namespace strata::scene::tables {
namespace {
const Word<LoadPer> kPer[] = {{"particle", LoadPer::Particle}, {"group", LoadPer::Group}};
}  // namespace

TableSpec load_spec() {
  return {
      "load",
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
              .choices(words(kPer))
              .def(R"("particle")")
              .doc("particle: each particle of the group gets the force; group: the force is shared "
                   "equally by the group's particles."),
      }};
}

LoadTable read_load(const Table& t) {
  Reader read(t, "load");
  LoadTable l;
  l.pos = t.where();
  read("group", l.group);
  read("type", l.type);
  read("times", l.times);
  read("forces", l.forces);
  read("per", l.per, kPer);
  read.done();
  return l;
}

}  // namespace strata::scene::tables

namespace strata::scene {
std::string_view to_string(LoadPer v) { return tables::word_of(tables::kPer, v); }
}  // namespace strata::scene
