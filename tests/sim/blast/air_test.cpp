// Tests of sim/blast/air: Rankine–Hugoniot relations and the Brode / Henrych equations.
#include "sim/blast/air.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace brisance::blast {
namespace {

TEST(RankineHugoniot, WeakShockTravelsAtTheSpeedOfSound) {
  const Ambient air;
  // Acoustic limit of eq. 2.15: U = a0 (1 + 3 p / (7 p0)) to first order.
  EXPECT_NEAR(rh_shock_velocity_m_s(1.0, air),
              air.sound_speed_m_s * (1.0 + 3.0 / (7.0 * air.pressure_pa)), 1e-8);
  EXPECT_NEAR(rh_density_behind_kg_m3(1.0, air), air.density_kg_m3, 1e-5);
  EXPECT_NEAR(rh_dynamic_pressure_pa(1.0, air), 0.0, 1e-5);
}

TEST(RankineHugoniot, ReflectionCoefficientRunsFromTwoToEight) {
  // Thesis §2.6.3: C_r -> 2 for p_s << p0 and -> 8 for p_s >> p0 (ideal gas, gamma = 1.4).
  EXPECT_NEAR(rh_reflected_overpressure_pa(10.0) / 10.0, 2.0, 1e-3);
  EXPECT_NEAR(rh_reflected_overpressure_pa(1e12) / 1e12, 8.0, 1e-5);
  // Eq. 2.29 is eq. 2.28, p_r = 2 p_s + (gamma + 1) q_s, with q_s from eq. 2.17.
  for (double p : {1e3, 3e4, 2e5, 1e6, 2e7}) {
    EXPECT_NEAR(rh_reflected_overpressure_pa(p), 2.0 * p + 2.4 * rh_dynamic_pressure_pa(p),
                1e-9 * p);
  }
}

TEST(RankineHugoniot, DynamicPressureIsHalfRhoUSquared) {
  // Eq. 2.17 against eq. 2.27 with u and rho from the conservation laws (eqs. 2.1, 2.2, 2.16).
  const Ambient air;
  for (double p : {2e3, 5e4, 3e5, 4e6}) {
    const double rho = rh_density_behind_kg_m3(p, air);
    const double u = rh_particle_velocity_m_s(p, air);
    // Momentum conservation (eq. 2.2): p = rho0 U u.
    EXPECT_NEAR(air.density_kg_m3 * rh_shock_velocity_m_s(p, air) * u, p, 2e-3 * p);
    EXPECT_NEAR(0.5 * rho * u * u, rh_dynamic_pressure_pa(p, air),
                2e-3 * rh_dynamic_pressure_pa(p, air));
  }
}

TEST(RankineHugoniot, ParticleVelocityIsTheGamma14ClosedForm) {
  // For gamma = 1.4: u = (5 p / (7 p0)) a0 / sqrt(1 + 6 p / (7 p0)) (Kinney & Graham, Explosive
  // Shocks in Air, 2nd ed., 1985). a0 = 340.29 m/s and p0 / rho0 agree to 1.5e-5.
  const Ambient air;
  for (double p : {1e3, 3e4, 2e5, 1e6}) {
    const double ratio = p / air.pressure_pa;
    const double closed =
        5.0 * ratio / 7.0 * air.sound_speed_m_s / std::sqrt(1.0 + 6.0 * ratio / 7.0);
    EXPECT_NEAR(rh_particle_velocity_m_s(p, air) / closed, 1.0, 1e-4) << p;
  }
}

TEST(BrodeEquations, FollowEquations2_20And2_21) {
  // Z = 0.5: 6.7 / 0.125 + 1 = 54.6 bar (near field, eq. 2.20).
  const EmpiricalOverpressure near = brode_overpressure(0.5);
  EXPECT_NEAR(near.overpressure_pa, 54.6e5, 1.0);
  EXPECT_TRUE(near.in_range);
  // Z = 5: 0.195 + 0.0582 + 0.0468 - 0.019 = 0.281 bar (eq. 2.21).
  const EmpiricalOverpressure far = brode_overpressure(5.0);
  EXPECT_NEAR(far.overpressure_pa, (0.975 / 5 + 1.455 / 25 + 5.85 / 125 - 0.019) * 1e5, 1e-6);
  EXPECT_TRUE(far.in_range);
  EXPECT_FALSE(brode_overpressure(60.0).in_range);  // below 0.1 bar
}

TEST(HenrychEquations, FollowEquations2_22To2_24) {
  EXPECT_NEAR(henrych_overpressure(1.0).overpressure_pa, (0.662 + 4.05 + 3.288) * 1e5, 1e-6);
  EXPECT_NEAR(henrych_overpressure(0.5).overpressure_pa,
              (6.194 / 0.5 - 0.326 / 0.25 - 2.132 / 0.125) * 1e5, 1e-6);
  EXPECT_NEAR(henrych_overpressure(0.1).overpressure_pa, (140.72 + 554.0 - 357.0 + 62.5) * 1e5,
              1e-3);
  EXPECT_TRUE(henrych_overpressure(9.0).in_range);
  EXPECT_FALSE(henrych_overpressure(0.02).in_range);
  EXPECT_FALSE(henrych_overpressure(12.0).in_range);
}

TEST(EmpiricalEquations, DecreaseWithScaledDistanceInTheirRanges) {
  double previous_brode = INFINITY, previous_henrych = INFINITY;
  for (double z = 0.3; z <= 10.0; z *= 1.05) {
    const double brode = brode_overpressure(z).overpressure_pa;
    EXPECT_LT(brode, previous_brode) << z;
    previous_brode = brode;
    if (z >= 1.0) {
      const double henrych = henrych_overpressure(z).overpressure_pa;
      EXPECT_LT(henrych, previous_henrych) << z;
      previous_henrych = henrych;
    }
  }
}

}  // namespace
}  // namespace brisance::blast
