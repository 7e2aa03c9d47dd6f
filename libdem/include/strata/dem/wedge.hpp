#pragma once
/// Thrust wedges of a 2D sandbox model: the critical taper of Coulomb wedge theory, and the
/// taper and fault dips measured from a shortened particle model.
#include <array>
#include <cstddef>
#include <vector>

namespace strata::dem {

/// The critical taper of a dry, non-cohesive Coulomb wedge on a horizontal base (Dahlen
/// 1984, "Noncohesive critical Coulomb wedges: an exact solution"): the surface slope alpha
/// solves alpha + psi_0(alpha) = psi_b with
///   psi_b = ½·asin(sin φ_b / sin φ) − ½·φ_b,   psi_0 = ½·asin(sin alpha / sin φ) − ½·alpha,
/// where φ and φ_b are the internal and basal friction angles and psi_b, psi_0 the angles of
/// the greatest compression to the base and to the surface. Coulomb planes lie at
/// ±(45° − φ/2) from the greatest compression, so at the base forethrusts (verging towards the
/// toe, dipping towards the backstop) dip at 45° − φ/2 − psi_b and backthrusts at
/// 45° − φ/2 + psi_b.
struct CriticalTaper {
  double taper_deg = 0;           ///< alpha
  double psi_b_deg = 0;           ///< greatest compression to the base
  double forethrust_dip_deg = 0;  ///< at the base
  double backthrust_dip_deg = 0;  ///< at the base
};

/// The critical taper for friction coefficients μ = tan φ (internal) and μ_b = tan φ_b
/// (basal). Throws strata::Error (Input) unless 0 < μ_b < μ: a base at least as strong as the
/// wedge gives no wedge.
CriticalTaper critical_taper(double internal_friction, double basal_friction);

/// The friction coefficients (internal, basal) that a forethrust and a backthrust dip imply
/// by the relations above: φ = 90° − (δ_f + δ_b) and psi_b = (δ_b − δ_f)/2, solved for φ_b.
/// Zero basal friction when the dips are equal; throws Input when they imply no friction.
std::array<double, 2> frictions_from_dips(double forethrust_dip_deg, double backthrust_dip_deg);

/// A fault: a straight line traced by the fault points.
struct Fault {
  bool forethrust = true;  ///< dips towards the backstop (verges towards the toe)
  double dip_deg = 0;      ///< from the horizontal, 0-90
  double x_at_base = 0;    ///< where the line meets the base (m)
  std::size_t points = 0;  ///< fault points within two spacings of it
};

/// What measure_wedge needs. Shortening acts along x, gravity along −y.
struct WedgeInput {
  /// Particle centres (x, y) and radii of the deforming cover at the time measured.
  std::vector<std::array<double, 3>> particles;
  /// Where the cover started: its top before shortening (m) and the base's height (m).
  double initial_top = 0;
  double base = 0;
  /// The backstop's (pushing wall's) position along x and the side it stands on: +1 when it
  /// stands at larger x than the cover (pushes towards −x), −1 otherwise.
  double backstop_x = 0;
  int backstop_side = 1;
  /// Points that trace the faults: e.g. the particles of the cover's shear zones (high shear
  /// strain), or the midpoints of bonds that broke in shear during shortening.
  std::vector<std::array<double, 2>> fault_points;
  /// Particle diameter (m): bins of the surface profile, Hough bins, the uplift that marks
  /// the deformed wedge.
  double spacing = 1;
};

struct Wedge {
  double taper_deg = 0;          ///< surface slope, least squares from the toe to the backstop
  double toe_x = 0;              ///< deformation front: last bin raised by a spacing (m)
  double width = 0;              ///< from the toe to the backstop (m)
  double max_uplift = 0;         ///< highest top above initial_top (m)
  std::size_t profile_bins = 0;  ///< surface bins in the fit
  std::vector<Fault> faults;     ///< strongest first
};

/// Measures the wedge: the surface profile (highest particle top in bins of two spacings),
/// the toe (the farthest bin from the backstop raised by at least one spacing, before five
/// bins in a row that are not), the taper (a least-squares line through the profile from
/// the toe to one spacing short of the backstop), and the faults (Hough lines through the
/// fault points over the wedge, taken one at a time by take_lines with each line's points
/// within two spacings set aside, kept when they dip 10-80°; the search ends at a line with
/// under 0.3 times the votes of the first). Deterministic.
Wedge measure_wedge(const WedgeInput& in);

}  // namespace strata::dem
