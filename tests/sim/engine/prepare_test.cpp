// Tests of the engine's prepare stages (sim/engine/model.hpp): body sources from objects and
// broken panes, the charge conversion, holds, clearing surfaces, the model prepare builds, and
// the sleeping rule.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/engine/model.hpp"
#include "sim/engine/sleeping.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace brisance::engine {
namespace {

using Eigen::Vector3d;

scene::ObjectSpec breakable_pane(const std::string& name, const Vector3d& position) {
  scene::ObjectSpec pane =
      testing::box_object(name, Vector3d(1.2, 0.9, 0.006), position, 2500.0 * 1.2 * 0.9 * 0.006);
  pane.fracture = scene::FractureSpec{};
  pane.fracture->grid = 256;
  pane.fracture->trigger = scene::FractureSpec::Trigger::always;
  return pane;
}

TEST(BlastCharge, TntEquivalentIsMassTimesFactor) {
  scene::ChargeSpec spec = testing::tnt(2.0, Vector3d::Zero());
  spec.tnt_factor = 1.3;
  spec.burst = blast::Burst::surface;
  const blast::Charge charge = blast_charge(spec);
  EXPECT_DOUBLE_EQ(charge.tnt_equivalent_kg, 2.6);
  EXPECT_EQ(charge.burst, blast::Burst::surface);
  EXPECT_EQ(charge.surface_model, spec.surface_model);
}

TEST(BodySources, AFragmentTheWaveCrossesWithinTwoCentimetresTakesOnePanelAFace) {
  // A pane 14 m from a charge. Square to it, the wave reaches all of a fragment within 2 cm of
  // path (under 0.1 ms, at most 5 cm a metre of extent here): one panel at each face's centroid
  // gives its force. With the charge off to the side at 60 degrees from the pane's normal, the
  // wave runs along the pane and crosses most pieces over more than 2 cm of path: those keep
  // their five or more panels a face.
  const auto loaded_on_one_panel = [](const Vector3d& charge, std::size_t& crossed_over_2cm,
                                      std::size_t& those_on_one) {
    scene::Scene s = testing::vacuum_scene();
    s.charges.push_back(testing::tnt(10.0, charge));
    s.objects.push_back(breakable_pane("pane", Vector3d(0.0, 1.5, 0.0)));
    const BodySources sources = body_sources(s);
    EXPECT_TRUE(sources.reports.at(0).broken);
    std::size_t one = 0;
    crossed_over_2cm = those_on_one = 0;
    for (const BodySource& fragment : sources.bodies) {
      double nearest = INFINITY, farthest = 0.0;  // the charge's paths to its face's corners
      for (const Vector3d& v : fragment.mesh.vertices) {
        if (v.z() < 0.0) continue;  // the back face's corners
        const double d = (fragment.position + fragment.orientation * v - charge).norm();
        nearest = std::min(nearest, d);
        farthest = std::max(farthest, d);
      }
      const bool on_one = fragment.load_panels.size() == 2u;
      one += on_one;
      if (farthest - nearest > 0.0201) {
        ++crossed_over_2cm;
        those_on_one += on_one;
      }
    }
    return static_cast<double>(one) / static_cast<double>(sources.bodies.size());
  };
  std::size_t crossed = 0, crossed_on_one = 0;
  EXPECT_GT(loaded_on_one_panel(Vector3d(0.0, 1.5, 14.0), crossed, crossed_on_one), 0.9);
  EXPECT_EQ(crossed_on_one, 0u);
  EXPECT_LT(
      loaded_on_one_panel(Vector3d(14.0 * std::sqrt(0.75), 1.5, 7.0), crossed, crossed_on_one),
      0.5);
  EXPECT_GT(crossed, 100u);
  EXPECT_EQ(crossed_on_one, 0u);
}

TEST(BodySources, ObjectsAsTheyAreAndBrokenPanesAsFragmentsInTheirPlace) {
  scene::Scene s = testing::vacuum_scene();
  s.charges.push_back(testing::tnt(1.0, Vector3d(0.0, 1.5, 3.0)));
  s.objects.push_back(testing::box_object("before", Vector3d::Ones(), Vector3d(5, 0, 0), 7.0));
  s.objects.push_back(breakable_pane("pane", Vector3d(0.0, 1.5, 0.0)));
  s.objects.push_back(testing::box_object("after", Vector3d::Ones(), Vector3d(-5, 0, 0), 3.0));
  const BodySources sources = body_sources(s);

  ASSERT_EQ(sources.reports.size(), 1u);
  const PaneReport& report = sources.reports[0];
  ASSERT_TRUE(report.broken);
  ASSERT_GT(report.fragment_count, 4u);
  ASSERT_EQ(sources.bodies.size(), 2 + report.fragment_count);
  EXPECT_EQ(report.first_body, 1u);
  EXPECT_EQ(sources.bodies.front().name, "before");
  EXPECT_EQ(sources.bodies.back().name, "after");
  EXPECT_FALSE(sources.bodies.front().fragment);
  EXPECT_FALSE(sources.bodies.front().breakaway_hold_n.has_value());
  // Its panels cut at the scene's panel size (1 m^2 faces into many).
  EXPECT_EQ(sources.bodies.front().load_panels.size(),
            geometry::make_panels(s.objects[0].mesh, s.simulation.max_panel_area_m2).size());
  EXPECT_GT(sources.bodies.front().load_panels.size(), 6u);

  double mass = 0.0;
  double area = 0.0;
  std::size_t merged = 0;  // fragments loaded on one panel a face
  for (std::uint32_t b = report.first_body; b < report.first_body + report.fragment_count; ++b) {
    const BodySource& fragment = sources.bodies[b];
    EXPECT_EQ(fragment.name, "pane/f" + std::to_string(b - report.first_body));
    EXPECT_TRUE(fragment.fragment);
    ASSERT_TRUE(fragment.breakaway_hold_n.has_value());
    EXPECT_GT(*fragment.breakaway_hold_n, 0.0);  // every fragment has crack edges
    EXPECT_GT(fragment.release_not_before_s, 0.0);
    // At least five panels per face (thesis §6.2), or one per face: always for a fragment under
    // 2 cm across, and for one the wave crosses within 2 cm of path (docs/fracture.md,
    // "Performance"); the panels not made counted in stats.panels_merged.
    double extent = 0.0;
    for (const Vector3d& u : fragment.mesh.vertices)
      for (const Vector3d& v : fragment.mesh.vertices)
        extent = std::max(extent, (u - v).head<2>().norm());
    if (fragment.load_panels.size() == 2u) {
      EXPECT_GE(fragment.panels_merged, 8u);
      ++merged;
    } else {
      EXPECT_GE(fragment.load_panels.size(), 10u);
      EXPECT_EQ(fragment.panels_merged, 0u);
      EXPECT_GT(extent, 0.02);
    }
    EXPECT_FALSE(fragment.drag_panels.empty());
    mass += fragment.mass_kg;
    area += fragment.frontal_area_m2;
  }
  EXPECT_GT(merged, 0u);
  // The fragments partition the pane (thesis ch. 5).
  EXPECT_NEAR(mass, s.objects[1].mass_kg, 1e-9 * s.objects[1].mass_kg);
  EXPECT_NEAR(area, 1.2 * 0.9, 1e-9);
}

TEST(BodySources, UnbrokenFramedPaneStaysOneAnchoredBody) {
  scene::Scene s = testing::vacuum_scene();
  s.charges.push_back(testing::tnt(0.001, Vector3d(0.0, 1.5, 50.0)));  // far too weak
  scene::ObjectSpec pane = breakable_pane("pane", Vector3d(0.0, 1.5, 0.0));
  pane.fracture->trigger = scene::FractureSpec::Trigger::automatic;
  pane.fracture->framed = true;
  s.objects.push_back(pane);
  const BodySources sources = body_sources(s);
  ASSERT_EQ(sources.reports.size(), 1u);
  EXPECT_FALSE(sources.reports[0].broken);
  ASSERT_EQ(sources.bodies.size(), 1u);
  EXPECT_EQ(sources.bodies[0].name, "pane");
  EXPECT_TRUE(sources.bodies[0].anchored);
  EXPECT_FALSE(sources.bodies[0].fragment);
}

TEST(PrepareHolds, LowerBodiesCarryTheWeightAboveThem) {
  scene::Scene s;
  // Two columns of three 1 kg boxes, and one box bridging both columns on top.
  const Vector3d size(0.2, 0.1, 0.1);
  for (int column = 0; column < 2; ++column)
    for (int row = 0; row < 3; ++row)
      s.objects.push_back(testing::box_object("c" + std::to_string(column) + std::to_string(row),
                                              size, Vector3d(0.2 * column, 0.05 + 0.1 * row, 0.0),
                                              1.0));
  s.objects.push_back(
      testing::box_object("bridge", size, Vector3d(0.1, 0.35, 0.0), 2.0));  // half on each
  const BodySources sources = body_sources(s);
  const std::vector<double> weight = supported_weights(sources.bodies, 10.0);
  ASSERT_EQ(weight.size(), 7u);
  EXPECT_NEAR(weight[6], 20.0, 1e-12);
  EXPECT_NEAR(weight[2], 10.0 + 10.0, 1e-12);  // top of a column: itself and half the bridge
  EXPECT_NEAR(weight[0], 30.0 + 10.0, 1e-12);  // bottom: its column and half the bridge
  EXPECT_NEAR(weight[3], 30.0 + 10.0, 1e-12);
}

TEST(ClearingSurfaces, TouchingCoplanarFacesClearFromTheWallsEdges) {
  scene::Scene s = testing::vacuum_scene();
  s.charges.push_back(testing::tnt(1.0, Vector3d(0.0, 0.5, 5.0)));
  // A wall of 4 x 2 bricks (0.2 x 0.1 x 0.1): 0.8 m wide, 0.2 m high; and a lone brick away.
  testing::add_box_grid(s, 8, 4, Vector3d(0.2, 0.1, 0.1), 0.2, 0.0, 0.0, 1.0);
  s.objects.push_back(
      testing::box_object("lone", Vector3d(0.2, 0.1, 0.1), Vector3d(5.0, 0.05, 0.0), 1.0));
  BodySources sources = body_sources(s);
  std::vector<BodyInfo> bodies;
  Stats stats;
  const Model model = prepare(s, sources.bodies, bodies, stats);
  bool seen_wall_front = false;
  bool seen_lone_front = false;
  for (const PanelModel& panel : model.panels) {
    if (panel.normal.z() < 0.99) continue;  // the front faces (+z, towards the charge)
    if (panel.body < 8) {
      EXPECT_NEAR(panel.clearing_distance_m, 0.1, 1e-12);  // half the wall's 0.2 m height
      seen_wall_front = true;
    } else {
      EXPECT_NEAR(panel.clearing_distance_m, 0.05, 1e-12);  // half its own 0.1 m height
      seen_lone_front = true;
    }
  }
  EXPECT_TRUE(seen_wall_front);
  EXPECT_TRUE(seen_lone_front);
}

TEST(Prepare, ModelOwnsItsValuesAndStartsBodiesAsTheSceneSays) {
  std::vector<BodySource> sources_kept;
  Model model;
  std::vector<BodyInfo> bodies;
  Stats stats;
  {
    scene::Scene s;  // gravity and a ground
    s.charges.push_back(testing::tnt(1.0, Vector3d(0.0, 0.5, 5.0)));
    scene::ObjectSpec anchored =
        testing::box_object("anchored", Vector3d::Ones(), Vector3d(3, 0.5, 0), 1.0);
    anchored.anchored = true;
    scene::ObjectSpec resting =
        testing::box_object("resting", Vector3d::Ones(), Vector3d(0, 0.5, 0), 1.0);
    scene::ObjectSpec frictionless =
        testing::box_object("frictionless", Vector3d::Ones(), Vector3d(-3, 2.0, 0), 1.0);
    frictionless.friction = 0.0;
    frictionless.orientation = Eigen::Quaterniond(2.0, 0.0, 0.0, 0.0);  // not normalised
    s.objects = {anchored, resting, frictionless};
    s.simulation.duration_s = 1.25;
    BodySources sources = body_sources(s);
    model = prepare(s, sources.bodies, bodies, stats);
  }  // the scene is gone: the model must not need it
  ASSERT_EQ(model.bodies.size(), 3u);
  EXPECT_EQ(model.initial_motion[0], Motion::anchored);
  EXPECT_EQ(model.initial_motion[1], Motion::held);
  EXPECT_EQ(model.initial_motion[2], Motion::awake);  // nothing holds it: it falls
  EXPECT_EQ(stats.bodies_anchored, 1u);
  EXPECT_FALSE(model.supported[1]);  // on the ground: the contact's friction, not a hold
  EXPECT_DOUBLE_EQ(model.timing.duration_s, 1.25);
  EXPECT_DOUBLE_EQ(model.initial_states[2].orientation.norm(), 1.0);
  EXPECT_DOUBLE_EQ(model.initial_states[2].position.y(), 2.0);
  ASSERT_EQ(bodies.size(), 3u);
  EXPECT_EQ(bodies[2].name, "frictionless");
  EXPECT_EQ(bodies[2].mesh.vertices.size(), 8u);
  // Anchored bodies have no panels; events are in order of arrival.
  for (const PanelModel& panel : model.panels)
    EXPECT_NE(panel.body, 0u);
  for (std::size_t e = 1; e < model.events.size(); ++e)
    EXPECT_LE(model.events[e - 1].arrival_time_s, model.events[e].arrival_time_s);
  EXPECT_EQ(stats.panels_back_facing, 0u);  // nothing sheltered: every face has events
}

TEST(Prepare, ShelteredFacesTurnedAwayFromTheChargeHaveNoEvents) {
  scene::Scene s;
  s.charges.push_back(testing::tnt(1.0, Vec3(0.0, 1.0, 10.0)));
  scene::ObjectSpec pane =
      testing::box_object("pane", Vec3(1.0, 1.0, 0.01), Vec3(0.0, 1.0, 0.0), 25.0);
  pane.sheltered = scene::kShelteredBack;  // -z: the charge is on +z
  s.objects.push_back(pane);
  s.simulation.max_panel_area_m2 = 10.0;
  Stats stats;
  std::vector<BodyInfo> bodies;
  BodySources sources = body_sources(s);
  const Model model = prepare(s, sources.bodies, bodies, stats);
  ASSERT_EQ(model.panels.size(), 6u);
  EXPECT_EQ(stats.panels_back_facing, 1u);
  EXPECT_EQ(model.events.size(), 5u);
  for (const PanelEvent& event : model.events) {
    const PanelModel& panel = model.panels[event.panel];
    EXPECT_FALSE(panel.sheltered && panel.normal.z() < 0.0);
  }
  // Turned around, the same face is struck head-on and loaded; the +z face now wraps.
  s.charges[0].position.z() = -10.0;
  sources = body_sources(s);
  bodies.clear();
  stats = Stats{};
  const Model turned = prepare(s, sources.bodies, bodies, stats);
  EXPECT_EQ(stats.panels_back_facing, 0u);
  EXPECT_EQ(turned.events.size(), 6u);
}

TEST(Sleeping, RestsLongEnoughThenSleepsAndMovingResetsTheClock) {
  double rest = 0.0;
  const double dt = 0.1;
  for (int i = 0; i < 4; ++i)
    EXPECT_FALSE(falls_asleep(true, 0.01, 0.0, dt, rest));
  EXPECT_NEAR(rest, 0.4, 1e-12);
  EXPECT_FALSE(falls_asleep(true, 1.0, 0.0, dt, rest));  // moving again
  EXPECT_EQ(rest, 0.0);
  for (int i = 0; i < 4; ++i)
    EXPECT_FALSE(falls_asleep(true, 0.01, 0.01, dt, rest));
  EXPECT_FALSE(falls_asleep(true, 0.01, 0.5 * 0.5, dt, rest));  // spinning at 0.5 rad/s
  EXPECT_EQ(rest, 0.0);
  for (int i = 0; i < 4; ++i)
    EXPECT_FALSE(falls_asleep(true, 0.01, 0.0, dt, rest));
  EXPECT_FALSE(falls_asleep(false, 0.0, 0.0, dt, rest));  // off the ground
  EXPECT_EQ(rest, 0.0);
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(falls_asleep(true, 0.0, 0.0, dt, rest), i == 4);
}

}  // namespace
}  // namespace brisance::engine
