#include "sim/io/result_json.hpp"

#include <cassert>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/io/frames.hpp"

namespace brisance::io {

namespace {

using nlohmann::json;

json vec3_to_json(const std::array<double, 3>& v) {
  return json::array({v[0], v[1], v[2]});
}

json quat_to_json(const std::array<double, 4>& q) {
  return json::array({q[0], q[1], q[2], q[3]});
}

json mesh_to_json(const geometry::TriangleMesh& mesh) {
  json vertices = json::array();
  vertices.get_ref<json::array_t&>().reserve(mesh.vertices.size());
  for (const geometry::Vec3& v : mesh.vertices)
    vertices.push_back(json::array({v.x(), v.y(), v.z()}));
  json triangles = json::array();
  triangles.get_ref<json::array_t&>().reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    triangles.push_back(json::array({t[0], t[1], t[2]}));
  return json{{"vertices", std::move(vertices)}, {"triangles", std::move(triangles)}};
}

// One entry of "bodies"; `animated` says whether the body's index is in result.animated.
json body_to_json(const engine::BodyInfo& body, bool animated) {
  return json{{"name", body.name},
              {"material", body.material},
              {"fragment", body.fragment},
              {"mass", body.mass_kg},
              {"mesh", mesh_to_json(body.mesh)},
              {"animated", animated},
              {"position", vec3_to_json(body.initial_pose.position)},
              {"orientation", quat_to_json(body.initial_pose.orientation)}};
}

// animated_flags[i] is true when body i is in result.animated: one pass, not a search per body.
std::vector<bool> animated_flags(const engine::Result& result) {
  std::vector<bool> flags(result.bodies.size(), false);
  for (const std::uint32_t index : result.animated) {
    assert(index < result.bodies.size());
    flags[index] = true;
  }
  return flags;
}

// Writes `[f(0),f(1),...,f(count-1)]`, dumping one element at a time so only one element's
// DOM exists at once.
template <typename ElementToJson>
void stream_array(std::ostream& out, std::size_t count, ElementToJson&& element_to_json) {
  out << '[';
  for (std::size_t i = 0; i < count; ++i) {
    if (i != 0) out << ',';
    out << element_to_json(i).dump();
  }
  out << ']';
}

}  // namespace

json final_state_to_json(const engine::FinalState& state) {
  return json{{"name", state.name},
              {"position", vec3_to_json(state.pose.position)},
              {"orientation", quat_to_json(state.pose.orientation)},
              {"linear_velocity", vec3_to_json(state.linear_velocity_m_s)},
              {"angular_velocity", vec3_to_json(state.angular_velocity_rad_s)}};
}

json warning_to_json(const engine::Warning& warning) {
  return json{{"code", warning.code}, {"message", warning.message}, {"count", warning.count}};
}

json final_states_to_json(const std::vector<engine::FinalState>& states) {
  json list = json::array();
  for (const engine::FinalState& state : states)
    list.push_back(final_state_to_json(state));
  return list;
}

json warnings_to_json(const std::vector<engine::Warning>& warnings) {
  json list = json::array();
  for (const engine::Warning& warning : warnings)
    list.push_back(warning_to_json(warning));
  return list;
}

json stats_to_json(const engine::Stats& stats) {
  // Binding every member by name makes a field added to Stats a compile error here until it is
  // written too, so "stats" always holds every field.
  const auto& [steps, simulated_time_s, wall_time_s, ended_early, bodies, bodies_anchored,
               bodies_never_released, fragments_held_by_frame, bodies_slept,
               bodies_static_in_frames, panels, panels_loaded, panels_back_facing,
               panels_not_reached, body_steps, occlusion_skipped, panels_shielded, panes_broken,
               panes_not_broken, fragments, panels_merged, collision_pairs, collision_pairs_skipped,
               contact_points] = stats;
  return json{{"steps", steps},
              {"simulated_time_s", simulated_time_s},
              {"wall_time_s", wall_time_s},
              {"ended_early", ended_early},
              {"bodies", bodies},
              {"bodies_anchored", bodies_anchored},
              {"bodies_never_released", bodies_never_released},
              {"fragments_held_by_frame", fragments_held_by_frame},
              {"bodies_slept", bodies_slept},
              {"bodies_static_in_frames", bodies_static_in_frames},
              {"panels", panels},
              {"panels_loaded", panels_loaded},
              {"panels_back_facing", panels_back_facing},
              {"panels_not_reached", panels_not_reached},
              {"body_steps", body_steps},
              {"panels_shielded", panels_shielded},
              {"occlusion_skipped", occlusion_skipped},
              {"panes_broken", panes_broken},
              {"panes_not_broken", panes_not_broken},
              {"fragments", fragments},
              {"panels_merged", panels_merged},
              {"collision_pairs", collision_pairs},
              {"collision_pairs_skipped", collision_pairs_skipped},
              {"contact_points", contact_points}};
}

json distribution_to_json(const engine::Distribution& d) {
  return json{{"count", d.count}, {"mean", d.mean}, {"min", d.min}, {"p10", d.p10},
              {"p50", d.p50},     {"p90", d.p90},   {"max", d.max}};
}

json hazard_to_json(const engine::PaneHazard& h) {
  return json{{"condition", h.condition},
              {"protection_level", h.protection_level},
              {"hazard_level", h.hazard_level},
              {"floor_height_m", h.floor_height_m},
              {"fragments_in_room", h.fragments_in_room},
              {"fragments_outside", h.fragments_outside},
              {"fragments_on_floor", h.fragments_on_floor},
              {"witness_impacts", h.witness_impacts},
              {"fragments_extrapolated", h.fragments_extrapolated},
              {"max_floor_distance_m", h.max_floor_distance_m},
              {"max_witness_height_m", h.max_witness_height_m}};
}

json pane_to_json(const engine::PaneReport& pane) {
  // Never-released fragments are null in release_times_s.
  json release_times = json::array();
  for (const double t : pane.release_times_s)
    release_times.push_back(t >= 0.0 ? json(t) : json(nullptr));
  return json{{"name", pane.name},
              {"broken", pane.broken},
              {"forced", pane.forced},
              {"peak_pressure_pa", pane.peak_pressure_pa},
              {"stress_pa", pane.stress_pa},
              {"strength_pa", pane.strength_pa},
              {"deflection_m", pane.deflection_m},
              {"small_deflection", pane.small_deflection},
              {"critical_crack_length_m", pane.critical_crack_length_m},
              {"growth_length_m", pane.growth_length_m},
              {"growth_length_given", pane.growth_length_given},
              {"growth_length_clamped", pane.growth_length_clamped},
              {"first_body", pane.first_body},
              {"fragment_count", pane.fragment_count},
              {"frontal_area_m2", distribution_to_json(pane.frontal_area_m2)},
              {"launch_speed_m_s", distribution_to_json(pane.launch_speed_m_s)},
              {"launch_speed_larger_half_m_s", pane.launch_speed_larger_half_m_s},
              {"launch_speed_smaller_half_m_s", pane.launch_speed_smaller_half_m_s},
              {"launch_speed_mass_weighted_m_s", pane.launch_speed_mass_weighted_m_s},
              {"cracks_start_s", pane.cracks_start_s},
              {"crack_origin_m", pane.crack_origin_m},
              {"released", pane.released},
              {"release_times_s", std::move(release_times)},
              {"release_time_s", distribution_to_json(pane.release_time_s)},
              {"empirical_mean_area_m2", pane.empirical_mean_area_m2},
              {"empirical_mean_speed_m_s", pane.empirical_mean_speed_m_s},
              {"hazard", hazard_to_json(pane.hazard)}};
}

json shielding_to_json(const engine::Result& result) {
  json list = json::array();
  for (const engine::ChargeShielding& charge : result.shielding) {
    json bodies = json::array();
    for (const engine::ShieldedBody& body : charge.bodies)
      bodies.push_back({{"body", body.body},
                        {"name", result.bodies[body.body].name},
                        {"attenuation", body.attenuation}});
    list.push_back({{"charge", charge.charge}, {"bodies", std::move(bodies)}});
  }
  return list;
}

json fracture_to_json(const std::vector<engine::PaneReport>& panes) {
  json list = json::array();
  for (const engine::PaneReport& pane : panes)
    list.push_back(pane_to_json(pane));
  return list;
}

json result_to_json(const engine::Result& result) {
  assert(result.poses.size() == result.frame_times_s.size() * result.animated.size());
  const std::vector<bool> animated = animated_flags(result);

  json bodies = json::array();
  for (std::size_t i = 0; i < result.bodies.size(); ++i)
    bodies.push_back(body_to_json(result.bodies[i], animated[i]));
  const FrameSet frame_set = frames_of(result);
  json frames = json::array();
  for (std::size_t f = 0; f < frame_set.frame_count(); ++f)
    frames.push_back(frame_to_json(frame_set, f));

  return json{{"bodies", std::move(bodies)},
              {"frames", std::move(frames)},
              {"final_state", final_states_to_json(result.final_state)},
              {"fracture", fracture_to_json(result.fracture)},
              {"shielding", shielding_to_json(result)},
              {"stats", stats_to_json(result.stats)},
              {"warnings", warnings_to_json(result.warnings)}};
}

// The same text as result_to_json(result).dump() and a newline, written element by element:
// a result of 10 000 bodies x 60 frames never holds its whole DOM (hundreds of MB of small
// allocations) in memory, and frames are written without one. The members are written in the
// order nlohmann::json dumps an object, sorted by key; io_tests checks the two texts are
// identical.
void write_result_json(const engine::Result& result, std::ostream& out, bool frame_velocities) {
  assert(result.poses.size() == result.frame_times_s.size() * result.animated.size());
  const std::vector<bool> animated = animated_flags(result);

  out << "{\"bodies\":";
  stream_array(out, result.bodies.size(),
               [&](std::size_t i) { return body_to_json(result.bodies[i], animated[i]); });
  out << ",\"final_state\":";
  stream_array(out, result.final_state.size(),
               [&](std::size_t i) { return final_state_to_json(result.final_state[i]); });
  out << ",\"fracture\":" << fracture_to_json(result.fracture).dump();
  out << ",\"frames\":";
  write_frames_array(out,
                     frame_velocities ? with_velocities(frames_of(result)) : frames_of(result));
  out << ",\"shielding\":" << shielding_to_json(result).dump();
  out << ",\"stats\":" << stats_to_json(result.stats).dump();
  out << ",\"warnings\":";
  stream_array(out, result.warnings.size(),
               [&](std::size_t i) { return warning_to_json(result.warnings[i]); });
  out << "}\n";
}

}  // namespace brisance::io
