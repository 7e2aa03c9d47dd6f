// Finite shear strain of particles from their start and current positions (2D).
#include "strata/dem/strain.hpp"

#include <strata/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace strata::dem {

std::vector<double> shear_strain_2d(const std::vector<std::array<double, 3>>& start,
                                    const std::vector<std::array<double, 3>>& now, double radius) {
  STRATA_CHECK(start.size() == now.size(), Input, "shear strain: {} start positions for {} particles",
               start.size(), now.size());
  STRATA_CHECK(radius > 0, Input, "shear strain: the neighbour radius must be > 0 (m), not {}", radius);
  const std::size_t n = start.size();
  std::vector<double> gamma(n, 0.0);
  if (n == 0) return gamma;
  // cell grid of the start positions
  auto cell = [&](double v) { return static_cast<std::int64_t>(std::floor(v / radius)); };
  auto key = [](std::int64_t cx, std::int64_t cy) { return (cx << 32) ^ (cy & 0xffffffff); };
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;
  for (std::size_t i = 0; i < n; ++i)
    grid[key(cell(start[i][0]), cell(start[i][1]))].push_back(static_cast<std::uint32_t>(i));
  const double r2 = radius * radius;
  for (std::size_t i = 0; i < n; ++i) {
    // A = Σ dX dXᵀ, B = Σ dx dXᵀ over the neighbours; F = B A⁻¹
    double a00 = 0, a01 = 0, a11 = 0, b00 = 0, b01 = 0, b10 = 0, b11 = 0;
    int count = 0;
    const std::int64_t cx = cell(start[i][0]), cy = cell(start[i][1]);
    for (std::int64_t gx = cx - 1; gx <= cx + 1; ++gx)
      for (std::int64_t gy = cy - 1; gy <= cy + 1; ++gy) {
        const auto it = grid.find(key(gx, gy));
        if (it == grid.end()) continue;
        for (const std::uint32_t j : it->second) {
          if (j == i) continue;
          const double X0 = start[j][0] - start[i][0], X1 = start[j][1] - start[i][1];
          if (X0 * X0 + X1 * X1 > r2) continue;
          const double x0 = now[j][0] - now[i][0], x1 = now[j][1] - now[i][1];
          a00 += X0 * X0, a01 += X0 * X1, a11 += X1 * X1;
          b00 += x0 * X0, b01 += x0 * X1, b10 += x1 * X0, b11 += x1 * X1;
          ++count;
        }
      }
    const double det = a00 * a11 - a01 * a01;
    if (count < 2 || det <= 1e-12 * (a00 + a11) * (a00 + a11)) continue;
    // A⁻¹ = [a11 −a01; −a01 a00]/det
    const double f00 = (b00 * a11 - b01 * a01) / det, f01 = (b01 * a00 - b00 * a01) / det;
    const double f10 = (b10 * a11 - b11 * a01) / det, f11 = (b11 * a00 - b10 * a01) / det;
    // C = FᵀF and its eigenvalues λ1² ≥ λ2²
    const double c00 = f00 * f00 + f10 * f10, c01 = f00 * f01 + f10 * f11, c11 = f01 * f01 + f11 * f11;
    const double mean = 0.5 * (c00 + c11), dev = std::hypot(0.5 * (c00 - c11), c01);
    const double l1 = mean + dev, l2 = mean - dev;
    if (!(l2 > 0)) continue;  // a neighbourhood turned inside out: no strain to speak of
    gamma[i] = 0.5 * std::log(l1 / l2);
  }
  return gamma;
}

}  // namespace strata::dem
