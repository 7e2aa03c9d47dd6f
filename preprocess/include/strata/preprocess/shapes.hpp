#pragma once
/// Primitive region shapes written directly in a scene: box, disk/cylinder, sphere, polygon.
/// A particle belongs to a region when its whole disk/sphere lies inside the shape.
#include <array>
#include <vector>

namespace strata::preprocess {

using Vec3 = std::array<double, 3>;

/// An axis-aligned bounding box.
struct Bounds {
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
};

/// A primitive shape in 2D (z ignored) or 3D.
struct Shape {
  enum class Kind { Box, Disk, Sphere, Polygon };
  Kind kind = Kind::Box;
  int dim = 2;
  Vec3 origin{0, 0, 0}, size{0, 0, 0};         ///< Box: lower corner and extent
  Vec3 center{0, 0, 0};                        ///< Disk, Sphere
  double radius = 0;                           ///< Disk (a cylinder along z in 3D), Sphere
  double z_min = 0, z_max = 0;                 ///< Disk in 3D: extent along z
  std::vector<std::array<double, 2>> polygon;  ///< Polygon vertices (2D; a prism along z in 3D)

  /// Whether a ball of radius `r` centred at `p` lies entirely inside the shape.
  bool contains(const Vec3& p, double r) const;
  /// Bounding box of the shape.
  Bounds bounds() const;
  /// Area (2D) or volume (3D) of the shape.
  double measure() const;
};

/// Signed distance from p to the boundary of a simple polygon (negative inside).
double polygon_signed_distance(const std::vector<std::array<double, 2>>& poly, double x, double y);

}  // namespace strata::preprocess
