#pragma once
/// How a load history goes from one listed value to the next: linearly, or smoothly (a
/// half cosine, zero rate at every listed time, so a load applied from rest sends no shock
/// into the model and a pulse [0, P, 0] at times [0, T/2, T] is the sin² (Hann) pulse
/// P·sin²(πt/T) of wave-propagation tests).
#include <cmath>
#include <numbers>

namespace strata {

enum class Ramp { Linear, Smooth };

/// The weight of the later of two listed values at the fraction s ∈ [0, 1] of the way
/// between their times: s (linear) or sin²(πs/2) (smooth).
inline double ramp_weight(double s, Ramp r) {
  if (r == Ramp::Linear) return s;
  const double h = std::sin(0.5 * std::numbers::pi * s);
  return h * h;
}

}  // namespace strata
