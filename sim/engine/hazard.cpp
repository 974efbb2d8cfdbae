// sim/engine/hazard: the glazing performance condition of each pane from where its released
// fragments land or strike in the test room behind it (GSA P100 table 8-1; hazard.hpp).
#include "sim/engine/hazard.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace brisance::engine {

namespace {

using Vec3 = scene::Vec3;
using Quat = scene::Quat;

// On the ground a fragment touches the floor when its lowest vertex is within this of it (the
// contact solver keeps a resting body within a fraction of a millimetre); a floor that is only a
// level (no ground) is touched when the lowest vertex crosses it.
constexpr double kGroundTolerance_m = 0.005;

// The test room behind one pane.
struct Room {
  Vec3 centre = Vec3::Zero();   // the pane's centre
  Vec3 inward = Vec3::UnitZ();  // unit normal of the pane pointing into the room
  double half_thickness_m = 0.0;
  double floor_y_m = 0.0;
  bool solid_floor = false;  // the scene's ground: fragments stop on it and may slide on
  double floor_tolerance_m = 0.0;
  Vec3 gravity = Vec3::Zero();
};

// Which side of the pane the room is on: its sheltered face (a window's back), else the side
// away from the charge that loads it hardest (the largest W^(1/3) / R).
Vec3 inward_normal(const scene::ObjectSpec& pane, const scene::Scene& scene) {
  const Vec3 normal = pane.orientation * Vec3::UnitZ();
  constexpr std::uint8_t kPlusZ = 1u << 4;
  constexpr std::uint8_t kMinusZ = 1u << 5;
  const bool back = (pane.sheltered & kMinusZ) != 0;
  const bool front = (pane.sheltered & kPlusZ) != 0;
  if (back != front) return back ? Vec3(-normal) : normal;
  double best = -1.0;
  Vec3 inward = -normal;
  for (const scene::ChargeSpec& charge : scene.charges) {
    const Vec3 to_charge = charge.position - pane.position;
    const double score =
        std::cbrt(charge.mass_kg * charge.tnt_factor) / std::max(to_charge.norm(), 1e-9);
    if (score > best) {
      best = score;
      inward = to_charge.dot(normal) >= 0.0 ? Vec3(-normal) : normal;
    }
  }
  return inward;
}

Room room_behind(const scene::ObjectSpec& pane, const scene::Scene& scene) {
  Room room;
  room.centre = pane.position;
  room.inward = inward_normal(pane, scene);
  room.half_thickness_m = 0.5 * pane.box_size_m.z();
  double lowest_corner = std::numeric_limits<double>::infinity();
  for (const Vec3& v : pane.mesh.vertices)
    lowest_corner = std::min(lowest_corner, (pane.position + pane.orientation * v).y());
  const auto& ground = scene.environment.ground;
  room.solid_floor = ground.has_value();
  room.floor_tolerance_m = room.solid_floor ? kGroundTolerance_m : 0.0;
  room.floor_y_m = std::min(ground ? ground->height_m : 0.0, lowest_corner);
  room.gravity = scene.environment.gravity_m_s2;
  return room;
}

// A fragment at one pose: how far its centroid is behind the pane's inner face, its height
// above the floor, and its lowest vertex's height above the floor.
struct Sample {
  double depth_m = 0.0;
  double height_m = 0.0;
  double lowest_m = 0.0;
};

Sample sample(const Pose& pose, const geometry::TriangleMesh& mesh, const Vec3& centroid,
              const Room& room) {
  const Vec3 position(pose.position[0], pose.position[1], pose.position[2]);
  const Quat q(pose.orientation[3], pose.orientation[0], pose.orientation[1], pose.orientation[2]);
  const Vec3 c = position + q * centroid;
  Sample s;
  s.depth_m = (c - room.centre).dot(room.inward) - room.half_thickness_m;
  s.height_m = c.y() - room.floor_y_m;
  s.lowest_m = std::numeric_limits<double>::infinity();
  for (const Vec3& v : mesh.vertices)
    s.lowest_m = std::min(s.lowest_m, (position + q * v).y() - room.floor_y_m);
  return s;
}

// Where one fragment went.
struct Fate {
  std::optional<double> witness_height_m;  // struck the witness panel at this height
  std::optional<double> floor_depth_m;     // else lay on the floor this far behind the pane
  double last_depth_m = 0.0;               // where it was at the end, if neither
  bool extrapolated = false;
};

// The smallest t >= 0 with a + b t + c t^2 / 2 = 0, if any.
std::optional<double> first_root(double a, double b, double c) {
  if (std::abs(c) < 1e-12) {
    if (std::abs(b) < 1e-12) return std::nullopt;
    const double t = -a / b;
    return t >= 0.0 ? std::optional<double>(t) : std::nullopt;
  }
  const double disc = b * b - 2.0 * c * a;
  if (disc < 0.0) return std::nullopt;
  const double root = std::sqrt(disc);
  double best = std::numeric_limits<double>::infinity();
  for (const double t : {(-b - root) / c, (-b + root) / c})
    if (t >= 0.0) best = std::min(best, t);
  return std::isfinite(best) ? std::optional<double>(best) : std::nullopt;
}

// Past the run's end: a ballistic path without drag (so no shorter than the real one) from the
// last state, to the floor or the witness panel, whichever comes first.
void extrapolate(const Sample& last, const FinalState& final_state, const Room& room, Fate& fate) {
  const Vec3 v(final_state.linear_velocity_m_s[0], final_state.linear_velocity_m_s[1],
               final_state.linear_velocity_m_s[2]);
  const std::optional<double> to_floor =
      first_root(last.lowest_m - room.floor_tolerance_m, v.y(), room.gravity.y());
  const std::optional<double> to_witness =
      last.depth_m >= kHazardWitnessDistance_m
          ? std::optional<double>(0.0)
          : first_root(last.depth_m - kHazardWitnessDistance_m, v.dot(room.inward),
                       room.gravity.dot(room.inward));
  if (!to_floor && !to_witness) return;
  fate.extrapolated = true;
  const auto at = [](double x0, double v0, double a, double t) {
    return x0 + v0 * t + 0.5 * a * t * t;
  };
  if (to_witness && (!to_floor || *to_witness <= *to_floor)) {
    fate.witness_height_m = at(last.height_m, v.y(), room.gravity.y(), *to_witness);
  } else {
    const double depth =
        at(last.depth_m, v.dot(room.inward), room.gravity.dot(room.inward), *to_floor);
    fate.floor_depth_m = std::max(fate.floor_depth_m.value_or(depth), depth);
  }
}

// Follows one released fragment through the frames: the first witness crossing ends it; a
// landing ends it on a floor that is only a level (no ground), and on the ground the furthest
// point it lay at counts (it may slide or bounce on).
Fate follow(const Result& result, std::uint32_t body, const std::optional<std::size_t>& animated,
            const Room& room) {
  const BodyInfo& info = result.bodies[body];
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& v : info.mesh.vertices)
    centroid += v;
  if (!info.mesh.vertices.empty()) centroid /= static_cast<double>(info.mesh.vertices.size());
  const bool moves = animated.has_value() && !result.frame_times_s.empty();
  const std::size_t frames = moves ? result.frame_times_s.size() : 1;
  Fate fate;
  Sample previous;
  bool on_floor = false;
  for (std::size_t f = 0; f < frames; ++f) {
    const Pose& pose = moves ? result.pose(f, *animated) : info.initial_pose;
    const Sample now = sample(pose, info.mesh, centroid, room);
    fate.last_depth_m = now.depth_m;
    const auto lerp = [&](double a, double b, double s) { return a + (b - a) * s; };
    // Where in (previous, now] it crossed the witness plane and came down to the floor, as a
    // fraction of the frame interval (linear between frames: a ballistic path sags by g dt^2 / 8,
    // 1.4 mm at 30 frames/s).
    std::optional<double> witness_at;
    if (f > 0 && previous.depth_m < kHazardWitnessDistance_m &&
        now.depth_m >= kHazardWitnessDistance_m)
      witness_at = (kHazardWitnessDistance_m - previous.depth_m) / (now.depth_m - previous.depth_m);
    std::optional<double> landed_at;
    // (A fragment of a pane standing on a floor level starts on it: it lands when it has moved.)
    if (now.lowest_m <= room.floor_tolerance_m && (f > 0 || room.solid_floor)) {
      landed_at =
          f > 0 && previous.lowest_m > room.floor_tolerance_m
              ? (previous.lowest_m - room.floor_tolerance_m) / (previous.lowest_m - now.lowest_m)
              : 1.0;
    }
    if (landed_at && (!witness_at || *landed_at < *witness_at)) {
      const double depth = f > 0 ? lerp(previous.depth_m, now.depth_m, *landed_at) : now.depth_m;
      fate.floor_depth_m = std::max(fate.floor_depth_m.value_or(depth), depth);
      on_floor = true;
      if (!room.solid_floor) return fate;  // below a floor level its path is not real
    }
    if (witness_at) {
      fate.witness_height_m = std::max(0.0, lerp(previous.height_m, now.height_m, *witness_at));
      return fate;
    }
    previous = now;
  }
  // Still in flight when the run ended (or never left the floor).
  if (!on_floor || previous.lowest_m > room.floor_tolerance_m) {
    if (body < result.final_state.size())
      extrapolate(previous, result.final_state[body], room, fate);
  }
  return fate;
}

