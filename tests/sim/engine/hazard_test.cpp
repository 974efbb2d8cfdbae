// The glazing hazard rating (GSA P100 table 8-1, sim/engine/hazard): constructed runs whose
// fragments fly closed-form ballistic paths, so where each lands or strikes is known by hand.
#include "sim/engine/hazard.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "sim/engine/result.hpp"
#include "sim/engine/simulator.hpp"
#include "sim/geometry/mesh.hpp"
#include "sim/scene/scene.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace brisance::engine {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kG = 9.81;
constexpr double kThickness = 0.006;
constexpr double kHalfFragment = 0.01;  // fragments are 2 cm cubes (their lowest vertex 1 cm down)

// A 1 x 1 m pane centred at (0, 1.5, 0), front +z, the room behind its -z face; no ground
// unless `ground`, so the floor is y = 0.
scene::Scene room_scene(bool ground = false, std::uint8_t sheltered = 1u << 5) {
  scene::Scene s;
  scene::ChargeSpec charge;
  charge.position = Vec3(0.0, 1.5, 10.0);
  s.charges.push_back(charge);
  if (!ground) s.environment.ground.reset();
  scene::ObjectSpec pane;
  pane.name = "pane";
  pane.box_size_m = Vec3(1.0, 1.0, kThickness);
  pane.mesh = geometry::make_box(pane.box_size_m);
  pane.position = Vec3(0.0, 1.5, 0.0);
  pane.sheltered = sheltered;
  pane.fracture = scene::FractureSpec{};
  s.objects.push_back(pane);
  return s;
}

// A broken pane whose fragments start at `starts` with velocities `velocities` at t = 0 and fly
// without drag under gravity for `duration_s`, sampled at 30 frames/s.
Result ballistic_run(const std::vector<Vec3>& starts, const std::vector<Vec3>& velocities,
                     double duration_s = 2.0) {
  Result r;
  const std::size_t frames = static_cast<std::size_t>(std::round(duration_s * 30.0)) + 1;
  for (std::size_t f = 0; f < frames; ++f)
    r.frame_times_s.push_back(static_cast<double>(f) / 30.0);
  PaneReport pane;
  pane.name = "pane";
  pane.broken = true;
  pane.first_body = 0;
  pane.fragment_count = starts.size();
  for (std::size_t k = 0; k < starts.size(); ++k) {
    BodyInfo body;
    body.name = "pane/f" + std::to_string(k);
    body.fragment = true;
    body.mesh = geometry::make_box(Vec3::Constant(2.0 * kHalfFragment));
    body.initial_pose.position = {starts[k].x(), starts[k].y(), starts[k].z()};
    r.bodies.push_back(body);
    r.animated.push_back(static_cast<std::uint32_t>(k));
    pane.release_times_s.push_back(0.0);
  }
  for (std::size_t f = 0; f < frames; ++f) {
    const double t = r.frame_times_s[f];
    for (std::size_t k = 0; k < starts.size(); ++k) {
      const Vec3 x = starts[k] + velocities[k] * t + 0.5 * Vec3(0.0, -kG, 0.0) * t * t;
      Pose pose;
      pose.position = {x.x(), x.y(), x.z()};
      r.poses.push_back(pose);
    }
  }
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const double t = r.frame_times_s.back();
    const Vec3 x = starts[k] + velocities[k] * t + 0.5 * Vec3(0.0, -kG, 0.0) * t * t;
    const Vec3 v = velocities[k] + Vec3(0.0, -kG, 0.0) * t;
    FinalState state;
    state.name = r.bodies[k].name;
    state.pose.position = {x.x(), x.y(), x.z()};
    state.linear_velocity_m_s = {v.x(), v.y(), v.z()};
    r.final_state.push_back(state);
  }
  r.fracture.push_back(pane);
  return r;
}

// Closed form: how far behind the pane's inner face a fragment leaving its centre plane at
// height y0 with speed u into the room lands (its lowest vertex reaching the floor y = 0).
double landing_depth(double y0, double u) {
  return u * std::sqrt(2.0 * (y0 - kHalfFragment) / kG) - 0.5 * kThickness;
}
// ... and the height of its centre where it reaches the witness panel.
double witness_height(double y0, double u) {
  const double t = (kHazardWitnessDistance_m + 0.5 * kThickness) / u;
  return y0 - 0.5 * kG * t * t;
}

