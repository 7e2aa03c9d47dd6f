// Coupled models of any interface between particle regions and FEM regions of a gmsh
// geometry (preprocess::build_coupled_model, general path; docs/preprocess.md): curved,
// inclined, several interfaces, 2D and 3D. Every model is checked for the invariants the
// coupling relies on (check_model), and the box path for its previous result.
#include <gtest/gtest.h>
#include <strata/config.hpp>
#include <strata/core/clock.hpp>
#include <strata/core/error.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/overlap.hpp>

#include "test_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <random>
#include <set>

namespace sp = strata::preprocess;
using sp::OverlapTag;
using sp::Vec3;

namespace {

bool verbose() { return std::getenv("STRATA_TEST_VERBOSE") != nullptr; }

double dist(const Vec3& a, const Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

/// Signed distance to a region's boundary, negative inside.
using Sdf = std::function<double(const Vec3&)>;

[[maybe_unused]] Sdf disk(double cx, double cy, double R) {
  return [=](const Vec3& p) { return std::hypot(p[0] - cx, p[1] - cy) - R; };
}
[[maybe_unused]] Sdf ball(Vec3 c, double R) {
  return [=](const Vec3& p) { return dist(p, c) - R; };
}
/// Convex polygon (counter-clockwise), exact for points near its sides.
[[maybe_unused]] Sdf convex_polygon(std::vector<std::array<double, 2>> v) {
  return [v](const Vec3& p) {
    double out = -HUGE_VAL;
    for (std::size_t k = 0; k < v.size(); ++k) {
      const auto& a = v[k];
      const auto& b = v[(k + 1) % v.size()];
      const double ex = b[0] - a[0], ey = b[1] - a[1], len = std::hypot(ex, ey);
      out = std::max(out, (ey * (p[0] - a[0]) - ex * (p[1] - a[1])) / len);  // outward normal (ey, -ex)
    }
    return out;
  };
}

/// What a test knows about its geometry.
struct Expect {
  std::vector<Sdf> particle_sdf;         ///< per particle region
  std::vector<double> particle_measure;  ///< per particle region (m² / m³)
  std::vector<double> fem_measure;       ///< per FEM region
  double measure_tol = 1e-9;             ///< relative, for the FEM groups (curved: chord error)
  /// How far (in d) the mesh's piecewise-linear Γ may stray from the exact one: the chord
  /// error, about (d/√3)²/(2R) for triangles of edge d on a sphere of radius R.
  double chord = 0.02;
  sp::Vec3 lo{}, hi{};           ///< the union of all regions is this box
  bool sites_near_gamma = true;  ///< some particle-region site lies within d/2 of Γ
};

double signed_measure(const sp::SimplexMesh& m, std::size_t e) {
  const int np = m.nodes_per_cell();
  const std::uint32_t* c = &m.cells[e * std::size_t(np)];
  const Vec3 a = m.node(c[0]), b = m.node(c[1]), cc = m.node(c[2]);
  const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
               ac[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
  if (m.dim == 2) return 0.5 * (ab[0] * ac[1] - ab[1] * ac[0]);
  const Vec3 dd = m.node(c[3]);
  const double ad[3] = {dd[0] - a[0], dd[1] - a[1], dd[2] - a[2]};
  return (ab[0] * (ac[1] * ad[2] - ac[2] * ad[1]) - ab[1] * (ac[0] * ad[2] - ac[2] * ad[0]) +
          ab[2] * (ac[0] * ad[1] - ac[1] * ad[0])) /
         6.0;
}

/// Angle (2D) or solid angle (3D, Van Oosterom & Strackee 1983) of element e at its local
/// vertex k.
double corner_angle(const sp::SimplexMesh& m, std::size_t e, int k) {
  const int np = m.nodes_per_cell();
  const std::uint32_t* c = &m.cells[e * std::size_t(np)];
  const Vec3 o = m.node(c[k]);
  std::vector<Vec3> v;
  for (int j = 0; j < np; ++j)
    if (j != k) {
      const Vec3 p = m.node(c[j]);
      v.push_back({p[0] - o[0], p[1] - o[1], p[2] - o[2]});
    }
  auto dot = [](const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  auto norm = [&](const Vec3& a) { return std::sqrt(dot(a, a)); };
  if (m.dim == 2) return std::acos(std::clamp(dot(v[0], v[1]) / (norm(v[0]) * norm(v[1])), -1.0, 1.0));
  const Vec3 &a = v[0], &b = v[1], &cc = v[2];
  const double triple = a[0] * (b[1] * cc[2] - b[2] * cc[1]) - a[1] * (b[0] * cc[2] - b[2] * cc[0]) +
                        a[2] * (b[0] * cc[1] - b[1] * cc[0]);
  const double la = norm(a), lb = norm(b), lc = norm(cc);
  const double den = la * lb * lc + dot(a, b) * lc + dot(a, cc) * lb + dot(b, cc) * la;
  return 2 * std::abs(std::atan2(triple, den));
}

/// A hash grid of points for the tests' own neighbour counts (independent of preprocess's).
struct Grid {
  double h;
  std::map<std::array<long long, 3>, std::vector<std::uint32_t>> cells;
  const std::vector<Vec3>* x;
  Grid(const std::vector<Vec3>& pts, double cell) : h(cell), x(&pts) {
    for (std::uint32_t i = 0; i < pts.size(); ++i) cells[key(pts[i])].push_back(i);
  }
  std::array<long long, 3> key(const Vec3& p) const {
    return {std::llround(std::floor(p[0] / h)), std::llround(std::floor(p[1] / h)),
            std::llround(std::floor(p[2] / h))};
  }
  template <typename F>
  void near(const Vec3& p, double radius, F&& f) const {
    const auto k = key(p);
    for (long long a = -1; a <= 1; ++a)
      for (long long b = -1; b <= 1; ++b)
        for (long long c = -1; c <= 1; ++c) {
          const auto it = cells.find({k[0] + a, k[1] + b, k[2] + c});
          if (it == cells.end()) continue;
          for (auto i : it->second)
            if (dist((*x)[i], p) <= radius) f(i);
        }
  }
};

/// Largest |Σ w·u(x_source) − u(x_target)| over the links for u(x) = a + B·x, relative to
/// max |u| over the sources and targets.
double affine_error(const sp::OverlapLinks& l, const std::vector<Vec3>& to_x, const std::vector<Vec3>& from_x,
                    int dim, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> U(-1, 1);
  double a[3], B[3][3];
  for (int i = 0; i < 3; ++i) {
    a[i] = U(rng);
    for (int j = 0; j < 3; ++j) B[i][j] = U(rng) * 1e3;  // gradients of order 1 over a metre / 1e3
  }
  auto u = [&](const Vec3& x, int c) {
    double s = a[c];
    for (int j = 0; j < dim; ++j) s += B[c][j] * x[std::size_t(j)];
    return s;
  };
  double worst = 0, scale = 0;
  for (std::size_t k = 0; k < l.size(); ++k)
    for (int c = 0; c < dim; ++c) {
      double s = 0;
      for (std::uint32_t j = l.first[k]; j < l.first[k + 1]; ++j) {
        s += l.weight[j] * u(from_x[l.source[j]], c);
        scale = std::max(scale, std::abs(u(from_x[l.source[j]], c)));
      }
      worst = std::max(worst, std::abs(s - u(to_x[l.target[k]], c)));
    }
  return worst / scale;
}

struct Stats {
  std::size_t particles = 0, band = 0, dem_boundary = 0, nodes = 0, fem_external = 0, fem_boundary = 0,
              elements = 0, ring = 0, copies_to_dem = 0, copies_to_fem = 0;
  double max_fit_sources = 0;
};

/// Every invariant of the general construction (overlap.hpp) on one model.
void check_model(const sp::OverlapModel& m, const std::vector<std::string>& particle_regions,
                 const std::vector<std::string>& fem_regions, const Expect& ex, double d, Stats& st) {
  const int dim = m.dim;
  const double r = d / 2, tol = 1e-9 * d, touch = d * (1 + 1e-6);
  const std::size_t np = m.particles.size(), nn = m.fem.node_count(), ne = m.fem.cell_count();
  const std::size_t npr = particle_regions.size(), nfr = fem_regions.size();
  const int npc = dim + 1;
  EXPECT_EQ(m.method, sp::OverlapMethod::General);
  EXPECT_EQ(m.particle_region_names, particle_regions);
  EXPECT_EQ(m.particle_tag.size(), np);
  EXPECT_EQ(m.particle_region.size(), np);
  EXPECT_EQ(m.node_tag.size(), nn);
  EXPECT_EQ(m.particles.radius, r);
  st.particles = np, st.nodes = nn, st.elements = ne;

  std::vector<Vec3> px(m.particles.x.begin(), m.particles.x.end()), nx(nn);
  for (std::size_t n = 0; n < nn; ++n) nx[n] = m.fem.node(n);
  const sp::BoundaryDistance gamma(m.interface_facets);
  EXPECT_GT(m.interface_facets.cell_count(), 0u);
  auto box_distance = [&](const Vec3& p) {
    double w = HUGE_VAL;
    for (int a = 0; a < dim; ++a)
      w = std::min({w, p[std::size_t(a)] - ex.lo[std::size_t(a)], ex.hi[std::size_t(a)] - p[std::size_t(a)]});
    return w;
  };

  // ---- particles: regions, whole inside the union, the band ----
  std::vector<std::size_t> per_region(npr, 0);
  std::size_t near_gamma = 0;
  for (std::size_t i = 0; i < np; ++i) {
    const Vec3& p = px[i];
    EXPECT_GE(box_distance(p), r - tol) << "particle " << i << " not whole inside the union";
    const int k = m.particle_region[i];
    if (k >= 0) {
      ASSERT_LT(std::size_t(k), npr);
      ++per_region[std::size_t(k)];
      EXPECT_NE(m.particle_tag[i], OverlapTag::External) << i;
      EXPECT_LE(ex.particle_sdf[std::size_t(k)](p), 0.02 * d) << "particle " << i << " outside its region";
      near_gamma += gamma(p) < r;
    } else {
      ++st.band;
      EXPECT_EQ(m.particle_tag[i], OverlapTag::External) << i;
      for (const auto& f : ex.particle_sdf)
        EXPECT_GE(f(p), -ex.chord * d) << "band site " << i << " in a particle region";
      EXPECT_LE(gamma(p), touch) << "band site " << i << " farther than d from the interface";
    }
  }
  // particles on the particle side within d/2 of Γ: Γ is no outer boundary
  if (ex.sites_near_gamma) {
    EXPECT_GT(near_gamma, 0u);
  }
  for (std::size_t k = 0; k < npr; ++k) {
    const double expect =
        ex.particle_measure[k] / (dim == 2 ? d * d * std::sqrt(3.0) / 2 : d * d * d / std::sqrt(2.0));
    EXPECT_GT(double(per_region[k]), 0.85 * expect) << particle_regions[k];
    EXPECT_LT(double(per_region[k]), 1.05 * expect) << particle_regions[k];
  }
  // DEM side complete: every band site touches a particle-region site; a particle-region
  // particle whose neighbours all fit whole inside the union (d + r from its boundary) has
  // all of them (6 in 2D, 12 in 3D), band sites across Γ included.
  const Grid grid(px, 1.01 * d);
  for (std::size_t i = 0; i < np; ++i) {
    std::size_t touching = 0, touching_inner = 0;
    grid.near(px[i], touch, [&](std::uint32_t j) {
      if (j == i) return;
      ++touching;
      touching_inner += m.particle_region[j] >= 0;
    });
    if (m.particle_region[i] < 0) {
      EXPECT_GT(touching_inner, 0u) << "band site " << i << " touches no particle of the particle regions";
    } else if (box_distance(px[i]) > d + r + tol) {
      EXPECT_EQ(touching, dim == 2 ? 6u : 12u) << "particle " << i << " misses neighbours";
    }
  }

  // ---- FEM mesh: groups, measures, the ring, complete stars ----
  ASSERT_EQ(m.fem.group_names.size(), nfr + npr);
  for (std::size_t k = 0; k < nfr; ++k) EXPECT_EQ(m.fem.group_names[k], fem_regions[k]);
  for (std::size_t k = 0; k < npr; ++k) {
    EXPECT_EQ(m.fem.group_names[nfr + k], particle_regions[k] + ":ring");
    EXPECT_EQ(m.ring_group(k), int(nfr + k));
  }
  std::vector<char> in_fem_region(nn, 0);
  std::set<std::vector<std::uint32_t>> fem_region_cells;
  std::vector<double> measure(nfr, 0.0);
  double gamma_size = 0, far_size = 0;
  std::size_t far_n = 0;
  for (std::size_t e = 0; e < ne; ++e) {
    const double v = signed_measure(m.fem, e);
    EXPECT_GT(v, 0) << "element " << e;
    const int g = m.fem.cell_group[e];
    ASSERT_TRUE(g >= 0 && std::size_t(g) < nfr + npr);
    std::vector<std::uint32_t> c(&m.fem.cells[e * npc], &m.fem.cells[e * npc] + npc);
    if (std::size_t(g) < nfr) {
      measure[std::size_t(g)] += v;
      for (auto n : c) in_fem_region[n] = 1;
      Vec3 centre{};
      for (auto n : c)
        for (int a = 0; a < 3; ++a) centre[std::size_t(a)] += nx[n][std::size_t(a)] / npc;
      for (const auto& f : ex.particle_sdf)
        EXPECT_GE(f(centre), -ex.chord * d) << "FEM element " << e << " in a particle region";
      // edge of the equilateral triangle / regular tetrahedron of the same measure
      const double edge = dim == 2 ? std::sqrt(4 * v / std::sqrt(3.0)) : std::cbrt(6 * std::sqrt(2.0) * v);
      if (gamma(centre) > (ex.hi[0] - ex.lo[0]) / 8) far_size += edge, ++far_n;
      std::sort(c.begin(), c.end());
      fem_region_cells.insert(c);
    } else {
      ++st.ring;
      Vec3 centre{};
      for (auto n : c)
        for (int a = 0; a < 3; ++a) centre[std::size_t(a)] += nx[n][std::size_t(a)] / npc;
      EXPECT_LE(ex.particle_sdf[std::size_t(g) - nfr](centre), 0.02 * d) << "ring element " << e;
    }
  }
  for (std::size_t k = 0; k < nfr; ++k)
    EXPECT_NEAR(measure[k], ex.fem_measure[k], ex.measure_tol * ex.fem_measure[k]) << fem_regions[k];
  for (std::size_t e = 0; e < ne; ++e) {
    if (std::size_t(m.fem.cell_group[e]) < nfr) continue;
    bool on_gamma = false;
    for (int a = 0; a < npc; ++a) on_gamma = on_gamma || in_fem_region[m.fem.cells[e * npc + a]];
    EXPECT_TRUE(on_gamma) << "ring element " << e << " has no node on the interface";
  }
  for (std::size_t f = 0; f < m.interface_facets.cell_count(); ++f) {
    const auto* c = &m.interface_facets.cells[f * std::size_t(dim)];
    for (int a = 0; a < dim; ++a) EXPECT_TRUE(in_fem_region[c[a]]);
    const Vec3 p = nx[c[0]], q = nx[c[1]];
    gamma_size += dist(p, q);
  }
  gamma_size /= double(m.interface_facets.cell_count());
  EXPECT_GT(gamma_size, 0.6 * d);
  EXPECT_LT(gamma_size, 1.4 * d);
  if (far_n > 0) {
    EXPECT_GT(far_size / double(far_n), 1.5 * d) << "no coarsening away from the interface";
  }
  // the FEM partition's forces are complete at every node it owns: the angles (solid angles)
  // of its elements at the node add up to a full turn (sphere) away from the outer boundary
  std::vector<double> angle(nn, 0.0);
  for (std::size_t e = 0; e < ne; ++e)
    for (int k = 0; k < npc; ++k) angle[m.fem.cells[e * npc + std::size_t(k)]] += corner_angle(m.fem, e, k);
  const double full = dim == 2 ? 2 * M_PI : 4 * M_PI;
  for (std::size_t n = 0; n < nn; ++n) {
    const bool external = m.node_tag[n] == OverlapTag::External;
    EXPECT_EQ(external, !in_fem_region[n]) << "node " << n;
    if (external) {
      ++st.fem_external;
      bool inside = false;
      for (const auto& f : ex.particle_sdf) inside = inside || f(nx[n]) <= ex.chord * d;
      EXPECT_TRUE(inside) << "FEM external node " << n << " outside the particle regions";
      EXPECT_GT(gamma(nx[n]), 0.25 * d) << "FEM external node " << n << " on the interface";
    } else if (box_distance(nx[n]) > tol) {
      EXPECT_NEAR(angle[n], full, 1e-9) << "node " << n << " misses elements";
    }
  }

  // ---- links ----
  std::vector<char> node_used(nn, 0), particle_used(np, 0);
  std::vector<std::uint32_t> band, ext_nodes;
  for (std::uint32_t i = 0; i < np; ++i)
    if (m.particle_tag[i] == OverlapTag::External) band.push_back(i);
  for (std::uint32_t n = 0; n < nn; ++n)
    if (m.node_tag[n] == OverlapTag::External) ext_nodes.push_back(n);
  const auto& fd = m.fem_to_dem;
  const auto& df = m.dem_to_fem;
  EXPECT_EQ(fd.target, band);
  EXPECT_EQ(df.target, ext_nodes);
  ASSERT_EQ(fd.first.size(), fd.size() + 1);
  ASSERT_EQ(df.first.size(), df.size() + 1);
  for (std::size_t k = 0; k < fd.size(); ++k) {
    double s = 0, lowest = HUGE_VAL;
    std::vector<std::uint32_t> src;
    for (auto j = fd.first[k]; j < fd.first[k + 1]; ++j) {
      const auto n = fd.source[j];
      ASSERT_LT(n, nn);
      EXPECT_NE(m.node_tag[n], OverlapTag::External)
          << "DEM external " << fd.target[k] << " reads an FEM external";
      EXPECT_TRUE(in_fem_region[n]);
      node_used[n] = 1;
      s += fd.weight[j];
      lowest = std::min(lowest, fd.weight[j]);
      src.push_back(n);
    }
    EXPECT_NEAR(s, 1.0, 1e-12);
    if (src.size() == 1) {
      ++st.copies_to_dem;
      EXPECT_EQ(fd.weight[fd.first[k]], 1.0);
      EXPECT_LE(dist(nx[src[0]], px[fd.target[k]]), tol);
    } else {
      ASSERT_EQ(src.size(), std::size_t(npc));
      std::sort(src.begin(), src.end());
      EXPECT_TRUE(fem_region_cells.count(src))
          << "DEM external " << fd.target[k] << ": sources are no FEM element";
      EXPECT_GE(lowest, -1e-9) << "DEM external " << fd.target[k] << " outside its element";
    }
  }
  for (std::size_t k = 0; k < df.size(); ++k) {
    double s = 0;
    for (auto j = df.first[k]; j < df.first[k + 1]; ++j) {
      const auto i = df.source[j];
      ASSERT_LT(i, np);
      EXPECT_GE(m.particle_region[i], 0) << "FEM external " << df.target[k] << " reads a band site";
      EXPECT_LE(dist(px[i], nx[df.target[k]]), 3.0 * d + tol);
      particle_used[i] = 1;
      s += df.weight[j];
    }
    EXPECT_NEAR(s, 1.0, 1e-12);
    st.max_fit_sources = std::max(st.max_fit_sources, double(df.first[k + 1] - df.first[k]));
    if (df.first[k + 1] - df.first[k] == 1) {
      ++st.copies_to_fem;
      EXPECT_EQ(df.weight[df.first[k]], 1.0);
      EXPECT_LE(dist(px[df.source[df.first[k]]], nx[df.target[k]]), tol);
    }
  }
  for (std::size_t n = 0; n < nn; ++n) {
    EXPECT_EQ(m.node_tag[n] == OverlapTag::Boundary, bool(node_used[n])) << "node " << n;
    st.fem_boundary += node_used[n];
  }
  for (std::size_t i = 0; i < np; ++i) {
    EXPECT_EQ(m.particle_tag[i] == OverlapTag::Boundary, bool(particle_used[i])) << "particle " << i;
    st.dem_boundary += particle_used[i];
  }
  // patch property: affine fields cross in both directions exactly
  std::mt19937_64 rng(12345);
  for (int trial = 0; trial < 3; ++trial) {
    EXPECT_LT(affine_error(fd, px, nx, dim, rng), 1e-10);
    EXPECT_LT(affine_error(df, nx, px, dim, rng), 1e-10);
  }
  if (verbose())
    std::printf(
        "particles %zu (band %zu, DEM boundary %zu), FEM nodes %zu (external %zu, boundary %zu), elements "
        "%zu "
        "(ring %zu), copies %zu + %zu, largest fit %g particles; interface facets %.3f d\n",
        st.particles, st.band, st.dem_boundary, st.nodes, st.fem_external, st.fem_boundary, st.elements,
        st.ring, st.copies_to_dem, st.copies_to_fem, st.max_fit_sources, gamma_size / d);
}

[[maybe_unused]] Stats check_model(const sp::OverlapModel& m,
                                   const std::vector<std::string>& particle_regions,
                                   const std::vector<std::string>& fem_regions, const Expect& ex, double d) {
  Stats st;
  check_model(m, particle_regions, fem_regions, ex, d, st);
  return st;
}

[[maybe_unused]] sp::OverlapModel timed(const std::string& name, const std::vector<std::string>& p,
                                        const std::vector<std::string>& f, const sp::OverlapOptions& o) {
  const auto t0 = strata::WallClock::now();
  sp::OverlapModel m = sp::build_coupled_model(strata::test::data(name), p, f, o);
  if (verbose()) std::printf("%s: built in %.3f s\n", name.c_str(), strata::seconds_since(t0));
  return m;
}

}  // namespace

#if STRATA_WITH_GMSH

// (a) A disk of particles in a square FEM region: one curved interface.
TEST(OverlapGeneral, DiskInSquare2D) {
  sp::OverlapOptions o;
  o.d = 0.001;
  const auto m = timed("disk_in_square.geo", {"disk"}, {"fem"}, o);
  Expect ex;
  const double R = 0.015;
  ex.particle_sdf = {disk(0.03, 0.03, R)};
  ex.particle_measure = {M_PI * R * R};
  // the FEM region's mesh has chords of about d on the circle: its area exceeds the exact
  // one by the segments, about (2πR)·d²/(12 R) ≈ 5e-4 relative here
  ex.fem_measure = {0.06 * 0.06 - M_PI * R * R};
  ex.measure_tol = 2e-3;
  ex.lo = {0, 0, 0}, ex.hi = {0.06, 0.06, 0};
  const Stats s = check_model(m, {"disk"}, {"fem"}, ex, o.d);
  EXPECT_GT(s.band, 80u);
  EXPECT_GT(s.fem_external, 50u);
}

// (b) A rectangle cut by an inclined line: particles on one side, FEM on the other, the
// interface at about 63° to every lattice row and meeting the outer boundary.
TEST(OverlapGeneral, InclinedCut2D) {
  sp::OverlapOptions o;
  o.d = 0.001;
  const auto m = timed("inclined_cut.geo", {"dem"}, {"fem"}, o);
  Expect ex;
  ex.particle_sdf = {convex_polygon({{0.04, 0}, {0.1, 0}, {0.1, 0.04}, {0.06, 0.04}})};
  ex.particle_measure = {0.05 * 0.04};
  ex.fem_measure = {0.05 * 0.04};
  ex.lo = {0, 0, 0}, ex.hi = {0.1, 0.04, 0};
  check_model(m, {"dem"}, {"fem"}, ex, o.d);
}

// (c1) Two particle inclusions (a disk, a tilted square) in one FEM matrix: two particle
// regions, each with its own interface; every particle knows its region.
TEST(OverlapGeneral, TwoInclusions2D) {
  sp::OverlapOptions o;
  o.d = 0.001;
  const auto m = timed("two_inclusions.geo", {"inc_a", "inc_b"}, {"matrix"}, o);
  Expect ex;
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  std::vector<std::array<double, 2>> sq;
  for (auto [u, v] : std::vector<std::array<double, 2>>{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
    sq.push_back({0.055 + 0.01 * (c * u - s * v), 0.025 + 0.01 * (s * u + c * v)});
  ex.particle_sdf = {disk(0.022, 0.025, 0.012), convex_polygon(sq)};
  ex.particle_measure = {M_PI * 0.012 * 0.012, 0.02 * 0.02};
  ex.fem_measure = {0.08 * 0.05 - ex.particle_measure[0] - ex.particle_measure[1]};
  ex.measure_tol = 2e-3;
  ex.lo = {0, 0, 0}, ex.hi = {0.08, 0.05, 0};
  check_model(m, {"inc_a", "inc_b"}, {"matrix"}, ex, o.d);
  // the band of each inclusion lies around that inclusion
  for (std::size_t k = 0; k < m.dem_to_fem.size(); ++k)
    for (auto j = m.dem_to_fem.first[k]; j < m.dem_to_fem.first[k + 1]; ++j) {
      const int reg = m.particle_region[m.dem_to_fem.source[j]];
      const Vec3 x = m.fem.node(m.dem_to_fem.target[k]);
      EXPECT_LE(ex.particle_sdf[std::size_t(reg)](x), 0.02 * o.d);
    }
}

// (c2) FEM | DEM | FEM with inclined interfaces: one particle strip, two interfaces, two
// FEM regions (groups in the order given).
TEST(OverlapGeneral, InclinedStripBetweenTwoFemBlocks2D) {
  sp::OverlapOptions o;
  o.d = 0.001;
  const auto m = timed("inclined_strip.geo", {"strip"}, {"left", "right"}, o);
  Expect ex;
  ex.particle_sdf = {convex_polygon({{0.035, 0}, {0.051, 0}, {0.061, 0.04}, {0.045, 0.04}})};
  ex.particle_measure = {0.016 * 0.04};
  ex.fem_measure = {0.5 * (0.035 + 0.045) * 0.04, 0.5 * (0.039 + 0.029) * 0.04};
  ex.lo = {0, 0, 0}, ex.hi = {0.09, 0.04, 0};
  check_model(m, {"strip"}, {"left", "right"}, ex, o.d);
  // band sites on both sides
  std::size_t left = 0, right = 0;
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    if (m.particle_region[i] < 0)
      (ex.particle_sdf[0](m.particles.x[i]) > 0 && m.particles.x[i][0] < 0.05 ? left : right)++;
  EXPECT_GT(left, 30u);
  EXPECT_GT(right, 30u);
}

// (d) 3D: an HCP ball of particles in an FEM box (a curved interface surface).
TEST(OverlapGeneral, SphereInBox3D) {
  sp::OverlapOptions o;
  o.kind = sp::LatticeKind::HCP;
  o.d = 0.012;
  o.far_size = 0.05;
  const auto m = timed("sphere_in_box.geo", {"ball"}, {"box"}, o);
  Expect ex;
  const double R = 0.06;
  ex.particle_sdf = {ball({0.1, 0.1, 0.1}, R)};
  ex.particle_measure = {4.0 / 3.0 * M_PI * R * R * R};
  ex.fem_measure = {0.2 * 0.2 * 0.2 - ex.particle_measure[0]};
  ex.measure_tol = 5e-3;
  ex.chord = 0.05;
  ex.lo = {0, 0, 0}, ex.hi = {0.2, 0.2, 0.2};
  const Stats s = check_model(m, {"ball"}, {"box"}, ex, o.d);
  EXPECT_LT(s.particles, 3000u);
}

// The general construction on two boxes (forced): with 51 equally spaced nodes on the
// interface line (gmsh Transfinite Curve), the lattice origin on that line and d dividing
// its length, the lattice row on Γ falls on FEM nodes. Those sites go to the upper region
// (fill_mesh's tie rule), here the FEM one: band sites on nodes, linked to them alone with
// weight 1 (the copy); the other band sites interpolate.
TEST(OverlapGeneral, CoincidentSitesBecomeCopies) {
  const auto geo = strata::test::scratch("two_blocks_transfinite.geo");
  std::ofstream(geo) << "Point(1) = {0, 0, 0}; Point(2) = {0.1, 0, 0}; Point(3) = {0.1, 0.05, 0};\n"
                        "Point(4) = {0, 0.05, 0}; Point(5) = {0.1, 0.1, 0}; Point(6) = {0, 0.1, 0};\n"
                        "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
                        "Line(5) = {3, 5}; Line(6) = {5, 6}; Line(7) = {6, 4};\n"
                        "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
                        "Curve Loop(2) = {-3, 5, 6, 7}; Plane Surface(2) = {2};\n"
                        "Transfinite Curve{3} = 51;\n"
                        "Physical Surface(\"lower\") = {1};\nPhysical Surface(\"upper\") = {2};\n";
  sp::OverlapOptions o;
  o.d = 0.002;
  o.force_general = true;
  o.origin = Vec3{0, 0.05, 0};
  const auto m = sp::build_coupled_model(geo, {"lower"}, {"upper"}, o);
  Expect ex;
  ex.particle_sdf = {convex_polygon({{0, 0}, {0.1, 0}, {0.1, 0.05}, {0, 0.05}})};
  ex.particle_measure = {0.1 * 0.05};
  ex.fem_measure = {0.1 * 0.05};
  ex.lo = {0, 0, 0}, ex.hi = {0.1, 0.1, 0};
  ex.sites_near_gamma = false;  // the row on Γ went to the FEM side
  const Stats s = check_model(m, {"lower"}, {"upper"}, ex, o.d);
  EXPECT_EQ(s.copies_to_dem, 49u);  // the row on Γ but its two ends (not whole inside)
}

// ---- the box path: unchanged ----

namespace {

/// FNV-1a over every member the box path had before the general path existed.
std::uint64_t box_hash(const sp::OverlapModel& m) {
  std::uint64_t h = 1469598103934665603ull;
  auto bytes = [&](const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 1099511628211ull;
  };
  auto vec = [&](const auto& v) {
    const std::uint64_t n = v.size();
    bytes(&n, 8);
    if (n) bytes(v.data(), n * sizeof(v[0]));
  };
  vec(m.particles.x), vec(m.particles.row), vec(m.particle_tag), vec(m.fem.x), vec(m.fem.y), vec(m.fem.z);
  vec(m.fem.cells), vec(m.fem.cell_group), vec(m.node_tag), vec(m.pair_particle), vec(m.pair_node);
  vec(m.pair_interface);
  for (const auto& g : m.fem.group_names) bytes(g.data(), g.size());
  bytes(&m.interface, 8), bytes(&m.layer_spacing, 8);
  return h;
}

}  // namespace

// build_coupled_model takes the box path for boxes sharing faces and returns build_overlap's
// model bit for bit: the hashes below are those of the box construction before the general
// path was added (gmsh 4.8.4, Debian 12), among them the coupled-wave example's models
// (examples/04_coupled_wave, d = 1 mm, far size 1 mm, growth 0.1). Its links are the
// coincidence pairs as copies.
TEST(OverlapGeneral, BoxPathKeepsItsResult) {
  struct Case {
    std::filesystem::path file;
    std::vector<std::string> fem;
    sp::OverlapOptions o;
    std::uint64_t hash;
  };
  sp::OverlapOptions o2, o3, ow;
  o2.d = 0.002;
  o3.kind = sp::LatticeKind::FCC, o3.d = 0.005, o3.far_size = 0.02, o3.growth = 1.0;
  ow.d = 0.001, ow.far_size = 0.001, ow.growth = 0.1;
  const auto wave = std::filesystem::path(STRATA_SOURCE_DIR) / "examples" / "04_coupled_wave";
  const std::vector<Case> cases = {
      {strata::test::data("two_blocks_2d.geo"), {"fem"}, o2, 0x9cec3a101690a2d2ull},
      {strata::test::data("two_blocks_3d.geo"), {"fem"}, o3, 0x6d151556db2335f8ull},
      {wave / "wave.geo", {"fem"}, ow, 0x6103e447c12bbabdull},
      {wave / "wave_embedded.geo", {"fem", "fem_exit"}, ow, 0x3771f0d9be5d1531ull},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file.filename().string());
    const auto m = sp::build_coupled_model(c.file, {"dem"}, c.fem, c.o);
    EXPECT_EQ(m.method, sp::OverlapMethod::Box);
    EXPECT_EQ(box_hash(m), c.hash);
    EXPECT_EQ(box_hash(sp::build_overlap(c.file, "dem", c.fem, c.o)), c.hash);
    // links: one copy per coincidence pair, targets ascending
    ASSERT_EQ(m.fem_to_dem.size() + m.dem_to_fem.size(), m.pair_particle.size());
    for (const auto* l : {&m.fem_to_dem, &m.dem_to_fem}) {
      ASSERT_EQ(l->first.size(), l->size() + 1);
      EXPECT_TRUE(std::is_sorted(l->target.begin(), l->target.end()));
      for (std::size_t k = 0; k < l->size(); ++k) {
        EXPECT_EQ(l->first[k + 1] - l->first[k], 1u);
        EXPECT_EQ(l->weight[l->first[k]], 1.0);
      }
    }
    for (std::size_t k = 0; k < m.pair_particle.size(); ++k) {
      const auto i = m.pair_particle[k], n = m.pair_node[k];
      const bool to_dem = m.particle_tag[i] == OverlapTag::External;
      const auto& l = to_dem ? m.fem_to_dem : m.dem_to_fem;
      const auto it = std::lower_bound(l.target.begin(), l.target.end(), to_dem ? i : n);
      ASSERT_NE(it, l.target.end());
      EXPECT_EQ(l.source[l.first[std::size_t(it - l.target.begin())]], to_dem ? n : i);
    }
    for (std::size_t i = 0; i < m.particles.size(); ++i)
      EXPECT_EQ(m.particle_region[i], m.particle_tag[i] == OverlapTag::External ? -1 : 0);
    EXPECT_EQ(m.particle_region_names, std::vector<std::string>{"dem"});
    EXPECT_EQ(m.ring_group(0), -1);
  }
}

// What selects the general path: regions that are not boxes, an origin or orientation of
// the lattice, force_general, several particle regions.
TEST(OverlapGeneral, PathSelection) {
  sp::OverlapOptions o;
  o.d = 0.002;
  EXPECT_EQ(sp::build_coupled_model(strata::test::data("two_blocks_2d.geo"), {"dem"}, {"fem"}, o).method,
            sp::OverlapMethod::Box);
  EXPECT_EQ(sp::build_coupled_model(strata::test::data("inclined_cut.geo"), {"dem"}, {"fem"}, o).method,
            sp::OverlapMethod::General);
  sp::OverlapOptions r = o;
  r.orientation_deg = 10;
  EXPECT_EQ(sp::build_coupled_model(strata::test::data("two_blocks_2d.geo"), {"dem"}, {"fem"}, r).method,
            sp::OverlapMethod::General);
  sp::OverlapOptions f = o;
  f.force_general = true;
  EXPECT_EQ(sp::build_coupled_model(strata::test::data("two_blocks_2d.geo"), {"dem"}, {"fem"}, f).method,
            sp::OverlapMethod::General);
}

namespace {
/// The message of the Error(Input) that f throws ("" when it throws none or another kind).
template <typename F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const strata::Error& e) {
    return e.kind() == strata::ErrorKind::Input ? e.what() : "";
  }
  return "";
}
}  // namespace

// Geometry errors are Error(Input) naming the region and what is allowed.
TEST(OverlapGeneral, GeometryErrorsNameTheRegion) {
  sp::OverlapOptions o;
  o.d = 0.001;
  const auto cut = strata::test::data("inclined_cut.geo");
  std::string e = input_error([&] { sp::build_coupled_model(cut, {"rock"}, {"fem"}, o); });
  EXPECT_NE(e.find("\"rock\""), std::string::npos) << e;
  EXPECT_NE(e.find("\"dem\", \"fem\""), std::string::npos) << e;  // the regions there are
  e = input_error([&] { sp::build_coupled_model(cut, {"dem"}, {"dem"}, o); });
  EXPECT_NE(e.find("listed twice"), std::string::npos) << e;
  e = input_error([&] { sp::build_coupled_model(cut, {"dem"}, {}, o); });
  EXPECT_NE(e.find("at least one of each"), std::string::npos) << e;
  sp::OverlapOptions o3 = o;
  o3.kind = sp::LatticeKind::HCP;
  o3.force_general = true;
  e = input_error([&] { sp::build_coupled_model(cut, {"dem"}, {"fem"}, o3); });
  EXPECT_NE(e.find("2D but the lattice"), std::string::npos) << e;
  // two rectangles that do not touch: no interface
  const auto apart = strata::test::scratch("apart.geo");
  std::ofstream(apart) << "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 0.02, 0.02};\n"
                          "Rectangle(2) = {0.03, 0, 0, 0.02, 0.02};\n"
                          "Physical Surface(\"grains\") = {1};\nPhysical Surface(\"solid\") = {2};\n";
  e = input_error([&] { sp::build_coupled_model(apart, {"grains"}, {"solid"}, o); });
  EXPECT_NE(e.find("particle region \"grains\" shares no boundary curve"), std::string::npos) << e;
  EXPECT_NE(e.find("allowed"), std::string::npos) << e;
  o.d = -1;
  EXPECT_FALSE(input_error([&] { sp::build_coupled_model(cut, {"dem"}, {"fem"}, o); }).empty());
}

#endif
