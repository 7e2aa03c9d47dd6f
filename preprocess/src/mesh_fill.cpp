// Lattice sites of meshes and geometry regions, element by element (see mesh_fill.hpp).
#include "strata/preprocess/mesh_fill.hpp"

#include <strata/core/clock.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "cgal_queries.hpp"

namespace strata::preprocess {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

std::int64_t pos_mod(std::int64_t a, std::int64_t m) { return ((a % m) + m) % m; }
}  // namespace

// ---- LatticeFrame ----------------------------------------------------------------------------

LatticeFrame::LatticeFrame(LatticeKind kind, double d, double orientation_deg, Vec3 origin)
    : kind_(kind), d_(d), h_(0.5 * std::numbers::sqrt3 * d), c_(d * std::sqrt(2.0 / 3.0)), origin_(origin) {
  STRATA_CHECK(d > 0 && std::isfinite(d), Input, "lattice: particle diameter {} must be > 0", d);
  const double th = orientation_deg * M_PI / 180.0;
  cos_ = std::cos(th);
  sin_ = std::sin(th);
  if (kind == LatticeKind::Hex2D) c_ = 0, origin_[2] = 0;
}

double LatticeFrame::cell_measure() const { return dim() == 2 ? h_ * d_ : d_ * d_ * d_ / std::sqrt(2.0); }

double LatticeFrame::packing_fraction() const {
  return dim() == 2 ? M_PI / (2 * std::numbers::sqrt3) : M_PI / (3 * std::sqrt(2.0));
}

void LatticeFrame::layer_shift(std::int64_t k, double& sx, double& sy) const {
  std::int64_t s = 0;
  if (kind_ == LatticeKind::HCP) s = k & 1;
  if (kind_ == LatticeKind::FCC) s = pos_mod(k, 3);
  sx = static_cast<double>(s) * 0.5 * d_;
  sy = static_cast<double>(s) * d_ / (2 * std::numbers::sqrt3);
}

Vec3 LatticeFrame::site(std::int64_t i, std::int64_t j, std::int64_t k) const {
  double sx, sy;
  layer_shift(k, sx, sy);
  const double lx = sx + (static_cast<double>(i) + ((j & 1) ? 0.5 : 0.0)) * d_;
  const double ly = sy + static_cast<double>(j) * h_;
  return {origin_[0] + cos_ * lx - sin_ * ly, origin_[1] + sin_ * lx + cos_ * ly,
          origin_[2] + static_cast<double>(k) * c_};
}

Vec3 LatticeFrame::to_local(const Vec3& p) const {
  const double dx = p[0] - origin_[0], dy = p[1] - origin_[1];
  return {cos_ * dx + sin_ * dy, -sin_ * dx + cos_ * dy, p[2] - origin_[2]};
}

