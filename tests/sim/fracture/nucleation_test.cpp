// Where a pane's cracks start (sim/fracture/nucleation): the largest bending stress of a simply
// supported plate by Navier's series, against Roark's centre coefficients for a uniform load and
// the symmetries of the plate for the others.
#include "sim/fracture/nucleation.hpp"

#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace brisance::fracture {
namespace {

using Vec2 = Eigen::Vector2d;

// A pressure (Pa) over a `width` x `height` pane as point forces at the centres of `cells` x
// `cells` cells.
std::vector<PointForce> sampled(double width, double height, int cells,
                                const std::function<double(double, double)>& pressure) {
  std::vector<PointForce> forces;
  const double dx = width / cells;
  const double dy = height / cells;
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j < cells; ++j) {
      const Vec2 p((i + 0.5) * dx, (j + 0.5) * dy);
      forces.push_back({p, pressure(p.x(), p.y()) * dx * dy});
    }
  }
  return forces;
}

TEST(Nucleation, AUniformLoadPeaksAtTheCentreWithRoarksCoefficient) {
  // Roark's Formulas for Stress and Strain, table 11.4 case 1a (nu = 0.3): the largest stress
  // of a simply supported plate under uniform q is beta q b^2 / t^2 at its centre, b the short
  // side; beta = 0.2874 at a/b = 1 and 0.6102 at a/b = 2.
  const double q = 1000.0;
  const double t = 0.01;
  for (const auto& [a, beta] : {std::pair{1.0, 0.2874}, std::pair{2.0, 0.6102}}) {
    const StressPeak peak = largest_bending_stress(
        a, 1.0, t, 0.3, sampled(a, 1.0, 64, [&](double, double) { return q; }));
    EXPECT_NEAR(peak.centre_stress_pa / (beta * q / (t * t)), 1.0, 0.01) << a;
    EXPECT_EQ(peak.point_m, Vec2(0.5 * a, 0.5)) << a;
    EXPECT_EQ(peak.stress_pa, peak.centre_stress_pa);
  }
}

TEST(Nucleation, AHydrostaticLoadShiftsThePeakToItsHeavierSide) {
  // q0 x / a is q0 / 2 uniform plus a load odd about the centre, which bends the centre not at
  // all: the centre's stress is half the uniform q0's (to the series' sampling). The peak lies
  // on the heavier side.
  const double q0 = 2000.0;
  const double t = 0.008;
  const auto uniform = largest_bending_stress(
      1.2, 0.9, t, 0.22, sampled(1.2, 0.9, 64, [&](double, double) { return q0; }));
  const auto ramp = largest_bending_stress(
      1.2, 0.9, t, 0.22, sampled(1.2, 0.9, 64, [&](double x, double) { return q0 * x / 1.2; }));
  EXPECT_NEAR(ramp.centre_stress_pa / uniform.centre_stress_pa, 0.5, 1e-6);
  EXPECT_GT(ramp.point_m.x(), 0.6 + 0.01);
  EXPECT_NEAR(ramp.point_m.y(), 0.45, 1e-9);
  EXPECT_GT(ramp.stress_pa, ramp.centre_stress_pa);
}

TEST(Nucleation, ALoadOffToOneCornerPullsThePeakTowardItAndMirrorsWithIt) {
  // A blast-like bump centred at (0.3, 0.25) on a 1.2 x 0.9 pane, and its mirror image about
  // the pane's vertical centre line: the peaks lie in the loaded quarter and mirror each other.
  const auto bump = [](double cx, double cy) {
    return [=](double x, double y) {
      return 5e4 * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2.0 * 0.1 * 0.1));
    };
  };
  const auto left =
      largest_bending_stress(1.2, 0.9, 0.006, 0.22, sampled(1.2, 0.9, 64, bump(0.3, 0.25)));
  const auto right =
      largest_bending_stress(1.2, 0.9, 0.006, 0.22, sampled(1.2, 0.9, 64, bump(0.9, 0.25)));
  EXPECT_LT(left.point_m.x(), 0.6);
  EXPECT_LT(left.point_m.y(), 0.45);
  EXPECT_LT((left.point_m - Vec2(0.3, 0.25)).norm(), 0.15);
  EXPECT_GT(left.stress_pa, 1.2 * left.centre_stress_pa);
  // One step of the finest search is 1.2 / 40 / 100 = 0.3 mm.
  EXPECT_NEAR(right.point_m.x(), 1.2 - left.point_m.x(), 3e-4);
  EXPECT_NEAR(right.point_m.y(), left.point_m.y(), 3e-4);
  EXPECT_NEAR(right.stress_pa / left.stress_pa, 1.0, 1e-9);
}

TEST(Nucleation, SizesAndTermsMustBePositive) {
  const std::vector<PointForce> none;
  EXPECT_THROW(largest_bending_stress(0.0, 1.0, 0.01, 0.3, none), std::invalid_argument);
  EXPECT_THROW(largest_bending_stress(1.0, 1.0, -0.01, 0.3, none), std::invalid_argument);
  EXPECT_THROW(largest_bending_stress(1.0, 1.0, 0.01, 0.3, none, 0), std::invalid_argument);
  // No load: no stress, and the centre stands.
  const StressPeak empty = largest_bending_stress(1.0, 1.0, 0.01, 0.3, none);
  EXPECT_EQ(empty.stress_pa, 0.0);
  EXPECT_EQ(empty.point_m, Vec2(0.5, 0.5));
}

}  // namespace
}  // namespace brisance::fracture
