// sim/engine/prepare: builds the read-only Model from the scene and its body sources — world
// settings, one body per source (mass properties, hull, drag shape, panels, hold, initial
// motion), the charges, clearing distances, and the panel events in order of arrival.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <numbers>

#include "sim/engine/model.hpp"

namespace brisance::engine {

namespace {

dynamics::Integrator to_dynamics(scene::Integrator integrator) {
  switch (integrator) {
    case scene::Integrator::explicit_euler:
      return dynamics::Integrator::explicit_euler;
    case scene::Integrator::semi_implicit_euler:
      return dynamics::Integrator::semi_implicit_euler;
    case scene::Integrator::rk4:
      return dynamics::Integrator::rk4;
  }
  return dynamics::Integrator::semi_implicit_euler;
}

// Flight-drag area from the body's panels: faces with equal or opposite normals merged; more
// than 16 faces: the mean projected area.
dynamics::DragShape drag_shape_from(const std::vector<geometry::Panel>& panels) {
  constexpr std::size_t kMaxFaces = 16;
  std::vector<Vec3> normals;
  std::vector<double> areas;
  double surface = 0.0;
  for (const geometry::Panel& panel : panels) {
    surface += panel.area_m2;
    bool merged = false;
    for (std::size_t i = 0; i < normals.size() && !merged; ++i) {
      if (std::abs(std::abs(normals[i].dot(panel.outward_normal)) - 1.0) < 1e-9) {
        areas[i] += 0.5 * panel.area_m2;
        merged = true;
      }
    }
    if (!merged) {
      normals.push_back(panel.outward_normal);
      areas.push_back(0.5 * panel.area_m2);
    }
  }
  dynamics::DragShape shape;
  if (normals.size() <= kMaxFaces)
    for (std::size_t i = 0; i < normals.size(); ++i)
      shape.add_face(normals[i], areas[i]);
  shape.mean_area_m2 = 0.25 * surface;  // Cauchy: mean projected area of a convex body
  return shape;
}

void prepare_world(const scene::Scene& scene, Model& model) {
  const scene::SimulationSpec& sim = scene.simulation;
  model.world.gravity_m_s2 = scene.environment.gravity_m_s2;
  model.world.air_density_kg_m3 = scene.environment.air_density_kg_m3;
  model.world.linear_damping_per_s = sim.linear_damping;
  model.world.angular_damping_per_s = sim.angular_damping;
  model.world.integrator = to_dynamics(sim.integrator);
  if (scene.environment.ground) {
    const scene::GroundSpec& g = *scene.environment.ground;
    model.ground = dynamics::Ground{g.height_m, g.friction, g.restitution};
  }
  model.load_options.shape = sim.pulse_shape;
  model.load_options.clearing = sim.clearing;
  model.rotation_factor = sim.rotation_factor;
  model.timing.duration_s = sim.duration_s;
  model.timing.frame_rate_hz = sim.frame_rate_hz;
  model.timing.time_step_s = sim.time_step_s;
  model.timing.tolerance = sim.tolerance;
  model.timing.sleep = sim.sleep;
  // Unset, body_substeps is on where it applies: semi-implicit Euler with collisions off (a
  // broken window over a ground: 29.6 k steps and 29.4 s without, 511 steps and 1.75 s with).
  const bool semi_implicit = sim.integrator == scene::Integrator::semi_implicit_euler;
  model.timing.body_substeps =
      sim.body_substeps.value_or(semi_implicit && sim.collisions == scene::CollisionMode::off);
  model.timing.turn_substeps =
      model.timing.body_substeps || (sim.collisions != scene::CollisionMode::off && semi_implicit);
  // The same turn per step as the adaptive step allows everyone (run.cpp, next_step).
  if (model.timing.turn_substeps)
    model.world.max_turn_per_substep_rad = 2.0 * std::sqrt(sim.tolerance);
  model.collisions = sim.collisions == scene::CollisionMode::on    ? Collisions::on
                     : sim.collisions == scene::CollisionMode::off ? Collisions::off
                                                                   : Collisions::automatic;
}

// One body from its source: mass properties, hull, drag shape and panels; its hold and how it
// starts (anchored, held, or falling).
void prepare_body(BodySource& source, double normal_force_n, bool standing, double gravity,
                  Model& model, Stats& stats, Checkpoint& checkpoint) {
  const auto index = static_cast<std::uint32_t>(model.bodies.size());
  // Fragments: the prism's mass properties in closed form (thesis §§6.3-6.4).
  const geometry::MassProperties& unit = source.unit_mass;
  const double density = source.mass_kg / unit.volume_m3;
  dynamics::BodyModel body;
  body.mass_kg = source.mass_kg;
  body.inverse_mass = 1.0 / source.mass_kg;
  dynamics::set_inertia(body, unit.inertia_kg_m2 * density);
  body.rotates = source.rotates;
  body.drag_coefficient = source.drag_coefficient;
  for (const Vec3& v : source.mesh.vertices) {
    checkpoint.tick(64);  // the search below makes a mesh of n vertices cost n^2 / 2
    const Vec3 p = v - unit.centre_of_mass;
    if (std::find(body.hull_points.begin(), body.hull_points.end(), p) == body.hull_points.end())
      body.hull_points.push_back(p);
    body.bounding_radius_m = std::max(body.bounding_radius_m, p.norm());
  }
  // Fragments are loaded on at least five panels per face (thesis §6.2); their drag shape
  // comes from their faces and side walls.
  const std::vector<geometry::Panel>& panels = source.load_panels;
  body.drag_shape = drag_shape_from(source.drag_panels.empty() ? panels : source.drag_panels);
  stats.panels += panels.size();
  stats.panels_merged += source.panels_merged;
  if (!source.anchored) {
    for (const geometry::Panel& panel : panels)
      model.panels.push_back(
          PanelModel{index, panel.centre - unit.centre_of_mass, panel.outward_normal, panel.area_m2,
                     panel.face_half_size_m, std::sqrt(panel.area_m2),
                     scene::is_sheltered(source.sheltered, panel.outward_normal)});
  }
  model.bodies.push_back(std::move(body));
  model.centre_of_mass.push_back(unit.centre_of_mass);
  dynamics::BodyState start;
  start.orientation = source.orientation.normalized();
  start.position = source.position + start.orientation * unit.centre_of_mass;
  model.initial_states.push_back(start);
  // A fragment is held by its own hold (the frame, the crack interlock) until the wave reaches
  // it, whatever its weight; other bodies by friction on what they rest on.
  const bool breakaway = source.breakaway_hold_n.has_value();
  const double hold = breakaway ? *source.breakaway_hold_n : source.friction * normal_force_n;
  model.hold_force_n.push_back(hold);
  Motion motion = Motion::held;
  if (source.anchored) {
    motion = Motion::anchored;
    ++stats.bodies_anchored;
  } else if (!breakaway && (hold <= 0.0 || !standing) && gravity > 0.0) {
    motion = Motion::awake;  // nothing holds it, or it stands on nothing: it falls from the start
  }
  model.initial_motion.push_back(motion);
  model.friction.push_back(source.friction);
  model.fragment.push_back(source.fragment ? 1 : 0);
  model.release_not_before_s.push_back(source.release_not_before_s);
  model.release_velocity_m_s.push_back(source.release_velocity_m_s);
  // Friction from the ground is the contact's job once the body moves; the hold's eq. 2.40
  // friction is for bodies resting on other bodies. A breakaway hold breaks once and for all.
  const bool on_ground = model.ground && world_box(source).min.y() <= model.ground->height_m + 5e-3;
  model.supported.push_back(!breakaway && motion == Motion::held && !on_ground);
}

// Events: every panel is loaded by every charge, on its front, its side or its rear (face by
// face, sim/blast/panel_load), except a sheltered panel facing away from the charge. A face
// against the ground or a neighbour is no exception: the wave reaches it from its edges, as it
// does a rear face, and opposite faces of a body in a wall or on the ground balance.
void prepare_events(const std::vector<BodySource>& sources, Model& model, Stats& stats,
                    Checkpoint& checkpoint) {
  // The radius of each charge as a sphere of TNT (1 600 kg/m³; the Kingery–Bulmash curves begin
  // near its surface, Z = 0.053).
  std::vector<double> charge_radius_m;
  for (const ChargeModel& charge : model.charges)
    charge_radius_m.push_back(
        std::cbrt(3.0 * charge.charge.tnt_equivalent_kg / (4.0 * std::numbers::pi * 1600.0)));
  // A panel at or beyond the distance a wave travels within the run (ChargeModel::reach_m) gets
  // no event from it (it would never start): no blast point is worked out for it (16 walls
  // 1 000 m apart, each reached by its own charge only, have 15 such (panel, charge) pairs to
  // every one reached).
  model.panel_beyond_reach.assign(model.panels.size(), 0);
  for (std::uint32_t p = 0; p < model.panels.size(); ++p) {
    checkpoint.tick(1024);
    const PanelModel& panel = model.panels[p];
    const BodySource& object = sources[panel.body];
    const Vec3 world_com = object.position + object.orientation * model.centre_of_mass[panel.body];
    const Vec3 centre = world_com + object.orientation * panel.centre;
    const Vec3 normal = object.orientation * panel.normal;
    bool sheltered_from_all = true;
    for (std::uint32_t c = 0; c < model.charges.size(); ++c) {
      const Vec3 d = centre - model.charges[c].position;
      const double distance = std::max(d.norm(), 1e-3);
      if (d.norm() < charge_radius_m[c]) ++model.panels_inside_charges;
      const blast::FaceKind kind = blast::face_kind(-normal.dot(d) / distance);
      if (panel.sheltered && kind != blast::FaceKind::front)
        continue;  // nothing reaches it from behind
      sheltered_from_all = false;
      if (distance >= model.charges[c].reach_m) {
        model.panel_beyond_reach[p] = 1;
        continue;
      }
      // Wholly shielded from this charge (thesis eq. 4.1 at f = 0): no load at all.
      if (!model.shielding.empty() &&
          (kind == blast::FaceKind::front
               ? model.shielding[c * model.panels.size() + p]
               : model.body_shielding[c * model.bodies.size() + panel.body]) <= 0.0f) {
        ++stats.panels_shielded;
        continue;
      }
      const blast::BlastPoint point = blast::blast_point(model.charges[c].charge, distance);
      model.events.push_back(PanelEvent{point.arrival_time_s, p, c});
    }
    if (sheltered_from_all) ++stats.panels_back_facing;
  }
  std::sort(model.events.begin(), model.events.end(), [](const PanelEvent& a, const PanelEvent& b) {
    if (a.arrival_time_s != b.arrival_time_s) return a.arrival_time_s < b.arrival_time_s;
    return a.panel != b.panel ? a.panel < b.panel : a.charge < b.charge;
  });
}

}  // namespace

Model prepare(const scene::Scene& scene, std::vector<BodySource>& sources,
              std::vector<BodyInfo>& bodies, Stats& stats, Checkpoint& checkpoint,
              double* shielding_wall_time_s) {
  Model model;
  prepare_world(scene, model);
  const double gravity = scene.environment.gravity_m_s2.norm();
  const std::vector<double> normal_force = supported_weights(sources, gravity);
  const std::optional<double> ground_height_m =
      model.ground ? std::optional(model.ground->height_m) : std::optional<double>();
  Footing feet = footing(sources, ground_height_m);
  checkpoint.poll();
  model.embedded_anchors = embedded_anchors(sources, ground_height_m, checkpoint);
  for (std::size_t b = 0; b < sources.size(); ++b) {
    checkpoint.tick(64);
    prepare_body(sources[b], normal_force[b], feet.standing[b], gravity, model, stats, checkpoint);
  }
  model.supports = std::move(feet.supports);

  for (const scene::ChargeSpec& spec : scene.charges) {
    const blast::Charge charge = blast_charge(spec);
    model.charges.push_back(ChargeModel{spec.position, charge,
                                        blast::wave_reach_m(charge, scene.simulation.duration_s)});
  }

  if (scene.simulation.clearing) {
    // Fragments keep the clearing distance their pane chose (their own edges, thesis §6.5, or
    // the pane's): their faces are coplanar and touch, but the sharing must not merge them.
    std::vector<double> own(model.panels.size());
    for (std::size_t p = 0; p < model.panels.size(); ++p)
      own[p] = model.panels[p].clearing_distance_m;
    share_clearing_across_surfaces(sources, model, checkpoint);
    for (std::size_t p = 0; p < model.panels.size(); ++p)
      if (model.fragment[model.panels[p].body]) model.panels[p].clearing_distance_m = own[p];
  }

  const auto shielding_start = std::chrono::steady_clock::now();
  prepare_shielding(scene.simulation, sources, model, stats, checkpoint);
  if (shielding_wall_time_s)
    *shielding_wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - shielding_start).count();
  prepare_events(sources, model, stats, checkpoint);
  checkpoint.poll();

  // The result's bodies, each with its mesh (moved out of its source: prepare is done with it).
  bodies.reserve(sources.size());
  for (std::size_t b = 0; b < sources.size(); ++b) {
    BodyInfo info;
    info.name = std::move(sources[b].name);
    info.material = std::move(sources[b].material);
    info.fragment = sources[b].fragment;
    info.mass_kg = sources[b].mass_kg;
    info.mesh = std::move(sources[b].mesh);
    info.initial_pose = origin_pose(model, b, model.initial_states[b]);
    bodies.push_back(std::move(info));
  }
  return model;
}

Pose origin_pose(const Model& model, std::size_t body, const dynamics::BodyState& state) {
  const Vec3 origin = state.position - state.orientation * model.centre_of_mass[body];
  Pose pose;
  pose.position = {origin.x(), origin.y(), origin.z()};
  pose.orientation = {state.orientation.x(), state.orientation.y(), state.orientation.z(),
                      state.orientation.w()};
  return pose;
}

}  // namespace brisance::engine
