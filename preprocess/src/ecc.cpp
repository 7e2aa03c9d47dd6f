// Eccentric lattices (ECC4D, Zhao et al. 2021) and bond lists (see ecc.hpp).
#include "strata/preprocess/ecc.hpp"

#include <strata/core/error.hpp>
#include <strata/core/parallel.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "site_grid.hpp"

namespace strata::preprocess {

std::size_t BondList::weakened() const {
  return std::size_t(
      std::count_if(stiffness_factor.begin(), stiffness_factor.end(), [](float f) { return f != 1.0f; }));
}

namespace detail {

SiteGrid::SiteGrid(const std::vector<const Lattice*>& parts, double cell) : parts_(parts), cell_(cell) {
  STRATA_CHECK(!parts_.empty(), Input, "bonds: no lattice given");
  STRATA_CHECK(cell > 0, Input, "bonds: grid cell {} must be > 0", cell);
  for (const Lattice* l : parts_) {
    first_.push_back(std::uint32_t(n_));
    n_ += l->size();
    STRATA_CHECK(n_ < std::numeric_limits<std::uint32_t>::max(), Input,
                 "bonds: {} sites or more; at most {} can be indexed", n_,
                 std::numeric_limits<std::uint32_t>::max());
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const Lattice* l : parts_)
    for (const auto& p : l->x)
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  if (n_ == 0) {
    start_.assign(2, 0);
    return;
  }
  if (parts_.size() == 1) single_ = parts_.front()->x.data();
  for (int a = 0; a < 3; ++a) {
    lo_[a] = lo[a];
    nc_[a] = std::max<std::int64_t>(1, std::int64_t((hi[a] - lo[a]) / cell) + 1);
  }
  STRATA_CHECK(
      double(nc_[0]) * double(nc_[1]) * double(nc_[2]) < double(std::numeric_limits<std::uint32_t>::max()),
      Input, "bonds: the sites span too many grid cells ({} x {} x {})", nc_[0], nc_[1], nc_[2]);
  // Counting sort of the sites by cell: each site's cell (in parallel), counts, offsets,
  // then the sites in order, so each cell lists its sites ascending.
  std::vector<std::uint32_t> cell_of(n_);
  for (std::size_t p = 0; p < parts_.size(); ++p) {
    const Lattice& l = *parts_[p];
    par::parallel_for(std::ptrdiff_t(l.size()), [&](std::ptrdiff_t k) {
      const Vec3& x = l.x[std::size_t(k)];
      cell_of[first_[p] + std::size_t(k)] = std::uint32_t(key(coord(x, 0), coord(x, 1), coord(x, 2)));
    });
  }
  start_.assign(std::size_t(cell_count()) + 1, 0);
  for (std::uint32_t c : cell_of) ++start_[std::size_t(c) + 1];
  for (std::size_t c = 0; c + 1 < start_.size(); ++c) start_[c + 1] += start_[c];
  sorted_.resize(n_);
  {
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t g = 0; g < n_; ++g) sorted_[fill[cell_of[g]]++] = std::uint32_t(g);
  }
}

}  // namespace detail

namespace {
/// The pairs (i, j > i) of the grid's sites for which touch(i, j, r²) holds, ascending by
/// i then j: count per site, prefix sum, write (in parallel, the same for any thread count).
template <typename Touch>
BondList list_pairs(const detail::SiteGrid& grid, Touch&& touch) {
  BondList b;
  const std::size_t n = grid.size();
  auto visit = [&](std::size_t i, auto&& emit) {
    const Vec3& p = grid.x(std::uint32_t(i));
    std::uint32_t found[64];
    int nf = 0;
    grid.for_each_near(p, [&](std::uint32_t j) {
      if (j <= i) return;
      const Vec3& q = grid.x(j);
      const double r2 =
          (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
      if (touch(std::uint32_t(i), j, r2) && nf < 64) found[nf++] = j;
    });
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
      const Vec3 &p = grid.x(std::uint32_t(i)), &q = grid.x(j);
      b.length[o] = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                              (p[2] - q[2]) * (p[2] - q[2]));
      ++o;
    });
  });
  for (double len : b.length) b.max_length = std::max(b.max_length, len);
  return b;
}

/// Largest radius of the sites, checked > 0.
double max_radius(const std::vector<const Lattice*>& sites) {
  double r = 0;
  for (const Lattice* l : sites) {
    STRATA_CHECK(l->size() == 0 || l->radius > 0, Input, "bonds: lattice radius {} must be > 0", l->radius);
    r = std::max(r, l->radius);
  }
  return r;
}
}  // namespace

