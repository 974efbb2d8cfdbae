// sim/scene/checks (private to sim/scene): the checks that look across the sections of a scene
// once they are parsed — unique object names, charges and objects above the ground, charges
// outside every object, and the limits on load panels and frame samples. Each adds its errors in
// the order of the charges and objects it is given; parse_scene calls them in a fixed order.
#pragma once

#include <optional>
#include <vector>

#include "sim/scene/reader.hpp"
#include "sim/scene/scene.hpp"
#include "sim/scene/sections.hpp"

namespace brisance::scene {

// Unique names; the second of a pair is the error. A generator reports only its first clash.
void check_unique_names(const std::vector<SceneObject>& objects, Errors& errors);

// A charge below the ground plane (buried charges are not modelled). Invalid charges (nullopt)
// are skipped; their indices still count for the pointers.
void check_charges_above_ground(const std::optional<GroundSpec>& ground,
                                const std::vector<std::optional<ChargeSpec>>& charges,
                                Errors& errors);

// Objects sunk into the ground: one error per explicit object, one per generator.
void check_objects_above_ground(const std::optional<GroundSpec>& ground,
                                const std::vector<SceneObject>& objects, Errors& errors);

// A charge strictly inside an object is an error; on its surface is allowed (a contact charge).
void check_charges_outside_objects(const std::vector<std::optional<ChargeSpec>>& charges,
                                   const std::vector<SceneObject>& objects, Errors& errors);

// The scene's load panels against max_panels and its frames x bodies against
// max_frame_samples; both only when the simulation section was valid (`simulation_ok`).
void check_limits(const std::vector<SceneObject>& objects, const SimulationSpec& simulation,
                  bool simulation_ok, const Limits& limits, Errors& errors);

}  // namespace brisance::scene
