// sim/scene/checks: the checks across sections of a parsed scene — unique names, charges and
// objects above the ground, charges outside objects, and the panel and frame-sample limits
// (see checks.hpp). The geometric queries they ask are sim/geometry's.
#include "sim/scene/checks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <unordered_map>
#include <utility>

#include "sim/geometry/queries.hpp"

namespace brisance::scene {

namespace {

// How far below the ground plane a vertex or charge may sit before it counts as buried, m: room
// for objects placed by hand at y = half their height with rounded numbers.
constexpr double kGroundTolerance_m = 1e-3;

}  // namespace

void check_unique_names(const std::vector<SceneObject>& objects, Errors& errors) {
  std::unordered_map<std::string_view, const SceneObject*> seen;
  seen.reserve(objects.size());
  std::vector<bool> generator_reported;
  for (const SceneObject& object : objects) {
    const auto [it, inserted] = seen.emplace(object.spec.name, &object);
    if (inserted) continue;
    if (object.generator) {
      if (generator_reported.size() <= *object.generator)
        generator_reported.resize(*object.generator + 1, false);
      if (generator_reported[*object.generator]) continue;
      generator_reported[*object.generator] = true;
    }
    const SceneObject& first = *it->second;
    std::string message = "the object name " + in_quotes(object.spec.name) +
                          " is already used (at " + first.name_pointer + "); ";
    message += object.generator ? "choose another name prefix for this generator"
                                : "object names must be unique, rename one of them";
    errors.add(object.name_pointer, message);
  }
}

void check_charges_above_ground(const std::optional<GroundSpec>& ground,
                                const std::vector<std::optional<ChargeSpec>>& charges,
                                Errors& errors) {
  if (!ground) return;
  for (std::size_t c = 0; c < charges.size(); ++c) {
    if (!charges[c]) continue;
    const double y = charges[c]->position.y();
    if (y >= ground->height_m - kGroundTolerance_m) continue;
    errors.add(child(child("", "charges"), c) + "/position",
               "the charge is " + format_number(ground->height_m - y) +
                   " m below the ground plane y = " + format_number(ground->height_m) +
                   " (buried charges are not modelled); raise it to at least the ground (a "
                   "charge on the ground is a surface burst)");
  }
}

void check_objects_above_ground(const std::optional<GroundSpec>& ground,
                                const std::vector<SceneObject>& objects, Errors& errors) {
  if (!ground) return;
  std::map<std::size_t, std::pair<std::size_t, double>> per_generator;  // count, deepest
  std::map<std::size_t, std::string> first_name;
  for (const SceneObject& object : objects) {
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vec3& vertex : object.spec.mesh.vertices)
      lowest = std::min(lowest, (object.spec.position + object.spec.orientation * vertex).y());
    if (lowest >= ground->height_m - kGroundTolerance_m) continue;
    const double depth = ground->height_m - lowest;
    if (object.generator) {
      auto& [count, deepest] = per_generator[*object.generator];
      if (count == 0) first_name[*object.generator] = object.spec.name;
      ++count;
      deepest = std::max(deepest, depth);
      continue;
    }
    errors.add(object.position_pointer,
               "object " + in_quotes(object.spec.name) + " reaches " + format_number(depth) +
                   " m below the ground plane y = " + format_number(ground->height_m) +
                   "; raise it by at least that much (or lower environment.ground.height)");
  }
  for (const auto& [generator, entry] : per_generator) {
    const auto& [count, deepest] = entry;
    errors.add(child(child(child("", "generators"), generator), "position"),
               std::to_string(count) + " generated objects (the first " +
                   in_quotes(first_name[generator]) + ") reach up to " + format_number(deepest) +
                   " m below the ground plane y = " + format_number(ground->height_m) +
                   "; raise the generator's position by at least that much");
  }
}

void check_charges_outside_objects(const std::vector<std::optional<ChargeSpec>>& charges,
                                   const std::vector<SceneObject>& objects, Errors& errors) {
  std::vector<geometry::BoundingSphere> spheres;
  spheres.reserve(objects.size());
  for (const SceneObject& object : objects)
    spheres.push_back(geometry::bounding_sphere(object.spec.mesh));
  for (std::size_t c = 0; c < charges.size(); ++c) {
    if (!charges[c]) continue;
    for (std::size_t o = 0; o < objects.size(); ++o) {
      const ObjectSpec& object = objects[o].spec;
      // The charge in the object's own frame.
      const Vec3 local = object.orientation.conjugate() * (charges[c]->position - object.position);
      // Within a nanometre per metre of size counts as on the surface, whatever rounding did.
      const double margin = 1e-9 * std::max(1.0, spheres[o].radius_m);
      if ((local - spheres[o].centre).norm() > spheres[o].radius_m + margin) continue;
      if (geometry::winding_number(object.mesh, local) <= 0.5) continue;
      if (geometry::distance_to_surface(object.mesh, local) <= margin) continue;
      errors.add(child(child("", "charges"), c) + "/position",
                 "the charge is inside object " + in_quotes(object.name) +
                     "; move the charge out of the object (or the object away from it)");
    }
  }
}

void check_limits(const std::vector<SceneObject>& objects, const SimulationSpec& simulation,
                  bool simulation_ok, const Limits& limits, Errors& errors) {
  // Panels: counted with geometry::count_panels, which counts exactly what make_panels would cut
  // without making the panels, so the count is the engine's. It caps the subdivision per face, so
  // one call stays bounded; equal boxes (a wall has two sizes) are counted once, and counting
  // stops as soon as the limit is passed.
  if (simulation_ok) {
    std::map<std::array<double, 3>, std::uint64_t> box_panels;
    std::uint64_t total = 0;
    for (const SceneObject& object : objects) {
      const ObjectSpec& spec = object.spec;
      const auto panels_of_object = [&] {
        return static_cast<std::uint64_t>(
            geometry::count_panels(spec.mesh, simulation.max_panel_area_m2));
      };
      if (spec.shape == ShapeType::box) {
        const std::array<double, 3> size = {spec.box_size_m.x(), spec.box_size_m.y(),
                                            spec.box_size_m.z()};
        auto [it, inserted] = box_panels.try_emplace(size, 0);
        if (inserted) it->second = panels_of_object();
        total += it->second;
      } else {
        total += panels_of_object();
      }
      if (total > limits.max_panels) break;
    }
    if (total > limits.max_panels) {
      errors.add("", "the scene's objects make more than " + std::to_string(limits.max_panels) +
                         " load panels (the limit max_panels); raise simulation.max_panel_area "
                         "(now " +
                         format_number(simulation.max_panel_area_m2) +
                         " m^2) or use fewer or smaller objects");
    }
  }
  // Frames x bodies: what the recorder may have to store.
  if (simulation_ok && !objects.empty()) {
    const double frames = std::ceil(simulation.duration_s * simulation.frame_rate_hz) + 1.0;
    const double samples = frames * static_cast<double>(objects.size());
    if (samples > static_cast<double>(limits.max_frame_samples)) {
      errors.add("/simulation",
                 format_number(frames) + " frames x " + std::to_string(objects.size()) +
                     " objects = " + format_number(samples) +
                     " frame samples, more than the limit max_frame_samples = " +
                     std::to_string(limits.max_frame_samples) +
                     "; shorten simulation.duration, lower simulation.frame_rate or use fewer "
                     "objects");
    }
  }
}

}  // namespace brisance::scene