void set_condition(PaneHazard& hazard, bool broken) {
  const auto set = [&](const char* condition, const char* protection, const char* level) {
    hazard.condition = condition;
    hazard.protection_level = protection;
    hazard.hazard_level = level;
  };
  if (!broken)
    set("1", "safe", "none");
  else if (hazard.fragments_in_room == 0)
    set("2", "very_high", "none");
  else if (hazard.witness_impacts > 0 && hazard.max_witness_height_m > kHazardWitnessHeight_m)
    set("5", "low", "high");
  else if (hazard.witness_impacts > 0)
    set("4", "medium", "medium");
  else if (hazard.max_floor_distance_m > kHazardVeryLowFloorDistance_m)
    set("3b", "high", "low");
  else
    set("3a", "high", "very_low");
}

}  // namespace

void rate_pane_hazards(const scene::Scene& scene, Result& result) {
  std::unordered_map<std::string_view, const scene::ObjectSpec*> objects;
  for (const scene::ObjectSpec& object : scene.objects)
    objects.emplace(object.name, &object);
  std::unordered_map<std::uint32_t, std::size_t> animated;
  for (std::size_t k = 0; k < result.animated.size(); ++k)
    animated.emplace(result.animated[k], k);
  for (PaneReport& pane : result.fracture) {
    PaneHazard& hazard = pane.hazard;
    hazard = PaneHazard{};
    const auto object = objects.find(pane.name);
    if (object == objects.end()) continue;
    const Room room = room_behind(*object->second, scene);
    hazard.floor_height_m = room.floor_y_m;
    for (std::size_t k = 0; k < pane.release_times_s.size(); ++k) {
      if (pane.release_times_s[k] < 0.0) continue;
      const auto body = static_cast<std::uint32_t>(pane.first_body + k);
      const auto found = animated.find(body);
      const Fate fate = follow(
          result, body,
          found == animated.end() ? std::nullopt : std::optional<std::size_t>(found->second), room);
      if (fate.extrapolated) ++hazard.fragments_extrapolated;
      if (fate.witness_height_m) {
        ++hazard.fragments_in_room;
        ++hazard.witness_impacts;
        hazard.max_witness_height_m = std::max(hazard.max_witness_height_m, *fate.witness_height_m);
      } else if (fate.floor_depth_m ? *fate.floor_depth_m > 0.0 : fate.last_depth_m > 0.0) {
        ++hazard.fragments_in_room;
        if (fate.floor_depth_m) {
          ++hazard.fragments_on_floor;
          hazard.max_floor_distance_m = std::max(hazard.max_floor_distance_m, *fate.floor_depth_m);
        }
      } else {
        ++hazard.fragments_outside;
      }
    }
    set_condition(hazard, pane.broken);
  }
}

}  // namespace brisance::engine
