// Eccentric lattices (ECC4D, SPEC C4) and bond lists (see ecc.hpp).
#include "strata/preprocess/ecc.hpp"

#include <strata/core/error.hpp>
#include <strata/core/parallel.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace strata::preprocess {

std::size_t BondList::weakened() const {
  return std::size_t(
      std::count_if(stiffness_factor.begin(), stiffness_factor.end(), [](float f) { return f != 1.0f; }));
}

BondList touching_pairs(const Lattice& l, double tol) {
  BondList b;
  const std::size_t n = l.size();
  if (n < 2) return b;
  const double d = 2 * l.radius, lo2 = (d * (1 - tol)) * (d * (1 - tol)),
               hi2 = (d * (1 + tol)) * (d * (1 + tol));
  STRATA_CHECK(d > 0, Input, "bonds: lattice radius {} must be > 0", l.radius);
  // Cell grid of side d(1 + tol): neighbours lie in the 3^dim cells around.
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const auto& p : l.x)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  const double cell = d * (1 + 2 * tol);
  std::int64_t nc[3];
  for (int a = 0; a < 3; ++a) nc[a] = std::max<std::int64_t>(1, std::int64_t((hi[a] - lo[a]) / cell) + 1);
  auto cell_of = [&](const Vec3& p, int a) {
    return std::min<std::int64_t>(nc[a] - 1, std::int64_t((p[a] - lo[a]) / cell));
  };
  auto key = [&](std::int64_t cx, std::int64_t cy, std::int64_t cz) {
    return (cz * nc[1] + cy) * nc[0] + cx;
  };
  const std::int64_t ncell = nc[0] * nc[1] * nc[2];
  STRATA_CHECK(ncell < (std::int64_t(1) << 40), Input, "bonds: the lattice spans too many cells ({})", ncell);
  // Counting sort of sites by cell.
  std::vector<std::uint64_t> start(std::size_t(ncell) + 1, 0);
  std::vector<std::uint32_t> sorted(n);
  std::vector<std::int64_t> cell_id(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = l.x[i];
    cell_id[i] = key(cell_of(p, 0), cell_of(p, 1), cell_of(p, 2));
    ++start[std::size_t(cell_id[i]) + 1];
  }
  for (std::int64_t c = 0; c < ncell; ++c) start[std::size_t(c) + 1] += start[std::size_t(c)];
  {
    std::vector<std::uint64_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) sorted[fill[std::size_t(cell_id[i])]++] = std::uint32_t(i);
  }
  // For each site i: its neighbours j > i, ascending. Count, prefix, write.
  auto visit = [&](std::size_t i, auto&& emit) {
    const auto& p = l.x[i];
    const std::int64_t cx = cell_of(p, 0), cy = cell_of(p, 1), cz = cell_of(p, 2);
    std::uint32_t found[64];
    int nf = 0;
    for (std::int64_t z = std::max<std::int64_t>(0, cz - 1); z <= std::min(nc[2] - 1, cz + 1); ++z)
      for (std::int64_t y = std::max<std::int64_t>(0, cy - 1); y <= std::min(nc[1] - 1, cy + 1); ++y)
        for (std::int64_t x = std::max<std::int64_t>(0, cx - 1); x <= std::min(nc[0] - 1, cx + 1); ++x) {
          const auto c = std::size_t(key(x, y, z));
          for (std::uint64_t s = start[c]; s < start[c + 1]; ++s) {
            const std::uint32_t j = sorted[s];
            if (j <= i) continue;
            const auto& q = l.x[j];
            const double r2 =
                (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
            if (r2 >= lo2 && r2 <= hi2 && nf < 64) found[nf++] = j;
          }
        }
    std::sort(found, found + nf);
    for (int k = 0; k < nf; ++k) emit(found[k]);
  };
  std::vector<std::uint64_t> offset(n + 1, 0);
  par::parallel_for(std::ptrdiff_t(n), [&](std::ptrdiff_t i) {
    std::uint64_t c = 0;
    visit(std::size_t(i), [&](std::uint32_t) { ++c; });
    offset[std::size_t(i) + 1] = c;
  });
  for (std::size_t i = 0; i < n; ++i) offset[i + 1] += offset[i];
  const std::size_t nb = offset[n];
  b.i.resize(nb);
  b.j.resize(nb);
  b.length.resize(nb);
  b.stiffness_factor.assign(nb, 1.0f);
  par::parallel_for(std::ptrdiff_t(n), [&](std::ptrdiff_t ii) {
    const auto i = std::size_t(ii);
    std::uint64_t o = offset[i];
    visit(i, [&](std::uint32_t j) {
      b.i[o] = std::uint32_t(i);
      b.j[o] = j;
      const auto &p = l.x[i], &q = l.x[j];
      b.length[o] = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                              (p[2] - q[2]) * (p[2] - q[2]));
      ++o;
    });
  });
  for (double len : b.length) b.max_length = std::max(b.max_length, len);
  return b;
}

