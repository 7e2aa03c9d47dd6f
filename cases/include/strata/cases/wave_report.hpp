#pragma once
/// `strata report wave`: a 2D FEM–DEM coupled model built from a geometry file.
///
/// Two physical surfaces sharing a straight side (default examples/04_coupled_wave/wave.geo:
/// an FEM block and a particle block side by side). Every run of the sweep is a scene (a
/// particle region and FEM region(s) from the geometry file, groups, boundaries and the
/// load below), built and stepped by the scene library's one run path (scene::Run): the
/// lattice fills the particle block and the one-layer overlap, gmsh meshes the FEM block so
/// that FEM nodes coincide with the overlap particles. What is special to this case is
/// analysis: the geometry measured once (`preprocess::build_overlap`: interfaces, gauge and
/// roller lines), the gauges read through the coupler's observers, the pulse windows.
///
///  - DEM: libdem `Simulation`, the bond stiffnesses of Liu, Pollard & Shi 2013 (Kn = 6.587e10
///    N/m, Ks = 2.371e10 N/m, ρ = 2650 kg/m² per unit thickness), unbreakable bonds, no contact
///    search, no damping, leapfrog at dt_DEM = dt_fraction × 2/√λmax of the infinite hex lattice.
///  - FEM: libfem linear triangles, plane stress, E = 2√3·Kn(Kn+Ks)/(3Kn+Ks) = 9.236e10 Pa,
///    ν = (Kn−Ks)/(3Kn+Ks) = 0.1905, ρ = 2650 kg/m³, thickness 1 m (the hexagonal lattice's
///    constants, Liu, Pollard & Shi 2013): the same long-wavelength elasticity and mass per area
///    as the lattice, so the impedances match.
///    dt_FEM = η·dt_DEM; central difference where that is below the FEM's explicit limit,
///    implicit Newmark (β = 1/4, γ = 1/2) otherwise ("auto").
///  - Rollers on both lateral sides (FEM nodes on the sides, the end particles of every
///    lattice column: lateral displacement held), so the wave is a 1D strain pulse.
///  - Load: traction σ(t) = Z·v0·sin²(πt/T) for 0 ≤ t ≤ T on the FEM's far side (Z = ρc,
///    c = √(E/((1−ν²)ρ))), giving an incident particle-velocity pulse of peak v0 and length
///    λ = c·T ("wavelength", given in particle diameters).
///  - Gauges: the mass-weighted mean velocity (along the propagation direction) of the FEM
///    nodes in a band halfway through the FEM block, and the mean velocity of one lattice
///    column a third of the way into the particle block.
///  - Incident, reflected and transmitted pulses are separated in time by their arrival times
///    at c (windows from 0.2·T before to 1.3·T after the arrival); the geometry must be long
///    enough for the windows not to overlap (checked). R = reflected/incident peak, R_E =
///    reflected/incident ∫v²dt; T and T_E likewise for the transmitted pulse (analytical
///    1D values for matched impedance: R = 0, T = 1, R_E + T_E = 1).
///  - Embedded (FEM | DEM | FEM, `exit_region` or `embedded`): a second FEM block beyond the
///    particle strip (examples/04_coupled_wave/wave_embedded.geo), coupled through a second
///    overlap of the same lattice and mesh (one FEM and one DEM partition). The pulse enters
///    the strip through the first overlap and leaves it through the second: R is the
///    reflection at the first interface, R2 the second interface's (seen back at the FEM
///    gauge once it has crossed the first one again, 2·D/c later, D the strip's length), T1
///    the pulse in the strip (DEM gauge), T the pulse after both interfaces (a gauge band in
///    the exit block, a third of the way in). Analytical: R = R2 = 0, T1 = T = 1.
///  - Series (`frames` > 0): one extra run (serial, η = series_eta, the longest pulse) writes
///    its scene outputs into DIR/series: particles.pvd, bonds.pvd and fem.pvd with the same
///    times (`frames` evenly spaced system steps, t = 0 and the end included; a coupled
///    frame is the state after the overlap exchange, so coincident sites hold the same
///    values, scene::show_overlap), probes.csv and summary.json, and PNGs of the pulse
///    crossing the overlap (FEM mesh and particles coloured by the velocity along the wave,
///    one colour range).
///  - Stability: a run's own energy check (particles and FEM together against the work of
///    the load) stops an exchange that pumps energy in; the point then reads "blew up".
#include <strata/couple/coupler.hpp>
#include <strata/fem/solver.hpp>
#include <strata/preprocess/overlap.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace strata::scene {
class Scene;
struct CoupledTable;
}  // namespace strata::scene

