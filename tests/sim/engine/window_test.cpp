// Breakable panes in the engine (DESIGN.md decision 9, thesis ch. 6): the blast's stress decides
// whether a pane breaks and at what scale, fragments break free as the wave reaches them, and the
// window scenes behave as the thesis describes.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/blast/air.hpp"
#include "sim/blast/blast_point.hpp"
#include "sim/engine/pane_pattern.hpp"
#include "sim/engine/simulator.hpp"
#include "sim/fracture/pane.hpp"
#include "sim/geometry/mesh.hpp"
#include "sim/scene/scene.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace brisance::engine {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

scene::Scene load(const std::string& name) {
  return testing::load_example_scene(name);
}

// A 1.2 m x 0.9 m x 6 mm annealed pane centred at (0, 1.5, 0), front face +z, no ground, and
// `mass_kg` of TNT at `charge` (a short run: fragments need only be launched).
scene::Scene pane_scene(double mass_kg, const Vec3& charge, int grid = 512) {
  scene::Scene s;
  scene::ChargeSpec c;
  c.mass_kg = mass_kg;
  c.position = charge;
  s.charges.push_back(c);
  s.environment.ground.reset();
  scene::ObjectSpec pane;
  pane.name = "pane";
  pane.shape = scene::ShapeType::box;
  pane.box_size_m = Vec3(1.2, 0.9, 0.006);
  pane.mesh = geometry::make_box(pane.box_size_m);
  pane.position = Vec3(0.0, 1.5, 0.0);
  pane.mass_kg = 2500.0 * pane.box_size_m.prod();
  pane.material = "annealed_glass";
  pane.fracture = scene::FractureSpec{};
  pane.fracture->grid = grid;
  s.objects.push_back(pane);
  s.simulation.duration_s = 0.1;
  return s;
}

TEST(PaneCoupling, RoarkTableAndPlateStress) {
  EXPECT_DOUBLE_EQ(fracture::roark_beta(1.0), 0.2874);
  EXPECT_DOUBLE_EQ(fracture::roark_beta(2.0), 0.6102);
  EXPECT_NEAR(fracture::roark_beta(1.1), 0.5 * (0.2874 + 0.3762), 1e-12);
  EXPECT_NEAR(fracture::roark_beta(1e9), 0.75, 1e-6);
  // A 1 m square, 10 mm plate under 1 kPa: 0.2874 * 1000 * 1 / 1e-4 = 2.874 MPa.
  const fracture::PlateResponse plate = fracture::simply_supported_plate(1, 1, 0.01, 1e3, 70e9);
  EXPECT_NEAR(plate.stress_pa, 2.874e6, 1.0);
  EXPECT_NEAR(plate.deflection_m, 0.0444 * 1e3 / (70e9 * 1e-6), 1e-12);
  // The same for width and height swapped.
  EXPECT_EQ(fracture::simply_supported_plate(1.2, 0.9, 0.006, 5e3, 70e9).stress_pa,
            fracture::simply_supported_plate(0.9, 1.2, 0.006, 5e3, 70e9).stress_pa);
}

TEST(PaneCoupling, GrowthLengthFallsAsPressureRises) {
  fracture::PaneFractureInput input;
  input.width_m = 1.2;
  input.height_m = 0.9;
  input.min_growth_length_m = 1e-4;
  input.max_growth_length_m = 0.45;
  double previous = INFINITY;
  for (double p : {6e3, 1e4, 2e4, 4e4, 8e4}) {
    input.pressure_pa = p;
    const fracture::PaneFracture f = fracture::pane_fracture(input);
    ASSERT_TRUE(f.breaks) << p;
    EXPECT_LT(f.growth_length_m, previous) << p;
    // eq. 5.5: a_c = (1/pi)(K_c / sigma)^2.
    EXPECT_NEAR(f.critical_crack_length_m,
                std::pow(input.fracture_toughness_pa_sqrt_m / f.plate.stress_pa, 2) / M_PI, 1e-18);
    previous = f.growth_length_m;
  }
  input.pressure_pa = 1e3;  // 9.6 MPa of stress: below 45 MPa
  EXPECT_FALSE(fracture::pane_fracture(input).breaks);
}

