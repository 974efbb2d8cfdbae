#include "sim/engine/simulator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <map>
#include <optional>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/panel_load.hpp"
#include "sim/blast/reflection.hpp"
#include "sim/dynamics/rigid_body.hpp"
#include "sim/engine/panes.hpp"
#include "sim/geometry/mesh.hpp"

namespace brisance::engine {

namespace {

using dynamics::Mat3;
using dynamics::Quat;
using dynamics::Vec3;

enum class Motion : std::uint8_t {
  anchored,  // never moves
  held,      // resting, held by friction until its load beats mu N (thesis §3.6)
  awake,     // integrated every step
  asleep,    // came to rest on the ground; woken by a new load
};

// A panel in its body's frame, relative to the body's centre of mass.
struct PanelModel {
  std::uint32_t body;
  Vec3 centre;
  Vec3 normal;  // outward, unit
  double area_m2;
  double clearing_distance_m;
};

struct ChargeModel {
  Vec3 position;
  blast::Charge charge;
};

// The wave of one charge reaching one panel (thesis §3.5.3). The arrival time comes from the
// Kingery–Bulmash fit at the panel's starting distance rather than from integrating U.
struct PanelEvent {
  double arrival_time_s;
  std::uint32_t panel;
  std::uint32_t charge;
};

// Everything that does not change while stepping (STYLE.md §1).
struct Model {
  std::vector<dynamics::BodyModel> bodies;
  std::vector<Vec3> centre_of_mass;  // shape frame: from the shape's origin to the centre of mass
  std::vector<double> hold_force_n;  // mu N, N: own weight plus the weight resting on it
  std::vector<std::uint8_t>
      supported;  // held on other bodies: friction resists its loads (eq. 2.40)
  std::vector<Motion> initial_motion;
  // Fragments of broken panes (thesis §6.7): per body, the index into `fragments` or -1, and
  // the earliest time it may break free (the wave's arrival at its centroid; 0 for others).
  std::vector<std::int32_t> fragment_of;
  std::vector<double> release_not_before_s;
  std::vector<PanelModel> panels;
  std::vector<ChargeModel> charges;
  std::vector<PanelEvent> events;  // ascending arrival time
  dynamics::WorldSettings world;
  std::optional<dynamics::Ground> ground;
  blast::PanelLoadOptions load_options;
  double rotation_factor = 1.0;
  const scene::SimulationSpec* simulation = nullptr;
};

struct ActiveLoad {
  std::uint32_t panel;
  double arrival_time_s;
  blast::PressureHistory history;  // net translatory pressure, Pa, time since arrival
};

class WarningLog {
 public:
  void add(const std::string& code, const std::string& message, std::uint64_t count = 1) {
    auto [it, inserted] = warnings_.try_emplace(code, Warning{code, message, 0});
    it->second.count += count;
  }
  std::vector<Warning> list() const {
    std::vector<Warning> out;
    for (const auto& [code, warning] : warnings_)
      out.push_back(warning);
    return out;
  }

