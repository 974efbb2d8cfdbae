#include "sim/io/result_codec.hpp"

#include <cassert>

#include <nlohmann/json.hpp>

#include "sim/io/result_json.hpp"

namespace brisance::io {

namespace {

using nlohmann::json;

// The body fields the summary and the meshes document share.
json body_entry(std::size_t index, const engine::BodyInfo& body, bool animated) {
  return json{{"index", index},
              {"name", body.name},
              {"material", body.material},
              {"fragment", body.fragment},
              {"mass", body.mass_kg},
              {"animated", animated},
              {"position", body.initial_pose.position},
              {"orientation", body.initial_pose.orientation}};
}

}  // namespace

std::vector<bool> animated_flags(std::size_t body_count, std::span<const std::uint32_t> animated) {
  std::vector<bool> flags(body_count, false);
  for (const std::uint32_t index : animated) {
    assert(index < body_count);
    flags[index] = true;
  }
  return flags;
}

json result_summary(const engine::Result& result) {
  const std::vector<bool> animated = animated_flags(result.bodies.size(), result.animated);
  json bodies = json::array();
  for (std::size_t i = 0; i < result.bodies.size(); ++i)
    bodies.push_back(body_entry(i, result.bodies[i], animated[i]));
  const double duration = result.frame_times_s.empty() ? 0.0 : result.frame_times_s.back();
  return json{{"bodies", std::move(bodies)},
              {"animated", result.animated},
              {"frame_count", result.frame_times_s.size()},
              {"duration", duration},
              {"frame_times", result.frame_times_s},
              {"final_state", final_states_to_json(result.final_state)},
              {"stats", stats_to_json(result.stats)},
              {"warnings", warnings_to_json(result.warnings)},
              {"fracture", fracture_to_json(result.fracture)},
              {"shielding", shielding_to_json(result)}};
}

std::string meshes_document_json(std::span<const engine::BodyInfo> bodies,
                                 const std::vector<bool>& animated) {
  assert(animated.size() == bodies.size());
  json list = json::array();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const geometry::TriangleMesh& mesh = bodies[i].mesh;
    json vertices = json::array();
    for (const geometry::Vec3& v : mesh.vertices)
      vertices.push_back(json::array({v.x(), v.y(), v.z()}));
    json triangles = json::array();
    for (const auto& t : mesh.triangles)
      triangles.push_back(json::array({t[0], t[1], t[2]}));
    json entry = body_entry(i, bodies[i], animated[i]);
    entry["mesh"] = {{"vertices", std::move(vertices)}, {"triangles", std::move(triangles)}};
    list.push_back(std::move(entry));
  }
  return json{{"bodies", std::move(list)}}.dump();
}

}  // namespace brisance::io