// A sliver of a pane: half its shorter side is below the finest cells' minimum growth length.
// The growth length is its half width (std::clamp with min above max was undefined behaviour).
TEST(PaneCoupling, ASliverGrowsAtItsHalfWidth) {
  fracture::PaneFractureInput input;
  input.width_m = 100.0;
  input.height_m = 0.001;
  input.thickness_m = 0.0005;
  input.pressure_pa = 1e8;  // about 300 MPa of stress
  input.min_growth_length_m = 0.05;
  input.max_growth_length_m = 0.0005;
  const fracture::PaneFracture f = fracture::pane_fracture(input);
  ASSERT_TRUE(f.breaks);
  EXPECT_EQ(f.growth_length_m, 0.0005);
}

TEST(PaneCoupling, EmpiricalFormulasAsPrinted) {
  // Eq. 2.45 at 0 Pa: one square inch times e^(2.4 - sqrt(12.5)).
  EXPECT_NEAR(fracture::empirical_fragment_area_m2(0.0),
              6.4516e-4 * std::exp(2.4 - std::sqrt(12.5)), 1e-15);
  EXPECT_GT(fracture::empirical_fragment_area_m2(1e4), fracture::empirical_fragment_area_m2(1e5));
  EXPECT_GT(fracture::empirical_fragment_velocity_m_s(1e5, 0.006),
            fracture::empirical_fragment_velocity_m_s(1e4, 0.006));
}

TEST(PaneCoupling, HigherPressureGivesSmallerFragments) {
  // The monotone response of fragment scale to pressure (thesis p. 5.4: "for higher pressure,
  // the average fragment size will be smaller"), median over seeds: one pattern can stop early.
  double previous_area = INFINITY;
  double previous_pressure = 0.0;
  for (double distance : {30.0, 20.0, 14.0}) {
    std::vector<double> areas;
    double pressure = 0.0;
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      scene::Scene s = pane_scene(10.0, Vec3(0.0, 1.5, distance));
      s.simulation.seed = seed;
      s.simulation.duration_s = 0.01;
      const Result r = simulate(s).result;
      ASSERT_EQ(r.fracture.size(), 1u);
      const PaneReport& pane = r.fracture[0];
      ASSERT_TRUE(pane.broken) << distance;
      EXPECT_FALSE(pane.growth_length_clamped) << distance;
      areas.push_back(pane.frontal_area_m2.mean);
      pressure = pane.peak_pressure_pa;
    }
    std::sort(areas.begin(), areas.end());
    EXPECT_GT(pressure, previous_pressure);
    EXPECT_LT(areas[1], previous_area) << "charge at " << distance << " m";
    previous_area = areas[1];
    previous_pressure = pressure;
  }
}

TEST(PaneCoupling, BelowStrengthThePaneStaysWhole) {
  // 10 kg at 100 m: about 2 kPa reflected, 19 MPa of stress, below annealed glass's 45 MPa.
  scene::Scene s = pane_scene(10.0, Vec3(0.0, 1.5, 100.0));
  const Result r = simulate(s).result;
  ASSERT_EQ(r.fracture.size(), 1u);
  EXPECT_FALSE(r.fracture[0].broken);
  EXPECT_LT(r.fracture[0].stress_pa, r.fracture[0].strength_pa);
  EXPECT_EQ(r.fracture[0].fragment_count, 0u);
  EXPECT_EQ(r.stats.panes_not_broken, 1u);
  EXPECT_EQ(r.stats.fragments, 0u);
  ASSERT_EQ(r.bodies.size(), 1u);
  EXPECT_EQ(r.bodies[0].name, "pane");
  // Tempered glass (120 MPa) holds where annealed (45 MPa) breaks.
  scene::Scene near = pane_scene(10.0, Vec3(0.0, 1.5, 40.0));
  const Result annealed = simulate(near).result;
  near.objects[0].fracture->strength_pa = 120e6;
  const Result tempered = simulate(near).result;
  EXPECT_GT(annealed.fracture[0].stress_pa, 45e6);
  EXPECT_LT(annealed.fracture[0].stress_pa, 120e6);
  EXPECT_TRUE(annealed.fracture[0].broken);
  EXPECT_FALSE(tempered.fracture[0].broken);
}

TEST(PaneCoupling, ExplicitParametersOverrideTheBlast) {
  // Artist control (thesis §6): break: always and a given growth length.
  scene::Scene s = pane_scene(10.0, Vec3(0.0, 1.5, 100.0));
  s.objects[0].fracture->trigger = scene::FractureSpec::Trigger::always;
  s.objects[0].fracture->growth_length_m = 0.05;
  const Result r = simulate(s).result;
  ASSERT_TRUE(r.fracture[0].broken);
  EXPECT_TRUE(r.fracture[0].forced);
  EXPECT_TRUE(r.fracture[0].growth_length_given);
  EXPECT_EQ(r.fracture[0].growth_length_m, 0.05);
  EXPECT_GT(r.fracture[0].fragment_count, 3u);
  // A given growth length replaces eq. 5.5's whatever the pressure.
  scene::Scene near = pane_scene(10.0, Vec3(0.0, 1.5, 14.0));
  near.objects[0].fracture->growth_length_m = 0.05;
  const Result given = simulate(near).result;
  EXPECT_EQ(given.fracture[0].growth_length_m, 0.05);
  EXPECT_FALSE(given.fracture[0].forced);
}