// ---- exact, consistent inside tests --------------------------------------------------------
namespace {

/// One facet of an element, with its nodes sorted by index (so that the elements on both
/// sides evaluate bit-identical signs), the sign of the element's own side, and a
/// floating-point filter scale.
struct Facet {
  Vec3 a, b, c;       // sorted by node index (c unused in 2D)
  double nx, ny, nz;  // (b - a) × (c - a) in 3D; (-(b - a)_y, (b - a)_x) in 2D
  double scale;       // error-bound scale: max|b - a| · max|c - a| (3D), max|b - a| (2D)
  int inner = 0;      // sign of the element's side
};

struct Tally {
  std::size_t candidates = 0, exact = 0;
  Tally& operator+=(const Tally& o) {
    candidates += o.candidates;
    exact += o.exact;
    return *this;
  }
};

inline double amax3(double a, double b, double c) {
  return std::max({std::abs(a), std::abs(b), std::abs(c)});
}

/// Sign of det[b - a, c - a, p - a] with the symbolic perturbation p + ε(1, ε, ε²) (3D) or
/// of (b - a) × (p - a) with p + ε(1, ε) (2D); never 0 for a non-degenerate facet.
template <int Dim>
inline int side(const Facet& f, const Vec3& p, Tally& t) {
  const double wx = p[0] - f.a[0], wy = p[1] - f.a[1];
  if constexpr (Dim == 3) {
    const double wz = p[2] - f.a[2];
    const double D = f.nx * wx + f.ny * wy + f.nz * wz;
    const double bound = 1e-13 * f.scale * amax3(wx, wy, wz);
    if (D > bound) return 1;
    if (D < -bound) return -1;
    ++t.exact;
    const int s = detail::orient3d_exact(f.a, f.b, f.c, p);
    if (s != 0) return s;
    // p + ε(1, ε, ε²): the sign of the normal's first non-zero component, exactly.
    int n = detail::orient2d_exact(f.a[1], f.a[2], f.b[1], f.b[2], f.c[1], f.c[2]);
    if (n == 0) n = detail::orient2d_exact(f.a[2], f.a[0], f.b[2], f.b[0], f.c[2], f.c[0]);
    if (n == 0) n = detail::orient2d_exact(f.a[0], f.a[1], f.b[0], f.b[1], f.c[0], f.c[1]);
    return n;
  } else {
    const double D = f.nx * wx + f.ny * wy;
    const double bound = 1e-13 * f.scale * std::max(std::abs(wx), std::abs(wy));
    if (D > bound) return 1;
    if (D < -bound) return -1;
    ++t.exact;
    const int s = detail::orient2d_exact(f.a[0], f.a[1], f.b[0], f.b[1], p[0], p[1]);
    if (s != 0) return s;
    // p + ε(1, ε): d/dpx = -(b - a)_y, d/dpy = (b - a)_x; signs of differences are exact.
    const double uy = f.b[1] - f.a[1], ux = f.b[0] - f.a[0];
    return uy != 0 ? (uy < 0 ? 1 : -1) : (ux > 0 ? 1 : -1);
  }
}

/// An element prepared for site enumeration.
template <int Dim>
struct Element {
  static constexpr int kN = Dim + 1;
  Facet facet[kN];
  Vec3 q[kN];           // vertices in lattice-local coordinates
  double m[kN][3];      // inward facet normals, local coordinates
  double lo[3], hi[3];  // local bounds
  Vec3 wlo, whi;        // world bounds

