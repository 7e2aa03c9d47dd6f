#pragma once
/// Hough transform of 2D points: finds dominant straight lines, e.g. shear bands traced by
/// broken-bond midpoints (in uniaxial compression: two conjugate, X-shaped bands).
#include <array>
#include <cstddef>
#include <functional>
#include <vector>

namespace strata::dem {

/// A line x·cos(theta) + y·sin(theta) = rho.
struct HoughLine {
  double theta;  ///< angle of the line's normal, radians in [0, π)
  double rho;    ///< signed distance of the line from the origin (m)
  double votes;  ///< (weighted) number of points within half a rho bin of the line
  /// Direction of the line itself, degrees in [0, 180) measured from the +x axis.
  double direction_deg() const;
  /// Signed distance of the point p from the line (m).
  double distance(const std::array<double, 2>& p) const;
};

struct HoughOptions {
  int theta_bins = 180;            ///< bins over [0, π)
  double rho_bin = 0;              ///< rho bin width (m); 0: 1/100 of the points' extent
  int lines = 2;                   ///< number of lines to return
  double suppress_theta_deg = 15;  ///< non-maximum suppression window in angle (degrees)
  double suppress_rho = 0;         ///< and in rho (m); 0: 10 rho bins
};

/// The strongest lines through `points` (x, y), strongest first. Deterministic.
std::vector<HoughLine> hough_lines(const std::vector<std::array<double, 2>>& points,
                                   const HoughOptions& options = {});

/// Lines taken one at a time, so that a line is not found again at a nearby angle: each round
/// takes the strongest line (`options.lines` is not used) through the points left, and `take`
/// gets it with the signed distances of those points to it and returns the half-width of the
/// zone about it whose points are set aside before the next round (negative: stop here). At
/// most `rounds` rounds, while at least `min_points` are left; ends at a line with under
/// `min_fraction` times the votes of the first (a stray alignment of scattered points).
/// Deterministic.
void take_lines(std::vector<std::array<double, 2>> points, HoughOptions options, int rounds,
                std::size_t min_points, double min_fraction,
                const std::function<double(const HoughLine&, const std::vector<double>&)>& take);

/// A shear band: a straight, narrow zone of broken bonds.
struct ShearBand {
  /// Inclination of the band to the loading axis, degrees in (-90, 90], counter-clockwise
  /// positive: the two bands of a conjugate pair have opposite signs.
  double angle_deg = 0;
  /// Full width at half maximum of the breaks' density across the band (m).
  double width = 0;
  HoughLine line;  ///< its centre line
  /// Half-width of the zone counted as the band: half its width, at least half a spacing.
  double reach = 0;
  std::size_t breaks = 0;  ///< points within `reach` of the centre line
  /// Whether the point p lies in the band (within `reach` of its centre line).
  bool holds(const std::array<double, 2>& p) const;
};

/// The conjugate pair of shear bands traced by `points` (the midpoints of broken bonds, e.g.
/// those that broke after the peak stress). Lines are taken one at a time, strongest first,
/// by the Hough transform with rho bins of one particle `spacing`; each line's points (within
/// one band width of it) are set aside before the next is sought, and the search ends at a
/// line with under 0.4 times the points of the first (a stray alignment of scattered breaks).
/// The bands are the first line leaning each way from the loading axis (`axis` 0: x, 1: y)
/// by 10 to 80 degrees: axial splitting and cracks along the platens are not shear bands.
/// A band's width is the full width at half maximum of the histogram (bins of half a
/// spacing) of its points' distances to the line, over ±8 spacings. None, one or two bands;
/// deterministic.
std::vector<ShearBand> conjugate_bands(const std::vector<std::array<double, 2>>& points, int axis,
                                       double spacing);

}  // namespace strata::dem
