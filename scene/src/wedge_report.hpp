#pragma once
// Internal: the thrust-wedge section of summary.json ([probe] wedge_group).
#include <nlohmann/json.hpp>
#include <strata/dem/simulation.hpp>

#include <string>
#include <vector>

namespace strata::scene {

/// The taper and faults of the shortened cover `group` (a 2D model shortened along x under
/// gravity along −y by `backstop`, a group of particles driven along x, or when that is empty
/// by the [[wall]] that moves along x), with the critical taper of `friction` (internal,
/// basal coefficients; empty: none) and the frictions the fore- and backthrust dips imply.
/// The cover's start (after settling) is its particles' positions less their displacements;
/// its faults are traced by its particles of highest shear strain since then.
nlohmann::json wedge_report(const dem::Simulation& sim, const std::string& group, const std::string& backstop,
                            const std::vector<double>& friction);

}  // namespace strata::scene