  void prepare(const SimplexMesh& mesh, std::size_t e, const LatticeFrame& fr, Tally& t) {
    const std::uint32_t* c = &mesh.cells[e * kN];
    Vec3 v[kN];
    for (int k = 0; k < kN; ++k) v[k] = mesh.node(c[k]), q[k] = fr.to_local(v[k]);
    for (int a = 0; a < 3; ++a) {
      lo[a] = kInf, hi[a] = -kInf, wlo[a] = kInf, whi[a] = -kInf;
      for (int k = 0; k < kN; ++k) {
        lo[a] = std::min(lo[a], q[k][a]), hi[a] = std::max(hi[a], q[k][a]);
        wlo[a] = std::min(wlo[a], v[k][a]), whi[a] = std::max(whi[a], v[k][a]);
      }
    }
    for (int f = 0; f < kN; ++f) {
      // facet f is opposite vertex f; its nodes sorted by index
      int idx[3], n = 0;
      for (int k = 0; k < kN; ++k)
        if (k != f) idx[n++] = k;
      std::sort(idx, idx + Dim, [&](int x, int y) { return c[x] < c[y]; });
      Facet& F = facet[f];
      F.a = v[idx[0]], F.b = v[idx[1]], F.c = Dim == 3 ? v[idx[2]] : Vec3{0, 0, 0};
      const double ux = F.b[0] - F.a[0], uy = F.b[1] - F.a[1], uz = F.b[2] - F.a[2];
      if constexpr (Dim == 3) {
        const double vx = F.c[0] - F.a[0], vy = F.c[1] - F.a[1], vz = F.c[2] - F.a[2];
        F.nx = uy * vz - uz * vy, F.ny = uz * vx - ux * vz, F.nz = ux * vy - uy * vx;
        F.scale = amax3(ux, uy, uz) * amax3(vx, vy, vz);
      } else {
        F.nx = -uy, F.ny = ux, F.nz = 0;
        F.scale = std::max(std::abs(ux), std::abs(uy));
      }
      F.inner = side<Dim>(F, v[f], t);
      // inward normal in local coordinates (for the column ranges only)
      const Vec3 &qa = q[idx[0]], &qb = q[idx[1]], &qf = q[f];
      double mx, my, mz = 0;
      if constexpr (Dim == 3) {
        const Vec3& qc = q[idx[2]];
        const double ax = qb[0] - qa[0], ay = qb[1] - qa[1], az = qb[2] - qa[2];
        const double bx = qc[0] - qa[0], by = qc[1] - qa[1], bz = qc[2] - qa[2];
        mx = ay * bz - az * by, my = az * bx - ax * bz, mz = ax * by - ay * bx;
      } else {
        mx = -(qb[1] - qa[1]), my = qb[0] - qa[0];
      }
      if (mx * (qf[0] - qa[0]) + my * (qf[1] - qa[1]) + mz * (qf[2] - qa[2]) < 0)
        mx = -mx, my = -my, mz = -mz;
      m[f][0] = mx, m[f][1] = my, m[f][2] = mz;
    }
  }

  bool inside(const Vec3& p, Tally& t) const {
    for (int f = 0; f < kN; ++f)
      if (side<Dim>(facet[f], p, t) != facet[f].inner) return false;
    return true;
  }