 private:
  std::map<std::string, Warning> warnings_;
};

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

// World-axis bounding box of a body at its starting pose.
struct Box {
  Vec3 min;
  Vec3 max;
};

Box world_box(const scene::ObjectSpec& object) {
  Box box{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};
  for (const Vec3& v : object.mesh.vertices) {
    const Vec3 p = object.position + object.orientation * v;
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

// The normal force each body presses down with at the start: its own weight plus the share of
// every body resting on it (thesis §3.6: "bricks high on the wall experience less friction ...
// lower bricks have more resistance"). A body rests on another if its bottom lies within 5 mm of
// the other's top and their footprints overlap; its load is split between its supports in
// proportion to the overlap areas. Loads are static: a body keeps its hold when the bodies above
// it are blown off.
std::vector<double> supported_weights(const scene::Scene& scene, double gravity) {
  constexpr double kContactGap_m = 5e-3;
  const std::size_t n = scene.objects.size();
  std::vector<Box> boxes(n);
  for (std::size_t i = 0; i < n; ++i)
    boxes[i] = world_box(scene.objects[i]);
  // Bodies by the height of their top, to find the supports of each bottom quickly.
  std::vector<std::size_t> by_top(n);
  for (std::size_t i = 0; i < n; ++i)
    by_top[i] = i;
  std::sort(by_top.begin(), by_top.end(),
            [&](std::size_t a, std::size_t b) { return boxes[a].max.y() < boxes[b].max.y(); });
  // Highest bottoms first, so a body's load is complete before it is passed down.
  std::vector<std::size_t> by_bottom = by_top;
  std::sort(by_bottom.begin(), by_bottom.end(),
            [&](std::size_t a, std::size_t b) { return boxes[a].min.y() > boxes[b].min.y(); });
  std::vector<double> weight(n);
  for (std::size_t i = 0; i < n; ++i)
    weight[i] = scene.objects[i].mass_kg * gravity;
  std::vector<std::pair<std::size_t, double>> supports;
  for (std::size_t body : by_bottom) {
    const Box& a = boxes[body];
    auto first = std::lower_bound(by_top.begin(), by_top.end(), a.min.y() - kContactGap_m,
                                  [&](std::size_t j, double y) { return boxes[j].max.y() < y; });
    supports.clear();
    double total = 0.0;
    for (auto it = first; it != by_top.end() && boxes[*it].max.y() <= a.min.y() + kContactGap_m;
         ++it) {
      if (*it == body) continue;
      const Box& b = boxes[*it];
      const double dx = std::min(a.max.x(), b.max.x()) - std::max(a.min.x(), b.min.x());
      const double dz = std::min(a.max.z(), b.max.z()) - std::max(a.min.z(), b.min.z());
      if (dx <= 0.0 || dz <= 0.0) continue;
      supports.emplace_back(*it, dx * dz);
      total += dx * dz;
    }
    for (const auto& [support, overlap] : supports)
      weight[support] += weight[body] * overlap / total;
  }
  return weight;
}

// Clearing (thesis eq. 2.31) relieves a front face from the free edges of the surface it lies
// in. Bricks in a wall share one front surface, so a brick's own 15 cm face is not what clears:
// the wall's is. Panels in the same plane (normals within 1e-6, offsets within 1 mm) on bodies
// that touch (bounding boxes within 5 mm) form one surface; each panel's clearing distance S
// becomes half the smaller in-plane extent of its surface (never less than its own face's).
void share_clearing_across_surfaces(const scene::Scene& scene, Model& model) {
  constexpr double kPlaneGap_m = 1e-3;
  constexpr double kTouchGap_m = 5e-3;
  const std::size_t n = model.panels.size();
  std::vector<Box> boxes;
  for (const scene::ObjectSpec& object : scene.objects)
    boxes.push_back(world_box(object));
  struct WorldPanel {
    Vec3 centre;
    Vec3 normal;
    double offset;
  };
  std::vector<WorldPanel> world(n);
  for (std::size_t p = 0; p < n; ++p) {
    const PanelModel& panel = model.panels[p];
    const scene::ObjectSpec& object = scene.objects[panel.body];
    const Quat q = object.orientation.normalized();
    const Vec3 com = object.position + q * model.centre_of_mass[panel.body];
    world[p].centre = com + q * panel.centre;
    world[p].normal = q * panel.normal;
    world[p].offset = world[p].normal.dot(world[p].centre);
  }
  // Union-find over panels: same plane and touching bodies.
  std::vector<std::size_t> parent(n);
  for (std::size_t p = 0; p < n; ++p)
    parent[p] = p;
  auto find = [&](std::size_t p) {
    while (parent[p] != p)
      p = parent[p] = parent[parent[p]];
    return p;
  };
  auto touching = [&](std::uint32_t a, std::uint32_t b) {
    const Box& x = boxes[a];
    const Box& y = boxes[b];
    return (x.min.array() <= y.max.array() + kTouchGap_m).all() &&
           (y.min.array() <= x.max.array() + kTouchGap_m).all();
  };
  // Pairs of panels in one plane, on one body or on two touching bodies. Each body's panels
  // (contiguous in model.panels) sorted by plane offset keep the search to panels that can share
  // a plane, and touching pairs of bodies come from a sweep along x, so a scene of many separate
  // bodies costs n log n rather than (panels in one plane)^2.
  const std::size_t bodies = boxes.size();
  std::vector<std::size_t> sorted(n);
  std::vector<std::size_t> first(bodies + 1, 0);  // body b: sorted[first[b] .. first[b + 1])
  for (std::size_t p = 0; p < n; ++p)
    ++first[model.panels[p].body + 1];
  for (std::size_t b = 0; b < bodies; ++b)
    first[b + 1] += first[b];
  for (std::size_t p = 0; p < n; ++p)
    sorted[p] = p;  // panels are stored body by body
  auto by_offset = [&](std::size_t a, std::size_t b) { return world[a].offset < world[b].offset; };
  for (std::size_t b = 0; b < bodies; ++b)
    std::sort(sorted.begin() + static_cast<std::ptrdiff_t>(first[b]),
              sorted.begin() + static_cast<std::ptrdiff_t>(first[b + 1]), by_offset);
  auto join_if_coplanar = [&](std::size_t a, std::size_t b) {
    if (world[a].normal.dot(world[b].normal) >= 1.0 - 1e-12) parent[find(a)] = find(b);
  };
  for (std::size_t b = 0; b < bodies; ++b)
    for (std::size_t i = first[b]; i < first[b + 1]; ++i)
      for (std::size_t j = i + 1;
           j < first[b + 1] && world[sorted[j]].offset - world[sorted[i]].offset <= kPlaneGap_m;
           ++j)
        join_if_coplanar(sorted[i], sorted[j]);
  auto join_bodies = [&](std::size_t body_a, std::size_t body_b) {
    const auto begin = sorted.begin() + static_cast<std::ptrdiff_t>(first[body_b]);
    const auto end = sorted.begin() + static_cast<std::ptrdiff_t>(first[body_b + 1]);
    for (std::size_t i = first[body_a]; i < first[body_a + 1]; ++i) {
      const std::size_t a = sorted[i];
      auto j = std::lower_bound(begin, end, world[a].offset - kPlaneGap_m,
                                [&](std::size_t q, double x) { return world[q].offset < x; });
      for (; j != end && world[*j].offset - world[a].offset <= kPlaneGap_m; ++j)
        join_if_coplanar(a, *j);
    }
  };
  std::vector<std::size_t> by_min_x(bodies);
  for (std::size_t b = 0; b < bodies; ++b)
    by_min_x[b] = b;
  std::sort(by_min_x.begin(), by_min_x.end(),
            [&](std::size_t a, std::size_t b) { return boxes[a].min.x() < boxes[b].min.x(); });
  for (std::size_t i = 0; i < bodies; ++i) {
    const std::size_t a = by_min_x[i];
    if (first[a] == first[a + 1]) continue;  // no panels (anchored)
    for (std::size_t j = i + 1;
         j < bodies && boxes[by_min_x[j]].min.x() <= boxes[a].max.x() + kTouchGap_m; ++j) {
      const std::size_t b = by_min_x[j];
      if (first[b] != first[b + 1] &&
          touching(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)))
        join_bodies(a, b);
    }
  }
  // In-plane extents of each surface, from the vertices of its bodies that lie in its plane:
  // along the plane's horizontal axis and the one across it (for a vertical wall: its width and
  // its height).
  struct Surface {
    Vec3 normal;
    double offset;
    std::vector<std::uint32_t> bodies;
  };
  std::map<std::size_t, Surface> surfaces;
  for (std::size_t p = 0; p < n; ++p) {
    Surface& surface = surfaces[find(p)];
    surface.normal = world[p].normal;
    surface.offset = world[p].offset;
    if (std::find(surface.bodies.begin(), surface.bodies.end(), model.panels[p].body) ==
        surface.bodies.end())
      surface.bodies.push_back(model.panels[p].body);
  }
  std::map<std::size_t, double> half_size;
  for (const auto& [root, surface] : surfaces) {
    Vec3 u = Vec3::UnitY().cross(surface.normal);
    if (u.norm() < 1e-6) u = Vec3::UnitX().cross(surface.normal);
    u.normalize();
    const Vec3 v = surface.normal.cross(u);
    double min_u = INFINITY, max_u = -INFINITY, min_v = INFINITY, max_v = -INFINITY;
    for (std::uint32_t body : surface.bodies) {
      const scene::ObjectSpec& object = scene.objects[body];
      for (const Vec3& vertex : object.mesh.vertices) {
        const Vec3 x = object.position + object.orientation * vertex;
        if (std::abs(surface.normal.dot(x) - surface.offset) > kPlaneGap_m) continue;
        min_u = std::min(min_u, u.dot(x)), max_u = std::max(max_u, u.dot(x));
        min_v = std::min(min_v, v.dot(x)), max_v = std::max(max_v, v.dot(x));
      }
    }
    half_size[root] = max_u > min_u ? 0.5 * std::min(max_u - min_u, max_v - min_v) : 0.0;
  }
  for (std::size_t p = 0; p < n; ++p)
    model.panels[p].clearing_distance_m =
        std::max(model.panels[p].clearing_distance_m, half_size[find(p)]);
}

Model prepare(const scene::Scene& scene, const BrokenScene& broken, Stats& stats) {
  Model model;
  const scene::SimulationSpec& sim = scene.simulation;
  model.simulation = &scene.simulation;
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
  const double gravity = scene.environment.gravity_m_s2.norm();
  const std::vector<double> normal_force = supported_weights(scene, gravity);

  for (const scene::ObjectSpec& object : scene.objects) {
    const auto index = static_cast<std::uint32_t>(model.bodies.size());
    const std::int32_t fragment_index = broken.changed ? broken.fragment_of[index] : -1;
    const FragmentBody* fragment =
        fragment_index >= 0 ? &broken.fragments[static_cast<std::size_t>(fragment_index)] : nullptr;
    // Fragments: the prism's mass properties in closed form (thesis §§6.3-6.4).
    const geometry::MassProperties unit =
        fragment ? fragment->unit_mass : geometry::mass_properties(object.mesh, 1.0);
    const double density = object.mass_kg / unit.volume_m3;
    dynamics::BodyModel body;
    body.mass_kg = object.mass_kg;
    body.inverse_mass = 1.0 / object.mass_kg;
    dynamics::set_inertia(body, unit.inertia_kg_m2 * density);
    body.rotates = object.rotates;
    body.drag_coefficient = object.drag_coefficient;
    for (const Vec3& v : object.mesh.vertices) {
      const Vec3 p = v - unit.centre_of_mass;
      if (std::find(body.hull_points.begin(), body.hull_points.end(), p) == body.hull_points.end())
        body.hull_points.push_back(p);
      body.bounding_radius_m = std::max(body.bounding_radius_m, p.norm());
    }
    // Fragments are loaded on at least five panels per face (thesis §6.2); their drag shape
    // comes from their faces and side walls.
    const std::vector<geometry::Panel> panels =
        fragment ? fragment->load_panels
                 : geometry::make_panels(object.mesh, sim.max_panel_area_m2);
    body.drag_shape = drag_shape_from(fragment ? fragment->drag_panels : panels);
    stats.panels += panels.size();
    if (!object.anchored) {
      for (const geometry::Panel& panel : panels)
        model.panels.push_back(PanelModel{index, panel.centre - unit.centre_of_mass,
                                          panel.outward_normal, panel.area_m2,
                                          panel.face_half_size_m});
    }
    model.bodies.push_back(std::move(body));
    model.centre_of_mass.push_back(unit.centre_of_mass);
    // A fragment is held by its own hold (the frame, the crack interlock) until the wave reaches
    // it, whatever its weight; other bodies by friction on what they rest on.
    const double hold = fragment ? fragment->hold_n : object.friction * normal_force[index];
    model.hold_force_n.push_back(hold);
    Motion motion = Motion::held;
    if (object.anchored) {
      motion = Motion::anchored;
      ++stats.bodies_anchored;
    } else if (!fragment && hold <= 0.0 && gravity > 0.0) {
      motion = Motion::awake;  // nothing holds it: it falls from the start
    }
    model.initial_motion.push_back(motion);
    model.fragment_of.push_back(fragment_index);
    model.release_not_before_s.push_back(fragment ? fragment->arrival_time_s : 0.0);
    // Friction from the ground is the contact's job once the body moves; the hold's eq. 2.40
    // friction is for bodies resting on other bodies. A fragment's hold breaks once and for all.
    const bool on_ground =
        model.ground && world_box(object).min.y() <= model.ground->height_m + 5e-3;
    model.supported.push_back(!fragment && motion == Motion::held && !on_ground);
  }

  for (const scene::ChargeSpec& charge : scene.charges) {
    blast::Charge c;
    c.tnt_equivalent_kg = charge.mass_kg * charge.tnt_factor;
    c.burst = charge.burst;
    c.surface_model = charge.surface_model;
    model.charges.push_back(ChargeModel{charge.position, c});
  }

  if (sim.clearing) {
    // Fragments keep the clearing distance their pane chose (their own edges, thesis §6.5, or
    // the pane's): their faces are coplanar and touch, but the sharing must not merge them.
    std::vector<double> own(model.panels.size());
    for (std::size_t p = 0; p < model.panels.size(); ++p)
      own[p] = model.panels[p].clearing_distance_m;
    share_clearing_across_surfaces(scene, model);
    for (std::size_t p = 0; p < model.panels.size(); ++p)
      if (model.fragment_of[model.panels[p].body] >= 0)
        model.panels[p].clearing_distance_m = own[p];
  }

  // Events: every panel that faces a charge; a panel facing none is never loaded.
  for (std::uint32_t p = 0; p < model.panels.size(); ++p) {
    const PanelModel& panel = model.panels[p];
    const scene::ObjectSpec& object = scene.objects[panel.body];
    const Vec3 world_com = object.position + object.orientation * model.centre_of_mass[panel.body];
    const Vec3 centre = world_com + object.orientation * panel.centre;
    const Vec3 normal = object.orientation * panel.normal;
    bool facing_any = false;
    for (std::uint32_t c = 0; c < model.charges.size(); ++c) {
      const Vec3 d = centre - model.charges[c].position;
      const double distance = std::max(d.norm(), 1e-3);
      if (normal.dot(d) >= 0.0) continue;  // back-facing (thesis §3.2.1: front panels only)
      facing_any = true;
      const blast::BlastPoint point = blast::blast_point(model.charges[c].charge, distance);
      model.events.push_back(PanelEvent{point.arrival_time_s, p, c});
    }
    if (!facing_any) ++stats.panels_back_facing;
  }
  std::sort(model.events.begin(), model.events.end(), [](const PanelEvent& a, const PanelEvent& b) {
    if (a.arrival_time_s != b.arrival_time_s) return a.arrival_time_s < b.arrival_time_s;
    return a.panel != b.panel ? a.panel < b.panel : a.charge < b.charge;
  });
  return model;
}

engine::Pose origin_pose(const Model& model, std::size_t body, const dynamics::BodyState& state) {
  const Vec3 origin = state.position - state.orientation * model.centre_of_mass[body];
  engine::Pose pose;
  pose.position = {origin.x(), origin.y(), origin.z()};
  pose.orientation = {state.orientation.x(), state.orientation.y(), state.orientation.z(),
                      state.orientation.w()};
  return pose;
}

// A sum of finite numbers is finite unless it overflows (beyond 1e308: no state of a body),
// and a NaN or an infinity in any term makes it NaN or infinite: one test instead of thirteen.
bool finite(const dynamics::BodyState& s) {
  return std::isfinite(s.position.sum() + s.velocity.sum() + s.orientation.coeffs().sum() +
                       s.angular_momentum.sum());
}

// The stepping loop and its mutable state.
class Run {
 public:
  Run(const scene::Scene& scene, const Model& model, Result& result, WarningLog& warnings)
      : scene_(scene), model_(model), result_(result), warnings_(warnings) {}

  bool execute(const RunHooks& hooks);
  const std::vector<double>& release_times_s() const { return release_time_s_; }
  const std::vector<double>& launch_speeds_m_s() const { return launch_speed_m_s_; }
  double speed_m_s(std::size_t body) const { return states_[body].velocity.norm(); }

 private:
  void activate(const PanelEvent& event);
  void apply_loads(double t0, double t1);
  void release_held(double t0, double t1);
  void integrate_awake(double dt);
  double next_step(double t, double until) const;
  void record_frame();

  const scene::Scene& scene_;
  const Model& model_;
  Result& result_;
  WarningLog& warnings_;

  std::vector<dynamics::BodyState> states_;
  std::vector<Motion> motion_;
  std::vector<double> rest_time_s_;
  std::vector<dynamics::ContactMemory> contacts_;  // per body, for warm-started ground contact
  std::vector<std::uint8_t> moved_;
  std::vector<std::uint8_t> panel_loaded_;
  std::vector<dynamics::StepLoads> loads_;
  std::vector<std::uint32_t> loaded_bodies_;  // bodies with nonzero loads this step
  std::vector<std::uint8_t> is_loaded_;
  // Per loaded body this step: the sum of its panels' force vectors at their largest (the start
  // of the step, or the wave's arrival within it: every pulse decays from its front), N, and
  // the time from which any load acted, s. The hold is judged on these, so whether a body is
  // released does not depend on the step size.
  std::vector<Vec3> peak_force_;
  std::vector<double> loaded_from_s_;
  // Fragments: when each broke free and its speed once its blast load ended (launch), or -1.
  std::vector<double> release_time_s_;
  std::vector<double> launch_speed_m_s_;
  std::vector<ActiveLoad> active_;
  std::size_t next_event_ = 0;
  std::vector<std::uint32_t> candidates_;      // bodies that may move (all but anchored)
  std::vector<engine::Pose> candidate_poses_;  // frame-major over candidates_
  // Step-size limits gathered while integrating, used for the next step.
  double max_angular_speed_ = 0.0;
  double min_contact_time_s_ = INFINITY;
  double min_active_duration_s_ = INFINITY;
};

void Run::activate(const PanelEvent& event) {
  const PanelModel& panel = model_.panels[event.panel];
  const dynamics::BodyState& state = states_[panel.body];
  const ChargeModel& charge = model_.charges[event.charge];
  const Vec3 centre = state.position + state.orientation * panel.centre;
  const Vec3 normal = state.orientation * panel.normal;
  const Vec3 d = centre - charge.position;
  const double distance = std::max(d.norm(), 1e-3);
  const double cos_incidence = -normal.dot(d) / distance;
  if (cos_incidence <= 0.0) return;  // turned away since the run began
  const blast::BlastPoint point = blast::blast_point(charge.charge, distance);
  const double angle = std::acos(std::min(1.0, cos_incidence));
  const blast::ObliqueReflection reflection = blast::oblique_reflection(
      point.incident_overpressure_pa, point.incident_impulse_pa_s, point.reflected_overpressure_pa,
      point.reflected_impulse_pa_s, angle);
  if (!point.in_validity_range)
    warnings_.add("blast_out_of_range",
                  "a panel lies outside the Kingery-Bulmash fitted range (Z 0.05-40 m/kg^(1/3)); "
                  "its load is continued from the range's end (see docs/blast-model.md)");
  if (!reflection.in_chart_range)
    warnings_.add("reflection_out_of_chart",
                  "a panel's incident overpressure lies outside the reflection chart "
                  "(1.4 kPa - 34.5 MPa); the nearest chart curve was used");
  blast::PanelWave wave;
  wave.incident_overpressure_pa = point.incident_overpressure_pa;
  wave.incident_impulse_pa_s = point.incident_impulse_pa_s;
  wave.positive_duration_s = point.positive_duration_s;
  wave.shock_velocity_m_s = point.shock_velocity_m_s;
  wave.dynamic_pressure_pa = point.dynamic_pressure_pa;
  wave.reflected_overpressure_pa = reflection.overpressure_pa;
  wave.reflected_impulse_pa_s = reflection.impulse_pa_s;
  wave.cos_incidence = cos_incidence;
  blast::PanelLoadOptions options = model_.load_options;
  options.clearing_distance_m = panel.clearing_distance_m;
  options.drag_coefficient = model_.bodies[panel.body].drag_coefficient;
  active_.push_back(
      ActiveLoad{event.panel, event.arrival_time_s, blast::net_translatory_history(wave, options)});
  panel_loaded_[event.panel] = 1;
}

void Run::apply_loads(double t0, double t1) {
  const bool moments = model_.world.integrator == dynamics::Integrator::rk4;
  std::size_t kept = 0;
  min_active_duration_s_ = INFINITY;
  for (std::size_t i = 0; i < active_.size(); ++i) {
    const ActiveLoad& load = active_[i];
    const PanelModel& panel = model_.panels[load.panel];
    const double a = t0 - load.arrival_time_s;
    const double b = t1 - load.arrival_time_s;
    const double impulse = load.history.impulse_pa_s(a, b) * panel.area_m2;
    if (impulse != 0.0 && motion_[panel.body] != Motion::anchored) {
      const dynamics::BodyState& state = states_[panel.body];
      const Vec3 push = -(state.orientation * panel.normal);  // pressure acts inward
      const Vec3 arm = state.orientation * panel.centre;
      dynamics::StepLoads& body = loads_[panel.body];
      body.impulse += impulse * push;
      body.angular_impulse += model_.rotation_factor * arm.cross(impulse * push);
      if (moments) body.impulse_moment += load.history.moment_pa_s2(a, b) * panel.area_m2 * push;
      const double from = std::max(a, 0.0);
      if (!is_loaded_[panel.body]) {
        is_loaded_[panel.body] = 1;
        loaded_bodies_.push_back(panel.body);
        peak_force_[panel.body].setZero();
        loaded_from_s_[panel.body] = t1;
      }
      peak_force_[panel.body] += load.history.pressure_pa(from) * panel.area_m2 * push;
      loaded_from_s_[panel.body] = std::min(loaded_from_s_[panel.body], load.arrival_time_s + from);
    }
    if (b < load.history.end_s()) {
      min_active_duration_s_ = std::min(min_active_duration_s_, load.history.end_s());
      active_[kept++] = std::move(active_[i]);
    }
  }
  active_.resize(kept);
}

void Run::release_held(double t0, double t1) {
  for (std::uint32_t body : loaded_bodies_) {
    if (motion_[body] == Motion::asleep) {
      motion_[body] = Motion::awake;  // a later wave wakes a resting body
      rest_time_s_[body] = 0.0;
    }
    const double hold = model_.hold_force_n[body];  // mu N, N
    dynamics::StepLoads& loads = loads_[body];
    if (motion_[body] == Motion::held) {
      // A fragment breaks free once the wave has reached its centroid and its load beats its
      // hold (thesis §6.7); the loads of its panels reached earlier are taken by the hold.
      const double not_before = model_.release_not_before_s[body];
      if (t1 < not_before || peak_force_[body].norm() <= hold) {
        loads = dynamics::StepLoads{};  // static friction takes the whole load
        continue;
      }
      motion_[body] = Motion::awake;
      if (model_.fragment_of[body] >= 0) release_time_s_[body] = std::max(t0, not_before);
    }
    // Thesis eq. 2.40, M x'' + R = F(t) with R = mu N: while the wave pushes a body off its
    // support, friction takes mu N of the push from the load's arrival on, so the body gains the
    // integral of (F - mu N). The push keeps its lever arm, so torque scales the same way.
    const double magnitude = loads.impulse.norm();
    if (model_.supported[body] && magnitude > 0.0) {
      const double resistance = hold * (t1 - loaded_from_s_[body]);
      const double keep = std::max(0.0, magnitude - resistance) / magnitude;
      loads.impulse *= keep;
      loads.angular_impulse *= keep;
      loads.impulse_moment *= keep;
    }
  }
}

void Run::integrate_awake(double dt) {
  constexpr double kRestSpeed_m_s = 0.05;
  constexpr double kRestAngularSpeed_rad_s = 0.1;
  constexpr double kRestTime_s = 0.5;
  const bool may_sleep = model_.simulation->sleep && model_.ground.has_value();
  double max_angular_squared = 0.0;
  std::uint64_t body_steps = 0;
  min_contact_time_s_ = INFINITY;
  for (std::uint32_t b = 0; b < states_.size(); ++b) {
    if (motion_[b] != Motion::awake) continue;
    const dynamics::BodyModel& body = model_.bodies[b];
    dynamics::BodyState& state = states_[b];
    const dynamics::BodyState before = state;
    // Most bodies carry no load: their step does not read loads_ (72 bytes a body).
    static const dynamics::StepLoads kNoLoads{};
    const Vec3 omega =
        dynamics::integrate(body, state, is_loaded_[b] ? loads_[b] : kNoLoads, model_.world, dt);
    bool touching = false;
    if (model_.ground)
      touching = dynamics::resolve_ground_contact(body, state, *model_.ground, &contacts_[b]);
    if (!finite(state)) {
      state = before;
      motion_[b] = Motion::asleep;
      warnings_.add("non_finite_state",
                    "a body's state became non-finite (NaN or infinity); it was frozen at its last "
                    "finite state");
      continue;
    }
    moved_[b] = 1;
    ++body_steps;
    if (!is_loaded_[b] && launch_speed_m_s_[b] < 0.0 && model_.fragment_of[b] >= 0)
      launch_speed_m_s_[b] = state.velocity.norm();
    // Squared speeds, roots only where needed: the largest root is the root of the largest.
    const double angular_squared = omega.squaredNorm();
    if (!model_.ground) {
      max_angular_squared = std::max(max_angular_squared, angular_squared);
      continue;
    }
    const double speed = state.velocity.norm();
    if (may_sleep && touching && speed < kRestSpeed_m_s &&
        std::sqrt(angular_squared) < kRestAngularSpeed_rad_s) {
      rest_time_s_[b] += dt;
      if (rest_time_s_[b] >= kRestTime_s) {
        motion_[b] = Motion::asleep;
        state.velocity.setZero();
        state.angular_momentum.setZero();
        ++result_.stats.bodies_slept;
        continue;
      }
    } else {
      rest_time_s_[b] = 0.0;
    }
    max_angular_squared = std::max(max_angular_squared, angular_squared);
    // A body that can reach the ground within a coarse step must take steps of a fraction of
    // its size, so contact is found before it sinks far in.
    if (speed > 0.0) {
      const double clearance =
          state.position.y() - body.bounding_radius_m - model_.ground->height_m;
      if (clearance < speed * 0.01)
        min_contact_time_s_ = std::min(min_contact_time_s_, body.bounding_radius_m / speed);
    }
  }
  result_.stats.body_steps += body_steps;
  max_angular_speed_ = std::sqrt(max_angular_squared);
  for (std::uint32_t b : loaded_bodies_) {
    loads_[b] = dynamics::StepLoads{};
    is_loaded_[b] = 0;
  }
  loaded_bodies_.clear();
}

double Run::next_step(double t, double until) const {
  const scene::SimulationSpec& sim = *model_.simulation;
  if (sim.time_step_s) return std::min(*sim.time_step_s, until - t);
  const bool busy =
      !active_.empty() || std::find(motion_.begin(), motion_.end(), Motion::awake) != motion_.end();
  if (!busy) {
    // Nothing moves: jump to the next frame or the next arrival.
    double next = until;
    if (next_event_ < model_.events.size())
      next = std::min(next, std::max(model_.events[next_event_].arrival_time_s, t + 1e-9));
    return next - t;
  }
  // The adaptive step: a fraction sqrt(tolerance) of every time scale in play — at tolerance
  // 1e-3, 3 % of the shortest active pulse, 0.06 rad of turn, a third of the time a body near
  // the ground takes to cross its own size, and 9.5 ms at most.
  const double fraction = std::sqrt(sim.tolerance);
  double dt = std::min(1.0 / sim.frame_rate_hz, 0.3 * fraction);
  if (min_active_duration_s_ < INFINITY) dt = std::min(dt, fraction * min_active_duration_s_);
  if (max_angular_speed_ > 0.0) dt = std::min(dt, 2.0 * fraction / max_angular_speed_);
  if (min_contact_time_s_ < INFINITY) dt = std::min(dt, 10.0 * fraction * min_contact_time_s_);
  if (next_event_ < model_.events.size() && active_.empty()) {
    // Land the first step of a wave on its arrival.
    const double arrival = model_.events[next_event_].arrival_time_s;
    if (arrival > t) dt = std::min(dt, arrival - t);
  }
  return std::clamp(dt, std::min(1e-6, until - t), until - t);
}

void Run::record_frame() {
  for (std::uint32_t body : candidates_)
    candidate_poses_.push_back(origin_pose(model_, body, states_[body]));
}

bool Run::execute(const RunHooks& hooks) {
  const scene::SimulationSpec& sim = *model_.simulation;
  const std::size_t bodies = model_.bodies.size();
  states_.resize(bodies);
  for (std::size_t b = 0; b < bodies; ++b) {
    const scene::ObjectSpec& object = scene_.objects[b];
    states_[b].orientation = object.orientation.normalized();
    states_[b].position = object.position + states_[b].orientation * model_.centre_of_mass[b];
  }
  motion_ = model_.initial_motion;
  rest_time_s_.assign(bodies, 0.0);
  contacts_.assign(bodies, dynamics::ContactMemory{});
  moved_.assign(bodies, 0);
  is_loaded_.assign(bodies, 0);
  peak_force_.assign(bodies, Vec3::Zero());
  loaded_from_s_.assign(bodies, 0.0);
  loads_.assign(bodies, dynamics::StepLoads{});
  release_time_s_.assign(bodies, -1.0);
  launch_speed_m_s_.assign(bodies, -1.0);
  panel_loaded_.assign(model_.panels.size(), 0);
  for (std::uint32_t b = 0; b < bodies; ++b)
    if (motion_[b] != Motion::anchored) candidates_.push_back(b);

  const auto frame_count =
      static_cast<std::size_t>(std::floor(sim.duration_s * sim.frame_rate_hz + 1e-9)) + 1;
  result_.frame_times_s.reserve(frame_count);
  candidate_poses_.reserve(frame_count * candidates_.size());
  result_.frame_times_s.push_back(0.0);
  record_frame();

  double t = 0.0;
  std::size_t frame = 1;
  int progress_reported = 0;
  while (t < sim.duration_s) {
    if (hooks.cancel_requested && hooks.cancel_requested()) return false;
    const double frame_time =
        frame < frame_count ? static_cast<double>(frame) / sim.frame_rate_hz : sim.duration_s;
    double dt = next_step(t, frame_time);
    double t1 = t + dt;
    if (frame_time - t1 <= 1e-12 * std::max(1.0, frame_time)) t1 = frame_time;
    dt = t1 - t;
    if (dt <= 0.0) break;

    while (next_event_ < model_.events.size() && model_.events[next_event_].arrival_time_s < t1)
      activate(model_.events[next_event_++]);
    apply_loads(t, t1);
    release_held(t, t1);
    integrate_awake(dt);
    ++result_.stats.steps;
    t = t1;

    if (t == frame_time && frame < frame_count) {
      result_.frame_times_s.push_back(frame_time);
      record_frame();
      ++frame;
    }
    if (hooks.progress) {
      const int percent = static_cast<int>(200.0 * t / sim.duration_s);
      if (percent > progress_reported) {
        progress_reported = percent;
        hooks.progress(std::min(1.0, t / sim.duration_s));
      }
    }
    // Everything at rest and no wave still to come: the remaining frames are the same.
    const bool quiet = active_.empty() && next_event_ == model_.events.size() &&
                       std::find(motion_.begin(), motion_.end(), Motion::awake) == motion_.end();
    if (quiet && t < sim.duration_s) {
      result_.stats.ended_early = true;
      for (; frame < frame_count; ++frame) {
        result_.frame_times_s.push_back(static_cast<double>(frame) / sim.frame_rate_hz);
        record_frame();
      }
      break;
    }
  }
  result_.stats.simulated_time_s = t;

  // Frames keep only the bodies that moved; the others are stored once (DESIGN.md decision 10).
  std::vector<std::size_t> kept;
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    if (moved_[candidates_[k]]) {
      kept.push_back(k);
      result_.animated.push_back(candidates_[k]);
    }
  }
  result_.poses.reserve(result_.frame_times_s.size() * kept.size());
  for (std::size_t f = 0; f < result_.frame_times_s.size(); ++f)
    for (std::size_t k : kept)
      result_.poses.push_back(candidate_poses_[f * candidates_.size() + k]);
  result_.stats.bodies_static_in_frames = bodies - result_.animated.size();

  for (std::size_t b = 0; b < bodies; ++b) {
    FinalState final_state;
    final_state.name = scene_.objects[b].name;
    final_state.pose = origin_pose(model_, b, states_[b]);
    const Vec3 v = states_[b].velocity;
    const Vec3 w = dynamics::angular_velocity(model_.bodies[b], states_[b]);
    final_state.linear_velocity_m_s = {v.x(), v.y(), v.z()};
    final_state.angular_velocity_rad_s = {w.x(), w.y(), w.z()};
    result_.final_state.push_back(std::move(final_state));
    if (motion_[b] == Motion::held) ++result_.stats.bodies_never_released;
  }
  std::vector<std::uint8_t> pending(model_.panels.size(), 0);
  for (std::size_t e = next_event_; e < model_.events.size(); ++e)
    pending[model_.events[e].panel] = !panel_loaded_[model_.events[e].panel];
  result_.stats.panels_not_reached =
      static_cast<std::uint64_t>(std::count(pending.begin(), pending.end(), 1));
  result_.stats.panels_loaded =
      static_cast<std::uint64_t>(std::count(panel_loaded_.begin(), panel_loaded_.end(), 1));
  return true;
}

Distribution distribution_of(std::vector<double> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  d.count = values.size();
  double sum = 0.0;
  for (double v : values)
    sum += v;
  d.mean = sum / static_cast<double>(values.size());
  // Nearest rank: the smallest value with at least p of the values at or below it.
  const auto rank = [&](double p) {
    const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(values.size())));
    return values[std::max<std::size_t>(k, 1) - 1];
  };
  d.min = values.front();
  d.p10 = rank(0.1);
  d.p50 = rank(0.5);
  d.p90 = rank(0.9);
  d.max = values.back();
  return d;
}