TEST(PaneCoupling, FragmentMassesSumToThePanesAndEveryPanelIsMadeOrCounted) {
  scene::Scene s = pane_scene(10.0, Vec3(0.0, 1.5, 14.0));
  const double pane_mass = s.objects[0].mass_kg;
  const Result r = simulate(s).result;
  const PaneReport& pane = r.fracture[0];
  ASSERT_TRUE(pane.broken);
  ASSERT_EQ(r.bodies.size(), pane.fragment_count);
  double total = 0.0;
  double volume = 0.0;
  for (const BodyInfo& body : r.bodies) {
    total += body.mass_kg;
    volume += geometry::mass_properties(body.mesh, 1.0).volume_m3;
  }
  EXPECT_NEAR(total, pane_mass, 1e-9 * pane_mass);
  EXPECT_NEAR(volume, 1.2 * 0.9 * 0.006, 1e-9);
  // Thesis §6.2: at least five panels per fragment face (the ear clipping's triangles, 5 to 16),
  // both faces, or one a face where the wave crosses the fragment within 2 cm of path; every
  // panel not made counted in stats.panels_merged. 14 m square in front of the pane's centre
  // the wave crosses each fragment within 5 cm of path per metre of its extent: most pieces
  // take one panel a face.
  std::uint64_t full = 0;
  for (const BodyInfo& body : r.bodies) {
    const std::size_t corners = body.mesh.vertices.size() / 2;  // a prism: both faces' corners
    full += 2 * std::clamp<std::size_t>(corners - 2, 5, 16);
  }
  EXPECT_EQ(r.stats.panels + r.stats.panels_merged, full);
  EXPECT_LT(r.stats.panels, 3u * pane.fragment_count);
  EXPECT_GE(r.stats.panels, 2u * pane.fragment_count);
}

TEST(PaneCoupling, FragmentsBreakFreeAsTheWaveSweepsThePane) {
  // A charge off to the side: the wave reaches the near edge first, but a piece is free only
  // when its load has beaten its hold, the wave has reached its centroid and the crack front —
  // from where the plate's stress peaks, at the terminal crack speed, from when the stress
  // reaches the strength (issue 11: fracture runs with the wave) — has passed all of its
  // outline. The charge 4 m to the side of the pane's centre (+x) pulls that point toward it.
  scene::Scene s = pane_scene(10.0, Vec3(4.0, 1.5, 8.0));
  s.objects[0].fracture->framed = true;
  const Result r = simulate(s).result;
  const PaneReport& pane = r.fracture[0];
  ASSERT_TRUE(pane.broken);
  ASSERT_GT(pane.released, 20u);
  ASSERT_GT(pane.cracks_start_s, 0.0);
  // The pane is 1.2 x 0.9 m; its cracks start right of its centre, on its horizontal mid-line.
  EXPECT_GT(pane.crack_origin_m[0], 0.6 + 1e-3);
  EXPECT_LT(pane.crack_origin_m[0], 1.2);
  EXPECT_NEAR(pane.crack_origin_m[1], 0.45, 0.01);
  const Vec3 origin(pane.crack_origin_m[0] - 0.6, pane.crack_origin_m[1] - 0.45, 0.0);
  blast::Charge charge;
  charge.tnt_equivalent_kg = 10.0;
  std::vector<std::pair<double, double>> by_outline;  // farthest outline from the origin, release
  std::size_t held_by_front = 0;
  for (std::size_t k = 0; k < pane.fragment_count; ++k) {
    const double release = pane.release_times_s[k];
    const BodyInfo& body = r.bodies[pane.first_body + k];
    const Vec3 centroid = Vec3(body.initial_pose.position.data()) +
                          geometry::mass_properties(body.mesh, 1.0).centre_of_mass;
    const double arrival =
        blast::blast_point(charge, (centroid - s.charges[0].position).norm()).arrival_time_s;
    if (release < 0.0) {
      // Never released: it did not move.
      EXPECT_EQ(std::count(r.animated.begin(), r.animated.end(), pane.first_body + k), 0);
      continue;
    }
    EXPECT_GE(release, arrival - 1e-12) << body.name;
    double outline = 0.0;  // the mesh is in the pane's frame, centred on the pane
    for (const Vec3& v : body.mesh.vertices)
      outline = std::max(outline, std::hypot(v.x() - origin.x(), v.y() - origin.y()));
    const double front = pane.cracks_start_s + outline / fracture::kTerminalCrackSpeed_m_s;
    EXPECT_GE(release, front - 1e-12) << body.name;
    if (release > arrival + 1e-5) ++held_by_front;
    by_outline.emplace_back(outline, release);
  }
  EXPECT_GT(held_by_front, 0u);
  // The front sweeps out from its origin: pieces reaching farther from it go later.
  std::sort(by_outline.begin(), by_outline.end());
  const std::size_t half = by_outline.size() / 2;
  double inner = 0.0, outer = 0.0;
  for (std::size_t i = 0; i < by_outline.size(); ++i)
    (i < half ? inner : outer) += by_outline[i].second;
  EXPECT_LT(inner / static_cast<double>(half),
            outer / static_cast<double>(by_outline.size() - half));
  // Framed: fragments along the frame are held harder; some stay in it, and the stats count them
  // as held by their frame.
  EXPECT_LT(pane.released, pane.fragment_count);
  EXPECT_EQ(r.stats.fragments_held_by_frame, pane.fragment_count - pane.released);
  EXPECT_GE(r.stats.bodies_never_released, r.stats.fragments_held_by_frame);
}

