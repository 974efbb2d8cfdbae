// sim/engine/sleeping (private to the engine): when a body resting on the ground stops being
// integrated (DESIGN.md decision 10). Inline: it runs for every awake body in every step.
#pragma once

#include <cmath>

namespace brisance::engine {

// Slower than these for kRestTime_s while touching the ground: asleep until a new load.
inline constexpr double kRestSpeed_m_s = 0.05;
inline constexpr double kRestAngularSpeed_rad_s = 0.1;
inline constexpr double kRestTime_s = 0.5;

// Accumulates the time a body has been at rest (`rest_time_s`, reset when it moves or leaves
// the ground) and returns true once it has rested long enough to sleep. `may_rest`: sleeping
// is on and the body touches the ground; `angular_speed_squared` in rad^2/s^2.
inline bool falls_asleep(bool may_rest, double speed_m_s, double angular_speed_squared, double dt,
                         double& rest_time_s) {
  if (may_rest && speed_m_s < kRestSpeed_m_s &&
      std::sqrt(angular_speed_squared) < kRestAngularSpeed_rad_s) {
    rest_time_s += dt;
    return rest_time_s >= kRestTime_s;
  }
  rest_time_s = 0.0;
  return false;
}

}  // namespace brisance::engine
