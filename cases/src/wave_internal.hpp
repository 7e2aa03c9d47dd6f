#pragma once
// Internal to the coupled wave (wave_model.cpp: the model and one run; wave_report.cpp: the
// sweep and its report): the timing of a pulse and the windows that separate its arrivals.
#include <strata/cases/wave_report.hpp>

namespace strata::cases::wave_detail {

// Arrival windows, in pulse durations T: from kBefore·T before the arrival at c to kAfter·T
// after it (the pulse lasts T; the rest leaves room for dispersion).
constexpr double kBefore = 0.2, kAfter = 1.3;

/// One pulse through the model: its duration T = λ/c, the arrival times at the gauges, the end
/// of the run and the traction σ0 = ρ·c·v0 that launches it.
struct PulsePlan {
  double T = 0, t_inc = 0, t_ref = 0, t_tra = 0, t_end = 0, sigma0 = 0;
  double t_ref2 = 0, t_exit = 0;  // embedded: second interface's reflection, exit gauge
};

/// The plan of a pulse of λ = lambda_d diameters; throws Input when the geometry is too short
/// for its windows to separate.
PulsePlan plan_of(const WaveModel& m, const WaveOptions& opt, double lambda_d);

}  // namespace strata::cases::wave_detail