TEST(PaneCoupling, ACloseChargeOffCentreStartsTheCracksTowardItsFoot) {
  // 0.5 kg of TNT 0.5 m in front of a point 0.4 m right of and 0.2 m above the pane's centre:
  // the plate's stress peaks between the centre and the charge's foot (pane coordinates
  // (1.0, 0.65)), held back from the foot by the supported edge 0.2 m beyond it. A charge
  // straight in front leaves the origin at the centre.
  const Result off = simulate(pane_scene(0.5, Vec3(0.4, 1.7, 0.5))).result;
  ASSERT_TRUE(off.fracture[0].broken);
  const Vec2 origin(off.fracture[0].crack_origin_m[0], off.fracture[0].crack_origin_m[1]);
  const Vec2 foot(1.0, 0.65);
  const Vec2 centre(0.6, 0.45);
  EXPECT_GT(origin.x(), centre.x() + 0.1);
  EXPECT_GT(origin.y(), centre.y() + 0.05);
  EXPECT_LT((origin - foot).norm(), 0.5 * (centre - foot).norm());
  const Result ahead = simulate(pane_scene(0.5, Vec3(0.0, 1.5, 0.5))).result;
  ASSERT_TRUE(ahead.fracture[0].broken);
  EXPECT_EQ(ahead.fracture[0].crack_origin_m, (std::array<double, 2>{0.6, 0.45}));
}

TEST(PaneCoupling, DeterministicFragmentsAndFrames) {
  scene::Scene s = pane_scene(10.0, Vec3(1.0, 1.5, 14.0));
  const Result a = simulate(s).result;
  const Result b = simulate(s).result;
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  EXPECT_EQ(a.fracture[0].release_times_s, b.fracture[0].release_times_s);
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (std::size_t i = 0; i < a.poses.size(); ++i) {
    ASSERT_EQ(a.poses[i].position, b.poses[i].position) << i;
    ASSERT_EQ(a.poses[i].orientation, b.poses[i].orientation) << i;
  }
  // Another scene seed, another pattern.
  s.simulation.seed = 99;
  const auto masses = [](const Result& r) {
    std::vector<double> m;
    for (const BodyInfo& body : r.bodies)
      m.push_back(body.mass_kg);
    return m;
  };
  EXPECT_NE(masses(simulate(s).result), masses(a));
}

// window.json's pane centre, head-on 10 m from 10 kg of TNT.
blast::BlastPoint window_blast_point() {
  blast::Charge charge;
  charge.tnt_equivalent_kg = 10.0;
  return blast::blast_point(charge, 10.0);
}