  /// Calls visit(i, j, k, p) for every site inside the element, by layer, row, column.
  template <typename Visit>
  void sites(const LatticeFrame& fr, Tally& t, Visit&& visit) const {
    const double d = fr.diameter(), h = fr.row_spacing(), cz = fr.layer_spacing();
    const double pad = 1e-6 * d;
    std::int64_t k0 = 0, k1 = 0;
    if constexpr (Dim == 3) {
      k0 = static_cast<std::int64_t>(std::ceil((lo[2] - pad) / cz));
      k1 = static_cast<std::int64_t>(std::floor((hi[2] + pad) / cz));
    }
    for (std::int64_t k = k0; k <= k1; ++k) {
      const double z = static_cast<double>(k) * cz;
      double sx, sy;
      fr.layer_shift(k, sx, sy);
      const auto j0 = static_cast<std::int64_t>(std::ceil((lo[1] - sy - pad) / h));
      const auto j1 = static_cast<std::int64_t>(std::floor((hi[1] - sy + pad) / h));
      for (std::int64_t j = j0; j <= j1; ++j) {
        const double y = sy + static_cast<double>(j) * h;
        double xlo = lo[0], xhi = hi[0];
        // column range: m·(q - a) >= 0 for every facet, on the line (y, z)
        for (int f = 0; f < kN; ++f) {
          const int a = f == 0 ? 1 : 0;  // a vertex on facet f
          const double mx = m[f][0];
          const double rhs = -(m[f][1] * (y - q[a][1]) + (Dim == 3 ? m[f][2] * (z - q[a][2]) : 0.0));
          const double norm = std::abs(m[f][0]) + std::abs(m[f][1]) + std::abs(m[f][2]);
          if (mx > 1e-12 * norm)
            xlo = std::max(xlo, q[a][0] + rhs / mx);
          else if (mx < -1e-12 * norm)
            xhi = std::min(xhi, q[a][0] + rhs / mx);
        }
        if (xlo > xhi + 2 * pad) continue;
        const double off = sx + ((j & 1) ? 0.5 * d : 0.0);
        const auto i0 = static_cast<std::int64_t>(std::ceil((xlo - off - pad) / d));
        const auto i1 = static_cast<std::int64_t>(std::floor((xhi - off + pad) / d));
        for (std::int64_t i = i0; i <= i1; ++i) {
          const Vec3 p = fr.site(i, j, k);
          ++t.candidates;
          if (inside(p, t)) visit(i, j, k, p);
        }
      }
    }
  }
};

template <int Dim>
Lattice fill_mesh_dim(const SimplexMesh& mesh, const LatticeFrame& fr, const BoundaryFilter& filter,
                      std::vector<std::size_t>* first_site, FillStats* stats) {
  const auto t0 = WallClock::now();
  const std::size_t ne = mesh.cell_count();
  const double r = filter.distance, tol = 1e-9 * fr.diameter();
  const bool filtering = filter.boundary != nullptr && r > 0;
  std::vector<std::uint32_t> count(ne);
  // Minimum distance to the boundary: only the boundary facets within r of an element's
  // bounds can come that close to its sites (most elements have none), and a site can only
  // be within r of a facet inside the facet's bounds grown by r (checked in lattice-local
  // coordinates, before the exact distance).
  struct Near {
    std::vector<std::uint32_t> ids;
    std::vector<std::array<double, 6>> box;  // local lo, hi grown by r
  };
  const SimplexMesh* facets = filtering ? &filter.boundary_facets() : nullptr;
  auto near_facets_of = [&](const Element<Dim>& el, Near& near) {
    if (!filtering) return;
    filter.boundary->facets_near_box(el.wlo, el.whi, r, near.ids);
    near.box.resize(near.ids.size());
    const int np = facets->nodes_per_cell();
    for (std::size_t f = 0; f < near.ids.size(); ++f) {
      auto& b = near.box[f];
      b = {kInf, kInf, kInf, -kInf, -kInf, -kInf};
      for (int v = 0; v < np; ++v) {
        const Vec3 q = fr.to_local(
            facets->node(facets->cells[std::size_t(near.ids[f]) * std::size_t(np) + std::size_t(v)]));
        for (int a = 0; a < 3; ++a) b[a] = std::min(b[a], q[a] - r), b[a + 3] = std::max(b[a + 3], q[a] + r);
      }
    }
  };
  auto keep = [&](const Near& near, const Vec3& p) {
    if (near.ids.empty()) return true;
    const Vec3 q = fr.to_local(p);
    for (std::size_t f = 0; f < near.ids.size(); ++f) {
      const auto& b = near.box[f];
      if (q[0] < b[0] || q[0] > b[3] || q[1] < b[1] || q[1] > b[4] || q[2] < b[2] || q[2] > b[5]) continue;
      if (distance_to_facet(*facets, near.ids[f], p) < r - tol) return false;
    }
    return true;
  };

  // Pass 1: sites per element.
  const Tally tally = par::parallel_sum<Tally>(std::ptrdiff_t(ne), [&](std::ptrdiff_t ie) {
    const auto e = std::size_t(ie);
    Tally t;
    Element<Dim> el;
    el.prepare(mesh, e, fr, t);
    Near near;
    near_facets_of(el, near);
    std::uint32_t n = 0;
    el.sites(fr, t,
             [&](std::int64_t, std::int64_t, std::int64_t, const Vec3& p) { n += keep(near, p) ? 1 : 0; });
    count[e] = n;
    return t;
  });

  const auto t1 = WallClock::now();
  // Prefix sum, then pass 2 writes each element's sites at its offset.
  std::vector<std::size_t> offset(ne + 1, 0);
  for (std::size_t e = 0; e < ne; ++e) offset[e + 1] = offset[e] + count[e];
  std::vector<std::uint32_t>().swap(count);
  Lattice l;
  l.dim = Dim;
  l.radius = 0.5 * fr.diameter();
  const std::size_t n = offset[ne];
  l.x.resize(n);
  l.row.resize(n);
  l.layer.resize(n);
  const auto t2 = WallClock::now();
  par::parallel_for(std::ptrdiff_t(ne), [&](std::ptrdiff_t ie) {
    const auto e = std::size_t(ie);
    Tally t;
    Element<Dim> el;
    el.prepare(mesh, e, fr, t);
    Near near;
    near_facets_of(el, near);
    std::size_t o = offset[e];
    el.sites(fr, t, [&](std::int64_t, std::int64_t j, std::int64_t k, const Vec3& p) {
      if (!keep(near, p)) return;
      l.x[o] = p;
      l.row[o] = static_cast<std::int32_t>(j);
      l.layer[o] = static_cast<std::int32_t>(k);
      ++o;
    });
    STRATA_ASSERT(o == offset[e + 1], "element {}: pass 2 found {} sites, pass 1 {}", e, o - offset[e],
                  offset[e + 1] - offset[e]);
  });
  {
    const auto t3 = WallClock::now();
    log::debug("fill_mesh: {} elements, {} sites: count {:.3f} s, allocate {:.3f} s, write {:.3f} s", ne, n,
               seconds_between(t0, t1), seconds_between(t1, t2), seconds_between(t2, t3));
  }
  if (first_site) *first_site = std::move(offset);
  if (stats) {
    stats->elements = ne;
    stats->candidates = tally.candidates;
    stats->exact_tests = tally.exact;
    stats->seconds = seconds_since(t0);
  }
  return l;
}

/// Sites inside a closed surface: every site of the (rotated) bounds is tested with CGAL,
/// row by row in parallel; a byte mask keeps the answers between the two passes.
Lattice fill_surface(const GeometryRegion& region, const LatticeFrame& fr, const BoundaryFilter& filter,
                     FillStats* stats) {
  const auto t0 = WallClock::now();
  const Bounds b = region.bounds();
  double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  for (int c = 0; c < 8; ++c) {
    const Vec3 p =
        fr.to_local({c & 1 ? b.hi[0] : b.lo[0], c & 2 ? b.hi[1] : b.lo[1], c & 4 ? b.hi[2] : b.lo[2]});
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  }
  const double d = fr.diameter(), h = fr.row_spacing(), cz = fr.layer_spacing(), pad = 1e-6 * d;
  struct Row {
    std::int64_t j, k, i0, i1;
    std::size_t first;  // offset of its first candidate in the mask
  };
  std::vector<Row> rows;
  std::size_t ncand = 0;
  const auto k0 = static_cast<std::int64_t>(std::ceil((lo[2] - pad) / cz)),
             k1 = static_cast<std::int64_t>(std::floor((hi[2] + pad) / cz));
  for (std::int64_t k = k0; k <= k1; ++k) {
    double sx, sy;
    fr.layer_shift(k, sx, sy);
    const auto j0 = static_cast<std::int64_t>(std::ceil((lo[1] - sy - pad) / h)),
               j1 = static_cast<std::int64_t>(std::floor((hi[1] - sy + pad) / h));
    for (std::int64_t j = j0; j <= j1; ++j) {
      const double off = sx + ((j & 1) ? 0.5 * d : 0.0);
      const auto i0 = static_cast<std::int64_t>(std::ceil((lo[0] - off - pad) / d)),
                 i1 = static_cast<std::int64_t>(std::floor((hi[0] - off + pad) / d));
      if (i1 < i0) continue;
      rows.push_back({j, k, i0, i1, ncand});
      ncand += std::size_t(i1 - i0 + 1);
    }
  }
  std::vector<char> mask(ncand, 0);
  std::vector<std::size_t> count(rows.size() + 1, 0);
  const double r = filter.distance, tol = 1e-9 * d;
  par::parallel_for(std::ptrdiff_t(rows.size()), [&](std::ptrdiff_t ir) {
    const Row& row = rows[std::size_t(ir)];
    std::size_t n = 0;
    for (std::int64_t i = row.i0; i <= row.i1; ++i) {
      const Vec3 p = fr.site(i, row.j, row.k);
      bool in = detail::surface_contains(*region.surface, p);
      if (in && filter.boundary && r > 0) in = (*filter.boundary)(p) >= r - tol;
      mask[row.first + std::size_t(i - row.i0)] = in ? 1 : 0;
      n += in ? 1 : 0;
    }
    count[std::size_t(ir) + 1] = n;
  });
  for (std::size_t i = 0; i < rows.size(); ++i) count[i + 1] += count[i];
  Lattice l;
  l.dim = 3;
  l.radius = 0.5 * d;
  l.x.resize(count.back());
  l.row.resize(count.back());
  l.layer.resize(count.back());
  par::parallel_for(std::ptrdiff_t(rows.size()), [&](std::ptrdiff_t ir) {
    const Row& row = rows[std::size_t(ir)];
    std::size_t o = count[std::size_t(ir)];
    for (std::int64_t i = row.i0; i <= row.i1; ++i) {
      if (!mask[row.first + std::size_t(i - row.i0)]) continue;
      l.x[o] = fr.site(i, row.j, row.k);
      l.row[o] = std::int32_t(row.j);
      l.layer[o] = std::int32_t(row.k);
      ++o;
    }
  });
  if (stats) {
    stats->elements = 0;
    stats->candidates = ncand;
    stats->exact_tests = 0;
    stats->seconds = seconds_since(t0);
  }
  return l;
}

}  // namespace

