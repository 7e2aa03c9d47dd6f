#pragma once
/// Converts the DEM state into io's neutral frames, with the selections of [output].
#include <strata/dem/simulation.hpp>
#include <strata/io/frame.hpp>
#include <strata/io/render.hpp>

#include <array>
#include <string>
#include <vector>

namespace strata::app {

/// Which particles and bonds the VTK frames hold ([output] particles, groups, slice_*, bonds).
struct FrameSelection {
  enum class Particles { All, Surface, None } particles = Particles::All;
  enum class Bonds { Broken, All, None } bonds = Bonds::Broken;
  std::uint32_t group_mask = 0;  ///< 0: any group; else particles with one of these group bits
  double slice_thickness = 0;    ///< 0: no slice
  std::array<double, 3> slice_point{}, slice_normal{0, 0, 1};
  /// Surface particles by id: fewer bonds at the start than a particle inside the lattice.
  std::vector<char> surface_by_id;

  /// Records which particles are on the surface (counting every bond entry, broken or not,
  /// so it holds after a restart too).
  void find_surface(const dem::Simulation& sim);
  /// Whether every particle is written.
  bool keeps_all() const { return particles == Particles::All && group_mask == 0 && slice_thickness == 0; }
};

/// Particles as points with the requested fields (id, radius, displacement, velocity, force,
/// group, damage); `radius` is always written (pictures and ParaView glyphs need it).
io::PointCloud particle_frame(const dem::Simulation& sim, const std::vector<std::string>& fields);

/// The points of `all` that `sel` keeps (all of them when sel.keeps_all()).
io::PointCloud select_particles(const dem::Simulation& sim, const io::PointCloud& all,
                                const FrameSelection& sel);

/// Bonds as line cells with state (io::BondState codes), Fn and Fs, indexing the points of
/// particle_frame: the broken ones (open or closed again), or all of them.
io::LineSet bond_frame(const dem::Simulation& sim, FrameSelection::Bonds which);

/// How pictures show a particle field (render_field / --field): its scale, unit and, for
/// damage, the fixed range [0, 1]. Shared by `strata run` and `strata render`.
io::RenderStyle field_style(const std::string& field);

}  // namespace strata::app
