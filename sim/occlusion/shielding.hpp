// sim/occlusion/shielding: the heuristic propagation model of thesis chapter 4. Around one charge,
// every object that may shadow (`blocks`) and every object that is loaded (`receives`) is
// projected separately onto the icosahedral sphere map (its pixel mask and its nearest and
// farthest depth per pixel); objects entirely in front of another at some pixel are its
// occluders. The occluders' masks are united and numbered by distance from their edge (fig. 4.4);
// the blocking factor b is the mean number under the shadowed object's mask, the radial separation
// k the gap between the nearest occluder's rear and the shadowed object's front over the latter's
// distance from the charge, and the load is scaled by f(b, k) of eq. 4.1.
//
// Beyond the thesis (which scales whole objects and "does not model differential loading") the
// same numbers are read per load panel, over the pixels the panel covers, so the exposed part of a
// half-hidden object takes its full load. Computed once per charge before stepping: the wave
// outruns the debris (thesis §4.2.2).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/occlusion/sphere_map.hpp"

namespace brisance::occlusion {

struct Settings {
  // Thesis §4.2.1: 32 pixels along a face's base and 28 rows.
  int face_columns = 32;
  int face_rows = 28;
  // Eq. 4.1's constants: f reaches 0 at b = blocking_offset + separation_slope * k.
  double blocking_offset = 1.0;
  double separation_slope = 7.0;
  // An object occludes another at a pixel when its farthest depth there is no more than this
  // beyond the other's nearest depth (touching objects shield each other), m.
  double depth_tolerance_m = 1e-3;
  // true: one attenuation per panel (differential loading); false: the thesis's one per object.
  bool per_panel = true;
};

// Thesis eq. 4.1: f(b, k) = x^3 - 2 x^1.5 + 1 with x = b / (offset + slope * k), 0 for x >= 1.
double attenuation(double blocking_factor, double radial_separation, double blocking_offset = 1.0,
                   double separation_slope = 7.0);

// One object as the charge sees it: a closed triangle mesh in the world frame.
struct Object {
  std::span<const Vec3> vertices;                           // world frame, m
  std::span<const std::array<std::uint32_t, 3>> triangles;  // indices into vertices
  bool blocks = true;                                       // may shadow others
  bool receives = true;                                     // is loaded, so wants its attenuation
};

// A load panel whose attenuation is wanted.
struct Panel {
  std::uint32_t object = 0;    // index into the objects
  Vec3 centre = Vec3::Zero();  // world frame, m
  double area_m2 = 0.0;
};

struct ObjectShielding {
  double attenuation = 1.0;              // f(b, k) for the whole object (the thesis's mode)
  double blocking_factor = 0.0;          // b, in pixels of the reference resolution (32 a face)
  double radial_separation = 0.0;        // k
  std::uint32_t mask_pixels = 0;         // pixels of its projection
  std::vector<std::uint32_t> occluders;  // indices of the objects that occlude it, ascending
};

struct Shielding {
  std::vector<ObjectShielding> objects;   // one per object
  std::vector<double> panel_attenuation;  // one per panel asked for, in [0, 1]
  std::uint32_t objects_occluded = 0;     // receiving objects with at least one occluder
  std::uint32_t occlusion_maps = 0;       // distinct occluder unions numbered
};

// The shielding of every object and panel from one charge. Panels are read per panel or get their
// object's attenuation, as settings.per_panel says. The map must have settings' resolution.
Shielding compute_shielding(const SphereMap& map, const Vec3& charge_m,
                            std::span<const Object> objects, std::span<const Panel> panels,
                            const Settings& settings);

// Whether any blocking object's angular footprint (its bounding cone from the charge) can overlap
// another receiving object's; when none can, no object shadows any other and the pass is skipped.
bool footprints_may_overlap(const Vec3& charge_m, std::span<const Object> objects);

}  // namespace brisance::occlusion
