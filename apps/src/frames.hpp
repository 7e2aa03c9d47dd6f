#pragma once
/// Converts the DEM state into io's neutral frames.
#include <strata/dem/simulation.hpp>
#include <strata/io/frame.hpp>

#include <string>
#include <vector>

namespace strata::app {

/// Particles as points with the requested fields (id, radius, displacement, velocity,
/// group, damage); `radius` is always written (pictures and ParaView glyphs need it).
io::PointCloud particle_frame(const dem::Simulation& sim, const std::vector<std::string>& fields);

/// Broken bonds (all of them, open or closed again) as line cells with state, Fn and Fs,
/// indexing the points of particle_frame.
io::LineSet broken_bond_frame(const dem::Simulation& sim);

}  // namespace strata::app