namespace {
/// splitmix64: a counter-based generator, so particle i's offset depends on (seed, i) only.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
/// Uniform in [0, 1) from the k-th draw of particle i.
double uniform(std::uint64_t seed, std::uint64_t i, std::uint64_t k) {
  return double(mix(mix(seed * 0x632be59bd9b4e019ULL + i) + k) >> 11) * 0x1.0p-53;
}
}  // namespace

void apply_eccentricity(Lattice& l, const EccOptions& o) {
  if (o.type == Eccentricity::None || o.ra == 0) return;
  STRATA_CHECK(o.ra >= 0 && o.ra < 1, Input, "eccentric lattice: ra = {} must be in [0, 1)", o.ra);
  const double a = o.ra * l.radius;
  const bool three = l.dim == 3;
  par::parallel_for(std::ptrdiff_t(l.size()), [&](std::ptrdiff_t ii) {
    const auto i = std::uint64_t(ii);
    auto& p = l.x[std::size_t(i)];
    if (o.type == Eccentricity::Cube) {
      // Type A: uniform in the cube (square) of half-side a.
      for (int c = 0; c < (three ? 3 : 2); ++c)
        p[std::size_t(c)] += a * (2 * uniform(o.seed, i, std::uint64_t(c)) - 1);
    } else {
      // Type B: uniform on the sphere (circle) of radius a.
      const double phi = 2 * M_PI * uniform(o.seed, i, 0);
      const double ct = three ? 2 * uniform(o.seed, i, 1) - 1 : 0.0,
                   st = std::sqrt(std::max(0.0, 1 - ct * ct));
      p[0] += a * st * std::cos(phi);
      p[1] += a * st * std::sin(phi);
      if (three) p[2] += a * ct;
    }
  });
}

EccLattice make_eccentric(const Lattice& regular, const EccOptions& o) {
  STRATA_CHECK(o.rc > 0 && o.rc <= 1, Input, "eccentric lattice: rc = {} must be in (0, 1]", o.rc);
  STRATA_CHECK(o.gamma >= 0 && o.gamma <= 1, Input, "eccentric lattice: gamma = {} must be in [0, 1]",
               o.gamma);
  EccLattice e;
  e.bonds = touching_pairs(regular);
  e.lattice = regular;
  apply_eccentricity(e.lattice, o);
  BondList& b = e.bonds;
  b.max_length = 0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    const auto &p = e.lattice.x[b.i[k]], &q = e.lattice.x[b.j[k]];
    b.length[k] = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                            (p[2] - q[2]) * (p[2] - q[2]));
    b.max_length = std::max(b.max_length, b.length[k]);
  }
  const double limit = o.rc * b.max_length;
  for (std::size_t k = 0; k < b.size(); ++k)
    b.stiffness_factor[k] = b.length[k] > limit ? float(o.gamma) : 1.0f;
  return e;
}

std::vector<std::size_t> histogram(const std::vector<double>& values, double lo, double hi, int bins) {
  std::vector<std::size_t> h(std::size_t(std::max(bins, 1)), 0);
  const double w = (hi - lo) / double(h.size());
  for (double v : values) {
    auto k = w > 0 ? std::int64_t(std::floor((v - lo) / w)) : 0;
    k = std::clamp<std::int64_t>(k, 0, std::int64_t(h.size()) - 1);
    ++h[std::size_t(k)];
  }
  return h;
}

void bond_directions(const Lattice& l, const BondList& b, std::vector<double>& azimuth,
                     std::vector<double>& polar) {
  azimuth.resize(b.size());
  polar.resize(l.dim == 3 ? b.size() : 0);
  for (std::size_t k = 0; k < b.size(); ++k) {
    const auto &p = l.x[b.i[k]], &q = l.x[b.j[k]];
    const double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
    double az = std::atan2(dy, dx) * 180 / M_PI;
    if (az < 0) az += 180;
    if (az >= 180) az -= 180;
    azimuth[k] = az;
    if (l.dim == 3)
      polar[k] = std::acos(std::min(1.0, std::abs(dz) / std::sqrt(dx * dx + dy * dy + dz * dz))) * 180 / M_PI;
  }
}

}  // namespace strata::preprocess
