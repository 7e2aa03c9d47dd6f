#pragma once
/// What `strata mesh` reports about a built model beyond counts: bond counts by length
/// class, and bond length and direction histograms (CSV and PNG) that show the spread of
/// an eccentric lattice (ECC4D, SPEC C4).
#include <strata/dem/simulation.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <vector>

namespace strata::app {

/// Bond geometry of a model at its initial state.
struct BondStats {
  double d_ref = 0;             ///< reference length: the particle diameter (m)
  std::vector<double> length;   ///< per bond (m)
  std::vector<double> azimuth;  ///< per bond: angle in the xy plane, [0, 180) degrees
  std::vector<double> polar;    ///< 3D: angle to the z axis, [0, 90] degrees
};

/// Bonds above this count are not listed one by one for the report (memory).
inline constexpr std::size_t kMaxReportedBonds = 20'000'000;

/// Lengths and directions of the model's bonds (empty above kMaxReportedBonds bonds).
BondStats bond_stats(const dem::Simulation& sim, double d_ref);

/// Bond counts by length class: classes of width `width`·d_ref centred on multiples of it,
/// as {"1.00": n, "1.02": n, ...} keyed by length / d_ref.
nlohmann::json bond_length_classes(const BondStats& s, double width = 0.02);

/// Writes bond_lengths.csv and bond_directions.csv into `dir`, and the matching PNG plots
/// when this build renders (a failed plot is a warning); returns the files written.
std::vector<std::filesystem::path> write_bond_histograms(const BondStats& s, const std::filesystem::path& dir,
                                                         int bins = 50);

}  // namespace strata::app