// Fragment statistics of every broken pane, once the run is over.
void report_fragments(const BrokenScene& broken, const Run& run, std::vector<PaneReport>& panes) {
  for (PaneReport& pane : panes) {
    if (!pane.broken) continue;
    std::vector<double> areas;
    std::vector<double> releases;
    std::vector<std::pair<double, double>> launched;  // area, launch speed
    for (std::uint32_t b = pane.first_body; b < pane.first_body + pane.fragment_count; ++b) {
      const FragmentBody& fragment =
          broken.fragments[static_cast<std::size_t>(broken.fragment_of[b])];
      areas.push_back(fragment.frontal_area_m2);
      const double release = run.release_times_s()[b];
      pane.release_times_s.push_back(release);
      if (release < 0.0) continue;
      releases.push_back(release);
      // Still loaded when the run ended: its speed then.
      const double launch = run.launch_speeds_m_s()[b];
      launched.emplace_back(fragment.frontal_area_m2, launch >= 0.0 ? launch : run.speed_m_s(b));
    }
    pane.released = releases.size();
    pane.frontal_area_m2 = distribution_of(std::move(areas));
    pane.release_time_s = distribution_of(std::move(releases));
    std::vector<double> speeds;
    for (const auto& [area, speed] : launched)
      speeds.push_back(speed);
    pane.launch_speed_m_s = distribution_of(std::move(speeds));
    std::sort(launched.begin(), launched.end());
    const std::size_t half = launched.size() / 2;
    double small = 0.0;
    double large = 0.0;
    for (std::size_t i = 0; i < launched.size(); ++i)
      (i < half ? small : large) += launched[i].second;
    if (half > 0) pane.launch_speed_smaller_half_m_s = small / static_cast<double>(half);
    if (launched.size() > half)
      pane.launch_speed_larger_half_m_s = large / static_cast<double>(launched.size() - half);
  }
}

}  // namespace

