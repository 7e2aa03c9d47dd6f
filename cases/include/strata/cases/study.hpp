#pragma once
/// Parameter studies: a scene run once for every combination of the values of a study's
/// [[vary]] keys, the numbers its [[measure]] entries name read from each run's summary.json,
/// tabulated with their mean and standard deviation over the `spread` key (the random seeds,
/// say) and plotted against the `x` key. `strata check|run STUDY` of a file with a [study]
/// table; e.g. the Poisson's ratio of eccentric lattices (ECC4D, Zhao et al. 2021) against Rc
/// for several Ra over ten seeds (examples/09_eccentric_poisson).
#include <strata/scene/scene.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace strata::cases {

/// One run of a study.
struct StudyPoint {
  std::vector<double> values;    ///< one per [[vary]], in its order
  std::vector<double> measures;  ///< one per [[measure]]; NaN when the run has no such number
  std::string status;            ///< "completed", or why not ("blew up: ...")
  double wall_s = 0;
};

/// Mean and standard deviation of each measure over the runs that differ only in `spread`.
struct StudyGroup {
  std::vector<double> values;  ///< one per [[vary]]; the spread key's is NaN
  std::size_t runs = 0;        ///< runs in the group, and with every measure finite
  std::size_t counted = 0;
  std::vector<double> mean, std;  ///< per measure (std: sample, n − 1; 0 for one run)
};

/// A study's runs, in the order they run (the last [[vary]] key fastest).
struct StudyPlan {
  std::vector<std::vector<std::string>> overrides;  ///< per run: study.set, then one per [[vary]]
  std::vector<std::vector<double>> values;          ///< per run: one value per [[vary]]
};
StudyPlan plan_study(const scene::Scene& study);

/// The groups of a study's points (in the order of their first run).
std::vector<StudyGroup> group_points(const scene::Scene& study, const std::vector<StudyPoint>& points);

/// Progress of a study, and its stop request (polled between runs and inside them).
class StudyObserver {
 public:
  virtual ~StudyObserver() = default;
  virtual void started(std::size_t runs) { (void)runs; }
  virtual void done(std::size_t run, const StudyPoint& p) { (void)run, (void)p; }
  virtual int stop_requested() { return 0; }
};

/// `strata check STUDY`: every run's scene loaded with its overrides (keys and values
/// checked), the first and the last run's models built (their time steps checked); prints the
/// plan. Throws strata::Error (Input) naming the run and the key.
int check_study_scene(const scene::Scene& study);

/// `strata run STUDY`: the runs, then study.csv, study.md, one PNG per measure and
/// summary.json, moved into `output` (or output.directory) with runs/NNNN/ all at once at the
/// end. Returns the exit status (128 + signal when stopped: what ran is written).
int run_study_scene(const scene::Scene& study, const std::filesystem::path& output, StudyObserver& observer);

}  // namespace strata::cases
