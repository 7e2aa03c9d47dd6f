#pragma once
/// Regular particle lattices in boxes: 2D hexagonal (rows along x), 3D hexagonal close
/// packing (ABAB, c-axis along z) and face-centred cubic (ABC, [111] along z), with the
/// selections that boundary conditions need (rows, columns, layers, boxes).
///
/// All particles have the same diameter d; neighbours touch exactly (centre distance d).
/// Generation is deterministic: sites are listed layer by layer (3D), row by row (bottom
/// to top), left to right.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace strata::preprocess {

/// Sites of a lattice.
struct Lattice {
  int dim = 2;
  double radius = 0;                     ///< d/2 (m)
  std::vector<std::array<double, 3>> x;  ///< centres (z = 0 in 2D)
  std::vector<std::int32_t> row;         ///< row within its layer (bottom row 0)
  std::vector<std::int32_t> layer;       ///< layer along z (3D; 0 in 2D)
  std::size_t size() const { return x.size(); }
  /// Frees the memory of the sites (e.g. once they are copied into a model).
  void release();
};

/// 2D hexagonal lattice in [x0, x0+W] × [y0, y0+H]: rows along x spaced d·√3/2, odd rows
/// shifted by d/2, keeping the sites whose whole disk lies inside the box (the specimen of
/// Liu, Pollard & Shi 2013: W = 0.030, H = 0.0305, d = 0.001 gives 1033 disks in 35 rows of
/// 30 and 29).
Lattice hex2d_box(double x0, double y0, double width, double height, double d);

/// 2D hexagonal block of `rows` rows with lower-left disk centre at (x0 + d/2, y0 + d/2):
/// even rows have `columns` disks, odd rows `columns - 1` when `shorter_odd_rows` (a block
/// with straight sides, like the 1033-disk specimen) or `columns` otherwise.
Lattice hex2d_rows(int rows, int columns, double d, double x0 = 0, double y0 = 0,
                   bool shorter_odd_rows = true);

/// 3D stacking of close-packed layers.
enum class Packing { HCP, FCC };

/// 3D close packing in the box [lo, lo + size], keeping spheres wholly inside; layers
/// along z spaced d·√(2/3) (HCP: ABAB, c-axis along z; FCC: ABC, [111] along z).
Lattice close_packed_box(Packing packing, std::array<double, 3> lo, std::array<double, 3> size, double d);

/// Number of sites a lattice of about n particles needs: the side of a square (2D) or cube
/// (3D) box that holds about n sites of diameter d.
double box_side_for(int dim, std::int64_t n, double d);

/// About how many sites a lattice of spacing d puts in a region of `measure`: area in 2D
/// (√3/2·d² per site of the hexagonal lattice), volume in 3D (d³/√2 per site of a close
/// packing).
double sites_in(double measure, double d, int dim);

/// Throws Error(Input) "<what> would hold about N particles ...: about X GB to build, more than
/// ..." when `sites` particles cannot be built on this machine: more than 32-bit particle ids
/// count, or more than its memory at the peak a bonded-particle model reaches while it is
/// built and run (sites, particles, bonds and the time-step estimate; measured at 10^6–10^7
/// particles, with a few per cent of room): 140 bytes per disk and 360 per sphere with shear
/// springs, 110 and 210 with normal springs only (`shear` false: no shear history is kept).
/// Checked before a lattice is filled, so that a tiny diameter is refused at once instead of
/// filling for hours or running out of memory.
void check_sites_fit(double sites, int dim, const std::string& what, bool shear = true);

// ---- selections (indices into the lattice, ascending) -----------------------------------
/// Sites of the highest / lowest row (2D); in 3D the highest / lowest layer.
std::vector<std::uint32_t> top_row(const Lattice& l);
std::vector<std::uint32_t> bottom_row(const Lattice& l);
/// In 3D, the same as top_row / bottom_row.
std::vector<std::uint32_t> top_layer(const Lattice& l);
std::vector<std::uint32_t> bottom_layer(const Lattice& l);
/// The first / last site of every row (every row of every layer in 3D).
std::vector<std::uint32_t> left_column(const Lattice& l);
std::vector<std::uint32_t> right_column(const Lattice& l);
/// Sites whose centre lies in the axis-aligned box [lo, hi] (z ignored in 2D).
std::vector<std::uint32_t> in_box(const Lattice& l, std::array<double, 3> lo, std::array<double, 3> hi);

}  // namespace strata::preprocess
