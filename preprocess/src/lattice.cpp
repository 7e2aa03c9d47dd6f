// Regular lattices (2D hex, 3D HCP/FCC) and selections on them.
#include "strata/preprocess/lattice.hpp"

#include <strata/core/error.hpp>
#include <strata/core/memory.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace strata::preprocess {

void Lattice::release() {
  std::vector<std::array<double, 3>>().swap(x);
  std::vector<std::int32_t>().swap(row);
  std::vector<std::int32_t>().swap(layer);
}

namespace {

/// Appends the sites of one close-packed layer at height z with in-plane shift (sx, sy)
/// (taken modulo the lattice), inside [lo, hi] shrunk by r.
void hex_layer(Lattice& l, double d, double z, double sx, double sy, const double lo[2], const double hi[2],
               int layer, double eps) {
  const double r = 0.5 * d, h = 0.5 * std::numbers::sqrt3 * d;
  sy = std::fmod(sy, 2 * h);
  const double ylo = lo[1] + r, yhi = hi[1] - r, xlo = lo[0] + r, xhi = hi[0] - r;
  for (int k = 0;; ++k) {
    const double y = ylo + sy + k * h;
    if (y > yhi + eps) break;
    // odd rows shift by d/2
    const double s = std::fmod(sx + (k % 2 ? 0.5 * d : 0.0), d);
    for (int c = 0;; ++c) {
      const double x = xlo + s + c * d;
      if (x > xhi + eps) break;
      l.x.push_back({x, y, z});
      l.row.push_back(k);
      l.layer.push_back(layer);
    }
  }
}
}  // namespace

Lattice hex2d_box(double x0, double y0, double width, double height, double d) {
  STRATA_CHECK(d > 0 && width >= d && height >= d, Input,
               "hex lattice: box {} x {} must hold at least one disk of diameter {}", width, height, d);
  Lattice l;
  l.dim = 2;
  l.radius = 0.5 * d;
  const double lo[2] = {x0, y0}, hi[2] = {x0 + width, y0 + height};
  const double n_est = width * height / (0.5 * std::numbers::sqrt3 * d * d) * 1.05 + 16;
  l.x.reserve(static_cast<std::size_t>(n_est));
  l.row.reserve(static_cast<std::size_t>(n_est));
  l.layer.reserve(static_cast<std::size_t>(n_est));
  hex_layer(l, d, 0.0, 0.0, 0.0, lo, hi, 0, 1e-9 * d);
  return l;
}

Lattice hex2d_rows(int rows, int columns, double d, double x0, double y0, bool shorter_odd_rows) {
  STRATA_CHECK(rows >= 1 && columns >= 2 && d > 0, Input, "hex lattice: {} rows x {} columns, d = {}", rows,
               columns, d);
  Lattice l;
  l.dim = 2;
  l.radius = 0.5 * d;
  const double h = 0.5 * std::numbers::sqrt3 * d;
  for (int k = 0; k < rows; ++k) {
    const int nc = (k % 2 && shorter_odd_rows) ? columns - 1 : columns;
    for (int c = 0; c < nc; ++c) {
      l.x.push_back({x0 + 0.5 * d + (k % 2 ? 0.5 * d : 0.0) + c * d, y0 + 0.5 * d + k * h, 0.0});
      l.row.push_back(k);
      l.layer.push_back(0);
    }
  }
  return l;
}

Lattice close_packed_box(Packing packing, std::array<double, 3> lo, std::array<double, 3> size, double d) {
  STRATA_CHECK(d > 0 && size[0] >= d && size[1] >= d && size[2] >= d, Input,
               "close packing: box {} x {} x {} must hold a sphere of diameter {}", size[0], size[1], size[2],
               d);
  Lattice l;
  l.dim = 3;
  l.radius = 0.5 * d;
  const double c = d * std::sqrt(2.0 / 3.0);
  const double lo2[2] = {lo[0], lo[1]}, hi2[2] = {lo[0] + size[0], lo[1] + size[1]};
  const double n_est = size[0] * size[1] * size[2] / (d * d * d / std::sqrt(2.0)) * 1.1 + 64;
  l.x.reserve(static_cast<std::size_t>(n_est));
  l.row.reserve(static_cast<std::size_t>(n_est));
  l.layer.reserve(static_cast<std::size_t>(n_est));
  // stacking positions A (0, 0), B (d/2, d/(2√3)), C (d, d/√3) in the layer plane
  const double shift[3][2] = {{0, 0}, {0.5 * d, d / (2 * std::numbers::sqrt3)}, {d, d / std::numbers::sqrt3}};
  const double eps = 1e-9 * d;
  for (int k = 0;; ++k) {
    const double z = lo[2] + 0.5 * d + k * c;
    if (z > lo[2] + size[2] - 0.5 * d + eps) break;
    const int s = packing == Packing::HCP ? k % 2 : k % 3;
    hex_layer(l, d, z, shift[s][0], shift[s][1], lo2, hi2, k, eps);
  }
  return l;
}

