// Elastic constants of lattice blocks against the analytical lattice values (Liu, Pollard &
// Shi 2013).
#include "dem_test_util.hpp"

#include <gtest/gtest.h>
#include <strata/dem/lattice_elastic.hpp>

#include <cmath>
#include <cstdio>

using namespace strata;
using namespace strata::dem;
using namespace strata::dem::test;

namespace {
struct Measured {
  double E, nu;
  double lateral_over_axial;  // interior lateral / axial stress (0 in an ideal uniaxial test)
};

// Least-squares slope of u against x.
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

// Uniaxial compression between frictionless platens (top/bottom rows or layers move along
// the loading axis only, lateral motion free), solved statically by dynamic relaxation
// with local damping. Stress from the platen force over the cross-section; strains from a
// least-squares fit of the displacements of the interior particles (middle half of the
// block in every direction), away from the platens and the free sides.
Measured measure(int dim, const preprocess::Lattice& lat, double cross_section) {
  const Material m = rock_material(false);
  Simulation sim(
      dim,
      Settings{
          .dt = 1e-12, .damping = Settings::Damping::Local, .local_alpha = 0.7, .contact_detection = false});
  add_lattice(sim, lat, sim.add_material(m));
  sim.add_to_group(preprocess::top_row(lat), "top");
  sim.add_to_group(preprocess::bottom_row(lat), "bottom");
  const int ax = dim - 1;
  const unsigned axm = 1u << ax;
  double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
  for (const auto& p : lat.x)
    for (int a = 0; a < dim; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  const double height = hi[ax] - lo[ax];
  sim.fix("bottom", axm);
  std::array<double, 3> vt{0, 0, 0};
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(0.5 * sim.critical_dt());
  // ramp the top platen to a strain of 1e-4 over 4000 steps, then hold and relax
  const int ramp = 4000;
  vt[ax] = -1e-4 * height / (ramp * sim.dt());
  sim.prescribe_velocity("top", vt, axm);
  sim.run(ramp);
  sim.prescribe_velocity("top", {0, 0, 0}, axm);
  for (int k = 0; k < 200; ++k) {
    sim.run(500);
    if (sim.kinetic_energy() < 1e-14 * sim.bond_energy()) break;
  }
  EXPECT_LT(sim.kinetic_energy(), 1e-9 * sim.bond_energy()) << "dynamic relaxation did not converge";
  const auto x = sim.positions();
  const auto u = sim.displacements();
  std::vector<double> coord[3], disp[3];
  std::vector<char> inside(x.size(), 0);
  std::size_t n_inside = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    bool in = true;
    for (int a = 0; a < dim; ++a) {
      const double s = (x[i][a] - u[i][a] - lo[a]) / (hi[a] - lo[a]);
      in = in && s > 0.25 && s < 0.75;
    }
    if (!in) continue;
    inside[i] = 1;
    ++n_inside;
    for (int a = 0; a < dim; ++a) {
      coord[a].push_back(x[i][a] - u[i][a]);
      disp[a].push_back(u[i][a]);
    }
  }
  // interior axial stress from the bond virial: σ = (1/V) Σ_p ½ Σ_b f_b·l_b over the
  // interior particles p (half of each bond to each end), V = n·(cell measure)
  double virial[3] = {0, 0, 0};
  for (const auto& b : sim.bonds()) {
    const double w = 0.5 * (inside[b.i] + inside[b.j]);
    if (w > 0)
      for (int a = 0; a < dim; ++a) virial[a] += w * b.force_on_i[a] * (x[b.j][a] - x[b.i][a]);
  }
  // compression positive: the bond pushes i away from j, force_on_i·l < 0
  const double cell = dim == 2 ? std::sqrt(3.0) / 2 * kRockD * kRockD : std::pow(kRockD, 3) / std::sqrt(2.0);
  double sig[3];
  for (int a = 0; a < dim; ++a) sig[a] = -virial[a] / (static_cast<double>(n_inside) * cell);
  const double platen = sim.group_force("top")[ax] / cross_section;
  const double e_axial = slope(coord[ax], disp[ax]);
  double e_lat = 0, s_lat = 0;
  for (int a = 0; a < ax; ++a) {
    e_lat += slope(coord[a], disp[a]) / ax;
    s_lat += sig[a] / ax;
  }
  std::printf("interior stress axial %.5e lateral %.5e, platen stress %.5e, strains %.4e %.4e\n", sig[ax],
              s_lat, platen, e_axial, e_lat);
  return {sig[ax] / -e_axial, -e_lat / e_axial, s_lat / sig[ax]};
}
}  // namespace

TEST(Elastic, HexBlockMatchesLatticeConstants) {
  // E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks), ν = (Kn−Ks)/(3Kn+Ks). A 60-row x 60-column
  // block; stress from the bond virial and strains from a displacement fit, both over the
  // interior (middle half in x and y): within 1 %.
  const double kn = 6.587e10, ks = 2.371e10;
  const auto [E, nu] = dem::hex_elastic(kn, ks);
  const int rows = 60, cols = 60;
  const auto lat = preprocess::hex2d_rows(rows, cols, kRockD);
  const Measured r = measure(2, lat, cols * kRockD);  // width per row: cols·d
  // The finite block's free edges leave a small lateral stress in the interior (measured
  // 0.2 % of the axial one, the 1/n surface effect): with the interior stresses and strains
  // of an isotropic 2D solid, ε_a = (σ_a - ν σ_l)/E and ε_l = (σ_l - ν σ_a)/E, so
  // ν = (q + r)/(1 + q r) with q = σ_l/σ_a (stresses compression positive) and r = -ε_l/ε_a.
  const double q = r.lateral_over_axial, rr = r.nu;
  const double nu_c = (rr + q) / (1 + q * rr);
  const double E_c = r.E * (1 - nu_c * q);
  EXPECT_NEAR(E_c / E, 1.0, 0.01) << "E = " << E_c << " expected " << E;
  EXPECT_NEAR(nu_c / nu, 1.0, 0.01) << "nu = " << nu_c << " expected " << nu;
  // without the correction the interior values are still within 2 %
  EXPECT_NEAR(r.E / E, 1.0, 0.02);
  EXPECT_NEAR(r.nu / nu, 1.0, 0.02);
}

TEST(Elastic, HcpBlockAlongCAxisMatchesLatticeConstants) {
  // Along the HCP c-axis E = 6√2·Kn(Kn+Ks)/(d(5Kn+Ks)), ν = (Kn−Ks)/(5Kn+Ks).
  // 20 x 20 x 20 mm block (~9000 spheres), interior stress (bond virial) and strains
  // (middle half of the block): within 3 % (the remaining 1/n surface effect: a 14 mm
  // block gives ν 4 % low; the lateral interior stress is 0.3 % of the axial one).
  const double kn = 6.587e10, ks = 2.371e10, d = kRockD;
  const auto [E, nu] = dem::close_packed_stacking_axis_elastic(kn, ks, d);
  const auto lat =
      preprocess::close_packed_box(preprocess::Packing::HCP, {0, 0, 0}, {20e-3, 20e-3, 20e-3}, d);
  const double area = static_cast<double>(preprocess::top_layer(lat).size()) * std::sqrt(3.0) / 2 * d * d;
  const Measured r = measure(3, lat, area);
  EXPECT_NEAR(r.E / E, 1.0, 0.03) << "E = " << r.E << " expected " << E;
  EXPECT_NEAR(r.nu / nu, 1.0, 0.03) << "nu = " << r.nu << " expected " << nu;
}
