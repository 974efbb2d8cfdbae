// Builds scenes in code for engine tests and benchmarks (the JSON parser is tested elsewhere).
#pragma once

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/geometry/mesh.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::testing {

#ifdef BRISANCE_SOURCE_DIR
// scenes/NAME parsed; a scene that does not parse throws, so the test fails with its errors.
inline scene::Scene load_example_scene(const std::string& name) {
  std::ifstream in(std::string(BRISANCE_SOURCE_DIR) + "/scenes/" + name);
  std::stringstream text;
  text << in.rdbuf();
  scene::ParseResult parsed = scene::parse_scene_text(text.str());
  if (!parsed.scene) {
    throw std::runtime_error(name + ": " + parsed.errors.front().pointer + " " +
                             parsed.errors.front().message);
  }
  return std::move(*parsed.scene);
}
#endif

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

// `count` boxes named b0, b1, ... in rows of `per_row` along x (centres x0 + pitch * column),
// stacked row on row from the height `bottom` of the first row's base.
inline void add_box_grid(scene::Scene& scene, int count, int per_row, const Eigen::Vector3d& size,
                         double pitch, double x0, double bottom, double mass) {
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d centre(pitch * (i % per_row) + x0,
                                 bottom + 0.5 * size.y() + size.y() * (i / per_row), 0.0);
    scene.objects.push_back(box_object("b" + std::to_string(i), size, centre, mass));
  }
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
