#pragma once
// CGAL behind a plain interface: exact orientation predicates, closed surfaces (STL/OFF).
// Without CGAL the predicates fall back to long double arithmetic and closed surfaces are
// Unsupported.
#include <strata/preprocess/geometry.hpp>

#include <filesystem>
#include <memory>

namespace strata::preprocess::detail {

/// Sign (-1, 0, 1) of det[b - a, c - a, p - a], exactly.
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p);
/// Sign of (b - a) × (c - a) in the plane (u, v), exactly.
int orient2d_exact(double au, double av, double bu, double bv, double cu, double cv);

/// Reads a closed triangle surface (.stl, .off); Error(Input) when it cannot be read or is
/// not closed. Faces are triangulated and oriented outward.
/// `unit`: metres per unit of the file's coordinates (the surface is scaled to metres).
std::shared_ptr<const ClosedSurface> read_closed_surface(const std::filesystem::path& file,
                                                         double unit = 1.0);
/// Inside test (points on the surface count as inside).
bool surface_contains(const ClosedSurface& s, const Vec3& p);
double surface_volume(const ClosedSurface& s);
Bounds surface_bounds(const ClosedSurface& s);
/// The surface's triangles as a SimplexMesh of dimension 2.
SimplexMesh surface_triangles(const ClosedSurface& s);

}  // namespace strata::preprocess::detail
