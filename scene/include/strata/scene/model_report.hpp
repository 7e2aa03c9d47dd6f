#pragma once
/// What strata reports about a model: the counts and time-step numbers of a built model
/// (`strata check`, the model part of summary.json), and what `strata mesh` reports about a
/// model description: bond counts by length class, bond length and direction histograms (CSV
/// and PNG) that show the spread of an eccentric lattice, and the particles and FEM meshes as
/// VTK files.
#include <strata/io/frame.hpp>
#include <strata/preprocess/ecc.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <vector>

#include <strata/scene/model.hpp>

namespace strata::scene {

/// Bond geometry of a model at its initial state.
struct BondStats {
  double d_ref = 0;             ///< reference length: the particle diameter (m)
  std::vector<double> length;   ///< per bond (m)
  std::vector<double> azimuth;  ///< per bond: angle in the xy plane, [0, 180) degrees
  std::vector<double> polar;    ///< 3D: angle to the z axis, [0, 90] degrees
};

/// Bonds above this count are not listed one by one for the histograms (memory).
inline constexpr std::size_t kMaxReportedBonds = 20'000'000;

/// Models above this many particles are written as their surface particles only (or none,
/// when even the surface holds more): `strata mesh -o` never writes 100 M points.
inline constexpr std::size_t kMaxWrittenParticles = 5'000'000;

/// Lengths and directions of the bonds build_model would make (listed region by region or
/// for all regions together, as the model bonds them); empty when `bonds` (their count)
/// is above kMaxReportedBonds or 0.
BondStats bond_stats(const ModelDescription& d, std::size_t bonds);

/// Bond counts by length class: {"1.00": n, "1.02": n, ...} keyed by length / d_ref,
/// classes of width c.width·d_ref centred on its multiples; empty classes are left out.
nlohmann::json bond_length_classes(const preprocess::PairCounts& c);

/// The particles with ids `ids` (ascending) as points: radius, id and group (the index of
/// the last-made group each belongs to, -1 for none, as dem::Simulation::last_group numbers
/// them).
io::PointCloud description_particles(const ModelDescription& d, const std::vector<std::uint32_t>& ids);

/// The FEM regions' meshes as one unstructured grid (triangles or tetrahedra), with the
/// cell array `region` (index into d.fem).
io::MeshFrame description_fem(const ModelDescription& d);

/// Writes bond_lengths.csv and bond_directions.csv into `dir`, and the matching PNG plots
/// when this build renders (a failed plot is a warning); returns the files written.
std::vector<std::filesystem::path> write_bond_histograms(const BondStats& s, const std::filesystem::path& dir,
                                                         int bins = 50);

/// The model numbers of a built model: scene, title, dimension, regions, groups, particles,
/// bonds, FEM nodes and elements, memory, dt, dt_crit, steps, simulated time, threads.
nlohmann::json model_json(const BuiltModel& m, const Scene& sc);

/// `strata mesh`: fills the regions (never builds the DEM), counts bonds by length class, and
/// with a non-empty `output` writes the particles (all up to kMaxWrittenParticles, else the
/// surface), the FEM meshes and the bond histograms there. Returns the report; its
/// "written" lists the files.
nlohmann::json mesh_report(const Scene& sc, const std::filesystem::path& output);

}  // namespace strata::scene
