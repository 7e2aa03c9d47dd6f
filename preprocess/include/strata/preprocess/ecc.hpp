#pragma once
/// Eccentric lattices (ECC4D of Zhao, Qiao, Zhang, Sun & Chen 2021, "Eccentric
/// four-dimensional lattice spring model for heterogeneous rock fracturing"): each particle's
/// centroid moves by a random offset, the bonds stay those of the regular lattice, and bonds
/// longer than Rc·L_max are weakened (k -> γ·k).
///
/// Bonding rule: the bonds of an eccentric lattice are the pairs that touch in the regular
/// lattice (centre distance d), found with a cell grid before the offsets are applied; their
/// lengths are measured after. (Bonding "touching pairs" after the offsets would lose most
/// bonds, since offset particles no longer touch.)
///
/// Type B offsets (sphere): that paper gives θ = arccos(U(0,1)), φ = 2π·U(−1,1), which only
/// covers the hemisphere z >= 0 and shifts every centroid upward on average by Ra·R/2.
/// strata draws uniformly on the whole sphere (cos θ = U(−1,1), φ = 2π·U(0,1)); in 2D on the
/// circle of radius Ra·R. Offsets come from a counter-based generator keyed by (seed,
/// particle index), so they do not depend on the number of threads.
#include <strata/preprocess/lattice.hpp>
#include <strata/preprocess/shapes.hpp>

#include <cstdint>
#include <vector>

namespace strata::preprocess {

/// Kind of centroid offsets.
enum class Eccentricity { None, Cube, Sphere };

struct EccOptions {
  Eccentricity type = Eccentricity::None;
  double ra = 0;     ///< Ra in [0, 1): offset size as a fraction of the radius R
  double rc = 1;     ///< Rc in (0, 1]: bonds longer than Rc·L_max are weakened
  double gamma = 1;  ///< γ: stiffness factor of weakened bonds
  std::uint64_t seed = 1;
};

/// Bonds as data (pairs i < j, ascending by i then j) with per-bond stiffness factors.
struct BondList {
  std::vector<std::uint32_t> i, j;
  std::vector<double> length;           ///< centre distance (m)
  std::vector<float> stiffness_factor;  ///< 1, or γ for weakened bonds
  double max_length = 0;                ///< L_max
  std::size_t size() const { return i.size(); }
  std::size_t weakened() const;
};

/// Pairs of sites whose centres lie within d·(1 ± tol) (d = 2·radius), by a cell grid;
/// every factor 1.
BondList touching_pairs(const Lattice& l, double tol = 1e-6);

/// Pairs of `sites` (several lattices taken as one set: site k of lattice p has the global
/// index k + the sizes of the lattices before it) whose centres lie within
/// (r_i + r_j)·(1 + tol), the bonding rule of dem::Simulation::bond_touching_pairs
/// (overlapping pairs included), ascending by i then j, global indices; every factor 1.
BondList touching_pairs(const std::vector<const Lattice*>& sites, double tol = 1e-6);

/// Touching pairs of a set of sites counted by length class, without storing the pairs.
struct PairCounts {
  std::size_t pairs = 0;
  double d_ref = 0;  ///< reference length of the classes (m)
  double width = 0;  ///< class width, as a fraction of d_ref
  /// by_class[k]: pairs with round(length / (d_ref·width)) = k (k = 50 is length = d_ref
  /// for the default width 0.02).
  std::vector<std::size_t> by_class;
};

/// Counts the pairs that touching_pairs(sites, tol) lists (e.g. the regions of a model:
/// the bond count of the model dem::Simulation::bond_touching_pairs builds from them). On a regular lattice
/// (no two sites closer than d) this is touching_pairs().size(). Streams over the cell grid of touching_pairs
/// (half of the neighbour cells per cell), in parallel over fixed blocks of cells whose partial counts are
/// added in block order: the same result for any number of threads. Memory: 4 bytes per site and per cell,
/// and 4 per site while the grid is sorted; never the pairs.
PairCounts count_touching_pairs(const std::vector<const Lattice*>& sites, double d_ref, double tol = 1e-6,
                                double width = 0.02);

/// Sites of `sites` (global indices as in count_touching_pairs: lattice after lattice,
/// ascending) that touch fewer than `full` others by the rule of count_touching_pairs: on a
/// regular lattice (full = 6 in 2D, 12 in 3D) its surface. Same grid, one byte per site.
std::vector<std::uint32_t> undercoordinated_sites(const std::vector<const Lattice*>& sites, int full,
                                                  double tol = 1e-6);

/// Moves every centroid by its ECC4D offset (uniform in a cube of half-side Ra·R, or
/// uniform on a sphere / circle of radius Ra·R).
void apply_eccentricity(Lattice& l, const EccOptions& opt);

/// The eccentric lattice and its bonds: bonds = touching pairs of `regular`, lengths after
/// the offsets, factors γ where length > Rc·L_max.
struct EccLattice {
  Lattice lattice;
  BondList bonds;
};
EccLattice make_eccentric(const Lattice& regular, const EccOptions& opt);

/// Counts of `values` in `bins` equal bins over [lo, hi] (values outside are clamped in).
std::vector<std::size_t> histogram(const std::vector<double>& values, double lo, double hi, int bins);

/// Bond directions for histograms: the azimuth in the xy plane in degrees, [0, 180)
/// (bonds have no sense), and in 3D the angle to the z axis in degrees, [0, 90].
void bond_directions(const Lattice& l, const BondList& b, std::vector<double>& azimuth_deg,
                     std::vector<double>& polar_deg);

}  // namespace strata::preprocess
