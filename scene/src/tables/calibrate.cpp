// [calibrate]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into CalibrateTable.
#include "table_file.hpp"

namespace strata::scene::tables {

TableSpec calibrate_spec() {
  return {
      "calibrate",
      false,
      false,
      "A calibration (`strata calibrate`): the elastic constants and strengths a rock should have, and "
      "the lattice that is to have them. strata chooses Kn and Ks from the lattice's analytical "
      "relations, corrects them by measuring a uniaxial compression specimen, then searches the bond "
      "strengths Fn_max and Fs0 so that the specimen's peak stress is the UCS and a Brazilian disc's "
      "splitting stress 2P/(πDt) is the tensile strength, and reports what it achieved. A calibration "
      "file holds [calibrate] and, besides, only [scene] and output.directory and output.render.",
      {
          K("youngs_modulus", Real, "Pa")
              .required()
              .gt(0)
              .doc("E to reach, measured on the uniaxial specimen."),
          K("poisson_ratio", Real)
              .required()
              .gt(-1)
              .lt(0.5)
              .doc("ν to reach. A lattice of normal and shear springs (Ks >= 0) gives at most 1/3 in 2D and "
                   "1/5 along the stacking axis of a 3D close packing; a target above that is refused."),
          K("ucs", Real, "Pa")
              .required()
              .gt(0)
              .doc("Uniaxial compressive strength to reach: the peak stress "
                   "of the uniaxial specimen."),
          K("tensile_strength", Real, "Pa")
              .required()
              .gt(0)
              .doc(
                  "Tensile strength to reach, as the Brazilian test measures it: 2P/(πDt) at the peak load P "
                  "of a disc of diameter D and thickness t loaded along a diameter."),
          K("density", Real, "kg/m^2 in 2D, kg/m^3 in 3D")
              .required()
              .gt(0)
              .doc("Mass density of the particles "
                   "(as [[material]] density)."),
          K("diameter", Real, "m").required().gt(0).doc("Particle diameter d."),
          K("lattice", Choice)
              .choices({"auto", "hex", "hcp", "fcc"})
              .def(R"("auto")")
              .doc("Packing, as [[region]] lattice: hex in 2D, hcp or fcc in 3D (auto: hex or hcp)."),
          K("friction", Real).ge(0).def("0.5").doc("μ of broken bonds and new contacts (kept as given)."),
          K("friction_strengthens_bonds", Bool)
              .def("true")
              .doc("As [[material]] friction_strengthens_bonds: the shear limit of an intact bond is "
                   "Fs0 + μ·max(Fn, 0) (true) or Fs0."),
          K("specimen_width", Real, "m")
              .ge(0)
              .def("0.0")
              .doc("Width of the uniaxial specimen (2D: a rectangle twice as tall; 3D: a cylinder twice as "
                   "tall as its diameter, along z) and diameter of the Brazilian disc (3D: half as thick "
                   "as wide). 0: 40 particle diameters."),
          K("damping_ratio", Real)
              .ge(0)
              .lt(1)
              .def("0.05")
              .doc("Viscous damping of the specimens, as a fraction of the critical damping 2·√(Kn·m) of "
                   "one particle on one bond (Li et al. 2017 used about 0.05)."),
          K("transits_to_peak", Real)
              .gt(0)
              .def("300.0")
              .doc("Loading rate: the platens reach the strain of the expected peak (UCS/E) in this many "
                   "times the time a compression wave takes to cross the specimen; more is slower and "
                   "closer to static."),
          K("iterations", Integer)
              .ge(1)
              .le(50)
              .def("8")
              .doc("Most pairs of specimen runs in the search of the bond strengths."),
          K("tolerance", Real)
              .gt(0)
              .lt(1)
              .def("0.03")
              .doc("Relative error of each target at which the search stops."),
          K("match", Choice)
              .choices({"ucs", "tensile_strength"})
              .def(R"("ucs")")
              .doc("Which strength to reach when the lattice cannot give the targets' ratio UCS/tensile "
                   "strength (bonded-particle lattices give too low a ratio for most rocks): the UCS, "
                   "or the tensile strength. The other is reported as achieved."),
          K("strength_spread", Choice)
              .choices(words(kSpread))
              .def(R"("none")")
              .doc("As [[region]] strength_spread, for the specimens: a spread of bond strengths, each "
                   "bond's tensile and shear strengths multiplied by a factor of mean 1 drawn from the "
                   "scene's seed. The search then matches the strengths of the heterogeneous specimens."),
          K("strength_cov", Real)
              .ge(0)
              .le(1)
              .def("0.0")
              .doc("Coefficient of variation of the specimens' bond strength factors; required above 0 with "
                   "strength_spread."),
      }};
}

CalibrateTable read_calibrate(const Table& t) {
  Reader read(t, "calibrate");
  CalibrateTable c;
  c.pos = t.where();
  read("youngs_modulus", c.youngs_modulus);
  read("poisson_ratio", c.poisson_ratio);
  read("ucs", c.ucs);
  read("tensile_strength", c.tensile_strength);
  read("density", c.density);
  read("diameter", c.diameter);
  read("lattice", c.lattice);
  read("friction", c.friction);
  read("friction_strengthens_bonds", c.friction_strengthens_bonds);
  read("specimen_width", c.specimen_width);
  read("damping_ratio", c.damping_ratio);
  read("transits_to_peak", c.transits_to_peak);
  read("iterations", c.iterations);
  read("tolerance", c.tolerance);
  read("match", c.match);
  read("strength_spread", c.strength_spread, kSpread);
  read("strength_cov", c.strength_cov);
  read.done();
  return c;
}

}  // namespace strata::scene::tables
