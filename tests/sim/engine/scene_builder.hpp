// Builds scenes in code for engine tests and benchmarks (the JSON parser is tested elsewhere).
#pragma once

#include <string>

#include "sim/geometry/mesh.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::testing {

inline scene::ObjectSpec box_object(const std::string& name, const Eigen::Vector3d& size,
                                    const Eigen::Vector3d& position, double mass) {
  scene::ObjectSpec object;
  object.name = name;
  object.shape = scene::ShapeType::box;
  object.box_size_m = size;
  object.mesh = geometry::make_box(size);
  object.position = position;
  object.mass_kg = mass;
  return object;
}

inline scene::ChargeSpec tnt(double mass_kg, const Eigen::Vector3d& position) {
  scene::ChargeSpec charge;
  charge.mass_kg = mass_kg;
  charge.position = position;
  return charge;
}

// No gravity, no air, no ground: only the blast acts.
inline scene::Scene vacuum_scene() {
  scene::Scene s;
  s.environment.gravity_m_s2.setZero();
  s.environment.air_density_kg_m3 = 0.0;
  s.environment.ground.reset();
  return s;
}

}  // namespace brisance::testing
