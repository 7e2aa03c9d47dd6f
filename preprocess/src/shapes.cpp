#include "strata/preprocess/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace strata::preprocess {

double polygon_signed_distance(const std::vector<std::array<double, 2>>& poly, double x, double y) {
  // Distance to the nearest edge, negative when inside (even-odd crossing rule).
  double d2 = std::numeric_limits<double>::infinity();
  bool inside = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const double ax = poly[j][0], ay = poly[j][1], bx = poly[i][0], by = poly[i][1];
    const double ex = bx - ax, ey = by - ay;
    const double len2 = ex * ex + ey * ey;
    const double t = len2 > 0 ? std::clamp(((x - ax) * ex + (y - ay) * ey) / len2, 0.0, 1.0) : 0.0;
    const double dx = x - (ax + t * ex), dy = y - (ay + t * ey);
    d2 = std::min(d2, dx * dx + dy * dy);
    if ((ay > y) != (by > y) && x < ax + (y - ay) * ex / ey) inside = !inside;
  }
  const double d = std::sqrt(d2);
  return inside ? -d : d;
}

bool Shape::contains(const Vec3& p, double r) const {
  const double eps = 1e-9 * r;  // sites exactly one radius from a face are kept
  switch (kind) {
    case Kind::Box:
      for (int a = 0; a < dim; ++a)
        if (p[a] - r < origin[a] - eps || p[a] + r > origin[a] + size[a] + eps) return false;
      return true;
    case Kind::Disk: {
      const double dx = p[0] - center[0], dy = p[1] - center[1];
      if (dim == 3 && (p[2] - r < z_min - eps || p[2] + r > z_max + eps)) return false;
      return std::sqrt(dx * dx + dy * dy) + r <= radius + eps;
    }
    case Kind::Sphere: {
      double d2 = 0;
      for (int a = 0; a < dim; ++a) d2 += (p[a] - center[a]) * (p[a] - center[a]);
      return std::sqrt(d2) + r <= radius + eps;
    }
    case Kind::Polygon:
      if (dim == 3 && (p[2] - r < z_min - eps || p[2] + r > z_max + eps)) return false;
      return polygon_signed_distance(polygon, p[0], p[1]) <= -r + eps;
  }
  return false;
}

Bounds Shape::bounds() const {
  Bounds b;
  switch (kind) {
    case Kind::Box:
      b.lo = origin;
      for (int a = 0; a < 3; ++a) b.hi[a] = origin[a] + size[a];
      break;
    case Kind::Disk:
    case Kind::Sphere:
      for (int a = 0; a < 3; ++a) b.lo[a] = center[a] - radius, b.hi[a] = center[a] + radius;
      if (kind == Kind::Disk) b.lo[2] = z_min, b.hi[2] = z_max;
      break;
    case Kind::Polygon:
      b.lo = {INFINITY, INFINITY, z_min};
      b.hi = {-INFINITY, -INFINITY, z_max};
      for (const auto& v : polygon)
        for (int a = 0; a < 2; ++a) b.lo[a] = std::min(b.lo[a], v[a]), b.hi[a] = std::max(b.hi[a], v[a]);
      break;
  }
  if (dim == 2) b.lo[2] = b.hi[2] = 0;
  return b;
}

double Shape::measure() const {
  const double depth = dim == 3 ? z_max - z_min : 1.0;
  switch (kind) {
    case Kind::Box:
      return dim == 3 ? size[0] * size[1] * size[2] : size[0] * size[1];
    case Kind::Disk:
      return M_PI * radius * radius * depth;
    case Kind::Sphere:
      return dim == 3 ? 4.0 / 3.0 * M_PI * radius * radius * radius : M_PI * radius * radius;
    case Kind::Polygon: {
      double a = 0;  // shoelace formula
      for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++)
        a += polygon[j][0] * polygon[i][1] - polygon[i][0] * polygon[j][1];
      return std::abs(a) / 2 * depth;
    }
  }
  return 0;
}

}  // namespace strata::preprocess