TEST(Hazard, AnUnbrokenPaneIsCondition1) {
  Result r = ballistic_run({}, {});
  r.fracture[0].broken = false;
  r.fracture[0].hazard.condition = "5";  // the rating replaces whatever was there
  rate_pane_hazards(room_scene(), r);
  EXPECT_EQ(r.fracture[0].hazard.condition, "1");
  EXPECT_EQ(r.fracture[0].hazard.protection_level, "safe");
  EXPECT_EQ(r.fracture[0].hazard.hazard_level, "none");
}

TEST(Hazard, GlassThrownOutTowardTheBlastOrHeldIsCondition2) {
  // One fragment blown back toward the charge (+z), one held in the frame, one that drops
  // straight down at the window: none enters the room.
  Result r = ballistic_run({Vec3(0.0, 1.5, 0.0), Vec3(0.3, 1.5, 0.0), Vec3(-0.3, 1.2, 0.0)},
                           {Vec3(0.0, 0.0, 4.0), Vec3(0.0, 0.0, -9.0), Vec3::Zero()});
  r.fracture[0].release_times_s[1] = -1.0;
  rate_pane_hazards(room_scene(), r);
  const PaneHazard& h = r.fracture[0].hazard;
  EXPECT_EQ(h.condition, "2");
  EXPECT_EQ(h.hazard_level, "none");
  EXPECT_EQ(h.fragments_in_room, 0u);
  EXPECT_EQ(h.fragments_outside, 2u);
}

TEST(Hazard, FloorLandingsWithinOneMetreAre3aAndWithinThreeAre3b) {
  // From 1.5 m a fragment falls for 0.549 s: 1.6 m/s lands 0.87 m behind the pane, 3.6 m/s
  // 1.97 m.
  for (const auto& [speed, condition] : {std::pair{1.6, "3a"}, std::pair{3.6, "3b"}}) {
    Result r = ballistic_run({Vec3(0.0, 1.5, 0.0), Vec3(0.2, 1.5, 0.0)},
                             {Vec3(0.0, 0.0, -speed), Vec3(0.0, 0.0, -0.5)});
    rate_pane_hazards(room_scene(), r);
    const PaneHazard& h = r.fracture[0].hazard;
    EXPECT_EQ(h.condition, condition) << speed;
    EXPECT_EQ(h.fragments_in_room, 2u);
    EXPECT_EQ(h.fragments_on_floor, 2u);
    EXPECT_EQ(h.witness_impacts, 0u);
    EXPECT_NEAR(h.max_floor_distance_m, landing_depth(1.5, speed), 2e-3) << speed;
    EXPECT_EQ(h.fragments_extrapolated, 0u);
  }
}

TEST(Hazard, WitnessImpactsBelowTwoFeetAre4AndAboveAre5) {
  // 20 m/s from 0.4 m strikes the panel at 0.29 m; from 1.5 m at 1.39 m.
  for (const auto& [height, condition] : {std::pair{0.4, "4"}, std::pair{1.5, "5"}}) {
    Result r = ballistic_run({Vec3(0.0, height, 0.0)}, {Vec3(0.0, 0.0, -20.0)});
    scene::Scene s = room_scene();
    if (height < 1.0) s.objects[0].position.y() = 0.5;  // the pane spans 0-1 m: floor y = 0
    rate_pane_hazards(s, r);
    const PaneHazard& h = r.fracture[0].hazard;
    EXPECT_EQ(h.condition, condition) << height;
    EXPECT_EQ(h.witness_impacts, 1u);
    EXPECT_NEAR(h.max_witness_height_m, witness_height(height, 20.0), 2e-3) << height;
  }
}

TEST(Hazard, FragmentsStillInFlightAtTheEndFollowTheirBallisticPath) {
  // The run ends at 0.1 s, before the fragment lands: the rating extrapolates to the same
  // landing the full path gives.
  Result r = ballistic_run({Vec3(0.0, 1.5, 0.0)}, {Vec3(0.0, 0.0, -3.0)}, 0.1);
  rate_pane_hazards(room_scene(), r);
  const PaneHazard& h = r.fracture[0].hazard;
  EXPECT_EQ(h.fragments_extrapolated, 1u);
  EXPECT_EQ(h.condition, "3b");
  EXPECT_NEAR(h.max_floor_distance_m, landing_depth(1.5, 3.0), 1e-6);
}

