//                       strata example 2: a custom pair law
//
// Compile with: cmake --build build --target ex2_custom_law
//               or, by hand against a build of the libraries in build/:
//               g++ -std=c++20 -O2 -fopenmp -I libdem/include -I libcore/include -I build/generated
//                   -I preprocess/include examples/api/ex2_custom_law.cpp build/lib/libstrata_dem.a
//                   build/lib/libstrata_preprocess.a build/lib/libstrata_core.a -lspdlog -lfmt
//
// Sample runs:  ex2_custom_law
//               ex2_custom_law --rows 60 --columns 60
//               ex2_custom_law --strain 3e-3 --tolerance 0.02
//
// Description:  This example adds a force law of its own to the DEM without changing
//               strata: a linear-elastic bond that never breaks. It registers the law under
//               a name, gives a material that name, and pulls a 2D hexagonal block of bonded
//               disks apart between two platens to an axial strain of 1e-3 — well beyond
//               the strain at which the rock's solid-lattice bonds (Liu, Pollard & Shi 2013)
//               would fail in tension. With the custom law no bond breaks, and the block's
//               measured Young's modulus must match the analytical value of the infinite
//               lattice (plane stress, per unit thickness t):
//
//                   E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks)
//
//               within the tolerance (default 1 %); the program returns non-zero otherwise
//               or if a bond broke.
//
//               A pair law is a small struct: its parameters and inline functions that
//               advance one pair by one step. register_law<Law>() compiles the DEM's step
//               loop for it in this program (the step loop is a template over the law; the
//               law is looked up by name once, when the model is initialised, never per
//               pair). strata/dem/laws.hpp lists what a law provides.
//
//               The modulus is measured as in example 1: stress from the bond forces and
//               strain from a fit of the displacements, both over the middle half of the
//               block, with the correction for the small lateral stress the free sides
//               leave in it.
#include <strata/core/error.hpp>
#include <strata/dem/register_law.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/lattice.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

namespace dem = strata::dem;
namespace ps = strata::dem::pair_state;

// The custom law: linear springs Fn = Kn·Un, Fs = Ks·Us on every bond, whatever their
// length or shear; it never breaks a bond. Pairs that were never bonded (contacts, found
// when contact detection is on) push with Kn·Un while they overlap and carry no shear.
struct LinearElasticLaw {
  // The name a Material's `law` uses, and one line for lists of laws.
  static constexpr const char* kName = "linear_elastic";
  static constexpr const char* kDescription = "linear normal and shear springs; bonds never break";

  double kn = 0, ks = 0;  // normal and shear stiffness (N/m)

  // The law of a pair of particles of material m (for two materials, strata passes the
  // pair's combined material: harmonic-mean stiffnesses). The strengths are not used.
  static LinearElasticLaw from_material(const dem::Material& m) { return {m.kn, m.ks}; }
  // The law with both stiffnesses times f (intact bonds of eccentric lattices).
  LinearElasticLaw scaled(double f) const { return {kn * f, ks * f}; }
  // Stiffnesses for the critical time step.
  dem::PairStiffness stiffness() const { return {kn, ks}; }

  // Reference kernel: one pair, one step. st: the pair's state byte; un: overlap (m,
  // compression positive); us: shear displacement (NS components, 1 in 2D, 3 in 3D), the
  // stored one plus this step's increment, turned into the current tangent plane; dus:
  // the increment alone (this law does not need it).
  template <int NS>
  dem::PairOutcome<NS> apply(std::uint8_t& st, double un, double* us, const double* /*dus*/) const {
    dem::PairOutcome<NS> o;
    if ((st & ps::kKindMask) == ps::kIntact) {
      o.fn = kn * un;
      for (int a = 0; a < NS; ++a) o.fs[a] = ks * us[a];
      return o;
    }
    for (int a = 0; a < NS; ++a) us[a] = 0;  // contact: frictionless, no tension
    if (un > 0) {
      st |= ps::kTouching;
      o.fn = kn * un;
    } else {
      st = static_cast<std::uint8_t>(st & ~ps::kTouching);
    }
    return o;
  }

  // Stored energy of a pair (J).
  template <int NS>
  double energy(std::uint8_t st, double un, const double* us) const {
    if ((st & ps::kKindMask) != ps::kIntact) return un > 0 ? 0.5 * kn * un * un : 0.0;
    double u2 = 0;
    for (int a = 0; a < NS; ++a) u2 += us[a] * us[a];
    return 0.5 * kn * un * un + 0.5 * ks * u2;
  }

