// [[material]]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into MaterialTable.
#include <strata/dem/laws.hpp>

#include "table_file.hpp"

namespace strata::scene::tables {
namespace {
/// The built-in pair laws: the choices of `law`, and their one-line descriptions.
std::vector<std::string> law_names() {
  std::vector<std::string> names;
  for (const auto& l : dem::kLaws) names.emplace_back(l.name);
  return names;
}
std::string law_docs() {
  std::string s;
  for (const auto& l : dem::kLaws) s += fmt::format(" {}: {}.", l.name, l.description);
  return s;
}
}  // namespace

TableSpec material_spec() {
  return {
      "material",
      true,
      true,
      "A bonded-particle material: density, bond stiffnesses and bond strengths of the solid-lattice "
      "law (Liu, Pollard & Shi 2013). Regions refer to a material by its name.",
      {
          K("name", String).required().doc("The material's name, used by the `material` key of [[region]]."),
          K("law", Choice)
              .choices(law_names())
              .def(R"("solid_lattice")")
              .doc("Force law between particles (all materials of a model use the same one)." + law_docs()),
          K("density", Real, "kg/m^2 in 2D, kg/m^3 in 3D")
              .required()
              .gt(0)
              .doc("Mass density: per unit thickness in 2D (a disk of diameter d has mass "
                   "ρ·(√3/2)·d², the area per disk of the hexagonal lattice), per volume in 3D."),
          K("kn", Real, "N/m")
              .gt(0)
              .doc("Kn: normal stiffness of a bond or contact, Fn = Kn·Un with Un the overlap, "
                   "compression positive (Liu, Pollard & Shi 2013). Required for a material of particle "
                   "regions, and of FEM regions without youngs_modulus (their continuum is the "
                   "lattice's)."),
          K("ks", Real, "N/m")
              .ge(0)
              .doc("Ks: shear stiffness, Fs = Ks·Us with Us the shear displacement accumulated since "
                   "the contact formed (Liu, Pollard & Shi 2013). Required with kn."),
          K("friction", Real)
              .ge(0)
              .def("0.0")
              .doc("μ: friction coefficient. A broken bond whose particles still touch carries "
                   "|Fs| ≤ μ·Fn and no tension (Liu, Pollard & Shi 2013)."),
          K("tensile_strength", Real, "N")
              .ge(0)
              .allow_inf()
              .def("inf")
              .doc("Fn_max: a bond breaks in tension when its normal force falls below −Fn_max "
                   "(Liu, Pollard & Shi 2013). inf: bonds never break in tension."),
          K("shear_strength", Real, "N")
              .ge(0)
              .allow_inf()
              .def("inf")
              .doc("Fs0: an intact bond breaks in shear when |Fs| exceeds Fs0 (Fs0 + μ·Fn with "
                   "friction_strengthens_bonds). inf: bonds never break in shear."),
          K("friction_strengthens_bonds", Bool)
              .def("true")
              .doc("Shear limit of an intact bond: Fs0 + μ·max(Fn, 0) when true (criterion (5) of Li et al. "
                   "2017, the default: at that paper's settings it gives the peak at strain 3.06e-3 against "
                   "its 2.8e-3), Fs0 alone when false (peak at 1.80e-3). See docs/dem.md."),
          K("youngs_modulus", Real, "Pa")
              .gt(0)
              .doc("E of the material where it fills an FEM region; give it with poisson_ratio. Default: "
                   "the continuum of the material's lattice, 2D E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks) per unit "
                   "thickness t, 3D the isotropic average 2√2·Kn(2Kn+3Ks)/(d(4Kn+Ks)) at the particle "
                   "regions' diameter d (Liu, Pollard & Shi 2013), so that particles and elements of one "
                   "material match across an overlap."),
          K("poisson_ratio", Real)
              .gt(-1)
              .lt(0.5)
              .doc("ν of the material where it fills an FEM region (with youngs_modulus). Default: the "
                   "lattice's, (Kn−Ks)/(3Kn+Ks) in 2D, (Kn−Ks)/(4Kn+Ks) in 3D."),
      }};
}

MaterialTable read_material(const Table& t) {
  Reader read(t, "material");
  MaterialTable m;
  m.pos = t.where();
  read("name", m.name);
  read("law", m.law);
  read("density", m.density);
  read("kn", m.kn);
  read("ks", m.ks);
  read("friction", m.friction);
  read("tensile_strength", m.tensile_strength);
  read("shear_strength", m.shear_strength);
  read("friction_strengthens_bonds", m.friction_strengthens_bonds);
  read("youngs_modulus", m.youngs_modulus);
  read("poisson_ratio", m.poisson_ratio);
  read.done();
  return m;
}

}  // namespace strata::scene::tables