TEST(Hazard, TheRoomIsAwayFromTheChargeWhenNoFaceIsSheltered) {
  // No sheltered face: the room lies on the side away from the charge. With the charge at -z,
  // a fragment flying to -z goes out toward the blast, and one flying to +z into the room.
  scene::Scene s = room_scene(false, 0);
  s.charges[0].position = Vec3(0.0, 1.5, -10.0);
  Result r = ballistic_run({Vec3(0.0, 1.5, 0.0), Vec3(0.2, 1.5, 0.0)},
                           {Vec3(0.0, 0.0, -20.0), Vec3(0.0, 0.0, 1.6)});
  rate_pane_hazards(s, r);
  const PaneHazard& h = r.fracture[0].hazard;
  EXPECT_EQ(h.fragments_outside, 1u);
  EXPECT_EQ(h.fragments_in_room, 1u);
  EXPECT_EQ(h.condition, "3a");
}

TEST(Hazard, OnTheGroundTheFurthestPointAFragmentLayAtCounts) {
  // With a ground at y = 0 the fragment lands 0.87 m in and slides on to 1.5 m; the ground's
  // floor is solid, so where it came to lie counts (3b); with no ground its path below the
  // floor level is not real and the first landing counts (3a).
  Result r = ballistic_run({Vec3(0.0, 1.5, 0.0)}, {Vec3(0.0, 0.0, -1.6)});
  const double t_land = std::sqrt(2.0 * (1.5 - kHalfFragment) / kG);
  for (std::size_t f = 0; f < r.frame_times_s.size(); ++f) {
    const double t = r.frame_times_s[f];
    if (t <= t_land) continue;
    // Slides along the floor at its landing speed, decelerating to rest at 1.5 m.
    const double slide = std::min(1.5, 1.6 * t_land + 1.6 * (t - t_land));
    r.poses[f].position = {0.0, kHalfFragment, -slide};
  }
  r.final_state[0].pose.position = {0.0, kHalfFragment, -1.5};
  r.final_state[0].linear_velocity_m_s = {0.0, 0.0, 0.0};
  Result on_ground = r;
  rate_pane_hazards(room_scene(true), on_ground);
  EXPECT_EQ(on_ground.fracture[0].hazard.condition, "3b");
  EXPECT_NEAR(on_ground.fracture[0].hazard.max_floor_distance_m, 1.5 - 0.5 * kThickness, 1e-9);
  rate_pane_hazards(room_scene(false), r);
  EXPECT_EQ(r.fracture[0].hazard.condition, "3a");
}

TEST(Hazard, TheFloorIsNeverAboveThePane) {
  // A ground at 2 m lies above the pane's lowest edge (1.0 m): the floor drops to that edge.
  scene::Scene s = room_scene(true);
  s.environment.ground->height_m = 2.0;
  Result r = ballistic_run({Vec3(0.0, 1.5, 0.0)}, {Vec3(0.0, 0.0, -1.0)});
  rate_pane_hazards(s, r);
  EXPECT_DOUBLE_EQ(r.fracture[0].hazard.floor_height_m, 1.0);
}

TEST(Hazard, TheExampleWindowIsAHighHazardAndAFarChargeLeavesItSafe) {
  // scenes/window.json: 10 kg of TNT 10 m in front of a 6 mm annealed pane 1.5 m up. Its
  // fragments leave at 6-8 m/s and cross the 3 m to the witness panel in under 0.5 s, falling
  // less than 1.2 m: well above 2 ft, condition 5.
  scene::Scene s = testing::load_example_scene("window.json");
  const RunOutcome near = simulate(s);
  ASSERT_EQ(near.result.fracture.size(), 1u);
  const PaneReport& pane = near.result.fracture[0];
  EXPECT_EQ(pane.hazard.condition, "5");
  EXPECT_EQ(pane.hazard.fragments_in_room + pane.hazard.fragments_outside, pane.released);
  EXPECT_GT(pane.hazard.witness_impacts, 0u);
  EXPECT_GT(pane.hazard.max_witness_height_m, kHazardWitnessHeight_m);
  // 10 kg at 200 m: 1.6 kPa, far below the pane's breaking pressure.
  s.charges[0].position.z() = 200.0;
  const RunOutcome far = simulate(s);
  ASSERT_FALSE(far.result.fracture[0].broken);
  EXPECT_EQ(far.result.fracture[0].hazard.condition, "1");
}

}  // namespace
}  // namespace brisance::engine
