#pragma once
/// Converts the DEM and FEM states into io's neutral frames, with the selections of [output].
#include <strata/couple/coupler.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/fem/mesh.hpp>
#include <strata/io/frame.hpp>
#include <strata/io/render.hpp>

#include <Eigen/Core>
#include <array>
#include <span>
#include <string>
#include <vector>

namespace strata::scene {

/// Which particles, bonds and contacts the VTK frames hold ([output] particles, groups,
/// slice_*, bonds, contacts).
struct FrameSelection {
  /// SurfaceAndSlice: the surface (within `groups`) and every particle that passes the group
  /// and slice selection.
  enum class Particles { All, Surface, SurfaceAndSlice, None } particles = Particles::All;
  enum class Bonds { Broken, All, None } bonds = Bonds::Broken;
  /// Never-bonded contacts that touch now, as lines with state BondState::Contact; only
  /// those whose two particles pass the group and slice selection.
  bool contacts = true;
  std::vector<std::string> groups;  ///< empty: any particle; else those in one of these groups
  double slice_thickness = 0;       ///< 0: no slice
  std::array<double, 3> slice_point{}, slice_normal{0, 0, 1};
  /// Surface particles by id: fewer bonds at the start than a particle inside the lattice.
  std::vector<char> surface_by_id;

  /// Records which particles are on the surface (counting every bond entry, broken or not,
  /// so it holds after a restart too).
  void find_surface(const dem::Simulation& sim);
  /// Whether every particle is written.
  bool keeps_all() const { return particles == Particles::All && groups.empty() && slice_thickness == 0; }
  /// Whether a particle in one of `groups` or not (`in_group`) with this centre passes the
  /// group and slice selection (not the surface one).
  bool in_groups_and_slice(bool in_group, const double* x) const;
  /// Per particle (internal order): 1 when it passes the group and slice selection; empty
  /// when every particle does.
  std::vector<std::uint8_t> passes(const dem::Simulation& sim) const;
  /// Internal rows, ascending, of the particles the particle frames hold: those that pass
  /// (`pass` from passes()) and, for Particles::Surface, lie on the surface (find_surface);
  /// for Particles::SurfaceAndSlice, those that pass and those on the surface in `groups`.
  std::vector<std::uint32_t> particle_rows(const dem::Simulation& sim,
                                           const std::vector<std::uint8_t>& pass) const;
};

/// Particles as points with the requested fields (id, radius, displacement, velocity, force,
/// group, damage); `radius` is always written (pictures and ParaView glyphs need it).
/// `group` is the index of the last-made group a particle belongs to (regions first, then
/// each [[group]], in scene order), -1 for none.
io::PointCloud particle_frame(const dem::Simulation& sim, const std::vector<std::string>& fields);
/// The same for the particles at these internal rows, in that order. Fields are read for
/// those particles only, except `force` and `shear_strain`, which are gathered over all.
io::PointCloud particle_frame(const dem::Simulation& sim, const std::vector<std::string>& fields,
                              std::span<const std::uint32_t> rows);

/// Bonds and contacts as line cells with state (io::BondState codes), Fn and Fs, indexing
/// the points of particle_frame: the bonds sel.bonds asks for (broken ones or all), then,
/// with sel.contacts, the touching never-bonded contacts (state BondState::Contact); of
/// each, those whose two particles pass the group and slice selection. A broken bond's state
/// is its current one: Closed while it touches again after having opened, else its mode.
io::LineSet bond_frame(const dem::Simulation& sim, const FrameSelection& sel);

/// One frame of the particles as a selection has them, read for the particles it writes
/// only, so that a frame of a large model costs memory in proportion to what it writes.
struct SelectedFrame {
  std::vector<std::uint32_t> rows;  ///< internal rows of `points`, ascending
  io::PointCloud points;            ///< the written particles and the ends of the written bonds
  std::vector<std::uint32_t> kept;  ///< indices into `points` of the written particles
  io::LineSet bonds;                ///< bond_frame's lines, indexing `points`
  /// The written particles (all of `points` when they are all written).
  io::PointCloud particles() const;
};
/// The frame of `sim` with `fields` that `sel` selects; with `every_point`, `points` holds
/// every particle (as particle_frame), which show_overlap needs.
SelectedFrame selected_frame(const dem::Simulation& sim, const std::vector<std::string>& fields,
                             const FrameSelection& sel, bool every_point);

/// A FEM mesh and its state as an io::MeshFrame: nodes (z = 0 in 2D, y = z = 0 in 1D),
/// cells (Tri3 triangles, Tet4 tetrahedra, Bar and Spring lines), point arrays
/// `displacement` and `velocity` (3 components, u and v of the DOF vectors, zero-padded),
/// cell arrays `stress` (6 components in ParaView's symmetric-tensor order xx, yy, zz, xy,
/// yz, xz; Pa; fem::element_stress), `von_mises` (Pa) and `block` (element block index).
/// A 1D mesh is drawn as 2D.
io::MeshFrame fem_frame(const fem::Mesh& mesh, const Eigen::VectorXd& u, const Eigen::VectorXd& v,
                        double time, std::int64_t step);

/// A frame of a coupled model shows its state after the overlap exchange: the external sites
/// of each side hold the values the coupler copies to them from the other side (the
/// displacement and velocity arrays, and the external particles' positions), so that the two
/// parts agree where their sites coincide; and both frames get the point array `overlap`
/// (0 internal, 1 boundary: a source of the other side's externals, 2 external). `mesh` is a
/// frame of the FEM, `particles` a particle_frame of `sim` (all particles); either may be null
/// (its frames off).
void show_overlap(const couple::Coupler& coupler, const dem::Simulation& sim, int dim, io::MeshFrame* mesh,
                  io::PointCloud* particles);

/// The walls where they are now, as a mesh ParaView and the pictures show: each wall a
/// line (2D) or a rectangle of two triangles (3D) in its plane, covering the particles' box
/// projected onto it and 5 % of the box's diagonal beyond; cell arrays `wall` (index in the
/// order of [[wall]]), `normal` and `velocity`. No cells when there are no walls.
io::MeshFrame wall_frame(const dem::Simulation& sim);

/// Shear strain since the start (after settling) of the particles `only` picks (all when
/// empty): dem::shear_strain_2d over them, each particle's neighbourhood the others within
/// 1.5 of their median diameters at the start (the first ring of a lattice, even an eccentric
/// one). One value per particle; 0 for those left out. 2D.
std::vector<double> shear_strain_since_start(const std::vector<std::array<double, 3>>& start,
                                             const std::vector<std::array<double, 3>>& now,
                                             const std::vector<double>& radii,
                                             const std::vector<std::uint8_t>& only = {});

/// How pictures show a particle field (render_field / --field): its scale, unit and, for
/// damage, the fixed range [0, 1]; the group field as categories named `group_names` (by
/// group index). Shared by `strata run` and `strata render`.
io::RenderStyle field_style(const std::string& field, const std::vector<std::string>& group_names = {});

}  // namespace strata::scene