RunOutcome simulate(const scene::Scene& input_scene, const RunHooks& hooks) {
  const auto start = std::chrono::steady_clock::now();
  RunOutcome outcome;
  Result& result = outcome.result;
  WarningLog warnings;
  // Breakable panes first: a broken pane is replaced by its fragments (DESIGN.md decision 9).
  const BrokenScene broken = break_panes(input_scene);
  const scene::Scene& scene = broken.effective(input_scene);
  for (const auto& [code, message] : broken.warnings)
    warnings.add(code, message);
  result.fracture = broken.reports;
  for (const PaneReport& pane : result.fracture) {
    if (pane.broken) {
      ++result.stats.panes_broken;
      result.stats.fragments += pane.fragment_count;
    } else {
      ++result.stats.panes_not_broken;
    }
  }
  const Model model = prepare(scene, broken, result.stats);
  result.stats.bodies = model.bodies.size();
  if (scene.simulation.occlusion == scene::OcclusionMode::on)
    warnings.add("occlusion_unavailable",
                 "occlusion was requested but is not in this build yet; no object shields another");

  for (std::size_t b = 0; b < scene.objects.size(); ++b) {
    BodyInfo info;
    info.name = scene.objects[b].name;
    info.mass_kg = scene.objects[b].mass_kg;
    info.mesh = scene.objects[b].mesh;
    dynamics::BodyState start_state;
    start_state.orientation = scene.objects[b].orientation.normalized();
    start_state.position =
        scene.objects[b].position + start_state.orientation * model.centre_of_mass[b];
    info.initial_pose = origin_pose(model, b, start_state);
    result.bodies.push_back(std::move(info));
  }

  Run run(scene, model, result, warnings);
  outcome.cancelled = !run.execute(hooks);
  if (!outcome.cancelled) report_fragments(broken, run, result.fracture);
  result.warnings = warnings.list();
  result.stats.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (hooks.progress && !outcome.cancelled) hooks.progress(1.0);
  return outcome;
}

}  // namespace brisance::engine
