// Builds scenes in code for engine tests and benchmarks (the JSON parser is tested elsewhere).
#pragma once

#include <cmath>
#include <cstdint>
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

// A closed unit sphere of `rings` bands of latitude and `around` facets each (poles as fans):
// every facet in its own tangent plane.
inline geometry::TriangleMesh uv_sphere(int rings, int around) {
  constexpr double kPi = 3.141592653589793;
  geometry::TriangleMesh mesh;
  mesh.vertices.emplace_back(0.0, 1.0, 0.0);
  for (int i = 1; i < rings; ++i) {
    const double theta = kPi * i / rings;
    for (int j = 0; j < around; ++j) {
      const double phi = 2.0 * kPi * j / around;
      mesh.vertices.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta),
                                 std::sin(theta) * std::sin(phi));
    }
  }
  mesh.vertices.emplace_back(0.0, -1.0, 0.0);
  const auto ring = [&](int i, int j) {
    return static_cast<std::uint32_t>(1 + i * around + (j % around));
  };
  for (int j = 0; j < around; ++j)
    mesh.triangles.push_back({0, ring(0, j + 1), ring(0, j)});
  for (int i = 0; i + 2 < rings; ++i)
    for (int j = 0; j < around; ++j) {
      mesh.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      mesh.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  const auto last = static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  for (int j = 0; j < around; ++j)
    mesh.triangles.push_back({last, ring(rings - 2, j), ring(rings - 2, j + 1)});
  return mesh;
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
