// sim/dynamics/coulomb: the Coulomb friction cone shared by the ground's and the body pairs'
// sequential-impulse solves. Inline: it runs for every contact in every sweep.
#pragma once

#include <cmath>

namespace brisance::dynamics {

// Scales the tangential impulse (a, b) back onto the disc of radius `limit` (mu times the
// normal impulse) when it lies outside it. Squared magnitudes: std::hypot's overflow guard cost
// more than the rest of the ground's sweep.
inline void clamp_to_friction_disc(double& a, double& b, double limit) {
  const double squared = a * a + b * b;
  if (squared > limit * limit) {
    const double scale = limit / std::sqrt(squared);
    a *= scale;
    b *= scale;
  }
}

}  // namespace brisance::dynamics
