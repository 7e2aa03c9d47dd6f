#pragma once
// A cell grid over the sites of one or more lattices, taken as one set of sites: the one
// neighbour search of the bond functions in ecc.cpp (listing touching pairs, counting them
// by length class, coordination numbers). Sites are sorted by cell with a counting sort;
// the grid holds one offset per cell and one index per site (4 bytes each), nothing else.
#include <strata/core/error.hpp>
#include <strata/preprocess/lattice.hpp>
#include <strata/preprocess/shapes.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace strata::preprocess::detail {

class SiteGrid {
 public:
  /// Site k of parts[p] has the global index first(p) + k (parts in order). Cells have side
  /// `cell`, at least the largest centre distance searched, so that the neighbours of a
  /// site lie in the 3^dim cells around its own.
  SiteGrid(const std::vector<const Lattice*>& parts, double cell);

  std::size_t size() const { return n_; }
  std::int64_t cell_count() const { return nc_[0] * nc_[1] * nc_[2]; }
  /// Centre and radius of the site with global index g.
  const Vec3& x(std::uint32_t g) const {
    if (single_) return single_[g];
    const std::size_t p = part_of(g);
    return parts_[p]->x[g - first_[p]];
  }
  double radius(std::uint32_t g) const { return parts_[part_of(g)]->radius; }
  /// Whether every site has the same radius (then radius(0) is it).
  bool uniform_radius() const {
    for (const Lattice* l : parts_)
      if (l->size() > 0 && l->radius != parts_.front()->radius) return false;
    return true;
  }

  /// Calls f(j) for every site j (global index) in the cells around p's cell, p's own
  /// site included.
  template <typename F>
  void for_each_near(const Vec3& p, F&& f) const {
    const std::int64_t cx = coord(p, 0), cy = coord(p, 1), cz = coord(p, 2);
    for (std::int64_t z = std::max<std::int64_t>(0, cz - 1); z <= std::min(nc_[2] - 1, cz + 1); ++z)
      for (std::int64_t y = std::max<std::int64_t>(0, cy - 1); y <= std::min(nc_[1] - 1, cy + 1); ++y)
        for (std::int64_t x = std::max<std::int64_t>(0, cx - 1); x <= std::min(nc_[0] - 1, cx + 1); ++x) {
          const auto c = std::size_t(key(x, y, z));
          for (std::uint32_t s = start_[c]; s < start_[c + 1]; ++s) f(sorted_[s]);
        }
  }

  /// Calls f(i, j) once for every unordered pair of sites that lie in the same cell or in
  /// neighbouring cells, for the cells [c0, c1) and their forward neighbours (a half shell
  /// of 13 cells in 3D, 4 in 2D): over all cells, every such pair exactly once.
  template <typename F>
  void for_each_pair(std::int64_t c0, std::int64_t c1, F&& f) const {
    if (c0 >= c1) return;
    // Cell coordinates of c0 once, then stepped along (no division per cell).
    std::int64_t cx = c0 % nc_[0], cy = c0 / nc_[0] % nc_[1], cz = c0 / (nc_[0] * nc_[1]);
    for (std::int64_t c = c0; c < c1; ++c) {
      const std::uint32_t b = start_[std::size_t(c)], e = start_[std::size_t(c) + 1];
      if (b != e) {
        for (std::uint32_t s = b; s < e; ++s)
          for (std::uint32_t t = s + 1; t < e; ++t) f(sorted_[s], sorted_[t]);
        for (const auto& o : kForward) {
          const std::int64_t x = cx + o[0], y = cy + o[1], z = cz + o[2];
          if (x < 0 || x >= nc_[0] || y < 0 || y >= nc_[1] || z >= nc_[2]) continue;
          const auto n = std::size_t(key(x, y, z));
          const std::uint32_t nb = start_[n], ne = start_[n + 1];
          for (std::uint32_t s = b; s < e; ++s)
            for (std::uint32_t t = nb; t < ne; ++t) f(sorted_[s], sorted_[t]);
        }
      }
      if (++cx == nc_[0]) {
        cx = 0;
        if (++cy == nc_[1]) cy = 0, ++cz;
      }
    }
  }

 private:
  /// Neighbour offsets after a cell in (z, y, x) order: half of the 26 around it.
  static constexpr std::int64_t kForward[13][3] = {{1, 0, 0},  {-1, 1, 0}, {0, 1, 0},  {1, 1, 0}, {-1, -1, 1},
                                                   {0, -1, 1}, {1, -1, 1}, {-1, 0, 1}, {0, 0, 1}, {1, 0, 1},
                                                   {-1, 1, 1}, {0, 1, 1},  {1, 1, 1}};

  std::size_t part_of(std::uint32_t g) const {
    std::size_t p = parts_.size() - 1;
    while (first_[p] > g) --p;
    return p;
  }
  std::int64_t coord(const Vec3& p, int a) const {
    return std::clamp<std::int64_t>(std::int64_t((p[a] - lo_[a]) / cell_), 0, nc_[a] - 1);
  }
  std::int64_t key(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return (z * nc_[1] + y) * nc_[0] + x;
  }

  std::vector<const Lattice*> parts_;
  const Vec3* single_ = nullptr;      ///< the sites when there is one part
  std::vector<std::uint32_t> first_;  ///< global index of each part's first site
  std::size_t n_ = 0;
  double cell_ = 0;
  double lo_[3] = {0, 0, 0};
  std::int64_t nc_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_;   ///< cell_count() + 1 offsets into sorted_
  std::vector<std::uint32_t> sorted_;  ///< global site indices by cell, ascending within a cell
};

}  // namespace strata::preprocess::detail