// Its front face written out from the parts (not through pane_face_load, which is what the
// tests check): the reflected pulse cleared from the pane's edges (S = 0.45 m), the relief
// delayed by the wave's sweep to them (head-on: h = 10 m, rho = 0).
blast::PressureHistory window_front_face_by_hand() {
  blast::Charge charge;
  charge.tnt_equivalent_kg = 10.0;
  const blast::BlastPoint point = window_blast_point();
  const blast::PanelWave wave =
      blast::panel_wave(point, 1.0, point.reflected_overpressure_pa, point.reflected_impulse_pa_s);
  blast::PanelLoadOptions options;
  options.clearing_distance_m = 0.45;
  options.clearing_delay_s = blast::clearing_delay_s(charge, 10.0, 0.0, 0.45);
  return blast::front_face_history(wave, options);
}

TEST(PaneCoupling, BreakageTakesTheClearedFrontFaceItsFragmentsTake) {
  // The pane is judged under the history its fragments' front faces take in the run: the
  // reflected pulse relieved from the pane's edges (S = half the shorter side, 0.45 m) over
  // 3 S / U into the stagnation pressure (thesis eqs. 2.30-2.31, sim/blast/panel_load), not the
  // uncleared reflected pulse. Built here by hand from the blast point and the face history.
  const scene::Scene s = pane_scene(10.0, Vec3(0.0, 1.5, 10.0));
  const PaneReport cleared = simulate(s).result.fracture.at(0);
  scene::Scene off = s;
  off.simulation.clearing = false;
  const PaneReport uncleared = simulate(off).result.fracture.at(0);
  EXPECT_EQ(cleared.peak_pressure_pa, uncleared.peak_pressure_pa);  // the front starts at P_r

  const blast::BlastPoint point = window_blast_point();
  PaneLoad load;
  load.peak_pressure_pa = point.reflected_overpressure_pa;
  load.history.components.push_back({0.0, window_front_face_by_hand()});
  // The cleared face carries less impulse than i_r: 3 S / U is about half of t_o here.
  ASSERT_LT(load.history.impulse_pa_s(0.0, 1.0), 0.9 * point.reflected_impulse_pa_s);
  const PaneSize size{1.2, 0.9, 0.006, 2500.0};
  const fracture::PlateResponse by_hand = pane_stress(*s.objects[0].fracture, size, load);
  EXPECT_NEAR(cleared.stress_pa / by_hand.stress_pa, 1.0, 1e-9);
  EXPECT_NEAR(cleared.deflection_m / by_hand.deflection_m, 1.0, 1e-9);
  EXPECT_LT(cleared.stress_pa, 0.95 * uncleared.stress_pa);
}

TEST(PaneCoupling, FragmentsLeaveWithThePlatesVelocityShape) {
  // Issue 11 / thesis §6.5: at the break the pane moves as its mode shape, fast at the centre
  // and still at the frame; the impulse it took until then is shared out in that shape, so a
  // fragment near the centre leaves faster than one near the edge (per-area sharing gave every
  // fragment the same speed within 0.5 %), and the pane's momentum is unchanged: with nothing
  // holding the fragments, no gravity and no flight drag, their mass-weighted mean velocity
  // is the cleared face's impulse per mass (the pane's back sheltered).
  scene::Scene s = pane_scene(10.0, Vec3(0.0, 1.5, 10.0));
  s.objects[0].sheltered = scene::kShelteredBack;
  s.objects[0].fracture->bond_strength_pa = 0.0;
  s.environment.gravity_m_s2 = Vec3::Zero();
  s.environment.air_density_kg_m3 = 0.0;
  s.simulation.duration_s = 0.05;
  const Result r = simulate(s).result;
  const PaneReport& pane = r.fracture.at(0);
  ASSERT_TRUE(pane.broken);
  ASSERT_EQ(pane.released, pane.fragment_count);
  ASSERT_GT(pane.fragment_count, 10u);

  double momentum = 0.0, mass = 0.0;
  double centre_speed = 0.0, edge_speed = 0.0;
  double centre_distance = INFINITY, edge_margin = INFINITY;
  for (std::size_t k = 0; k < pane.fragment_count; ++k) {
    const std::size_t b = pane.first_body + k;
    const double m = r.bodies[b].mass_kg;
    const double vz = r.final_state[b].linear_velocity_m_s[2];
    momentum += m * vz;
    mass += m;
  }
  // Where each fragment lies in the pane: the mean of its mesh's vertices (the pane's centred
  // frame). The one nearest the centre against the one nearest the frame.
  for (std::size_t k = 0; k < pane.fragment_count; ++k) {
    const std::size_t b = pane.first_body + k;
    Vec3 c = Vec3::Zero();
    for (const Vec3& v : r.bodies[b].mesh.vertices)
      c += v;
    c /= static_cast<double>(r.bodies[b].mesh.vertices.size());
    const double speed = std::abs(r.final_state[b].linear_velocity_m_s[2]);
    const double from_centre = std::hypot(c.x(), c.y());
    const double margin = std::min(0.6 - std::abs(c.x()), 0.45 - std::abs(c.y()));
    if (from_centre < centre_distance) centre_distance = from_centre, centre_speed = speed;
    if (margin < edge_margin) edge_margin = margin, edge_speed = speed;
  }
  EXPECT_GT(centre_speed, 1.5 * edge_speed) << centre_distance << " " << edge_margin;

  const double per_mass = window_front_face_by_hand().total_impulse_pa_s() / (2500.0 * 0.006);
  // The fragments' panels lie up to 0.75 m off the axis: distance and incidence change their
  // impulse by about 1 %.
  EXPECT_NEAR(-momentum / mass / per_mass, 1.0, 0.03);
}

