#include "strata/preprocess/fill.hpp"

#include <strata/core/error.hpp>

#include <cmath>

namespace strata::preprocess {

namespace {
Lattice box_lattice(LatticeKind kind, const Bounds& b, double d) {
  const Vec3 size{b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]};
  if (kind == LatticeKind::Hex2D) return hex2d_box(b.lo[0], b.lo[1], size[0], size[1], d);
  return close_packed_box(kind == LatticeKind::HCP ? Packing::HCP : Packing::FCC, b.lo, size, d);
}
}  // namespace

Lattice fill_shape(const Shape& shape, LatticeKind kind, double d, double orientation_deg) {
  STRATA_CHECK(d > 0, Input, "particle diameter {} must be > 0", d);
  const Bounds b = shape.bounds();
  const double r = d / 2;
  if (orientation_deg == 0.0) {
    // Unrotated: the lattice of the bounding box already keeps whole particles inside it.
    Lattice l = box_lattice(kind, b, d);
    if (shape.kind == Shape::Kind::Box) return l;
    return filter(l, [&](std::size_t i) { return shape.contains(l.x[i], r); });
  }
  // Rotated: fill a square (cube) around the bounds wide enough to cover them in any
  // orientation, rotate the sites about the centre, keep those inside the shape.
  const double th = orientation_deg * M_PI / 180.0, c = std::cos(th), s = std::sin(th);
  const Vec3 mid{(b.lo[0] + b.hi[0]) / 2, (b.lo[1] + b.hi[1]) / 2, (b.lo[2] + b.hi[2]) / 2};
  const double half = std::hypot(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1]) / 2 + d;
  Bounds cover = b;
  cover.lo[0] = mid[0] - half, cover.hi[0] = mid[0] + half;
  cover.lo[1] = mid[1] - half, cover.hi[1] = mid[1] + half;
  Lattice l = box_lattice(kind, cover, d);
  for (auto& p : l.x) {
    const double dx = p[0] - mid[0], dy = p[1] - mid[1];
    p[0] = mid[0] + c * dx - s * dy;
    p[1] = mid[1] + s * dx + c * dy;
  }
  return filter(l, [&](std::size_t i) { return shape.contains(l.x[i], r); });
}

}  // namespace strata::preprocess
