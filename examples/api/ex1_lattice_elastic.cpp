//                       strata example 1: elastic constants of a hexagonal lattice
//
// Compile with: cmake --build build --target ex1_lattice_elastic
//
// Sample runs:  ex1_lattice_elastic
//               ex1_lattice_elastic --rows 60 --columns 60
//               ex1_lattice_elastic --rows 20 --columns 20 --tolerance 0.005
//
// Description:  This example builds a 2D block of equal disks in a hexagonal lattice, bonds
//               every touching pair with the solid-lattice law (linear normal and shear
//               springs Kn, Ks; Liu, Pollard & Shi 2013), squeezes it quasi-statically
//               between two frictionless platens and measures its Young's modulus and
//               Poisson's ratio. It compares them with the analytical values of the
//               infinite lattice (plane stress, per unit thickness t):
//
//                   E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks),      ν = (Kn−Ks)/(3Kn+Ks),
//
//               and returns non-zero when either differs by more than the tolerance.
//
//               It shows the library API without a scene file: a lattice from
//               strata::preprocess, a strata::dem::Simulation with a material, particles,
//               bonds, named groups and boundary conditions, a checked time step, dynamic
//               relaxation with local damping, and the probes that give stress and strain.
//
//               Stress and strain are measured over the interior of the block (its middle
//               half in x and y), away from the platen rows and the free sides, which are
//               softer than the infinite lattice. The free sides also leave a small lateral
//               stress in the interior (it falls as 1/n with the block size n), so the plain
//               ratios σ/ε and −ε_lateral/ε_axial read ν about 1.6 % low on the default
//               40 × 40 block; step 10 corrects for it, after which both constants agree
//               with the lattice values to better than 0.1 % (the check allows 1 %).
#include <strata/core/error.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/lattice.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

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
  namespace dem = strata::dem;
  namespace pre = strata::preprocess;
  const auto start = std::chrono::steady_clock::now();

  // 1. Parse the command line: block size (rows, disks per row) and the accepted relative
  //    difference between measured and analytical constants.
  int rows = 40, columns = 40;
  double tolerance = 0.01;  // the tolerance tests/dem/test_elastic.cpp uses for a 60 × 60 block
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--rows" && i + 1 < argc) {
      rows = std::atoi(argv[++i]);
    } else if (a == "--columns" && i + 1 < argc) {
      columns = std::atoi(argv[++i]);
    } else if (a == "--tolerance" && i + 1 < argc) {
      tolerance = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: %s [--rows N] [--columns N] [--tolerance T]\n", argv[0]);
      return 2;
    }
  }
  if (rows < 8 || columns < 8 || !(tolerance > 0)) {
    std::fprintf(stderr, "need --rows >= 8, --columns >= 8 and --tolerance > 0\n");
    return 2;
  }

  try {
    // 2. The material: the rock of Liu, Pollard & Shi (2013) for disks of d = 1 mm, with
    //    unbreakable bonds (strengths left at +infinity) since we only want the elastic
    //    response. Density is per unit thickness in 2D (kg/m²); a disk's mass is
    //    ρ·(√3/2)·d², the area of its hexagonal cell.
    const double d = 1e-3;  // disk diameter (m)
    dem::Material rock;
    rock.density = 2650.0;  // kg/m²
    rock.kn = 6.587e10;     // normal bond stiffness Kn (N/m)
    rock.ks = 2.371e10;     // shear bond stiffness Ks (N/m)

    const double kn = rock.kn, ks = rock.ks;
    const double E_lattice = 2 * std::sqrt(3.0) * kn * (kn + ks) / (3 * kn + ks);  // E·t (N/m)
    const double nu_lattice = (kn - ks) / (3 * kn + ks);

    // 3. The lattice: `rows` rows of disks along x, spaced d·√3/2, odd rows shifted by d/2
    //    and one disk shorter so that both sides are straight. Sites are listed row by row
    //    from the bottom, which is also the order of the particle ids below.
    const pre::Lattice lattice = pre::hex2d_rows(rows, columns, d);

    // 4. The simulation: 2D, local (non-viscous) damping for dynamic relaxation, and no
    //    search for new contacts (bonds never break here, so nothing new can touch). The
    //    time step is set after initialise(), from the critical step of the model.
    dem::Settings settings;
    settings.dt = 1e-12;  // placeholder, replaced by 0.5·critical_dt() below
    settings.damping = dem::Settings::Damping::Local;
    settings.local_alpha = 0.7;
    settings.contact_detection = false;
    dem::Simulation sim(2, settings);

    const int material = sim.add_material(rock);
    sim.reserve(lattice.size());
    for (const auto& x : lattice.x) sim.add_particle(x, lattice.radius, material);
    sim.bond_touching_pairs();  // every pair at distance d is bonded

    // 5. Boundary conditions: the bottom row is a frictionless platen (held along y, free
    //    along x), the top row another one that will move down. Groups are named sets of
    //    particle ids; the lattice selections return the ids of its rows.
    sim.add_to_group(pre::bottom_row(lattice), "bottom");
    sim.add_to_group(pre::top_row(lattice), "top");
    sim.fix("bottom", dem::kY);

    // 6. Initialise: sort particles, build search structures and compute the critical time
    //    step 2/√λmax of the bonded lattice (for the infinite lattice 2·√(m/(6Kn+2Ks))). A
    //    time step above it would be refused with a strata::Error.
    sim.initialise();
    sim.set_dt(0.5 * sim.critical_dt());
    std::printf("block: %d rows x %d columns, %zu disks, %zu bonds; dt = %.3e s (0.5 x critical %.3e s)\n",
                rows, columns, sim.particle_count(), sim.bond_count(), sim.dt(), sim.critical_dt());

    // 7. Load quasi-statically: move the top platen down to an axial strain of 1e-4 over
    //    4000 steps (about 50 wave transits of the default block), then hold it and let local
    //    damping remove the kinetic energy until the block is at rest (dynamic relaxation).
    double y_lo = 1e9, y_hi = -1e9, x_lo = 1e9, x_hi = -1e9;
    for (const auto& p : lattice.x) {
      x_lo = std::min(x_lo, p[0]);
      x_hi = std::max(x_hi, p[0]);
      y_lo = std::min(y_lo, p[1]);
      y_hi = std::max(y_hi, p[1]);
    }
    const double height = y_hi - y_lo;
    const int ramp_steps = 4000;
    const double strain_target = 1e-4;
    sim.prescribe_velocity("top", {0, -strain_target * height / (ramp_steps * sim.dt()), 0}, dem::kY);
    sim.run(ramp_steps);
    sim.prescribe_velocity("top", {0, 0, 0}, dem::kY);
    int relax_steps = 0;
    while (relax_steps < 100000 && sim.kinetic_energy() > 1e-14 * sim.bond_energy()) {
      sim.run(500);
      relax_steps += 500;
    }
    std::printf("loaded in %d steps, relaxed in %d more: kinetic / stored energy = %.1e\n", ramp_steps,
                relax_steps, sim.kinetic_energy() / sim.bond_energy());
    if (!(sim.kinetic_energy() < 1e-9 * sim.bond_energy())) {
      std::fprintf(stderr, "dynamic relaxation did not converge\n");
      return 1;
    }

    // 8. Strains: least-squares fits of the displacements of the interior particles (the
    //    middle half of the block in x and y, away from the platens and the free sides)
    //    against their initial positions. Read-access functions return arrays in the
    //    model's internal (spatially sorted) order; initial position = position − displacement.
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
    const double strain_axial = slope(y0, uy);    // negative: shortening along y
    const double strain_lateral = slope(x0, ux);  // positive: the block widens

    // 9. Stresses over the same interior, from the bond forces (virial): σ_aa = −(1/A) Σ_b
    //    f_a·l_a, summed over the bonds with half of each bond to each end particle, with
    //    A = (number of interior particles) × (hexagonal cell area (√3/2)·d²); compression
    //    is positive. The platen reaction over the block width gives a cruder axial figure
    //    that includes the softer rows next to the platens.
    double virial[2] = {0, 0};
    for (const auto& b : sim.bonds()) {
      const double w = 0.5 * (interior[b.i] + interior[b.j]);
      if (w == 0) continue;
      for (int a = 0; a < 2; ++a) virial[a] += w * b.force_on_i[a] * (x[b.j][a] - x[b.i][a]);
    }
    const double area = static_cast<double>(n_interior) * std::sqrt(3.0) / 2 * d * d;
    const double stress_axial = -virial[1] / area;    // N/m (stress × thickness)
    const double stress_lateral = -virial[0] / area;  // N/m, small: the free sides are far
    const double stress_platen = sim.group_force("top")[1] / (columns * d);  // N/m

    // 10. Elastic constants. The interior is not quite in uniaxial stress: the free sides
    //     leave a small lateral stress q = σ_lateral/σ_axial in it (the 1/n surface effect).
    //     For an isotropic 2D solid ε_a = (σ_a − ν·σ_l)/E and ε_l = (σ_l − ν·σ_a)/E, so with
    //     r = −ε_l/ε_a: ν = (r + q)/(1 + q·r) and E = (σ_a/−ε_a)·(1 − ν·q). With q = 0 these
    //     are the plain ratios, printed too.
    const double q = stress_lateral / stress_axial, r = -strain_lateral / strain_axial;
    const double nu_plain = r, E_plain = stress_axial / -strain_axial;
    const double nu = (r + q) / (1 + q * r);
    const double E = E_plain * (1 - nu * q);
    std::printf("interior: strains %.4e (axial) %.4e (lateral); stresses %.4e (axial) %.4e (lateral) N/m\n",
                strain_axial, strain_lateral, stress_axial, stress_lateral);
    std::printf("platen stress %.4e N/m; E*t from it and the interior strain: %.4e N/m\n", stress_platen,
                stress_platen / -strain_axial);

    // 11. Compare with the lattice values.
    const double dE = E / E_lattice - 1, dnu = nu / nu_lattice - 1;
    std::printf("%-26s %13s %13s %13s %8s\n", "", "plain ratio", "corrected", "analytical", "diff");
    std::printf("%-26s %13.5e %13.5e %13.5e %+7.2f%%\n", "Young's modulus E*t (N/m)", E_plain, E, E_lattice,
                100 * dE);
    std::printf("%-26s %13.5f %13.5f %13.5f %+7.2f%%\n", "Poisson's ratio", nu_plain, nu, nu_lattice,
                100 * dnu);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const bool ok = std::abs(dE) <= tolerance && std::abs(dnu) <= tolerance;
    std::printf("%s: corrected E and nu %s within %.1f%% of the lattice values (%.2f s)\n",
                ok ? "PASS" : "FAIL", ok ? "are" : "are NOT", 100 * tolerance, seconds);
    return ok ? 0 : 1;
  } catch (const strata::Error& e) {
    std::fprintf(stderr, "strata: error: %s\n", e.what());
    return 1;
  }
}