  // Optional batch form: `apply` and `energy` for one bond without branches, so that the
  // bond pass vectorises it; the same expressions in the same order, so both forms give
  // the same bits. Here the bond pass has already added this step's increment to b.us and
  // summed b.u2 = |b.us|²; kBroken = false promises an intact bond. (Without this member
  // every bond would take `apply`: correct, slower.)
  template <int NS, bool kBroken, bool kEnergy>
  dem::BondLaneResult<NS> lane(const dem::BondLane<NS>& b) const {
    const bool intact = !kBroken || b.st == ps::kIntact;
    const bool touch = b.un > 0;
    const double kni = kn * b.kf, ksi = ks * b.kf;
    dem::BondLaneResult<NS> o;
    o.fn = intact ? kni * b.un : (touch ? kn * b.un : 0.0);
    for (int a = 0; a < NS; ++a) {
      o.us[a] = intact ? b.us[a] : 0.0;
      o.fs[a] = ksi * o.us[a];
    }
    o.st = intact ? b.st : (touch ? (b.st | ps::kTouching) : (b.st & ~std::int64_t{ps::kTouching}));
    o.done = true;  // no bond ever needs the reference kernel: none breaks
    if constexpr (kEnergy)
      o.energy = intact ? 0.5 * kni * b.un * b.un + 0.5 * ksi * b.u2 : (touch ? 0.5 * kn * b.un * b.un : 0.0);
    return o;
  }
};

// Least-squares slope of u against x: the strain du/dx of a linear displacement field.
double slope(const std::vector<double>& x, const std::vector<double>& u) {
  double mx = 0, mu = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    mu += u[i];
  }
  mx /= static_cast<double>(x.size());
  mu /= static_cast<double>(x.size());
  double sxx = 0, sxu = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxu += (x[i] - mx) * (u[i] - mu);
  }
  return sxu / sxx;
}

}  // namespace