namespace strata::cases {

/// Sweep defaults that depend on the model (one place for `strata report wave` and scenes).
inline const std::vector<int> kWaveEtas{1, 2, 4, 5, 10};
inline const std::vector<double> kWaveWavelengths{10, 20, 40, 80};
/// FEM | DEM | FEM: η = 10, stable with one interface, is not with two.
inline const std::vector<int> kWaveEmbeddedEtas{1, 2, 5};
inline const std::vector<double> kWaveEmbeddedWavelengths{20, 40};

struct WaveOptions {
  std::filesystem::path output = "out/wave";  ///< directory for wave_sweep.{csv,md,png}, wave_gauges.png
  std::filesystem::path geometry;             ///< empty: examples/04_coupled_wave/wave.geo
  std::string particle_region = "dem";        ///< physical surface filled with particles
  std::string fem_region = "fem";             ///< physical surface meshed for the FEM (loaded)
  /// Second FEM surface, beyond the particles (FEM | DEM | FEM); empty: none.
  std::string exit_region;
  /// FEM | DEM | FEM defaults: geometry examples/04_coupled_wave/wave_embedded.geo, exit region
  /// "fem_exit", η ∈ {1, 2, 5}, λ ∈ {20, 40} d (η = 10, stable with one interface, is not with two).
  bool embedded = false;
  std::vector<int> etas = kWaveEtas;                   ///< integer η >= 1
  std::string modes = "both";                          ///< serial, parallel or both
  std::vector<double> wavelengths = kWaveWavelengths;  ///< pulse length c·T in particle diameters
  double d = 1e-3;                                     ///< particle diameter (m)
  /// dt_DEM / (2/√λmax of the hex lattice). 0.15 keeps dt_FEM = η·dt_DEM <= 1.5 x the DEM
  /// limit up to η = 10: the overlap exchange itself was measured unstable from about 2.5 x
  /// (see examples/04_coupled_wave/README.md), whatever the FEM integrator.
  double dt_fraction = 0.15;
  std::string fem_scheme = "auto";  ///< auto, central-difference, explicit-newmark, implicit-newmark
  double fem_far_size =
      1;  ///< largest FEM element (particle diameters); 1: uniform, the cleanest measurement
  double fem_growth = 0.1;     ///< FEM element size growth per metre away from the interface
  double peak_velocity = 0.1;  ///< v0 of the incident pulse (m/s)
  int repeats = 1;             ///< runs per point, fastest wall time kept
  /// Threads of the parallel loops inside each partition (libdem, libfem); 0: all. The
  /// default 1: these models are small, and a thread hand-off per step costs more than it
  /// saves. Independent of `modes` (the parallel mode runs the two partitions on two threads).
  int threads = 1;
  bool quick = false;  ///< η ∈ {1, 5}, λ = 20 d, serial and parallel (CTest)
  bool no_plot = false;
  /// Frames of the VTK series of one extra run (DIR/series); 0: none; -1: 12 (3 with quick).
  int frames = -1;
  int series_eta = 1;       ///< η of the series run (serial, the longest pulse)
  bool check_only = false;  ///< print the model and the stability numbers, then stop
  /// Refuse the whole sweep (Input, exit 2, before it starts) when the coupler would refuse
  /// an η (an explicit FEM above its limit, or dt_DEM above the DEM partition's). Otherwise
  /// (`strata report wave`) such points show as "refused" rows.
  bool refuse_unstable_eta = false;
  std::string title;            ///< shown above the report and in summary.json
  std::filesystem::path scene;  ///< the scene file (summary.json); empty for `strata report`
};

/// `strata report wave`'s defaults that depend on other flags: with `embedded`, η and λ
/// still at their defaults become kWaveEmbedded*; `quick` sets η {1, 5}, λ {20}; frames -1
/// becomes 12 (quick 3). A scene fills its options from its keys instead (wave_scene_options).
WaveOptions wave_report_defaults(WaveOptions opt);

/// VTK series and pictures of one run (run_wave writes them when given one).
struct WaveSeries {
  std::filesystem::path dir;                ///< particles.pvd, fem.pvd and their frames; PNGs in dir/png
  int frames = 0;                           ///< evenly spaced system steps from 0 to the end, both included
  bool pictures = true;                     ///< render PNGs of the pulse crossing the overlap
  std::vector<std::filesystem::path> pngs;  ///< written pictures (out)
};

/// Everything built once from the geometry.
struct WaveModel {
  std::filesystem::path geometry;
  preprocess::OverlapModel overlap;
  double d = 0;
  double kn = 0, ks = 0, rho = 0;  ///< lattice (N/m, N/m, kg/m²)
  double E = 0, nu = 0, c = 0;     ///< FEM plane stress (Pa, -), long-wave P speed (m/s)
  double dt_dem = 0;               ///< DEM step (s)
  double dem_dt_crit = 0;          ///< 2/√λmax of the infinite hex lattice (s), >= libdem's own
  double fem_explicit_dt = 0;      ///< FEM explicit limit, rollers and overlap externals held (s)
  double fem_length = 0;
  /// Particle block's extent along the propagation axis (m); embedded: the strip's length D
  /// between the two interfaces.
  double dem_length = 0;
  bool embedded = false;  ///< a second FEM block beyond the particles (overlap.interfaces[1])
  double exit_length = 0, exit_gauge_depth = 0;     ///< exit block's depth, its gauge's from Γ2 (m)
  double load_depth = 0;                            ///< depth of the loaded FEM side (m)
  double fem_gauge_depth = 0, dem_gauge_depth = 0;  ///< distances of the gauges from Γ (m)
  double build_s = 0;                               ///< preprocess time (s)
  std::size_t particles = 0, fem_nodes = 0, fem_elements = 0;
};

/// Builds the particles, the FEM mesh and the overlap from the geometry file.
WaveModel build_wave_model(const WaveOptions& opt);

/// One coupled run.
struct WaveRun {
  double lambda_d = 0;  ///< pulse length in particle diameters
  int eta = 1;
  couple::Execution mode = couple::Execution::Serial;
  std::string fem_scheme;     ///< integrator used
  std::string status = "ok";  ///< "ok", "refused: why", "blew up: ..." or "unstable: ..."
  double dt_dem = 0, dt_fem = 0, duration = 0;
  std::int64_t fem_steps = 0, dem_steps = 0;
  double v0 = 0;        ///< analytical incident peak velocity (m/s)
  double incident = 0;  ///< measured incident peak at the FEM gauge (m/s)
  double r_peak = 0;    ///< max |v| in the reflected window / incident peak
  double floor = 0;     ///< max |v| between the incident and reflected windows / incident peak
  double r_energy = 0;  ///< ∫v² reflected / ∫v² incident (FEM gauge)
  double t_peak = 0;    ///< max |v| at the DEM gauge / incident peak
  double t_energy = 0;  ///< ∫v² transmitted (DEM gauge) / ∫v² incident (FEM gauge)
  /// Embedded only (NaN otherwise): the second interface's reflection at the FEM gauge
  /// (peak, energy) and the pulse after both interfaces at the exit gauge (peak, energy).
  double r2_peak = std::nan(""), r2_energy = std::nan("");
  double exit_peak = std::nan(""), exit_energy = std::nan("");
  double setup_s = 0;  ///< building the model from the geometry (meshing included) and its checks (s)
  double wall_s = 0;   ///< set-up + the time loop (scene::RunResult::step_seconds), fastest of `repeats` (s)
  std::vector<double> t_fem, v_fem, t_dem, v_dem;       ///< gauge signals
  std::vector<double> v_exit;                           ///< exit gauge (embedded), at t_fem
  double t_inc = 0, t_ref = 0, t_tra = 0, pulse_T = 0;  ///< arrival times, pulse duration (s)
  double t_ref2 = 0, t_exit = 0;                        ///< embedded: R2 and exit arrivals (s)
  std::uint64_t dem_hash = 0;                           ///< libdem state hash at the end
  std::vector<double> fem_u;                            ///< FEM displacement at the end
};

/// Runs one point through scene::Run. `scheme` "auto" picks central difference when η·dt_DEM
/// is below the FEM explicit limit and implicit Newmark otherwise. A point the coupler
/// refuses (an explicit FEM above its limit) comes back with status "refused: ...", one the
/// run stops as a blow-up with "blew up: ...". Its files go to a scratch folder removed
/// afterwards, or with `series` to series->dir, with its pictures (the wall time then
/// includes the pictures).
WaveRun run_wave(const WaveModel& m, const WaveOptions& opt, double lambda_d, int eta, couple::Execution mode,
                 const std::string& scheme, WaveSeries* series = nullptr);

/// The stability numbers of a planned sweep: each partition's limit and the coupler's own
/// check (couple::coupled_stability, with its notes) at every η, from the partitions exactly
/// as run_wave builds them.
struct WaveStability {
  std::vector<couple::CoupledStability> per_eta;
  std::vector<int> refused;           ///< η the coupler would refuse
  std::vector<std::string> problems;  ///< "eta = 10: why", for those η
  bool dem_problem = false;           ///< dt_DEM itself is above the DEM partition's limit
};
WaveStability wave_stability(const WaveModel& m, const WaveOptions& opt);

/// Where a refusal points: the [coupled] key of the scene that it names (file:line:col), or
/// nowhere (no table) for `strata report`.
struct WaveRefuse {
  const scene::CoupledTable* table = nullptr;
};

/// The one path behind `strata report wave` and `strata check|run` of a wave scene: validates
/// `opt` (defaults already filled in), builds the model, prints it and the stability numbers
/// (JSON with `json`), refuses (Input, exit 2; through `refuse` at the scene key) a pulse too
/// long for the geometry and, with opt.refuse_unstable_eta, an η the coupler would refuse;
/// stops there with opt.check_only; else runs the sweep over wavelengths, η and modes and
/// writes wave_sweep.{csv,md,png}, wave_gauges.png, summary.json and series/ into opt.output
/// all at once (through a staging folder: a failed sweep writes nothing). Returns the exit status.
int wave_sweep(const WaveOptions& opt, const WaveRefuse& refuse = {}, bool json = false);

/// `strata report wave`: wave_sweep(wave_report_defaults(opt)).
int wave_report_cmd(const WaveOptions& opt);

/// The options of a [coupled] scene with case = "wave" (geometry resolved relative to the
/// scene file; η, λ, repeats and threads from the case's defaults when not given; output is
/// output.directory, no_plot is !output.render, refuse_unstable_eta is !force).
WaveOptions wave_scene_options(const scene::Scene& sc, bool force);
/// `strata check SCENE` of a wave scene: the model and the stability numbers; exit 2 at the
/// scene key when the sweep would be refused.
int check_wave_scene(const scene::Scene& sc, bool json, bool force);
/// `strata run SCENE` of a wave scene: the same checks, then the sweep, written to `output`
/// (empty: output.directory); `threads` >= 0 overrides [coupled].threads.
int run_wave_scene(const scene::Scene& sc, const std::filesystem::path& output, bool force, int threads);

}  // namespace strata::cases