Lattice fill_mesh(const SimplexMesh& mesh, const LatticeFrame& frame, const BoundaryFilter& filter,
                  std::vector<std::size_t>* first_site, FillStats* stats) {
  STRATA_CHECK(mesh.dim == frame.dim(), Input,
               "filling a mesh of {}D elements with a {}D lattice; allowed: hex in 2D, hcp or fcc in 3D",
               mesh.dim, frame.dim());
  return mesh.dim == 2 ? fill_mesh_dim<2>(mesh, frame, filter, first_site, stats)
                       : fill_mesh_dim<3>(mesh, frame, filter, first_site, stats);
}

RegionFill fill_region(const GeometryRegion& region, const FillOptions& opt) {
  STRATA_CHECK(opt.d > 0, Input, "region \"{}\" of {}: particle diameter {} must be > 0", region.name,
               region.file, opt.d);
  STRATA_CHECK(opt.min_boundary_distance >= 0, Input,
               "region \"{}\" of {}: min_boundary_distance {} must be >= 0", region.name, region.file,
               opt.min_boundary_distance);
  const int ldim = opt.kind == LatticeKind::Hex2D ? 2 : 3;
  STRATA_CHECK(
      ldim == region.dim, Input,
      "region \"{}\" of {} is {}D but the lattice is {}D; allowed: hex for 2D regions, hcp or fcc for 3D",
      region.name, region.file, region.dim, ldim);
  Vec3 origin;
  if (opt.origin) {
    origin = *opt.origin;
  } else {
    const Bounds b = region.bounds();
    for (int a = 0; a < 3; ++a) origin[a] = b.lo[a] + 0.5 * opt.d;
    if (region.dim == 2) origin[2] = 0;
  }
  const LatticeFrame frame(opt.kind, opt.d, opt.orientation_deg, origin);
  std::unique_ptr<BoundaryDistance> dist;
  BoundaryFilter filter;
  if (opt.min_boundary_distance > 0) {
    dist = std::make_unique<BoundaryDistance>(region.boundary);
    filter = {dist.get(), opt.min_boundary_distance};
  }
  RegionFill f;
  f.measure = region.measure();
  if (region.surface) {
    f.lattice = fill_surface(region, frame, filter, &f.stats);
  } else {
    std::vector<std::size_t> first;
    f.lattice = fill_mesh(region.mesh, frame, filter, &first, &f.stats);
    f.entity_tags = region.entity_tags;
    for (std::size_t c : region.entity_first_cell) f.entity_first_site.push_back(first[c]);
  }
  const double r = 0.5 * opt.d;
  const double one = region.dim == 2 ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r;
  f.packing = f.measure > 0 ? double(f.lattice.size()) * one / f.measure : 0.0;
  return f;
}