int main(int argc, char* argv[]) {
  namespace pre = strata::preprocess;

  // 1. Parse the command line: block size, axial strain and the accepted relative
  //    difference between the measured and the analytical modulus.
  int rows = 40, columns = 40;
  double strain_target = 1e-3, tolerance = 0.01;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--rows" && i + 1 < argc) {
      rows = std::atoi(argv[++i]);
    } else if (a == "--columns" && i + 1 < argc) {
      columns = std::atoi(argv[++i]);
    } else if (a == "--strain" && i + 1 < argc) {
      strain_target = std::atof(argv[++i]);
    } else if (a == "--tolerance" && i + 1 < argc) {
      tolerance = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: %s [--rows N] [--columns N] [--strain S] [--tolerance T]\n", argv[0]);
      return 2;
    }
  }
  if (rows < 8 || columns < 8 || !(strain_target > 0 && strain_target < 0.05) || !(tolerance > 0)) {
    std::fprintf(stderr, "need --rows >= 8, --columns >= 8, 0 < --strain < 0.05 and --tolerance > 0\n");
    return 2;
  }

  try {
    // 2. Register the law. From now on a material may name it; the registry also lists
    //    the laws built into strata.
    dem::register_law<LinearElasticLaw>();
    std::printf("pair laws:\n");
    for (const dem::LawInfo& l : dem::available_laws()) std::printf("  %-15s %s\n", l.name, l.description);

    // 3. The material: the rock of Liu, Pollard & Shi (2013) for disks of d = 1 mm,
    //    including its bond strengths, with the custom law. Density is per unit thickness
    //    in 2D (kg/m²).
    const double d = 1e-3;  // disk diameter (m)
    dem::Material rock;
    rock.density = 2650.0;
    rock.kn = 6.587e10;               // Kn (N/m)
    rock.ks = 2.371e10;               // Ks (N/m)
    rock.tensile_strength = 1.252e4;  // Fn_max (N): what solid-lattice bonds would break at
    rock.shear_strength = 3.690e4;    // Fs0 (N)
    rock.law = LinearElasticLaw::kName;
    const double kn = rock.kn, ks = rock.ks;
    const double E_lattice = 2 * std::sqrt(3.0) * kn * (kn + ks) / (3 * kn + ks);  // E·t (N/m)

    // 4. The lattice: `rows` rows of `columns` disks (odd rows one shorter: straight sides).
    const pre::Lattice lattice = pre::hex2d_rows(rows, columns, d);

    // 5. The simulation: 2D, local damping for dynamic relaxation, no contact search (no
    //    bond breaks, so nothing new can touch). Particles, bonds between touching disks,
    //    and two platens: the bottom row held along y, the top row pulled up; both free
    //    along x (frictionless).
    dem::Settings settings;
    settings.dt = 1e-12;  // replaced by 0.5·critical_dt() after initialise()
    settings.damping = dem::Settings::Damping::Local;
    settings.local_alpha = 0.7;
    settings.contact_detection = false;
    dem::Simulation sim(2, settings);
    const int material = sim.add_material(rock);
    sim.reserve(lattice.size());
    for (const auto& x : lattice.x) sim.add_particle(x, lattice.radius, material);
    sim.bond_touching_pairs();
    sim.add_to_group(pre::bottom_row(lattice), "bottom");
    sim.add_to_group(pre::top_row(lattice), "top");
    sim.fix("bottom", dem::kY);

    // 6. Initialise: this is where the model looks its law up by name and builds the step
    //    loop compiled for it; then the critical time step (from the law's stiffnesses).
    sim.initialise();
    sim.set_dt(0.5 * sim.critical_dt());
    std::printf("block: %d rows x %d columns, %zu disks, %zu bonds, law '%s'; dt = %.3e s\n", rows, columns,
                sim.particle_count(), sim.bond_count(), rock.law.c_str(), sim.dt());

    // 7. Pull quasi-statically: the top platen moves up to the target strain over 4000
    //    steps, then holds while local damping brings the block to rest.
    double x_lo = 1e9, x_hi = -1e9, y_lo = 1e9, y_hi = -1e9;
    for (const auto& p : lattice.x) {
      x_lo = std::min(x_lo, p[0]);
      x_hi = std::max(x_hi, p[0]);
      y_lo = std::min(y_lo, p[1]);
      y_hi = std::max(y_hi, p[1]);
    }
    const int ramp_steps = 4000;
    sim.prescribe_velocity("top", {0, strain_target * (y_hi - y_lo) / (ramp_steps * sim.dt()), 0}, dem::kY);
    sim.run(ramp_steps);
    sim.prescribe_velocity("top", {0, 0, 0}, dem::kY);
    int relax_steps = 0;
    while (relax_steps < 100000 && sim.kinetic_energy() > 1e-14 * sim.bond_energy()) {
      sim.run(500);
      relax_steps += 500;
    }
    if (!(sim.kinetic_energy() < 1e-9 * sim.bond_energy())) {
      std::fprintf(stderr, "dynamic relaxation did not converge\n");
      return 1;
    }

    // 8. The bonds: the largest tension against the rock's tensile strength, and the number
    //    of broken bonds (none with this law).
    double tension = 0;
    for (const auto& b : sim.bonds()) tension = std::max(tension, -b.fn);
    std::printf(
        "pulled in %d steps, relaxed in %d more; largest bond tension %.3e N = %.1f x Fn_max, "
        "%zu broken bonds\n",
        ramp_steps, relax_steps, tension, tension / rock.tensile_strength, sim.broken_count());

    // 9. Strains over the interior (middle half of the block in x and y): least-squares
    //    fits of the displacements against the initial positions (position − displacement).
    const auto x = sim.positions();
    const auto u = sim.displacements();
    std::vector<char> interior(x.size(), 0);
    std::vector<double> x0, ux, y0, uy;
    std::size_t n_interior = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double sx = (x[i][0] - u[i][0] - x_lo) / (x_hi - x_lo);
      const double sy = (x[i][1] - u[i][1] - y_lo) / (y_hi - y_lo);
      if (sx <= 0.25 || sx >= 0.75 || sy <= 0.25 || sy >= 0.75) continue;
      interior[i] = 1;
      ++n_interior;
      x0.push_back(x[i][0] - u[i][0]);
      ux.push_back(u[i][0]);
      y0.push_back(x[i][1] - u[i][1]);
      uy.push_back(u[i][1]);
    }
    const double strain_axial = slope(y0, uy);    // positive: stretched along y
    const double strain_lateral = slope(x0, ux);  // negative: the block narrows

    // 10. Stresses over the same interior from the bond forces (virial), tension positive:
    //     σ_aa = (1/A) Σ_b f_a·l_a with half of each bond to each end particle and A the
    //     interior particles' hexagonal cells, (√3/2)·d² each.
    double virial[2] = {0, 0};
    for (const auto& b : sim.bonds()) {
      const double w = 0.5 * (interior[b.i] + interior[b.j]);
      if (w == 0) continue;
      for (int a = 0; a < 2; ++a) virial[a] += w * b.force_on_i[a] * (x[b.j][a] - x[b.i][a]);
    }
    const double area = static_cast<double>(n_interior) * std::sqrt(3.0) / 2 * d * d;
    const double stress_axial = virial[1] / area, stress_lateral = virial[0] / area;  // N/m

    // 11. Young's modulus, corrected for the small lateral stress q = σ_l/σ_a the free sides
    //     leave in the interior (isotropic 2D solid: ν = (r + q)/(1 + q·r) with
    //     r = −ε_l/ε_a, and E = (σ_a/ε_a)·(1 − ν·q)).
    const double q = stress_lateral / stress_axial, r = -strain_lateral / strain_axial;
    const double nu = (r + q) / (1 + q * r);
    const double E = stress_axial / strain_axial * (1 - nu * q);

    // 12. Compare with the lattice value; fail on a larger difference or a broken bond.
    const double diff = E / E_lattice - 1;
    std::printf("interior strain %.4e, stress %.4e N/m: E*t = %.5e N/m, analytical %.5e N/m (%+.2f%%)\n",
                strain_axial, stress_axial, E, E_lattice, 100 * diff);
    const bool ok = std::abs(diff) <= tolerance && sim.broken_count() == 0;
    std::printf("%s: E*t within %.1f%% of the lattice value and no broken bond\n", ok ? "PASS" : "FAIL",
                100 * tolerance);
    return ok ? 0 : 1;
  } catch (const strata::Error& e) {
    std::fprintf(stderr, "strata: error: %s\n", e.what());
    return 1;
  }
}
