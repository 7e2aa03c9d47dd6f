#pragma once
/// Filling primitive shapes with regular lattices.
#include <strata/preprocess/lattice.hpp>
#include <strata/preprocess/shapes.hpp>

namespace strata::preprocess {

/// Lattice kinds a region can be filled with.
enum class LatticeKind { Hex2D, HCP, FCC };

/// Fills `shape` with a lattice of diameter d, rotated by `orientation_deg` about the z axis
/// through the centre of the shape's bounds, keeping the particles whose whole disk/sphere
/// lies inside the shape. Row and layer indices are those of the (rotated) lattice, so
/// top_row/bottom_row/left_column/right_column keep their meaning for boxes.
Lattice fill_shape(const Shape& shape, LatticeKind kind, double d, double orientation_deg = 0.0);

/// Keeps the sites for which keep(i) is true (rows and layers follow).
template <typename Pred>
Lattice filter(const Lattice& l, Pred&& keep) {
  Lattice out;
  out.dim = l.dim;
  out.radius = l.radius;
  for (std::size_t i = 0; i < l.size(); ++i) {
    if (!keep(i)) continue;
    out.x.push_back(l.x[i]);
    out.row.push_back(l.row[i]);
    out.layer.push_back(l.layer.empty() ? 0 : l.layer[i]);
  }
  return out;
}

}  // namespace strata::preprocess