// ---- selections ----------------------------------------------------------------------------

std::vector<std::uint32_t> near_facets(const SimplexMesh& facets, const Lattice& l, double width) {
  std::vector<std::uint32_t> out;
  if (facets.cell_count() == 0) return out;
  const BoundaryDistance dist(facets);
  std::vector<char> in(l.size(), 0);
  const double tol = 1e-9 * (l.radius > 0 ? l.radius : 1.0);
  // Sites outside the facets' bounds grown by the width are farther than it from every
  // facet: a box test skips the distance query for them (most sites, for a planar group).
  Bounds b = facets.bounds();
  for (int a = 0; a < 3; ++a) b.lo[a] -= width + 2 * tol, b.hi[a] += width + 2 * tol;
  par::parallel_for(std::ptrdiff_t(l.size()), [&](std::ptrdiff_t i) {
    const Vec3& p = l.x[std::size_t(i)];
    bool near = true;
    for (int a = 0; a < 3; ++a) near = near && p[a] >= b.lo[a] && p[a] <= b.hi[a];
    in[std::size_t(i)] = near && dist(p) <= width + tol ? 1 : 0;
  });
  for (std::size_t i = 0; i < l.size(); ++i)
    if (in[i]) out.push_back(std::uint32_t(i));
  return out;
}

