#pragma once
// Internal: the thrust-wedge section of summary.json ([probe] wedge_group).
#include <nlohmann/json.hpp>
#include <strata/dem/simulation.hpp>

#include <string>
#include <vector>

namespace strata::scene {

/// The taper and faults of the shortened cover `group` (a 2D model shortened by a moving
/// wall along x under gravity along −y), with the critical taper of `friction` (internal,
/// basal coefficients; empty: none) and the frictions the fore- and backthrust dips imply.
/// The cover's start (after settling) is its particles' positions less their displacements;
/// its faults are traced by the bonds that broke in shear after settling.
nlohmann::json wedge_report(const dem::Simulation& sim, const std::string& group,
                            const std::vector<double>& friction);

}  // namespace strata::scene
