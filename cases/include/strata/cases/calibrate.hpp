#pragma once
/// Calibration of a bonded-particle lattice against a rock's E, ν, UCS and tensile strength:
/// `strata calibrate FILE` on a file with a [calibrate] table.
///
/// 1. Elastic: Kn and Ks from the lattice's analytical relations (2D hexagonal, 3D close
///    packing along its stacking axis), then corrected by measuring a uniaxial specimen whose
///    bonds do not break (a finite specimen is a little softer than the infinite lattice): the
///    targets given to the analytical inversion are moved by the measured misfit, E
///    proportionally and ν by its difference, until both are within the tolerance.
/// 2. Strength: at fixed stiffness, the peak stresses of a specimen are proportional to the
///    bond strengths when Fn_max and Fs0 are scaled together (the response is quasi-static and
///    the law is linear up to breaking), so only their ratio q = Fs0/Fn_max sets UCS/BTS.
///    A secant search on log q (bisection once the target is bracketed) finds the q whose
///    uniaxial and Brazilian specimens give the target ratio; Fn_max is rescaled after every
///    pair so the next pair runs near the target strengths. When no q in [1/16, 64] reaches the
///    ratio, the q that comes closest is kept and [calibrate] match says which strength is met.
/// 3. A final pair of specimens with the chosen parameters gives the achieved values.
///
/// Every run goes through scene::Run. The specimen scenes are written beside the results,
/// so the final runs can be repeated or changed with `strata run`.
#include <strata/scene/run.hpp>
#include <strata/scene/scene.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace strata::cases {

/// The parameters of the solid-lattice law a calibration chooses.
struct LatticeParameters {
  double kn = 0, ks = 0;       ///< N/m
  double fn_max = 0, fs0 = 0;  ///< N
};

/// One specimen run of a calibration.
struct CalibrationRun {
  std::string stage;     ///< "elastic", "strength" or "final"
  int iteration = 0;     ///< within the stage, from 1
  std::string specimen;  ///< "uniaxial" or "brazilian"
  LatticeParameters p;
  double youngs_modulus = 0;  ///< Pa, uniaxial only
  double poisson_ratio = 0;   ///< uniaxial only
  double strength = 0;        ///< Pa: the peak stress (uniaxial) or 2P/(πDt) (Brazilian); 0 for elastic runs
  double peak_strain = 0;     ///< axial strain at the peak (uniaxial)
  bool failed = false;        ///< the specimen failed (its stress fell after the peak) before the last step
  std::size_t particles = 0;
  std::int64_t steps = 0;
  double seconds = 0;
  std::filesystem::path directory;
};

struct CalibrationResult {
  LatticeParameters p;           ///< the chosen parameters
  LatticeParameters analytical;  ///< Kn, Ks from the analytical relations alone
  double youngs_modulus = 0, poisson_ratio = 0, ucs = 0, tensile_strength = 0;  ///< achieved
  double peak_strain = 0;     ///< of the final uniaxial specimen
  bool ratio_reached = true;  ///< whether some q gave the target UCS/tensile strength ratio
  double best_ratio = 0;      ///< UCS/tensile strength of the final pair
  std::vector<CalibrationRun> runs;
  std::string markdown;  ///< calibration.md
  std::vector<std::filesystem::path> written;
};

/// Shows a calibration's runs; `begin` and `end` bracket each run, the RunObserver calls of
/// scene::Run come in between.
class CalibrateObserver : public scene::RunObserver {
 public:
  virtual void begin(const std::string& label) { (void)label; }
  virtual void end(const CalibrationRun& run) { (void)run; }
};

/// Runs the calibration of `sc` (which has a [calibrate] table) and writes into `output`:
/// calibration.md (targets, achieved values, the chosen [[material]]), calibration.json,
/// calibration.csv (every run), uniaxial.toml and brazilian.toml (the final specimens) with
/// their outputs in uniaxial/ and brazilian/, and the runs of the search in runs/. Throws
/// strata::Error (Input) for a scene without [calibrate], (Numerical) when a specimen blows up.
CalibrationResult calibrate(const scene::Scene& sc, const std::filesystem::path& output,
                            CalibrateObserver& observer);

/// Width of the uniaxial specimen and diameter of the Brazilian disc: [calibrate]
/// specimen_width, or 40 particle diameters.
double specimen_width(const scene::CalibrateTable& c);

/// Kn and Ks from the lattice's analytical relations alone, at the targets E and ν: 2D
/// hexagonal (E·t, t the scene's thickness), 3D close packing along its stacking axis z (the
/// uniaxial specimen's axis). Throws strata::Error (Input) for a scene without [calibrate].
LatticeParameters analytical_springs(const scene::Scene& sc);

/// The scene text of a calibration specimen ("uniaxial" or "brazilian") of `sc`'s lattice with
/// the parameters `p`: platens that approach at `strain_rate` (1/s, relative to the loaded
/// length) up to `strain`, a run that stops once the specimen has failed, and frames and
/// pictures only for a final run.
std::string specimen_scene(const scene::Scene& sc, const std::string& specimen, const LatticeParameters& p,
                           double strain_rate, double strain, bool final_run);

}  // namespace strata::cases