std::vector<std::uint32_t> hole_rim(const GeometryRegion& r, const Lattice& l, int hole, double width) {
  STRATA_CHECK(r.dim == 2, Input, "region \"{}\" of {}: holes are selected in 2D regions only", r.name,
               r.file);
  STRATA_CHECK(hole >= 1 && hole <= r.hole_count, Input,
               "region \"{}\" of {}: no hole {}; the region has {} hole(s), numbered 1.. from left to right",
               r.name, r.file, hole, r.hole_count);
  SimplexMesh rim;
  rim.dim = 1;
  rim.x = r.boundary.x, rim.y = r.boundary.y, rim.z = r.boundary.z;
  for (std::size_t s = 0; s < r.boundary.cell_count(); ++s)
    if (r.facet_loop[s] == hole)
      rim.cells.insert(rim.cells.end(), &r.boundary.cells[2 * s], &r.boundary.cells[2 * s] + 2);
  return near_facets(rim, l, width);
}

std::vector<std::uint32_t> physical_group_members(const Geometry& g, const RegionFill& f,
                                                  const std::string& physical, double width) {
  if (const auto* ents = g.region_entities(physical); ents != nullptr && !f.entity_tags.empty()) {
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < f.entity_tags.size(); ++i) {
      if (std::find(ents->begin(), ents->end(), f.entity_tags[i]) == ents->end()) continue;
      for (std::size_t s = f.entity_first_site[i]; s < f.entity_first_site[i + 1]; ++s)
        out.push_back(std::uint32_t(s));
    }
    return out;
  }
  if (g.boundaries.count(physical)) return near_facets(g.boundary(physical), f.lattice, width);
  std::string names;
  for (const auto& n : g.region_names()) names += (names.empty() ? "\"" : ", \"") + n + "\"";
  for (const auto& n : g.boundary_names()) names += (names.empty() ? "\"" : ", \"") + n + "\"";
  fail(ErrorKind::Input, "{}: no physical group named \"{}\"; the groups are: {}", g.file, physical,
       names.empty() ? "(none)" : names);
}

}  // namespace strata::preprocess