double box_side_for(int dim, std::int64_t n, double d) {
  const double cell = dim == 2 ? 0.5 * std::numbers::sqrt3 * d * d : d * d * d / std::sqrt(2.0);
  return dim == 2 ? std::sqrt(static_cast<double>(n) * cell) : std::cbrt(static_cast<double>(n) * cell);
}

namespace {
std::vector<std::uint32_t> where(const Lattice& l, auto&& pred) {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < l.size(); ++i)
    if (pred(i)) out.push_back(static_cast<std::uint32_t>(i));
  return out;
}
}  // namespace

std::vector<std::uint32_t> top_row(const Lattice& l) {
  if (l.size() == 0) return {};
  if (l.dim == 3) return top_layer(l);
  const auto m = *std::max_element(l.row.begin(), l.row.end());
  return where(l, [&](std::size_t i) { return l.row[i] == m; });
}
std::vector<std::uint32_t> bottom_row(const Lattice& l) {
  if (l.size() == 0) return {};
  if (l.dim == 3) return bottom_layer(l);
  const auto m = *std::min_element(l.row.begin(), l.row.end());
  return where(l, [&](std::size_t i) { return l.row[i] == m; });
}
std::vector<std::uint32_t> top_layer(const Lattice& l) {
  if (l.size() == 0) return {};
  if (l.dim == 2) return top_row(l);
  const auto m = *std::max_element(l.layer.begin(), l.layer.end());
  return where(l, [&](std::size_t i) { return l.layer[i] == m; });
}
std::vector<std::uint32_t> bottom_layer(const Lattice& l) {
  if (l.size() == 0) return {};
  if (l.dim == 2) return bottom_row(l);
  const auto m = *std::min_element(l.layer.begin(), l.layer.end());
  return where(l, [&](std::size_t i) { return l.layer[i] == m; });
}
// Sites of a row are listed left to right: the first / last listed site of each
// (layer, row) is the left / right end of that row.
namespace {
std::vector<std::uint32_t> row_ends(const Lattice& l, bool last) {
  std::map<std::pair<std::int32_t, std::int32_t>, std::uint32_t> end;
  for (std::size_t i = 0; i < l.size(); ++i) {
    const auto key = std::make_pair(l.layer.empty() ? 0 : l.layer[i], l.row[i]);
    const auto it = end.find(key);
    if (it == end.end())
      end.emplace(key, static_cast<std::uint32_t>(i));
    else if (last)
      it->second = static_cast<std::uint32_t>(i);
  }
  std::vector<std::uint32_t> out;
  for (const auto& [k, i] : end) out.push_back(i);
  std::sort(out.begin(), out.end());
  return out;
}
}  // namespace
std::vector<std::uint32_t> left_column(const Lattice& l) { return row_ends(l, false); }
std::vector<std::uint32_t> right_column(const Lattice& l) { return row_ends(l, true); }
std::vector<std::uint32_t> in_box(const Lattice& l, std::array<double, 3> lo, std::array<double, 3> hi) {
  return where(l, [&](std::size_t i) {
    for (int a = 0; a < l.dim; ++a)
      if (l.x[i][a] < lo[a] || l.x[i][a] > hi[a]) return false;
    return true;
  });
}

double sites_in(double measure, double d, int dim) {
  const double per_site = dim == 2 ? std::sqrt(3.0) / 2 * d * d : d * d * d / std::sqrt(2.0);
  return measure / per_site;
}

void check_sites_fit(double sites, int dim, const std::string& what, bool shear) {
  const double ids = double(std::numeric_limits<std::uint32_t>::max());
  const double per_site = dim == 2 ? (shear ? 140.0 : 110.0) : (shear ? 360.0 : 210.0);
  const double bytes = sites * per_site, memory = double(sys::physical_memory_bytes());
  if (!(sites > ids) && !(memory > 0 && bytes > memory)) return;
  fail(ErrorKind::Input,
       "{} would hold about {:.3g} particles: about {:.3g} GB to build, more than {}; allowed: larger "
       "particles or a smaller region",
       what, sites, bytes / 1e9,
       sites > ids
           ? fmt::format("the {} particles that 32-bit ids number", std::numeric_limits<std::uint32_t>::max())
           : fmt::format("this machine's {:.3g} GB of memory", memory / 1e9));
}

}  // namespace strata::preprocess
