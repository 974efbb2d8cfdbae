// write_sample_glb OUTPUT_DIR: writes .glb files of synthetic results for the Khronos glTF
// validator (tests/gltf/validate.mjs, run by CTest as io.gltf_validator):
//   empty.glb          no bodies: an empty scene
//   static_only.glb    three static bodies, no animation
//   one_frame.glb      animated bodies but a single frame: no animation
//   animated_50x61.glb 50 bodies (40 animated, tumbling, one of >65535 vertices with 32-bit
//                      indices), 61 frames at 60 Hz
// The .glb files already in OUTPUT_DIR are removed first, so none is left from an older build.
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/engine/result.hpp"
#include "sim/io/gltf.hpp"

namespace {

using brisance::engine::BodyInfo;
using brisance::engine::Pose;
using brisance::engine::Result;
using brisance::geometry::TriangleMesh;
using brisance::geometry::Vec3;

// A box of half extents `half` whose every face is cut into a `cuts` x `cuts` grid of quads,
// two triangles each, wound counter-clockwise seen from outside. Faces do not share vertices.
TriangleMesh tessellated_box(const Vec3& half, int cuts) {
  TriangleMesh mesh;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      // u x v points along +axis; swapping them for the negative face keeps the winding outward.
      int u = (axis + 1) % 3;
      int v = (axis + 2) % 3;
      if (sign < 0) std::swap(u, v);
      const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
      for (int j = 0; j <= cuts; ++j) {
        for (int i = 0; i <= cuts; ++i) {
          Vec3 p = Vec3::Zero();
          p[axis] = sign * half[axis];
          p[u] = half[u] * (-1.0 + 2.0 * i / cuts);
          p[v] = half[v] * (-1.0 + 2.0 * j / cuts);
          mesh.vertices.push_back(p);
        }
      }
      const auto row = static_cast<std::uint32_t>(cuts + 1);
      for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(cuts); ++j) {
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(cuts); ++i) {
          const std::uint32_t a = first + j * row + i;
          mesh.triangles.push_back({a, a + 1, a + row + 1});
          mesh.triangles.push_back({a, a + row + 1, a + row});
        }
      }
    }
  }
  return mesh;
}

// A tetrahedron, the shape of a small fragment.
TriangleMesh tetrahedron(double size_m) {
  TriangleMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(size_m, 0, 0), Vec3(0, size_m, 0), Vec3(0, 0, size_m)};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

BodyInfo body(std::string name, TriangleMesh mesh, const std::array<double, 3>& position,
              std::string material = "", bool fragment = false) {
  BodyInfo info;
  info.name = std::move(name);
  info.material = std::move(material);
  info.fragment = fragment;
  info.mass_kg = 10.0;
  info.mesh = std::move(mesh);
  info.initial_pose.position = position;
  return info;
}

std::array<double, 4> about_axis(const Vec3& axis, double angle_rad) {
  const Vec3 unit = axis.normalized();
  const double s = std::sin(angle_rad / 2);
  return {unit.x() * s, unit.y() * s, unit.z() * s, std::cos(angle_rad / 2)};
}

Result static_only() {
  Result result;
  result.bodies.push_back(body("ground", tessellated_box(Vec3(10, 0.25, 10), 1), {0, -0.25, 0}));
  result.bodies.push_back(
      body("wall", tessellated_box(Vec3(3, 1.5, 0.1), 4), {0, 1.5, -4}, "concrete"));
  result.bodies.push_back(
      body("column", tessellated_box(Vec3(0.2, 2, 0.2), 2), {2, 2, -2}, "steel"));
  result.bodies.back().initial_pose.orientation = about_axis(Vec3::UnitY(), 0.5);
  return result;
}

// `animated_count` of `body_count` bodies fly off ballistically and tumble; every third one
// stores its quaternion with alternating sign, as a solver may, so the writer's sign continuity
// is exercised. Body 0 is the ground, tessellated past the 16-bit index limit.
Result animated(int body_count, int animated_count, int frame_count) {
  Result result;
  result.bodies.push_back(body("ground", tessellated_box(Vec3(10, 0.25, 10), 60), {0, -0.25, 0}));
  for (int i = 1; i < body_count; ++i) {
    const double x = -4.5 + (i % 10);
    const double z = -2.0 - (i / 10);
    result.bodies.push_back(
        // Glass fragments (two primitives: faces and crack faces) and bricks: every material.
        i % 2 ? body("fragment_" + std::to_string(i), tetrahedron(0.3), {x, 0.5, z},
                     "annealed_glass", true)
              : body("block_" + std::to_string(i), tessellated_box(Vec3(0.3, 0.2, 0.1), 1),
                     {x, 0.2, z}, "brick"));
  }
  for (int i = body_count - animated_count; i < body_count; ++i)
    result.animated.push_back(static_cast<std::uint32_t>(i));
  for (int f = 0; f < frame_count; ++f)
    result.frame_times_s.push_back(f / 60.0);

  const Vec3 gravity(0, -9.81, 0);
  for (int f = 0; f < frame_count; ++f) {
    const double t = result.frame_times_s[static_cast<std::size_t>(f)];
    for (const std::uint32_t index : result.animated) {
      const Pose& start = result.bodies[index].initial_pose;
      const Vec3 velocity(std::sin(index * 0.7) * 4, 6 + index % 5, -std::cos(index * 0.3) * 3);
      const Vec3 spin_axis(std::cos(index * 1.3), 1.0, std::sin(index * 0.9));
      const double spin_rad_s = 4.0 + index % 7;
      Pose pose;
      for (int c = 0; c < 3; ++c)
        pose.position[c] = start.position[c] + velocity[c] * t + 0.5 * gravity[c] * t * t;
      pose.orientation = about_axis(spin_axis, spin_rad_s * t);
      if (index % 3 == 0 && f % 2 == 1)
        for (double& component : pose.orientation)
          component = -component;
      result.poses.push_back(pose);
    }
  }
  return result;
}

void write(const std::filesystem::path& path, const Result& result) {
  std::ofstream out(path, std::ios::binary);
  brisance::io::write_glb(result, out);
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());
  std::cout << "wrote " << path.string() << " (" << std::filesystem::file_size(path) << " bytes)\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: write_sample_glb OUTPUT_DIR\n";
    return 2;
  }
  try {
    const std::filesystem::path directory = argv[1];
    std::filesystem::create_directories(directory);
    for (const auto& entry : std::filesystem::directory_iterator(directory))
      if (entry.path().extension() == ".glb") std::filesystem::remove(entry.path());

    write(directory / "empty.glb", Result{});
    write(directory / "static_only.glb", static_only());
    write(directory / "one_frame.glb", animated(5, 4, 1));
    write(directory / "animated_50x61.glb", animated(50, 40, 61));
  } catch (const std::exception& error) {
    std::cerr << "write_sample_glb: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
