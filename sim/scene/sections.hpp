// sim/scene/sections (private to sim/scene): the parsers of the scene's sections — charges,
// environment, simulation (parse_sections.cpp), objects with their shapes, materials, mass and
// fracture (parse_objects.cpp) and generators (parse_generators.cpp). Each checks the values of
// its own section with the reader and reports every problem; the checks across sections live in
// checks.hpp.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/scene/reader.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::scene {

// The charge, or nullopt when it has no valid position. A charge with a valid position is
// returned even when other fields have errors (they are in `errors`), so that the scene-wide
// checks still see it and report their problems in the same pass.
std::optional<ChargeSpec> parse_charge(const json& value, const std::string& pointer,
                                       Errors& errors);
EnvironmentSpec parse_environment(const json& value, const std::string& pointer, Errors& errors);
SimulationSpec parse_simulation(const json& value, const std::string& pointer, const Limits& limits,
                                Errors& errors);

// One entry of `objects` or a generated object, with where it came from for error pointers.
struct SceneObject {
  ObjectSpec spec;
  std::string name_pointer;              // where its name was given
  std::string position_pointer;          // where its placement was given
  std::optional<std::size_t> generator;  // index into `generators`, if generated
};

// The object, or nullopt when its name, shape or placement is invalid. As with charges, an
// object whose other fields have errors (in `errors`) is still returned for the scene-wide checks.
std::optional<SceneObject> parse_object(const json& value, const std::string& pointer,
                                        const Limits& limits, const MeshSources& meshes,
                                        Errors& errors);

// The objects one entry of `generators` makes, none if it is invalid. `objects_before`: objects
// already in the scene, for the max_objects check before anything is generated (a generator
// asking for millions of bricks must not allocate them).
std::vector<SceneObject> parse_generator(const json& value, const std::string& pointer,
                                         std::size_t generator_index, std::size_t objects_before,
                                         const Limits& limits, Errors& errors);

// ---------------------------------------------------------------------------------------------
// Shared by objects and generators

// Case-insensitive lookup of a material name.
std::optional<Material> find_material(std::string_view name);
std::string material_names();            // every material, for messages
std::string breakable_material_names();  // those that may carry `fracture`

// A body's `mass` (kg) or `density` (kg/m^3), at most one of the two: both given, or an invalid
// value, is reported. Neither given leaves `given` false for the caller to default or report.
struct MassOrDensity {
  bool given = false;  // `mass` or `density` is present, valid or not
  std::optional<double> mass_kg;
  std::optional<double> density_kg_m3;
};
MassOrDensity read_mass_or_density(const Fields& fields);

// The `fracture` member of an object or a window generator. `material` is the object's, if any:
// a breakable one supplies Young's modulus, K_c and the strength, which the fields may
// override. `allow_framed`: objects say whether an anchored frame holds them; a window's
// `frame` says it for its pane.
std::optional<FractureSpec> parse_fracture(const json& value, const std::string& pointer,
                                           const std::optional<Material>& material,
                                           bool allow_framed, Errors& errors);

}  // namespace brisance::scene