BondList touching_pairs(const Lattice& l, double tol) {
  if (l.size() < 2) return {};
  const double d = 2 * l.radius, lo2 = (d * (1 - tol)) * (d * (1 - tol)),
               hi2 = (d * (1 + tol)) * (d * (1 + tol));
  STRATA_CHECK(d > 0, Input, "bonds: lattice radius {} must be > 0", l.radius);
  // Cell grid of side d(1 + 2 tol): neighbours lie in the 3^dim cells around.
  const detail::SiteGrid grid({&l}, d * (1 + 2 * tol));
  return list_pairs(grid, [&](std::uint32_t, std::uint32_t, double r2) { return r2 >= lo2 && r2 <= hi2; });
}

BondList touching_pairs(const std::vector<const Lattice*>& sites, double tol) {
  STRATA_CHECK(tol >= 0 && tol < 1, Input, "bonds: tolerance {} must be in [0, 1)", tol);
  const double rmax = max_radius(sites), f1 = (1 + tol) * (1 + tol);
  if (rmax == 0) return {};
  const detail::SiteGrid grid(sites, 2 * rmax * (1 + 2 * tol));
  return list_pairs(grid, [&](std::uint32_t i, std::uint32_t j, double r2) {
    const double r = grid.radius(i) + grid.radius(j);
    return r2 <= r * r * f1;
  });
}

PairCounts count_touching_pairs(const std::vector<const Lattice*>& sites, double d_ref, double tol,
                                double width) {
  STRATA_CHECK(d_ref > 0 && width > 0, Input, "bond counts: d_ref = {} and width = {} must be > 0", d_ref,
               width);
  STRATA_CHECK(tol >= 0 && tol < 1, Input, "bond counts: tolerance {} must be in [0, 1)", tol);
  PairCounts out;
  out.d_ref = d_ref;
  out.width = width;
  const double rmax = max_radius(sites);
  if (rmax == 0) return out;
  const double f1 = (1 + tol) * (1 + tol), unit = 1 / (d_ref * width);
  const std::size_t classes = std::size_t(std::lround(2 * rmax * (1 + tol) * unit)) + 1;
  const detail::SiteGrid grid(sites, 2 * rmax * (1 + 2 * tol));
  // Fixed blocks of cells, each with its own class counts, added in block order.
  constexpr std::int64_t kBlock = 1 << 14;
  const std::int64_t ncell = grid.cell_count(), nblock = (ncell + kBlock - 1) / kBlock;
  std::vector<std::size_t> partial(std::size_t(nblock) * classes, 0);
  // One radius for all sites (the usual case): the limit is a constant.
  const bool uniform = grid.uniform_radius();
  const double r_uniform = 2 * sites.front()->radius, limit2 = r_uniform * r_uniform * f1;
  par::parallel_for(std::ptrdiff_t(nblock), [&](std::ptrdiff_t blk) {
    std::size_t* h = &partial[std::size_t(blk) * classes];
    grid.for_each_pair(
        blk * kBlock, std::min(ncell, (blk + 1) * kBlock), [&](std::uint32_t i, std::uint32_t j) {
          const Vec3 &p = grid.x(i), &q = grid.x(j);
          const double r2 =
              (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
          double lim2 = limit2;
          if (!uniform) {
            const double r = grid.radius(i) + grid.radius(j);
            lim2 = r * r * f1;
          }
          // class: length / (d_ref·width) rounded to nearest (lengths are positive)
          if (r2 <= lim2) ++h[std::min(classes - 1, std::size_t(std::sqrt(r2) * unit + 0.5))];
        });
  });
  out.by_class.assign(classes, 0);
  for (std::int64_t blk = 0; blk < nblock; ++blk)
    for (std::size_t k = 0; k < classes; ++k) out.by_class[k] += partial[std::size_t(blk) * classes + k];
  for (std::size_t n : out.by_class) out.pairs += n;
  return out;
}

std::vector<std::uint32_t> undercoordinated_sites(const std::vector<const Lattice*>& sites, int full,
                                                  double tol) {
  STRATA_CHECK(tol >= 0 && tol < 1, Input, "coordination: tolerance {} must be in [0, 1)", tol);
  const double rmax = max_radius(sites);
  std::vector<std::uint32_t> out;
  if (rmax == 0) return out;
  const double f1 = (1 + tol) * (1 + tol);
  const detail::SiteGrid grid(sites, 2 * rmax * (1 + 2 * tol));
  std::vector<std::uint8_t> under(grid.size(), 0);
  par::parallel_for(std::ptrdiff_t(grid.size()), [&](std::ptrdiff_t gi) {
    const auto i = std::uint32_t(gi);
    const Vec3& p = grid.x(i);
    const double ri = grid.radius(i);
    int n = 0;
    grid.for_each_near(p, [&](std::uint32_t j) {
      if (j == i) return;
      const Vec3& q = grid.x(j);
      const double r2 =
          (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
      const double r = ri + grid.radius(j);
      n += r2 <= r * r * f1;
    });
    under[i] = n < full;
  });
  for (std::size_t i = 0; i < under.size(); ++i)
    if (under[i]) out.push_back(std::uint32_t(i));
  return out;
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