TEST(BlastWind, TheAirIsStillBeforeTheWaveArrives) {
  // A 1 g, 5 x 5 cm card 10 m from 10 kg TNT, face on, falling. Before the wave arrives the air
  // is still: it falls exactly as with no charge at all (an invariant: it passes on the old
  // engine too). Light debris starting from rest in the flow approaches the wind's speed and
  // never passes it: dynamics_tests Drag.ALightBodyIsCarriedByTheWindAndNeverPassesIt.
  scene::Scene s;
  s.charges.push_back(testing::tnt(10.0, Vec3(0.0, 0.0, 0.0)));
  s.environment.ground.reset();
  scene::ObjectSpec card =
      testing::box_object("card", Vec3(0.05, 0.05, 0.001), Vec3(0.0, 0.0, 10.0), 1e-3);
  card.rotates = false;
  s.objects.push_back(card);
  blast::Charge charge;
  charge.tnt_equivalent_kg = 10.0;
  const blast::BlastPoint point = blast::blast_point(charge, 10.0);
  s.simulation.duration_s = 0.5 * point.arrival_time_s;
  const Result before = simulate(s).result;
  scene::Scene no_charge = s;
  no_charge.charges.clear();
  const Result alone = simulate(no_charge).result;
  EXPECT_EQ(before.final_state.at(0).linear_velocity_m_s,
            alone.final_state.at(0).linear_velocity_m_s);
  EXPECT_EQ(before.final_state.at(0).linear_velocity_m_s[2], 0.0);
}

TEST(WindowScenes, WindowIsBlownOut) {
  // Thesis ch. 6: fragments blown away from the charge (at +z), larger ones faster (§6.5: each
  // fragment clears from its own edges). Hundreds of them with the static small-deflection
  // stress (778 MPa at window.json's 80.9 kPa); dozens with the dynamic plate model, whose
  // membrane action holds the stress to 184 MPa under the front face cleared from the pane's
  // edges (213 MPa uncleared): eq. 5.5's growth length is (778/184)^2 = 18 x longer
  // (docs/fracture.md, "Breakage: dynamic against static").
  scene::Scene by_static = load("window.json");
  by_static.objects[0].fracture->breakage = scene::FractureSpec::Breakage::static_plate;
  by_static.simulation.duration_s = 0.01;
  EXPECT_GE(simulate(by_static).result.fracture[0].fragment_count, 500u);
  const Result r = simulate(load("window.json")).result;
  ASSERT_EQ(r.fracture.size(), 1u);
  const PaneReport& pane = r.fracture[0];
  ASSERT_TRUE(pane.broken);
  EXPECT_NEAR(pane.stress_pa, 184e6, 1e6);
  EXPECT_GE(pane.fragment_count, 500u);
  EXPECT_GT(pane.released, pane.fragment_count / 2);
  // Larger fragments faster (thesis §6.5) holds where the thesis has it, with each fragment
  // clearing from its own edges. With the pane's clearing (the default) the pieces leave in the
  // plate's mode shape, and the smallest are the splinters of the branching zone at the centre,
  // where the plate moves fastest: there the smaller half is the faster (docs/fracture.md).
  scene::Scene own = load("window.json");
  own.objects[0].fracture->clearing = scene::FractureSpec::Clearing::fragment;
  own.simulation.duration_s = 0.1;
  const PaneReport own_pane = simulate(own).result.fracture.at(0);
  EXPECT_GT(own_pane.launch_speed_larger_half_m_s, own_pane.launch_speed_smaller_half_m_s);
  std::size_t away = 0;
  for (std::size_t k = 0; k < pane.fragment_count; ++k) {
    if (pane.release_times_s[k] < 0.0) continue;
    const FinalState& f = r.final_state[pane.first_body + k];
    if (f.linear_velocity_m_s[2] < 0.0 && f.pose.position[2] < -0.1) ++away;
  }
  EXPECT_EQ(away, pane.released);
  EXPECT_EQ(r.stats.bodies_anchored, 4u);  // the frame
}

TEST(WindowScenes, ShelteredPaneFliesWithTheMomentumTheWaveGives) {
  // A pane with a room behind it takes at most about i_r per area from the pressure: its
  // fragments' momentum over their mass (the mass-weighted mean launch speed) lies between 0.6
  // and 1.3 times i_r / (rho h) (issue 11's bound; bench/results/window_fragments.txt has the
  // table over charges and thicknesses).
  scene::Scene s = load("window.json");
  const scene::ObjectSpec& pane = s.objects[0];
  ASSERT_EQ(pane.sheltered, scene::kShelteredBack);
  const double mass_per_area = pane.mass_kg / (pane.box_size_m.x() * pane.box_size_m.y());
  const blast::BlastPoint point = blast::blast_point(
      blast::Charge{s.charges[0].mass_kg}, (s.charges[0].position - pane.position).norm());
  const double bound = point.reflected_impulse_pa_s / mass_per_area;
  const Result sheltered = simulate(s).result;
  const double speed = sheltered.fracture[0].launch_speed_mass_weighted_m_s;
  EXPECT_GT(speed, 0.6 * bound);
  EXPECT_LT(speed, 1.3 * bound);
  // The plain mean over fragments too (issue 11's "mean launch speed"): with the radial-ring
  // pattern it is within the bound as well (0.91; the crack tree's 32 pieces gave 0.58).
  EXPECT_GT(sheltered.fracture[0].launch_speed_m_s.mean, 0.6 * bound);
  EXPECT_LT(sheltered.fracture[0].launch_speed_m_s.mean, 1.3 * bound);
  // Held fragments keep the load they took before breaking free: most of the glass leaves the
  // frame — by mass more than 80 % with either breakage model (the crack tree's 32 pieces: 27
  // released). What stays are slivers along the frame, whose crack faces and glazing bite hold
  // them (by count the static model releases 79 % of its ~2 000 pieces). A fragment whose load
  // beat its hold goes once the crack front has passed it, even if the wave has passed by then.
  const auto released_mass_fraction = [](const Result& r) {
    double released = 0.0, total = 0.0;
    for (std::size_t b = 0; b < r.bodies.size(); ++b) {
      if (!r.bodies[b].fragment) continue;
      total += r.bodies[b].mass_kg;
      if (r.final_state[b].pose.position != r.bodies[b].initial_pose.position)
        released += r.bodies[b].mass_kg;
    }
    return released / total;
  };
  EXPECT_GT(released_mass_fraction(sheltered), 0.8);
  EXPECT_GT(static_cast<double>(sheltered.fracture[0].released),
            0.8 * static_cast<double>(sheltered.fracture[0].fragment_count));
  scene::Scene by_static = s;
  by_static.objects[0].fracture->breakage = scene::FractureSpec::Breakage::static_plate;
  const Result static_sheltered = simulate(by_static).result;
  EXPECT_GT(released_mass_fraction(static_sheltered), 0.8);
  std::printf("  released by mass: dynamic %.3f, static %.3f; by count %.3f, %.3f\n",
              released_mass_fraction(sheltered), released_mass_fraction(static_sheltered),
              static_cast<double>(sheltered.fracture[0].released) /
                  static_cast<double>(sheltered.fracture[0].fragment_count),
              static_cast<double>(static_sheltered.fracture[0].released) /
                  static_cast<double>(static_sheltered.fracture[0].fragment_count));
  // In the open, the wave wraps around onto the pane's back and takes part of the push away.
  s.objects[0].sheltered = 0;
  const double open = simulate(s).result.fracture[0].launch_speed_m_s.mean;
  EXPECT_LT(open, 0.9 * speed);
  EXPECT_GT(open, 0.3 * speed);
}

TEST(WindowScenes, OverdampedWindowBarelyMoves) {
  // Thesis §6.5, fig. 6.6: damping 1000 times normal (air 1000 times as dense) compresses the
  // flight into a short distance.
  const auto mean_travel = [](const Result& r) {
    const PaneReport& pane = r.fracture[0];
    double sum = 0.0;
    for (std::size_t k = 0; k < pane.fragment_count; ++k)
      sum += std::abs(r.final_state[pane.first_body + k].pose.position[2]);
    return sum / static_cast<double>(pane.fragment_count);
  };
  const Result normal = simulate(load("window.json")).result;
  const Result overdamped = simulate(load("window_overdamped.json")).result;
  ASSERT_EQ(normal.fracture[0].fragment_count, overdamped.fracture[0].fragment_count);
  EXPECT_LT(mean_travel(overdamped), 0.05 * mean_travel(normal));
}

// A window in a wall's opening: its anchored frame holds to the world, so when the wall around
// it is blown away the run must say that the frame was left in the air.
scene::Scene wall_with_window(double charge_kg, double charge_z_m, double brick_mass_kg) {
  const std::string text = R"({
    "charges": [{"position": [0, 0.6, )" +
                           std::to_string(charge_z_m) + R"(], "mass": )" +
                           std::to_string(charge_kg) + R"(}],
    "generators": [{"type": "brick_wall", "name": "wall", "rows": 8, "columns": 6,
                    "brick_size": [0.4, 0.15, 0.1], "brick_mass": )" +
                           std::to_string(brick_mass_kg) + R"(,
                    "openings": [{"position": [0, 0.6], "size": [0.8, 0.6],
                                  "window": {"fracture": {"growth_length": 0.3}}}]}],
    "simulation": {"duration": 0.3, "body_substeps": true}
  })";
  const scene::ParseResult parsed = scene::parse_scene_text(text);
  EXPECT_TRUE(parsed.scene.has_value());
  return parsed.scene.value_or(scene::Scene{});
}

std::uint64_t floating_count(const Result& result) {
  for (const Warning& warning : result.warnings)
    if (warning.code == "anchored_body_floating") return warning.count;
  return 0;
}

TEST(WindowInAWall, AFrameLeftInTheAirIsReported) {
  // 20 kg of TNT 3 m in front: the wall goes, the frame's four bars stay where they were.
  const Result blown = simulate(wall_with_window(20.0, 3.0, 10.0)).result;
  EXPECT_EQ(floating_count(blown), 4u);
  for (const FinalState& body : blown.final_state) {
    if (body.name == "wall/opening0/frame/bottom") {
      EXPECT_NEAR(body.pose.position[1], 0.325, 1e-12);  // anchored: not moved
    }
  }
  // 20 g 10 m away against 200 kg bricks: nothing moves, nothing floats.
  const Result standing = simulate(wall_with_window(0.02, 10.0, 200.0)).result;
  EXPECT_EQ(floating_count(standing), 0u);
  EXPECT_TRUE(standing.animated.empty());
}

TEST(PaneCoupling, BreakingPressureAndPatternUseOneStressForBothModels) {
  // `brisance fracture` and a job judge a pane with the same function: just above the breaking
  // pressure of a pulse shape the pane breaks, just below it does not, for either model; the
  // static model's breaking pressure does not depend on the pulse, the dynamic one's does.
  const PaneSize pane{1.2, 0.9, 0.006, 2500.0};
  const auto triangle = [](double peak_pa, double duration_s) {
    PaneLoad load;
    load.peak_pressure_pa = peak_pa;
    load.history.components.push_back(response::pulse_component(blast::make_pulse(
        blast::PulseShape::triangle_same_period, peak_pa, duration_s, 0.5 * peak_pa * duration_s)));
    return load;
  };
  double dynamic_short = 0.0;
  for (const auto model :
       {scene::FractureSpec::Breakage::static_plate, scene::FractureSpec::Breakage::dynamic}) {
    scene::FractureSpec spec;
    spec.breakage = model;
    std::vector<double> breaking;
    for (const double duration_s : {0.002, 0.2}) {
      const double p = breaking_pressure_pa(spec, pane, triangle(1e3, duration_s));
      breaking.push_back(p);
      EXPECT_TRUE(pane_pattern(spec, pane, triangle(1.002 * p, duration_s), 1).response.breaks);
      EXPECT_FALSE(pane_pattern(spec, pane, triangle(0.997 * p, duration_s), 1).response.breaks);
    }
    if (model == scene::FractureSpec::Breakage::static_plate) {
      EXPECT_EQ(breaking[0], breaking[1]);
    } else {
      // A short pulse (t_d / T about 0.05; T = 36 ms) needs more pressure than a long one (about
      // 5).
      EXPECT_GT(breaking[0], 3.0 * breaking[1]);
      dynamic_short = breaking[0];
    }
  }
  EXPECT_GT(dynamic_short, 0.0);
}

}  // namespace
}  // namespace brisance::engine
